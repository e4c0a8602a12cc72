"""What a study leaves on disk: ``<name>.npz`` (every array), ``<name>*.csv`` (tables), ``<name>.json``.

:func:`save` writes a :class:`~rocking.study.config.Study` with its
configuration, the configuration's hash, software versions, summary and
timing; :func:`load` reads it back without recomputing anything, and refuses
with a :class:`~rocking.model.params.ParameterError` naming the file a study
whose files are damaged, foreign or do not belong together.

Every file is written atomically (:func:`atomic_write`: a temporary file in
the same folder, then ``os.replace``): a reader, or a rerun after Ctrl-C or a
killed process, sees a whole file or none. Arrays are read with
``allow_pickle=False``: nothing read from a file is executed. The same
helpers store and check the tiles of a study (:mod:`rocking.study.tiles`):
:func:`checksum` of the arrays and :func:`layout` (names, shapes, dtypes).
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from collections.abc import Callable
from contextlib import suppress
from pathlib import Path

import numpy as np

from ..model.loading import ModelError, load_model
from ..model.params import ParameterError
from .config import Study, config_hash, tree_hash, versions

#: Kinds of saved studies, and the parts of their JSON record that :func:`load` needs.
#: Version of the layout of a saved study's files: a study saved with another is refused, in one line.
STUDY_FORMAT = 2

KINDS = ("map", "spectrum", "optimize", "design", "threshold", "ida", "fragility")
RECORD = {"kind": str, "config": dict, "summary": dict}

#: What reading a damaged or foreign ``.npz`` raises. zipfile and NumPy raise many types for a
#: damaged file: BadZipFile (a bad archive, a CRC), NotImplementedError (a damaged version
#: field), ValueError and SyntaxError (a member's header), EOFError and OSError (truncated
#: data), KeyError, zlib.error, MemoryError (a header asking for a huge array), ... Any of
#: them means the same (the file cannot be used), and nothing read is executed (no pickles).
UNREADABLE = (Exception,)

#: The first bytes of a zip archive (an ``.npz``).
ZIP_MAGIC = b"PK\x03\x04"


def atomic_write(path: Path, write: Callable, mode: str = "wb") -> None:
    """Write through ``write(file)`` to a temporary file next to ``path``, then rename it over ``path``.

    Parameters
    ----------
    path : Path
        The file to write; its folder must exist.
    write : callable
        ``write(file)``, given the open temporary file.
    mode : {"wb", "w"}, optional
        Binary, or text (UTF-8, newlines as written).

    Notes
    -----
    A reader (or a rerun after Ctrl-C or a killed process) sees either the old
    file, or no file, or the whole new one. No fsync: it would cost as much as
    a small tile's work, and only a power cut can leave a damaged file, which
    :func:`load` and :func:`rocking.study.tiles.load_tile` refuse.
    """
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        text = {"encoding": "utf-8", "newline": ""} if "b" not in mode else {}
        with os.fdopen(fd, mode, **text) as f:
            write(f)
        os.replace(tmp, path)
    except BaseException:
        # Ctrl-C may come just after the rename (the signal is handled when os.replace returns): no tmp then.
        with suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def layout(arrays: dict) -> dict:
    """Name -> ``{"dtype": ..., "shape": [...]}`` of ``arrays``, JSON-ready."""
    return {k: {"dtype": np.asarray(v).dtype.str, "shape": list(np.shape(v))} for k, v in sorted(arrays.items())}


def checksum(arrays: dict) -> str:
    """SHA-256 of the content of ``arrays``: each name, dtype, shape and bytes, in sorted order of names."""
    digest = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        digest.update(f"{name}\0{a.dtype.str}\0{a.shape}\0".encode())
        digest.update(a.tobytes())
    return digest.hexdigest()


def read_npz(path: Path) -> dict:
    """Every array of the ``.npz`` at ``path``, read without pickles.

    Raises
    ------
    ValueError
        If the file is not a zip archive (e.g. a ``.npy``, a text file).
    Exception
        Any of :data:`UNREADABLE` for a truncated or damaged archive.
    """
    # Our own file object: np.load leaves the file it opened open when the archive is damaged.
    with open(path, "rb") as f:
        if f.read(len(ZIP_MAGIC)) != ZIP_MAGIC:
            raise ValueError("not an .npz archive")
        f.seek(0)
        with np.load(f, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}


def describe(exc: BaseException) -> str:
    """An exception as a short reason for a one-line message."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _stem(path: str | Path) -> Path:
    path = Path(path)
    return path.with_suffix("") if path.suffix in (".npz", ".json", ".csv", ".nc") else path


def write_csv(path: Path, columns: dict, chunk: int = 10_000) -> None:
    """Write equal-length columns as CSV with a header, atomically; floats as their shortest exact ``repr``.

    Rows are formatted ``chunk`` at a time, so that a big map needs no Python
    object per value of the whole table at once.
    """
    names = list(columns)
    data = [np.asarray(columns[k]).ravel() for k in names]
    row = ",".join("%r" if d.dtype.kind == "f" else "%s" for d in data) + "\n"

    def write(f) -> None:
        f.write(",".join(names) + "\n")
        for start in range(0, len(data[0]) if data else 0, chunk):
            f.writelines(row % values for values in zip(*(d[start : start + chunk].tolist() for d in data)))

    atomic_write(path, write, mode="w")


def make_folder(folder: str | Path, what: str) -> Path:
    """``folder``, created if needed and checked to be writable; ``what`` names it in the error.

    Raises
    ------
    ParameterError
        If it cannot be created (a part of the path is a file) or written (permissions).
    """
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        # A probe file: permissions, read-only mounts and ACLs all answer the same way (os.access does not).
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise ParameterError(f"{what} {folder}: cannot write there ({_why(folder, exc)})") from None
    return folder


def _why(folder: Path, exc: OSError) -> str:
    """Why ``folder`` cannot be written, in words: the file in its way, or the system's reason."""
    for part in (folder, *folder.parents):
        if part.exists() and not part.is_dir():
            return f"{part} is a file, not a folder" if part != folder else "it is a file, not a folder"
    return exc.strerror or describe(exc)


def save(study: Study, folder: str | Path, name: str | None = None, command: dict | None = None) -> list[Path]:
    """Write ``study`` into ``folder`` as ``<name>.npz``, ``.json``, its CSV tables (``<name>.csv``,
    ``<name>-windows.csv``, ...) and its labelled :class:`xarray.Dataset` as ``<name>.nc``
    (:mod:`rocking.study.dataset`), each atomically.

    The JSON record lists the arrays (:func:`layout`) and their :func:`checksum`,
    which :func:`load` checks.

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    ParameterError
        If ``folder`` cannot be created or written.
    """
    folder = make_folder(folder, "output folder")
    stem = folder / (name or study.kind)
    atomic_write(stem.with_suffix(".npz"), lambda f: np.savez(f, **study.arrays))
    written = [stem.with_suffix(".npz")]
    for table, columns in study.tables.items():
        # Tables are named after the kind ("spectrum-windows"); a study saved under another name keeps its own.
        if name and table.startswith(study.kind):
            table = name + table[len(study.kind) :]
        path = folder / f"{table}.csv"
        write_csv(path, columns)
        written.append(path)
    from .dataset import to_dataset, write_netcdf  # the studies' modules, which it reads, store their tiles here

    software = versions()
    written.append(write_netcdf(to_dataset(study, software), stem.with_suffix(".nc")))
    record = {
        "kind": study.kind,
        "config": study.config,
        "config_sha256": config_hash(study.config),
        "versions": software,
        "summary": study.summary,
        "run": study.run,
        "format": STUDY_FORMAT,
        "files": [p.name for p in written],
        "arrays": layout(study.arrays),
        "arrays_sha256": checksum(study.arrays),
    }
    if command is not None:
        record["command"] = command
    text = json.dumps(record, indent=2, sort_keys=True) + "\n"
    atomic_write(stem.with_suffix(".json"), lambda f: f.write(text), mode="w")
    return [*written, stem.with_suffix(".json")]


def _read_record(meta: Path) -> dict:
    """The JSON record of a saved study, checked to be one."""
    try:
        record = json.loads(meta.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:  # UnicodeDecodeError and JSONDecodeError are ValueErrors
        raise ParameterError(f"{meta}: not a saved study's JSON ({describe(exc)})") from None
    if not isinstance(record, dict):
        raise ParameterError(f"{meta}: not a saved study's JSON (a {type(record).__name__}, not an object)")
    for key, kind in RECORD.items():
        if not isinstance(record.get(key), kind):
            raise ParameterError(f"{meta}: not a saved study's JSON (no {kind.__name__} {key!r})")
    if record.get("format", 1) != STUDY_FORMAT:
        raise ParameterError(
            f"{meta}: a study saved in format {record.get('format', 1)} (by rocking "
            f"{(record.get('versions') or {}).get('rocking', 'of another version')}); this version reads format "
            f"{STUDY_FORMAT}: recompute it"
        )
    if record["kind"] not in KINDS:
        raise ParameterError(f"{meta}: unknown kind of study {record['kind']!r} (known: {', '.join(KINDS)})")
    return record


def _read_arrays(npz: Path, record: dict) -> dict:
    """The arrays of a saved study, checked against its JSON record (layout and checksum, when recorded)."""
    try:
        arrays = read_npz(npz)
    except UNREADABLE as exc:
        raise ParameterError(f"{npz}: not a readable .npz, truncated or damaged ({describe(exc)})") from None
    expected = record.get("arrays")
    if isinstance(expected, dict):
        missing = sorted(set(expected) - set(arrays))
        if missing:
            raise ParameterError(f"{npz}: array(s) {', '.join(missing)} missing (its JSON lists them)")
        found = layout(arrays)
        wrong = sorted(k for k in expected if found[k] != expected[k])
        if wrong:
            raise ParameterError(f"{npz}: array(s) {', '.join(wrong)} differ in shape or type from its JSON")
    if "arrays_sha256" in record and checksum(arrays) != record["arrays_sha256"]:
        raise ParameterError(f"{npz}: its arrays do not match the checksum of its JSON (changed or damaged)")
    return arrays


def _trust(folder: str | Path, record: dict, meta: Path) -> None:
    """Load the model folder the user named for a saved study, checked to be the one the study was run with."""
    damper = record["config"].get("damper")
    saved = damper if isinstance(damper, dict) else {}
    # Compared before the folder's code is loaded: a folder of another content is not run at all.
    if not Path(folder).is_dir() or saved.get("model_sha256") != tree_hash(Path(folder).resolve()):
        raise ParameterError(
            f"trust_model {folder}: not the model folder {meta} was run with (no such folder, or its SHA-256 "
            "differs from config.damper.model_sha256)"
        )
    try:
        load_model(Path(folder))
    except ModelError as exc:
        raise ParameterError(f"trust_model: {exc}") from None


def load(path: str | Path, *, trust_model: str | Path | None = None) -> Study:
    """Read a saved study back from its ``.npz``/``.json`` pair (either path, or the common stem), with its
    tables made again from them (:mod:`rocking.study.tables`).

    A saved file never selects code to run: a study of a model of the user's own names it, but that
    model is used (for its units) only if the user names its folder again, as ``trust_model``
    (:func:`rocking.model.loading.saved_model`); a built-in model needs nothing.

    Studies saved before the JSON listed its arrays (``"arrays"``,
    ``"arrays_sha256"``) are read without those checks.

    Raises
    ------
    ParameterError
        Naming the file, if either file is missing, the JSON is not a saved
        study's (not JSON, not an object, no ``kind``/``config``/``summary``,
        an unknown kind), the ``.npz`` cannot be read (truncated, damaged, not
        an archive), or its arrays differ from what the JSON lists; or if
        ``trust_model`` is not the model the study was run with.
    """
    stem = _stem(path)
    npz, meta = stem.with_suffix(".npz"), stem.with_suffix(".json")
    for p in (npz, meta):
        if not p.is_file():
            raise ParameterError(f"no saved study at {stem}: {p} is missing (a study writes both .npz and .json)")
    record = _read_record(meta)
    if trust_model is not None:
        _trust(trust_model, record, meta)
    arrays = _read_arrays(npz, record)
    run = record.get("run") if isinstance(record.get("run"), dict) else {}
    from .tables import tables  # the studies' modules, which it reads, store their tiles here

    try:
        made = tables(record["kind"], arrays, record["config"])
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        raise ParameterError(f"{meta}: its configuration and arrays do not make its tables ({describe(exc)})") from None
    return Study(record["kind"], record["config"], arrays, tables=made, summary=record["summary"], run=run)
