"""Studies past beta_f (issue 39, docs/model.md section 16): the landings' restitution e_n reaches the user, a
response that flew is a class of its own (it flew and landed, or flew and overturned), and a vertical study keeps
the flight results."""

import math
import warnings

import numpy as np
import pytest

import rocking
from rocking.cli.main import main
from rocking.plot.figures import map_figure, vertical_spectra_figure
from rocking.sim.problem import STATUS
from rocking.study import ida as ida_module
from rocking.study import overturning_map as overturning_map_module
from rocking.study.config import Grid, Setting, Tuning, config_hash
from rocking.study.fragility import FitWarning
from rocking.study.overturning_map import (
    FLIES_AND_LANDS_CLASS,
    FLIES_AND_OVERTURNS_CLASS,
    FLIGHT_FIELDS,
    UndeterminedWarning,
    envelope,
    overturning_map,
    response_classes,
    undetermined,
)
from rocking.study.spectrum import envelope as spectrum_envelope
from rocking.study.spectrum import minimum_overturning_spectrum
from rocking.study.tiles import Execution
from rocking.study.vocabulary import NOT_COMPUTED

BLOCK = rocking.Block.reference()


def test_a_setting_passes_a_floor_whose_landings_bounce_even_where_it_never_slides():
    plastic, bouncing = Setting(BLOCK), Setting(BLOCK, floor=rocking.Floor(e_n=0.4))
    assert plastic.floor_args() == {} and "floor" not in plastic.record()
    assert bouncing.floor_args() == {"floor": rocking.Floor(math.inf, math.inf, 0.4)}
    # JSON has no inf: the floor that never slides is said by leaving mu_s, mu_k out, a plastic one by leaving e_n out.
    assert bouncing.record()["floor"] == {"e_n": 0.4}
    assert Setting(BLOCK, floor=rocking.Floor(0.5, 0.4)).record()["floor"] == {"mu_s": 0.5, "mu_k": 0.4}
    assert Setting(BLOCK, floor=rocking.Floor(0.5, 0.4, 1.0)).record()["floor"] == {
        "mu_s": 0.5,
        "mu_k": 0.4,
        "e_n": 1.0,
    }
    assert config_hash(plastic.record()) != config_hash(bouncing.record())


def test_the_python_studies_take_the_landings_restitution_as_the_command_line_does(tmp_path):
    study = rocking.overturning_map(
        BLOCK, None, Omega=[4.0], beta=[2.0], e_n=0.5, mu=0.6, runs=tmp_path, workers=1, progress=False, study=True
    )
    assert study.config["floor"] == {"mu_s": 0.6, "mu_k": 0.6, "e_n": 0.5}
    with pytest.raises(rocking.ParameterError, match=r"^e_n must be in \[0, 1\] \(got -0.1\)"):
        rocking.minimum_overturning_spectrum(BLOCK, None, Omega=[4.0], beta=[2.0], e_n=-0.1, runs=tmp_path)


def test_the_command_line_takes_the_landings_restitution_and_a_saved_study_keeps_it(tmp_path, capsys):
    argv = ["map", "--Omega", "4", "4", "1", "--beta", "2", "3", "2", "--full", "--workers", "1", "--no-progress"]
    assert main([*argv, "--vertical-ratio", "0.5", "--e-n", "0.5", "--out", str(tmp_path)]) == 0
    s = rocking.load(tmp_path / "map.nc").summary
    flew = s["bare_flies_and_lands"] + s["bare_flies_and_overturns"]
    assert f"map: the base flew in {flew} cells alone ({s['bare_flies_and_overturns']} then overturned)" in (
        capsys.readouterr().out
    )
    saved = rocking.load(tmp_path / "map.nc")
    assert saved.config["floor"] == {"e_n": 0.5}
    assert saved.data.attrs["e_n"] == 0.5 and math.isinf(saved.data.attrs["mu_s"])
    assert main([*argv, "--e-n", "1.5", "--out", str(tmp_path / "bad")]) == 2
    assert "rocking map: error: --e-n must be in [0, 1] (got 1.5)" in capsys.readouterr().err


@pytest.mark.parametrize("floor", [{"e_n": 2.0}, {"mu_s": 0.5}, {}, {"e_n": 0.0}])
def test_a_saved_floor_is_read_back_only_as_a_study_records_it(floor):
    from rocking.study.storage import _setting

    config = {**Setting(BLOCK).record(), "floor": floor}
    with pytest.raises(rocking.ParameterError, match=r"^(e_n must be in \[0, 1\]|floor: )"):
        _setting(config)


def _flying(real_run_cases, beta_of_flight: float):
    """``run_cases`` whose responses of amplitude ``a_g`` above ``beta_of_flight g tan(alpha)`` flew once (the
    study layer's reading of flights, before a back end flies: their verdicts stay the back end's)."""

    def run_cases(cases, backend="c", threads=1):
        result = dict(real_run_cases(cases, backend, threads))
        flew = np.abs(cases.settings["a_g"]) > beta_of_flight * BLOCK.g * BLOCK.tan_alpha
        result["flights"] = np.where(flew, 1, 0)
        result["flight_time"] = np.where(flew, 0.01, 0.0)
        result["jump_max"] = np.where(flew, 1e-3, 0.0)
        return result

    return run_cases


def _vertical_map(tmp_path, **kwargs):
    setting = Setting(BLOCK, vertical_ratio=0.5)
    grids = (Grid("Omega", 2.0, 10.0, 17), Grid("beta", 1.0, 7.0, 17))  # below beta_f = 8: no status flight
    return overturning_map(setting, Tuning(0.05), *grids, Execution(workers=1, progress=False), runs=tmp_path, **kwargs)


def test_a_map_keeps_the_flights_and_refines_on_the_classes_of_responses_that_flew(tmp_path, monkeypatch):
    monkeypatch.setattr(overturning_map_module, "run_cases", _flying(overturning_map_module.run_cases, 4.2))
    full = _vertical_map(tmp_path / "full", full=True)
    data = full.data
    for k in (*FLIGHT_FIELDS, "flew"):
        assert data[k].dims == ("part", "Omega", "beta", "sign")
    assert data["flight_time"].attrs["units"] == "s" and data["jump_max"].attrs["units"] == "m"
    assert data["flew"].attrs["flag_meanings"] == "not_computed on_the_floor flew"
    flew = data["flew"].values == 1
    assert np.array_equal(flew, data["flights"].values > 0) and flew[:, :, data["beta"].values > 4.2].all()
    classes = response_classes(*(data[k].values for k in ("overturned", "impacts", "status")), None, data["flights"])
    over = data["overturned"].values
    assert np.array_equal(classes == FLIES_AND_OVERTURNS_CLASS, flew & over)
    assert np.array_equal(classes == FLIES_AND_LANDS_CLASS, flew & ~over)
    env = envelope(data)
    s = full.summary
    for part in ("bare", "damper"):
        governing = env["flew"].sel(part=part).values == 1
        a = env["overturned"].sel(part=part).values
        assert s[f"{part}_flies_and_lands"] == (governing & ~a).sum()
        assert s[f"{part}_flies_and_overturns"] == (governing & a).sum()
        assert s[f"{part}_undetermined"] == 0  # a response that flew and landed has its verdict
    # The map's figure draws them as classes of their own, with their legend entries, from the saved study too.
    rocking.save(full, tmp_path / "saved")
    loaded = rocking.load(tmp_path / "saved" / "map.nc")
    assert loaded.summary == full.summary and np.array_equal(loaded.data["flew"].values, data["flew"].values)
    labels = {t.get_text() for legend in map_figure(loaded).legends for t in legend.get_texts()}
    assert {"flies and lands, not overturned", "flies and overturns"} <= labels
    # An adaptive map refines on those classes: where its cells were filled in, they take what the class tells.
    adaptive = _vertical_map(tmp_path / "adaptive", coarse=4).data
    computed = adaptive["computed"].values[..., None] & np.ones(adaptive["sign"].size, bool)
    assert not computed.all()
    assert np.array_equal(adaptive["overturned"].values, over)
    assert np.array_equal(adaptive["flew"].values, data["flew"].values)
    grounded = ~computed & (adaptive["flew"].values == 0)
    assert (adaptive["flights"].values[grounded] == 0).all() and (adaptive["jump_max"].values[grounded] == 0).all()
    aloft = ~computed & (adaptive["flew"].values == 1)
    assert aloft.any() and np.isnan(adaptive["jump_max"].values[aloft]).all()
    assert (adaptive["flights"].values[aloft] == NOT_COMPUTED).all()


def test_a_jammed_landing_and_a_flight_without_flight_functions_have_no_verdict():
    status = np.array([STATUS.index(name) for name in ("jammed", "flight", "rest", "overturned")])
    assert undetermined(status).tolist() == [True, True, False, False]
    classes = response_classes([False, False, False, True], [0, 0, 0, 2], status, None, [1, 0, 1, 1])
    assert classes.tolist() == [-2 - status[0], -2 - status[1], FLIES_AND_LANDS_CLASS, FLIES_AND_OVERTURNS_CLASS]


def test_a_spectrum_counts_the_responses_that_flew_and_says_whether_beta_min_flew(tmp_path, monkeypatch):
    monkeypatch.setattr(overturning_map_module, "run_cases", _flying(overturning_map_module.run_cases, 2.2))
    setting = Setting(BLOCK, vertical_ratio=0.5)
    scan = Grid("beta", 0.5, 7.5, 15)
    study = minimum_overturning_spectrum(
        setting, Tuning(0.05), Grid("Omega", 2.0, 12.0, 6), scan, Execution(workers=1, progress=False), runs=tmp_path
    )
    data = study.data
    beta_min, flew = data["beta_min"].values, data["beta_min_flew"].values
    assert data["flown"].dims == ("part", "Omega", "sign") and np.isfinite(beta_min).any()
    # The planted flights are those above beta = 2.2: beta_min's response flew exactly where beta_min lies above.
    assert np.array_equal(flew == 1, np.nan_to_num(beta_min) > 2.2)
    scanned = np.count_nonzero(scan.values() > 2.2)
    # Every scan amplitude above flew, and the bisection's there: with a verdict, else without.
    assert (data["flown"].values + data["undetermined"].values >= scanned).all()
    env = spectrum_envelope(data)
    for part in ("bare", "damper"):
        assert study.summary[part]["flown"] == env["flown"].sel(part=part).sum()
        assert study.summary[part]["flown"] == data["flown"].sel(part=part).sum()
    # The vertical spectra figure rings those beta_min, with a legend entry that says so.
    labels = [t.get_text() for legend in vertical_spectra_figure([study]).legends for t in legend.get_texts()]
    assert any(label.startswith("ringed: the response overturning") for label in labels)


def test_an_ida_with_a_vertical_component_keeps_the_flights_and_counts_how_they_ended(tmp_path, monkeypatch):
    real = ida_module.run_cases

    def run_cases(cases, backend="c", threads=1):  # the responses that rocked past alpha / 3 flew (planted)
        result = dict(real(cases, backend, threads))
        flew = result["theta_max"] > BLOCK.alpha / 3
        return {**result, "flights": flew.astype(np.int64), "flight_time": 0.01 * flew, "jump_max": 1e-3 * flew}

    monkeypatch.setattr(ida_module, "run_cases", run_cases)
    site = rocking.model.stochastic.SiteModel(arias=0.5, d595=3.0, t_mid=2.0, f_mid=4.0, f_slope=-0.1, zeta_f=0.2)
    suite = rocking.study.suite.suite_of(stochastic=3, seed=7, site=site, vertical_ratio=0.3)
    with pytest.warns(FitWarning):
        study = ida_module.incremental_dynamic_analysis(
            Setting(BLOCK), Tuning(0.05), suite, Grid("level", 1.0, 4.0, 4), Execution(workers=1, progress=False),
            runs=tmp_path, check="none",
        )  # fmt: skip
    data = study.data
    assert data["jump_max"].dims == ("part", "motion", "level", "sign") and data["jump_max"].attrs["units"] == "m"
    flew, over = data["flights"].values > 0, data["overturned"].values.astype(bool)
    assert flew.any() and (flew & over).any()
    assert data["flies_and_lands"].values.tolist() == (flew & ~over).sum(axis=(1, 2, 3)).tolist()
    assert data["flies_and_overturns"].values.tolist() == (flew & over).sum(axis=(1, 2, 3)).tolist()
    plain = rocking.study.suite.suite_of(stochastic=1, seed=7, site=site)
    assert "flights" not in ida_module.response_fields(plain) and "flights" in ida_module.response_fields(suite)


def test_a_vertical_map_past_beta_f_holds_each_cells_flights_and_its_adaptive_map_the_same_classes(tmp_path):
    setting = Setting(BLOCK, vertical_ratio=1.0)  # beta_f = 4
    grids = (Grid("Omega", 4.0, 12.0, 17), Grid("beta", 2.0, 8.0, 17))
    serial = Execution(workers=1, progress=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UndeterminedWarning)  # jammed landings: counted, no verdict
        full = overturning_map(setting, Tuning(0.05, stops=True), *grids, serial, runs=tmp_path, full=True)
        adaptive = overturning_map(setting, Tuning(0.05, stops=True), *grids, serial, runs=tmp_path, coarse=4)
    data = full.data
    flew = data["flew"].values == 1
    assert flew.any() and (flew & data["overturned"].values).any() and (flew & ~data["overturned"].values).any()
    # Each cell is the single run of its pulse (the block alone here, with its flights).
    for Omega, beta in ((8.0, 5.0), (12.0, 7.25), (4.5, 6.5)):
        cell = data.sel(part="bare", Omega=Omega, beta=beta, sign=1)
        pulse = rocking.OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega, vertical=rocking.Vertical(1.0))
        r = rocking.simulate(BLOCK, None, pulse)
        assert int(cell["flights"]) == r.flights and STATUS[int(cell["status"])] == r.status
        # The map's batch runs in lanes: its values to issue 40's bound (tests/test_lanes.py).
        assert (float(cell["flight_time"]), float(cell["jump_max"])) == pytest.approx(
            (r.flight_time, r.jump_max), rel=1e-7
        )
    # The adaptive map, refined on the classes of flight too, finds the same overturning and flights.
    assert not adaptive.data["computed"].values.all()
    for k in ("overturned", "flew"):
        assert np.array_equal(adaptive.data[k].values, data[k].values), k
