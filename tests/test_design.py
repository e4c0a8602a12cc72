"""The design answer: one damper with stops for a band of pulses, both directions (rocking design)."""

from __future__ import annotations

import argparse

import numpy as np
import pytest

import rocking
from rocking import Block, Damper, OneSinePulse, Stops
from rocking.cli.study import add_study_commands
from rocking.model.params import ParameterError
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.design import best_candidate, design, design_table, edge_warnings, envelope, stroke_use, verdict
from rocking.study.overturning_map import TMaxWarning
from rocking.study.spectrum import envelope as spectrum_envelope
from rocking.study.spectrum import minimum_overturning_spectrum
from rocking.study.tiles import Execution
from rocking.study.vocabulary import ABOVE

SERIAL = Execution(workers=1, progress=False)
SETTING = Setting(Block.reference())
BAND, BETA = Grid("Omega", 4.0, 6.0, 2), Grid("beta", 0.5, 20.0, 27)
SEARCH = {"Tm": Grid("Tm", 0.5, 4.0, 3, log=True), "zeta": Grid("zeta", 0.02, 0.2, 2, log=True), "refine": 1}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    return tmp_path_factory.mktemp("runs")


@pytest.fixture(scope="module")
def small(runs):
    return design(SETTING, BAND, BETA, SERIAL, runs=runs, **SEARCH)


def test_design_is_the_best_damper_that_keeps_its_mass_on_the_block(small):
    a, s = small.data, small.summary
    assert s["directions"]["signs"] == [1, -1]
    worst = np.nanmin(a["candidate_gain"].values, axis=1)
    np.testing.assert_array_equal(a["candidate_worst_gain"].values, worst)
    on = a["candidate_on_block"].values
    assert on.any()
    assert s["worst_gain"] == pytest.approx(worst[on].max())
    assert s["worst_gain"] == pytest.approx(np.nanmin(a["gain_opt"].values))
    # The gain is the ratio of the envelopes over the directions: the reduction over sign.
    beta_min = envelope(a)["beta_min"]
    np.testing.assert_allclose(a["gain_opt"], beta_min.sel(part="damper") / beta_min.sel(part="bare"))
    np.testing.assert_array_equal(beta_min, a["beta_min"].min("sign"))
    # Coarse, then 1 along T_m and 1 along zeta: the best is at T_m's largest and zeta's smallest, refined inwards.
    assert (s["Tm_at_edge"], s["zeta_at_edge"]) == (1, -1)
    assert a["candidate_r"].size == s["candidates"] == 3 * 2 + 1 + 1
    d = s["damper"]
    m, omega_m = d["gamma"] * SETTING.block.M, 2 * np.pi / d["T_m_s"]
    assert (d["m_kg"], d["k_m_N_per_m"]) == pytest.approx((m, m * omega_m**2))
    assert d["c_N_s_per_m"] == pytest.approx(2 * d["zeta"] * m * omega_m)
    assert d["L_m"] == pytest.approx(SETTING.block.B / 2 - 0.02)


def test_design_gain_is_what_the_spectrum_gives_for_that_damper(small, tmp_path):
    """The same damper through minimum_overturning_spectrum (a Tuning with stops and the stroke): the same gain."""
    d = small.summary["damper"]
    tuning = Tuning(
        gamma=d["gamma"], omega_ratio=1 / d["Tm_ratio"], zeta=d["zeta"], h=d["h_m"], stops=True, stroke=d["L_m"]
    )
    spectrum = minimum_overturning_spectrum(SETTING, tuning, BAND, BETA, SERIAL, runs=tmp_path)
    beta_min = spectrum_envelope(spectrum.data)["beta_min"]
    gain = beta_min.sel(part="damper") / beta_min.sel(part="bare")
    np.testing.assert_allclose(small.data["gain_opt"], gain, rtol=1e-12)


def test_design_stroke_use_is_that_of_single_runs(small):
    """x_max / L at the bare block's beta_min, both directions, through rocking.simulate and a Damper with Stops."""
    block, d, data = SETTING.block, small.summary["damper"], small.data
    stops = Stops(L=d["L_m"], k_b=d["k_b_N_per_m"], c_b=d["c_b_N_s_per_m"])
    damper = Damper(m=d["m_kg"], k_m=d["k_m_N_per_m"], c=d["c_N_s_per_m"], h=d["h_m"], stops=stops)
    bare = envelope(data)["beta_min"].sel(part="bare").values
    for i, Om in enumerate(data["Omega"].values):
        runs = {
            sign: rocking.simulate(block, damper, OneSinePulse.from_nondim(block, beta=bare[i], Omega=Om, sign=sign))
            for sign in (1, -1)
        }
        for sign, run in runs.items():
            at = {"Omega": Om, "sign": sign}
            assert data["stroke_use"].sel(at).item() == pytest.approx(run.x_max / d["L_m"], rel=1e-9)
            assert data["stop_contacts"].sel(at).item() == run.stop_contacts
        assert stroke_use(data)[i] == pytest.approx(max(r.x_max for r in runs.values()) / d["L_m"], rel=1e-9)


def test_design_resumes_from_its_tiles(small, runs):
    again = design(SETTING, BAND, BETA, SERIAL, runs=runs, **SEARCH)
    assert again.run["tiles_computed"] == 0 and again.run["tiles_reused"] == small.summary["candidates"] + 1
    assert again.summary == small.summary


def test_optimum_at_an_edge_is_flagged(runs):
    """A one-point grid: the optimum is both ends of it."""
    study = design(
        SETTING,
        BAND,
        BETA,
        SERIAL,
        runs=runs,
        Tm=Grid("Tm", 1.0, 1.0, 1, log=True),
        zeta=Grid("zeta", 0.05, 0.05, 1, log=True),
        refine=0,
    )
    assert study.summary["Tm_at_edge"] == -1 and study.summary["zeta_at_edge"] == -1


def test_design_warns_of_responses_cut_at_t_max(tmp_path):
    """A t_after of 0.01 s cuts the runs at t_max: the design warns with their count."""
    short = Setting(Block.reference(), t_after=0.01)
    search = {"Tm": Grid("Tm", 0.5, 4.0, 2, log=True), "zeta": Grid("zeta", 0.02, 0.2, 2, log=True), "refine": 0}
    with pytest.warns(TMaxWarning, match=r"^design: \d+ response\(s\) reached t_max \(t_after = 0.01 s"):
        design(short, Grid("Omega", 4.0, 4.0, 1), BETA, SERIAL, runs=tmp_path, **search)


def test_best_candidate_prefers_dampers_on_the_block_then_shorter_periods():
    r, z = np.array([1.0, 2.0, 0.5, 3.0]), np.array([0.1, 0.1, 0.1, 0.1])
    assert best_candidate(r, z, [1.2, 1.5, 1.5, 2.0], [True, True, True, False]) == 2
    assert best_candidate(r, z, [1.2, 1.5, 1.5, 2.0], [False] * 4) == 3  # none on the block: the best, flagged


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"stroke": 0.25}, r"stroke must be in \(0, B/2\)"),
        ({"gamma": 0.0}, r"gamma"),
        ({"Tm": Grid("Tm", 0.5, 2.0, 3)}, r"logarithmic"),
        ({"refine": -1}, r"refine must be an integer"),
        ({"directions": "up"}, r"directions must be one of"),
    ],
)
def test_bad_design_input_is_refused_naming_it(kwargs, message, tmp_path):
    with pytest.raises(ParameterError, match=message):
        design(SETTING, BAND, BETA, SERIAL, runs=tmp_path, **kwargs)


def test_cli_design_writes_data_and_prints_the_damper_in_si(tmp_path, capsys):
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(
        [
            "design",
            "--Omega",
            "4",
            "6",
            "2",
            "--beta",
            "0.5",
            "20",
            "27",
            "--Tm-ratio",
            "0.5",
            "4",
            "3",
            "--zeta-grid",
            "0.02",
            "0.2",
            "2",
            "--refine",
            "1",
            "--workers",
            "1",
            "--no-progress",
            "--out",
            str(tmp_path),
        ]
    )
    assert args.func(args) == 0
    out = capsys.readouterr().out
    assert "design: m = 50 kg (gamma = 0.05), k_m = " in out and "N s/m" in out
    assert "pulses of sign +1 and -1" in out
    summary = rocking.study.storage.load(tmp_path / "design").summary
    assert f"design: {summary['verdict']['text']}\n" in out  # the study's verdict in words, its own line
    for name in ("design.nc", "design.json", "design.csv", "design-candidates.csv", "design.png"):
        assert (tmp_path / name).is_file()
    assert rocking.study.storage.load(tmp_path / "design").summary["worst_gain"] > 0


def test_demo_runs_the_damper_as_built_beside_the_unlimited_guide(tmp_path, capsys, monkeypatch):
    """`rocking demo` on small grids: maps and spectra with stops and unlimited, the design and Omega*, each saved
    under its own name with its own tables."""
    import rocking.cli.study as study_cli

    for name, grid in (
        ("MAP_OMEGA", (2.0, 8.0, 3)),
        ("MAP_BETA", (1.0, 9.0, 3)),
        ("SPECTRUM_OMEGA", (2.0, 8.0, 3)),
        ("SPECTRUM_BETA", (0.5, 15.0, 12)),
        ("DESIGN_OMEGA", (4.0, 6.0, 2)),
        ("LAM_GRID", (4.0, 4.0, 1)),
        ("P_GRID", (2.0, 2.0, 1)),
        ("OMEGA_GRID", (4.0, 14.0, 2)),
        ("VERTICAL_OMEGA", (2.0, 8.0, 2)),
        ("VERTICAL_BETA", (0.5, 9.0, 6)),
    ):
        monkeypatch.setattr(study_cli, name, grid)
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(["demo", "--workers", "2", "--no-progress", "--out", str(tmp_path)])
    assert args.func(args) == 0
    out = capsys.readouterr().out
    assert "only with the mass past the block's edge" in out and "design: m = 50 kg" in out
    for stem in ("map", "map-unlimited", "spectrum", "spectrum-unlimited", "design", "threshold"):
        assert (tmp_path / f"{stem}.png").is_file() and (tmp_path / f"{stem}.json").is_file()
    assert (tmp_path / "spectrum-vertical.png").is_file() and (tmp_path / "spectrum-vertical-1.json").is_file()
    assert rocking.study.storage.load(tmp_path / "spectrum-vertical-0p5").config["vertical"]["ratio"] == 0.5
    assert (tmp_path / "spectrum-unlimited-windows.csv").is_file() and (tmp_path / "map-unlimited.csv").is_file()
    stopped, unlimited = (rocking.study.storage.load(tmp_path / stem) for stem in ("map", "map-unlimited"))
    assert stopped.config["damper"]["stops"] and "stops" not in unlimited.config["damper"]


def _summary(worst, lower_bound=False, Tm_edge=0, zeta_edge=0) -> dict:
    return {
        "worst_gain": worst,
        "worst_at_Omega": 2.0,
        "worst_gain_is_lower_bound": lower_bound,
        "Tm_at_edge": Tm_edge,
        "zeta_at_edge": zeta_edge,
    }


@pytest.mark.parametrize("summary, text", [
    (_summary(1.15), "helps: worst gain 1.15 over the band (at Omega = 2)"),
    (_summary(1.15, lower_bound=True),
     "helps: worst gain 1.15 over the band (at Omega = 2, a lower bound: the damped block survived the scan there)"),
    (_summary(1.0), "no useful gain (worst gain 1.00 <= 1.01, at Omega = 2)"),
    (_summary(1.01), "no useful gain (worst gain 1.01 <= 1.01, at Omega = 2)"),
    (_summary(0.93), "makes some pulses worse: worst gain 0.93 < 1 (at Omega = 2); no damper of this budget and "
                     "stroke helps over the whole band"),
    (_summary(None), "no verdict: the gain is undefined over the whole band (the block alone survives the beta scan; "
                     "widen beta= / --beta)"),
])  # fmt: skip
def test_design_verdict_in_words(summary, text):
    """What the design achieved, in words: a gain of at most 1.01 (the Omega* threshold) is no useful gain."""
    assert verdict(summary)["text"] == text


def test_design_edge_warnings_name_the_option_that_widens_the_range():
    damper = {"Tm_ratio": 0.1, "zeta": 0.5}
    assert edge_warnings({**_summary(1.2), "damper": damper}) == []
    assert edge_warnings({**_summary(1.2, Tm_edge=-1, zeta_edge=1), "damper": damper}) == [
        "design: the optimal T_m p / 2 pi = 0.1 is the smallest of its search range: the best may lie beyond; widen "
        "it (Tm_ratio= / --Tm-ratio MIN MAX N, MIN below 0.1)",
        "design: the optimal zeta = 0.5 is the largest of its search range: the best may lie beyond; widen it "
        "(zeta_grid= / --zeta-grid MIN MAX N, MAX above 0.5)",
    ]


def test_a_beta_min_not_reached_is_censored_in_the_designs_table(small):
    """Issue 38 item 3: in design.csv a beta_min the scan did not reach is NaN beside its lower bound (the scan's
    end), never the scan's end as a value; one direction's flag is set to ABOVE here so that the case is there."""
    data = small.data.copy(deep=True)
    data["flag"].loc[{"part": "damper", "sign": -1, "Omega": data["Omega"].values[0]}] = ABOVE
    table = design_table(data)
    for part in ("bare", "damper"):
        for sign, name in ((1, "pos"), (-1, "neg")):
            raw = data["beta_min"].sel(part=part, sign=sign).values
            above = data["flag"].sel(part=part, sign=sign).values == ABOVE
            value, bound = table[f"{part}_beta_min_{name}"], table[f"{part}_beta_min_lower_bound_{name}"]
            np.testing.assert_array_equal(value, np.where(above, np.nan, raw))
            np.testing.assert_array_equal(bound, np.where(above, raw, np.nan))
    assert np.isnan(table["damper_beta_min_neg"][0]) and table["damper_beta_min_lower_bound_neg"][0] > 0
