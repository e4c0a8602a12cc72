"""Recorded accelerograms from files: PEER NGA .AT2 (with the header variants found in the wild) and columns."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from rocking.model.params import ParameterError
from rocking.model.records import STANDARD_GRAVITY, read_at2, read_columns, read_record, uniform_step

VALUES = np.array([0.0063010, 0.0063250, -0.0012345, -0.0234567, 0.5, -0.25, 1.0e-5, 0.0])

#: The header of an NGA-West2 record, and older or hand-edited variants of its line 4.
WEST2 = [
    "PEER NGA STRONG MOTION DATABASE RECORD",
    "Imperial Valley 1940-05-19 04:37 El Centro Array #9 180",
    "ACCELERATION TIME SERIES IN UNITS OF G",
]
LINE4 = [
    "NPTS=    8, DT=   .0100 SEC",
    "NPTS=8 DT=0.01",
    "NPTS = 8, DT = 0.0100 SEC,",
    "   8    0.0100    NPTS, DT",
    "DT= .0100 SEC, NPTS=     8",
]


def _write(path, header: list[str], body: str) -> str:
    path.write_text("\n".join(header) + "\n" + body)
    return str(path)


def _body(values, per_line=5, fmt="{:15.7E}") -> str:
    lines = [values[i : i + per_line] for i in range(0, len(values), per_line)]
    return "\n".join("".join(fmt.format(v) for v in line) for line in lines) + "\n"


@pytest.mark.parametrize("line4", LINE4)
def test_at2_header_variants_are_read(tmp_path, line4):
    record = read_at2(_write(tmp_path / "r.AT2", [*WEST2, line4], _body(VALUES)))
    assert record.dt == 0.01 and record.duration == pytest.approx(0.07)
    np.testing.assert_allclose(record.acceleration, VALUES * STANDARD_GRAVITY, rtol=1e-7)


def test_at2_values_written_without_separators_or_with_fortran_d_exponents(tmp_path):
    """Negative values in fixed columns run together ("-.1234E-01-.2345E-01"); some tools write D exponents."""
    body = "-.1234567E-01-.2345678E-01 .5000000E+00\n .1000000D-04-.2500000D+00 .0000000D+00 .1D+00 .2\n"
    record = read_at2(_write(tmp_path / "r.AT2", [*WEST2, "NPTS=8, DT=.005 SEC"], body))
    np.testing.assert_allclose(
        record.acceleration / STANDARD_GRAVITY, [-0.01234567, -0.02345678, 0.5, 1e-5, -0.25, 0.0, 0.1, 0.2]
    )


@pytest.mark.parametrize(
    ("header", "body", "message"),
    [
        ([*WEST2, "NPTS=    9, DT=   .0100 SEC"], _body(VALUES), r"declares NPTS = 9 but the file holds 8 values"),
        ([*WEST2, "NPTS=    8, DT=   .0100 SEC"], _body(VALUES[:7]), r"NPTS = 8 but the file holds 7 values"),
        ([*WEST2, "NPTS=    8"], _body(VALUES), r"line 4: line 4 must give NPTS and DT"),
        ([*WEST2, "NPTS=    8, DT= 0 SEC"], _body(VALUES), r"line 4: DT must be in \[1e-06, 10\] s \(got 0.0\)"),
        ([WEST2[0], WEST2[1], "VELOCITY TIME SERIES IN UNITS OF CM/S", "NPTS=8, DT=.01"], _body(VALUES),
         r"line 3: line 3 must give the units"),
        ([*WEST2, "NPTS=8, DT=.01"], _body(VALUES).replace("5.0000000E-01", "NaN"), r"line 5: not a number: 'NaN'"),
        ([*WEST2, "NPTS=8, DT=.01"], _body(VALUES) + "1e999\n", r"line 7: the acceleration '1e999' g is beyond"),
        (WEST2[:2], "", r"an AT2 file has 4 header lines"),
    ],
)  # fmt: skip
def test_bad_at2_files_are_refused_naming_the_file_and_line(tmp_path, header, body, message):
    path = _write(tmp_path / "bad.AT2", header, body)
    with pytest.raises(ParameterError, match=message) as info:
        read_at2(path)
    assert str(info.value).startswith(path) and "\n" not in str(info.value)


def test_unreadable_and_binary_files_are_refused(tmp_path):
    with pytest.raises(ParameterError, match=r"missing.AT2: cannot be read"):
        read_at2(tmp_path / "missing.AT2")
    binary = tmp_path / "b.AT2"
    binary.write_bytes(b"\x00\x01\x02" * 10)
    with pytest.raises(ParameterError, match=r"b.AT2, line 1: holds NUL bytes: not a text file"):
        read_at2(binary)


def test_columns_with_times_or_alone_in_any_unit(tmp_path):
    csv = tmp_path / "r.csv"
    csv.write_text("# a comment\ntime_s,acc_g\n" + "".join(f"{1.5 + 0.02 * i},{v}\n" for i, v in enumerate(VALUES)))
    record = read_columns(csv, "g")
    assert record.dt == pytest.approx(0.02)
    np.testing.assert_allclose(record.acceleration, VALUES * STANDARD_GRAVITY)
    txt = tmp_path / "r.txt"
    txt.write_text("".join(f"  {v * 981.0}\n" for v in VALUES))
    alone = read_columns(txt, "cm/s2", dt=0.01, time_column=False)
    np.testing.assert_allclose(alone.acceleration, VALUES * 9.81)
    assert read_record(txt, "m/s2", dt=0.01, time_column=False).dt == 0.01


@pytest.mark.parametrize(
    ("text", "kwargs", "message"),
    [
        (
            "t,a\n0,1\n0.01,2\n0.02,3\n0.04,4\n0.05,5\n",
            {"unit": "g"},
            r"line 5: times must be uniformly spaced: step 0.02 s where the others are 0.01 s",
        ),
        ("0,1\n0.01,nan\n", {"unit": "g"}, r"line 2: not a number: 'nan'"),
        ("0,1\n0.01,2,3\n", {"unit": "g"}, r"line 2: expected 2 column\(s\), got 3"),
        ("0,1\n", {"unit": "g"}, r"needs at least 2 samples"),
        ("0,1\n0.01,2\n", {"unit": "gal"}, r"unit must be one of g, m/s2, cm/s2 \(got 'gal'\)"),
        ("0,1\n0.01,2\n", {"unit": None}, r"give the unit of the accelerations"),
        ("1\n2\n", {"unit": "g", "time_column": False, "dt": -0.1}, r"bad.csv: dt must be in \[1e-06, 10\] s"),
        ("0,1\n0.01,x2\n", {"unit": "g"}, r"line 2: not a number"),
    ],
)
def test_bad_column_files_are_refused_in_one_line(tmp_path, text, kwargs, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ParameterError, match=message):
        read_record(path, **kwargs)


def test_uniform_step_names_the_first_irregular_step():
    assert uniform_step([0.0, 0.005, 0.01, 0.015]) == pytest.approx(0.005)
    # Times written in single precision (0.00499999989, ..., 39.9949989) are a uniform record; a missing sample
    # among them is not.
    single = np.arange(8000, dtype=np.float32) * np.float32(0.005)
    assert uniform_step(single.astype(float)) == pytest.approx(0.005, rel=1e-6)
    with pytest.raises(ParameterError, match="uniformly spaced"):
        uniform_step(np.delete(single, 4000).astype(float))
    with pytest.raises(ParameterError, match=r"^times: times must increase"):
        uniform_step([0.0, 0.0, 0.0])


# --- issue 23: special files, bounds on what is read, strict numbers, units in headers, encodings ------------

import os  # noqa: E402
import threading  # noqa: E402

from hypothesis import HealthCheck, event, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from rocking import SampledMotion  # noqa: E402
from rocking.model import records  # noqa: E402

AT2_HEADER = [*WEST2, "NPTS=    8, DT=   .0100 SEC"]
CSV = "time [s],a [g]\n" + "".join(f"{0.01 * i:.2f},{v}\n" for i, v in enumerate(VALUES))


def _refused(read, path, message):
    """``read(path)`` refuses the file in one line that starts with its name and matches ``message``."""
    with pytest.raises(ParameterError, match=message) as info:
        read(path)
    text = str(info.value)
    assert text.startswith(str(path)) and "\n" not in text, text
    return text


def _within(seconds, read, path) -> dict:
    """``{"result": read(path)}`` or ``{"error": exception}``, ``read`` run in a thread that must finish within
    ``seconds``: a read that blocks (a named pipe opened for reading waits for a writer) fails the test instead
    of hanging the suite."""
    outcome = {}

    def target():
        try:
            outcome["result"] = read(path)
        except Exception as exc:  # handed to the test, which checks its class
            outcome["error"] = exc

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(seconds)
    if thread.is_alive():
        os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))  # a writer releases the blocked reader
        pytest.fail(f"reading {path} blocked for {seconds} s")
    return outcome


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
@pytest.mark.parametrize("name", ["pipe.AT2", "pipe.csv"])
def test_a_named_pipe_is_refused_without_blocking(tmp_path, name):
    fifo = tmp_path / name
    os.mkfifo(fifo)
    link = tmp_path / f"link-{name}"
    link.symlink_to(fifo)
    for path in (fifo, link):
        error = _within(10.0, lambda p: read_record(p, "g" if name.endswith("csv") else None), path).get("error")
        assert isinstance(error, ParameterError), error
        assert str(error).startswith(str(path)) and "is a named pipe" in str(error), error


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
def test_a_named_pipe_put_in_place_after_the_check_is_refused_without_blocking(tmp_path, monkeypatch):
    """The race: os.stat saw a regular file, and a pipe is opened. Opened without blocking, it is refused from
    its fstat."""
    fifo, regular = tmp_path / "swapped.AT2", tmp_path / "regular.AT2"
    os.mkfifo(fifo)
    regular.write_text("x")
    real_stat = os.stat
    monkeypatch.setattr(os, "stat", lambda p, *a, **k: real_stat(regular if str(p) == str(fifo) else p, *a, **k))
    error = _within(10.0, read_at2, fifo).get("error")
    assert isinstance(error, ParameterError) and str(error) == (
        f"{fifo}: is a named pipe, not a regular file: only regular files are read"
    )


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
def test_cli_simulate_refuses_a_named_pipe_as_motion(tmp_path, capsys):
    from rocking.cli.main import main

    fifo = tmp_path / "m.AT2"
    os.mkfifo(fifo)
    assert _within(10.0, lambda p: main(["simulate", "--motion", str(p)]), fifo) == {"result": 2}
    assert f"rocking simulate: error: {fifo}: is a named pipe, not a regular file" in capsys.readouterr().err


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_a_link_to_a_device_is_refused_before_it_is_read(tmp_path, device):
    if not os.path.exists(device):
        pytest.skip(f"no {device}")
    for name, read in (("r.AT2", read_at2), ("r.csv", lambda p: read_columns(p, "g"))):
        link = tmp_path / name
        link.symlink_to(device)
        _refused(read, link, rf"r\.(AT2|csv): is a character device \({device}\), not a regular file")


def test_a_directory_or_a_path_that_is_not_one_is_refused(tmp_path):
    _refused(read_at2, tmp_path, r": is a directory, not a regular file")
    with pytest.raises(ParameterError, match=r"^a record file must be a path \(got int\)$"):
        read_record(3)
    odd = str(tmp_path / "a\nb.AT2")
    with pytest.raises(ParameterError, match=r"b.AT2': cannot be read") as info:
        read_at2(odd)
    assert str(info.value).startswith(repr(odd)) and "\n" not in str(info.value)  # a name with a line break, quoted


def test_a_file_larger_than_max_bytes_is_refused_from_its_size(tmp_path, monkeypatch):
    path = _write(tmp_path / "big.AT2", AT2_HEADER, _body(VALUES))
    monkeypatch.setattr(records, "MAX_BYTES", 100)
    _refused(read_at2, path, r"big.AT2: holds \d+ bytes, more than the 100 a record file may have \(MAX_BYTES\)$")


def test_a_line_longer_than_max_line_is_refused_at_that_line(tmp_path, monkeypatch):
    monkeypatch.setattr(records, "MAX_LINE", 120)
    one_line = _write(tmp_path / "one.AT2", AT2_HEADER, " ".join(f"{v:.7E}" for v in VALUES) * 3)
    _refused(read_at2, one_line, r"one.AT2, line 5: longer than the 120 characters a line may have \(MAX_LINE\)$")


def test_a_record_of_more_than_max_samples_is_refused_early(tmp_path, monkeypatch):
    monkeypatch.setattr(records, "MAX_SAMPLES", 6)
    path = _write(tmp_path / "many.AT2", AT2_HEADER, _body(VALUES))
    _refused(
        read_at2,
        path,
        r"many.AT2, line 4: more than the 6 samples a record may have \(MAX_SAMPLES; "
        r"got NPTS = 8\)$",
    )
    rows = tmp_path / "many.csv"
    rows.write_text(CSV + "garbage that is never read\n")
    # Counted before any row is parsed (issue 36): the line the parser would stop at is never reached.
    _refused(
        lambda p: read_columns(p, "g"),
        rows,
        r"many.csv: more than the 6 samples a record may have \(MAX_SAMPLES; got 10 lines neither blank nor comments, "
        r"counted before any was parsed\)$",
    )


def test_an_at2_file_is_read_no_further_than_its_npts(tmp_path):
    """More values than NPTS: refused at the line holding the first value beyond, before the rest is read (here
    a line that would be refused otherwise, and a line longer than any allowed)."""
    body = _body(VALUES) + _body(VALUES) + "not numbers\n" + "1 " * records.MAX_LINE
    path = _write(tmp_path / "long.AT2", AT2_HEADER, body)
    _refused(
        read_at2,
        path,
        r"long.AT2, line 7: the header declares NPTS = 8 but the file holds more values "
        r"\(13 by this line\)$",
    )


@pytest.mark.parametrize(
    ("line4", "message"),
    [
        ("NPTS=    8, DT= 1e300 SEC", r"line 4: DT must be in \[1e-06, 10\] s \(got 1e\+300\)"),
        ("NPTS=    8, DT= 1e-9 SEC", r"line 4: DT must be in \[1e-06, 10\] s \(got 1e-09\)"),
        ("NPTS=    1, DT= .01 SEC", r"line 4: NPTS must be >= 2 \(got 1\)"),
        ("NPTS= 3000000, DT= 0.01 SEC", r"line 4: the record lasts 30000 s \(3000000 samples at dt = 0.01 s\): "
                                        r"at most 11000 s"),
        ("NPTS= " + "9" * 5000 + ", DT= .01", r"line 4: more than the 4000000 samples .*got NPTS = 9{20}\)$"),
    ],
)  # fmt: skip
def test_an_at2_header_out_of_range_is_refused_at_line_4(tmp_path, line4, message):
    _refused(read_at2, _write(tmp_path / "h.AT2", [*WEST2, line4], _body(VALUES)), message)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("1..2", r"line 5: not a number: '1..2'"),
        ("1.2.3", r"line 5: not a number: '1.2.3'"),
        ("1_000", r"line 5: not a number: '1_000'"),
        ("inf", r"line 5: not a number: 'inf'"),
        ("-Infinity", r"line 5: not a number: '-Infinity'"),
        ("0x10", r"line 5: not a number: '0x10'"),
        ("\u0661", r"line 5: not a number: '\u0661'"),  # ARABIC-INDIC DIGIT ONE, which float takes
        ("1e", r"line 5: not a number: '1e'"),
        ("1.0E-02+", r"line 5: not a number: '1.0E-02\+'"),
        ("2e5", r"line 5: the acceleration '2e5' g is beyond 100000 m/s\^2 in magnitude"),
    ],
)
def test_at2_values_must_be_plain_numbers(tmp_path, value, message):
    body = f"{value} " + _body(VALUES[1:])
    _refused(read_at2, _write(tmp_path / "v.AT2", AT2_HEADER, body), message)


@pytest.mark.parametrize(
    ("row", "message"),
    [
        ("0.01,1_000", r"line 3: not a number: '1_000'"),
        ("0.01, nan", r"line 3: not a number: 'nan'"),
        ("0.01,inf", r"line 3: not a number: 'inf'"),
        ("0.01,1..2", r"line 3: not a number: '1..2'"),
        ("0.01,,2", r"line 3: expected 2 column\(s\), got 3"),
        ("0.01;", r"line 3: not a number: an empty cell"),
        ("0.01,1e999", r"line 3: the acceleration '1e999' g is beyond 100000 m/s\^2"),
        ("1e999,1", r"line 3: the time '1e999' s is not finite"),
        ("0.01,\u0661", r"line 3: not a number: '\u0661'"),
    ],
)
def test_column_values_must_be_plain_numbers(tmp_path, row, message):
    path = tmp_path / "v.csv"
    path.write_text(f"t,a\n0,1\n{row}\n0.02,3\n")
    _refused(lambda p: read_columns(p, "g"), path, message)


def test_a_first_row_like_a_number_is_not_skipped_as_the_header(tmp_path):
    """'1_000' and 'nan' are numbers to Python: a first line holding them is a row, refused, not column names."""
    for first in ("1_000,1", "nan,1"):
        path = tmp_path / "first.csv"
        path.write_text(f"{first}\n0.01,2\n0.02,3\n")
        _refused(lambda p: read_columns(p, "g"), path, r"first.csv, line 1: not a number")


def test_plain_float_agrees_with_the_number_grammar():
    """_plain reads a line with float at once when it holds only the characters of numbers and separators: from
    those characters (D exponents aside), float must take exactly what NUMBER matches."""
    import itertools

    for n in range(1, 6):
        for chars in itertools.product("01.eE+-", repeat=n):
            text = "".join(chars)
            assert (records._plain(text, [text]) is not None) == bool(records.NUMBER.fullmatch(text)), text


@pytest.mark.parametrize(
    ("header", "unit", "scale"),
    [
        ("time [s],a [g]", None, STANDARD_GRAVITY),
        ("time [s],a [g]", "g", STANDARD_GRAVITY),
        ("t (sec)  acc (cm/s^2)", None, 0.01),
        ("t(s);a(m/s²)", "m/s2", 1.0),
        ("time [seconds], acceleration [M/S**2]", None, 1.0),
        ("time [s], a [gal]", "cm/s2", 0.01),
        ("t [s], a [m s^-2]", None, 1.0),
        ("t, a [cm/sec/sec]", None, 0.01),
        ("time_s,acc_g", "m/s2", 1.0),  # no unit in brackets: the names are names
    ],
)
def test_a_unit_in_the_header_is_used_or_must_agree(tmp_path, header, unit, scale):
    path = tmp_path / "u.csv"
    path.write_text(header + "\n" + CSV.split("\n", 1)[1])
    record = read_record(path, unit)
    np.testing.assert_allclose(record.acceleration, VALUES * scale)


@pytest.mark.parametrize(
    ("header", "unit", "message"),
    [
        ("time [s],a [g]", "m/s2", r"line 1: the header states accelerations in g but the unit given is m/s2"),
        ("time [s],a [cm/s2]", "g", r"line 1: the header states accelerations in cm/s2 but the unit given is g"),
        ("time [ms],a [g]", None, r"line 1: the header states the unit 'ms', which is none of g, m/s2, cm/s2"),
        ("time [s],a [mm/s2]", "m/s2", r"line 1: the header states the unit 'mm/s2'"),
        ("t [s],a [m/s]", "m/s2", r"line 1: the header states the unit 'm/s'"),
        ("a1 [g],a2 [m/s2]", None, r"line 1: the header states accelerations in g and m/s2: one unit only"),
        ("time,a", None, r"u.csv: give the unit of the accelerations \(g, m/s2, cm/s2\): the file does not state"),
    ],
)
def test_a_unit_in_the_header_that_disagrees_or_is_unknown_is_refused(tmp_path, header, unit, message):
    path = tmp_path / "u.csv"
    path.write_text(header + "\n" + CSV.split("\n", 1)[1])
    _refused(lambda p: read_record(p, unit), path, message)


def test_every_column_error_names_the_file(tmp_path):
    path = tmp_path / "c.csv"
    path.write_text("0,1\n1e300,2\n")
    _refused(
        lambda p: read_columns(p, "g"),
        path,
        r"c.csv, line 2: the time step must be in \[1e-06, 10\] s "
        r"\(got 1e\+300\)",
    )
    path.write_text("".join(f"{10 * i},1\n" for i in range(1201)))
    _refused(
        lambda p: read_columns(p, "g"),
        path,
        r"c.csv, line 1201: the record lasts 12000 s \(1201 samples at "
        r"dt = 10 s\): at most 11000 s$",
    )
    _refused(lambda p: read_columns(p, "g", dt=0.1), path, r"c.csv: give dt \(s\) for a file of accelerations alone")
    _refused(
        lambda p: read_columns(p, "g", dt=1e300, time_column=False),
        path,
        r"c.csv: dt must be in \[1e-06, 10\] s \(got 1e\+300\)",
    )
    _refused(lambda p: read_record(p, "g", dt=0.01, time_column=False), path, r"c.csv, line 1: expected 1 column")


@pytest.mark.parametrize("codec", ["utf-16", "utf-16-le", "utf-16-be", "utf-32", "utf-8-sig", "latin-1"])
def test_text_with_a_byte_order_mark_is_decoded(tmp_path, codec):
    text = CSV.replace("time [s],a [g]", "# Station Sète, 1.5 m/s²\ntime [s],a [g]")
    data = text.encode(codec)
    if codec in ("utf-16-le", "utf-16-be"):  # these codecs write no mark: add it
        data = "\ufeff".encode(codec) + data
    path = tmp_path / "e.csv"
    path.write_bytes(data)
    np.testing.assert_allclose(read_record(path).acceleration, VALUES * STANDARD_GRAVITY)
    at2 = tmp_path / "e.AT2"
    at2.write_bytes(
        ("\ufeff" if codec.startswith("utf-16-") else "").encode(codec)
        + ("\n".join(AT2_HEADER) + "\n" + _body(VALUES)).encode(codec)
    )
    np.testing.assert_allclose(read_at2(at2).acceleration, VALUES * STANDARD_GRAVITY, rtol=1e-7)


def test_utf16_without_a_byte_order_mark_is_refused_with_a_hint(tmp_path):
    path = tmp_path / "w.csv"
    path.write_bytes(CSV.encode("utf-16-le"))
    _refused(
        lambda p: read_columns(p, "g"),
        path,
        r"w.csv, line 1: holds NUL bytes: not a text file \(UTF-16 "
        r"without a byte-order mark\? save it as UTF-8\)$",
    )


# --- fuzz: any bytes give a Record or the project's error, never another exception, never a hang -----------

AT2_TEXT = ("\n".join(AT2_HEADER) + "\n" + _body(VALUES)).encode()
CSV_TEXT = CSV.encode()
ALPHABET = b"0123456789.eEdD+-,; \t\r\n#[]()gsm/_NnaIif\x00\xff\xfe\xef\xbb\xbf"


@st.composite
def _mutated(draw, base: bytes) -> bytes:
    """``base`` with a few bytes replaced, inserted or deleted, drawn mostly from the characters that matter."""
    data = bytearray(base)
    for _ in range(draw(st.integers(1, 6))):
        at = draw(st.integers(0, len(data)))
        piece = draw(st.binary(min_size=1, max_size=4) | st.sampled_from([bytes([c]) for c in ALPHABET]))
        kind = draw(st.sampled_from(["replace", "insert", "delete"]))
        if kind == "insert":
            data[at:at] = piece
        elif kind == "replace":
            data[at : at + len(piece)] = piece
        else:
            del data[at : at + len(piece)]
    return bytes(data)


FILES = st.one_of(
    st.binary(max_size=300),
    st.binary(max_size=200).map(lambda b: AT2_TEXT[:120] + b),
    _mutated(AT2_TEXT),
    _mutated(CSV_TEXT),
)


def check_any_bytes(data: bytes, folder) -> str:
    """Read ``data`` as an AT2 file and as columns (unit given or not): a valid Record, which a SampledMotion
    accepts, or a one-line ParameterError naming the file. Returns which."""
    outcomes = []
    for name, read in (("f.AT2", read_at2), ("f.csv", lambda p: read_columns(p, "g")), ("f.txt", read_record)):
        path = folder / name
        path.write_bytes(data)
        try:
            record = read(path)
        except ParameterError as exc:
            assert str(exc).startswith(str(path)) and "\n" not in str(exc), str(exc)
            outcomes.append("refused")
            continue
        assert np.all(np.isfinite(record.acceleration)) and record.acceleration.size >= 2
        SampledMotion(record.acceleration, dt=record.dt)
        outcomes.append("record")
    return ",".join(outcomes)


#: Examples of the fuzz test; a larger run: ROCKING_RECORDS_FUZZ=20000 pytest --hypothesis-show-statistics -k fuzz.
FUZZ_EXAMPLES = int(os.environ.get("ROCKING_RECORDS_FUZZ", "150"))


@settings(max_examples=FUZZ_EXAMPLES, deadline=2000, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=FILES)
def test_fuzz_any_bytes_give_a_record_or_a_parameter_error(tmp_path, data):
    event(check_any_bytes(data, tmp_path))


def test_cli_simulate_takes_the_unit_a_header_states_and_refuses_a_contradiction(tmp_path, capsys):
    from rocking.cli.main import main

    path = tmp_path / "r.csv"
    path.write_text("time [s], a [cm/s2]\n" + "".join(f"{0.01 * i:.2f}, {50.0 * np.sin(i / 5)}\n" for i in range(64)))
    assert main(["simulate", "--motion", str(path), "--json"]) == 0
    assert '"pga": 0.49' in capsys.readouterr().out  # 50 cm/s2 at most
    assert main(["simulate", "--motion", str(path), "--unit", "m/s2"]) == 2
    err = capsys.readouterr().err
    assert f"error: {path}, line 1: the header states accelerations in cm/s2 but the unit given is m/s2" in err


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")
def test_a_suites_file_replaced_by_a_pipe_is_refused_without_blocking(tmp_path):
    """A study's suite hashes its files again when a tile reads them: with the readers' checks, not read_bytes."""
    import hashlib

    from rocking.study.suite import Suite

    path = Path(_write(tmp_path / "s.AT2", AT2_HEADER, _body(VALUES)))
    assert records.file_sha256(path) == hashlib.sha256(path.read_bytes()).hexdigest()
    suite = Suite.from_files([path])
    path.unlink()
    os.mkfifo(path)
    error = _within(10.0, lambda _: suite.motion(0), path).get("error")
    assert isinstance(error, ParameterError) and str(error).endswith(
        "s.AT2: is a named pipe, not a regular file: only regular files are read"
    )


def test_implausible_records_warn_and_are_read(tmp_path):
    """A record read in g whose peak exceeds 20 g (cm/s2 by mistake), a dt above 0.05 s: a PlausibilityWarning
    each, naming the file; the record is read all the same. In cm/s2 the same numbers are plausible."""
    from rocking import PlausibilityWarning

    path = tmp_path / "cm.txt"
    path.write_text("time [s], a [g]\n0, 0\n0.01, 350\n0.02, -120\n")
    with pytest.warns(PlausibilityWarning, match=r"cm\.txt: read in g, its PGA is 350 g \(> 20 g\)"):
        record = read_record(path)
    assert np.max(np.abs(record.acceleration)) == pytest.approx(350 * STANDARD_GRAVITY)
    coarse = tmp_path / "coarse.txt"
    coarse.write_text("0 0\n0.1 1\n0.2 0\n")
    with pytest.warns(PlausibilityWarning, match=r"coarse\.txt: dt = 0\.1 s \(> 0\.05 s\)"):
        read_columns(coarse, "m/s2")
    plain = tmp_path / "plain.txt"
    plain.write_text("0, 0\n0.01, 350\n0.02, -120\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        read_columns(plain, "cm/s2")
