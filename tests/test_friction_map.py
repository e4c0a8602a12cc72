"""Maps on a floor with friction, the regime map over (mu, beta) and its command (issue 37 item 4).

The block is the issue's: H = 2 m, B = 0.5 m, M = 1000 kg under one-sine pulses of T_g = 0.5 s. The numbers
it is held to come from outside the code: Shenton (1996)'s initiation rule (a symmetric block at rest slides
first when mu < B/H = 0.25, rocks first above), the floor's static hold (no slip while a_g < mu g), and the
issue's independent sliding-only model (peak slip 31.45 mm at mu = 0.2, a_g = 0.4 g).
"""

import argparse
import json

import numpy as np
import pytest

import rocking
from rocking.cli.study import add_study_commands, map_lines
from rocking.plot.figures import MAP_SLID_CLASSES, _outcome_classes, friction_figure, map_figure
from rocking.study.friction_map import envelope as friction_envelope
from rocking.study.overturning_map import FIELDS, envelope, response_classes
from rocking.study.storage import load
from rocking.study.vocabulary import (
    OVERTURNS,
    REGIMES,
    REST,
    ROCKS,
    SLIDES,
    SLIDES_AND_ROCKS,
    combined_regime,
    regime,
)

BLOCK = rocking.Block(2.0, 0.5, 1000.0)
G = BLOCK.g


def _map(tmp_path, **floor):
    """A one-cell map (T_g = 0.5 s, a_g = 0.4 g) of the issue's block, alone and damped, every cell computed."""
    return rocking.overturning_map(
        BLOCK,
        {"gamma": 0.05},
        T_g=[0.5],
        a_g=[0.4 * G],
        full=True,
        backend="numpy",
        runs=tmp_path / "runs",
        progress=False,
        workers=1,
        study=True,
        **floor,
    )


def test_regime_codes_are_bits_and_combine_over_directions():
    theta, u = [0.0, 0.1, 1e-17, 0.1, 0.1], [1e-32, 0.0, 0.02, 0.01, 0.03]  # below 1e-9: round-off, no motion
    assert regime([False, False, False, False, True], theta, u, 1e-9).tolist() == [
        REST,
        ROCKS,
        SLIDES,
        SLIDES_AND_ROCKS,
        OVERTURNS,
    ]
    # One direction rocks, the other slides: the pulse does both; one overturns: it overturns.
    assert combined_regime(np.array([[ROCKS, SLIDES], [REST, OVERTURNS], [REST, -1]])).tolist() == [
        SLIDES_AND_ROCKS,
        OVERTURNS,
        -1,
    ]


def test_a_map_on_a_floor_with_friction_classes_slides_and_rocks(tmp_path):
    sliding, rocking_ = _map(tmp_path, mu=0.2), _map(tmp_path, mu=0.5)
    bare = {name: envelope(s.data).sel(part="bare").squeeze() for name, s in (("slides", sliding), ("rocks", rocking_))}
    # mu = 0.2 < B/H: the block slides and never lifts; its peak slip is the sliding-only model's 31.45 mm.
    assert int(bare["slides"]["regime"]) == SLIDES
    assert float(bare["slides"]["theta_max"]) == 0.0
    assert float(bare["slides"]["u_max"]) == pytest.approx(31.45e-3, rel=0.01)
    # mu = 0.5 > B/H: it rocks and its base holds.
    assert int(bare["rocks"]["regime"]) == ROCKS
    assert float(bare["rocks"]["u_max"]) == 0.0
    data = sliding.data
    assert data["u_max"].attrs["units"] == "m" and data["u_end"].attrs["units"] == "m"
    assert data["regime"].attrs["flag_meanings"].split()[1:] == list(REGIMES.values())
    assert sliding.summary["bare_slid"] == 1 and rocking_.summary["bare_slid"] == 0
    assert "the base slid without overturning in 1 cells alone" in " ".join(map_lines(sliding))
    # The figure's classes: slid (not overturned) apart from safe; the legend names it.
    env = envelope(data)
    cls = _outcome_classes(env, "bare", env["overturned"].sel(part="bare").values, np.zeros((1, 1), int), False)
    assert cls.tolist() == [[MAP_SLID_CLASSES[SLIDES]]]
    fig = map_figure(sliding)
    labels = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert "not overturned, slides" in labels
    assert r"floor $\mu_s$ = 0.2, $\mu_k$ = 0.2" in fig.get_suptitle()
    assert "floor" not in map_figure(_map(tmp_path)).get_suptitle()  # the paper's floor: the title it had
    table = sliding.tables["map"]
    assert table["bare_regime"].tolist() == ["slides"]


def test_an_adaptive_map_refines_on_the_regime():
    over = np.array([False, False, True])
    classes = response_classes(over, np.array([0, 0, 2]), np.array([1, 1, 0]), np.array([SLIDES, ROCKS, 4]))
    assert len(set(classes.tolist())) == 3  # slid, rocked, overturned after 2 impacts: three classes
    assert classes[2] == 2
    assert response_classes(over, np.array([0, 0, 2]), np.array([1, 1, 0])).tolist() == [-1, -1, 2]


def test_a_map_on_the_papers_floor_keeps_its_variables(tmp_path):
    study = rocking.overturning_map(
        rocking.Block.reference(),
        {"gamma": 0.05},
        Omega=[3.0],
        beta=[2.0],
        full=True,
        runs=tmp_path / "runs",
        progress=False,
        workers=1,
        study=True,
    )
    assert set(study.data.data_vars) == {*FIELDS, "computed"}
    assert "floor" not in study.config
    assert "regime" not in envelope(study.data) and "bare_slid" not in study.summary
    assert not any(k.endswith(("_regime", "_u_max")) for k in study.tables["map"])


def test_the_friction_map_dataset(tmp_path):
    study = rocking.friction_map(
        BLOCK,
        T_g=0.5,
        mu=[0.15, 0.3, 0.5],
        a_g=[0.15 * G, 0.3 * G, 0.4 * G],
        runs=tmp_path / "runs",
        progress=False,
        workers=1,
        study=True,
    )
    data = study.data
    assert data["regime"].dims == ("mu", "beta", "sign")
    assert data.sizes == {"mu": 3, "beta": 3, "sign": 1}
    assert data["a_g"].attrs["units"] == "m/s^2" and data["u_max"].attrs["units"] == "m"
    assert data.attrs["T_g"] == pytest.approx(0.5)
    env = friction_envelope(data)["regime"].values
    # a_g = 0.15 g is below both the floor's hold (mu g) and the uplift threshold (g tan alpha = 0.25 g): rest.
    assert env[:, 0].tolist() == [REST] * 3
    # Below B/H the block slides first, above it rocks first (Shenton 1996).
    assert env[0, 2] == SLIDES and env[2, 2] == ROCKS
    s = study.summary
    assert sum(s[name] for name in REGIMES.values()) == s["cells"] == 9
    assert s["B_over_H"] == 0.25
    fig = friction_figure(study)
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any("B/H" in t for t in texts)


def test_the_friction_map_refuses_a_floor_and_a_bad_frequency(tmp_path):
    with pytest.raises(rocking.ParameterError, match="give Omega or T_g"):
        rocking.friction_map(BLOCK, mu=[0.2, 0.3], beta=[1.0, 2.0], runs=tmp_path, progress=False)
    with pytest.raises(rocking.ParameterError, match="T_g"):
        rocking.friction_map(BLOCK, T_g=-1.0, mu=[0.2, 0.3], beta=[1.0, 2.0], runs=tmp_path, progress=False)


def test_the_friction_command_parses_and_writes(tmp_path, capsys):
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    argv = ["friction", "--H", "2", "--B", "0.5", "--M", "1000", "--T-g", "0.5", "--mu", "0.15", "0.5", "2"]
    argv += ["--a-g", "0.4g", "0.4g", "1", "--out", str(tmp_path), "--workers", "1", "--no-progress", "--pdf"]
    args = parser.parse_args(argv)
    assert args.func(args) == 0
    assert "1 slides" in capsys.readouterr().out
    for suffix in ("nc", "json", "csv", "png", "pdf"):
        assert (tmp_path / f"friction.{suffix}").is_file()
    back = load(tmp_path / "friction")
    assert (
        back.kind == "friction" and back.config["backend"] == "c"
    )  # both back ends follow friction: the studies' default
    assert back.data["mu"].values.tolist() == [0.15, 0.5]
    assert json.loads((tmp_path / "friction.json").read_text())["config"]["pulse_Omega"] == pytest.approx(
        2 * np.pi / (0.5 * BLOCK.p)
    )


def test_an_adaptive_map_fills_in_the_regime_not_a_status(tmp_path):
    """The cells an adaptive map on a finite floor does not compute take the regime around them, and no status."""
    study = rocking.overturning_map(
        BLOCK,
        {"gamma": 0.05},
        T_g=[0.5, 0.6, 0.7, 0.8, 0.9],
        a_g=[0.1 * G, 0.12 * G, 0.14 * G, 0.16 * G, 0.18 * G],
        mu=0.5,
        coarse=4,
        backend="numpy",
        runs=tmp_path / "runs",
        progress=False,
        workers=1,
        study=True,
    )
    data = study.data
    filled = ~data["computed"].values
    assert filled.any()  # every pulse below the uplift and slip thresholds: rest throughout, filled in
    assert (data["regime"].values[filled] == REST).all()
    assert (data["status"].values[filled] == -1).all()
    assert study.tables["map"]["bare_regime"].tolist() == ["rest"] * 25


def test_simulate_says_how_far_the_base_slid(capsys):
    """The issue's sliding-only model: peak 31.45 mm, residual 1.57 mm at mu = 0.2, a_g = 0.4 g, T_g = 0.5 s."""
    from rocking.cli.main import main

    argv = ["simulate", "--H", "2", "--B", "0.5", "--M", "1000", "--a-g", str(0.4 * G), "--omega-g", str(4 * np.pi)]
    assert main([*argv, "--mu", "0.2", "--backend", "numpy"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if "the base slid" in x)
    peak, residual = (float(line.split(f"{name} = ")[1].split(" mm")[0]) for name in ("u_max", "u_end"))
    assert peak == pytest.approx(31.45, rel=0.01) and residual == pytest.approx(1.57, rel=0.01)


def test_an_interrupted_friction_map_resumes_from_its_tiles(tmp_path):
    """The regime map runs on the studies' tiles: an interruption keeps the finished ones, a rerun loads them."""
    from rocking.study.config import Grid, Setting
    from rocking.study.friction_map import friction_map
    from rocking.study.tiles import Execution, Interrupted

    setting = Setting(BLOCK, backend="numpy")
    grids = (4.7, Grid("mu", 0.15, 0.5, 2), Grid("beta", 1.2, 1.6, 2))
    serial = Execution(workers=1, progress=False)

    def interrupt(task):
        raise KeyboardInterrupt

    with pytest.raises(Interrupted):
        friction_map(setting, *grids, serial, runs=tmp_path, tile=(1, 2), on_tile=interrupt)
    resumed = friction_map(setting, *grids, serial, runs=tmp_path, tile=(1, 2))
    assert (resumed.run["tiles_reused"], resumed.run["tiles_computed"]) == (1, 1)
    assert friction_envelope(resumed.data)["regime"].values.tolist() == [[SLIDES, SLIDES], [ROCKS, ROCKS]]
