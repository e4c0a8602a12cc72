"""One damper from design to study, and the same verdicts from Python as from the command line (issue 38, 1-2)."""

from __future__ import annotations

import argparse
import warnings

import numpy as np
import pytest

import rocking
from rocking.cli.study import add_study_commands
from rocking.study.api import _tuning
from rocking.study.optimize import EdgeWarning
from rocking.study.spectrum import envelope

#: The showcase of issue 38 (2.2 m x 0.6 m, 350 kg, e = 2 cm) and a design whose best damper makes a pulse worse.
BLOCK = rocking.Block(H=2.2, B=0.6, M=350.0, e=0.02)
OMEGA, BETA = [1.237, 8.245], np.linspace(0.25, 7.33, 40)
SEARCH = {"Tm_ratio": rocking.Grid("Tm", 0.1, 10.0, 5, log=True), "zeta_grid": [0.02, 0.5], "refine": 0}
QUIET = {"progress": False, "workers": 1}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    return tmp_path_factory.mktemp("runs")


@pytest.fixture(scope="module")
def designed(runs):
    """The design's study and the warnings it raised, each (category, message)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        study = rocking.design(BLOCK, Omega=OMEGA, beta=BETA, gamma=0.05, runs=runs, study=True, **SEARCH, **QUIET)
    return study, [(w.category, str(w.message), w.filename) for w in caught]


def test_design_from_python_warns_and_carries_the_verdict(designed):
    """The gain 0.956 at Omega = 1.24 (< 1): the verdict "harms", warned as a DesignWarning at the caller's line,
    with the optimum at the smallest T_m p / 2 pi tried warned as an EdgeWarning; the Dataset carries the verdict."""
    study, caught = designed
    assert study.summary["worst_gain"] < 1.0
    assert study.summary["verdict"]["code"] == "harms"
    assert study.summary["verdict"]["text"].startswith("makes some pulses worse: worst gain 0.96 < 1")
    categories = [c for c, _, _ in caught]
    assert rocking.DesignWarning in categories and EdgeWarning in categories
    assert f"design: {study.summary['verdict']['text']}" in [m for _, m, _ in caught]
    assert {f for _, _, f in caught} == {__file__}  # attributed to the user's line, not to the package
    ds = study.to_dataset()
    assert (ds.attrs["verdict"], ds.attrs["verdict_text"]) == ("harms", study.summary["verdict"]["text"])


def test_the_command_line_prints_the_studys_verdict_and_warnings(designed, tmp_path, capsys):
    """`rocking design` with the same inputs: the verdict line and the same warnings, from the study."""
    study, caught = designed
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    block = ["--H", "2.2", "--B", "0.6", "--M", "350", "--e", "0.02", "--gamma", "0.05"]
    grids = ["--Omega", "1.237", "8.245", "2", "--beta", "0.25", "7.33", "40", "--Tm-ratio", "0.1", "10", "5"]
    grids += ["--zeta-grid", "0.02", "0.5", "2", "--refine", "0", "--workers", "1", "--no-progress"]
    args = parser.parse_args(["design", *block, *grids, "--out", str(tmp_path)])
    assert args.func(args) == 0
    printed = capsys.readouterr()
    assert f"design: {study.summary['verdict']['text']}\n" in printed.out
    for _, message, _ in caught:
        assert f"rocking design: warning: {message}\n" in printed.err


def test_a_designs_damper_runs_in_a_spectrum_and_in_simulate(designed, runs):
    """The design's Damper (its stops included) in a spectrum gives the design's own gain over the band; simulate
    takes it as it is."""
    study, _ = designed
    damper = rocking.designed_damper(study)
    assert isinstance(damper, rocking.Damper) and isinstance(damper.stops, rocking.Stops)
    assert rocking.designed_damper(study.to_dataset()) == damper
    assert damper.stops.L == pytest.approx(study.summary["damper"]["L_m"])
    ds = rocking.minimum_overturning_spectrum(BLOCK, damper, Omega=OMEGA, beta=BETA, runs=runs, **QUIET)
    beta_min = envelope(ds)["beta_min"]
    gain = beta_min.sel(part="damper").values / beta_min.sel(part="bare").values
    np.testing.assert_allclose(gain, study.data["gain_opt"].values, rtol=1e-6)
    pulse = rocking.OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0)
    assert rocking.simulate(BLOCK, damper, pulse).status in ("overturned", "rest", "bounded", "t_max")


def test_a_damper_is_the_variant_of_its_model_and_parameters():
    block = rocking.Block.reference()
    damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    assert _tuning(damper) == rocking.Variant("omd", damper.as_params())
    with pytest.raises(rocking.ParameterError, match="m = 0 is the block alone"):
        _tuning(rocking.Damper(m=0.0, k_m=0.0))


def test_tuning_takes_Tm_ratio_as_the_mapping_does():
    assert rocking.Tuning(Tm_ratio=2.0) == _tuning({"Tm_ratio": 2.0}) == rocking.Tuning(omega_ratio=0.5)
    assert rocking.Tuning(Tm_ratio=2.0).Tm_ratio == 2.0
    with pytest.raises(rocking.ParameterError, match="not both"):
        rocking.Tuning(Tm_ratio=2.0, omega_ratio=3.0)
    with pytest.raises(rocking.ParameterError, match="Tm_ratio must be > 0"):
        rocking.Tuning(Tm_ratio=0.0)


def test_the_default_pad_is_one_physical_pad_whatever_the_damper(designed):
    """Stops.at_edges and the studies' stops=True: a 20 mm neoprene pad of 50 x 50 mm, E = 5 MPa (k_b = E A / t =
    6.25e5 N/m), for a soft light damper, a stiff heavy one and the design alike; its damping ratio 0.2 on each
    mass, hence one restitution (docs/model.md section 11)."""
    soft = rocking.Damper.from_nondim(BLOCK, gamma=0.02, omega_ratio=0.5, zeta=0.05)
    stiff = rocking.Damper.from_nondim(BLOCK, gamma=0.2, omega_ratio=10.0, zeta=0.3)
    pads = [rocking.Stops.at_edges(BLOCK, damper) for damper in (soft, stiff)]
    assert pads[0].k_b == pads[1].k_b == designed[0].summary["damper"]["k_b_N_per_m"] == 5e6 * 0.05 * 0.05 / 0.02
    for pad, damper in zip(pads, (soft, stiff)):
        assert pad.c_b / (2 * np.sqrt(pad.k_b * damper.m)) == pytest.approx(0.2)


def test_a_design_saved_before_the_verdict_prints_and_draws_the_same_words(designed):
    """A design saved without `verdict` in its summary (before issue 38): its verdict is made from its summary by
    the same function, for the command's line and the figure's title."""
    import dataclasses

    from rocking.cli.study import design_lines
    from rocking.plot.figures import design_figure

    study, _ = designed
    old = dataclasses.replace(study, summary={k: v for k, v in study.summary.items() if k != "verdict"})
    assert design_lines(old) == design_lines(study)
    titles = [text.get_text() for text in design_figure(old).texts]
    assert any("Damper design: makes some pulses worse" in t for t in titles)
