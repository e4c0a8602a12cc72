"""Studies (map, spectrum) of any generated variant, given by name or folder with explicit parameters."""

from __future__ import annotations

import json

import numpy as np
import pytest

import rocking
from rocking import Block, OneSinePulse
from rocking.cli.main import main
from rocking.model.params import ParameterError
from rocking.sim.cases import pulse_cases
from rocking.study.config import Grid, Setting, Tuning, Variant, config_hash, part_config
from rocking.study.optimize import optimal_damper
from rocking.study.overturning_map import envelope, outcome, overturning_map
from rocking.study.spectrum import envelope as spectrum_envelope
from rocking.study.spectrum import minimum_overturning_spectrum
from rocking.study.tiles import Execution

BLOCK = Block.reference()
SETTING = Setting(BLOCK, backend="c")
SERIAL = Execution(workers=1, progress=False)
OMEGA = Grid("Omega", 1.0, 6.0, 4)
BETA = Grid("beta", 1.0, 6.0, 5)

#: A pendulum whose bob hangs at the omd's mass point (H + h), gamma = 0.05, tuned near p, zeta = 0.05.
L = 0.5
OMEGA_M = BLOCK.p
PENDULUM = {
    "m": 0.05 * BLOCK.M,
    "l": L,
    "x_p": 0.0,
    "y_p": BLOCK.H + 0.05 + L,
    "k_phi": max(0.05 * BLOCK.M * L**2 * (OMEGA_M**2 - BLOCK.g / L), 0.0),
    "c_phi": 2 * 0.05 * 0.05 * BLOCK.M * L**2 * OMEGA_M,
}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    return tmp_path_factory.mktemp("runs")


@pytest.fixture(scope="module")
def pendulum_map(runs):
    return overturning_map(
        SETTING, Variant("pendulum", PENDULUM), OMEGA, BETA, SERIAL, runs=runs, tile=(2, 3), full=True
    )


def test_pendulum_map_agrees_with_simulate(pendulum_map):
    both = envelope(pendulum_map.data)
    for k in ("overturned", "impacts", "theta_max", "x_max", "status"):
        assert both[k].shape == (2, OMEGA.n, BETA.n)  # part, Omega, beta
    assert pendulum_map.config["damper"]["model"] == "pendulum"
    a = both.sel(part="damper")
    assert a["overturned"].any() and not a["overturned"].all()
    assert pendulum_map.config["directions"]["signs"] == [1, -1]  # a Variant may not be symmetric
    for i, j in [(0, 0), (1, 2), (2, 3), (3, 4), (3, 1)]:  # the envelope is the response of the worse direction
        sign = int(a["worst_sign"][i, j])
        pulse = OneSinePulse.from_nondim(BLOCK, beta=float(a["beta"][j]), Omega=float(a["Omega"][i]), sign=sign)
        r = rocking.simulate(BLOCK, PENDULUM, pulse, model="pendulum", backend="c")
        assert a["overturned"][i, j] == r.overturned, (i, j)
        assert a["impacts"][i, j] == r.impacts, (i, j)
        theta = pendulum_map.data["theta_max"].sel(part="damper").values[i, j]
        assert theta.max() == pytest.approx(r.theta_max, rel=1e-12)


def test_pendulum_spectrum(runs):
    study = minimum_overturning_spectrum(
        SETTING,
        Variant("pendulum", PENDULUM),
        Grid("Omega", 2.0, 5.0, 3),
        Grid("beta", 0.5, 6.0, 12),
        SERIAL,
        runs=runs,
    )
    both = spectrum_envelope(study.data)
    assert both["beta_min"].shape == (2, 3)  # part, Omega
    assert both["scan_outcome"].shape == (2, 3, 12)
    a = both.sel(part="damper")
    assert np.isfinite(a["beta_min"]).all()
    for i, Om in enumerate(a["Omega"].values):  # beta_min overturns the pendulum-damped block, in its worse direction
        sign = int(a["worst_sign"][i])
        pulse = OneSinePulse.from_nondim(BLOCK, beta=float(a["beta_min"][i]), Omega=Om, sign=sign)
        assert rocking.simulate(BLOCK, PENDULUM, pulse, model="pendulum", backend="c").overturned


def test_vanishing_pendulum_reproduces_bare_map(runs):
    tiny = Variant("pendulum", {**PENDULUM, "m": 1e-6, "c_phi": 1e-6, "k_phi": 0.0})
    study = overturning_map(SETTING, tiny, OMEGA, BETA, SERIAL, runs=runs, tile=(4, 5))
    a = study.data
    np.testing.assert_array_equal(a["overturned"].sel(part="damper"), a["overturned"].sel(part="bare"))
    # The impacts before overturning; the bare block's safe responses end at their early verdict, the pendulum's
    # (no bound derived for it) at rest, with more impacts.
    damper, bare = (outcome(a["overturned"].sel(part=p), a["impacts"].sel(part=p)) for p in ("damper", "bare"))
    np.testing.assert_array_equal(damper, bare)


def test_changed_variant_parameter_reuses_no_tile(pendulum_map, runs):
    changed = Variant("pendulum", {**PENDULUM, "c_phi": 2 * PENDULUM["c_phi"]})
    before = part_config("map", "damper", SETTING, damper=Variant("pendulum", PENDULUM).record())
    after = part_config("map", "damper", SETTING, damper=changed.record())
    assert config_hash(before) != config_hash(after)
    assert Variant("pendulum", PENDULUM).record()["model_sha256"]
    study = overturning_map(SETTING, changed, OMEGA, BETA, SERIAL, runs=runs, tile=(2, 3), full=True)
    assert study.run["run_folders"]["damper"] != pendulum_map.run["run_folders"]["damper"]
    assert study.run["run_folders"]["bare"] == pendulum_map.run["run_folders"]["bare"]
    assert study.run["tiles_computed"] == 4 and study.run["tiles_reused"] == 4  # the bare part only


def test_variant_by_folder_is_absolute():
    folder = rocking.load_model("pendulum").folder
    v = Variant(str(folder), PENDULUM)
    assert v.name == "pendulum" and v.record()["model"] == "pendulum"
    assert v.record()["model_sha256"] == Variant("pendulum", PENDULUM).record()["model_sha256"]


def test_bad_inputs_give_clear_errors():
    with pytest.raises(ParameterError, match="unknown model 'nosuch'"):
        Variant("nosuch", {})
    with pytest.raises(ParameterError, match="needs parameter\\(s\\) l"):
        Variant("pendulum", {k: v for k, v in PENDULUM.items() if k != "l"})
    with pytest.raises(ParameterError, match="no parameter\\(s\\) gamma"):
        Variant("pendulum", {**PENDULUM, "gamma": 0.05})
    with pytest.raises(ParameterError, match="k_phi must be a finite number"):
        Variant("pendulum", {**PENDULUM, "k_phi": "stiff"})
    with pytest.raises(ParameterError, match="not both"):
        pulse_cases(BLOCK, 2.0, 3.0, gamma=0.05, params=PENDULUM, model="pendulum")
    with pytest.raises(ParameterError, match="needs parameter\\(s\\) c_phi"):
        pulse_cases(BLOCK, 2.0, 3.0, params={k: v for k, v in PENDULUM.items() if k != "c_phi"}, model="pendulum")
    with pytest.raises(ParameterError, match="M set by the block"):
        pulse_cases(BLOCK, 2.0, 3.0, params={**PENDULUM, "M": 1.0}, model="pendulum")
    with pytest.raises(ParameterError, match="l must be finite and > 0"):
        pulse_cases(BLOCK, 2.0, 3.0, params={**PENDULUM, "l": -1.0}, model="pendulum")
    with pytest.raises(ParameterError, match="unknown model"):
        pulse_cases(BLOCK, 2.0, 3.0, params={}, model="nosuch")
    with pytest.raises(ParameterError, match="l must be finite and > 0"):  # refused before any tile runs
        overturning_map(SETTING, Variant("pendulum", {**PENDULUM, "l": 0.0}), OMEGA, BETA, SERIAL, runs="/nonexistent")
    with pytest.raises(ParameterError, match="not a Tuning or a Variant"):
        optimal_damper(SETTING, Variant("pendulum", PENDULUM), OMEGA, BETA, SERIAL)
    with pytest.raises(ParameterError, match="Tuning \\(omd\\) or Variant"):
        overturning_map(SETTING, {"gamma": 0.05}, OMEGA, BETA, SERIAL)
    cases = pulse_cases(BLOCK, [2.0, 3.0], 3.0, params=PENDULUM, model="pendulum")  # the omd path is unchanged
    assert cases.model.name == "pendulum" and cases.p.shape == (2, 12)
    assert pulse_cases(BLOCK, 2.0, 3.0, **Tuning(0.05).record()).model.name == "omd"


def _param_options(params: dict) -> list[str]:
    return [o for k, v in params.items() for o in ("--param", f"{k}={v!r}")]


def test_cli_map_of_a_variant(tmp_path, capsys):
    argv = ["map", "--model", "pendulum", *_param_options(PENDULUM)]
    argv += ["--Omega", "1", "4", "4", "--beta", "1", "6", "4", "--out", str(tmp_path)]
    argv += ["--no-progress", "--workers", "1"]
    assert main(argv) == 0
    for ext in ("nc", "png", "json", "csv"):
        assert (tmp_path / f"map.{ext}").stat().st_size > 0
    record = json.loads((tmp_path / "map.json").read_text())
    assert record["config"]["damper"]["model"] == "pendulum"
    assert record["config"]["damper"]["params"] == PENDULUM
    assert rocking.load(tmp_path / "map").data["overturned"].sel(part="damper").shape == (4, 4, 2)  # and sign
    capsys.readouterr()


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--model", "pendulum", "--gamma", "0.1"], "--gamma: damper options of the omd model"),
        (["--param", "m=1"], "give the model with --model"),
        (["--model", "pendulum", "--param", "m"], "--param takes NAME=VALUE"),
        (["--model", "pendulum", "--param", "m=heavy"], "--param m must be a number"),
        (["--model", "pendulum", "--param", "m=1"], "needs parameter(s) l"),
        (["--model", "nosuch"], "unknown model 'nosuch'"),
    ],
)
def test_cli_bad_variant_options(extra, message, tmp_path, capsys):
    assert main(["spectrum", "--out", str(tmp_path), "--no-progress", "--workers", "1", *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
