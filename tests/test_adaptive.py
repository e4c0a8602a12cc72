"""Adaptive maps (rocking.study.adaptive): the full map's classification, from fewer responses, resumable."""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rocking import Block
from rocking.cli.study import add_study_commands
from rocking.model.params import ParameterError
from rocking.study import adaptive
from rocking.study.adaptive import check_coarse, check_verify
from rocking.study.config import Grid, Setting, Tuning, Variant
from rocking.study.overturning_map import FIELDS, envelope, outcome, overturning_map, undetermined
from rocking.study.tiles import Execution, Interrupted

SERIAL = Execution(workers=1, progress=False)
POOL = Execution(workers=2, progress=False)
#: The bench map of `make bench` (bench/run.py, bench/adaptive.py): the reference block and damper, rtol 1e-8.
BENCH = Setting(Block.reference(), rtol=1e-8)
BENCH_DAMPER = Tuning(0.05, omega_ratio=1.0, zeta=0.05, h=0.05)


def adaptive_and_full(tmp_path, setting, damper, Omega, beta, **adaptive):
    """The adaptive map and the full map of the same cells."""
    runs = tmp_path / "runs"
    return (
        overturning_map(setting, damper, Omega, beta, POOL, runs=runs, **adaptive),
        overturning_map(setting, damper, Omega, beta, POOL, runs=runs, full=True),
    )


def assert_same_classification(adaptive, full) -> None:
    """Outcomes (envelope and per direction), the responses without a verdict and the effect are the full
    map's; the cells computed are the full map's responses, bit for bit; and some cells were not computed."""
    a, f = adaptive.data, full.data
    for what, (got, want) in {"per direction": (a, f), "envelope": (envelope(a), envelope(f))}.items():
        np.testing.assert_array_equal(*(outcome(x["overturned"], x["impacts"]) for x in (got, want)), err_msg=what)
        np.testing.assert_array_equal(*(undetermined(x["status"]) for x in (got, want)), err_msg=what)
    for part in ("bare", "damper"):
        computed = a["computed"].sel(part=part).values
        assert f["computed"].sel(part=part).all() and 0 < computed.sum() < computed.size
        for k in FIELDS:
            np.testing.assert_array_equal(a[k].sel(part=part).values[computed], f[k].sel(part=part).values[computed])
        assert np.isnan(envelope(a)["theta_max"].sel(part=part).values[~computed]).all()  # never invented
    np.testing.assert_array_equal(envelope(a)["effect"], envelope(f)["effect"])
    assert adaptive.run["responses"] < full.run["responses"] == full.run["responses_full_grid"]


def test_the_bench_map_adaptive_is_the_full_map(tmp_path):
    """The bench map (Omega, beta in [1, 10]) at 81 x 81 (five coarse blocks of 16 per axis)."""
    grids = Grid("Omega", 1.0, 10.0, 81), Grid("beta", 1.0, 10.0, 81)
    adaptive, full = adaptive_and_full(tmp_path, BENCH, BENCH_DAMPER, *grids)
    assert_same_classification(adaptive, full)
    assert adaptive.run["responses"] < 0.5 * full.run["responses"]
    refinement = {"adaptive": True, "coarse": 16, "verify": 16, "edges": True}
    assert adaptive.config["refinement"] == adaptive.summary["refinement"] == refinement
    assert adaptive.summary["guarantee"] == (
        "every region of one class extending over 16 cells along Omega or beta (1.8 in Omega, 1.8 in beta) is "
        "found, whole; smaller ones only near class boundaries"
    )
    assert full.config["refinement"] == {"adaptive": False}
    assert adaptive.run["run_folders"]["bare"] != full.run["run_folders"]["bare"]  # tiles of their own
    assert envelope(adaptive.data)["effect"].any()
    assert_inferred_counts(adaptive, full)


def assert_inferred_counts(adaptive, full) -> None:
    """The summary says how many cells of each part and count were inferred, not computed, from the map's
    ``computed``; the cells the full map counts are the adaptive map's, computed or inferred, and within the
    bounds it gives; a full map infers nothing."""
    s, f, env = adaptive.summary, full.summary, envelope(adaptive.data)
    for part in ("bare", "damper"):
        inferred = ~adaptive.data["computed"].sel(part=part).values
        assert s[f"{part}_inferred"] == inferred.sum() > 0
        assert s[f"{part}_overturned_inferred"] == (env["overturned"].sel(part=part).values & inferred).sum()
        assert f[f"{part}_inferred"] == f[f"{part}_overturned_inferred"] == 0
    computed_both = adaptive.data["computed"].all("part").values
    for name, sign in (("saved", 1), ("lost", -1)):
        assert s[name] - s[f"{name}_inferred"] == (computed_both & (env["effect"].values == sign)).sum()
        assert s[name] - s[f"{name}_inferred"] <= f[name] <= s[name] + s[f"{name}_possible"]
        assert f[f"{name}_inferred"] == f[f"{name}_possible"] == 0


def test_the_bare_block_map_adaptive_is_the_full_map(tmp_path):
    """The block alone in both parts (the model ``block`` as the damper), on the map command's range of pulses,
    with grid sizes that are not 1 + a multiple of the coarse step (the last blocks are clipped)."""
    grids = Grid("Omega", 0.5, 15.0, 40), Grid("beta", 1.0, 15.0, 37)
    adaptive, full = adaptive_and_full(tmp_path, BENCH, Variant("block", {}), *grids, coarse=8)
    assert_same_classification(adaptive, full)
    computed = adaptive.data["computed"]
    np.testing.assert_array_equal(
        computed.sel(part="bare"), computed.sel(part="damper")
    )  # the same block refines alike


def test_a_second_block_adaptive_is_the_full_map(tmp_path):
    """A slender, smaller block, eccentric the other way (its safe windows above beta_min, docs/model.md 10.4)."""
    block = Block.from_nondim(p=2.0, alpha=0.2, e_ratio=-0.04)
    grids = Grid("Omega", 2.0, 10.0, 49), Grid("beta", 1.0, 12.0, 60)
    adaptive, full = adaptive_and_full(tmp_path, Setting(block), Tuning(0.05), *grids)
    assert_same_classification(adaptive, full)


def test_an_interrupted_adaptive_map_resumes_from_its_rounds(tmp_path):
    grids = Grid("Omega", 1.0, 10.0, 17), Grid("beta", 1.0, 10.0, 17)
    whole = overturning_map(BENCH, BENCH_DAMPER, *grids, SERIAL, runs=tmp_path / "whole", coarse=8, tile=(4, 4))
    done = []

    def crash(task):
        done.append(task.path.name)
        if len(done) == 10:  # round 0 is 2 x 3 tiles of 4 cells: this is inside a later round
            raise KeyboardInterrupt

    runs = tmp_path / "runs"
    with pytest.raises(Interrupted) as interrupted:
        overturning_map(BENCH, BENCH_DAMPER, *grids, POOL, runs=runs, coarse=8, tile=(4, 4), on_tile=crash)
    assert done[-1].startswith("round-") and not done[-1].startswith("round-0-")
    stored = len(list(runs.rglob("round-*.npz")))
    assert interrupted.value.kept == stored  # the tiles of the rounds before are counted too
    resumed = overturning_map(BENCH, BENCH_DAMPER, *grids, POOL, runs=runs, coarse=8, tile=(4, 4))
    assert resumed.run["tiles_reused"] == stored >= 10
    assert resumed.run["tiles_reused"] + resumed.run["tiles_computed"] == whole.run["tiles_computed"]
    xr.testing.assert_identical(resumed.data, whole.data)
    again = overturning_map(BENCH, BENCH_DAMPER, *grids, SERIAL, runs=runs, coarse=8, tile=(4, 4))
    assert (again.run["tiles_computed"], again.run["tiles_reused"]) == (0, whole.run["tiles_computed"])


def refine(classes: np.ndarray, coarse: int, verify: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """The classes an adaptive map gives to a known field of classes ``(n, m)`` (the fake evaluator reads it),
    and the cells it computed."""
    got, computed, _ = adaptive.refine(lambda r, c: classes[r, c][:, None], (*classes.shape, 1), coarse, verify)
    return got[..., 0], computed


def test_near_is_scipys_maximum_filter_of_the_cells_given():
    """The cells near others, in NumPy, against scipy.ndimage.maximum_filter (zero beyond the grid's edges) over
    random grids, cells and radii: one radius, and one per axis."""
    from scipy import ndimage

    rng = np.random.default_rng(40)
    for trial in range(300):
        shape = tuple(int(n) for n in rng.integers(1, 30, 2))
        rows, cols = (rng.integers(0, n, rng.integers(0, 12)) for n in shape)
        rows, cols = rows[: min(rows.size, cols.size)], cols[: min(rows.size, cols.size)]
        radius = int(rng.integers(0, 12)) if trial % 2 else rng.integers(0, 12, 2)
        hit = np.zeros(shape, bool)
        hit[rows, cols] = True
        size = tuple(2 * np.broadcast_to(radius, 2) + 1)
        expected = ndimage.maximum_filter(hit, size=size, mode="constant")
        np.testing.assert_array_equal(adaptive.near(shape, rows, cols, radius), expected)


def test_what_an_unverified_adaptive_map_can_miss():
    """A straight boundary is found exactly; an island smaller than the coarse step that no computed cell
    touches is missed without the verification; a finer coarse step, or a larger island, finds it."""
    i, j = np.meshgrid(np.arange(50), np.arange(45), indexing="ij")
    sloped = np.where(3 * i + 2 * j > 100, 1, -1)
    got, computed = refine(sloped, 16)
    np.testing.assert_array_equal(got, sloped)
    assert computed.sum() < sloped.size / 2
    island = np.full((33, 33), -1)
    island[5:8, 5:8] = 0  # 3 x 3 cells, between the corners 0 and 16 of a coarse block
    assert (refine(island, 16)[0] == -1).all()
    np.testing.assert_array_equal(refine(island, 2)[0], island)
    large = np.full((33, 33), -1)
    large[10:30, 3:14] = 0  # holds the lattice points (16, 8) and (24, 8) of the coarse step 8
    np.testing.assert_array_equal(refine(large, 8)[0], large)


@pytest.mark.parametrize("corner", [(1, 1), (3, 5), (9, 2), (13, 13), (40, 25)])
def test_the_verification_finds_an_island_of_its_step_inside_a_coarse_block(corner):
    """An island of 4 x 4 cells anywhere inside a coarse block of 16 holds a point of the offset lattice of
    step 4: verified from step 4 it is found, cell for cell, and at a fraction of the cells."""
    field = np.full((49, 45), -1)
    field[corner[0] : corner[0] + 4, corner[1] : corner[1] + 4] = 2
    got, computed = refine(field, 16, verify=4)
    np.testing.assert_array_equal(got, field)
    assert computed.sum() < field.size / 3


@pytest.mark.parametrize("start", [(3, 5), (21, 9), (37, 40), (50, 60)])
def test_the_verification_finds_a_filament_one_cell_wide_across_a_coarse_block_edge(start):
    """A filament of another class one cell wide and 17 long (a diagonal step in it), far from any boundary
    (issue 35: 2 x 25 cells of a 400 x 400 map, lost, missed), crosses an edge of the coarse blocks, which the
    verification computes: it is found, traced whole, cell for cell; one of 14 cells strictly inside a coarse
    block, off every lattice of the verification and far from any boundary, is missed: the bound is honest."""
    field = np.full((81, 81), -1)
    i, j = start
    field[i, j : j + 9] = 2
    field[i + 1, j + 8 : j + 17] = 2  # 8-connected to the first half
    got, computed = refine(field, 16, verify=16)
    np.testing.assert_array_equal(got, field)
    assert computed.sum() < field.size / 3
    short = np.full((81, 81), -1)
    short[35, 33:47] = 2  # rows and columns 33 to 46: no edge (32, 48), no point of the lattice (8 + 16 a)
    assert (refine(short, 16, verify=16)[0] == -1).all()


def test_the_verification_traces_an_island_near_a_boundary_and_on_the_grid_edge():
    """Islands of one and two cells within a few cells of a boundary, and one on the grid's edge (the map of
    issue 25: safe on the edge, 3 cells from an overturned region), are found: the verification refines near
    every boundary down to the cells next to it, and samples the grid's edges."""
    i, j = np.meshgrid(np.arange(65), np.arange(65), indexing="ij")
    field = np.where(j > 40 + i // 4, 0, -1)
    field[0, 36:38] = 2  # on the edge, 3 cells from the region 0
    field[30, 44] = -1  # a safe cell in the region 0, 2 cells from its boundary
    got, computed = refine(field, 16, verify=16)
    np.testing.assert_array_equal(got, field)
    assert (refine(field, 16)[0] != field).sum() == 2  # unverified, the edge island is missed
    assert computed.sum() < field.size / 3


def test_every_boundary_of_a_verified_map_lies_between_computed_cells():
    """The verification ends when the cells next to every boundary of the result are computed and agree."""
    rng = np.random.default_rng(5)
    field = np.where(rng.random((40, 40)) < 0.02, 1, -1)  # scattered single cells
    got, computed = refine(field, 8, verify=8)
    differ = np.zeros(field.shape, bool)
    differ[1:] |= got[1:] != got[:-1]
    differ[:-1] |= got[1:] != got[:-1]
    differ[:, 1:] |= got[:, 1:] != got[:, :-1]
    differ[:, :-1] |= got[:, 1:] != got[:, :-1]
    assert computed[differ].all()
    np.testing.assert_array_equal(got[computed], field[computed])


@pytest.mark.parametrize("shape", [(1, 1), (1, 37), (37, 1), (2, 2), (3, 50), (17, 17), (18, 40)])
@pytest.mark.parametrize("coarse", [1, 4, 16, 64])
def test_grids_of_any_size_are_refined_to_their_last_cell(shape, coarse):
    """One value per axis, fewer cells than the coarse step, sizes that are not 1 + a multiple of it: the
    blocks are clipped, every cell is computed or filled, and a boundary across the grid is found."""
    i, j = np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij")
    field = np.where(i + 2 * j > 25, 2, -1)
    got, computed = refine(field, coarse)
    np.testing.assert_array_equal(got, field)
    corners = [(0, 0), (0, -1), (-1, 0), (-1, -1)]
    assert all(computed[c] for c in corners)
    assert computed.all() == (coarse == 1 or max(shape) <= 2)
    verified, _ = refine(field, coarse, coarse)
    np.testing.assert_array_equal(verified, field)


@pytest.mark.parametrize("coarse", [0, 3, 12, -16, 2.0, True, "16", 2**18])
def test_a_bad_coarse_step_is_refused_in_one_line(coarse):
    with pytest.raises(ParameterError, match=r"^coarse must be a power of two \(1, 2, 4, \.\.\.\) in \[1, 131072\]"):
        check_coarse(coarse)


@pytest.mark.parametrize("verify", [3, -2, 32, 2.0, "4"])
def test_a_bad_verification_step_is_refused_in_one_line(verify):
    with pytest.raises(ParameterError, match=r"^verify must be 0 or a power of two in \[1, coarse = 16\]"):
        check_verify(verify, 16)


def test_the_command_line_maps_adaptive_by_default(tmp_path, capsys):
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))

    def cli(*argv: str) -> int:
        args = parser.parse_args(
            [
                "map",
                "--Omega",
                "1",
                "10",
                "17",
                "--beta",
                "1",
                "10",
                "17",
                "--workers",
                "1",
                "--no-progress",
                "--out",
                str(tmp_path),
                *argv,
            ]
        )
        return args.func(args)

    assert cli("--coarse", "8") == 0
    assert "map: adaptive (coarse step 8, verified from step 8):" in capsys.readouterr().out
    table = (tmp_path / "map.csv").read_text()
    assert ",not_computed," in table and "bare_computed" in table.splitlines()[0]
    for argv, message in (
        (("--coarse", "6"), "coarse must be a power of two"),
        (("--full", "--coarse", "8"), "not both"),
    ):
        assert cli(*argv) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.splitlines()) == 1
    assert cli("--full") == 0
    assert "adaptive" not in capsys.readouterr().out


def load_bench():
    """bench/adaptive.py as a module (bench/ is not a package: its scripts import each other from their folder,
    as they do when run)."""
    path = Path(__file__).parent.parent / "bench" / "adaptive.py"
    if str(path.parent) not in sys.path:
        sys.path.insert(0, str(path.parent))
    spec = importlib.util.spec_from_file_location("bench_adaptive", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_bench_reports_the_cells_that_differ(tmp_path, capsys):
    """bench/adaptive.py counts a changed outcome, per direction and in the envelope, and the effect; its
    matrix of pulses and guides prints a row per map and exits 0 only when no cell differs."""
    bench = load_bench()
    grids = Grid("Omega", 1.0, 10.0, 17), Grid("beta", 1.0, 10.0, 17)
    study = overturning_map(BENCH, BENCH_DAMPER, *grids, SERIAL, runs=tmp_path / "runs", full=True)
    changed = study.data.copy(deep=True)
    assert bench.misclassified(changed, study.data) == 0
    changed["overturned"].values[1, 3, 4, 0] = ~changed["overturned"].values[1, 3, 4, 0]  # the damper's, sign +1
    # One cell of one direction, and what follows in the envelope and the effect, each counted once.
    before, after = envelope(study.data), envelope(changed)
    follows = [
        (outcome(x["overturned"].values, x["impacts"].values)[1, 3, 4], x["effect"].values[3, 4])
        for x in (before, after)
    ]
    assert bench.misclassified(changed, study.data) == 1 + sum(b != a for b, a in zip(*follows))
    code = bench.main(
        [
            "-n",
            "17",
            "--workers",
            "1",
            "--coarse",
            "8",
            "--pulses",
            "ricker",
            "--stops",
            "both",
            "--json",
            str(tmp_path / "bench.json"),
        ]
    )
    out = capsys.readouterr().out
    assert code == 0 and out.count("cells differ)") == 2 and "| ricker | stops | 8 | 0 |" in out
    written = json.loads((tmp_path / "bench.json").read_text())
    assert written["command"].startswith("python bench/adaptive.py -n 17 ") and "date" in written["machine"]
    rows = written["maps"]
    assert [(r["stops"], r["misclassified"], r["verify"]) for r in rows] == [(False, 0, 8), (True, 0, 8)]
