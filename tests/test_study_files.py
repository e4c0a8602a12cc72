"""Studies and their files (issue 10): damaged tiles, atomic saves, unreadable studies, Ctrl-C,
unreachable Dask, unwritable output folders, and the checks of a study's configuration."""

from __future__ import annotations

import argparse
import dataclasses
import errno
import glob
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import rocking
import rocking.cli.study
from rocking import Block, ParameterError
from rocking.cli.study import add_study_commands
from rocking.model import outputs
from rocking.study import files, storage, tiles
from rocking.study.config import MAX_CELLS, MAX_N, Grid, Setting, Tuning, Variant
from rocking.study.optimize import optimal_damper
from rocking.study.overturning_map import overturning_map
from rocking.study.spectrum import minimum_overturning_spectrum
from rocking.study.storage import load, save
from rocking.study.tiles import Execution, TileWarning, load_tile, save_tile

SETTING = Setting(Block.reference())
SERIAL = Execution(workers=1, progress=False)
OMEGA = Grid("Omega", 1.0, 6.0, 4)
BETA = Grid("beta", 0.5, 6.0, 12)
TILE = (2, 5)  # 2 x 3 tiles per part
GRIDS = ["--Omega", "1", "6", "4", "--beta", "0.5", "6", "12", "--tile", "2", "5", "--full"]
ROOT = Path(rocking.__file__).resolve().parent.parent


def cli(argv: list[str]) -> int:
    """``rocking <argv>`` through :func:`add_study_commands` on a fresh parser."""
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    return args.func(args)


def one_line_error(capsys, command: str) -> str:
    """The error the command printed: exactly one line, ``rocking COMMAND: error: ...``, no traceback."""
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"rocking {command}: error: "), err
    return err


def same_bits(a: xr.Dataset, b: xr.Dataset) -> None:
    """Two studies' data hold the same variables (coordinates included), bit for bit."""
    assert a.variables.keys() == b.variables.keys()
    for k in a.variables:
        x, y = a[k].values, b[k].values
        assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), k


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The reference map, and its run folder (to copy and damage)."""
    runs = tmp_path_factory.mktemp("reference") / "runs"
    return overturning_map(SETTING, Tuning(), OMEGA, BETA, SERIAL, runs=runs, tile=TILE, full=True), runs


# --- 1. damaged tiles -----------------------------------------------------------------------------


def _rewrite(path: Path, change) -> None:
    """Save the tile's arrays changed by ``change(arrays)``, with a manifest that matches them (a valid tile)."""
    arrays = load_tile(path)
    save_tile(path, change(arrays))


def _keep_manifest(path: Path) -> None:
    """Change one value and keep the old manifest: a valid .npz whose content no longer matches its checksum."""
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["impacts"] = arrays["impacts"] + 1
    np.savez(path, **arrays)


DAMAGES = {
    # A valid .npz with wrong values, as another program (or an older rocking) would write it: no manifest.
    "valid npz, wrong values": lambda p, other: np.savez(p, **{**load_tile(p), "impacts": np.full((2, 5), 7)}),
    "valid npz, wrong values, old manifest": lambda p, other: _keep_manifest(p),
    "truncated": lambda p, other: p.write_bytes(p.read_bytes()[: p.stat().st_size // 2]),
    "flipped byte": lambda p, other: p.write_bytes(_flip(p.read_bytes(), p.stat().st_size // 2)),
    "missing key": lambda p, other: _rewrite(p, lambda a: {k: v for k, v in a.items() if k != "x_max"}),
    "wrong shape": lambda p, other: _rewrite(p, lambda a: {k: v[:1] for k, v in a.items()}),
    "foreign file (.npy)": lambda p, other: _npy(p),
    "another tile's file": lambda p, other: shutil.copyfile(other, p),
}


def _npy(path: Path) -> None:
    """A NumPy file that is not an archive, under the name of one."""
    with open(path, "wb") as f:
        np.save(f, np.arange(10))


def _flip(data: bytes, at: int) -> bytes:
    return data[:at] + bytes([data[at] ^ 0xFF]) + data[at + 1 :]


def test_damaged_tiles_are_recomputed_with_a_warning_never_reused(reference, tmp_path, capsys):
    ref, ref_runs = reference
    runs = tmp_path / "runs"
    shutil.copytree(ref_runs, runs)
    stored = sorted(runs.rglob("tile-*.npz"))
    assert len(stored) == 12
    damaged = {}
    for (kind, damage), path in zip(DAMAGES.items(), stored):
        damage(path, stored[-1])
        damaged[path] = kind
    with pytest.warns(TileWarning) as caught:
        study = overturning_map(SETTING, Tuning(), OMEGA, BETA, SERIAL, runs=runs, tile=TILE, full=True)
    warned = {Path(str(w.message).partition(": damaged tile")[0]) for w in caught}
    assert warned == set(damaged), {str(w.message) for w in caught}
    assert (study.run["tiles_computed"], study.run["tiles_reused"]) == (len(damaged), 12 - len(damaged))
    same_bits(study.data, ref.data)
    for path in damaged:  # recomputed and stored whole: the next run reuses all, silently
        tile, ref_tile = load_tile(path), load_tile(ref_runs / path.relative_to(runs))
        assert tile.keys() == ref_tile.keys() and all(np.array_equal(tile[k], ref_tile[k]) for k in tile)
    # The command line shows the warning in one line, like its errors.
    (stored[0]).write_bytes(b"not a tile")
    assert cli(["map", *GRIDS, "--workers", "1", "--no-progress", "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert (
        err == f"rocking map: warning: {stored[0]}: damaged tile (unreadable (ValueError: not an .npz archive)); "
        "computing it again\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", TileWarning)
        again = overturning_map(SETTING, Tuning(), OMEGA, BETA, SERIAL, runs=runs, tile=TILE, full=True)
    assert again.run["tiles_reused"] == 12
    same_bits(again.data, ref.data)


# --- 2. atomic saves ------------------------------------------------------------------------------


def _leftovers(folder: Path) -> list[str]:
    """Temporary files and folders of a save or a tile left in ``folder`` (none should be)."""
    return sorted(p.name for p in folder.rglob(".*"))


def test_a_study_is_published_whole_or_not_at_all(reference, tmp_path, monkeypatch):
    study = reference[0]
    written = save(study, tmp_path)
    assert [p.suffix for p in written] == [".nc", ".csv", ".json"]  # the JSON record last
    before = {p.name: p.read_bytes() for p in written}
    changed = dataclasses.replace(study, data=study.data.assign(impacts=study.data["impacts"] * 0))

    def crash(*args, **kwargs):
        raise KeyboardInterrupt  # Ctrl-C while the files are written

    monkeypatch.setattr(storage, "write_csv", crash)
    with pytest.raises(KeyboardInterrupt):
        save(changed, tmp_path)
    assert {p.name: p.read_bytes() for p in written} == before and not _leftovers(tmp_path)  # the old study, whole
    monkeypatch.undo()
    real_replace = storage.os.replace
    moved = []

    def crash_after_one(src, dst):
        if moved:
            raise KeyboardInterrupt  # Ctrl-C between two renames of the publication
        moved.append(dst)
        real_replace(src, dst)

    monkeypatch.setattr(storage.os, "replace", crash_after_one)
    with pytest.raises(KeyboardInterrupt):
        save(changed, tmp_path)
    monkeypatch.undo()
    assert not (tmp_path / "map.json").exists() and not _leftovers(tmp_path)  # no study, never a mix of two
    with pytest.raises(ParameterError, match="map.json is missing .* a save cut short leaves no .json"):
        load(tmp_path / "map")
    # A save killed outright leaves its temporary folder: the next save of that name removes it.
    abandoned = tmp_path / f".map.saving-{_dead_pid()}-x"
    abandoned.mkdir()
    (abandoned / "map.nc").write_bytes(b"partial")
    save(changed, tmp_path)
    assert not _leftovers(tmp_path)
    same_bits(load(tmp_path / "map").data, changed.data)


def _dead_pid() -> int:
    """The id of a process that has ended."""
    process = subprocess.Popen([sys.executable, "-c", "pass"])
    process.wait()
    return process.pid


@pytest.mark.parametrize("umask", [0o022, 0o027, 0o002])
def test_new_files_have_the_mode_of_the_umask(reference, tmp_path, umask):
    old = os.umask(umask)
    try:
        written = save(reference[0], tmp_path)
        tile = tmp_path / "runs" / "tile.npz"
        tile.parent.mkdir()
        save_tile(tile, {"a": np.arange(3)})
    finally:
        os.umask(old)
    modes = {p.name: oct(p.stat().st_mode & 0o777) for p in [*written, tile]}
    assert modes == {p.name: oct(0o666 & ~umask) for p in [*written, tile]}


# --- 2b. a full disk ------------------------------------------------------------------------------

MAP_FILES = ("map.nc", "map.csv", "map.json")


def _enospc(*args, **kwargs):
    raise OSError(errno.ENOSPC, "No space left on device")


def _full_at(monkeypatch, stage: str) -> None:
    """Make the writer of ``stage`` (``tile`` after 3 tiles, or a study's file) fail as on a full disk."""
    if stage == "map.nc, older xarray":  # it writes the file itself; the library's error has no errno
        monkeypatch.setattr(outputs, "no_space", lambda folder: True)
        error = {None: ValueError("invalid engine for creating bytes with to_netcdf")}
        monkeypatch.setattr(
            "xarray.Dataset.to_netcdf",
            lambda self, path=None, **k: _raise(error.get(path, RuntimeError("NetCDF: HDF error"))),
        )
        return
    real = outputs.write_file
    tiles_written = []

    def write_file(path, write, mode="wb"):
        if stage == "tile" and ".tile-" in path.name:
            tiles_written.append(path)
            if len(tiles_written) > 3:
                _enospc()
        if path.name == stage:
            _enospc()
        real(path, write, mode)

    for module in (outputs, files, storage):  # every atomic write (tiles, NetCDF), the CSV tables, the study
        monkeypatch.setattr(module, "write_file", write_file)


def _raise(exc: Exception):
    raise exc


@pytest.mark.parametrize("stage", ["tile", *MAP_FILES, "map.nc, older xarray"])
def test_a_full_disk_gives_one_line_keeps_the_tiles_and_a_rerun_completes(stage, tmp_path, monkeypatch, capsys):
    argv = ["map", *GRIDS, "--workers", "1", "--no-progress", "--out", str(tmp_path)]
    with monkeypatch.context() as patched:
        _full_at(patched, stage)
        assert cli(argv) == 1
    kept = len(list((tmp_path / "runs").rglob("tile-*.npz")))
    file = re.escape(str(tmp_path / stage.split(",")[0]))
    where = r"\S+/runs/map-\w+-\w+/tile-\d+-\d+\.npz" if stage == "tile" else file
    assert re.fullmatch(
        f"rocking map: error: disk full writing {where}: {kept} tiles kept, rerun to resume\n", capsys.readouterr().err
    )
    assert kept == (3 if stage == "tile" else 12)
    assert not [f for f in MAP_FILES if (tmp_path / f).exists()] and not _leftovers(tmp_path)
    assert cli(argv) == 0
    assert f"{12 - kept} tiles computed, {kept} reused" in capsys.readouterr().out
    assert all((tmp_path / f).is_file() for f in MAP_FILES)
    load(tmp_path / "map")


def test_a_full_disk_at_the_figures_keeps_the_published_study(tmp_path, monkeypatch, capsys):
    argv = ["map", *GRIDS, "--workers", "1", "--no-progress", "--out", str(tmp_path), "--pdf"]
    with monkeypatch.context() as patched:
        patched.setattr("matplotlib.figure.Figure.savefig", _enospc)
        patched.setattr(rocking.cli.study, "no_space", lambda folder: True)
        assert cli(argv) == 1
    assert capsys.readouterr().err == (
        f"rocking map: error: disk full writing {tmp_path / 'map.png'} and .pdf: 12 tiles kept, rerun to resume\n"
    )
    assert all((tmp_path / f).is_file() for f in MAP_FILES)  # the data are published, whole
    load(tmp_path / "map")
    assert cli(argv) == 0 and (tmp_path / "map.pdf").is_file()


def _mount_tmpfs(folder: Path, size: str, remount: bool = False) -> bool:
    options = f"remount,size={size}" if remount else f"size={size}"
    mount = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(folder)], capture_output=True)
    return mount.returncode == 0


def test_a_real_full_disk_a_tmpfs(tmp_path, capsys):
    """On a small tmpfs (mounting needs root: skipped otherwise), growing until the study fits: every failure
    is one line and publishes nothing, and the last run completes with every file."""
    disk = tmp_path / "disk"
    disk.mkdir()
    if shutil.which("mount") is None or not _mount_tmpfs(disk, "64k"):
        pytest.skip("cannot mount a tmpfs here (mounting needs root)")
    try:
        argv = ["map", *GRIDS, "--workers", "1", "--no-progress", "--out", str(disk / "out")]
        failed_at = []
        for size in range(64, 2048, 32):
            assert _mount_tmpfs(disk, f"{size}k", remount=True)
            code = cli(argv)
            err = capsys.readouterr().err
            if code == 0:
                break
            assert code == 1, err
            match = re.fullmatch(
                r"rocking map: error: disk full writing (\S+( and \.pdf)?): (\d+) tiles kept, "
                r"rerun to resume\n",
                err,
            )
            assert match, err
            failed_at.append(Path(match.group(1)).name)
            assert not _leftovers(disk / "out")
            # No study, or the whole one of an earlier run (published before its figures did not fit).
            present = [f for f in MAP_FILES if (disk / "out" / f).exists()]
            assert present in ([], list(MAP_FILES)), (failed_at, present)
        assert code == 0 and all((disk / "out" / f).is_file() for f in MAP_FILES), failed_at
        load(disk / "out" / "map")
        assert any(name.startswith("tile-") for name in failed_at), failed_at
        assert any(name in MAP_FILES for name in failed_at), failed_at
    finally:
        subprocess.run(["umount", str(disk)], check=True)


# --- 3. unreadable saved studies ------------------------------------------------------------------


def _rewrite_nc(folder: Path, change) -> None:
    """Write the study's NetCDF file again with its data changed by ``change(dataset)``."""
    data = xr.load_dataset(folder / "map.nc", engine="netcdf4")
    (folder / "map.nc").unlink()
    change(data).to_netcdf(folder / "map.nc", engine="netcdf4")


def _old_format(folder: Path, version: int) -> None:
    """The record of a study saved in format ``version`` by an earlier version: 2, an .npz of arrays named by
    dimension; 3, an IDA's fit in its JSON summary."""
    record = json.loads((folder / "map.json").read_text())
    record["format"] = version
    (folder / "map.json").write_text(json.dumps(record))


def _edited(folder: Path, change) -> None:
    """The record edited by hand: ``change(record)``, its checksums left as saved."""
    record = json.loads((folder / "map.json").read_text())
    change(record)
    (folder / "map.json").write_text(json.dumps(record))


BROKEN = {
    "truncated nc": ("map.nc", lambda f: (f / "map.nc").write_bytes((f / "map.nc").read_bytes()[:900])),
    "nc of text": ("map.nc", lambda f: (f / "map.nc").write_text("hello")),
    "nc of a .npy": ("map.nc", lambda f: _npy(f / "map.nc")),
    "changed variable": ("map.nc", lambda f: _rewrite_nc(f, lambda d: d.assign(impacts=d["impacts"] * 0 + 1))),
    "missing variable": ("map.nc", lambda f: _rewrite_nc(f, lambda d: d.drop_vars("computed"))),
    "another study's file": ("map.nc", lambda f: _rewrite_nc(f, lambda d: d.isel(beta=slice(1, None)))),
    "format 2": ("map.json", lambda f: _old_format(f, 2)),
    "format 3": ("map.json", lambda f: _old_format(f, 3)),
    "corrupt JSON": ("map.json", lambda f: (f / "map.json").write_text('{"kind": "map", ')),
    "binary JSON": ("map.json", lambda f: (f / "map.json").write_bytes(b"\xff\xfe\x00")),
    "foreign JSON": ("map.json", lambda f: (f / "map.json").write_text('{"name": "something else"}')),
    "JSON list": ("map.json", lambda f: (f / "map.json").write_text("[1, 2]")),
    "edited geometry": ("map.json", lambda f: _edited(f, lambda r: r["config"]["block"].update(e=0.1))),
    "edited damper": ("map.json", lambda f: _edited(f, lambda r: r["config"].update(damper={"gamma": "abc"}))),
    "edited summary": ("map.json", lambda f: _edited(f, lambda r: r["summary"].update(saved=999))),
    "unknown kind": ("map.json", lambda f: (f / "map.json").write_text('{"kind": "x", "config": {}, "summary": {}}')),
}


@pytest.mark.parametrize("broken", BROKEN)
def test_unreadable_studies_give_one_line_errors(broken, reference, tmp_path, capsys):
    culprit, damage = BROKEN[broken]
    save(reference[0], tmp_path)
    damage(tmp_path)
    assert cli(["redraw", str(tmp_path / "map.nc")]) == 2
    assert str(tmp_path / culprit) in one_line_error(capsys, "redraw")
    with pytest.raises(ParameterError, match=str(tmp_path / culprit)):
        rocking.load(tmp_path / "map")


# --- 4. Ctrl-C ------------------------------------------------------------------------------------

#: Sixteen tiles of 10 x 10 long pulses below the uplift threshold (two parts, bare and damped), about 0.1 s each
#: on the C back end: the first is kept before the interrupt, not the last.
SLOW = ["--Omega", "0.01", "0.012", "40", "--beta", "0.3", "0.6", "20", "--tile", "10", "10", "--full"]


def test_ctrl_c_ends_a_study_at_once_and_keeps_its_finished_tiles(tmp_path, capsys):
    argv = ["map", *SLOW, "--workers", "2", "--no-progress", "--out", str(tmp_path)]
    process = subprocess.Popen(
        [sys.executable, "-m", "rocking.cli.main", *argv], cwd=ROOT, stderr=subprocess.PIPE, text=True
    )
    deadline = time.monotonic() + 60
    while not glob.glob(str(tmp_path / "runs" / "*" / "tile-*.npz")) and time.monotonic() < deadline:
        assert process.poll() is None, process.communicate()
        time.sleep(0.01)
    start = time.monotonic()
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=30)
    took = time.monotonic() - start
    kept = len(list(tmp_path.rglob("tile-*.npz")))
    assert process.returncode == 130 and took < 2.0, (process.returncode, took, err)
    assert err == (
        f"rocking map: interrupted: {kept} of 16 tiles kept in {tmp_path / 'runs'}; "
        "run the same command again to resume\n"
    )
    assert 1 <= kept < 16 and not list(tmp_path.rglob("*.tmp"))
    assert cli(argv) == 0
    assert f"{16 - kept} tiles computed, {kept} reused" in capsys.readouterr().out


# --- 5. Dask --------------------------------------------------------------------------------------


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_dask_unreachable_or_missing_gives_one_line_errors(tmp_path, monkeypatch, capsys):
    pytest.importorskip("distributed")
    monkeypatch.setattr(tiles, "SCHEDULER_TIMEOUT", 1.0)
    address = f"tcp://127.0.0.1:{_closed_port()}"
    start = time.monotonic()
    assert cli(["map", *GRIDS, "--no-progress", "--out", str(tmp_path), "--scheduler", address]) == 2
    assert time.monotonic() - start < 4.0
    err = one_line_error(capsys, "map")
    assert f"scheduler {address}: no Dask scheduler answered within 1 s" in err
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if the dask extra were not installed
    for option in (["--dask-workers", "2"], ["--scheduler", address]):
        assert cli(["map", *GRIDS, "--out", str(tmp_path), *option]) == 2
        assert 'Dask, which is not installed (no module distributed): pip install "rocking[dask]"' in one_line_error(
            capsys, "map"
        )


# --- 6. unwritable output -------------------------------------------------------------------------


def test_unwritable_output_gives_one_line_errors_naming_it(reference, tmp_path, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("in the way")
    for out, why in ((blocker, "it is a file, not a folder"), (blocker / "sub", f"{blocker} is a file, not a folder")):
        for command in ("map", "spectrum", "optimize"):
            assert cli([command, "--Omega", "1", "6", "2", "--out", str(out)]) == 2
            assert one_line_error(capsys, command) == (
                f"rocking {command}: error: --out {out}: cannot write there ({why})\n"
            )
        with pytest.raises(ParameterError, match=f"output folder {out}: cannot write there"):
            save(reference[0], out)
        with pytest.raises(ParameterError, match=f"tiles folder {out}/runs/map-bare-.*: cannot write there"):
            overturning_map(SETTING, Tuning(), OMEGA, BETA, SERIAL, runs=out / "runs")
    assert blocker.read_text() == "in the way"


# --- the configuration ----------------------------------------------------------------------------

BLOCK = Block.reference()
NAN, INF = float("nan"), float("inf")

BAD_CONFIGURATIONS = [
    (lambda: Grid("Omega", 1.0, 2.0, MAX_N + 1), f"Omega: the number of values N must be an integer in [1, {MAX_N}]"),
    (lambda: Grid("Omega", 1.0, 2.0, 3.0), "Omega: the number of values N must be an intege"),
    (lambda: Grid("Omega", 1.0, 2.0, True), "Omega: the number of values N must be an intege"),
    (lambda: Grid("Omega", NAN, 2.0, 3), "Omega: low end must be a finite numbe"),
    (lambda: Grid("beta", 1.0, INF, 3), "beta: high end must be a finite numbe"),
    (lambda: Grid("beta", "1", 2.0, 3), "beta: low end must be a finite numbe"),
    (lambda: Grid("beta", True, 2.0, 3), "beta: low end must be a finite numbe"),
    (lambda: Grid("beta", 1.0, 2.0, 3, log="yes"), "beta: log must be True or False"),
    (lambda: Grid(7, 1.0, 2.0, 3), "a grid's name must be a string"),
    (lambda: Setting("reference"), "block must be a rocking.Block"),
    (lambda: Setting(BLOCK, rtol=NAN), "rtol must be finite (got nan)"),
    (lambda: Setting(BLOCK, rtol=True), "rtol must be a real number (got True)"),
    (lambda: Setting(BLOCK, t_after=INF), "t_after must be finite (got inf)"),
    (lambda: Setting(BLOCK, t_after=True), "t_after must be a real number"),
    (lambda: Setting(BLOCK, backend=None), "backend must be one of c, numpy"),
    (lambda: Tuning(gamma=NAN), "gamma must be finite (got nan)"),
    (lambda: Tuning(gamma=0), "gamma must be in [1e-10, 10] (got 0.0)"),
    (lambda: Tuning(zeta=-0.1), "zeta must be in [0, 10]"),
    (lambda: Tuning(h=INF), "h must be finite (got inf)"),
    (lambda: Tuning(omega_ratio="1"), "omega_ratio must be a real number"),
    (lambda: Variant("no-such-model"), "no-such-model"),
    (lambda: Variant("pendulum", [1.0]), "params must be a dict"),
    (
        lambda: Variant("pendulum", {"m": NAN, "l": 0.3, "x_p": 0, "y_p": 0, "k_phi": 0, "c_phi": 1}),
        "m must be a finite numbe",
    ),
    (lambda: Execution(workers=0), "workers must be an integer in [1, 1024]"),
    (lambda: Execution(workers=10**6), "workers must be an integer in [1, 1024]"),
    (lambda: Execution(workers=2.0), "workers must be an integer in [1, 1024]"),
    (lambda: Execution(dask_workers=True), "dask_workers must be an integer in [1, 1024]"),
    (lambda: Execution(scheduler=" "), "scheduler must be an address"),
    (lambda: Execution(progress="no"), "progress must be True or False"),
    (
        lambda: overturning_map(SETTING, Tuning(), Grid("Omega", 1, 2, 5000), Grid("beta", 1, 2, 5000), SERIAL),
        f"Omega (5000) x beta (5000): 25000000 cells, at most {MAX_CELLS}",
    ),
    (lambda: overturning_map("setting", Tuning(), OMEGA, BETA, SERIAL), "setting must be a rocking.Setting"),
    (lambda: overturning_map(SETTING, Tuning(), (1, 6, 4), BETA, SERIAL), "Omega must be a rocking.Grid"),
    (lambda: overturning_map(SETTING, Tuning(), OMEGA, BETA, 2), "execution must be a rocking.Execution"),
    (lambda: overturning_map(SETTING, Tuning(), OMEGA, BETA, SERIAL, tile=(2.5, 3)), "tile must be two integers"),
    (lambda: overturning_map(SETTING, Tuning(), OMEGA, BETA, SERIAL, runs=3), "runs must be a folde"),
    (lambda: minimum_overturning_spectrum(SETTING, Tuning(), OMEGA, 5, SERIAL), "beta must be a rocking.Grid"),
    (lambda: minimum_overturning_spectrum(SETTING, Tuning(), OMEGA, BETA, SERIAL, tol=NAN), "beta_tol must be"),
    (lambda: optimal_damper(SETTING, [True], OMEGA, BETA, SERIAL), "gamma must be a real number"),
    (lambda: optimal_damper(SETTING, [0.05], OMEGA, BETA, SERIAL, refine=True), "refine must be an intege"),
    (lambda: optimal_damper(SETTING, [0.05], OMEGA, BETA, SERIAL, zeta=NAN), "zeta must be finite (got nan)"),
    (lambda: optimal_damper(SETTING, [0.05], OMEGA, BETA, SERIAL, h=INF), "h must be finite (got inf)"),
]


@pytest.mark.parametrize("make, message", BAD_CONFIGURATIONS)
def test_bad_configurations_are_refused_up_front(make, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # nothing may be written (out/runs) before the refusal: it would be here
    with pytest.raises(ParameterError, match=re.escape(message)):
        make()
    assert not list(tmp_path.iterdir())
