"""Incremental dynamic analysis and fragility over suites of records and of stochastic motions."""

from __future__ import annotations

import argparse
import dataclasses
import warnings

import numpy as np
import pytest

import rocking
from rocking import Block, Damper, SampledMotion
from rocking.cli.study import add_study_commands
from rocking.model.intensity import pga
from rocking.model.params import ParameterError
from rocking.model.stochastic import SiteModel
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.fragility import FITTED
from rocking.study.ida import envelope, incremental_dynamic_analysis, motion_measure, tile_bounds
from rocking.study.overturning_map import TMaxWarning
from rocking.study.suite import Suite
from rocking.study.tiles import Execution
from rocking.study.vocabulary import FIT_STATUSES

SERIAL = Execution(workers=1, progress=False)
BLOCK = Block.reference()
SETTING = Setting(BLOCK, t_after=5.0)
SITE = SiteModel(arias=0.46, d595=6.0, t_mid=4.0, f_mid=3.0, f_slope=-0.05, zeta_f=0.25, duration=12.0)


def _at2(path, a, dt=0.005):
    header = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "test",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {len(a)}, DT= {dt:.4f} SEC",
    ]
    body = "\n".join("".join(f"{v:15.7E}" for v in a[i : i + 5]) for i in range(0, len(a), 5))
    path.write_text("\n".join(header) + "\n" + body + "\n")
    return path


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    folder = tmp_path_factory.mktemp("records")
    t = np.arange(1201) * 0.005
    shapes = [np.sin(2 * np.pi * f * t) * np.exp(-(((t - 3) / 1.5) ** 2)) for f in (1.0, 1.5, 2.0)]
    return [_at2(folder / f"r{i}.AT2", 0.2 * a) for i, a in enumerate(shapes)]


@pytest.fixture(scope="module")
def ida(records, tmp_path_factory):
    suite = Suite.from_files(records)
    return incremental_dynamic_analysis(
        SETTING,
        Tuning(0.05, stops=True),
        suite,
        Grid("scales", 0.5, 4.0, 8),
        SERIAL,
        runs=tmp_path_factory.mktemp("runs"),
    )


def test_ida_warns_of_responses_cut_at_t_max(records, tmp_path):
    """A t_after of 0.01 s after a record cuts runs still rocking at t_max: the IDA warns with their count."""
    short = Setting(BLOCK, t_after=0.01)
    with pytest.warns(TMaxWarning, match=r"^ida: \d+ response\(s\) reached t_max \(t_after = 0.01 s"):
        study = incremental_dynamic_analysis(
            short, Tuning(0.05), Suite.from_files(records[:1]), Grid("scales", 0.5, 8.0, 6), SERIAL, runs=tmp_path
        )
    assert (study.data["status"] == rocking.sim.problem.STATUS.index("t_max")).any()


def test_ida_outcomes_are_those_of_single_runs_in_the_worse_direction(ida, records):
    """Each cell is the envelope over both directions of rocking.simulate of the record at that scale."""
    both, levels = envelope(ida.data), ida.data["level"].values
    a = both.sel(part="damper")
    damper = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    damper = Damper(m=damper.m, k_m=damper.k_m, c=damper.c, h=0.05, stops=rocking.Stops.at_edges(BLOCK, damper))
    record = rocking.model.records.read_at2(records[1])
    for j in (2, 5, 7):
        runs = [
            rocking.simulate(
                BLOCK,
                damper,
                SampledMotion(record.acceleration, dt=record.dt, sign=sign).scaled(levels[j]),
                t_after=5.0,
            )
            for sign in (1, -1)
        ]
        assert bool(a["overturned"].values[1, j]) == any(r.overturned for r in runs)
        assert a["x_max"].values[1, j] == pytest.approx(max(r.x_max for r in runs), rel=1e-9)
    assert ida.kind == "ida" and ida.data.sizes["motion"] == 3 and ida.summary == {}
    bare = both["overturned"].sel(part="bare")
    assert bare.any() and not bare.all()


def test_ida_summary_and_tables_report_each_motion(ida):
    both, table, levels = envelope(ida.data), ida.tables["ida-motions"], ida.data["level"].values
    assert list(table["motion"]) == ["r0.AT2", "r1.AT2", "r2.AT2"]
    for part in ("bare", "damper"):
        over = both["overturned"].sel(part=part).values.astype(bool)
        first = [levels[row.argmax()] if row.any() else np.nan for row in over]
        np.testing.assert_array_equal(ida.data["first"].sel(part=part), first)
        np.testing.assert_array_equal(ida.data["fraction"].sel(part=part), over.mean(axis=0))
        np.testing.assert_array_equal(table[f"{part}_first"], first)
        reversals = (over[:, :-1] & ~over[:, 1:]).sum(axis=1)
        np.testing.assert_array_equal(table[f"{part}_reversals"], reversals)
        sensitive = ida.data["sensitive"].sel(part=part).values.sum(axis=(1, 2))
        np.testing.assert_array_equal(table[f"{part}_sensitive_responses"], sensitive)
    fits = ida.tables["ida-fit"]
    assert list(fits["part"]) == ["bare", "damper"]
    np.testing.assert_array_equal(fits["fit_status"], ida.data["fit_status"].values)
    np.testing.assert_array_equal(fits["median"], ida.data["median"].values)


def test_fragility_scales_each_motion_to_the_level_of_its_measure(tmp_path):
    suite = Suite.stochastic(SITE, 3, seed=5)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        study = incremental_dynamic_analysis(
            SETTING, Tuning(0.05), suite, Grid("pga", 1.0, 6.0, 6), SERIAL, measure_name="pga", runs=tmp_path
        )
    fit_warned = [w for w in caught if issubclass(w.category, rocking.FitWarning)]
    fitted = [FIT_STATUSES[code] in FITTED for code in study.data["fit_status"].values]
    assert any(fitted) and len(fit_warned) >= sum(fitted)  # three motions: every fitted part is warned, here
    assert {w.filename for w in fit_warned} <= {__file__}
    for i in range(3):
        motion = suite.motion(i)
        assert study.data["im"].values[i] == pytest.approx(pga(motion.a, motion.dt))
    assert study.kind == "fragility" and study.data["median"].attrs["units"] == "m/s^2"
    again = incremental_dynamic_analysis(
        SETTING, Tuning(0.05), suite, Grid("pga", 1.0, 6.0, 6), SERIAL, measure_name="pga", runs=tmp_path
    )
    tiles = 2 * len(tile_bounds(3, 6 * 2))  # three motions of six levels and two directions, each part
    assert again.run["tiles_computed"] == 0 and again.run["tiles_reused"] == study.run["tiles_computed"] == tiles


def test_a_record_changed_after_the_suite_was_made_is_refused(records, tmp_path):
    path = tmp_path / "r.AT2"
    path.write_bytes(records[0].read_bytes())
    suite = Suite.from_files([path])
    path.write_text(path.read_text().replace("E-01", "E-02", 1))
    with pytest.raises(ParameterError, match=r"r.AT2: changed since the suite was made"):
        suite.motion(0)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: Suite.from_files([]), r"a suite needs 1 to"),
        (lambda: Suite.stochastic(SITE, 0, 1), r"^n must be an integer"),
        (lambda: Suite.stochastic(SITE, 2, -1), r"^seed must be an integer >= 0"),
        (lambda: incremental_dynamic_analysis(SETTING, Tuning(), Suite.stochastic(SITE, 1, 0), Grid("x", 1.0, 2.0, 2),
                                              SERIAL, measure_name="pgd"), r"measure must be one of scale, pga"),
    ],
)  # fmt: skip
def test_bad_suites_and_measures_are_refused(call, message):
    with pytest.raises(ParameterError, match=message):
        call()


PULSES = [
    rocking.OneSinePulse.from_period(4.0, 0.6),
    rocking.OneCosinePulse.from_period(4.0, 1.1, sign=-1),
    rocking.RickerWavelet.from_period(4.0, 0.8, antisymmetric=True),
    rocking.MavroeidisPapageorgiou.from_period(4.0, 1.4, gamma_mp=2.0, nu=1.0),
]


@pytest.fixture(scope="module")
def pulse_fragility(tmp_path_factory):
    suite, levels = Suite.from_pulses(PULSES), Grid("a", 2.0, 20.0, 7)
    return incremental_dynamic_analysis(
        SETTING, Tuning(0.05), suite, levels, SERIAL, measure_name="amplitude", runs=tmp_path_factory.mktemp("runs")
    )


def test_a_suite_of_pulses_at_an_amplitude_is_each_pulse_of_that_amplitude_in_the_worse_direction(pulse_fragility):
    """Each cell is the envelope over both directions of rocking.simulate of the pulse with a_g = the level."""
    data, both = pulse_fragility.data, envelope(pulse_fragility.data)
    np.testing.assert_array_equal(data["im"], [4.0] * 4)
    bare, damped = both.sel(part="bare"), both.sel(part="damper")
    damper = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    checked = 0
    for i, pulse in enumerate(PULSES):
        for j in (1, 3, 6):
            a_g = float(data["level"][j])
            scaled = [dataclasses.replace(pulse, a_g=a_g, sign=sign * pulse.sign) for sign in (1, -1)]
            runs = [rocking.simulate(BLOCK, part, motion, t_after=5.0) for part in (None, damper) for motion in scaled]
            assert bool(bare["overturned"][i, j]) == (runs[0].overturned or runs[1].overturned)
            assert bool(damped["overturned"][i, j]) == (runs[2].overturned or runs[3].overturned)
            assert bare["theta_max"].values[i, j] == pytest.approx(max(r.theta_max for r in runs[:2]), rel=1e-9)
            checked += 1
    assert checked == 12 and bare["overturned"].any() and not bare["overturned"].all()
    assert pulse_fragility.data["level"].attrs["units"] == "m/s^2"
    assert pulse_fragility.config["suite"]["pulses"][3]["family"] == "mp"


@pytest.mark.parametrize(
    ("pulse", "name", "exact"),
    [
        (rocking.OneSinePulse.from_period(3.0, 0.5), "pga", 3.0),
        (rocking.OneSinePulse.from_period(3.0, 0.5), "pgv", 2 * 3.0 * 0.5 / (2 * np.pi)),  # 2 a_g / omega_g
        (rocking.OneCosinePulse.from_period(3.0, 0.5, sign=-1), "pgv", 3.0 * 0.5 / (2 * np.pi)),  # a_g / omega_g
        (rocking.OneCosinePulse.from_period(3.0, 0.5), "arias", np.pi / (2 * 9.80665) * 3.0**2 * 0.5 / 2),  # standard g
        (rocking.RickerWavelet.from_period(3.0, 0.5), "pga", 3.0),
        (rocking.MavroeidisPapageorgiou.from_period(3.0, 0.5, gamma_mp=2.0), "pgv", 3.0 * 0.5 / (2 * np.pi)),  # A
    ],
)  # fmt: skip
def test_the_measures_of_a_pulse_are_those_of_its_closed_form(pulse, name, exact):
    assert motion_measure(pulse, name) == pytest.approx(exact, rel=1e-6)


def test_bad_pulse_suites_are_refused(records):
    with pytest.raises(ParameterError, match=r"pulses\[0\] is a SampledMotion"):
        Suite.from_pulses([SampledMotion([0.0, 1.0, 0.0], dt=0.01)])
    with pytest.raises(ParameterError, match=r"measure 'amplitude' is the a_g of a suite of pulses"):
        incremental_dynamic_analysis(
            SETTING, Tuning(), Suite.from_files(records), Grid("a", 1.0, 2.0, 2), SERIAL, measure_name="amplitude"
        )


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--pulses", "mp", "--periods", "1"], "--pulses mp needs --gamma-mp too"),
        (["--pulses", "sine", "--periods", "1", "--nu", "1"], "--gamma-mp and --nu are the shape of --pulses mp"),
        (["--stochastic", "2", "--periods", "1"], "--periods: only with --pulses FAMILY"),
        (["--pulses", "sine"], "--pulses sine needs --periods"),
        (["--pulses", "sine", "--periods", "1", "--seed", "2"], "--pulses makes its own suite: no --seed"),
        (["--pulses", "cosine", "--periods", "1", "-1"], "T_g must be > 0 s (got -1.0)"),
        (["--pulses", "cosine", "--periods", "1", "--amplitude", "nan"], "a_g must be finite (got nan)"),
    ],
)  # fmt: skip
def test_cli_pulse_suites_refuse_bad_options(argv, message, capsys, tmp_path):
    assert _cli(["fragility", *argv, "--out", str(tmp_path)]) == 2
    assert message in capsys.readouterr().err


def test_cli_fragility_of_pulses_against_their_amplitude(tmp_path, capsys):
    argv = [
        "fragility",
        "--pulses",
        "ricker",
        "--periods",
        "0.5",
        "1",
        "--amplitude",
        "2",
        "--im",
        "amplitude",
        "--levels",
        "2",
        "12",
        "3",
        "--workers",
        "1",
        "--no-progress",
        "--t-after",
        "5",
        "--out",
        str(tmp_path),
    ]
    assert _cli(argv) == 0
    study = rocking.study.storage.load(tmp_path / "fragility.json")
    assert study.data["im"].values.tolist() == [2.0, 2.0]
    assert [p["T_g"] for p in study.config["suite"]["pulses"]] == pytest.approx([0.5, 1.0])
    assert "fragility, bare:" in capsys.readouterr().out


def _cli(argv):
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    return args.func(args)


def test_cli_ida_and_fragility_write_data_and_print_the_fits(records, tmp_path, capsys):
    base = ["--workers", "1", "--no-progress", "--t-after", "5"]
    assert (
        _cli(["ida", "--motions", *map(str, records), "--scales", "0.5", "4", "4", "--out", str(tmp_path / "i"), *base])
        == 0
    )
    assert (
        _cli(
            [
                "fragility",
                "--stochastic",
                "2",
                "--seed",
                "1",
                "--duration",
                "12",
                "--d595",
                "6",
                "--t-mid",
                "4",
                "--levels",
                "1",
                "6",
                "3",
                "--out",
                str(tmp_path / "f"),
                *base,
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert "ida, bare:" in out and "fragility, damper:" in out
    for name in ("i/ida.png", "i/ida-motions.csv", "f/fragility.png", "f/fragility.json"):
        assert (tmp_path / name).is_file()
    assert _cli(["fragility", "--motions", str(records[0]), "--stochastic", "2", *base]) == 2
    assert "give one of --motions FILES, --stochastic N or --pulses FAMILY" in capsys.readouterr().err


def test_cli_simulate_a_record_scaled_by_a_factor_or_to_a_pga(records, capsys):
    from rocking.cli.main import main

    argv = ["simulate", "--motion", str(records[0]), "--scale", "1.5", "--gamma", "0.05", "--omega-ratio", "1"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    peak = 1.5 * np.max(np.abs(rocking.model.records.read_at2(records[0]).acceleration))
    assert f"PGA={peak:.4g} m/s2" in out and "with damper:" in out
    assert main(["simulate", "--motion", str(records[0]), "--pga", "3", "--json"]) == 0
    assert '"pga": 3.0' in capsys.readouterr().out
    assert main(["simulate", "--motion", str(records[0]), "--beta", "2"]) == 2
    assert "--beta: options of a pulse; --motion gives a recorded motion" in capsys.readouterr().err


def _extrapolation_warnings(caught) -> list:
    return [w for w in caught if issubclass(w.category, rocking.FitWarning) and "extrapolated" in str(w.message)]


def test_a_median_above_the_levels_tested_warns_and_is_marked_and_an_unchecked_suite_says_so(tmp_path):
    """Three Ricker pulses at 1 to 3 m/s^2: with the damper one of three overturns the block at 3 m/s^2 and the fitted
    median lies above it: a FitWarning naming the median, the level and the fraction, the Dataset's and the tables'
    ``median_extrapolated``, the printed line and the figure say it; the block alone's median lies within the levels:
    no such warning. Pulses are not checked against the tolerance: no ``sensitive``, NaN counts, "not checked"."""
    from rocking.cli.study import fit_lines
    from rocking.plot.figures import ida_figure
    from rocking.study.fragility import MEDIAN_PLACES

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        study = rocking.fragility(
            BLOCK, {"gamma": 0.05}, pulses="ricker", periods=[1.0, 2.0, 4.0], amplitude=3.0, levels=[1.0, 2.0, 3.0],
            im="amplitude", t_after=5.0, runs=tmp_path, workers=1, progress=False, study=True,
        )  # fmt: skip
    data = study.data
    places = [MEDIAN_PLACES[code] for code in data["median_extrapolated"].values]
    assert places == ["within_levels", "above_levels"]
    bare, damper = (float(data["median"].sel(part=p)) for p in ("bare", "damper"))
    assert 1.0 <= bare <= 3.0 < damper
    fraction = float(data["fraction"].sel(part="damper", level=3.0))
    assert 0 < fraction < 0.5
    extrapolated = _extrapolation_warnings(caught)
    assert [str(w.message) for w in extrapolated] == [
        f"block with the damper: the fitted median {damper:.4g} m/s^2 lies above the highest level tested, 3 m/s^2, "
        f"at which {100 * fraction:.0f} % of the motions overturn the block: the median is extrapolated, not measured; "
        "test higher levels"
    ]
    assert extrapolated[0].filename == __file__
    fits = study.tables["fragility-fit"]
    np.testing.assert_array_equal(fits["median_extrapolated"], data["median_extrapolated"].values)
    lines = fit_lines(study)
    assert "extrapolated" not in lines[0] and f"the fitted median {damper:.4g} m/s^2 lies above" in lines[1]
    # Not checked: nothing is marked sensitive or not, the counts are NaN and the words say so.
    assert "sensitive" not in data and not any(k.endswith("_sensitive") for k in study.tables["fragility"])
    assert np.isnan(data["sensitive_responses"]).all() and np.isnan(data["sensitive_fraction"]).all()
    assert np.isnan(study.tables["fragility-motions"]["damper_sensitive_responses"]).all()
    unchecked = "sensitivity to the tolerance not checked (pulses are checked only with --check tolerance)"
    assert all(line.endswith(unchecked) for line in lines)
    legend = [t.get_text() for t in ida_figure(study).axes[0].get_legend().get_texts()]
    assert "with damper: median above the highest level tested: extrapolated" in legend
    assert any(t.startswith("lognormal fit: median") and "(extrapolated)" in t for t in legend)


def test_a_suite_checked_against_the_tolerance_counts_its_sensitive_responses_and_one_not_checked_does_not(
    records, tmp_path
):
    """A record at three scales: checked by default, ``sensitive`` and its counts are there (0 or more, never NaN);
    with ``check="none"`` they are not: NaN, and the words say "not checked"."""
    from rocking.cli.study import fit_lines

    suite, scales = Suite.from_files(records[:1]), Grid("scales", 0.5, 2.0, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rocking.FitWarning)
        runs = [
            incremental_dynamic_analysis(SETTING, Tuning(0.05), suite, scales, SERIAL, runs=tmp_path, check=check)
            for check in (None, "none")
        ]
    checked, unchecked = (study.data for study in runs)
    assert checked["sensitive"].dtype == bool and not np.isnan(checked["sensitive_responses"]).any()
    assert "sensitive" not in unchecked and np.isnan(unchecked["sensitive_responses"]).all()
    assert "bare_sensitive" in runs[0].tables["ida"] and "bare_sensitive" not in runs[1].tables["ida"]
    assert all("responses sensitive to the tolerance" in line for line in fit_lines(runs[0]))
    assert all(line.endswith("not checked (--check none)") for line in fit_lines(runs[1]))
