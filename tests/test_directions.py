"""Both directions of the pulse in the studies: the choice of signs, the envelope, the mirror symmetry."""

from __future__ import annotations

import numpy as np
import pytest

from rocking import Block
from rocking.model.params import ParameterError
from rocking.sim.cases import pulse_cases, run_cases
from rocking.study.config import Grid, Setting, Tuning, Variant
from rocking.study.directions import beta_min_envelope, choose, response_envelope, worst
from rocking.study.optimize import bare_beta_min, optimal_damper
from rocking.study.overturning_map import envelope, overturning_map
from rocking.study.spectrum import beta_min_or_bound, minimum_overturning_spectrum
from rocking.study.spectrum import envelope as spectrum_envelope
from rocking.study.tiles import Execution

SERIAL = Execution(workers=1, progress=False)
ECCENTRIC = Block.reference()  # e = +0.025 m
SYMMETRIC = Block(H=ECCENTRIC.H, B=ECCENTRIC.B, M=ECCENTRIC.M)
OMEGA, BETA = Grid("Omega", 2.0, 8.0, 4), Grid("beta", 1.0, 9.0, 9)


def test_auto_runs_both_directions_unless_block_and_damper_are_symmetric():
    assert choose("auto", ECCENTRIC, Tuning())["signs"] == [1, -1]
    assert "eccentric (e = 0.025 m)" in choose("auto", ECCENTRIC, Tuning())["reason"]
    symmetric = choose("auto", SYMMETRIC, Tuning(stops=True))
    assert symmetric["signs"] == [1] and "docs/model.md 10.6" in symmetric["reason"]
    assert choose("auto", SYMMETRIC, None)["signs"] == [1]  # the omd damper a study searches
    variant = Variant("pendulum", {"m": 50.0, "l": 0.5, "x_p": 0.0, "y_p": 2.55, "k_phi": 0.0, "c_phi": 1.0})
    assert choose("auto", SYMMETRIC, variant)["signs"] == [1, -1]  # any model: not known to be symmetric
    assert choose("negative", ECCENTRIC, Tuning())["signs"] == [-1]
    assert choose("both", SYMMETRIC, Tuning())["signs"] == [1, -1]
    with pytest.raises(ParameterError, match=r"^directions must be one of auto, both, positive, negative \(got 'up'\)"):
        choose("up", ECCENTRIC, Tuning())


def test_batch_signs_per_case_are_the_single_sign_batches():
    """pulse_cases(sign=array) gives, case by case, the batches of one sign."""
    Omega, beta = np.array([2.0, 4.0, 7.5]), np.array([1.5, 3.0, 10.0])
    mixed = run_cases(pulse_cases(ECCENTRIC, Omega, beta, gamma=0.05, sign=np.array([1, -1, -1])))
    for i, sign in enumerate((1, -1, -1)):
        one = run_cases(pulse_cases(ECCENTRIC, Omega[i], beta[i], gamma=0.05, sign=sign))
        for k in ("overturned", "impacts", "theta_max", "x_max"):
            assert mixed[k][i] == one[k][0]
    with pytest.raises(ParameterError, match=r"^sign must be \+1 or -1, or an array of them"):
        pulse_cases(ECCENTRIC, Omega, beta, sign=np.array([1, 0, 1]))


def test_worse_direction_is_overturned_sooner_then_undetermined_then_larger_rotation():
    overturned = np.array([[True, True], [False, True], [False, False], [False, False]])
    impacts = np.array([[3, 1], [0, 5], [7, 2], [0, 0]])
    theta = np.array([[1.6, 1.6], [0.2, 1.6], [0.1, 0.3], [0.4, 0.3]])
    unknown = np.array([[False, False], [False, False], [True, False], [False, False]])
    np.testing.assert_array_equal(worst(overturned, impacts, theta, unknown), [1, 1, 0, 0])


def test_envelopes_take_the_worse_direction_and_the_largest_maxima():
    by_sign = {
        "overturned": np.array([[False, True]]),
        "impacts": np.array([[4, 2]]),
        "theta_max": np.array([[0.1, 1.6]]),
        "x_max": np.array([[0.3, 0.2]]),
        "status": np.array([[1, 2]]),
    }
    env = response_envelope(by_sign, np.zeros((1, 2), bool))
    assert env["overturned"][0] and env["impacts"][0] == 2 and env["status"][0] == 2
    assert env["x_max"][0] == 0.3 and env["worst_sign_index"][0] == 1
    spectra = {
        "beta_min": np.array([[2.0, 1.5]]),
        "beta_safe": np.array([[1.9, 1.4]]),
        "flag": np.array([[0, 0]]),
        "impacts": np.array([[3, 1]]),
        "undetermined": np.array([[1, 2]]),
        "scan_outcome": np.array([[[-1, -1, 4], [-1, 2, 1]]]),
    }
    env = beta_min_envelope(spectra)
    assert (env["beta_min"][0], env["beta_safe"][0], env["impacts"][0], env["undetermined"][0]) == (1.5, 1.4, 1, 3)
    np.testing.assert_array_equal(env["scan_outcome"][0], [-1, 2, 1])


def test_mirrored_pulse_mirrors_a_symmetric_block(tmp_path):
    """docs/model.md 10.6: with e = 0 the two directions give the same outcomes and maxima."""
    study = overturning_map(
        Setting(SYMMETRIC), Tuning(stops=True), OMEGA, BETA, SERIAL, directions="both", runs=tmp_path
    )
    for part in ("bare", "damper"):
        a = study.data.sel(part=part)
        pos, neg = (a["overturned"].sel(sign=sign).values for sign in (1, -1))
        np.testing.assert_array_equal(pos, neg)
        np.testing.assert_array_equal(a["impacts"].sel(sign=1), a["impacts"].sel(sign=-1))
        np.testing.assert_allclose(a["theta_max"].sel(sign=1), a["theta_max"].sel(sign=-1), rtol=1e-6)
        assert pos.any()


def test_studies_of_an_eccentric_block_report_the_envelope(tmp_path):
    """Map, spectrum and optimisation of the eccentric reference block run both signs; the envelope is the
    worse; the gain is the ratio of the envelopes."""
    setting = Setting(ECCENTRIC)
    study = overturning_map(setting, Tuning(), OMEGA, BETA, SERIAL, runs=tmp_path)
    both = envelope(study.data)
    assert study.summary["directions"]["signs"] == [1, -1]
    for part in ("bare", "damper"):
        by_sign = study.data["overturned"].sel(part=part)
        np.testing.assert_array_equal(both["overturned"].sel(part=part), by_sign.any("sign"))
        assert (by_sign.sel(sign=1) != by_sign.sel(sign=-1)).any()  # the directions differ: one sign would not do
    saved = both["overturned"].sel(part="bare") & ~both["overturned"].sel(part="damper")
    np.testing.assert_array_equal(both["effect"] == 1, saved)
    table = study.tables["map"]
    assert {"bare_outcome_pos", "bare_outcome_neg", "damper_worst_sign"} <= set(table)

    spectrum = minimum_overturning_spectrum(
        setting, Tuning(), OMEGA, Grid("beta", 0.5, 12.0, 24), SERIAL, runs=tmp_path
    )
    both = spectrum_envelope(spectrum.data)
    # A beta_min not reached in the scan is censored (NaN): the envelope compares its lower bound.
    filled = spectrum.data["beta_min"].copy(data=beta_min_or_bound(spectrum.data))
    for part in ("bare", "damper"):
        by_sign = filled.sel(part=part)
        np.testing.assert_array_equal(beta_min_or_bound(both.sel(part=part)), by_sign.min("sign"))
        np.testing.assert_array_equal(
            both["worst_sign"].sel(part=part), np.where(by_sign.sel(sign=1) <= by_sign.sel(sign=-1), 1, -1)
        )

    optimum = optimal_damper(
        setting,
        [0.05],
        Grid("Omega", 4.0, 4.0, 1),
        Grid("beta", 0.5, 12.0, 24),
        SERIAL,
        Tm=Grid("Tm", 1.0, 1.0, 1, log=True),
        refine=0,
        runs=tmp_path,
    )
    o = optimum.data
    bare, damper = (both["beta_min"].sel(part=part).values[[1]] for part in ("bare", "damper"))
    np.testing.assert_allclose(bare_beta_min(o), bare)  # Omega = 4 is the spectrum's 2nd
    np.testing.assert_allclose(o["beta_min"].values, spectrum.data["beta_min"].sel(part="bare").values[[1]])
    np.testing.assert_allclose(o["gain_opt"].values[0], damper / bare)
    assert o["edge_opt"].values[0, 0] == -1  # a grid of one period: its optimum is at the edge


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"stroke": 0.1}, r"^stroke is the half-stroke of the stops: give it with stops=True"),
        ({"stops": True, "stroke": -0.1}, r"^stroke must be in \(0, 1000\] m"),
        ({"stops": True, "stroke": float("nan")}, r"^stroke"),
        ({"stops": True, "stroke": "0.1"}, r"^stroke"),
    ],
)
def test_a_stroke_is_refused_without_stops_or_out_of_range(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        Tuning(**kwargs)


def test_a_stroke_past_the_blocks_edge_is_refused_before_any_work(tmp_path):
    with pytest.raises(ParameterError, match=r"^stroke must be in \(0, B/2\)"):
        pulse_cases(ECCENTRIC, [2.0], [2.0], gamma=0.05, stops=True, stroke=0.3)
    with pytest.raises(ParameterError, match=r"stroke must be in \(0, B/2\)"):
        overturning_map(Setting(ECCENTRIC), Tuning(stops=True, stroke=0.3), OMEGA, BETA, SERIAL, runs=tmp_path)
