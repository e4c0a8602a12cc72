"""Studies in the units of the job (issue 38 item 3): pulse grids in seconds and m/s^2 or g, SI columns, and a
beta_min not reached in the scan stored as censored (NaN with its lower bound)."""

import math

import numpy as np
import pandas as pd
import pytest

import rocking
from rocking.cli.main import main
from rocking.cli.options import acceleration
from rocking.model.records import STANDARD_GRAVITY

#: The job of issue 38: a 2.2 m x 0.6 m, 350 kg showcase with e = 2 cm.
BLOCK = ("--H", "2.2", "--B", "0.6", "--M", "350", "--e", "0.02")
QUICK = ("--workers", "1", "--no-progress")


def _block() -> rocking.Block:
    return rocking.Block(2.2, 0.6, 350.0, 0.02)


def _ratios(block: rocking.Block, T_g, a_g) -> tuple:
    """``Omega`` (increasing) and ``beta`` of the periods and amplitudes, by docs/model.md section 9."""
    T_g, a_g = np.asarray(T_g, float), np.asarray(a_g, float)
    return 2 * math.pi / (T_g[::-1] * block.p), a_g / (block.g * block.B / block.H)


@pytest.mark.parametrize(("text", "value"), [("4.9", 4.9), ("0.5g", 0.5 * STANDARD_GRAVITY), (" 2G ", 2 * 9.80665)])
def test_an_acceleration_is_typed_in_m_per_s2_or_in_g(text, value):
    assert acceleration(text, "--a-g") == pytest.approx(value, rel=1e-15)


def test_an_acceleration_in_another_unit_is_refused_in_one_line():
    with pytest.raises(rocking.ParameterError, match=r"^--a-g takes accelerations in m/s\^2 .* \(got '0.5x'\)$"):
        acceleration("0.5x", "--a-g")


def test_a_spectrum_in_seconds_is_the_spectrum_in_ratios(tmp_path):
    block = _block()
    T_g, a_g = np.linspace(0.3, 2.0, 4), np.linspace(1.0, 12.0, 12)
    Omega, beta = _ratios(block, T_g, a_g)
    keywords = {"runs": tmp_path, "workers": 1, "progress": False}
    si = rocking.minimum_overturning_spectrum(block, None, T_g=T_g, a_g=a_g, **keywords)
    ratios = rocking.minimum_overturning_spectrum(block, None, Omega=Omega, beta=beta, **keywords)
    np.testing.assert_allclose(si["Omega"], Omega, rtol=1e-14)
    np.testing.assert_allclose(si["T_g"], T_g[::-1], rtol=1e-14)
    np.testing.assert_allclose(si["a_g_beta_scan"], a_g, rtol=1e-14)
    np.testing.assert_allclose(si["beta_min"], ratios["beta_min"], rtol=1e-12)
    assert np.isfinite(si["beta_min"]).any()


def test_a_map_and_a_spectrum_in_seconds_and_g_on_the_command_line_are_pythons_in_ratios(tmp_path):
    block = _block()
    T_g, a_g = np.linspace(0.3, 2.0, 4), np.linspace(0.2, 1.0, 5) * STANDARD_GRAVITY
    Omega, beta = _ratios(block, T_g, a_g)
    argv = ["--T-g", "0.3", "2", "4", "--a-g", "0.2g", "1g", "5", *BLOCK, *QUICK]
    assert main(["map", *argv, "--full", "--out", str(tmp_path / "c")]) == 0
    csv = pd.read_csv(tmp_path / "c" / "map.csv")
    python = rocking.overturning_map(
        block, None, Omega=Omega, beta=beta, full=True, runs=tmp_path / "p", workers=1, progress=False, study=True
    )
    table = python.tables["map"]
    np.testing.assert_allclose(csv["Omega [1]"], table["Omega"], rtol=1e-14)
    np.testing.assert_allclose(csv["beta [1]"], table["beta"], rtol=1e-14)
    for part in ("bare", "damper"):
        np.testing.assert_array_equal(csv[f"{part}_outcome"], table[f"{part}_outcome"])
    assert {-1, 1} <= set(csv["bare_outcome"])  # some pulses overturn the block, some do not
    # The SI columns beside the ratios: every period and amplitude given, in s and m/s^2.
    np.testing.assert_allclose(sorted(set(csv["T_g [s]"])), T_g, rtol=1e-12)
    np.testing.assert_allclose(sorted(set(csv["a_g [m/s^2]"])), a_g, rtol=1e-12)

    assert main(["spectrum", *argv, "--out", str(tmp_path / "s")]) == 0
    csv = pd.read_csv(tmp_path / "s" / "spectrum.csv")
    np.testing.assert_allclose(csv["T_g [s]"], T_g[::-1], rtol=1e-12)
    np.testing.assert_allclose(csv["T_g [s]"], 2 * math.pi / (csv["Omega [1]"] * block.p), rtol=1e-14)


@pytest.mark.parametrize("command", ["map", "spectrum", "design"])
@pytest.mark.parametrize(("ratio", "si"), [("--Omega", "--T-g"), ("--beta", "--a-g")])
def test_a_quantity_given_both_ways_is_refused_in_one_line(command, ratio, si, tmp_path, capsys):
    assert main([command, ratio, "1", "2", "3", si, "1", "2", "3", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err == f"rocking {command}: error: give {ratio} or {si}, not both\n"
    assert not any(tmp_path.iterdir())  # refused before any work


def test_a_quantity_given_both_ways_in_python_is_refused(tmp_path):
    with pytest.raises(rocking.ParameterError, match=r"^give Omega or T_g, not both$"):
        rocking.overturning_map(_block(), Omega=[2.0], T_g=[1.0], beta=[1.0], runs=tmp_path, progress=False)
    with pytest.raises(rocking.ParameterError, match=r"^give beta or a_g, one of them$"):
        rocking.minimum_overturning_spectrum(_block(), Omega=[2.0], runs=tmp_path, progress=False)


def test_a_grid_even_in_seconds_is_saved_with_its_values_and_loads_back(tmp_path):
    block = _block()
    grid = rocking.Grid("T_g", 0.3, 2.0, 3)
    study = rocking.minimum_overturning_spectrum(
        block, None, T_g=grid, a_g=[2.0, 6.0, 12.0], runs=tmp_path / "r", workers=1, progress=False, study=True
    )
    rocking.save(study, tmp_path / "out")
    loaded = rocking.load(tmp_path / "out" / "spectrum.nc")
    assert loaded.config["Omega"]["values"] == study.config["Omega"]["values"]
    np.testing.assert_allclose(loaded.data["T_g"], grid.values()[::-1], rtol=1e-14)


def test_a_beta_min_not_reached_in_the_scan_is_censored_with_its_lower_bound(tmp_path):
    from rocking.plot.figures import spectrum_figure
    from rocking.study.spectrum import envelope
    from rocking.study.vocabulary import ABOVE

    # At Omega = 6 the reference block needs beta ~ 2.8 (docs/model.md section 9): a scan up to 0.8 never overturns.
    study = rocking.minimum_overturning_spectrum(
        rocking.Block.reference(), None, Omega=[6.0], beta=[0.5, 0.8], runs=tmp_path / "r", workers=1,
        progress=False, study=True,
    )  # fmt: skip
    for data in (study.data, envelope(study.data)):
        assert (data["flag"] == ABOVE).all()
        assert data["beta_min"].isnull().all()
        assert (data["beta_min_lower_bound"] == 0.8).all()
    rocking.save(study, tmp_path / "o")
    csv = pd.read_csv(tmp_path / "o" / "spectrum.csv")
    assert csv["bare_beta_min [1]"].isna().all() and (csv["bare_beta_min_lower_bound [1]"] == 0.8).all()
    # In SI units beside it: a_g = beta g tan(alpha), censored alike.
    bound = 0.8 * rocking.Block.reference().a_g(1.0)
    assert csv["bare_a_g_min [m/s^2]"].isna().all()
    np.testing.assert_allclose(csv["bare_a_g_min_lower_bound [m/s^2]"], bound, rtol=1e-14)
    loaded = rocking.load(tmp_path / "o" / "spectrum.nc").data
    assert loaded["beta_min"].isnull().all() and (loaded["beta_min_lower_bound"] == 0.8).all()
    # Drawn as a bound (an open triangle, not joined), never as a point of the curve.
    ax = spectrum_figure(study).axes[0]
    at_bound = [line for line in ax.lines if np.isclose(np.asarray(line.get_ydata(), float), 0.8).any()]
    assert at_bound and all(line.get_linestyle() == "None" for line in at_bound)  # the marker and its arrow
    assert any(line.get_marker() == "^" and line.get_markerfacecolor() == "white" for line in at_bound)
    curves = [line for line in ax.lines if line.get_linestyle() == "-"]
    assert len(curves) == 2 and all(np.isnan(np.asarray(line.get_ydata(), float)).all() for line in curves)


def test_the_spectrums_gain_is_the_studys_words_in_python_and_on_the_command_line(tmp_path, capsys):
    """Issue 38 item 1: the gain line the command prints is the study's (its summary and the Dataset's
    ``gain_text``), so that Python tells the same; the command only prints it."""
    argv = ["spectrum", "--H", "2.2", "--B", "0.6", "--M", "350", "--e", "0.02", "--gamma", "0.05"]
    argv += ["--T-g", "0.3", "2", "4", "--a-g", "0.1g", "1.2g", "12", "--workers", "1", "--no-progress"]
    assert main([*argv, "--out", str(tmp_path)]) == 0
    printed = [line for line in capsys.readouterr().out.splitlines() if line.startswith("spectrum: gain")]
    study = rocking.load(tmp_path / "spectrum")
    gain = study.summary["gain"]
    assert printed == [f"spectrum: {gain['text']}"] and gain["frequencies"] >= 1
    assert gain["min"] <= gain["max"] and 0 <= gain["below_1"] <= gain["frequencies"]
    block = _block()
    tuned = {"gamma": 0.05}
    ds = rocking.minimum_overturning_spectrum(
        block,
        tuned,
        T_g=np.linspace(0.3, 2.0, 4),
        a_g=np.linspace(0.1, 1.2, 12) * STANDARD_GRAVITY,
        runs=tmp_path / "py",
        workers=1,
        progress=False,
    )
    assert ds.attrs["gain_text"] == gain["text"]
