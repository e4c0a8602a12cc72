"""One validation table: every bound lives in ``rocking.model.checks.RANGES``, and the checks of a run's
settings and of ``make_problem``'s options name its entries instead of restating numbers."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest

import rocking
from rocking import Block, MavroeidisPapageorgiou, OneSinePulse, ParameterError
from rocking.model import checks, params
from rocking.model.checks import RANGES
from rocking.sim import boundary, problem
from rocking.sim.boundary import CASE, CODES
from rocking.sim.problem import OPTIONS, make_problem

ROOT = Path(__file__).resolve().parent.parent
#: The modules that check a run's settings and options.
CHECKING = ("rocking/sim/boundary.py", "rocking/sim/problem.py", "rocking/sim/accuracy.py")
#: The options of make_problem that no range bounds: a name or object, and an array checked by its model (a
#: Floor's coefficients are its fields mu_s and mu_k, each checked against RANGES["mu"]).
UNRANGED_OPTIONS = {"model", "y0", "floor"}

BLOCK = Block(H=1.0, B=0.25, M=100.0)
PULSE = OneSinePulse(a_g=3.0, omega_g=6.0)


def _checked_fields() -> dict[str, str]:
    return {f.name: f.valid for f in CASE if f.valid is not None}


def test_checks_is_a_leaf_module():
    tree = ast.parse((ROOT / "rocking/model/checks.py").read_text())
    imported = [alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names] + [
        node.module or "" for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and not node.level
    ]
    relative = [node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.level]
    assert not relative and not [name for name in imported if name.split(".")[0] == "rocking"]


def test_params_re_exports_the_table_and_the_checks():
    """Code that imports them from rocking.model.params, as before the move, gets the same objects."""
    for name in checks.__all__:
        assert getattr(params, name) is getattr(checks, name), name
    assert rocking.ParameterError is checks.ParameterError


def test_every_check_of_a_setting_is_an_entry_of_ranges_or_a_code_set():
    for name, valid in _checked_fields().items():
        assert (valid in RANGES) != (valid in CODES), f"{name}: {valid!r}"


def test_every_option_is_checked_against_an_entry_of_ranges_or_its_setting():
    """An option is a RANGES entry, or a setting whose check is one; an option that is both names one range."""
    fields = _checked_fields()
    assert set(problem._OPTION_CHECKS) <= set(OPTIONS)
    for name in set(OPTIONS) - UNRANGED_OPTIONS:
        assert name in RANGES or name in fields, name
        if name in RANGES and name in fields:
            assert fields[name] == name, f"{name} is checked against {fields[name]!r} and {name!r}"


def _literals(path: str) -> list[tuple[int, float]]:
    tree = ast.parse((ROOT / path).read_text())
    return [
        (node.lineno, node.value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant) and type(node.value) in (int, float)
    ]


def test_no_bound_of_a_setting_or_an_option_is_restated():
    """The bounds of the entries the checks name appear as numbers in no module that checks settings.

    0 and 1 are everywhere (a count, an index); a default that equals another entry's bound is no bound.
    """
    named = set(_checked_fields().values()) | set(OPTIONS)
    bounds = {
        bound
        for name in named & set(RANGES)
        for bound in (RANGES[name].low, RANGES[name].high)
        if math.isfinite(bound) and bound not in (0, 1)
    }
    defaults = {value for value in (*OPTIONS.values(), *(f.default for f in CASE)) if isinstance(value, (int, float))}
    restated = [
        (path, line, value) for path in CHECKING for line, value in _literals(path) if value in bounds - defaults
    ]
    assert not restated


@pytest.mark.parametrize(
    ("name", "values"),
    [
        ("t_max", (-1.0, 0.0, 1e-300, 15.0, 3e4, math.nextafter(3e4, math.inf), math.inf, math.nan)),
        ("rtol", (0.0, math.nextafter(1e-12, 0.0), 1e-12, 1e-8, 1e-2, 0.011, math.nan)),
        ("max_events", (0, 1, 10_000, 100_000_000, 100_000_001)),
    ],
)
def test_an_option_and_its_setting_accept_the_same_values(name, values):
    """``make_problem(name=...)`` and the check of the setting ``name`` agree with ``RANGES[name]``."""
    for value in values:
        valid = value in RANGES[name]
        try:
            make_problem(BLOCK, None, PULSE, **{name: value})
        except ParameterError as error:
            assert not valid, f"{name}={value!r}: {error}"
            assert str(error).startswith(f"{name} must be ")
        else:
            assert valid, f"make_problem took {name}={value!r}"
        try:
            boundary.check(name, value)
        except ParameterError as error:
            assert not valid, f"{name}={value!r}: {error}"
        else:
            assert valid, f"the setting took {name}={value!r}"


def test_t_max_has_one_range_that_every_motion_and_t_after_fit():
    """A run of the longest motion followed for the longest t_after is a valid t_max, given or derived.

    Before the one table, t_max was refused above 11000 s when given, yet the run of a Mavroeidis-Papageorgiou
    pulse of 20 cycles of 1000 s (20,000 s long) derived a longer one: two ranges for one setting.
    """
    assert _checked_fields()["t_max"] == "t_max"
    longest = MavroeidisPapageorgiou(a_g=1.0, omega_g=RANGES["omega_g"].low, gamma_mp=RANGES["gamma_mp"].high)
    assert longest.t_p >= RANGES["record_length"].high  # a sampled motion is no longer
    derived = make_problem(BLOCK, None, longest, t_after=RANGES["t_after"].high).t_max
    assert derived in RANGES["t_max"]
    assert make_problem(BLOCK, None, longest, t_max=derived).t_max == derived
    with pytest.raises(ParameterError, match=r"^t_max must be in \(0, 30000\] s \(got 30001\)"):
        boundary.check("t_max", 30001)
