"""What a study leaves on disk: ``<name>.nc`` (its data), ``<name>*.csv`` (its tables), ``<name>.json`` (its record).

:func:`save` writes a :class:`~rocking.study.result.Study` with its
configuration, the configuration's hash, software versions, summary and
timing; :func:`load` reads it back without recomputing anything, and refuses
with a :class:`~rocking.model.params.ParameterError` naming the file a study
whose files are damaged, foreign, incomplete or do not belong together.

A study's files are published together: all are written into a temporary
folder beside them, then renamed into place, the JSON record last (and an
older record removed first). The JSON is the mark of a complete study:
:func:`load` needs it, so a save cut short (a full disk, Ctrl-C, a killed
process) leaves the older study whole or no study, never a mix. A full disk
raises :class:`~rocking.study.files.DiskFull` naming the file, and nothing partial stays behind.

What is read is bounded before it is read (:mod:`rocking.study.files`): the record's size, nesting and texts
(:func:`check_texts`), the NetCDF file's storage and variables from its metadata (:func:`_open_checked`). A loaded
study's configuration is checked field by field by the table of the command line's checks (:data:`SAVED_FIELDS`),
and against its arrays (:func:`check_config`, :func:`check_variables`: grids, directions, shapes).
"""

from __future__ import annotations

import hashlib
import inspect
import json
import math
import os
import re
import shutil
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import Any

import numpy as np

from ..model.checks import check_in_range
from ..model.floor import Floor
from ..model.loading import ModelError, load_model
from ..model.motion import PULSE_TYPES
from ..model.motion import describe as describe_motion
from ..model.outputs import write_netcdf
from ..model.params import Block, ParameterError, shown
from ..model.records import input_refusal
from ..model.stochastic import SiteModel
from ..sim.accuracy import CHECKS
from .adaptive import check_coarse, check_verify
from .config import (
    MAX_N,
    Grid,
    Setting,
    Tuning,
    check_signs,
    config_hash,
    floor_attrs,
    is_count,
    is_number,
    name_text,
    tree_hash,
    versions,
    vertical_attrs,
)
from .dataset import to_dataset
from .directions import DIRECTIONS, SIGNS
from .files import (
    MAX_STUDY_BYTES,
    DiskFull,
    check_hdf5,
    checksum,
    describe,
    is_full,
    layout,
    make_folder,
    name_lock,
    read_json,
    write_csv,
    write_file,
)
from .friction_map import friction_attrs
from .ida import LEVELS
from .kinds import KINDS
from .optimize import MAX_REFINE, check_gammas
from .overturning_map import _check_tile
from .result import Study
from .spectrum import check_tol
from .suite import MAX_MOTIONS, Suite
from .vocabulary import PART_NAMES

#: Version of the layout of a saved study's files: a study saved with another is refused, in one line.
#: 4: an IDA's and a fragility's fit and counts are variables of its data, its summary empty (3: JSON in its
#: summary, keyed ``theta``/``beta``); 3: its data are its NetCDF file (2: arrays named after their dimensions in
#: an ``.npz``).
STUDY_FORMAT = 4

#: The parts of a saved study's JSON record that :func:`load` needs.
RECORD = {"kind": str, "config": dict, "summary": dict, "variables": dict, "variables_sha256": str}

#: Bytes of a NetCDF file besides its variables' (its header, attributes, HDF5's structures) that are read.
NETCDF_OVERHEAD = 16 << 20


def study_stem(path: str | Path) -> Path:
    """The common stem of a saved study's files from any of them (``map.nc``, ``map.json``, ``map.csv``) or
    the stem itself."""
    path = Path(path)
    return path.with_suffix("") if path.suffix in (".npz", ".json", ".csv", ".nc") else path


def _data_files(study: Study, name: str, software: dict) -> dict:
    """The files of ``study`` saved as ``name`` but its JSON record: file name -> ``write(path)``."""
    files: dict[str, Callable[[Path], None]] = {
        f"{name}.nc": lambda path: write_netcdf(to_dataset(study, software), path)
    }
    for table, columns in study.tables.items():
        # Tables are named after the kind ("spectrum-windows"); a study saved under another name keeps its own.
        if table.startswith(study.kind):
            table = name + table[len(study.kind) :]
        files[f"{table}.csv"] = lambda path, columns=columns: write_csv(path, headed(columns, study.data))
    return files


def headed(columns: dict, data) -> dict:
    """A table's columns as its CSV shows them: each name with its unit (``theta_max [rad]``, as a history's CSV),
    read from the variable of ``data`` it comes from (its own name, or ``<part>_<name>``); a coded column
    (``flag_values``) followed by ``<name>_text``, the words of its codes."""
    out = {}
    for name, values in columns.items():
        source = _source(name, data)
        codes = np.asarray(values)
        units = None if source is None or codes.dtype.kind not in "biuf" else source.attrs.get("units")
        out[f"{name} [{units}]" if units else name] = values
        if source is not None and "flag_values" in source.attrs and codes.dtype.kind in "iu":
            words = dict(zip(source.attrs["flag_values"].tolist(), source.attrs["flag_meanings"].split()))
            out[f"{name}_text"] = np.array([words.get(c, "") for c in codes.ravel().tolist()], object)
    return out


def _source(column: str, data):
    """The variable of ``data`` a table's column shows: its own name, or ``<part>_<name>[_pos|_neg]`` (one part,
    one direction), or the value a ``<name>_lower_bound`` bounds, or None. Data without parts may still hold one
    part's variables (an optimisation's ``beta_min``, of the block alone): their columns name it too."""
    parts = [str(p) for p in data["part"].values] if "part" in data.coords else list(PART_NAMES)
    names = [column, *(column[len(p) + 1 :] for p in parts if column.startswith(f"{p}_"))]
    names += [n.removesuffix(end) for n in names for end in ("_pos", "_neg") if n.endswith(end)]
    # A censored value's lower bound (``beta_min_lower_bound``) is in the unit of the value.
    names += [n.removesuffix("_lower_bound") for n in names if n.endswith("_lower_bound")]
    return next((data.variables[n] for n in names if n in data.variables), None)


def variables(data) -> dict:
    """Every variable of a study's data (coordinates included) by name: what its record lists and checks."""
    return {name: variable.values for name, variable in data.variables.items()}


def data_layout(data) -> dict:
    """Name -> ``{"dims": [...], "dtype": ..., "shape": [...]}`` of every variable of ``data``, JSON-ready."""
    shapes = layout(variables(data))
    return {name: {"dims": list(data[name].dims), **shapes[name]} for name in shapes}


def _record(study: Study, software: dict, files: list[str], command: dict | None) -> dict:
    """The JSON record of ``study``: what :func:`load` reads and checks."""
    record = {
        "kind": study.kind,
        "config": study.config,
        "config_sha256": config_hash(study.config),
        "versions": software,
        "summary": study.summary,
        "summary_sha256": summary_hash(study.summary),
        "run": study.run,
        "format": STUDY_FORMAT,
        "files": files,
        "variables": data_layout(study.data),
        "variables_sha256": checksum(variables(study.data)),
    }
    return {**record, "command": command} if command is not None else record


def summary_hash(summary: dict) -> str:
    """SHA-256 of the canonical JSON of a study's ``summary`` (sorted keys, exact float repr; NaN as the record
    writes it)."""
    text = json.dumps(summary, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _check_unchanged(record: dict, meta: Path) -> None:
    """Refuse a record whose configuration or summary is not the one saved with its results: the checksums
    written beside them (``config_sha256``; ``summary_sha256`` in files saved since it was added) differ, as
    after an edit by hand, which would describe the results by inputs they were not computed from."""
    try:
        config_same = record.get("config_sha256") == config_hash(record["config"])
    except (TypeError, ValueError):  # not JSON of finite numbers: not what save wrote
        config_same = False
    if not config_same:
        raise ParameterError(
            f"{meta}: config: not the configuration its results were computed from (its SHA-256 is not the "
            "config_sha256 saved with it: edited or damaged); to run a changed configuration, give it to the "
            "study's command as --config"
        )
    if "summary_sha256" in record and record["summary_sha256"] != summary_hash(record["summary"]):
        raise ParameterError(
            f"{meta}: summary: not the summary saved with its results (its SHA-256 is not summary_sha256: edited "
            "or damaged)"
        )


def _alive(pid: int) -> bool:
    """False only if no process ``pid`` runs (this machine's)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (OSError, OverflowError):  # another user's process, or no such number: keep its files
        return True
    return True


def _remove_abandoned(folder: Path, name: str) -> None:
    """Remove the temporary folders of saves of ``name`` whose process is gone (killed while saving)."""
    prefix = f".{name}.saving-"
    for old in folder.iterdir():
        pid = old.name[len(prefix) :].partition("-")[0]
        if old.name.startswith(prefix) and pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(old, ignore_errors=True)


@contextmanager
def _staging(folder: Path, name: str) -> Iterator[Path]:
    """A new temporary folder in ``folder`` for the files of the study ``name``, removed on leaving."""
    _remove_abandoned(folder, name)
    try:
        staging = Path(tempfile.mkdtemp(prefix=f".{name}.saving-{os.getpid()}-", dir=folder))
    except OSError as exc:
        if is_full(exc):
            raise DiskFull(folder / f"{name}.nc") from None
        raise
    try:
        yield staging
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _write_staged(write: Callable, staged: Path, final: Path) -> None:
    """``write(staged)``; a full disk is a :class:`DiskFull` naming ``final``, the file the user asked for."""
    try:
        write(staged)
    except Exception as exc:
        if is_full(exc, staged.parent):
            raise DiskFull(final) from None
        raise


def _publish(staging: Path, folder: Path, files: list[str]) -> None:
    """Move ``files`` from ``staging`` into ``folder``: the old JSON record removed first, the new one last.

    A rename in one folder needs no space and does not fail half way; a process killed between the first
    and the last leaves no record, which :func:`load` reports as no study, never a mix of two.
    """
    (folder / files[-1]).unlink(missing_ok=True)
    for file in files:
        os.replace(staging / file, folder / file)


def save(study: Study, folder: str | Path, name: str | None = None, command: dict | None = None) -> list[Path]:
    """Write ``study`` into ``folder``: its labelled :class:`xarray.Dataset` as ``<name>.nc``
    (:mod:`rocking.study.dataset`), its CSV tables (``<name>.csv``, ``<name>-windows.csv``, ...) and its record
    ``<name>.json``, published together (see the module's text).

    The JSON record lists the arrays (:func:`layout`) and their :func:`checksum`,
    which :func:`load` checks; files of an earlier save under the same name are replaced.

    Returns
    -------
    list of Path
        The files written, the JSON record last.

    Raises
    ------
    ParameterError
        If ``folder`` cannot be created or written.
    DiskFull
        If the disk is full (or the quota used up): nothing is published, an earlier study of that name is
        kept whole, and the temporary files are removed.
    """
    folder = make_folder(folder, "output folder")
    name = name or study.kind
    software = versions()
    files = _data_files(study, name, software)
    text = json.dumps(_record(study, software, list(files), command), indent=2, sort_keys=True) + "\n"
    files[f"{name}.json"] = lambda path: write_file(path, lambda f: f.write(text), mode="w")
    with name_lock(folder, name), _staging(folder, name) as staging:
        for file, write in files.items():
            _write_staged(write, staging / file, folder / file)
        _publish(staging, folder, list(files))
    return [folder / file for file in files]


#: Longest text anywhere in a saved record, key or value: a model's folder is a path of at most 4096 bytes
#: (PATH_MAX), every other text a name or a sentence.
MAX_TEXT = 4096


def check_texts(value) -> None:
    """Refuse a text of a saved record (a key or a value, at any depth) longer than :data:`MAX_TEXT` characters or
    not printable (a line break, a control character): each is shown in one line, in a message or a figure.

    Raises
    ------
    ParameterError
        Naming where the text is.
    """
    todo: list[tuple[tuple, object]] = [((), value)]
    while todo:
        where, node = todo.pop()
        items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
        for key, child in items:
            for text in (key, child):
                if isinstance(text, str) and not (len(text) <= MAX_TEXT and text.isprintable()):
                    controls = "" if text.isprintable() else " with line breaks or control characters"
                    raise ParameterError(
                        f"{_place((*where, key))}: a text of {len(text)} characters{controls}; a saved study's texts "
                        f"are at most {MAX_TEXT} printable characters"
                    )
            if isinstance(child, (dict, list)):  # its keys: the depth is bounded (MAX_JSON_DEPTH), not a path's text
                todo.append(((*where, key), child))


def _place(keys: tuple) -> str:
    """Where a value is in a record, from its keys (``config.damper.model``, ``summary.x[3]``), in one short line."""
    text = "".join(f".{name_text(k)}" if isinstance(k, str) else f"[{k}]" for k in keys)[1:]
    return text if len(text) <= 200 else text[:197] + "..."


def read_record(meta: Path) -> dict:
    """The JSON record of a saved study at ``meta``, checked to be one: bounded (:func:`read_json`), an object
    of this format with a known kind, its configuration, summary, arrays (their layout) and their checksum.

    Raises
    ------
    ParameterError
        Naming the file and what is wrong.
    """
    try:
        record = read_json(meta)
    except (OSError, ValueError) as exc:  # UnicodeDecodeError and JSONDecodeError are ValueErrors
        raise ParameterError(f"{meta}: not a saved study's JSON ({describe(exc)})") from None
    if not isinstance(record, dict):
        raise ParameterError(f"{meta}: not a saved study's JSON (a {type(record).__name__}, not an object)")
    if record.get("format", 1) != STUDY_FORMAT:
        software = record.get("versions")
        by = software.get("rocking") if isinstance(software, dict) else None
        raise ParameterError(
            f"{meta}: a study saved in format {shown(record.get('format', 1))} (by rocking "
            f"{by[:40] if isinstance(by, str) else 'of another version'}); this version reads format "
            f"{STUDY_FORMAT}: recompute it"
        )
    for key, kind in RECORD.items():
        if not isinstance(record.get(key), kind):
            raise ParameterError(f"{meta}: not a saved study's JSON (no {kind.__name__} {key!r})")
    if record["kind"] not in KINDS:
        raise ParameterError(f"{meta}: unknown kind of study {shown(record['kind'])} (known: {', '.join(KINDS)})")
    try:
        check_texts(record)
    except ParameterError as exc:
        raise ParameterError(f"{meta}: {exc}") from None
    return record


#: A saved variable's dtype: bool, integer or float of 1 to 8 bytes, in any byte order, or a short text (a label).
_DTYPE = re.compile(r"[<>|=]([biuf][1248]|U[1-9][0-9]{0,2})")


def _shapes(listed: dict) -> dict:
    """Name -> ``(dims, shape, dtype)`` of the variables a JSON record lists, each checked to be plain."""
    out = {}
    for name, entry in listed.items():
        dims, shape, dtype = (
            (entry.get(k) for k in ("dims", "shape", "dtype")) if isinstance(entry, dict) else [None] * 3
        )
        if not (isinstance(shape, list) and len(shape) <= 8 and all(is_count(n) and n >= 0 for n in shape)):
            raise ParameterError(f"{name_text(name)}: shape must be a list of at most 8 sizes (got {shown(shape)})")
        if not (isinstance(dims, list) and len(dims) == len(shape) and all(isinstance(d, str) for d in dims)):
            raise ParameterError(f"{name_text(name)}: dims must name each of its dimensions (got {shown(dims)})")
        if not (isinstance(dtype, str) and _DTYPE.fullmatch(dtype)):
            raise ParameterError(
                f"{name_text(name)}: dtype must be a bool, integer, float or short text such as <f8 "
                f"(got {shown(dtype)})"
            )
        out[name] = (tuple(dims), tuple(shape), np.dtype(dtype))
    return out


def _motions(suite) -> int:
    """The number of motions of a suite's record (:meth:`rocking.study.suite.Suite.record`)."""
    if not isinstance(suite, dict):
        raise ParameterError(f"suite must be the record of a suite of motions (got {shown(suite)})")
    listed = next((suite[key] for key in ("files", "pulses") if key in suite), None)
    n = len(listed) if isinstance(listed, list) else suite.get("n")
    if not (is_count(n) and 1 <= n <= MAX_MOTIONS):
        raise ParameterError(f"suite: its motions must number 1 to {MAX_MOTIONS} (got {shown(n)})")
    return n


def _counts(kind: str, config: dict) -> dict:
    """Sizes of dimensions that a configuration gives besides its grids: mass ratios, motions."""
    if kind == "optimize":
        gammas = config.get("gammas")
        if not (isinstance(gammas, list) and gammas and all(is_number(g) for g in gammas)):
            raise ParameterError(f"gammas must be a list of mass ratios (got {shown(gammas)})")
        return {"gamma": len(gammas), "gamma_or_best": len(gammas) + 1}
    if kind in ("ida", "fragility"):
        return {"motion": _motions(config.get("suite"))}
    return {}


def _fields_of(name: str, record, required: set | frozenset, optional: set | frozenset = frozenset()) -> dict:
    """``record`` if it is an object with the keys ``required`` and some of ``optional``, else a ParameterError."""
    if not isinstance(record, dict):
        fields = ", ".join(sorted(required | optional))
        raise ParameterError(f"{name} must be an object of {fields} (got {shown(record)})")
    missing, unknown = sorted(required - set(record)), sorted(set(record) - required - optional)
    if missing or unknown:
        found = f"no {', '.join(missing)}" if missing else f"no field(s) {', '.join(map(name_text, unknown[:5]))}"
        raise ParameterError(f"{name}: {found} in it (its fields: {', '.join(sorted(required | optional))})")
    return record


def _floor_fields(record) -> dict:
    """A saved floor's fields: ``mu_s`` and ``mu_k`` with ``e_n`` optional (a floor with friction), or ``e_n`` alone
    (landings that bounce on a floor that never slides: JSON has no inf)."""
    friction = not isinstance(record, dict) or bool({"mu_s", "mu_k"} & set(record))
    if friction:
        return _fields_of("floor", record, {"mu_s", "mu_k"}, {"e_n"})
    return _fields_of("floor", record, {"e_n"})


def _block(record) -> Block:
    """The :class:`Block` of a saved configuration's ``block``, by the ranges of the command line's block."""
    if not isinstance(record, dict):
        raise ParameterError(f"block must be the record of a rocking.Block (got {shown(record)})")
    fields = set(inspect.signature(Block).parameters)
    block = _fields_of("block", record, {"H", "B"}, fields - {"H", "B"})
    try:
        return Block(**block)
    except TypeError as exc:  # a field missing
        raise ParameterError(f"block: {exc}") from None


def _setting(config: dict) -> None:
    """The block, pulse, vertical component and solver of a saved configuration, checked by :class:`Setting` (the
    command line's table, :data:`rocking.model.checks.RANGES`) and recorded as a study records them."""
    block = _block(config["block"]) if "block" in config else Block.reference()  # a threshold: blocks of its grids
    pulse = _fields_of("pulse", config.get("pulse", {"motion": "sine"}), {"motion"}, {"gamma_mp", "nu"})
    vertical = config.get("vertical", {})
    if vertical != {}:
        vertical = _fields_of("vertical", vertical, {"ratio", "phase"})
    if pulse.get("gamma_mp") is not None:
        check_in_range("gamma_mp", pulse["gamma_mp"])
    # A study saved before the floor had friction holds none: the paper's floor; one that never slides but whose
    # landings bounce, only e_n.
    floor = _floor_fields(config["floor"]) if "floor" in config else {}
    solver: dict[str, Any] = {key: config.get(key) for key in ("rtol", "t_after", "backend")}  # None: refused
    setting = Setting(
        block,
        **solver,
        pulse=pulse["motion"],
        gamma_mp=pulse.get("gamma_mp"),
        nu=pulse.get("nu", 0.0),
        vertical_ratio=vertical.get("ratio", 0.0),
        vertical_phase=vertical.get("phase", 0.0),
        floor=Floor(**floor),
    )
    record = setting.record()
    if "block" not in config:
        del record["block"]
    for key in ("pulse", "vertical", "floor"):
        if key in config and key not in record:
            raise ParameterError(f"{key}: {shown(config[key])} is what a study records by leaving {key} out")
    for key, value in record.items():
        if config.get(key) != value:
            raise ParameterError(f"{key}: {shown(config.get(key))}, not as a study records it ({shown(value)})")


#: A generated model's parameter, as a saved variant names it: a Python identifier (the generated code's name).
_PARAMETER = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,63}")


def _damper(name: str, record) -> None:
    """A saved damper: a :class:`Tuning`'s record checked by :class:`Tuning` (the command line's ranges), or a
    :class:`Variant`'s: its model's name or folder, its parameters (identifiers, finite numbers) and its hash."""
    if isinstance(record, dict) and "model" in record:
        variant = _fields_of(name, record, {"model", "params"}, {"model_sha256"})
        if not (isinstance(variant["model"], str) and variant["model"]):
            raise ParameterError(f"{name}.model must be a model's name or folder (got {shown(variant['model'])})")
        params = variant["params"]
        if not (isinstance(params, dict) and len(params) <= 64):
            raise ParameterError(f"{name}.params must be at most 64 values by name (got {shown(params)})")
        for key, value in params.items():
            if not (_PARAMETER.fullmatch(key) and is_number(value)):
                raise ParameterError(
                    f"{name}.params: {name_text(key)} must be a parameter's name (a Python identifier) with a finite "
                    f"number (got {shown(value)})"
                )
        digest = variant.get("model_sha256", "0" * 64)
        if not (isinstance(digest, str) and re.fullmatch(r"[0-9a-f]{64}", digest)):
            raise ParameterError(f"{name}.model_sha256 must be a SHA-256 in hexadecimal (got {shown(digest)})")
        return
    fields = inspect.signature(Tuning).parameters
    tuning = _fields_of(name, record, set(), set(fields))
    try:
        Tuning(**tuning)
    except ParameterError as exc:
        raise ParameterError(f"{name}: {exc}") from None


def _dampers(name: str, value) -> None:
    if not (isinstance(value, list) and 1 <= len(value) <= 8):
        raise ParameterError(f"{name} must be a list of 1 to 8 dampers (got {shown(value)})")
    for i, record in enumerate(value):
        _damper(f"{name}[{i}]", record)


def _directions(name: str, value, config: dict) -> None:
    """The directions a study chose (:func:`rocking.study.directions.choose`): a choice, its signs, its reason."""
    chosen = _fields_of(name, value, {"directions", "signs", "reason"})
    if not (isinstance(chosen["directions"], str) and chosen["directions"] in DIRECTIONS):
        raise ParameterError(
            f"{name}.directions must be one of {', '.join(DIRECTIONS)} (got {shown(chosen['directions'])})"
        )
    signs = check_signs(f"{name}.signs", chosen["signs"])
    if chosen["directions"] in SIGNS and signs != list(SIGNS[chosen["directions"]]):
        raise ParameterError(f"{name}.signs must be {list(SIGNS[chosen['directions']])} for {chosen['directions']}")
    if "signs" in config and config["signs"] != signs:
        raise ParameterError(f"{name}.signs must be the study's signs {shown(config['signs'])} (got {shown(signs)})")
    if not isinstance(chosen["reason"], str):
        raise ParameterError(f"{name}.reason must be a sentence (got {shown(chosen['reason'])})")


def _refinement(name: str, value) -> None:
    # "edges" (the verification computed the coarse blocks' edges) is absent from maps saved before it.
    refinement = _fields_of(name, value, {"adaptive"}, {"coarse", "verify", "edges"})
    if not isinstance(refinement["adaptive"], bool):
        raise ParameterError(f"{name}.adaptive must be true or false (got {shown(refinement['adaptive'])})")
    if refinement["adaptive"]:
        fields = _fields_of(name, refinement, {"adaptive", "coarse", "verify"}, {"edges"})
        check_verify(refinement["verify"], check_coarse(fields["coarse"]))
        if not isinstance(fields.get("edges", False), bool):
            raise ParameterError(f"{name}.edges must be true or false (got {shown(fields['edges'])})")
    elif len(refinement) > 1:
        raise ParameterError(f"{name}: coarse, verify and edges belong to an adaptive refinement (adaptive is false)")


def _site(name: str, record) -> SiteModel:
    """A stochastic suite's site model, checked by :class:`SiteModel`."""
    site = _fields_of(name, record, set(), set(inspect.signature(SiteModel).parameters))
    try:
        return SiteModel(**site)
    except (TypeError, ParameterError) as exc:
        raise ParameterError(f"{name}: {exc}") from None


def _record_files(name: str, files) -> None:
    """The record files of a suite as it saved them: each a path, its SHA-256 and its unit."""
    if not isinstance(files, list):
        raise ParameterError(f"{name} must be a list of record files (got {shown(files)})")
    for i, file in enumerate(files):
        entry = _fields_of(f"{name}[{i}]", file, {"path", "sha256", "unit"})
        ok = isinstance(entry["path"], str) and entry["path"] and isinstance(entry["sha256"], str)
        if not (ok and re.fullmatch(r"[0-9a-f]{64}", entry["sha256"]) and isinstance(entry["unit"], (str, type(None)))):
            raise ParameterError(f"{name}[{i}] must be a path, its SHA-256 and its unit (got {shown(file)})")


def _pulse(name: str, record) -> None:
    """A pulse of a suite as :meth:`Suite.record` saves it, made again by its class (the ranges of its inputs)."""
    classes = {cls.__name__: cls for cls, _ in PULSE_TYPES.values()}
    kind = record.get("type") if isinstance(record, dict) else None
    if not (isinstance(kind, str) and kind in classes):
        raise ParameterError(f"{name}.type must be one of {', '.join(classes)} (got {shown(kind)})")
    fields = set(inspect.signature(classes[kind]).parameters)
    entry = _fields_of(name, record, {"type", "family", "T_g"}, fields)
    try:
        pulse = classes[kind](**{k: v for k, v in entry.items() if k in fields})
    except (TypeError, ParameterError) as exc:
        raise ParameterError(f"{name}: {exc}") from None
    if entry["family"] != describe_motion(pulse).family or entry["T_g"] != pulse.T_g:
        raise ParameterError(f"{name}: its family and T_g must be those of its pulse")


def _suite(name: str, value) -> None:
    """A suite of motions as :meth:`Suite.record` saves it: record files, pulses (each made again) or a stochastic
    suite (made again by :meth:`Suite.stochastic`)."""
    _motions(value)
    if "files" in value:
        suite = _fields_of(name, value, {"files"}, {"vertical"})
        _record_files(f"{name}.files", suite["files"])
        if "vertical" in suite:
            vertical = _fields_of(f"{name}.vertical", suite["vertical"], {"files", "convention"})
            _record_files(f"{name}.vertical.files", vertical["files"])
    elif "pulses" in value:
        for i, pulse in enumerate(_fields_of(name, value, {"pulses"})["pulses"]):
            _pulse(f"{name}.pulses[{i}]", pulse)
    else:
        suite = _fields_of(name, value, {"stochastic", "seed", "n"}, {"vertical"})
        vertical = _fields_of(f"{name}.vertical", suite.get("vertical", {}), set(), {"ratio", "site", "convention"})
        site = _site(f"{name}.stochastic", suite["stochastic"])
        other = _site(f"{name}.vertical.site", vertical["site"]) if "site" in vertical else None
        Suite.stochastic(site, suite["n"], suite["seed"], vertical.get("ratio", 0.0), other)


def _count(low: int, high: int):
    def check(name: str, value) -> None:
        if not (is_count(value) and low <= value <= high):
            raise ParameterError(f"{name} must be an integer in [{low}, {high}] (got {shown(value)})")

    return check


def _one_of(*choices):
    def check(name: str, value) -> None:
        if not any(value is c or (isinstance(c, str) and value == c) for c in choices):
            raise ParameterError(f"{name} must be one of {', '.join(map(str, choices))} (got {shown(value)})")

    return check


def _positive(name: str, value) -> None:
    if not (is_number(value) and value > 0):
        raise ParameterError(f"{name} must be a number > 0 (got {shown(value)})")


def _grid(name: str, value) -> None:
    Grid.from_record(name, value)


#: Every field of a saved configuration, each with its check: the functions the studies and the command line check
#: their inputs with (:class:`Setting`, :class:`Tuning`, :class:`Grid`, the studies' own checks; the ranges of
#: :data:`rocking.model.checks.RANGES`). ``check(name, value)``; those of the setting (block, pulse, vertical,
#: solver) are checked together (:func:`_setting`), the directions against the signs (:func:`_directions`).
SAVED_FIELDS: dict[str, Callable | None] = {
    "kind": None,  # the record's kind: compared in check_config
    **dict.fromkeys(("block", "rtol", "t_after", "backend", "pulse", "vertical", "floor"), None),  # _setting
    "directions": None,  # _directions
    "damper": _damper,
    "dampers": _dampers,
    **dict.fromkeys(("Omega", "beta", "Tm_ratio", "zeta_grid", "lam", "p", "levels", "mu"), _grid),
    "pulse_Omega": _positive,
    "signs": check_signs,
    "tile": lambda name, value: _check_tile(value),
    "refinement": _refinement,
    "beta_tol": lambda name, value: check_tol(value),
    "columns": _count(1, MAX_N),
    "gammas": lambda name, value: check_gammas(value if isinstance(value, list) else None, name),
    "zeta": check_in_range,
    "h": check_in_range,
    "stops": _one_of(True),
    "refine": _count(0, MAX_REFINE),
    "e_ratio": check_in_range,
    "M": check_in_range,
    "a_max_g": _positive,
    "measure": _one_of(*LEVELS),
    "suite": _suite,
    "check": _one_of(None, *CHECKS),
}


def check_fields(kind: str, config: dict) -> None:
    """Check every field of a saved ``config`` of a ``kind`` study by :data:`SAVED_FIELDS`: a field it does not
    list is refused.

    Raises
    ------
    ParameterError
        In one line naming the field and its valid range.
    """
    unknown = [key for key in config if key not in SAVED_FIELDS]
    if unknown:
        raise ParameterError(f"{name_text(unknown[0])}: not a field of a saved study's configuration")
    if config.get("kind", kind) != kind:
        raise ParameterError(f"kind: {shown(config['kind'])}, not {kind} (the record's)")
    try:
        _setting(config)
    except ParameterError as exc:
        raise ParameterError(f"setting: {exc}") from None
    for key, value in config.items():
        check = SAVED_FIELDS[key]
        if check is not None:
            check(key, value)
    if "directions" in config:
        _directions("directions", config["directions"], config)


def check_config(kind: str, config: dict) -> tuple[dict, dict]:
    """Check a saved study's configuration: what its data's coordinates and dimensions must be.

    Every field must be valid (:func:`check_fields`), and it must be plain JSON (no NaN).

    Returns
    -------
    expected : dict
        Dimension -> ``(field, values)``: the values the configuration gives its coordinate.
    sizes : dict
        Dimension -> size, as the configuration gives them.

    Raises
    ------
    ParameterError
        Naming the field and its valid range.
    """
    try:
        config_hash(config)
    except ValueError:
        raise ParameterError("holds NaN or infinity, which a saved configuration never does") from None
    check_fields(kind, config)
    expected = {}
    for key, dim in KINDS[kind].grids.items():
        expected[dim] = (key, Grid.from_record(key, config.get(key)).values())
    expected["sign"] = ("signs", np.array(check_signs("signs", config.get("signs"))))
    sizes = {dim: len(values) for dim, (_, values) in expected.items()}
    return expected, {**sizes, **_counts(kind, config)}


def check_variables(kind: str, listed: dict, sizes: dict) -> None:
    """Check the variables a saved study's JSON record lists (``listed``) against the sizes of
    :func:`check_config`, before any is read: every variable has the dimensions of its kind
    (:attr:`rocking.study.kinds.Kind.dims`), of one size each (``sizes`` is completed), the coordinates are
    there, and all hold at most :data:`MAX_STUDY_BYTES`.

    Raises
    ------
    ParameterError
        Naming the variable.
    """
    shapes = _shapes(listed)
    missing = sorted(dim for dim in KINDS[kind].grids.values() if dim not in shapes) + (
        ["sign"] if "sign" not in shapes else []
    )
    if missing:
        raise ParameterError(f"{', '.join(missing)} missing (the coordinates of a {kind} study)")
    for name, (dims, shape, _) in sorted(shapes.items()):
        try:
            schema = KINDS[kind].dims(name)
        except KeyError:
            raise ParameterError(f"{name_text(name)}: not a variable of a {kind} study") from None
        if dims != schema:
            raise ParameterError(f"{name_text(name)} has dimensions ({', '.join(dims)}), not ({', '.join(schema)})")
        for dim, size in zip(dims, shape):
            if sizes.setdefault(dim, size) != size:
                raise ParameterError(
                    f"{name_text(name)} has {size} values along {dim}, not {sizes[dim]} "
                    "(as its configuration or its other variables)"
                )
    total = sum(math.prod(shape) * dtype.itemsize for _, shape, dtype in shapes.values())
    if total > MAX_STUDY_BYTES:
        raise ParameterError(f"{total} bytes in all, at most {MAX_STUDY_BYTES} in a study")


#: dtype kinds of a saved variable as xarray stores them in NetCDF-4: a bool as a byte (its ``dtype`` attribute
#: says bool); a text as a variable-length string (``str``).
_STORED_KIND = {"b": "i"}


def _stored_as(variable, dtype: np.dtype) -> bool:
    """Whether the NetCDF ``variable`` stores values of the saved ``dtype`` as xarray writes them."""
    if dtype.kind == "U":
        return variable.dtype is str
    stored = variable.dtype
    size = 1 if dtype.kind == "b" else dtype.itemsize
    kind = _STORED_KIND.get(dtype.kind, dtype.kind)
    return isinstance(stored, np.dtype) and stored.kind == kind and stored.itemsize == size


def _check_stored(nc: Path, file, listed: dict) -> None:
    """Refuse the variables of the open NetCDF ``file`` unless they are those ``listed`` (name -> ``(dims, shape,
    dtype)``, :func:`_shapes`), of those dimensions, shapes and dtypes as stored: read from its metadata, before any
    data. The bytes then read are those of the shapes listed."""
    if file.data_model != "NETCDF4" or file.groups:
        raise ParameterError(f"{nc}: not a NetCDF-4 file of a study (a {file.data_model} file, or one with groups)")
    found = file.variables
    extra, missing = sorted(set(found) - set(listed)), sorted(set(listed) - set(found))
    if extra or missing:
        names = ", ".join(map(name_text, (extra + missing)[:5])) + (", ..." if len(extra + missing) > 5 else "")
        raise ParameterError(f"{nc}: variable(s) {names} differ from those its JSON lists")
    for name, (dims, shape, dtype) in listed.items():
        variable = found[name]
        if tuple(variable.dimensions) != dims or tuple(variable.shape) != shape or not _stored_as(variable, dtype):
            raise ParameterError(f"{nc}: variable {name_text(name)} differs in dimensions, shape or type from its JSON")


def _open_checked(nc: Path, listed: dict):
    """The data of the NetCDF file ``nc``, read after its storage (:func:`rocking.study.files.check_hdf5`) and its
    variables (:func:`_check_stored`) are checked; any failure of the NetCDF or HDF5 library is one line."""
    import netCDF4
    import xarray as xr

    unreadable = f"{nc}: not a readable NetCDF file of a study"
    try:
        check_hdf5(nc)
    except (ValueError, ParameterError) as exc:  # its reasons, in one line; no HDF5 library found
        raise ParameterError(f"{nc}: {exc}") from None
    except Exception as exc:  # noqa: BLE001  (a damaged file: any type, as UNREADABLE says)
        raise ParameterError(f"{unreadable} ({describe(exc)})") from None
    try:
        file = netCDF4.Dataset(nc, "r")
    except Exception as exc:  # noqa: BLE001
        raise ParameterError(f"{unreadable} ({describe(exc)})") from None
    try:
        _check_stored(nc, file, listed)
        with xr.open_dataset(xr.backends.NetCDF4DataStore(file)) as opened:
            return opened.load()
    except ParameterError:
        raise
    except Exception as exc:  # noqa: BLE001
        raise ParameterError(f"{unreadable} ({describe(exc)})") from None
    finally:
        with suppress(Exception):
            file.close()


def _read_data(nc: Path, record: dict):
    """The data of a saved study, checked against its JSON record: the file's size against the layout's, its
    storage and variables (names, dimensions, shapes, dtypes) from its metadata, then, once read, its content
    against the record's checksum."""
    listed = _shapes(record["variables"])
    limit = sum(math.prod(shape) * dtype.itemsize for _, shape, dtype in listed.values()) + NETCDF_OVERHEAD
    size = nc.stat().st_size
    if size > limit:
        raise ParameterError(f"{nc}: {size} bytes, more than the {limit} its JSON allows")
    data = _open_checked(nc, listed)
    if not isinstance(data.attrs.get("kind"), str) or "config" not in data.attrs:
        raise ParameterError(f"{nc}: not a rocking study (no kind and configuration in its attributes)")
    found = data_layout(data)
    wrong = sorted(k for k in listed if found.get(k) != record["variables"][k])
    if wrong or set(found) != set(listed):
        names = ", ".join(map(name_text, (wrong or sorted(set(found) ^ set(listed)))[:5]))
        raise ParameterError(f"{nc}: variable(s) {names} differ in shape or type from its JSON")
    if checksum(variables(data)) != record["variables_sha256"]:
        raise ParameterError(f"{nc}: its variables do not match the checksum of its JSON (changed or damaged)")
    data.attrs.clear()  # the configuration and summary are the record's, checked
    if record["kind"] in ("map", "spectrum"):  # their pulses' vertical component, as the study made them
        data.attrs.update(vertical_attrs(record["config"]), **floor_attrs(record["config"]))
    if record["kind"] == "friction":  # its pulses' one frequency
        data.attrs.update(friction_attrs(record["config"]))
    return data


def _check_coordinates(data, expected: dict, meta: Path) -> None:
    """Refuse coordinates that are not the values the configuration gives them."""
    for dim, (field, values) in expected.items():
        if not np.allclose(data[dim].values, values, rtol=1e-9, atol=0.0):
            raise ParameterError(f"{meta}: config: {field} gives other values than the coordinate {dim} holds")


def _trust(folder: str | Path, record: dict, meta: Path) -> None:
    """Load the model folder the user named for a saved study, checked to be the one the study was run with."""
    damper = record["config"].get("damper")
    saved = damper if isinstance(damper, dict) else {}
    # Compared before the folder's code is loaded: a folder of another content is not run at all.
    try:
        digest = tree_hash(Path(folder).resolve()) if Path(folder).is_dir() else None
    except OSError as exc:
        raise ParameterError(f"trust_model {folder}: cannot be read ({describe(exc)})") from None
    if digest is None or saved.get("model_sha256") != digest:
        raise ParameterError(
            f"trust_model {folder}: not the model folder {meta} was run with (no such folder, or its SHA-256 "
            "differs from config.damper.model_sha256)"
        )
    try:
        load_model(Path(folder))
    except ModelError as exc:
        raise ParameterError(f"trust_model: {exc}") from None


def load(path: str | Path, *, trust_model: str | Path | None = None) -> Study:
    """Read a saved study back from its ``.nc``/``.json`` pair (either path, or the common stem), its tables
    made from its data by its kind (:data:`rocking.study.kinds.KINDS`).

    A saved file never selects code to run: a study of a model of the user's own names it, but that
    model is used (for its units) only if the user names its folder again, as ``trust_model``
    (:func:`rocking.model.loading.saved_model`); a built-in model needs nothing.

    The JSON record is the mark of a whole study (:func:`save` writes it last): without it there is no
    study. Its texts are bounded (:func:`check_texts`), its configuration and summary are checked to be those
    saved with its results (their SHA-256s: which anyone can make again, so they prove no origin), every field of
    its configuration by the command line's table (:func:`check_fields`), its configuration against the variables it
    lists (:func:`check_config`, :func:`check_variables`), and the NetCDF file's size, storage and variables
    against that list from its metadata, before any of its data is read (:func:`_open_checked`: no external,
    virtual or filtered datasets, no variable the record does not list).

    Raises
    ------
    ParameterError
        Naming the file, if either file is missing, the JSON is not a saved
        study's (not JSON, too large or deep, not an object, no ``kind``/``config``/``summary``/``variables``,
        an unknown kind, another format: a study saved by an earlier version is refused in one line), its
        configuration or summary was changed after it was saved, its configuration is not valid or contradicts
        its variables, the ``.nc`` cannot be read (truncated, damaged, not NetCDF-4, larger than its JSON says:
        any failure of the NetCDF or HDF5 library), stores data outside itself, or its variables differ from what
        the JSON lists;
        or if ``trust_model`` is not the model the study was run with.
    """
    stem = study_stem(path)
    nc, meta = stem.with_suffix(".nc"), stem.with_suffix(".json")
    for p in (meta, nc):
        if not p.is_file():
            raise ParameterError(
                f"no saved study at {stem}: {p} is missing (a study writes its .nc and .csv, "
                "then its .json; a save cut short leaves no .json: save or run it again)"
            )
        refused = input_refusal(p)
        if refused:
            raise ParameterError(f"{p}: {refused}")
    record = read_record(meta)
    kind, config = record["kind"], record["config"]
    _check_unchanged(record, meta)
    try:
        expected, sizes = check_config(kind, config)
    except ParameterError as exc:
        raise ParameterError(f"{meta}: config: {exc}") from None
    try:
        check_variables(kind, record["variables"], sizes)
    except ParameterError as exc:
        raise ParameterError(f"{meta}: variables: {exc}") from None
    if trust_model is not None:
        _trust(trust_model, record, meta)
    data = _read_data(nc, record)
    _check_coordinates(data, expected, meta)
    try:
        KINDS[kind].tables(data, config)  # made here too, so that a loaded study's tables never fail later
    except (KeyError, TypeError, ValueError, IndexError, ParameterError) as exc:
        raise ParameterError(f"{meta}: its configuration and data do not make its tables ({describe(exc)})") from None
    run = record.get("run") if isinstance(record.get("run"), dict) else {}
    return Study(kind, config, data, summary=record["summary"], run=run, tabulate=KINDS[kind].tables)
