"""Adaptive beta scans of spectra (rocking.study.adaptive.refine_scan): the full scan's results wherever no feature
is narrower than the coarse step, from fewer responses."""

from __future__ import annotations

import argparse

import numpy as np
import pytest

from rocking import Block
from rocking.cli.study import SPECTRUM_BETA, SPECTRUM_OMEGA, add_study_commands
from rocking.model.params import ParameterError
from rocking.study.adaptive import narrowest_feature, refine_scan
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.spectrum import (
    COLUMN_FIELDS,
    SCAN_COARSE,
    beta_min,
    envelope,
    minimum_overturning_spectrum,
    safe_windows,
)
from rocking.study.tiles import Execution

POOL = Execution(workers=2, progress=False)
#: The bench spectrum (bench/adaptive_spectrum.py): rocking spectrum's grids, the bench block and damper of
#: tests/test_adaptive.py.
BENCH = Setting(Block.reference(), rtol=1e-8)
BENCH_DAMPER = Tuning(0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
GRIDS = Grid("Omega", *SPECTRUM_OMEGA), Grid("beta", *SPECTRUM_BETA)


#: The coarse step to ask for (rocking.study.spectrum.SCAN_COARSE).
ASKED = 4


def adaptive_and_full(tmp_path, setting, damper, coarse=ASKED):
    runs = tmp_path / "runs"
    return (
        minimum_overturning_spectrum(setting, damper, *GRIDS, POOL, runs=runs, coarse=coarse),
        minimum_overturning_spectrum(setting, damper, *GRIDS, POOL, runs=runs),
    )


def assert_full_results_but_for_narrow_features(adaptive, full, coarse) -> None:
    """Every column (part, Omega, direction) whose full scan has no feature narrower than the coarse step (a run of
    one class touching neither end of the scan) has the full scan's outcomes, beta_min, beta_safe, flag, impacts
    and responses without a verdict; every column that differs has such a feature; at every Omega where both
    directions agree, the envelope and the windows are the full spectrum's. Fewer responses, counted."""
    envelopes = [envelope(x.data) for x in (adaptive, full)]
    Omega = full.data["Omega"].values
    for part in ("bare", "damper"):
        a, f = (x.data.sel(part=part) for x in (adaptive, full))
        scan_f = f["scan_outcome"].values
        wide = narrowest_feature(scan_f.reshape(-1, scan_f.shape[-1])).reshape(scan_f.shape[:-1]) >= coarse
        same = (a["scan_outcome"].values == scan_f).all(axis=-1)
        assert same[wide].all(), part
        assert wide.sum() > 0.6 * wide.size, part  # most columns are exact by this rule alone
        for k in COLUMN_FIELDS:
            np.testing.assert_array_equal(a[k].values[same], f[k].values[same], err_msg=k)
        agree = same.all(axis=1)
        for k in (*COLUMN_FIELDS, "scan_outcome"):
            got, want = (e[k].sel(part=part).values[agree] for e in envelopes)
            np.testing.assert_array_equal(got, want, err_msg=k)
        windows = [{tuple(w) for w in safe_windows(e, part) if w[0] in Omega[agree]} for e in envelopes]
        assert windows[0] == windows[1]
    counts = adaptive.run
    assert counts["scan_responses_full"] == full.run["scan_responses"] == full.run["scan_responses_full"]
    assert counts["scan_responses"] < counts["responses"] < full.run["responses"]
    assert counts["scan_responses"] < full.run["scan_responses"] / 1.5  # verified from the coarse step


def test_the_bench_spectrum_adaptive_is_the_full_spectrum_but_for_narrow_features(tmp_path):
    adaptive, full = adaptive_and_full(tmp_path, BENCH, BENCH_DAMPER)
    assert_full_results_but_for_narrow_features(adaptive, full, ASKED)
    refinement = {"adaptive": True, "coarse": 4, "verify": 4}
    assert adaptive.config["refinement"] == adaptive.summary["refinement"] == refinement
    assert full.config["refinement"] == {"adaptive": False}
    assert adaptive.run["run_folders"]["bare"] != full.run["run_folders"]["bare"]  # tiles of their own
    assert len(safe_windows(envelope(full.data), "damper")) > 0  # windows are compared, not only their absence


def test_a_second_block_adaptive_is_the_full_spectrum_but_for_narrow_features(tmp_path):
    """The slender, smaller block of tests/test_adaptive.py, eccentric the other way, with the paper's damper;
    a coarse step of 8."""
    block = Block.from_nondim(p=2.0, alpha=0.2, e_ratio=-0.04)
    adaptive, full = adaptive_and_full(tmp_path, Setting(block), Tuning(0.05), coarse=8)
    assert_full_results_but_for_narrow_features(adaptive, full, 8)


def test_what_an_adaptive_scan_misses_on_the_bench_spectrum():
    """At Omega = 3, pulses of negative sign, the damped bench block overturns at one scan amplitude, beta =
    1.875, and at none of its neighbours up to 3.25: a band narrower than one step of the scan, which an
    adaptive scan finds only if it computes that very amplitude."""
    damper = BENCH_DAMPER.case_args()
    beta = Grid("beta", *SPECTRUM_BETA).values()
    full = beta_min(BENCH, [3.0], beta, damper, sign=-1)
    assert narrowest_feature(full["scan_outcome"])[0] == 1
    assert full["beta_min"][0] == pytest.approx(1.857, abs=1e-3) and full["scan_outcome"][0, 11] >= 0
    # Index 11 is 3 modulo 4: between two safe computed points of the step 4, off the verification's lattice
    # (2 + 4 a), and farther than its halo from a class change.
    missed = beta_min(BENCH, [3.0], beta, damper, sign=-1, coarse=4)
    assert missed["beta_min"][0] == pytest.approx(3.25, abs=1e-2) and missed["scan_outcome"][0, 11] == -1
    assert missed["responses"][0] < full["responses"][0]
    # The step 2 is verified on the odd amplitudes: every amplitude is computed, the band is found.
    found = beta_min(BENCH, [3.0], beta, damper, sign=-1, coarse=2)
    assert found["beta_min"][0] == full["beta_min"][0]


def refined(field: np.ndarray, coarse: int) -> tuple[np.ndarray, np.ndarray, int, list]:
    """:func:`refine_scan` of a known field of classes ``(n, m)``; the points asked for in each round."""
    asked = []

    def classify(rows, indices):
        asked.append((rows, indices))
        return field[rows, indices]

    classes, computed, rounds = refine_scan(classify, field.shape, coarse)
    return classes, computed, rounds, asked


def test_a_scan_is_refined_where_its_classes_differ_and_misses_what_lies_between_agreeing_points():
    """Boundaries are found exactly, from a point every ``coarse`` and the bisections of the intervals across
    them, every scan at once in one call per round; a band narrower than the coarse step between two points of
    one class is missed (as documented), and found with a finer step."""
    m = 65
    field = np.full((4, m), -1)
    field[0, 23:] = 0  # one boundary
    field[1, 10:40], field[1, 40:] = 2, 0  # a band of 30 points, then another class
    field[2, 33:36] = 1  # a band of 3 points, between computed points 32 and 48 of one class: missed
    classes, computed, rounds, asked = refined(field, 16)
    np.testing.assert_array_equal(classes[:2], field[:2])
    assert (classes[2:] == -1).all()
    assert rounds == len(asked) == 5  # the lattice, then bisections down to neighbours: log2(16) rounds
    assert computed.sum() == sum(len(rows) for rows, _ in asked) < field.size / 3
    assert all(computed[r, i].all() for r, i in asked) and computed[:, [0, 16, 32, 48, 64]].all()
    assert set(np.unique(asked[1][0])) == {0, 1}  # only the scans with a boundary are refined
    assert narrowest_feature(field).tolist() == [m, 30, 3, m]
    np.testing.assert_array_equal(refined(field, 2)[0], field)  # every band holds a point of the step 2


@pytest.mark.parametrize("m", [1, 2, 3, 7, 16, 17, 50])
@pytest.mark.parametrize("coarse", [1, 2, 4, 64])
def test_scans_of_any_length_are_refined_to_their_last_point(m, coarse):
    field = np.where(np.arange(m) >= m // 2, 3, -1)[None, :].repeat(2, axis=0)
    field[1] = field[1, ::-1]
    classes, computed, rounds, _ = refined(field, coarse)
    np.testing.assert_array_equal(classes, field)
    assert computed[:, 0].all() and computed[:, -1].all()
    assert computed.all() or (coarse > 1 and m > 3)
    assert not computed.all() or m < 50 or coarse == 1
    assert rounds <= 1 + int(np.log2(coarse))


def test_the_default_and_a_coarse_step_of_1_share_their_tiles_and_other_steps_do_not(tmp_path):
    grids = Grid("Omega", 2.0, 6.0, 3), Grid("beta", 0.5, 10.0, 20)
    run = {}
    for name, how in (("full", {}), ("1", {"coarse": 1}), ("4", {"coarse": 4}), ("8", {"coarse": 8})):
        run[name] = minimum_overturning_spectrum(BENCH, BENCH_DAMPER, *grids, POOL, runs=tmp_path, **how).run
    assert run["1"]["tiles_reused"] == run["full"]["tiles_computed"] and run["1"]["tiles_computed"] == 0
    assert run["1"]["responses"] == run["full"]["responses"]  # the counts are stored with the tiles
    assert run["4"]["tiles_reused"] == run["8"]["tiles_reused"] == 0
    assert len({r["run_folders"]["damper"] for r in run.values()}) == 3


@pytest.mark.parametrize("coarse", [0, 3, -4, 2.0, True, "4", 2**18])
def test_a_bad_coarse_step_is_refused_in_one_line(coarse, tmp_path):
    grids = Grid("Omega", 2.0, 6.0, 3), Grid("beta", 0.5, 10.0, 20)
    with pytest.raises(ParameterError, match=r"^coarse must be a power of two \(1, 2, 4, \.\.\.\) in \[1, 131072\]"):
        minimum_overturning_spectrum(BENCH, BENCH_DAMPER, *grids, POOL, runs=tmp_path, coarse=coarse)
    with pytest.raises(ParameterError, match=r"^coarse must be a power of two"):
        beta_min(BENCH, [2.0], [1.0, 2.0], coarse=coarse)


def test_scans_are_full_by_default_because_the_bench_spectrum_has_one_amplitude_bands():
    """The default is every amplitude: an adaptive step misses bands such as the one pinned below."""
    assert SCAN_COARSE == 1


def test_the_command_line_scans_every_amplitude_unless_asked(tmp_path, capsys):
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))

    def cli(*argv: str) -> int:
        args = parser.parse_args(
            [
                "spectrum",
                "--Omega",
                "2",
                "6",
                "3",
                "--beta",
                "0.5",
                "10",
                "20",
                "--workers",
                "1",
                "--no-progress",
                "--out",
                str(tmp_path),
                *argv,
            ]
        )
        return args.func(args)

    assert cli() == 0
    assert "adaptive" not in capsys.readouterr().out
    for argv, message in ((("--coarse", "6"), "coarse must be a power of two"),):
        assert cli(*argv) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.splitlines()) == 1
    assert cli("--coarse", "8") == 0
    out = capsys.readouterr().out
    assert "spectrum: adaptive scans (coarse step 8):" in out and "of 240 scan responses" in out


@pytest.mark.parametrize("start", [1, 5, 18, 27, 50])
def test_a_verified_scan_finds_every_band_of_its_verification_step(start):
    """A band of 4 points of another class anywhere in a scan holds a point ``2 + 4 a`` of the verification
    from step 4: the scan of coarse step 16 verified from 4 finds it; unverified, it is missed where it falls
    between computed points."""
    field = np.full((2, 65), -1)
    field[0, 40:] = 0
    field[:, start : start + 4] = 3
    classes, computed, _ = refine_scan(lambda r, i: field[r, i], field.shape, 16, verify=4)
    np.testing.assert_array_equal(classes, field)
    assert not computed.all()
    unverified = refine_scan(lambda r, i: field[r, i], field.shape, 16)[0]
    assert (unverified == field).all() == (start <= 16 <= start + 3 or start <= 32 <= start + 3)
