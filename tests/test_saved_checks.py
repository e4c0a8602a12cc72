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
import warnings
from pathlib import Path

import numpy as np
import pytest

import rocking
from rocking.cli.main import main
from rocking.model.stochastic import DEFAULT_SITE
from rocking.plot import figures
from rocking.study import files, storage
from rocking.study.config import config_hash
from rocking.study.overturning_map import TMaxWarning, overturning_map
from rocking.study.storage import summary_hash

from .crafted_hdf5 import add_dataset, zero_global_heap

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


def test_metadata_the_hdf5_library_loops_on_is_refused_in_time(saved, tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(files, "HDF5_CHECK_SECONDS", 2.0)
    stem = _copy(saved, tmp_path)
    zero_global_heap(stem.with_suffix(".nc"))
    start = time.perf_counter()
    with pytest.raises(rocking.ParameterError, match=re.escape("its HDF5 metadata cannot be read in 2 s (damaged)")):
        rocking.load(stem)
    assert time.perf_counter() - start < 10
    _redraw_one_line(stem, capsys)


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


# --- saved strings and configuration fields (item 3) ------------------------------------------------------


@pytest.fixture(scope="module")
def variant(tmp_path_factory):
    """A small map of a model variant (its damper names its model: a saved text in the figure's title), saved."""
    folder = tmp_path_factory.mktemp("variant")
    grids = rocking.Grid("Omega", 2.0, 6.0, 2), rocking.Grid("beta", 1.0, 6.0, 3)
    damper = rocking.Variant("pendulum", {"m": 50.0, "l": 0.5, "x_p": 0.0, "y_p": 2.55, "k_phi": 0.0, "c_phi": 1.0})
    execution = rocking.Execution(workers=1, progress=False)
    block = rocking.Block.reference()
    with warnings.catch_warnings():  # long pendulum responses reach t_max: no matter here
        warnings.simplefilter("ignore", TMaxWarning)
        study = overturning_map(rocking.Setting(block), damper, *grids, execution, runs=folder / "runs", full=True)
    rocking.save(study, folder)
    return folder


def _forged(source: Path, folder: Path, change) -> Path:
    """A copy of the saved map at ``source`` whose record is changed by ``change(record)`` and its configuration's
    hash made again (anyone can: the hash proves no origin): its stem."""
    stem = _copy(source, folder)
    record = json.loads(stem.with_suffix(".json").read_text())
    change(record)
    record["config_sha256"] = config_hash(record["config"])
    record["summary_sha256"] = summary_hash(record["summary"])
    stem.with_suffix(".json").write_text(json.dumps(record))
    return stem


def _set(*where):
    """``change(record)`` setting ``record["config"][where...]`` to a value: ``_set("vertical")(value)``."""

    def to(value):
        def change(record):
            node = record["config"]
            for key in where[:-1]:
                node = node[key]
            node[where[-1]] = value

        return change

    return to


SQRT_400 = "$" + "\\sqrt{" * 400 + "x" + "}" * 400 + "$"

#: Hostile saved configurations of a map, each with what its one-line refusal says: the field and its range.
HOSTILE = {
    "vertical without phase": (_set("vertical")({"ratio": 0.5}), "config: setting: vertical: no phase in it"),
    "vertical phase a text": (
        _set("vertical")({"ratio": 0.5, "phase": "0"}),
        "config: setting: vertical_phase must be",
    ),
    "vertical a list": (_set("vertical")([0.5, 0.0]), "config: setting: vertical must be an object of phase, ratio"),
    "vertical ratio 11": (_set("vertical")({"ratio": 11.0, "phase": 0.0}), "vertical_ratio must be in [0, 10]"),
    "directions.signs [1, -1, 7]": (
        _set("directions", "signs")([1, -1, 7]),
        "config: directions.signs must be the directions of the pulses",
    ),
    "directions unknown": (_set("directions", "directions")("sideways"), "directions.directions must be one of auto"),
    "directions.reason a number": (_set("directions", "reason")(3), "directions.reason must be a sentence"),
    "block.H a text": (_set("block", "H")("2"), "config: setting: H must be"),
    "block.H 1e9": (_set("block", "H")(1e9), "config: setting: H must be in"),
    "block an unknown field": (_set("block", "colour")(1), "config: setting: block: no field(s) colour"),
    "rtol a list": (_set("rtol")([1e-8]), "config: setting: rtol must be"),
    "t_after negative": (_set("t_after")(-1.0), "config: setting: t_after must be in"),
    "backend unknown": (_set("backend")("fortran"), "config: setting: backend must be one of c, numpy"),
    "pulse unknown": (_set("pulse")({"motion": "square"}), "config: setting: pulse must be one of"),
    "pulse a text": (_set("pulse")("mp"), "config: setting: pulse must be an object of gamma_mp, motion, nu"),
    "damper.gamma a text": (_set("damper", "gamma")("abc"), "config: damper: gamma must be"),
    "damper.zeta 11": (_set("damper", "zeta")(11.0), "config: damper: zeta must be in [0, 10]"),
    "damper an unknown field": (_set("damper", "mass")(1.0), "config: damper: no field(s) mass"),
    "damper.stops a text": (_set("damper", "stops")("yes"), "config: damper: stops must be True or False"),
    "Omega a number": (_set("Omega")(4), "config: Omega must be a grid"),
    "tile a text": (_set("tile")("32"), "config: tile must be two integers"),
    "refinement.coarse 3": (_set("refinement", "coarse")(3), "config: coarse must be a power of two"),
    "refinement.adaptive a text": (_set("refinement", "adaptive")("yes"), "refinement.adaptive must be true"),
    "signs a dict": (_set("signs")({"1": 1}), "config: signs must be the directions of the pulses"),
    "an unknown field": (_set("colour")("red"), "config: colour: not a field of a saved study's configuration"),
    "a kind of another study": (_set("kind")("spectrum"), "config: kind: 'spectrum', not map"),
}


@pytest.mark.parametrize("case", HOSTILE)
def test_hostile_saved_configurations_are_refused_in_one_line(case, saved, tmp_path, capsys):
    change, message = HOSTILE[case]
    stem = _forged(saved, tmp_path, change)
    with pytest.raises(rocking.ParameterError) as refused:
        rocking.load(stem)
    text = str(refused.value)
    assert "\n" not in text and text.startswith(f"{stem}.json: ") and message in text, text
    capsys.readouterr()
    assert main(["redraw", str(stem)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err


#: Fields of the other kinds' configurations, each with a wrong value and the refusal's words (the table is one).
OTHER_FIELDS = {
    "beta_tol": ("0.001", "beta_tol must be a relative tolerance in (0, 0.1]"),
    "columns": (0, "columns must be an integer in [1, 100000]"),
    "gammas": ([0.05, "x"], "gamma must be"),
    "zeta": (-1.0, "zeta must be in [0, 10]"),
    "h": ("0.05", "h must be"),
    "stops": (False, "stops must be one of True"),
    "refine": (10**6, "refine must be an integer in [0, 1000]"),
    "e_ratio": (0.7, "e_ratio must be in"),
    "M": (None, "M must be"),
    "a_max_g": (0, "a_max_g must be a number > 0"),
    "measure": ("pga2", "measure must be one of scale, pga, pgv, arias, cav, amplitude"),
    "suite": ({"n": 10**9}, "suite: its motions must number 1 to"),
    "suite of a pulse out of range": (
        {"pulses": [{"type": "RickerWavelet", "family": "ricker", "T_g": 1.0, "a_g": -3.0, "omega_g": 6.28}]},
        "suite.pulses[0]: a_g must be",
    ),
    "suite of a pulse of another class": ({"pulses": [{"type": "os.system"}]}, "suite.pulses[0].type must be one of"),
    "suite of files without hashes": (
        {"files": [{"path": "/etc/passwd", "sha256": "x", "unit": "g"}]},
        "suite.files[0] must be a path, its SHA-256 and its unit",
    ),
    "suite stochastic of a negative seed": (
        {"stochastic": DEFAULT_SITE.record(), "seed": -1, "n": 3},
        "seed must be an integer >= 0",
    ),
    "check": (1, "check must be one of None, none, tolerance"),
    "dampers": ([{"gamma": 99.0}], "dampers[0]: gamma must be in"),
    "levels": ({"low": 1, "high": 2}, "levels: scale must be linear or log"),
}


@pytest.mark.parametrize("field", OTHER_FIELDS)
def test_every_field_of_every_kind_is_checked(field, saved):
    config = json.loads((saved / "map.json").read_text())["config"]
    value, message = OTHER_FIELDS[field]
    with pytest.raises(rocking.ParameterError, match=re.escape(message)):
        storage.check_fields("map", {**config, field.split(" ")[0]: value})


def test_a_saved_variant_loads_and_redraws(variant, capsys):
    assert rocking.load(variant / "map").config["damper"]["model"] == "pendulum"
    assert main(["redraw", str(variant / "map")]) == 0


SAVED_TEXTS = {
    "model of 100 kB": (_set("damper", "model")("m" * 100_000), "config.damper.model: a text of 100000 characters"),
    "model with a line break": (_set("damper", "model")("pendulum\nx"), "with line breaks or control characters"),
    "parameter not a name": (
        _set("damper", "params")({"m$\\sqrt{x}$": 1.0}),
        "damper.params: m$\\sqrt{x}$ must be a parameter's name",
    ),
    "summary text of 100 kB": (
        lambda record: record["summary"].update(note="s" * 100_000),
        "summary.note: a text of 100000 characters",
    ),
}


@pytest.mark.parametrize("case", SAVED_TEXTS)
def test_saved_texts_are_bounded_on_load(case, variant, tmp_path, capsys):
    change, message = SAVED_TEXTS[case]
    stem = _forged(variant, tmp_path, change)
    with pytest.raises(rocking.ParameterError, match=re.escape(message)):
        rocking.load(stem)
    capsys.readouterr()
    assert main(["redraw", str(stem)]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_a_saved_text_is_never_mathtext_in_a_title(variant, tmp_path, capsys):
    """A model name of nested square roots (depth 400: mathtext's RecursionError) within the bound of texts is drawn
    as plain text, shortened, at once."""
    stem = _forged(variant, tmp_path, _set("damper", "model")(SQRT_400))
    assert rocking.load(stem).config["damper"]["model"] == SQRT_400  # within MAX_TEXT: a saved folder's path may be
    start = time.perf_counter()
    assert main(["redraw", str(stem)]) == 0
    assert time.perf_counter() - start < 30
    assert figures._saved_text(SQRT_400) == "..." + SQRT_400[-57:].replace("$", "\\$")
