"""The parametric study: maps, spectra, optimal damper, resumable tiles, data, figures, CLI."""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import threading
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import rocking
from rocking import Block, load_model
from rocking.cli.study import add_study_commands, map_lines, spectrum_lines
from rocking.model.params import ParameterError
from rocking.sim.problem import STATUS
from rocking.study import config as study_config
from rocking.study.config import Grid, Setting, Tuning, config_hash, part_config
from rocking.study.optimize import EdgeWarning, bare_beta_min, optimal_damper, refinement, threshold_frequency
from rocking.study.overturning_map import TMaxWarning, UndeterminedWarning, envelope, outcome, overturning_map
from rocking.study.result import Study
from rocking.study.spectrum import beta_min, minimum_overturning_spectrum, safe_windows, windows
from rocking.study.spectrum import envelope as spectrum_envelope
from rocking.study.storage import load
from rocking.study.tiles import IN_FLIGHT_PER_WORKER, Execution, Task, local_pool, run_tiles
from rocking.study.vocabulary import ABOVE, BELOW, BRACKETED, SAFE

SETTING = Setting(Block.reference(), backend="c")
SERIAL = Execution(workers=1, progress=False)
POOL = Execution(workers=2, progress=False)
OMEGA = Grid("Omega", 1.0, 6.0, 4)
BETA = Grid("beta", 0.5, 6.0, 12)
TUNING = Tuning(0.05)


def cli(argv: list[str]) -> int:
    """Run ``rocking <argv>`` through :func:`add_study_commands` on a fresh parser."""
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    return args.func(args)


def tiny(*extra: str) -> list[str]:
    return ["--workers", "1", "--no-progress", *extra]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    return tmp_path_factory.mktemp("runs")


@pytest.fixture(scope="module")
def ref_map(runs):
    return overturning_map(SETTING, TUNING, OMEGA, BETA, SERIAL, runs=runs, tile=(2, 5), full=True)


# --- physics of the studies --------------------------------------------------------------


def test_map_agrees_with_spectrum(ref_map, runs):
    spectrum = minimum_overturning_spectrum(SETTING, TUNING, OMEGA, BETA, POOL, runs=runs)
    beta = ref_map.data["beta"].values
    step = beta[1] - beta[0]
    both = envelope(ref_map.data)
    for part in ("bare", "damper"):
        for i in range(OMEGA.n):
            overturned = both["overturned"].sel(part=part).values[i]
            assert overturned.any() and not overturned[0]
            lowest = beta[np.argmax(overturned)]
            column = spectrum_envelope(spectrum.data).sel(part=part).isel(Omega=i)
            assert column["flag"] == BRACKETED
            assert 0 <= lowest - column["beta_min"] <= step
            # The scan of the spectrum is the map's column: the same outcomes.
            np.testing.assert_array_equal(column["scan_outcome"].values != SAFE, overturned)


def test_vanishing_damper_reproduces_bare_map(ref_map, runs):
    light = overturning_map(SETTING, Tuning(1e-6), OMEGA, BETA, SERIAL, runs=runs, tile=(2, 5), full=True)
    assert light.run["tiles_reused"] == light.run["tiles_computed"]  # the bare half is shared with ref_map
    a = light.data
    np.testing.assert_array_equal(
        envelope(a)["overturned"].sel(part="damper"), envelope(ref_map.data)["overturned"].sel(part="bare")
    )
    # Per direction: where both directions barely uplift, their theta_max tie and the envelope may pick either.
    # A mass of 1e-6 M shifts each impact slightly, and dozens of impacts add up: theta_max to 1e-3.
    # The impacts before overturning; a safe response counts its impacts up to its early verdict (rule 4).
    damper, bare = (outcome(a["overturned"].sel(part=p), a["impacts"].sel(part=p)) for p in ("damper", "bare"))
    np.testing.assert_array_equal(damper, bare)
    np.testing.assert_allclose(a["theta_max"].sel(part="damper"), a["theta_max"].sel(part="bare"), rtol=1e-3)
    assert light.summary["saved"] == light.summary["lost"] == 0


def test_damper_changes_outcomes(ref_map):
    """The reference damper saves cells: the comparison map is not trivially empty."""
    s = ref_map.summary
    assert s["saved"] > 0
    assert s["saved"] == int((envelope(ref_map.data)["effect"] == 1).sum())
    assert s["cells"] == OMEGA.n * BETA.n


def test_spectrum_reports_windows_of_a_slender_block(tmp_path):
    """docs/model.md 10.4: below the no-impact boundary (9.417 at Omega = 6) the slender block survives a window."""
    setting = Setting(Block.from_nondim(p=2.0, alpha=0.2), backend="c")
    study = minimum_overturning_spectrum(
        setting, TUNING, Grid("Omega", 6.0, 6.0, 1), Grid("beta", 3.0, 11.0, 33), SERIAL, runs=tmp_path
    )
    both = spectrum_envelope(study.data)
    w = safe_windows(both, "bare")
    assert len(w) >= 1 and study.summary["bare"]["windows"] == len(w)
    assert np.all(w[:, 1] > both["beta_min"].sel(part="bare").values[0])
    assert np.any((w[:, 1] < 9.417) & (w[:, 2] > 8.5))
    assert len(study.tables["spectrum-windows"]["Omega"]) == len(w) + len(safe_windows(both, "damper"))


def test_windows_and_flags():
    beta = np.arange(1.0, 9.0)
    np.testing.assert_array_equal(windows(beta, [0, 0, 1, 0, 0, 1, 1, 0]), [[4.0, 5.0], [8.0, 8.0]])
    assert windows(beta, np.zeros(8)).shape == (0, 2)
    r = beta_min(SETTING, [0.5, 1.0, 3.0], [1.5, 50.0], tol=0.01)  # far too coarse: bounds, not brackets
    assert r["flag"][0] == BELOW and r["beta_min"][0] == 1.5
    assert set(r["flag"]) <= {BELOW, ABOVE, BRACKETED}


def test_optimal_damper(tmp_path):
    study = optimal_damper(
        SETTING,
        [0.05],
        Grid("Omega", 3.0, 6.0, 2),
        BETA,
        POOL,
        Tm=Grid("Tm-ratio", 0.5, 2.0, 3, log=True),
        refine=1,
        runs=tmp_path,
    )
    a = {name: variable.values for name, variable in study.data.variables.items()}
    assert study.data["gain_opt"].dims == ("gamma", "Omega") and study.data["beta_min"].dims == ("Omega", "sign")
    assert a["gain_opt"].shape == (1, 2) and np.all(np.isfinite(a["gain_opt"]))
    assert np.all(a["gain_opt"] >= np.nanmax(a["gain_coarse"], axis=2))
    np.testing.assert_allclose(a["Tm_over_Tg_opt"], a["r_opt"] * a["Omega"])
    # The optimum is what the spectrum gives for that damper.
    r_opt, Omega = a["r_opt"][0, 1], a["Omega"][1]
    direct = beta_min(
        SETTING, [Omega], BETA.values(), {"gamma": 0.05, "omega_ratio": 1 / r_opt, "zeta": 0.05, "h": 0.05}
    )
    assert direct["beta_min"][0] / bare_beta_min(study.data).values[1] == a["gain_opt"][0, 1]
    assert set(study.summary["Omega_star"]) == {"0.05", "best"}


def test_refinement_points():
    r = np.geomspace(0.1, 10.0, 5)
    inner = refinement(r, 2, 2)
    assert inner.size == 4 and np.all((inner > r[1]) & (inner < r[3])) and not np.any(np.isclose(inner, r[2]))
    edge = refinement(r, 0, 2)
    assert np.all((edge[:2] > r[0]) & (edge[:2] < r[1])) and np.all(np.isnan(edge[2:]))


def test_threshold_frequency():
    Omega = np.arange(1.0, 7.0)
    t = threshold_frequency(Omega, [1.5, 1.2, 1.03, 1.005, 1.02, 1.0])
    assert (t["low"], t["high"], t["status"]) == (5.0, 6.0, "bracketed")
    assert 5.0 < t["Omega_star"] < 6.0
    assert threshold_frequency(Omega, np.full(6, 1.0))["status"] == "below_range"
    assert threshold_frequency(Omega, np.full(6, 1.2))["status"] == "above_range"
    assert threshold_frequency(Omega, np.full(6, np.nan))["status"] == "undefined"
    skip = threshold_frequency(Omega, [1.2, 1.2, 1.2, 1.2, np.nan, 1.0])  # the bracket is made of defined gains
    assert (skip["low"], skip["high"], skip["defined_up_to"]) == (4.0, 6.0, 6.0)
    tail = threshold_frequency(Omega, [1.2, 1.2, 1.2, 1.2, np.nan, np.nan])
    assert (tail["status"], tail["low"], tail["defined_up_to"]) == ("above_range", 4.0, 4.0)


def test_responses_without_a_verdict_are_counted_and_change_no_effect(tmp_path):
    """A damper 1e4 times stiffer than the block, undamped, passes max_steps (docs/simulation.md, rule 5): the
    studies count those responses, warn, and a map leaves the damper's effect there at 0."""
    stiff = Tuning(0.05, omega_ratio=1e4, zeta=0.0)
    with pytest.warns(UndeterminedWarning, match="map: 8 response"):  # 4 cells, 2 directions
        study = overturning_map(
            SETTING, stiff, Grid("Omega", 1.0, 4.0, 2), Grid("beta", 1.2, 3.0, 2), SERIAL, runs=tmp_path / "map"
        )
    both = envelope(study.data)
    assert (both["status"].sel(part="damper") == STATUS.index("max_steps")).all()
    assert both["overturned"].sel(part="bare").any() and not both["effect"].any()
    assert (study.summary["bare_undetermined"], study.summary["damper_undetermined"]) == (0, 4)
    with pytest.warns(UndeterminedWarning, match="spectrum"):
        spectrum = minimum_overturning_spectrum(
            SETTING, stiff, Grid("Omega", 1.0, 4.0, 2), BETA, SERIAL, runs=tmp_path / "spectrum"
        )
    undetermined = spectrum_envelope(spectrum.data)["undetermined"].sel(part="damper")
    assert undetermined.min() >= BETA.n and spectrum.summary["bare"]["undetermined"] == 0


def test_responses_cut_at_t_max_are_counted_and_warned(tmp_path):
    """A t_after of 0.01 s cuts most runs at t_max: they still count as not overturned, but the map, the spectrum
    and the optimisation warn with their count and the printed lines say it; the default t_after does not warn."""
    short = Setting(Block.reference(), t_after=0.01)
    grids = Grid("Omega", 1.0, 10.0, 3), Grid("beta", 1.0, 10.0, 3)
    with pytest.warns(TMaxWarning, match=r"t_after = 0.01 s after the pulse\) before overturning") as caught:
        study = overturning_map(short, TUNING, *grids, SERIAL, runs=tmp_path / "map", full=True)
    count = int((study.data["status"] == STATUS.index("t_max")).sum())
    assert count > 0 and [str(w.message).split(" reached")[0] for w in caught] == [f"map: {count} response(s)"]
    s = study.summary
    line = map_lines(study)[0]
    assert f"; {s['bare_t_max']} cells alone and {s['damper_t_max']} with the damper reached t_max" in line
    with pytest.warns(TMaxWarning, match=r"^spectrum: \d+ response\(s\) reached t_max"):
        spectrum = minimum_overturning_spectrum(short, TUNING, grids[0], BETA, SERIAL, runs=tmp_path / "spectrum")
    assert spectrum.summary["t_max"]["bare"] > 0
    assert any("with the damper reached t_max" in line for line in spectrum_lines(spectrum))
    with pytest.warns(TMaxWarning, match=r"^optimize: \d+ response\(s\) reached t_max"):
        optimal_damper(short, [0.05], Grid("Omega", 4.0, 4.0, 1), BETA, SERIAL, runs=tmp_path / "optimize")
    with warnings.catch_warnings():
        warnings.simplefilter("error", TMaxWarning)
        default = overturning_map(SETTING, TUNING, *grids, SERIAL, runs=tmp_path / "default", full=True)
    assert "t_max" not in map_lines(default)[0]


def _map_study(summary: dict, refinement: dict) -> Study:
    """A map's Study with only what its printed lines read."""
    return Study("map", {"refinement": refinement}, None, summary=summary)


def test_map_line_counts_the_saved_cells_of_unknown_stroke():
    """An adaptive map fills in saved cells without their stroke: the saved line says how many."""
    summary = {
        "cells": 400,
        "bare_overturned": 235,
        "damper_overturned": 163,
        "saved": 72,
        "saved_past_edges": 57,
        "saved_stroke_not_computed": 15,
        "lost": 0,
        **dict.fromkeys(("bare_undetermined", "damper_undetermined", "bare_t_max", "damper_t_max"), 0),
    }
    line = map_lines(_map_study(summary, {"adaptive": False}))[0]
    assert line.endswith(
        "saved 72 (57 only with the mass past the block's edge, 15 of unknown stroke: cells filled in by the "
        "adaptive map; --full computes them), lost 0"
    )
    full = map_lines(_map_study({**summary, "saved_stroke_not_computed": 0}, {"adaptive": False}))[0]
    assert full.endswith("saved 72 (57 only with the mass past the block's edge), lost 0")


def test_the_lines_of_an_adaptive_map_say_what_rests_on_cells_inferred():
    """The counts of an adaptive map: how many cells of each part were inferred, not computed, how many of its
    saved and lost cells rest on them, and how many more they could hold (issue 35: lost 668, 709 with --full)."""
    summary = {
        "cells": 160000,
        "bare_overturned": 45777,
        "damper_overturned": 41450,
        "saved": 4995,
        "saved_past_edges": 0,
        "lost": 668,
        "guarantee": "every region of one class extending over 16 cells along Omega or beta (...) is found, whole",
        **dict.fromkeys(("bare_undetermined", "damper_undetermined", "bare_t_max", "damper_t_max"), 0),
        **{"bare_inferred": 126419, "bare_overturned_inferred": 29877, "damper_inferred": 127490},
        **{"damper_overturned_inferred": 26977, "saved_inferred": 3285, "saved_possible": 123385},
        **{"lost_inferred": 134, "lost_possible": 127105},
    }
    refinement = {"adaptive": True, "coarse": 16, "verify": 16, "edges": True}
    run = {"responses": 66091, "responses_full_grid": 320000, "rounds": 21}
    lines = map_lines(Study("map", {"refinement": refinement}, None, summary=summary, run=run))
    assert lines[-1] == (
        "map: inferred, not computed: 126419 cells alone (29877 counted overturned), 127490 with the damper (26977 "
        "counted overturned); saved 4995: 1710 computed, up to 123385 more among the inferred cells; lost 668: 534 "
        "computed, up to 127105 more among the inferred cells (where the guarantee above does not reach; --full "
        "computes every cell)"
    )
    every = {**summary, **dict.fromkeys(("bare_inferred", "damper_inferred"), 0)}
    assert "inferred" not in map_lines(Study("map", {"refinement": refinement}, None, summary=every, run=run))[-1]


@pytest.mark.parametrize("Omega", [Grid("Omega", 4.0, 4.0, 1), Grid("Omega", 2.0, 6.0, 3)])
def test_an_adaptive_map_that_computed_every_cell_says_so(Omega, tmp_path):
    """On a grid smaller than the coarse step every cell is computed: the guarantee says that, not a bound in
    regions larger than the grid."""
    study = overturning_map(SETTING, TUNING, Omega, Grid("beta", 3.0, 3.0, 1), SERIAL, runs=tmp_path)
    assert study.data["computed"].all()
    assert study.summary["guarantee"] == "every cell computed (the refinement covered the whole grid): nothing missed"


# --- tiles: resuming and configurations -----------------------------------------------------


class Crash(RuntimeError):
    pass


def pid_tile(payload) -> dict:
    """A tile that tells which process computed it, and whether Ctrl-C would stop that process."""
    return {
        "pid": np.array([os.getpid()]),
        "sigint_ignored": np.array([signal.getsignal(signal.SIGINT) is signal.SIG_IGN]),
    }


def held_tile(payload) -> dict:
    """A tile that, given ``(started, release)`` events, says it runs and waits to be released."""
    if payload is not None:
        started, release = payload
        started.set()
        assert release.wait(30)
    return {"held": np.array([payload is not None])}


@pytest.mark.parametrize("backend, pool", [("c", "threads"), ("numpy", "processes")])
def test_local_workers_are_threads_on_c_and_processes_on_numpy(backend, pool, tmp_path):
    """C releases the GIL: threads of this process; NumPy does not: processes, which leave
    Ctrl-C to this process (it waits for their running tiles and stores them)."""
    assert local_pool(backend) == pool
    seen = set()

    def place(task, arrays):
        seen.add((int(arrays["pid"][0]), bool(arrays["sigint_ignored"][0])))

    stats = run_tiles([Task(tmp_path / f"{i}.npz", pid_tile, i) for i in range(4)], place, POOL, backend=backend)
    assert stats.computed == 4
    pids, ignored = {pid for pid, _ in seen}, {flag for _, flag in seen}
    assert (pids == {os.getpid()}) == (pool == "threads")
    assert ignored == {pool == "processes"}


def test_threads_give_the_serial_arrays(ref_map, tmp_path, monkeypatch):
    monkeypatch.setattr("rocking.study.tiles.ProcessPoolExecutor", None)  # threads only: no process pool can start
    threaded = overturning_map(SETTING, TUNING, OMEGA, BETA, POOL, runs=tmp_path / "map", tile=(2, 5), full=True)
    assert threaded.run["tiles_computed"] == 2 * 2 * 3
    xr.testing.assert_identical(threaded.data, ref_map.data)
    # Columns bisect independently: how they are grouped into tiles changes nothing either.
    serial, threaded = (
        minimum_overturning_spectrum(SETTING, TUNING, OMEGA, BETA, execution, runs=tmp_path / name, columns=columns)
        for name, execution, columns in (("serial", SERIAL, 1), ("threads", POOL, 3))
    )
    assert (serial.run["tiles_computed"], threaded.run["tiles_computed"]) == (2 * OMEGA.n, 2 * 2)
    xr.testing.assert_identical(threaded.data, serial.data)


def test_interrupted_threads_store_their_running_tiles(tmp_path):
    """Tiles that finish while an interruption is handled are kept (Python tiles on threads cannot be stopped)."""
    release = threading.Event()
    started = [threading.Event() for _ in range(2)]
    tasks = [Task(tmp_path / "quick.npz", held_tile, None)]
    tasks += [Task(tmp_path / f"held-{i}.npz", held_tile, (event, release)) for i, event in enumerate(started)]

    def interrupt(task):
        assert all(event.wait(30) for event in started)  # both held tiles run: none is merely queued
        threading.Timer(0.2, release.set).start()  # they are still running when the interruption comes
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_tiles(tasks, lambda task, arrays: None, POOL, backend="c", on_tile=interrupt)
    assert sorted(path.name for path in tmp_path.iterdir()) == ["held-0.npz", "held-1.npz", "quick.npz"]
    assert run_tiles(tasks, lambda task, arrays: None, POOL, backend="c").reused == 3


@pytest.mark.parametrize("interruption", [Crash, KeyboardInterrupt])
def test_resume_recomputes_nothing_finished(ref_map, tmp_path, interruption):
    done = []

    def crash_after_five(task):
        done.append(task.path)
        if len(done) == 5:
            raise interruption

    with pytest.raises(interruption):
        overturning_map(
            SETTING, TUNING, OMEGA, BETA, POOL, runs=tmp_path, tile=(2, 3), full=True, on_tile=crash_after_five
        )
    # The five tiles handed over, and those still in flight, which the interruption waited for.
    stored = len(list(tmp_path.rglob("tile-*.npz")))
    assert 5 <= stored <= 5 + IN_FLIGHT_PER_WORKER * POOL.workers
    resumed = overturning_map(SETTING, TUNING, OMEGA, BETA, POOL, runs=tmp_path, tile=(2, 3), full=True)
    total = 2 * 2 * 4  # parts x Omega tiles x beta tiles
    assert (resumed.run["tiles_reused"], resumed.run["tiles_computed"]) == (stored, total - stored)
    again = overturning_map(SETTING, TUNING, OMEGA, BETA, SERIAL, runs=tmp_path, tile=(2, 3), full=True)
    assert (again.run["tiles_reused"], again.run["tiles_computed"]) == (total, 0)
    assert not list(tmp_path.rglob("*.tmp"))
    xr.testing.assert_identical(resumed.data, ref_map.data)  # other tiling, same cells


def test_changed_configuration_reuses_no_tile(ref_map, runs):
    changed = overturning_map(SETTING, Tuning(0.05, zeta=0.1), OMEGA, BETA, SERIAL, runs=runs, tile=(2, 5), full=True)
    assert changed.run["run_folders"]["bare"] == ref_map.run["run_folders"]["bare"]
    assert changed.run["run_folders"]["damper"] != ref_map.run["run_folders"]["damper"]
    assert changed.run["tiles_computed"] == changed.run["tiles_reused"] == 6  # 2 x 3 tiles per part
    other = Setting(Block.reference(), rtol=1e-7, backend="c")
    fresh = overturning_map(other, TUNING, OMEGA, BETA, SERIAL, runs=runs, tile=(2, 5), full=True)
    assert (fresh.run["tiles_computed"], fresh.run["tiles_reused"]) == (12, 0)


def test_every_input_changes_the_configuration_hash():
    grids = {"damper": TUNING.record(), "Omega": OMEGA.record(), "beta": BETA.record()}
    base = part_config("map", "damper", SETTING, **grids)
    variants = [
        part_config("spectrum", "damper", SETTING, **grids),
        part_config("map", "damper", Setting(Block(H=2.0, B=0.5, M=1000.0, e=0.0)), **grids),
        part_config("map", "damper", SETTING, **{**grids, "damper": Tuning(0.06).record()}),
        part_config("map", "damper", SETTING, **{**grids, "Omega": Grid("Omega", 1.0, 6.0, 5).record()}),
        part_config("map", "damper", SETTING, **{**grids, "beta": Grid("beta", 0.5, 6.5, 12).record()}),
        part_config("map", "damper", Setting(Block.reference(), rtol=1e-7), **grids),
        part_config("map", "damper", Setting(Block.reference(), t_after=10.0), **grids),
        part_config("map", "damper", Setting(Block.reference(), backend="numpy"), **grids),
    ]
    hashes = {config_hash(c) for c in [base, *variants]}
    assert len(hashes) == 1 + len(variants)
    assert set(base["model_sha256"]) == {"block", "omd"}
    assert base["solver_sha256"] == study_config.solver_hash()


def _each_file_changes(folders, digest):
    """``digest()`` changes when any one file under ``folders`` gains a byte."""
    before = digest()
    files = sorted(p for folder in folders for p in folder.rglob("*") if p.is_file())
    assert files
    for path in files:
        original = path.read_bytes()
        path.write_bytes(original + b" ")
        try:
            assert digest() != before, path
        finally:
            path.write_bytes(original)


def test_every_source_of_the_simulator_keys_the_tiles(tmp_path):
    """Tiles of an older simulator are never reused: every file of rocking.sim and rocking.model is hashed."""
    root = Path(rocking.__file__).resolve().parent
    folders = []
    for package in study_config.SOLVER_PACKAGES:
        shutil.copytree(root / package, tmp_path / package, ignore=shutil.ignore_patterns("__pycache__"))
        folders.append(tmp_path / package)
    assert study_config.tree_hash(*folders) == study_config.solver_hash()
    names = {p.name for f in folders for p in f.rglob("*")}
    assert {"c_backend.py", "sim.c", "sim.h", "loading.py", "pulse.py"} <= names
    _each_file_changes(folders, lambda: study_config.tree_hash(*folders))


def test_every_generated_file_keys_the_tiles(tmp_path):
    """A regenerated model (any of its files) never reuses tiles of the old one."""
    folder = tmp_path / "omd"
    shutil.copytree(load_model("omd").folder, folder, ignore=shutil.ignore_patterns("__pycache__"))
    assert study_config.model_hash(str(folder)) == study_config.model_hash("omd")
    _each_file_changes([folder], lambda: study_config.tree_hash(folder))


# --- data, figures, CLI ---------------------------------------------------------------------


def test_cli_writes_data_and_figures_and_redraws_them(tmp_path, monkeypatch, capsys):
    out = str(tmp_path)
    grids = ["--Omega", "2", "5", "3", "--beta", "0.5", "5", "6"]
    # The PDF on request only: --pdf, or --formats.
    assert cli(["map", *tiny(*grids, "--out", out, "--pdf")]) == 0
    assert cli(["spectrum", *tiny(*grids, "--out", out)]) == 0
    optimize = ["--gammas", "0.05", "0.1", "--Tm-ratio", "0.5", "2", "3", "--refine", "1"]
    assert cli(["optimize", *tiny(*grids, *optimize, "--out", out, "--formats", "PNG,pdf")]) == 0
    printed = capsys.readouterr().out
    assert "saved" in printed and "Omega*" in printed and str(tmp_path) in printed
    kinds = ("map", "spectrum", "optimize")
    assert not (tmp_path / "spectrum.pdf").exists()
    for kind in kinds:
        for ext in ("nc", "csv", "json", "png") + ("pdf",) * (kind != "spectrum"):
            assert (tmp_path / f"{kind}.{ext}").stat().st_size > 0, (kind, ext)
        record = json.loads((tmp_path / f"{kind}.json").read_text())
        assert record["config"]["kind"] == kind and record["config_sha256"]
        assert {"python", "numpy", "scipy", "sympy", "rocking", "model_sha256"} <= set(record["versions"])
    assert load(tmp_path / "map").data["overturned"].shape == (2, 3, 6, 2)  # part, Omega, beta, sign

    for kind in kinds:
        (tmp_path / f"{kind}.png").unlink()
        (tmp_path / f"{kind}.pdf").unlink(missing_ok=True)

    def no_simulation(*args, **kwargs):
        raise AssertionError("redraw must not simulate")

    monkeypatch.setattr("rocking.study.overturning_map.run_cases", no_simulation)
    assert cli(["redraw", out]) == 0
    assert [p.name for p in tmp_path.glob("*.pdf")] == []
    assert cli(["redraw", str(tmp_path / "spectrum.nc"), "--pdf"]) == 0
    assert (tmp_path / "spectrum.pdf").stat().st_size > 0
    for kind in kinds:
        assert (tmp_path / f"{kind}.png").stat().st_size > 0
    # Any of a study's files names it, its CSV table too: the figures keep the study's stem.
    assert cli(["redraw", str(tmp_path / "map.csv")]) == 0
    assert not list(tmp_path.glob("map.csv.*"))


@pytest.mark.parametrize(
    "argv, message",
    [
        (["map", "--Omega", "1", "2", "0"], "Omega: the number of values N must be an integer in [1, 100000]"),
        (["map", "--Omega", "3", "2", "5"], "Omega: the range MIN MAX must have MIN < MAX"),
        (["map", "--beta", "0", "2", "5"], "beta: values must be > 0"),
        (["spectrum", "--beta", "1", "2", "x"], "--beta takes MIN MAX N"),
        (["map", "--rtol", "0"], "rtol must be in [1e-12, 0.01]"),
        (["map", "--rtol=-1e-8"], "rtol must be in [1e-12, 0.01]"),
        (["spectrum", "--beta-tol", "0"], "--beta-tol must be a relative tolerance in (0, 0.1]"),
        (["optimize", "--gammas", "0.05", "-1"], "gamma must be in [1e-10, 10] (got -1.0)"),
        (["optimize", "--gammas", "0.05", "0.05"], "--gammas must list distinct mass ratios m/M"),
        (["optimize", "--Tm-ratio", "10", "0.1", "5"], "Tm-ratio: the range MIN MAX must have MIN < MAX"),
        (["optimize", "--refine", "-1"], "refine must be an integer in [0, 1000]"),
        (["map", "--gamma", "0"], "gamma must be in [1e-10, 10] (got 0.0)"),
        (["map", "--Tm-ratio", "-2"], "--Tm-ratio must be > 0"),
        (["map", "--H", "2", "--B", "0.5", "--M", "1000", "--e", "0.3"], "e must be in (-B/2, B/2)"),
        (["map", "--e", "0.1"], "a block by its dimensions needs --H, --B, --M too (got --e)"),
        (["map", "--H", "2", "--lam", "4"], "not both"),
        (["map", "--lam", "4"], "needs --p"),
        (["map", "--workers", "0"], "workers must be an integer in [1, 1024]"),
        (["map", "--backend", "fortran"], "backend must be one of c, numpy"),
        (["map", "--t-after", "0"], "--t-after must be in (0, 10000] s"),
        (["map", "--tile", "0", "4"], "tile sizes must be >= 1"),
        (["redraw", "/nonexistent/study"], "no saved study"),
    ],
)
def test_bad_parameters_give_clear_errors(argv, message, capsys, tmp_path):
    options = [] if argv[0] == "redraw" else tiny("--out", str(tmp_path))
    assert cli([argv[0], *options, *argv[1:]]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


@pytest.mark.parametrize("argv", [["map", "--bogus"], ["map", "--Omega", "1", "2"], ["spectrum", "--workers", "two"]])
def test_malformed_options_are_argparse_errors(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        cli(argv)
    assert exc.value.code == 2 and "error:" in capsys.readouterr().err


def test_library_errors_name_the_parameter():
    with pytest.raises(ParameterError, match="Omega: the range"):
        Grid("Omega", 2.0, 1.0, 3)
    with pytest.raises(ParameterError, match="scheduler .* or dask_workers"):
        Execution(scheduler="tcp://127.0.0.1:1", dask_workers=2)
    with pytest.raises(ParameterError, match="coarse T_m grid must be logarithmic"):
        optimal_damper(SETTING, [0.05], OMEGA, BETA, SERIAL, Tm=Grid("Tm", 0.1, 10.0, 3))
    with pytest.raises(ParameterError, match="columns must be an integer >= 1"):
        minimum_overturning_spectrum(SETTING, TUNING, OMEGA, BETA, SERIAL, columns=0)


def test_repeated_mass_ratios_are_refused_before_any_simulation(monkeypatch):
    """Each mass ratio labels its results: a repeated one would fail only after all the work."""

    def no_simulation(*args, **kwargs):
        raise AssertionError("refused inputs must not simulate")

    monkeypatch.setattr("rocking.study.overturning_map.run_cases", no_simulation)
    message = r"^gammas must list distinct mass ratios m/M, to 6 significant digits \(got 0.05 more than once\)$"
    with pytest.raises(ParameterError, match=message):
        optimal_damper(SETTING, [0.05, 0.1, 0.05], OMEGA, BETA, SERIAL)
    with pytest.raises(ParameterError, match=message):
        rocking.optimal_damper(Block.reference(), [0.05, 0.0500000001], Omega=[4.0], beta=[0.5, 2.0, 4.0])


def test_a_map_tells_the_cells_saved_only_past_the_blocks_edge(tmp_path):
    """The paper's unlimited guide: cells the damper saves with its mass beyond B/2 are counted apart
    (issue 12: on the demo map every saved cell needed more than B/2). Every cell's stroke: a full map."""
    study = overturning_map(
        SETTING,
        TUNING,
        Grid("Omega", 5.0, 9.0, 5),
        Grid("beta", 4.0, 12.0, 9),
        SERIAL,
        runs=tmp_path / "map",
        full=True,
    )
    both, half = envelope(study.data), SETTING.block.B / 2
    saved, x_max = both["effect"].values > 0, both["x_max"].sel(part="damper").values
    assert study.summary["saved"] == saved.sum() > 0
    assert study.summary["saved_past_edges"] == int((saved & (x_max > half)).sum())
    assert 0 < study.summary["saved_past_edges"] <= study.summary["saved"]
    stroke = study.tables["map"]["damper_stroke_over_half_width"]
    assert np.array_equal(stroke, np.ravel(x_max) / half)
    assert int(np.sum((stroke > 1) & np.ravel(saved))) == study.summary["saved_past_edges"]
    from rocking.plot.figures import map_figure

    title = map_figure(study).axes[2].get_title()
    assert f"({study.summary['saved_past_edges']} only past the edge)" in title


def test_a_map_of_the_damper_with_stops_at_the_edges(tmp_path, capsys):
    """Tuning(stops=True) runs the damper of Stops.at_edges: contacts and bumper forces per cell, no mass past the
    block's edge, and fewer cells saved than the unlimited guide claims; the command line gives the same arrays.
    Every cell's contacts and forces: full maps."""
    grids = Grid("Omega", 5.0, 9.0, 5), Grid("beta", 4.0, 12.0, 9)
    free = overturning_map(SETTING, TUNING, *grids, SERIAL, runs=tmp_path / "free", full=True)
    stopped = overturning_map(SETTING, Tuning(0.05, stops=True), *grids, SERIAL, runs=tmp_path / "stops", full=True)
    a = stopped.data
    damper, bare = a.sel(part="damper"), a.sel(part="bare")
    assert damper["stop_contacts"].max() > 0 and np.nanmax(damper["bumper_force_max"]) > 0
    assert (bare["stop_contacts"] == 0).all() and (bare["bumper_force_max"] == 0).all()
    x_max = envelope(a)["x_max"].sel(part="damper").values
    assert np.nanmax(x_max) <= SETTING.block.B / 2 and stopped.summary["saved_past_edges"] == 0
    assert stopped.summary["saved"] < free.summary["saved"]
    L = SETTING.block.B / 2 - 0.02  # Stops.at_edges
    np.testing.assert_allclose(stopped.tables["map"]["damper_stroke_over_L"], np.ravel(x_max) / L)
    assert "damper_stroke_over_L" not in free.tables["map"]
    shorter = overturning_map(
        SETTING, Tuning(0.05, stops=True, stroke=0.1), *grids, SERIAL, runs=tmp_path / "short", full=True
    )
    shorter_x_max = envelope(shorter.data)["x_max"].sel(part="damper").values
    assert np.nanmax(shorter_x_max) < np.nanmax(x_max)
    np.testing.assert_allclose(shorter.tables["map"]["damper_stroke_over_L"], np.ravel(shorter_x_max) / 0.1)
    assert stopped.config["damper"]["stops"] is True and "stops" not in free.config["damper"]
    argv = [
        "map",
        "--stops",
        "--full",
        "--Omega",
        "5",
        "9",
        "5",
        "--beta",
        "4",
        "12",
        "9",
        "--workers",
        "1",
        "--no-progress",
    ]
    assert cli([*argv, "--out", str(tmp_path / "cli")]) == 0
    saved = load(tmp_path / "cli" / "map")
    for k in ("overturned", "stop_contacts", "x_max"):
        assert np.array_equal(saved.data[k], a[k], equal_nan=True), k


def test_stops_of_a_tuning_must_be_a_flag():
    with pytest.raises(ParameterError, match=r"^stops must be True or False"):
        Tuning(0.05, stops="edges")


def test_a_spectrum_of_the_damper_with_stops(tmp_path):
    """Tuning(stops=True) in a spectrum: the same bare block, another damped one (at Omega = 2 the stopped damper's
    beta_min, 1.265, is below even the bare block's, 1.284; the unlimited one claims 1.335)."""
    Omega, beta = Grid("Omega", 2.0, 6.0, 3), Grid("beta", 0.5, 10.0, 20)
    free = minimum_overturning_spectrum(SETTING, TUNING, Omega, beta, SERIAL, runs=tmp_path / "free")
    stopped = minimum_overturning_spectrum(SETTING, Tuning(0.05, stops=True), Omega, beta, SERIAL, runs=tmp_path / "s")
    xr.testing.assert_identical(stopped.data.sel(part="bare"), free.data.sel(part="bare"))
    assert not np.array_equal(stopped.data["beta_min"].sel(part="damper"), free.data["beta_min"].sel(part="damper"))


def test_the_optimal_damper_with_stops_at_the_edges(tmp_path):
    """optimal_damper(stops=True) searches the damper with stops: its gains differ from the unlimited guide's."""
    grids = Grid("Omega", 2.0, 4.0, 2), Grid("beta", 0.5, 8.0, 16)
    search = {"Tm": Grid("Tm-ratio", 0.5, 2.0, 4, log=True), "refine": 1}
    free = optimal_damper(SETTING, [0.05], *grids, SERIAL, runs=tmp_path / "free", **search)
    with pytest.warns(EdgeWarning, match=r"at 1 of 2 \(gamma, Omega\) points \(0 at the smallest, 0.5; 1 at the"):
        stopped = optimal_damper(SETTING, [0.05], *grids, SERIAL, runs=tmp_path / "stops", stops=True, **search)
    assert int(np.abs(stopped.data["edge_opt"]).sum()) == 1
    assert stopped.config["stops"] is True and "stops" not in free.config
    assert np.array_equal(stopped.data["beta_min"], free.data["beta_min"])
    assert not np.array_equal(stopped.data["gain_coarse"], free.data["gain_coarse"], equal_nan=True)
    with pytest.raises(ParameterError, match=r"^stops must be True or False"):
        optimal_damper(SETTING, [0.05], *grids, SERIAL, runs=tmp_path / "x", stops=1)
