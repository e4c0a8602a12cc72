"""Tests for rocking.model.pulse: the one-sine ground acceleration pulse."""

import math

import numpy as np
import pytest

from rocking.model.params import Block, ParameterError
from rocking.model.pulse import OneSinePulse


def test_pulse_defaults_and_float_storage():
    pulse = OneSinePulse(a_g=np.int64(3), omega_g=2)
    assert (pulse.a_g, pulse.omega_g, pulse.psi) == (3.0, 2.0, 0.0)
    assert all(type(v) is float for v in (pulse.a_g, pulse.omega_g, pulse.psi))


def test_period_and_duration_without_phase():
    pulse = OneSinePulse(a_g=1.0, omega_g=4.0)
    assert pulse.T_g == pytest.approx(math.pi / 2, rel=1e-15)
    assert pulse.t_p == pulse.T_g


@pytest.mark.parametrize("psi", [0.0, 0.5, math.pi, 6.0])
def test_duration_with_phase(psi):
    pulse = OneSinePulse(a_g=1.0, omega_g=3.0, psi=psi)
    assert pulse.t_p == pytest.approx((2 * math.pi - psi) / 3.0, rel=1e-15)
    assert pulse.T_g == pytest.approx(2 * math.pi / 3.0, rel=1e-15)


def test_acceleration_known_values_without_phase():
    pulse = OneSinePulse(a_g=2.5, omega_g=5.0)
    T = pulse.T_g
    assert pulse.acceleration(0.0) == 0.0
    assert pulse.acceleration(T / 4) == pytest.approx(2.5, rel=1e-14)
    assert pulse.acceleration(T / 2) == pytest.approx(0.0, abs=1e-14)
    assert pulse.acceleration(3 * T / 4) == pytest.approx(-2.5, rel=1e-14)
    assert pulse.acceleration(T / 12) == pytest.approx(1.25, rel=1e-14)


def test_acceleration_is_zero_outside_pulse():
    pulse = OneSinePulse(a_g=2.5, omega_g=5.0)
    assert pulse.acceleration(-0.1) == 0.0
    assert pulse.acceleration(pulse.t_p * (1 + 1e-9)) == 0.0
    assert pulse.acceleration(pulse.t_p + pulse.T_g / 4) == 0.0
    assert pulse.acceleration(100.0) == 0.0


def test_acceleration_with_phase():
    psi = math.pi / 2
    pulse = OneSinePulse(a_g=3.0, omega_g=2.0, psi=psi)
    assert pulse.acceleration(0.0) == pytest.approx(3.0, rel=1e-15)
    # The pulse ends where the sine cycle ends, not one full period later.
    assert pulse.acceleration(pulse.t_p - 1e-9) == pytest.approx(0.0, abs=1e-7)
    assert pulse.acceleration(pulse.t_p + 0.25 * pulse.T_g) == 0.0
    assert pulse.acceleration(pulse.t_p * 0.5) == pytest.approx(3.0 * math.sin(2.0 * 0.5 * pulse.t_p + psi), rel=1e-14)


def test_acceleration_returns_float_for_scalars():
    pulse = OneSinePulse(a_g=1.0, omega_g=1.0)
    for t in (0.5, 2, np.float64(0.5), 50.0):
        assert type(pulse.acceleration(t)) is float


@pytest.mark.parametrize("shape", [(7,), (3, 4), (2, 1, 5)])
def test_acceleration_is_vectorised(shape):
    pulse = OneSinePulse(a_g=1.5, omega_g=2.0, psi=0.3)
    t = np.linspace(-1.0, 2 * pulse.t_p, math.prod(shape)).reshape(shape)
    acc = pulse.acceleration(t)
    assert isinstance(acc, np.ndarray) and acc.shape == shape
    expected = [pulse.acceleration(float(ti)) for ti in t.ravel()]
    np.testing.assert_array_equal(acc.ravel(), expected)


def test_acceleration_accepts_lists():
    pulse = OneSinePulse(a_g=1.0, omega_g=2 * math.pi)
    np.testing.assert_allclose(pulse.acceleration([0.25, 0.75, 1.5]), [1.0, -1.0, 0.0], atol=1e-15)


@pytest.mark.parametrize("beta", [0.0, 1.0, 3.7, 15.0])
@pytest.mark.parametrize("Omega", [0.5, 2.0, 15.0])
def test_from_nondim_round_trip(beta, Omega):
    block = Block.reference()
    pulse = OneSinePulse.from_nondim(block, beta=beta, Omega=Omega, psi=0.4)
    assert pulse.beta(block) == pytest.approx(beta, rel=1e-12)
    assert pulse.Omega(block) == pytest.approx(Omega, rel=1e-12)
    assert pulse.psi == 0.4


def test_from_nondim_scales():
    block = Block.from_nondim(p=2.0, lam=5.0, g=9.81)
    pulse = OneSinePulse.from_nondim(block, beta=1.0, Omega=3.0)
    assert pulse.a_g == pytest.approx(9.81 / 5.0, rel=1e-12)
    assert pulse.omega_g == pytest.approx(6.0, rel=1e-12)


PULSE_OK = {"a_g": 1.0, "omega_g": 2.0, "psi": 0.0}


@pytest.mark.parametrize(
    "name, value",
    [
        ("a_g", -0.1),
        ("a_g", math.nan),
        ("a_g", math.inf),
        ("a_g", "1g"),
        ("omega_g", 0.0),
        ("omega_g", -1.0),
        ("omega_g", math.inf),
        ("psi", -0.1),
        ("psi", 2 * math.pi),
        ("psi", 7.0),
        ("psi", math.nan),
    ],
)
def test_pulse_validation(name, value):
    with pytest.raises(ParameterError, match=rf"^{name} must"):
        OneSinePulse(**{**PULSE_OK, name: value})


def test_pulse_error_message_gives_range_and_value():
    with pytest.raises(ParameterError, match=r"^psi must be in \[0, 2 pi\) = \[0, 6\.28319\) rad"):
        OneSinePulse(a_g=1.0, omega_g=1.0, psi=-1.0)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"beta": -1.0, "Omega": 1.0}, "beta"),
        ({"beta": math.nan, "Omega": 1.0}, "beta"),
        ({"beta": 1.0, "Omega": 0.0}, "Omega"),
        ({"beta": 1.0, "Omega": -2.0}, "Omega"),
        ({"beta": 1.0, "Omega": 1.0, "psi": 7.0}, "psi"),
    ],
)
def test_from_nondim_validation(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        OneSinePulse.from_nondim(Block.reference(), **kwargs)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"a_g": 1e300, "omega_g": 2.0}, r"^a_g must be in \[0, 100000\] m/s\^2"),
        ({"a_g": 1.0, "omega_g": 1e-300}, r"^omega_g must be in \[2 pi/1000, 2 pi/0\.001\] = \[0\.00628319, 6283"),
        ({"a_g": 1.0, "omega_g": 1e300}, r"^omega_g must be in .*sine periods from 1 ms to 1000 s"),
        ({"a_g": True, "omega_g": 2.0}, r"^a_g must be a real number \(got True\), in \[0, 100000\] m/s\^2: "),
        ({"a_g": 1.0, "omega_g": "2"}, r"^omega_g must be a real number"),
    ],
)
def test_pulse_ranges(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        OneSinePulse(**kwargs)


@pytest.mark.parametrize(
    "block, kwargs, message",
    [
        (Block.reference(), {"beta": 0.5, "Omega": 5e-324}, r"^Omega must be in \[0\.01, 1000\]"),
        (Block.reference(), {"beta": 0.5, "Omega": 1e-6}, r"^Omega must be in"),
        (Block.reference(), {"beta": 1e300, "Omega": 1.0}, r"^beta must be in \[0, 10000\]"),
        (Block.from_nondim(p=0.2, lam=1.0), {"beta": 1.0, "Omega": 0.01}, r"^beta = 1\.0, Omega = 0\.01 .* omega_g"),
        (None, {"beta": 1.0, "Omega": 1.0}, r"^block must be a rocking\.Block \(got NoneType\)$"),
    ],
)
def test_from_nondim_ranges(block, kwargs, message):
    with pytest.raises(ParameterError, match=message):
        OneSinePulse.from_nondim(block, **kwargs)


@pytest.mark.parametrize("sign", [0, 2, True, 1.0, "-1", None])
def test_the_sign_of_a_pulse_is_plus_or_minus_one(sign):
    with pytest.raises(ParameterError, match=r"^sign must be \+1 or -1"):
        OneSinePulse(a_g=1.0, omega_g=2.0, sign=sign)
    with pytest.raises(ParameterError, match=r"^sign must be \+1 or -1"):
        OneSinePulse.from_nondim(Block.reference(), beta=2.0, Omega=3.0, sign=sign)


def test_a_pulse_of_sign_minus_one_is_the_opposite_ground_motion():
    up = OneSinePulse(a_g=3.0, omega_g=2.0, psi=0.5)
    down = OneSinePulse(a_g=3.0, omega_g=2.0, psi=0.5, sign=-1)
    t = np.linspace(-1.0, 4.0, 50)
    assert np.array_equal(down.acceleration(t), -up.acceleration(t))
    assert down.beta(Block.reference()) == up.beta(Block.reference())  # beta is the amplitude
