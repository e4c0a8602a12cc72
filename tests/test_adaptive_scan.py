"""Spectra scan every amplitude (issue 35): the bench spectrum's one-amplitude band that an adaptive scan stepped
over is found; the adaptive scans of earlier versions are gone, and what they saved is refused or said in one line."""

from __future__ import annotations

import json

import numpy as np
import pytest

import rocking
from rocking.cli.main import main
from rocking.cli.study import SPECTRUM_BETA, spectrum_lines
from rocking.study.config import Grid, Setting, Tuning, config_hash
from rocking.study.spectrum import beta_min, minimum_overturning_spectrum
from rocking.study.storage import summary_hash
from rocking.study.tiles import Execution

#: The bench spectrum (bench/adaptive_spectrum.py): the reference block and the bench damper.
BENCH = Setting(rocking.Block.reference(), rtol=1e-8)
BENCH_DAMPER = Tuning(0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
SPECTRUM = ["spectrum", "--Omega", "2", "6", "3", "--beta", "0.5", "10", "20", "--no-progress", "--workers", "1"]


def test_the_full_scan_finds_the_one_amplitude_band_below_a_safe_stretch():
    """At Omega = 3, pulses of negative sign, the damped bench block overturns at one scan amplitude, beta =
    1.875, and at none of the next ones up to 3.25: a band that a scan skipping that amplitude cannot see (an
    adaptive scan of step 16 reported 3.252, issue 35). The full scan brackets beta_min just below it."""
    beta = Grid("beta", *SPECTRUM_BETA).values()
    full = beta_min(BENCH, [3.0], beta, BENCH_DAMPER.case_args(), sign=-1)
    over = full["scan_outcome"][0] >= 0
    assert beta[11] == 1.875 and over[11] and not over[:11].any() and not over[12:22].any() and beta[22] == 3.25
    assert full["beta_min"][0] == pytest.approx(1.857, abs=1e-3)
    assert full["scan_responses"][0] == beta.size and full["responses"][0] > beta.size  # every amplitude, bisected


def test_spectra_have_no_coarse_step_any_more(tmp_path, capsys):
    grids = Grid("Omega", 2.0, 6.0, 3), Grid("beta", 0.5, 10.0, 20)
    execution = Execution(workers=1, progress=False)
    with pytest.raises(TypeError, match="coarse"):
        minimum_overturning_spectrum(BENCH, BENCH_DAMPER, *grids, execution, runs=tmp_path, coarse=4)
    with pytest.raises(TypeError, match="coarse"):
        beta_min(BENCH, [2.0], [1.0, 2.0], coarse=4)
    with pytest.raises(SystemExit):
        main([*SPECTRUM, "--out", str(tmp_path), "--coarse", "8"])
    assert "rocking spectrum: error: unrecognized arguments: --coarse" in capsys.readouterr().err
    study = minimum_overturning_spectrum(BENCH, BENCH_DAMPER, *grids, execution, runs=tmp_path)
    assert study.config["refinement"] == {"adaptive": False}  # the key of the full spectra of earlier versions
    assert study.run["scan_responses"] == 2 * 3 * 2 * 20  # parts, Omega, signs, amplitudes


def _as_saved_before(path, coarse) -> None:
    """Make the study saved at ``path`` one of an earlier version: its command gave ``--coarse`` (None: not
    given) and, given, its configuration records adaptive scans; the hashes made again, as that version wrote."""
    record = json.loads(path.read_text())
    record["command"]["options"]["coarse"] = coarse
    if coarse is not None:
        refinement = {"adaptive": True, "coarse": coarse, "verify": coarse}
        record["config"]["refinement"] = record["summary"]["refinement"] = refinement
        record["config_sha256"] = config_hash(record["config"])
        record["summary_sha256"] = summary_hash(record["summary"])
    path.write_text(json.dumps(record))


def test_a_spectrum_saved_with_adaptive_scans_loads_and_says_so_and_its_rerun_is_refused(tmp_path, capsys):
    assert main([*SPECTRUM, "--out", str(tmp_path / "a")]) == 0
    full = rocking.load(tmp_path / "a" / "spectrum.json")
    assert not any("adaptive" in line for line in spectrum_lines(full))
    _as_saved_before(tmp_path / "a" / "spectrum.json", 16)
    old = rocking.load(tmp_path / "a" / "spectrum.json")
    assert np.array_equal(old.data["beta_min"].values, full.data["beta_min"].values)
    said = [line for line in spectrum_lines(old) if "adaptive" in line]
    assert said == [
        "spectrum: saved by an earlier version with adaptive scans (coarse step 16): amplitudes not computed took "
        "the outcome around them: a band of overturning amplitudes between them may have been missed, and "
        "beta_min be too high; run it again to scan every amplitude"
    ]
    capsys.readouterr()
    config = ["spectrum", "--config", str(tmp_path / "a" / "spectrum.json"), "--no-progress", "--workers", "1"]
    assert main([*config, "--out", str(tmp_path / "b")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "option coarse = 16 was removed: adaptive beta scans" in err, err
    assert not (tmp_path / "b").exists()


def test_a_spectrum_saved_before_without_coarse_reruns_exactly(tmp_path, capsys):
    assert main([*SPECTRUM, "--out", str(tmp_path / "a")]) == 0
    _as_saved_before(tmp_path / "a" / "spectrum.json", None)
    capsys.readouterr()
    config = ["spectrum", "--config", str(tmp_path / "a" / "spectrum.json"), "--no-progress", "--workers", "1"]
    assert main([*config, "--out", str(tmp_path / "b")]) == 0
    assert (
        f"spectrum: the configuration of {tmp_path / 'a' / 'spectrum.json'}, rerun exactly" in capsys.readouterr().out
    )
