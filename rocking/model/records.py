"""Recorded accelerograms from files: the PEER NGA ``.AT2`` format and plain text or CSV columns.

A file is data: it is parsed, never executed, and every value is checked. Whatever is
wrong (a missing or unreadable header, a count that does not match, a value that is not
a finite number, a time step that is not uniform, a missing unit) is refused with one
line naming the file and, where it applies, the line.

The result is a :class:`Record`: the acceleration in m/s^2 at uniform steps ``dt`` from
``t = 0``.

Units
-----
Accelerations in files are in ``g`` (9.80665 m/s^2, the standard gravity NGA uses),
``m/s2`` or ``cm/s2`` (gal); times in ``s``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .motion import irregular_step
from .params import ParameterError

#: Standard gravity, m/s^2: the ``g`` of records in units of g (PEER NGA).
STANDARD_GRAVITY = 9.80665
#: Accelerations a file may be in, and their value in m/s^2.
UNITS = {"g": STANDARD_GRAVITY, "m/s2": 1.0, "cm/s2": 0.01}
#: Largest file read, bytes (a 200 Hz record of an hour is about 10 MB of text).
MAX_BYTES = 100_000_000

#: A number as Fortran and C write it (also run together, "-.12E-01-.34E-01"; D exponents too).
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?")
#: ``NPTS= 4000, DT= .0050 SEC`` and its variants (any order, "=" or ":" or spaces, a unit after DT).
_NPTS = re.compile(r"\bNPTS\s*[=:]?\s*(\d+)", re.IGNORECASE)
_DT = re.compile(r"\bDT\s*[=:]?\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)", re.IGNORECASE)
#: The older NGA header: "3000    0.0100    NPTS, DT".
_OLD = re.compile(r"^\s*(\d+)\s+([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s+NPTS\s*,?\s*DT", re.IGNORECASE)


@dataclass(frozen=True)
class Record:
    """A ground acceleration sampled at uniform steps from ``t = 0``.

    Attributes
    ----------
    acceleration : ndarray
        Samples, m/s^2 (finite).
    dt : float
        Time step, s (> 0).
    name : str
        Where it came from (the file, or a label).
    """

    acceleration: np.ndarray
    dt: float
    name: str = ""

    @property
    def duration(self) -> float:
        """Time of the last sample, s."""
        return (len(self.acceleration) - 1) * self.dt

    @property
    def times(self) -> np.ndarray:
        """The sample times, s."""
        return np.arange(len(self.acceleration)) * self.dt


def _fail(path, text: str, line: int | None = None) -> ParameterError:
    where = f"{path}, line {line}" if line is not None else f"{path}"
    return ParameterError(f"{where}: {text}")


def _read_text(path) -> list[str]:
    """The lines of a text file, refusing what is not one (missing, too large, binary, not UTF-8/Latin-1)."""
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise _fail(path, f"{size} bytes, more than the {MAX_BYTES} a record may have")
        data = path.read_bytes()
    except OSError as exc:
        raise _fail(path, f"cannot be read ({exc.strerror or exc})") from None
    if b"\0" in data:
        raise _fail(path, "is not a text file (it holds NUL bytes)")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    return text.splitlines()


def _unit(path, unit: str) -> float:
    if unit not in UNITS:
        raise _fail(path, f"unit must be one of {', '.join(UNITS)} (got {unit!r})")
    return UNITS[unit]


def _values(path, lines: list[str], first: int) -> tuple[np.ndarray, list[int]]:
    """The numbers of ``lines[first:]``, and the line (1-based) of each; a line with anything else is refused."""
    values, where = [], []
    for i, line in enumerate(lines[first:], start=first + 1):
        numbers = _NUMBER.findall(line)
        rest = _NUMBER.sub("", line).replace(",", " ").strip()
        if rest:
            raise _fail(path, f"not a number: {rest.split()[0][:40]!r}", i)
        for number in numbers:
            values.append(float(number.replace("d", "e").replace("D", "E")))
            where.append(i)
    a = np.asarray(values, float)
    bad = ~np.isfinite(a)
    if bad.any():
        raise _fail(path, f"the value {values[int(np.argmax(bad))]!r} is not finite", where[int(np.argmax(bad))])
    return a, where


def _at2_header(path, lines: list[str]) -> tuple[int, float, float]:
    """``(npts, dt, unit)`` of an AT2 header: the units on line 3, NPTS and DT on line 4."""
    if len(lines) < 4:
        raise _fail(path, f"an AT2 file has 4 header lines; this one has {len(lines)} line(s)")
    units = lines[2].upper()
    if "UNITS OF G" not in units and not re.search(r"\bIN\s+G\b", units):
        raise _fail(path, f"line 3 must give the units (\"... IN UNITS OF G\"): got {lines[2].strip()[:60]!r}", 3)
    old = _OLD.match(lines[3])
    npts, dt = (old.group(1), old.group(2)) if old else (_match(_NPTS, lines[3]), _match(_DT, lines[3]))
    if npts is None or dt is None:
        got = lines[3].strip()[:60]
        raise _fail(path, f"line 4 must give NPTS and DT (\"NPTS= 4000, DT= .0050 SEC\"): got {got!r}", 4)
    npts, dt = int(npts), float(dt)
    if npts < 2:
        raise _fail(path, f"NPTS must be >= 2 (got {npts})", 4)
    if not (math.isfinite(dt) and dt > 0):
        raise _fail(path, f"DT must be > 0 s (got {dt!r})", 4)
    return npts, dt, UNITS["g"]


def _match(pattern: re.Pattern, line: str) -> str | None:
    m = pattern.search(line)
    return m.group(1) if m else None


def read_at2(path) -> Record:
    """A PEER NGA ``.AT2`` record: 4 header lines (title, event, "ACCELERATION ... IN UNITS OF G",
    "NPTS= n, DT= dt SEC" or the older "n dt NPTS, DT"), then the ``n`` values in g.

    Returns
    -------
    Record
        In m/s^2 (``g`` = :data:`STANDARD_GRAVITY`).

    Raises
    ------
    ParameterError
        Naming the file (and the line): unreadable, a header that is missing or malformed, a count of
        values other than NPTS, a value that is not a finite number.
    """
    lines = _read_text(path)
    npts, dt, unit = _at2_header(path, lines)
    values, _ = _values(path, lines, 4)
    if values.size != npts:
        raise _fail(path, f"the header declares NPTS = {npts} but the file holds {values.size} values "
                          "(truncated or damaged?)")  # fmt: skip
    return Record(values * unit, dt, str(path))


def read_columns(path, unit: str, *, dt: float | None = None, time_column: bool = True) -> Record:
    """A record in plain text or CSV: one row per sample, ``time, acceleration`` or the acceleration alone.

    Separators: commas, semicolons, tabs or spaces. Lines starting with ``#`` and a first line of
    column names are skipped.

    Parameters
    ----------
    path : path
        The file.
    unit : {"g", "m/s2", "cm/s2"}
        The unit of the accelerations (required: a file does not say it).
    dt : float, optional
        The time step, s, when the file holds the accelerations alone (``time_column=False``).
    time_column : bool
        Whether the first column holds the times, s (uniformly spaced from any start; the record starts
        at ``t = 0``).

    Raises
    ------
    ParameterError
        Naming the file (and the line): unreadable, a unit missing or unknown, a row of the wrong number of
        columns, a value that is not a finite number, times that are not uniformly spaced, fewer than 2 rows.
    """
    scale = _unit(path, unit)
    if time_column == (dt is not None):
        raise ParameterError("give dt (s) for a file of accelerations alone, or time_column=True, not both")
    lines = _read_text(path)
    rows, where = [], []
    for i, line in enumerate(lines, start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        cells = [c for c in re.split(r"[,;\s]+", text) if c]
        if not rows and not _NUMBER.fullmatch(cells[0]):
            continue  # the column names
        if len(cells) != (2 if time_column else 1):
            raise _fail(path, f"expected {2 if time_column else 1} column(s), got {len(cells)}", i)
        try:
            row = [float(c) for c in cells]
        except ValueError:
            raise _fail(path, f"not a number: {cells!r}", i) from None
        if not all(math.isfinite(x) for x in row):
            raise _fail(path, f"the value {cells} is not finite", i)
        rows.append(row)
        where.append(i)
    if len(rows) < 2:
        raise _fail(path, f"a record needs at least 2 samples (got {len(rows)})")
    data = np.asarray(rows)
    if time_column:
        dt = uniform_step(data[:, 0], path, where)
    elif not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
        raise ParameterError(f"dt must be > 0 s (got {dt!r})")
    return Record(data[:, -1] * scale, float(dt), str(path))


def uniform_step(t, path="times", lines=None) -> float:
    """The step of uniformly spaced times ``t`` (:func:`rocking.model.motion.irregular_step`), else a one-line
    error naming the first irregular step (and its line of ``path``)."""
    dt, k = irregular_step(t)
    if not dt > 0:
        raise _fail(path, f"times must increase (mean step {dt!r} s)", None if lines is None else lines[-1])
    if k is not None:
        step = float(t[k + 1] - t[k])
        raise _fail(path, f"times must be uniformly spaced: step {step:.6g} s where the others are "
                          f"{float(np.median(np.diff(t))):.6g} s",
                    None if lines is None else lines[k + 1])  # fmt: skip
    return dt


def read_record(path, unit: str | None = None, **kwargs) -> Record:
    """A record by its file's extension: ``.AT2`` (units in the file), else columns (``unit`` required)."""
    if Path(path).suffix.upper() == ".AT2":
        if unit not in (None, "g"):
            raise _fail(path, f"an AT2 file is in g; unit {unit!r} does not apply")
        return read_at2(path)
    if unit is None:
        raise _fail(path, f"give the unit of the accelerations ({', '.join(UNITS)}): a text file does not say it")
    return read_columns(path, unit, **kwargs)
