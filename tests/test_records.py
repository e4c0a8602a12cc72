"""Recorded accelerograms from files: PEER NGA .AT2 (with the header variants found in the wild) and columns."""

from __future__ import annotations

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
    np.testing.assert_allclose(record.acceleration / STANDARD_GRAVITY,
                               [-0.01234567, -0.02345678, 0.5, 1e-5, -0.25, 0.0, 0.1, 0.2])  # fmt: skip


@pytest.mark.parametrize(
    ("header", "body", "message"),
    [
        ([*WEST2, "NPTS=    9, DT=   .0100 SEC"], _body(VALUES), r"declares NPTS = 9 but the file holds 8 values"),
        ([*WEST2, "NPTS=    8, DT=   .0100 SEC"], _body(VALUES[:7]), r"NPTS = 8 but the file holds 7 values"),
        ([*WEST2, "NPTS=    8"], _body(VALUES), r"line 4: line 4 must give NPTS and DT"),
        ([*WEST2, "NPTS=    8, DT= 0 SEC"], _body(VALUES), r"line 4: DT must be > 0 s"),
        ([WEST2[0], WEST2[1], "VELOCITY TIME SERIES IN UNITS OF CM/S", "NPTS=8, DT=.01"], _body(VALUES),
         r"line 3: line 3 must give the units"),
        ([*WEST2, "NPTS=8, DT=.01"], _body(VALUES).replace("5.0000000E-01", "NaN"), r"line 5: not a number: 'NaN'"),
        ([*WEST2, "NPTS=8, DT=.01"], _body(VALUES) + "1e999\n", r"line 7: the value 'inf'|not finite|NPTS"),
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
    with pytest.raises(ParameterError, match=r"is not a text file"):
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
        ("t,a\n0,1\n0.01,2\n0.02,3\n0.04,4\n0.05,5\n", {"unit": "g"},
         r"line 5: times must be uniformly spaced: step 0.02 s where the others are 0.01 s"),
        ("0,1\n0.01,nan\n", {"unit": "g"}, r"line 2: the value .* is not finite"),
        ("0,1\n0.01,2,3\n", {"unit": "g"}, r"line 2: expected 2 column\(s\), got 3"),
        ("0,1\n", {"unit": "g"}, r"needs at least 2 samples"),
        ("0,1\n0.01,2\n", {"unit": "gal"}, r"unit must be one of g, m/s2, cm/s2 \(got 'gal'\)"),
        ("0,1\n0.01,2\n", {"unit": None}, r"give the unit of the accelerations"),
        ("1\n2\n", {"unit": "g", "time_column": False, "dt": -0.1}, r"^dt must be > 0 s"),
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
    with pytest.raises(ParameterError, match=r"^times: times must increase"):
        uniform_step([0.0, 0.0, 0.0])
