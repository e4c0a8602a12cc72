"""Issue 23, item 1: every public constructor taking numbers gives a valid object or a ParameterError.

Any value in any numeric parameter (integers beyond the doubles, nan and infinities, strings,
None, booleans, complex numbers, fractions, NumPy scalars and arrays) ends as a valid object, or
as a one-line :class:`ParameterError` naming a parameter; nothing else escapes. The checks of
``rocking.model.params`` (``as_real``, ``check_in_range``) are the one place that decides.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rocking
from rocking import ParameterError
from rocking.study.config import Tuning

BLOCK = rocking.Block.reference()
DAMPER = rocking.Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
RECORD = rocking.SampledMotion([0.0, 1.0, -0.5, 0.0], dt=0.01)

#: Values no check may let through unconverted, nor fail on with anything but a ParameterError.
HOSTILE = st.one_of(
    st.integers(),  # up to hundreds of digits: float() overflows beyond 1.8e308
    st.sampled_from([10**400, -(10**400), 10**1000, 2**1024, Fraction(10**400, 3), math.nan, math.inf, -math.inf]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.fractions(),
    st.text(max_size=5),
    st.none(),
    st.booleans(),
    st.complex_numbers(),
    st.builds(np.float32, st.floats(width=32)),
    st.builds(np.int64, st.integers(-(2**63), 2**63 - 1)),
    st.builds(np.complex128, st.complex_numbers()),
    st.builds(np.array, st.lists(st.floats(-10, 10), max_size=3)),
    st.lists(st.floats(-10, 10), max_size=3),
)


def value(low: float, high: float) -> st.SearchStrategy:
    """A plausible value in ``[low, high]`` half the time (valid objects are made too), else a hostile one."""
    integers = [st.integers(math.ceil(low), math.floor(high))] if math.ceil(low) <= math.floor(high) else []
    return st.one_of(st.floats(low, high), *integers, HOSTILE)


def samples() -> st.SearchStrategy:
    """A record's samples: a plausible array, or hostile elements in a list."""
    plausible = st.lists(st.floats(-20, 20), min_size=2, max_size=6)
    return st.one_of(plausible, st.lists(st.one_of(st.floats(-20, 20), HOSTILE), min_size=2, max_size=4), HOSTILE)


def sign() -> st.SearchStrategy:
    return st.one_of(st.sampled_from([1, -1]), HOSTILE)


#: Each public constructor with a strategy for its keyword arguments (every numeric one drawn).
CONSTRUCTORS = {
    "Block": (
        rocking.Block,
        st.fixed_dictionaries(
            {"H": value(0.1, 5), "B": value(0.1, 2), "M": value(1, 1e4)},
            optional={"e": value(-0.05, 0.05), "I_G": value(1, 1e3), "g": value(1, 20)},
        ),
    ),
    "Block.from_nondim": (
        rocking.Block.from_nondim,
        st.fixed_dictionaries(
            {"p": value(0.5, 10)},
            optional={
                "lam": value(1, 10),
                "alpha": value(0.05, 1),
                "M": value(1, 1e4),
                "e_ratio": value(-0.2, 0.2),
                "g": value(1, 20),
            },
        ),
    ),
    "Damper": (
        rocking.Damper,
        st.fixed_dictionaries(
            {"m": value(0, 100), "k_m": value(0, 1e4)},
            optional={"c": value(0, 100), "h": value(0, 0.2)},
        ),
    ),
    "Damper.from_nondim": (
        lambda **kw: rocking.Damper.from_nondim(BLOCK, **kw),
        st.fixed_dictionaries(
            {"gamma": value(0, 0.2)},
            optional={"T_m": value(0.5, 10), "omega_ratio": value(0.2, 5), "zeta": value(0, 0.3), "h": value(0, 0.2)},
        ),
    ),
    "Stops": (
        rocking.Stops,
        st.fixed_dictionaries({"L": value(0.01, 0.3), "k_b": value(1, 1e6)}, optional={"c_b": value(0, 100)}),
    ),
    "Stops.at_edges": (
        lambda **kw: rocking.Stops.at_edges(BLOCK, DAMPER, **kw),
        st.fixed_dictionaries(
            {},
            optional={"depth": value(0.001, 0.1), "k_b": value(1e4, 1e7), "zeta_b": value(0, 1)},
        ),
    ),
    "Tuning": (
        Tuning,
        st.fixed_dictionaries(
            {},
            optional={"gamma": value(0, 0.2), "omega_ratio": value(0.2, 5), "zeta": value(0, 0.3), "h": value(0, 0.2)},
        ),
    ),
    "SampledMotion(dt)": (
        rocking.SampledMotion,
        st.fixed_dictionaries(
            {"a": samples(), "dt": value(1e-3, 0.1)},
            optional={"scale": value(0, 10), "sign": sign()},
        ),
    ),
    "SampledMotion(t)": (
        rocking.SampledMotion,
        st.fixed_dictionaries(
            {"a": st.just([0.0, 1.0, 0.0]), "t": samples()},
            optional={"scale": value(0, 10)},
        ),
    ),
    "SampledMotion.scaled": (RECORD.scaled, st.fixed_dictionaries({"factor": value(0, 10)})),
    "SampledMotion.scaled_to_pga": (RECORD.scaled_to_pga, st.fixed_dictionaries({"target": value(0, 10)})),
}
for _name, _cls, _shape in (
    ("OneSinePulse", rocking.OneSinePulse, {"psi": value(0, 6)}),
    ("OneCosinePulse", rocking.OneCosinePulse, {}),
    ("RickerWavelet", rocking.RickerWavelet, {}),
    ("MavroeidisPapageorgiou", rocking.MavroeidisPapageorgiou, {"gamma_mp": value(1.1, 5), "nu": value(0, 6)}),
):
    _required = {"gamma_mp": _shape["gamma_mp"]} if "gamma_mp" in _shape else {}
    _optional = {**{k: v for k, v in _shape.items() if k != "gamma_mp"}, "sign": sign()}
    CONSTRUCTORS[_name] = (
        _cls,
        st.fixed_dictionaries({"a_g": value(0, 20), "omega_g": value(1, 40), **_required}, optional=_optional),
    )
    CONSTRUCTORS[f"{_name}.from_nondim"] = (
        lambda _c=_cls, **kw: _c.from_nondim(BLOCK, **kw),
        st.fixed_dictionaries({"beta": value(0, 15), "Omega": value(0.5, 15), **_required}, optional=_optional),
    )
    CONSTRUCTORS[f"{_name}.from_period"] = (
        _cls.from_period,
        st.fixed_dictionaries({"a_g": value(0, 20), "T_g": value(0.1, 10), **_required}, optional=_optional),
    )


def _numbers_of(obj) -> list:
    """The numbers a constructed object stores in its fields."""
    return [v for v in (getattr(obj, f.name) for f in dataclasses.fields(obj)) if isinstance(v, float)]


@pytest.mark.parametrize("name", sorted(CONSTRUCTORS))
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_any_input_gives_a_valid_object_or_a_parameter_error(name, data):
    make, arguments = CONSTRUCTORS[name]
    kwargs = data.draw(arguments, label="kwargs")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no NumPy cast may drop a complex part or overflow on the way
        try:
            obj = make(**kwargs)
        except ParameterError as exc:
            message = str(exc)
            assert "\n" not in message and len(message) < 400, message
            return
    assert all(math.isfinite(x) for x in _numbers_of(obj)), obj


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: rocking.Block(H=10**400, B=0.5, M=1.0), r"^H must be in \[0\.001, 1000\] m \(got 1e\+400\): "),
        (lambda: rocking.Block(H=2.0, B=0.5, M=-(10**5000)), r"^M must be in \[1e-06, 1e\+12\] kg \(got -1e\+5000\)"),
        (lambda: rocking.OneSinePulse(a_g=10**400, omega_g=1.0), r"^a_g must be in \[0, 100000\] m/s\^2 \(got 1e\+400"),
        (lambda: rocking.Damper(m=1.0, k_m=1j), r"^k_m must be a real number \(got 1j\), in \[0, 1e\+30\] N/m: "),
        (lambda: rocking.Damper.from_nondim(BLOCK, gamma=0.05, T_m=10**400), r"^T_m must be in \[2 pi/\(1e4 p\), "),
        # Found by Hypothesis (when k_b was m (60 omega_m)^2): an overflow before any check.
        (
            lambda: rocking.Stops.at_edges(BLOCK, DAMPER, k_b=1e152),
            r"^k_b must be in \(0, 1e\+30\] N/m \(got 1e\+152\)",
        ),
        (lambda: rocking.OneCosinePulse.from_period(1.0, None), r"^T_g must be a real number \(got None\), > 0 s$"),
        (lambda: rocking.OneSinePulse(a_g=np.array([1.0, 2.0]), omega_g=1.0), r"^a_g must be a real number \(got arr"),
        (lambda: rocking.SampledMotion([0.0, 1j], dt=0.1), r"^a must be an array of real numbers \(got dtype complex"),
        (lambda: rocking.SampledMotion([0.0, "1"], dt=0.1), r"^a must be an array of real numbers \(got dtype <U"),
        (lambda: rocking.SampledMotion([0.0, 10**400], dt=0.1), r"^a must be finite: a\[1\] = inf$"),
        (lambda: rocking.SampledMotion([0.0, 1.0], dt=0.1, scale=10**400), r"^scale must be finite \(got 1e\+400\)"),
        (lambda: rocking.simulate(BLOCK, None, rocking.OneSinePulse(1.0, 1.0), y0=[10**400, 0.0]), r"^y0 must hold 2"),
    ],
)
def test_the_instances_of_the_issue_name_the_parameter_and_its_range(make, message):
    with pytest.raises(ParameterError, match=message):
        make()


def test_a_huge_integer_is_shown_by_its_magnitude():
    """Python prints no int of more than 4300 digits: the message must not try."""
    with pytest.raises(ParameterError, match=r"got 1e\+10000\)"):
        rocking.Block(H=10**10000, B=0.5, M=1.0)


@pytest.mark.parametrize("gamma", [1e-3, 0.013, 0.05, 0.31, 2.7])
@pytest.mark.parametrize("omega_ratio", [1e-3, 0.37, 1.0, 3.3, 1e4])
def test_a_damper_made_at_the_bounds_of_its_ranges_is_accepted_where_it_is_used(gamma, omega_ratio):
    # zeta = c / (2 m omega_m) of a damper made from zeta = 10 comes back a few ulps off (10.000000000000002):
    # rounding, not a value outside [0, 10]; a value given beyond it is still refused.
    damper = rocking.Damper.from_nondim(BLOCK, gamma=gamma, omega_ratio=omega_ratio, zeta=10.0)
    assert damper.check_on(BLOCK) is damper
    if omega_ratio <= 100:  # the pads' frequency, 60 omega_m by default, within its range of [1e-3 p, 1e4 p]
        stops = rocking.Stops.at_edges(BLOCK, damper, zeta_b=10.0)
        assert stops.check_on(BLOCK, damper) is stops
    with pytest.raises(rocking.ParameterError, match=r"^zeta must be in \[0, 10\] \(got 10\.001\)"):
        rocking.Damper.from_nondim(BLOCK, gamma=gamma, omega_ratio=omega_ratio, zeta=10.001)
