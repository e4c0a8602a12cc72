"""The boundary between the back ends, declared once in rocking/sim/boundary.py, and everything built from it.

csrc/boundary.h, rocking/sim/fields.py and the table of docs/simulation.md are fresh; the ctypes
structures, the NumPy records, Problem and Response have the tables' fields in
their order; the loaded C library reports the same layout and constants; and a
field added to the table reaches the header, the documentation and the checks.
"""

from __future__ import annotations

import ctypes
import dataclasses
import math
import re

import numpy as np
import pytest

from rocking import Block, OneSinePulse, ParameterError
from rocking.model.checks import RANGES
from rocking.sim import boundary, numpy_backend
from rocking.sim import c_backend as cb
from rocking.sim.boundary import CASE, CONSTANTS, FAILED, MOTIONS, PHASES, RESULT, STATUSES, STOPPED, Field
from rocking.sim.fields import ProblemFields, ResponseFields
from rocking.sim.problem import (
    CONTACT,
    PIVOT_A,
    PIVOT_A_PRIME,
    RESULT_FIELDS,
    STATUS,
    Problem,
    Response,
    make_problem,
)

CASE_NAMES = [f.name for f in CASE]
RESULT_NAMES = [f.name for f in RESULT]
#: The results the tolerance check adds (rocking.sim.accuracy), after those of C.
CHECKED_NAMES = [f.name for f in boundary.CHECKED]


# --------------------------------------------------------------------------- #
# Generated text                                                               #
# --------------------------------------------------------------------------- #


def test_the_c_header_is_fresh():
    """csrc/boundary.h is what `python -m rocking.sim.boundary` writes from the tables."""
    assert boundary.HEADER.read_text(encoding="utf-8") == boundary.c_header(), (
        "csrc/boundary.h is stale: run `python -m rocking.sim.boundary`"
    )


def test_the_python_fields_are_fresh():
    """fields.py is what `python -m rocking.sim.boundary` writes from the tables."""
    assert boundary.FIELDS.read_text(encoding="utf-8") == boundary.python_fields(), (
        "rocking/sim/fields.py is stale: run `python -m rocking.sim.boundary`"
    )


def test_the_documentation_table_is_fresh():
    """The boundary table of docs/simulation.md is what `python -m rocking.sim.boundary` writes."""
    text = boundary.DOC.read_text(encoding="utf-8")
    assert text.count(boundary.DOC_BEGIN) == 1 and text.count(boundary.DOC_END) == 1
    assert boundary.document(text) == text, "docs/simulation.md is stale: run `python -m rocking.sim.boundary`"


def _struct_fields(header: str, name: str) -> list[str]:
    body = re.search(rf"typedef struct {name} \{{(.*?)\}} {name};", header, re.S).group(1)
    return re.findall(r"(\w+);", body)


def _x_macro(header: str, name: str) -> list[str]:
    return re.findall(r"X\((\w+)\)", re.search(rf"#define {name}\(X\) (.*)", header).group(1))


def test_the_header_declares_the_tables_in_their_order():
    header = boundary.c_header()
    assert _struct_fields(header, "rocking_case") == CASE_NAMES
    assert _struct_fields(header, "rocking_result") == RESULT_NAMES
    assert _x_macro(header, "ROCKING_CASE_FIELDS") == CASE_NAMES
    assert _x_macro(header, "ROCKING_RESULT_FIELDS") == RESULT_NAMES
    codes = [f"ROCKING_{c.name.upper()}" for c in (*STATUSES, FAILED, STOPPED, *PHASES)]
    codes += [f"ROCKING_MOTION_{c.name.upper()}" for c in MOTIONS]
    assert _x_macro(header, "ROCKING_CONSTANTS") == [f"ROCKING_{c.name}" for c in CONSTANTS] + codes
    for c in CONSTANTS:
        assert float(re.search(rf"#define ROCKING_{c.name} (\S+)", header).group(1)) == c.value
    for c in (*STATUSES, FAILED, STOPPED, *PHASES):
        assert int(re.search(rf"ROCKING_{c.name.upper()} = (-?\d+),", header).group(1)) == c.value
    for c in MOTIONS:
        assert int(re.search(rf"ROCKING_MOTION_{c.name.upper()} = (-?\d+),", header).group(1)) == c.value
    assert re.search(r"#define ROCKING_SIM_API_VERSION (\d+)", header).group(1) == str(boundary.API_VERSION)


def test_a_new_field_reaches_the_header_the_documentation_and_the_checks(monkeypatch):
    """Adding a setting is one Field in CASE: the header, the docs table and the checks follow."""
    extra = Field("extra_setting", boundary.DOUBLE, "s", "a setting added for this test", "positive", 1.0)
    monkeypatch.setattr(boundary, "CASE", (*CASE, extra))
    header = boundary.c_header()
    assert _struct_fields(header, "rocking_case") == [*CASE_NAMES, "extra_setting"]
    assert _x_macro(header, "ROCKING_CASE_FIELDS") == [*CASE_NAMES, "extra_setting"]
    assert "    double extra_setting; /* a setting added for this test [s] */" in header
    assert (
        "| `extra_setting` | double | s | finite and > 0 | `1.0` | a setting added for this test |"
        in boundary.markdown()
    )
    assert "    extra_setting: float = 1.0\n" in boundary.python_fields()
    assert boundary.check("extra_setting", 2.0) == 2.0
    with pytest.raises(ParameterError, match=r"^extra_setting must be finite and > 0 \(got 0\)$"):
        boundary.check("extra_setting", 0.0)


# --------------------------------------------------------------------------- #
# The tables' own consistency, and their checks                               #
# --------------------------------------------------------------------------- #


def test_codes():
    assert STATUS == tuple(c.name for c in STATUSES)
    assert all(c.value == i for i, c in enumerate(STATUSES)) and FAILED.value < 0 and STOPPED.value < 0
    assert FAILED.name not in STATUS and STOPPED.name not in STATUS  # never a result
    assert FAILED.value != STOPPED.value
    assert (CONTACT, PIVOT_A, PIVOT_A_PRIME) == (0, 1, -1) == tuple(c.value for c in PHASES)
    assert boundary.constant_values() == tuple(
        float(c.value) for c in (*CONSTANTS, *STATUSES, FAILED, STOPPED, *PHASES, *MOTIONS)
    )
    assert len({f.name for f in (*CASE, *RESULT)}) == len(CASE) + len(RESULT)


@pytest.mark.parametrize("f", [f for f in CASE if f.valid], ids=lambda f: f.name)
def test_every_checked_setting_refuses_nan_naming_itself_and_its_range(f):
    assert f.valid in RANGES or f.valid in boundary.CODES
    if not f.required:  # a default is valid
        assert boundary.check(f.name, f.default) == f.default
    with pytest.raises(ParameterError) as info:
        boundary.check(f.name, math.nan)
    assert str(info.value) == f"{f.name} must be {boundary.valid_text(f.valid)} (got nan)"


def test_the_numpy_back_end_s_constants_are_the_table_s():
    """The C library's constants are checked at load; a copy the NumPy back end keeps must equal them too."""
    for c in CONSTANTS:
        if hasattr(numpy_backend, c.name):
            assert getattr(numpy_backend, c.name) == c.value, c.name


# --------------------------------------------------------------------------- #
# ctypes, NumPy records and the loaded library                                 #
# --------------------------------------------------------------------------- #

_CTYPE = {boundary.DOUBLE: ctypes.c_double, boundary.INT64: ctypes.c_int64, boundary.INT32: ctypes.c_int32}
_NUMPY = {
    boundary.DOUBLE: np.float64,
    boundary.INT64: np.int64,
    boundary.INT32: np.int32,
    boundary.DOUBLES: np.uintp,
    boundary.SERIES: np.uintp,
}


@pytest.mark.parametrize(
    "table, structure, record",
    [(CASE, cb._Case, cb.CASE_DTYPE), (RESULT, cb._Result, cb.RESULT_DTYPE)],
    ids=["case", "result"],
)
def test_ctypes_structures_and_numpy_records_have_the_tables_fields(table, structure, record):
    names = [f.name for f in table]
    assert [name for name, _ in structure._fields_] == names
    assert list(record.names) == names
    for f, (_, ctype) in zip(table, structure._fields_):
        if f.kind in (boundary.DOUBLES, boundary.SERIES):
            assert ctype == ctypes.c_void_p, f.name  # an address, as the records' np.uintp
        else:
            assert ctype == _CTYPE[f.kind], f.name
        assert record.fields[f.name][0] == np.dtype(_NUMPY[f.kind]), f.name
    # The record lays its fields out where the structure does (what the C batch reads).
    assert [getattr(structure, n).offset for n in names] == [record.fields[n][1] for n in names]
    assert ctypes.sizeof(structure) == record.itemsize


@pytest.mark.parametrize("model", ["block", "omd"])
def test_the_library_reports_the_tables_layout_and_constants(model):
    lib = cb.library(model).lib
    case = np.zeros(len(CASE) + 1, dtype=np.int64)
    result = np.zeros(len(RESULT) + 1, dtype=np.int64)
    lib.rocking_layout(
        case.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)), result.ctypes.data_as(ctypes.POINTER(ctypes.c_int64))
    )
    assert case.tolist() == [getattr(cb._Case, n).offset for n in CASE_NAMES] + [ctypes.sizeof(cb._Case)]
    assert result.tolist() == [getattr(cb._Result, n).offset for n in RESULT_NAMES] + [ctypes.sizeof(cb._Result)]
    constants = np.zeros(len(boundary.constant_values()))
    lib.rocking_constants(constants.ctypes.data_as(ctypes.POINTER(ctypes.c_double)))
    assert tuple(constants) == boundary.constant_values()
    assert lib.rocking_api_version() == boundary.API_VERSION


# --------------------------------------------------------------------------- #
# Problem and Response                                                         #
# --------------------------------------------------------------------------- #


def test_problem_fields_follow_the_case_table():
    fields = dataclasses.fields(Problem)
    assert [f.name for f in fields] == ["model", "p", *CASE_NAMES]
    by_name = {f.name: f for f in fields}
    for f in CASE:
        default = by_name[f.name].default
        if f.required:
            assert default is dataclasses.MISSING, f.name
        else:
            assert default == f.default, f.name
    block = Block.reference()
    problem = make_problem(block, None, OneSinePulse.from_nondim(block, beta=2.0, Omega=3.0))
    assert list(problem.settings()) == CASE_NAMES


def test_response_fields_follow_the_result_table():
    assert [f.name for f in dataclasses.fields(Response)] == [*RESULT_NAMES, *CHECKED_NAMES, "history", "inputs"]
    assert list(RESULT_FIELDS) == RESULT_NAMES
    assert RESULT_FIELDS["status"] is np.int64 and RESULT_FIELDS["overturned"] is bool
    record = np.zeros(1, dtype=cb.RESULT_DTYPE)[0]
    record["status"], record["overturned"], record["theta_max"] = 3, 1, 0.5
    response = Response.from_record(record)
    assert (response.status, response.overturned, response.theta_max) == ("max_events", True, 0.5)
    assert list(response.summary()) == [*RESULT_NAMES, *CHECKED_NAMES]


@pytest.mark.parametrize(
    "cls, names, table",
    [
        (ProblemFields, ["model", "p", *CASE_NAMES], CASE),
        (ResponseFields, [*RESULT_NAMES, *CHECKED_NAMES], boundary.SUMMARY),
        (Response, ["history", "inputs"], ()),
    ],
    ids=["Problem", "Response", "Response's own"],
)
def test_the_docstrings_mention_every_field(cls, names, table):
    doc = cls.__doc__
    for name in names:
        assert re.search(rf"^\s+{name} : ", doc, re.M), f"{cls.__name__}'s docstring lacks {name}"
    for f in table:
        assert f.doc[1:] in " ".join(doc.split()), f.name  # its meaning, from the table


def test_problem_and_response_are_classes_of_their_fields():
    """Type checkers and editors read the fields from the generated classes that Problem and Response extend."""
    assert issubclass(Problem, ProblemFields) and issubclass(Response, ResponseFields)
    annotations = {**ProblemFields.__annotations__, **ResponseFields.__annotations__}
    assert annotations["a_g"] == "float" and annotations["y0"] == "np.ndarray | None"
    assert annotations["status"] == "str" and annotations["sensitive"] == "bool"
    block = Block.reference()
    problem = make_problem(block, None, OneSinePulse.from_nondim(block, beta=2.0, Omega=3.0))
    with pytest.raises(ParameterError, match=r"^rtol must be in \[1e-12, 0.01\] \(got 5\)$"):
        dataclasses.replace(problem, rtol=5.0)  # Problem's own checks run on construction, not only its fields'
    assert type(dataclasses.replace(problem, phase0=np.int64(0)).phase0) is int
