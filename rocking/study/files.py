"""Files of the studies, written whole and read within bounds: the primitives under saved studies and tiles.

A file is written atomically (:func:`atomic_write`: a temporary file in its folder renamed over it; a symbolic
link in its place is replaced, never followed) or created anew (:func:`write_file`), with the mode of any new
file, ``0666`` less the umask; a full disk raises :class:`DiskFull` naming the file, and nothing partial stays
behind (the writing side lives in :mod:`rocking.model.outputs`, below the simulator, which writes its histories
alike). Two writers of one study's files into one folder are serialised by a lock on its name
(:func:`name_lock`).

What is read is bounded before it is read: a JSON record's size and nesting (:func:`read_json`), an archive's
arrays from the zip's headers (:func:`read_npz`: uncompressed members, each the size its ``.npy`` header says,
within a limit), the storage of a NetCDF-4 file's datasets from its HDF5 metadata (:func:`check_hdf5`: in the
file itself, unfiltered); arrays are read with ``allow_pickle=False``: nothing read from a file is executed; a
file of the kernel or a device (under /proc, /sys, /dev) is never read
(:func:`rocking.model.records.input_refusal`). :func:`checksum` and :func:`layout` describe arrays (names,
shapes, dtypes, content) for the records that check them.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import hashlib
import json
import math
import re
import subprocess
import sys
import tempfile
import zipfile
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager, suppress
from pathlib import Path

import numpy as np
from numpy.lib import format as npy

from ..model.outputs import FULL as FULL
from ..model.outputs import DiskFull as DiskFull
from ..model.outputs import atomic_write as atomic_write
from ..model.outputs import is_full as is_full
from ..model.outputs import no_space as no_space
from ..model.outputs import replace_file as replace_file
from ..model.outputs import write_file as write_file
from ..model.params import ParameterError
from ..model.records import input_refusal
from ..sim.cbuild import lock
from .config import MAX_CELLS

#: What reading a damaged or foreign ``.npz`` raises. zipfile and NumPy raise many types for a
#: damaged file: BadZipFile (a bad archive, a CRC), NotImplementedError (a damaged version
#: field), ValueError and SyntaxError (a member's header), EOFError and OSError (truncated
#: data), KeyError, zlib.error, MemoryError (a header asking for a huge array), ... Any of
#: them means the same (the file cannot be used), and nothing read is executed (no pickles).
UNREADABLE = (Exception,)

#: The first bytes of a zip archive (an ``.npz``).
ZIP_MAGIC = b"PK\x03\x04"

#: The first bytes of an HDF5 file (a NetCDF-4 file is one), where the NetCDF library writes them: at its start.
HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"

#: Seconds the check of a NetCDF file's HDF5 metadata may take (:func:`check_hdf5`; a study's takes milliseconds).
HDF5_CHECK_SECONDS = 10.0

#: Largest JSON record read (a configuration of two grids of MAX_N explicit values is 5 MB), and its
#: deepest nesting (a record is 5 deep): bounds checked before parsing, so that neither memory nor
#: Python's recursion limit decides.
MAX_JSON_BYTES = 64 << 20
MAX_JSON_DEPTH = 32

#: Largest sum of the arrays of a study: a map of MAX_CELLS cells in both directions holds 3.2 GB
#: (324 bytes per cell).
MAX_STUDY_BYTES = MAX_CELLS * 400

#: Largest ``.npy`` header of a member (NumPy writes 128 bytes, more for many dimensions).
MAX_NPY_HEADER = 4096


@contextmanager
def name_lock(folder: Path, name: str) -> Iterator[None]:
    """Hold the lock on the files of the study ``name`` in ``folder`` (``.<name>.lock``, the C cache's lock).

    Two commands saving one study name into one folder take turns: each publishes its data and draws its
    figures as a whole, so that the figures beside the data are always those of that data. Reentrant: a save
    under its caller's lock takes it again at no cost.

    Raises
    ------
    ParameterError
        If the lock cannot be taken (its file cannot be created, or is a symbolic link): one line naming it.
    """
    path = Path(folder) / f".{name}.lock"
    stack = ExitStack()
    try:
        stack.enter_context(lock(path))
    except OSError as exc:  # ELOOP: a symbolic link planted in its place
        raise ParameterError(f"cannot lock {path} against another save of {name} ({describe(exc)})") from None
    with stack:
        yield


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


def _npy_bytes(zf: zipfile.ZipFile, info: zipfile.ZipInfo) -> int:
    """The bytes a member must hold: its ``.npy`` header and the array that header announces."""
    with zf.open(info) as f:
        version = npy.read_magic(f)
        read_header = {(1, 0): npy.read_array_header_1_0, (2, 0): npy.read_array_header_2_0}.get(version)
        if read_header is None:
            raise ValueError(f"member {info.filename}: .npy format {version}, not one NumPy's savez writes")
        shape, _, dtype = read_header(f, max_header_size=MAX_NPY_HEADER)
        return f.tell() + math.prod(shape) * dtype.itemsize


def check_archive(zf: zipfile.ZipFile, limit: int) -> None:
    """Refuse an archive from its headers, before any array is read: members that are compressed (the bytes
    read are then the bytes on disk), more than ``limit`` bytes in all, or whose ``.npy`` header announces
    another size than the member's.

    Raises
    ------
    ValueError
        With the reason.
    """
    infos = zf.infolist()
    total = sum(info.file_size for info in infos)
    if total > limit:
        raise ValueError(f"its members hold {total} bytes, more than the {limit} expected")
    for info in infos:
        if info.compress_type != zipfile.ZIP_STORED:
            raise ValueError(f"member {info.filename} is compressed; arrays are stored as np.savez writes them")
        announced = _npy_bytes(zf, info)
        if announced != info.file_size:
            raise ValueError(
                f"member {info.filename}: its header announces {announced} bytes, it holds {info.file_size}"
            )


def read_npz(path: Path, limit: int = MAX_STUDY_BYTES) -> dict:
    """Every array of the ``.npz`` at ``path``, read without pickles, after :func:`check_archive` with ``limit``.

    Raises
    ------
    ValueError
        If the file is not a zip archive (e.g. a ``.npy``, a text file), or its headers are refused.
    Exception
        Any of :data:`UNREADABLE` for a truncated or damaged archive.
    """
    refused = input_refusal(path)
    if refused:
        raise ValueError(refused)
    # Our own file object: np.load leaves the file it opened open when the archive is damaged.
    with open(path, "rb") as f:
        if f.read(len(ZIP_MAGIC)) != ZIP_MAGIC:
            raise ValueError("not an .npz archive")
        f.seek(0)
        with zipfile.ZipFile(f) as zf:
            check_archive(zf, limit)
        f.seek(0)
        with np.load(f, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}


#: A JSON string, escapes included: brackets inside strings do not nest.
_JSON_STRING = re.compile(r'"[^"\\]*(?:\\.[^"\\]*)*"')


def json_depth(text: str) -> int:
    """The deepest nesting of arrays and objects in the JSON ``text``, counted without parsing it."""
    code = np.frombuffer(_JSON_STRING.sub("", text).encode(), np.uint8)
    marks = code[np.isin(code, np.frombuffer(b"[]{}", np.uint8))]
    steps = np.where((marks == ord("[")) | (marks == ord("{")), 1, -1)
    return int(np.cumsum(steps).max(initial=0))


def read_json(path: Path) -> object:
    """The JSON value in the file at ``path``, its size and nesting checked before it is parsed.

    Raises
    ------
    OSError
        If it cannot be read.
    ValueError
        If it is not a regular file (a FIFO would never end), a file of the kernel or a device (under /proc,
        /sys, /dev: ``/proc/kmsg`` is a regular file that waits for the kernel's messages), larger than
        :data:`MAX_JSON_BYTES`, not UTF-8, nested deeper than :data:`MAX_JSON_DEPTH`, or not JSON.
    """
    refused = input_refusal(path)
    if refused:
        raise ValueError(refused)
    if path.exists() and not path.is_file():
        raise ValueError("not a regular file")
    with open(path, "rb") as f:
        data = f.read(MAX_JSON_BYTES + 1)
    if len(data) > MAX_JSON_BYTES:
        raise ValueError(f"larger than {MAX_JSON_BYTES >> 20} MB")
    text = data.decode("utf-8")
    depth = json_depth(text)
    if depth > MAX_JSON_DEPTH:
        raise ValueError(f"nested {depth} deep, at most {MAX_JSON_DEPTH}")
    return json.loads(text)


@functools.cache
def hdf5_library() -> str:
    """The file of the HDF5 library that the NetCDF library loaded.

    Raises
    ------
    ParameterError
        If it is not found.
    """
    import netCDF4  # noqa: F401  (loads the NetCDF library and its HDF5)

    with suppress(OSError):
        with open("/proc/self/maps") as maps:  # Linux: the libraries this process loaded
            for line in maps:
                name = line.rsplit("/", 1)[-1].strip()
                if name.startswith("libhdf5") and not name.startswith("libhdf5_hl") and ".so" in name:
                    return line[line.index("/") :].strip()
    found = ctypes.util.find_library("hdf5") or ctypes.util.find_library("hdf5_serial")
    if found is None:
        raise ParameterError("cannot check a NetCDF file's storage: the HDF5 library of netCDF4 is not found")
    return found


def check_hdf5(path: Path) -> None:
    """Refuse an HDF5 (NetCDF-4) file from its metadata, before any of its data are read: every link must be a
    hard link to a dataset that keeps its own bytes in the file, unfiltered; no groups, soft or external links
    (:mod:`rocking.study.hdf5_walk`). Checked in a process of its own within :data:`HDF5_CHECK_SECONDS`: the HDF5
    library loops forever on some damaged metadata, and may crash on others.

    Raises
    ------
    ValueError
        With the reason, for a file that breaks these rules or that the HDF5 library cannot read in time.
    ParameterError
        If the HDF5 library cannot be found.
    """
    with open(path, "rb") as f:
        if f.read(len(HDF5_MAGIC)) != HDF5_MAGIC:
            raise ValueError("not a NetCDF-4 (HDF5) file")
    walk = [sys.executable, "-I", "-S", str(Path(__file__).with_name("hdf5_walk.py")), hdf5_library(), str(path)]
    try:
        done = subprocess.run(walk, capture_output=True, text=True, timeout=HDF5_CHECK_SECONDS, check=False)
    except subprocess.TimeoutExpired:
        raise ValueError(f"its HDF5 metadata cannot be read in {HDF5_CHECK_SECONDS:g} s (damaged)") from None
    try:
        answer = json.loads(done.stdout)
    except ValueError:
        answer = None
    if not isinstance(answer, dict) or (answer.get("ok") is not True and not isinstance(answer.get("refused"), str)):
        raise ValueError(f"the HDF5 library fails on its metadata (damaged; exit {done.returncode})")
    if "refused" in answer:
        raise ValueError(answer["refused"].splitlines()[0] if answer["refused"] else "refused")


def describe(exc: BaseException) -> str:
    """An exception as a short reason for a one-line message."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def write_csv(path: Path, columns: dict, chunk: int = 10_000) -> None:
    """Write equal-length columns as CSV with a header into the new file ``path`` (:func:`save` writes it in
    its temporary folder); floats as their shortest exact ``repr``, other values as ``str``.

    Rows are formatted ``chunk`` at a time, so that a big map needs no Python
    object per value of the whole table at once.
    """
    names = list(columns)
    data = [np.asarray(columns[k]).ravel() for k in names]

    def write(f) -> None:
        f.write(",".join(names) + "\n")
        for start in range(0, len(data[0]) if data else 0, chunk):
            rows = zip(*(csv_texts(d[start : start + chunk]) for d in data))
            f.write("\n".join(map(",".join, rows)) + "\n")  # joins: twice as fast as a "%s,%s,..." per row

    write_file(path, write, mode="w")


def csv_texts(values: np.ndarray) -> list[str]:
    """The texts of a 1-d column of a CSV table: ``repr`` of each float, ``str`` of anything else.

    A column of few distinct values (a map's grid coordinates, its codes and counts) formats each of them once:
    formatting is most of a table's writing time. Floats are told apart by their bits (``-0.0`` is not ``0.0``).
    """
    text = repr if values.dtype.kind == "f" else str
    if values.dtype.kind in "biuf" and values.itemsize <= 8:  # a float's bits as an integer of its size
        keys = values.view(f"i{values.itemsize}") if values.dtype.kind == "f" else values
        first, inverse = np.unique(keys, return_index=True, return_inverse=True)[1:]
        if 2 * first.size < values.size:
            return np.array([text(v) for v in values[first].tolist()], object)[inverse].tolist()
    return list(map(text, values.tolist()))


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
