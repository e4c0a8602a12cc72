"""Recorded accelerograms from files: the PEER NGA ``.AT2`` format and plain text or CSV columns.

A file is data: it is parsed, never executed, and every value is checked. Whatever is
wrong (a file that is not a regular file, a missing or unreadable header, a count that
does not match, a value that is not a plain finite number, a time step that is not
uniform or out of range, a unit missing or contradicted) is refused with one line naming
the file and, where it applies, the line.

The result is a :class:`Record`: the acceleration in m/s^2 at uniform steps ``dt`` from
``t = 0``.

Bounds
------
Only a regular file is read: a symbolic link is followed to its target, and a named pipe,
a device (``/dev/zero``, ``/dev/urandom``), a directory or a socket is refused before it is
opened (and opened without blocking, so a pipe put in its place meanwhile cannot block
either). A file of the kernel or of a device, under /proc, /sys or /dev once its links are
resolved, is refused too, even where it is a regular file (``/proc/kmsg`` waits for the
kernel's messages and, read by root, consumes them): :func:`input_refusal`, which every
input file of rocking passes (records, saved studies, specs). The file is read line by line,
and reading stops at the first bound passed:

- :data:`MAX_BYTES` bytes in the file (refused from its size before reading);
- :data:`MAX_LINE` characters in one line (a file without line breaks is not read whole);
- :data:`MAX_SAMPLES` samples in a record (an AT2 header that declares more is refused at
  line 4), and in an AT2 file no more values than its header's ``NPTS``: reading stops at
  the first value beyond them. A file of columns large enough to hold more rows (two bytes
  a row at least) has its rows counted before any is parsed (:func:`_count_rows`, a pass
  in C over its text): more than :data:`MAX_SAMPLES` are refused at once, not after parsing
  four million of them.

The memory of a read is that of the samples kept, 8 bytes each.

Numbers
-------
A value is a plain decimal number, :data:`NUMBER` (``-1.25``, ``.5``, ``3.``, ``2E-03``, and
Fortran's ``1.0D-02`` exponents), in ASCII. What Python's ``float`` also takes is refused:
``1_000``, ``nan``, ``inf``, digits of other scripts. A value that overflows (``1e999``) or
whose acceleration passes ``RANGES["a_g"]`` (10,000 g) is refused at its line. In an AT2
file values are separated by blanks (or commas), or run together when the next one starts
with its sign (``-.1234E-01-.2345E-01``, as fixed-width Fortran columns write negative
values); ``1..2`` is refused.

Encodings
---------
UTF-8 (its byte-order mark skipped), Latin-1 for a line that is not UTF-8, and UTF-16 or
UTF-32 with a byte-order mark. A file holding NUL bytes otherwise is refused (binary, or
UTF-16 without a byte-order mark).

Units
-----
Accelerations in files are in ``g`` (9.80665 m/s^2, the standard gravity NGA uses),
``m/s2`` or ``cm/s2`` (gal); times in ``s``. An AT2 file is in g. A header line of columns
may state the units in brackets or parentheses (``time [s], a [g]``, ``t (sec)  acc
(cm/s^2)``; the spellings of :data:`UNIT_SPELLINGS`): a stated acceleration unit must be the
one given, and is used when none is given; a stated time unit must be seconds.
"""

from __future__ import annotations

import hashlib
import io
import math
import os
import re
import stat
from array import array
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .motion import irregular_step
from .params import RANGES, ParameterError, check_in_range
from .plausibility import check_record

#: Standard gravity, m/s^2: the ``g`` of records in units of g (PEER NGA).
STANDARD_GRAVITY = 9.80665
#: Accelerations a file may be in, and their value in m/s^2.
UNITS = {"g": STANDARD_GRAVITY, "m/s2": 1.0, "cm/s2": 0.01}
#: Largest file read, bytes (a 200 Hz record of an hour is about 10 MB of text).
MAX_BYTES = 100_000_000
#: Longest line read, characters (an AT2 line has 80, a row of columns a few dozen).
MAX_LINE = 10_000
#: Most samples in a record: over an hour at 1 kHz, 5 hours at 200 Hz (a record lasts at most
#: ``RANGES["record_length"]``, 11,000 s); 32 MB of floats.
MAX_SAMPLES = 4_000_000
#: The units a header of columns may state, as :func:`unit_spelling` writes them: the unit each is.
UNIT_SPELLINGS = {
    "g": "g", "gs": "g", "g's": "g",
    "m/s2": "m/s2", "m/s/s": "m/s2", "ms-2": "m/s2",
    "cm/s2": "cm/s2", "cm/s/s": "cm/s2", "cms-2": "cm/s2", "gal": "cm/s2", "gals": "cm/s2",
    "s": "s",
}  # fmt: skip

#: A number without its sign: the integer digits then an optional fraction, or a fraction alone; an exponent.
#: Each part is unambiguous: no input makes the regular expressions built on it backtrack at length.
_UNSIGNED = r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eEdD][-+]?\d+)?"
#: A number: decimal or scientific, in ASCII, Fortran's D exponents too (``-1.25``, ``.5``, ``2E-03``, ``1.0D-02``).
NUMBER = re.compile(rf"[-+]?{_UNSIGNED}", re.ASCII)
#: Numbers run together, each after the first starting with its sign ("-.12E-01-.34E-01").
_RUN = re.compile(rf"[-+]?{_UNSIGNED}(?:[-+]{_UNSIGNED})+", re.ASCII)
#: A number in a header (no D exponent).
_DECIMAL = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"
#: ``NPTS= 4000, DT= .0050 SEC`` and its variants (any order, "=" or ":" or spaces, a unit after DT).
_NPTS = re.compile(r"\bNPTS\s*[=:]?\s*(\d+)", re.IGNORECASE | re.ASCII)
_DT = re.compile(rf"\bDT\s*[=:]?\s*({_DECIMAL})", re.IGNORECASE | re.ASCII)
#: The older NGA header: "3000    0.0100    NPTS, DT".
_OLD = re.compile(rf"^\s*(\d+)\s+({_DECIMAL})\s+NPTS\s*,?\s*DT", re.IGNORECASE | re.ASCII)
#: A character of no number (E exponents) nor separator: see :func:`_plain`.
_NOT_NUMERIC = re.compile(r"[^0-9.eE+\-,;\s]", re.ASCII)
#: Cells of a row: one comma or semicolon (blanks around it allowed), or blanks.
_CELL_SEPARATOR = re.compile(r"\s*[,;]\s*|\s+", re.ASCII)
#: A unit stated in a header, in brackets or parentheses.
_STATED_UNIT = re.compile(r"[\[(]([^\[\]()]*)[\])]")
#: Byte-order marks, longest first (UTF-32 LE begins with UTF-16 LE's), and the codec that reads past each.
_BOMS = (
    (b"\xff\xfe\x00\x00", "utf-32"), (b"\x00\x00\xfe\xff", "utf-32"),
    (b"\xff\xfe", "utf-16"), (b"\xfe\xff", "utf-16"), (b"\xef\xbb\xbf", "utf-8-sig"),
)  # fmt: skip
#: Folders of the kernel's and the devices' files: nothing under them (links resolved) is an input file.
SYSTEM_FOLDERS = ("/proc", "/sys", "/dev")
_FILE_KINDS = (
    (stat.S_ISFIFO, "a named pipe"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
    (stat.S_ISDIR, "a directory"), (stat.S_ISSOCK, "a socket"),
)  # fmt: skip


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
    """The error of a reader: ``"<file>, line <n>: <text>"`` on one line (a name with line breaks is quoted)."""
    name = str(path)
    name = name if name.isprintable() else repr(name)
    return ParameterError(f"{name}, line {line}: {text}" if line is not None else f"{name}: {text}")


# --------------------------------------------------------------------------- #
# Opening a regular file and reading its lines, within the bounds              #
# --------------------------------------------------------------------------- #


def input_refusal(path) -> str | None:
    """Why ``path`` is not read as an input file, or None: it lies under one of :data:`SYSTEM_FOLDERS` once its
    symbolic links are resolved. The one check of every input file (records, saved studies, specs), each
    reader raising its own error with this text."""
    try:
        real = os.path.realpath(path)
    except (OSError, ValueError, TypeError):  # a NUL in the path, a loop: the reader's own error says so
        return None
    folder = next((f for f in SYSTEM_FOLDERS if real == f or real.startswith(f + os.sep)), None)
    if folder is None:
        return None
    via = f" ({real})" if real != os.path.abspath(path) else ""
    return (
        f"is a file of the kernel or a device{via}, under {folder}: not an input file "
        f"(nothing under {', '.join(SYSTEM_FOLDERS)} is read)"
    )


def _kind(mode: int) -> str:
    """What a file of ``mode`` is, for the message refusing it."""
    return next((kind for test, kind in _FILE_KINDS if test(mode)), "not a regular file")


def _regular(path, status: os.stat_result) -> None:
    """Refuse what is not a regular file of at most :data:`MAX_BYTES` bytes, naming what it is instead."""
    if not stat.S_ISREG(status.st_mode):
        target = os.path.realpath(path)
        via = f" ({target})" if target != os.path.abspath(path) else ""
        raise _fail(path, f"is {_kind(status.st_mode)}{via}, not a regular file: only regular files are read")
    if status.st_size > MAX_BYTES:
        raise _fail(path, f"holds {status.st_size} bytes, more than the {MAX_BYTES} a record file may have (MAX_BYTES)")


def _encoding(raw: io.BufferedReader) -> str:
    """The codec of a file from its byte-order mark (UTF-8, where it has none); the codec skips the mark."""
    start = raw.peek(4)[:4]
    return next((codec for bom, codec in _BOMS if start.startswith(bom)), "utf-8")


@contextmanager
def _opened_bytes(path) -> Iterator[io.BufferedReader]:
    """The bytes of the regular file ``path``; refused if it is not one.

    The file is checked before it is opened, so that a device is never opened and a pipe never waited on, and
    again once open (without blocking), in case it was replaced meanwhile.
    """
    try:
        path = os.fspath(path)
    except TypeError:
        raise ParameterError(f"a record file must be a path (got {type(path).__name__})") from None
    try:
        status = os.stat(path)
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the path
        raise _read_failure(path, exc) from None
    _regular(path, status)
    refused = input_refusal(path)
    if refused:
        raise _fail(path, refused)
    try:  # without blocking: a named pipe put in the file's place since os.stat must not wait for a writer
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except OSError as exc:
        raise _read_failure(path, exc) from None
    with open(fd, "rb") as raw:
        _regular(path, os.fstat(fd))
        yield raw


@contextmanager
def _opened(path) -> Iterator[io.TextIOWrapper]:
    """The text of the regular file ``path`` (:func:`_opened_bytes`), decoded (:func:`_encoding`)."""
    with _opened_bytes(path) as raw:
        codec = _encoding(raw)
        # Not UTF-8: kept as escapes, and the line read again as Latin-1 (_decoded); UTF-16/32 errors: U+FFFD.
        errors = "surrogateescape" if codec.startswith("utf-8") else "replace"
        with io.TextIOWrapper(raw, encoding=codec, errors=errors, newline=None) as text:
            yield text


def file_sha256(path) -> str:
    """The SHA-256 of a record file, read as the readers read it: a regular file (else refused, unopened),
    in chunks, at most :data:`MAX_BYTES` bytes.

    Raises
    ------
    ParameterError
        Naming the file: not a regular file, unreadable, larger than :data:`MAX_BYTES`.
    """
    digest, total = hashlib.sha256(), 0
    try:
        with _opened_bytes(path) as raw:
            for chunk in iter(lambda: raw.read(1 << 20), b""):
                total += len(chunk)
                if total > MAX_BYTES:  # grown since its size was checked
                    raise _fail(path, f"more than the {MAX_BYTES} bytes a record file may have (MAX_BYTES)")
                digest.update(chunk)
    except OSError as exc:
        raise _read_failure(path, exc) from None
    return digest.hexdigest()


def _decoded(line: str) -> str:
    """``line`` as Latin-1 if it was not UTF-8 (its undecodable bytes kept as surrogate escapes)."""
    if line.isascii():
        return line
    try:
        line.encode("utf-8")
    except UnicodeEncodeError:
        return line.encode("utf-8", "surrogateescape").decode("latin-1")
    return line


def _lines(path, text: io.TextIOWrapper) -> Iterator[tuple[int, str]]:
    """``(number, line)`` of the file's lines, 1-based, without line breaks; within :data:`MAX_LINE` and
    :data:`MAX_BYTES` (counted in characters, each at least a byte: it bounds a file growing as it is read)."""
    total = 0
    for number, line in enumerate(iter(lambda: text.readline(MAX_LINE + 1), ""), start=1):
        total += len(line)
        if len(line) > MAX_LINE and not line.endswith("\n"):
            raise _fail(path, f"longer than the {MAX_LINE} characters a line may have (MAX_LINE)", number)
        if total > MAX_BYTES:
            raise _fail(path, f"more than the {MAX_BYTES} bytes a record file may have (MAX_BYTES)", number)
        if "\0" in line:
            raise _fail(
                path, "holds NUL bytes: not a text file (UTF-16 without a byte-order mark? save it as UTF-8)", number
            )
        yield number, _decoded(line.rstrip("\n"))


def _read_failure(path, exc: OSError | ValueError) -> ParameterError:
    """The error of a file that cannot be opened or read, with the system's reason."""
    return _fail(path, f"cannot be read ({getattr(exc, 'strerror', None) or exc})")


# --------------------------------------------------------------------------- #
# Values and the checks every record passes                                    #
# --------------------------------------------------------------------------- #


def _shown(text: str) -> str:
    """A piece of a file quoted in a message: at most 40 characters, escaped."""
    return repr(text[:40])


def _number(text: str) -> float:
    """The value of a :data:`NUMBER`."""
    return float(text.replace("d", "e").replace("D", "E"))


def _plain(line: str, tokens: list[str]) -> list[float] | None:
    """The values of ``tokens``, the pieces of ``line`` between separators, if each is a :data:`NUMBER` with an
    E exponent; None if not (or maybe not). The common case at once: from the characters of numbers and
    separators, ``float`` takes exactly those numbers (tests/test_records.py checks it)."""
    if _NOT_NUMERIC.search(line):
        return None
    try:
        return list(map(float, tokens))
    except ValueError:
        return None


def _at2_line(path, line: str, number: int) -> tuple[list[str], list[float]]:
    """The numbers of one line of an AT2 file's values, as written and as values; anything else is refused."""
    tokens = line.replace(",", " ").split()
    values = _plain(line, tokens)
    if values is not None:
        return tokens, values
    texts = []
    for token in tokens:
        if NUMBER.fullmatch(token):
            texts.append(token)
        elif _RUN.fullmatch(token):
            texts.extend(NUMBER.findall(token))
        else:
            raise _fail(path, f"not a number: {_shown(token)}", number)
    return texts, [_number(t) for t in texts]


def _acceleration(path, texts: list[str], values: list[float], scale: float, unit: str, number: int) -> list[float]:
    """``values``, accelerations written ``texts`` in ``unit`` (``scale`` m/s^2), if each is finite and within
    ``RANGES["a_g"]``."""
    if not values or max(map(abs, values)) * scale <= RANGES["a_g"].high:
        return values
    for text, value in zip(texts, values):
        if not abs(value) * scale <= RANGES["a_g"].high:  # also inf: "1e999" is a number that overflows
            raise _fail(
                path,
                f"the acceleration {_shown(text)} {unit} is beyond {RANGES['a_g'].high:g} m/s^2 "
                f"in magnitude: {RANGES['a_g'].why}",
                number,
            )
    return values


def _checked_step(path, name: str, dt: object, line: int | None) -> float:
    """``dt`` if it lies in ``RANGES["pulse_dt"]`` (that of :class:`rocking.SampledMotion`), else the error
    naming the file and ``line``."""
    try:
        return check_in_range(name, dt, "pulse_dt")
    except ParameterError as exc:
        raise _fail(path, str(exc), line) from None


def _checked_length(path, n: int, dt: float, line: int | None) -> None:
    """Refuse a record of ``n`` samples at ``dt`` lasting longer than ``RANGES["record_length"]``."""
    longest = RANGES["record_length"].high
    if (n - 1) * dt > longest:
        raise _fail(
            path,
            f"the record lasts {(n - 1) * dt:g} s ({n} samples at dt = {dt:g} s): at most {longest:g} s",
            line,
        )


def _too_many(path, n: object, line: int | None) -> ParameterError:
    """The error of a record of more than :data:`MAX_SAMPLES` samples (``n``: how many, or what says so)."""
    return _fail(path, f"more than the {MAX_SAMPLES} samples a record may have (MAX_SAMPLES; got {n})", line)


# --------------------------------------------------------------------------- #
# PEER NGA .AT2                                                                #
# --------------------------------------------------------------------------- #


def _at2_header(path, lines: list[str]) -> tuple[int, float]:
    """``(npts, dt)`` of an AT2 header: the units (g) on line 3, NPTS and DT on line 4, within the bounds."""
    if len(lines) < 4:
        raise _fail(path, f"an AT2 file has 4 header lines; this one has {len(lines)} line(s)")
    units = lines[2].upper()
    if "UNITS OF G" not in units and not re.search(r"\bIN\s+G\b", units):
        raise _fail(path, f'line 3 must give the units ("... IN UNITS OF G"): got {_shown(lines[2].strip())}', 3)
    old = _OLD.match(lines[3])
    npts, dt = (old.group(1), old.group(2)) if old else (_match(_NPTS, lines[3]), _match(_DT, lines[3]))
    if npts is None or dt is None:
        got = _shown(lines[3].strip())
        raise _fail(path, f'line 4 must give NPTS and DT ("NPTS= 4000, DT= .0050 SEC"): got {got}', 4)
    if len(npts) > len(str(MAX_SAMPLES)) or int(npts) > MAX_SAMPLES:  # int() of thousands of digits is refused
        raise _too_many(path, f"NPTS = {npts[:20]}", 4)
    npts = int(npts)
    if npts < 2:
        raise _fail(path, f"NPTS must be >= 2 (got {npts})", 4)
    dt = _checked_step(path, "DT", float(dt), 4)
    _checked_length(path, npts, dt, 4)
    return npts, dt


def _match(pattern: re.Pattern, line: str) -> str | None:
    """The first group of ``pattern`` in ``line``, or None."""
    m = pattern.search(line)
    return m.group(1) if m else None


def _at2_body(path, lines: Iterator[tuple[int, str]], npts: int) -> np.ndarray:
    """The ``npts`` values after the header, m/s^2; reading stops at the first value beyond ``npts``."""
    values = array("d")
    for number, line in lines:
        values.extend(_acceleration(path, *_at2_line(path, line, number), STANDARD_GRAVITY, "g", number))
        if len(values) > npts:
            raise _fail(
                path,
                f"the header declares NPTS = {npts} but the file holds more values ({len(values)} by this line)",
                number,
            )
    if len(values) != npts:
        raise _fail(
            path, f"the header declares NPTS = {npts} but the file holds {len(values)} values (truncated or damaged?)"
        )
    return np.frombuffer(values, float) * STANDARD_GRAVITY


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
        Naming the file (and the line): not a regular file, unreadable, past a bound (:data:`MAX_BYTES`,
        :data:`MAX_LINE`, :data:`MAX_SAMPLES`), a header that is missing or malformed, a DT out of
        ``RANGES["pulse_dt"]``, a record longer than ``RANGES["record_length"]``, a count of values other than NPTS,
        a value that is not a plain finite number (:data:`NUMBER`) or an acceleration beyond ``RANGES["a_g"]``.
    """
    try:
        with _opened(path) as text:
            lines = _lines(path, text)
            npts, dt = _at2_header(path, [line for _, (_, line) in zip(range(4), lines)])
            acceleration = _at2_body(path, lines, npts)
    except OSError as exc:
        raise _read_failure(path, exc) from None
    return _plausible(Record(acceleration, dt, str(path)), "g")


# --------------------------------------------------------------------------- #
# Columns: text or CSV                                                         #
# --------------------------------------------------------------------------- #


def unit_spelling(text: str) -> str:
    """``text`` as :data:`UNIT_SPELLINGS` spells units: lower case, without blanks, ``^``, ``*``, ``.`` and
    ``·``, ``²`` and ``⁻`` as ``2`` and ``-``, ``sec``/``second(s)`` as ``s`` (``m/sec^2`` -> ``m/s2``)."""
    text = text.lower().replace("²", "2").replace("⁻", "-")
    text = re.sub(r"[\s^*.·]", "", text)
    return re.sub(r"sec(?:ond)?s?", "s", text)


def _stated_unit(path, line: str, number: int) -> str | None:
    """The acceleration unit a header line states in brackets or parentheses (None: it states none).

    Every stated unit must be known (:data:`UNIT_SPELLINGS`), a time unit must be seconds, and the
    accelerations must have one unit.
    """
    units = set()
    for stated in _STATED_UNIT.findall(line):
        unit = UNIT_SPELLINGS.get(unit_spelling(stated))
        if unit is None:
            raise _fail(
                path,
                f"the header states the unit {_shown(stated.strip())}, which is none of "
                f"{', '.join(UNITS)} (accelerations: also m/s^2, cm/s^2, gal) or s (times)",
                number,
            )
        if unit != "s":
            units.add(unit)
    if len(units) > 1:
        raise _fail(path, f"the header states accelerations in {' and '.join(sorted(units))}: one unit only", number)
    return units.pop() if units else None


def _agreed_unit(path, given: str | None, stated: str | None, number: int | None) -> str:
    """The unit of the accelerations: the given one, which the header's must match, or the header's."""
    if given is not None and stated is not None and given != stated:
        raise _fail(
            path,
            f"the header states accelerations in {stated} but the unit given is {given}: correct one of them",
            number,
        )
    unit = given if given is not None else stated
    if unit is None:
        raise _fail(
            path,
            f"give the unit of the accelerations ({', '.join(UNITS)}): the file does not state it "
            "(a header such as 'time [s], a [g]' would)",
        )
    return unit


def _is_header(cells: list[str]) -> bool:
    """A line of column names: no cell that Python's float takes (so that '1_000' or 'nan' are refused as
    values, not skipped as names)."""
    for cell in cells:
        try:
            float(cell)
        except ValueError:
            continue
        return False
    return True


#: A number written with a decimal comma ("0,01").
_DECIMAL_COMMA = re.compile(r"[-+]?\d+,\d+", re.ASCII)


def _decimal_comma(text: str, count: int) -> str:
    """Why a row of ``count`` columns split into twice as many: ``": decimal commas are not read ..."``, or nothing.

    A row without a point whose commas stand between digits, in twice the cells expected ("0,01;0,5" or
    "0,01,0,5" for two columns), is written with decimal commas: each comma cut a number in two.
    """
    first = _DECIMAL_COMMA.search(text)
    if first is None or "." in text or len(_CELL_SEPARATOR.split(text)) != 2 * count:
        return ""
    return f": decimal commas are not read: use a point ({first.group().replace(',', '.')}, not {first.group()})"


def _row(path, text: str, number: int, count: int) -> tuple[list[str], list[float]]:
    """The ``count`` cells of a row, as written and as values; refused unless each is a :data:`NUMBER`."""
    cells = _CELL_SEPARATOR.split(text)
    if len(cells) != count:
        raise _fail(path, f"expected {count} column(s), got {len(cells)}{_decimal_comma(text, count)}", number)
    values = _plain(text, cells)
    if values is not None:
        return cells, values
    for cell in cells:
        if not NUMBER.fullmatch(cell):
            raise _fail(path, f"not a number: {_shown(cell) if cell else 'an empty cell'}", number)
    return cells, [_number(c) for c in cells]


def _column_rows(path, lines, unit: str | None, time_column: bool) -> tuple[array, array, array, str | None]:
    """The times, the accelerations (in their unit) and the line numbers of a file's rows, and the unit of its
    accelerations (None only if it has no rows).

    Blank lines and lines starting with ``#`` are skipped, and the first other line if it names the columns.
    """
    times, accelerations, where = array("d"), array("d"), array("q")
    stated, header_line = None, None
    for number, line in lines:
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        if not where and header_line is None and _is_header(_CELL_SEPARATOR.split(text)):
            stated, header_line = _stated_unit(path, text, number), number
            continue
        if not where:  # the first row: the unit is settled before any value is read
            unit = _agreed_unit(path, unit, stated, header_line)
        assert unit is not None  # agreed at the first row
        cells, values = _row(path, text, number, 2 if time_column else 1)
        accelerations.extend(_acceleration(path, cells[-1:], values[-1:], UNITS[unit], unit, number))
        if time_column:
            times.append(_finite_time(path, cells[0], values[0], number))
        where.append(number)
        if len(where) > MAX_SAMPLES:
            raise _too_many(path, len(where), number)
    return times, accelerations, where, unit


#: The start of a line that may be a row (or the header): neither blank nor a comment.
_ROW_START = re.compile(r"^[^\S\n]*[^\s#]", re.MULTILINE)
#: Fewest bytes of a row (a value and its line break): a smaller file cannot hold too many rows.
MIN_ROW_BYTES = 2


def _count_rows(path, text: io.TextIOWrapper, chunk: int = 1 << 22) -> int:
    """The lines of ``text`` that are neither blank nor comments (the rows, and a header line), counted by a
    regular expression over chunks of the text, without parsing any: what a file's size allows is checked before
    the rows are read, as an AT2 header's NPTS is."""
    count, carried = 0, ""
    for block in iter(lambda: text.read(chunk), ""):
        block = carried + block
        cut = block.rfind("\n") + 1  # the last line may go on in the next chunk
        count += len(_ROW_START.findall(block, 0, cut))
        carried = block[cut:]
        if len(carried) > MAX_LINE:
            raise _fail(path, f"holds a line longer than the {MAX_LINE} characters a line may have (MAX_LINE)")
    return count + len(_ROW_START.findall(carried))


def _check_row_count(path, size: int) -> None:
    """Refuse a file of columns of more than :data:`MAX_SAMPLES` rows (and a header) before parsing any: counted
    (:func:`_count_rows`) if its ``size`` in bytes could hold that many."""
    if size <= MIN_ROW_BYTES * (MAX_SAMPLES + 1):
        return
    with _opened(path) as text:
        rows = _count_rows(path, text)
    if rows > MAX_SAMPLES + 1:
        raise _too_many(path, f"{rows} lines neither blank nor comments, counted before any was parsed", None)


def _finite_time(path, text: str, value: float, number: int) -> float:
    """``value``, the time written ``text``, if it is finite (``1e999`` is a number that overflows)."""
    if not math.isfinite(value):
        raise _fail(path, f"the time {_shown(text)} s is not finite", number)
    return value


def read_columns(path, unit: str | None = None, *, dt: float | None = None, time_column: bool = True) -> Record:
    """A record in plain text or CSV: one row per sample, ``time, acceleration`` or the acceleration alone.

    Separators: a comma or a semicolon (with blanks around it or not), or tabs and spaces. Lines starting
    with ``#`` and blank lines are skipped, and a first line of column names, which may state the units
    in brackets or parentheses (``time [s], a [cm/s2]``).

    Parameters
    ----------
    path : path
        The file (a regular file).
    unit : {"g", "m/s2", "cm/s2"}, optional
        The unit of the accelerations. Required unless the header states it; if both do, they must agree.
    dt : float, optional
        The time step, s, when the file holds the accelerations alone (``time_column=False``).
    time_column : bool
        Whether the first column holds the times, s (uniformly spaced from any start; the record starts
        at ``t = 0``).

    Raises
    ------
    ParameterError
        Naming the file (and the line): not a regular file, unreadable, past a bound (:data:`MAX_BYTES`,
        :data:`MAX_LINE`, :data:`MAX_SAMPLES`), a unit missing, unknown or contradicting the header, a row of
        the wrong number of columns, a value that is not a plain finite number (:data:`NUMBER`), an
        acceleration beyond ``RANGES["a_g"]``, times that are not uniformly spaced, a step out of
        ``RANGES["pulse_dt"]``, fewer than 2 rows, a record longer than ``RANGES["record_length"]``.
    """
    if unit is not None and unit not in UNITS:
        raise _fail(path, f"unit must be one of {', '.join(UNITS)} (got {unit!r})")
    if time_column == (dt is not None):
        raise _fail(path, "give dt (s) for a file of accelerations alone, or time_column=True, not both")
    if dt is not None:
        dt = _checked_step(path, "dt", dt, None)
    try:
        with _opened(path) as text:
            _check_row_count(path, os.fstat(text.fileno()).st_size)
        with _opened(path) as text:
            times, accelerations, where, unit = _column_rows(path, _lines(path, text), unit, time_column)
    except OSError as exc:
        raise _read_failure(path, exc) from None
    if len(where) < 2:
        raise _fail(path, f"a record needs at least 2 samples (got {len(where)})")
    if time_column:
        dt = _checked_step(path, "the time step", uniform_step(np.frombuffer(times), path, where), where[-1])
    assert dt is not None and unit is not None  # dt given or read from the times; unit agreed at the first row
    _checked_length(path, len(where), dt, where[-1])
    return _plausible(Record(np.frombuffer(accelerations) * UNITS[unit], float(dt), str(path)), unit)


def _plausible(record: Record, unit: str) -> Record:
    """``record``, read in ``unit``, after the plausibility warnings of its peak and its step."""
    pga_g = float(np.max(np.abs(record.acceleration))) / STANDARD_GRAVITY
    check_record(pga_g, record.dt, unit, record.name)
    return record


def uniform_step(t, path="times", lines=None) -> float:
    """The step of uniformly spaced times ``t`` (:func:`rocking.model.motion.irregular_step`), else a one-line
    error naming the first irregular step (and its line of ``path``)."""
    with np.errstate(over="ignore", invalid="ignore"):  # times far apart: an infinite step, refused below
        dt, k = irregular_step(t)
    if not dt > 0:
        raise _fail(path, f"times must increase (mean step {dt!r} s)", None if lines is None else lines[-1])
    if k is not None:
        step = float(t[k + 1] - t[k])
        raise _fail(
            path,
            f"times must be uniformly spaced: step {step:.6g} s where the others are "
            f"{float(np.median(np.diff(t))):.6g} s",
            None if lines is None else lines[k + 1],
        )
    return dt


def read_record(path, unit: str | None = None, **kwargs) -> Record:
    """A record by its file's extension: ``.AT2`` (in g), else columns (``unit``, or the one their header states)."""
    try:
        suffix = Path(path).suffix.upper()
    except TypeError:
        raise ParameterError(f"a record file must be a path (got {type(path).__name__})") from None
    if suffix == ".AT2":
        if unit not in (None, "g"):
            raise _fail(path, f"an AT2 file is in g; unit {unit!r} does not apply")
        return read_at2(path)
    return read_columns(path, unit, **kwargs)


def paired_vertical(record: Record, vertical: Record, label: str) -> np.ndarray:
    """The samples of the ``vertical`` record at the times of the horizontal ``record``: the same dt is required;
    a shorter vertical record is taken as 0 after its end, a longer one is cut at the horizontal record's.

    Raises
    ------
    ParameterError
        ``label`` (the option and the vertical file) first, if the two records' dt differ.
    """
    if not math.isclose(vertical.dt, record.dt, rel_tol=1e-9):
        raise ParameterError(
            f"{label}: dt = {vertical.dt:g} s, the horizontal record's is {record.dt:g} s; the pair must share its dt"
        )
    n = record.acceleration.size
    return np.concatenate((vertical.acceleration[:n], np.zeros(max(0, n - vertical.acceleration.size))))
