"""A saved study is checked before it is read (issue 36): its NetCDF file's storage and variables from its
metadata (no data read for a file the record does not describe), damaged files in one line; its saved strings and
configuration fields bounded and validated as the command line's."""

from __future__ import annotations

import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import rocking
from rocking.cli.main import main
from rocking.study.overturning_map import overturning_map

from .crafted_hdf5 import add_dataset

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("rocking_bench_damaged_nc", ROOT / "bench" / "damaged_nc.py")
damaged_nc = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(damaged_nc)


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """A small map of both directions (the reference block is eccentric), saved: its folder."""
    folder = tmp_path_factory.mktemp("saved")
    grids = rocking.Grid("Omega", 1.0, 6.0, 4), rocking.Grid("beta", 1.0, 6.0, 5)
    execution = rocking.Execution(workers=1, progress=False)
    study = overturning_map(
        rocking.Setting(rocking.Block.reference()), rocking.Tuning(0.04), *grids, execution, runs=folder / "runs"
    )
    rocking.save(study, folder)
    return folder


def _copy(saved: Path, folder: Path) -> Path:
    """A copy of the saved map in ``folder``: its stem."""
    for suffix in (".nc", ".json"):
        shutil.copy(saved / f"map{suffix}", folder / f"map{suffix}")
    return folder / "map"


def _redraw_one_line(stem: Path, capsys) -> str:
    """``rocking redraw`` of ``stem``: exit 2 and one line naming its NetCDF file."""
    capsys.readouterr()
    assert main(["redraw", str(stem)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("rocking redraw: error: ") and f"{stem}.nc" in err, err
    return err


# --- crafted files: refused from their metadata, before any data are read ---------------------------------

CRAFTED = {
    # Never written: the file stays small, a read would allocate them.
    "unlisted variable of 2.5e8 doubles": (lambda nc, d: add_dataset(nc, "extra", 250_000_000), "variable(s) extra"),
    "unlisted variable of 1e11 doubles": (lambda nc, d: add_dataset(nc, "extra", 10**11), "variable(s) extra"),
    "external file /dev/zero": (
        lambda nc, d: add_dataset(nc, "zero", 250_000_000, external="/dev/zero"),
        "dataset zero is stored in 1 external file(s)",
    ),
    "virtual dataset": (
        lambda nc, d: add_dataset(nc, "copy", 4, virtual=(str(d / "other.nc"), "Omega")),
        "dataset copy is virtual",
    ),
}


@pytest.mark.parametrize("case", CRAFTED)
def test_crafted_files_are_refused_from_their_metadata(case, saved, tmp_path, capsys):
    stem = _copy(saved, tmp_path)
    shutil.copy(saved / "map.nc", tmp_path / "other.nc")
    craft, message = CRAFTED[case]
    craft(stem.with_suffix(".nc"), tmp_path)
    assert stem.with_suffix(".nc").stat().st_size < 200_000  # nothing written: the attack is in the metadata
    start = time.perf_counter()
    with pytest.raises(rocking.ParameterError, match=re.escape(message)) as refused:
        rocking.load(stem)
    assert time.perf_counter() - start < 2.0
    assert "\n" not in str(refused.value) and str(stem.with_suffix(".nc")) in str(refused.value)
    assert message in _redraw_one_line(stem, capsys)


def test_a_listed_variable_stored_elsewhere_is_refused(saved, tmp_path):
    """A variable of the record's name, shape and type whose bytes are in an external file: refused by its storage."""
    stem = _copy(saved, tmp_path)
    add_dataset(stem.with_suffix(".nc"), "x_max", 80, external="/dev/zero", replace=True)
    with pytest.raises(rocking.ParameterError, match="dataset x_max is stored in 1 external file"):
        rocking.load(stem)


def _run_measured(argv: list[str], folder: Path, timeout: float = 60.0) -> tuple[str, int]:
    """Run ``argv``: its output (stdout and stderr) and its largest resident size, KiB; killed after ``timeout`` s."""
    out = folder / "out.txt"
    with open(out, "w") as f:
        process = subprocess.Popen(argv, cwd=ROOT, stdout=f, stderr=subprocess.STDOUT)
    deadline = time.monotonic() + timeout
    while True:
        pid, status, usage = os.wait4(process.pid, os.WNOHANG)
        if pid:
            process.returncode = os.waitstatus_to_exitcode(status)
            return out.read_text().strip(), usage.ru_maxrss
        if time.monotonic() > deadline:
            process.kill()
            process.wait()
            raise AssertionError(f"{argv} hung: {out.read_text()[-300:]}")
        time.sleep(0.05)


def test_an_external_fifo_never_blocks_and_nothing_is_allocated(saved, tmp_path):
    """An unlisted dataset stored in a FIFO (a read would block forever): load and redraw refuse it in one line,
    at once, in processes that stay small (no 2 GB read)."""
    stem = _copy(saved, tmp_path)
    os.mkfifo(tmp_path / "fifo")
    add_dataset(stem.with_suffix(".nc"), "extra", 250_000_000, external=str(tmp_path / "fifo"))
    load = f"import rocking\ntry:\n    rocking.load({str(stem)!r})\nexcept rocking.ParameterError as e:\n    print(e)"
    for argv in ([sys.executable, "-c", load], [sys.executable, "-m", "rocking", "redraw", str(stem)]):
        text, kib = _run_measured(argv, tmp_path)
        assert text.count("\n") == 0 and "dataset extra is stored in 1 external file(s)" in text, text
        assert kib < 1_000_000, kib  # far below the 2 GB of the dataset


# --- damaged copies of a real map.nc: one line or the same data ------------------------------------------


def test_damaged_copies_are_refused_in_one_line_or_read_whole(saved, tmp_path):
    """40 damaged copies (the bench's 400: bench/damaged_nc.py), checked in this process: refused in one line
    naming the file, or read with the data saved (the damage hit bytes that hold none); nothing else."""
    original = rocking.load(saved / "map").data
    outcomes = {"refused": 0, "loaded": 0}
    for copy in damaged_nc.copies(saved, tmp_path, 40, seed=3636):
        try:
            data = rocking.load(copy["stem"]).data
        except rocking.ParameterError as exc:
            assert "\n" not in str(exc) and copy["stem"] in str(exc), str(exc)
            outcomes["refused"] += 1
            continue
        for name, variable in original.variables.items():
            assert data[name].values.tobytes() == variable.values.tobytes(), (copy, name)
        outcomes["loaded"] += 1
    assert outcomes["refused"] > 0 and outcomes["loaded"] > 0, outcomes


def test_a_saved_study_still_loads_as_saved(saved):
    study = rocking.load(saved / "map")
    record = json.loads((saved / "map.json").read_text())
    assert set(study.data.variables) == set(record["variables"])
    assert study.data["part"].values.tolist() == ["bare", "damper"] and study.data["computed"].dtype == np.bool_
