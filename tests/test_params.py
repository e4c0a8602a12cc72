"""Tests for rocking.model.params: construction, derived quantities, round trips, validation."""

import math

import numpy as np
import pytest

import rocking
from rocking.model.params import Block, Damper, ParameterError

G = 9.81


# --- Block -----------------------------------------------------------------------


def test_block_stores_floats_and_homogeneous_inertia():
    block = Block(H=np.int64(2), B=1, M=np.float32(3.0))
    assert all(type(v) is float for v in block.as_params().values())
    assert block.I_G == pytest.approx(3.0 * (1.0 + 4.0) / 12)
    assert block.e == 0.0 and block.g == G


def test_block_explicit_inertia_is_kept():
    assert Block(H=2.0, B=0.5, M=10.0, I_G=7.5).I_G == 7.5


def test_reference_block_values():
    block = Block.reference()
    assert (block.H, block.B, block.M, block.e, block.g) == (2.0, 0.5, 1000.0, 0.025, G)
    assert block.I_G == pytest.approx(1000.0 * (0.25 + 4.0) / 12, rel=1e-14)
    assert block.lam == pytest.approx(4.0, rel=1e-14)
    assert block.alpha == pytest.approx(math.atan(0.25), rel=1e-14)
    assert block.tan_alpha == pytest.approx(0.25, rel=1e-14)
    assert block.R == pytest.approx(math.sqrt(4.25) / 2, rel=1e-14)
    assert block.I_O == pytest.approx(4 / 3 * 1000.0 * block.R**2, rel=1e-14)
    assert block.p == pytest.approx(math.sqrt(3 * G / (4 * block.R)), rel=1e-14)
    assert block.p == pytest.approx(2.67167, abs=1e-5)


@pytest.mark.parametrize("H, B", [(2.0, 0.5), (1.0, 1.0), (10.0, 0.3), (0.4, 2.0)])
def test_homogeneous_p_formula(H, B):
    block = Block(H=H, B=B, M=123.0, e=0.1 * B)
    assert block.p == pytest.approx(math.sqrt(3 * G / (4 * block.R)), rel=1e-14)


def test_p_uses_given_inertia():
    block = Block(H=2.0, B=0.5, M=10.0, I_G=4.0)
    assert block.I_O == pytest.approx(4.0 + 10.0 * block.R**2, rel=1e-14)
    assert block.p == pytest.approx(math.sqrt(10.0 * G * block.R / block.I_O), rel=1e-14)


def test_block_as_params_keys():
    params = Block.reference().as_params()
    assert set(params) == {"M", "I_G", "B", "H", "e", "g"}
    assert params["e"] == 0.025


def test_block_is_frozen():
    with pytest.raises(AttributeError):
        Block.reference().H = 3.0


@pytest.mark.parametrize("p", [0.5, 2.3, 7.0])
@pytest.mark.parametrize("lam", [1.0, 4.0, 25.0])
def test_block_from_nondim_lam_round_trip(p, lam):
    block = Block.from_nondim(p=p, lam=lam, M=500.0, e_ratio=0.05, g=9.80665)
    assert block.p == pytest.approx(p, rel=1e-12)
    assert block.lam == pytest.approx(lam, rel=1e-12)
    assert block.e / block.B == pytest.approx(0.05, rel=1e-12)
    assert block.M == 500.0 and block.g == 9.80665
    assert block.R == pytest.approx(3 * 9.80665 / (4 * p**2), rel=1e-12)


@pytest.mark.parametrize("alpha", [0.02, 0.25, 1.2])
def test_block_from_nondim_alpha_round_trip(alpha):
    block = Block.from_nondim(p=1.7, alpha=alpha)
    assert block.alpha == pytest.approx(alpha, rel=1e-12)
    assert block.p == pytest.approx(1.7, rel=1e-12)
    assert block.M == 1.0 and block.e == 0.0


def test_block_from_nondim_reproduces_reference_geometry():
    ref = Block.reference()
    block = Block.from_nondim(p=ref.p, lam=ref.lam, M=ref.M, e_ratio=ref.e / ref.B)
    for key, value in ref.as_params().items():
        assert block.as_params()[key] == pytest.approx(value, rel=1e-12)


BLOCK_OK = {"H": 2.0, "B": 0.5, "M": 1000.0, "e": 0.0, "I_G": None, "g": G}


@pytest.mark.parametrize(
    "name, value",
    [
        ("H", 0.0),
        ("H", -1.0),
        ("H", math.nan),
        ("H", math.inf),
        ("H", "2.0"),
        ("B", 0.0),
        ("B", -0.5),
        ("B", None),
        ("M", 0.0),
        ("M", -1.0),
        ("M", -math.inf),
        ("e", 0.25),
        ("e", -0.25),
        ("e", 0.3),
        ("e", math.nan),
        ("I_G", 0.0),
        ("I_G", -1.0),
        ("I_G", math.inf),
        ("I_G", "x"),
        ("g", 0.0),
        ("g", -9.81),
        ("g", math.nan),
        ("H", True),
    ],
)
def test_block_validation(name, value):
    with pytest.raises(ParameterError, match=rf"^{name} must") as info:
        Block(**{**BLOCK_OK, name: value})
    assert isinstance(info.value, ValueError)


def test_block_error_messages_give_range_and_value():
    with pytest.raises(ParameterError, match=r"^H must be in \[0\.001, 1000\] m \(got -1\.0\): from a 1 mm"):
        Block(H=-1, B=0.5, M=1.0)
    with pytest.raises(
        ParameterError,
        match=r"^e must be in \(-B/2, B/2\) = \(-0\.25, 0\.25\) m \(got 0\.3\)$",
    ):
        Block(H=2.0, B=0.5, M=1.0, e=0.3)
    with pytest.raises(ParameterError, match=r"^B must be a real number \(got 'wide'\), in \[0\.001, 1000\] m: "):
        Block(H=2.0, B="wide", M=1.0)
    with pytest.raises(ParameterError, match=r"^M must be finite \(got nan\), in \[1e-06, 1e\+12\] kg: "):
        Block(H=2.0, B=0.5, M=math.nan)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"p": 0.0, "lam": 4.0}, "p"),
        ({"p": -1.0, "lam": 4.0}, "p"),
        ({"p": math.inf, "lam": 4.0}, "p"),
        ({"p": 2.0, "lam": 0.0}, "lam"),
        ({"p": 2.0, "lam": -4.0}, "lam"),
        ({"p": 2.0, "lam": "tall"}, "lam"),
        ({"p": 2.0, "alpha": 0.0}, "alpha"),
        ({"p": 2.0, "alpha": math.pi / 2}, "alpha"),
        ({"p": 2.0, "alpha": -0.1}, "alpha"),
        ({"p": 2.0, "lam": 4.0, "e_ratio": 0.5}, "e_ratio"),
        ({"p": 2.0, "lam": 4.0, "e_ratio": -0.7}, "e_ratio"),
        ({"p": 2.0, "lam": 4.0, "M": 0.0}, "M"),
        ({"p": 2.0, "lam": 4.0, "g": 0.0}, "g"),
        ({"p": 2.0}, "lam"),
        ({"p": 2.0, "lam": 4.0, "alpha": 0.25}, "alpha"),
    ],
)
def test_block_from_nondim_validation(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        Block.from_nondim(**kwargs)


# --- Damper ----------------------------------------------------------------------


def test_damper_derived_quantities():
    damper = Damper(m=np.int32(20), k_m=500, c=12.0, h=0.05)
    assert all(type(v) is float for v in damper.as_params().values())
    assert damper.as_params() == {"m": 20.0, "k_m": 500.0, "c": 12.0, "h": 0.05}
    assert damper.omega_m == pytest.approx(5.0, rel=1e-14)
    assert damper.T_m == pytest.approx(2 * math.pi / 5.0, rel=1e-14)
    assert damper.zeta == pytest.approx(12.0 / (2 * 20.0 * 5.0), rel=1e-14)
    assert damper.gamma(Block.reference()) == pytest.approx(0.02, rel=1e-14)


def test_damper_defaults():
    damper = Damper(m=1.0, k_m=1.0)
    assert (damper.c, damper.h) == (0.0, 0.0)


@pytest.mark.parametrize("quantity", ["omega_m", "T_m", "zeta"])
def test_damper_without_mass_has_no_frequency(quantity):
    damper = Damper(m=0.0, k_m=0.0)
    assert damper.gamma(Block.reference()) == 0.0
    with pytest.raises(ParameterError, match=rf"{quantity} is undefined for m = 0"):
        getattr(damper, quantity)


@pytest.mark.parametrize("T_m", [0.1, 2.0, 30.0])
@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.3])
def test_damper_from_nondim_T_m_round_trip(T_m, zeta):
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, T_m=T_m, zeta=zeta, h=0.05)
    assert damper.T_m == pytest.approx(T_m, rel=1e-12)
    assert damper.zeta == pytest.approx(zeta, rel=1e-12, abs=1e-15)
    assert damper.gamma(block) == pytest.approx(0.05, rel=1e-12)
    assert damper.h == 0.05
    assert damper.k_m == pytest.approx(damper.m * damper.omega_m**2, rel=1e-12)


@pytest.mark.parametrize("omega_ratio", [0.1, 1.0, 10.0])
def test_damper_from_nondim_omega_ratio_round_trip(omega_ratio):
    block = Block.from_nondim(p=1.3, lam=6.0, M=250.0)
    damper = Damper.from_nondim(block, gamma=0.2, omega_ratio=omega_ratio)
    assert damper.omega_m / block.p == pytest.approx(omega_ratio, rel=1e-12)
    assert damper.zeta == pytest.approx(0.05, rel=1e-12)
    assert damper.gamma(block) == pytest.approx(0.2, rel=1e-12)
    assert damper.m == pytest.approx(50.0, rel=1e-12)


def test_damper_from_nondim_zero_mass_is_bare_block():
    damper = Damper.from_nondim(Block.reference(), gamma=0.0, T_m=1.0)
    assert damper.as_params() == {"m": 0.0, "k_m": 0.0, "c": 0.0, "h": 0.0}


DAMPER_OK = {"m": 10.0, "k_m": 100.0, "c": 1.0, "h": 0.0}


@pytest.mark.parametrize(
    "name, value",
    [
        ("m", -1.0),
        ("m", math.nan),
        ("m", "heavy"),
        ("k_m", -1.0),
        ("k_m", math.inf),
        ("k_m", 0.0),
        ("c", -0.1),
        ("c", math.nan),
        ("h", -0.05),
        ("h", math.inf),
        ("h", [0.0]),
    ],
)
def test_damper_validation(name, value):
    with pytest.raises(ParameterError, match=rf"^{name} must"):
        Damper(**{**DAMPER_OK, name: value})


def test_damper_error_message_gives_range_and_value():
    with pytest.raises(ParameterError, match=r"^c must be in \[0, 1e\+30\] N s/m \(got -2\.0\): "):
        Damper(m=1.0, k_m=1.0, c=-2)
    with pytest.raises(ParameterError, match=r"k_m must be > 0 N/m when m > 0"):
        Damper(m=1.0, k_m=0.0)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"gamma": -0.01, "T_m": 1.0}, "gamma"),
        ({"gamma": "big", "T_m": 1.0}, "gamma"),
        ({"gamma": 0.05, "T_m": 0.0}, "T_m"),
        ({"gamma": 0.05, "T_m": -1.0}, "T_m"),
        ({"gamma": 0.05, "T_m": math.nan}, "T_m"),
        ({"gamma": 0.05, "omega_ratio": 0.0}, "omega_ratio"),
        ({"gamma": 0.05, "omega_ratio": -2.0}, "omega_ratio"),
        ({"gamma": 0.05, "T_m": 1.0, "zeta": -0.01}, "zeta"),
        ({"gamma": 0.05, "T_m": 1.0, "h": -0.01}, "h"),
        ({"gamma": 0.05}, "T_m"),
        ({"gamma": 0.05, "T_m": 1.0, "omega_ratio": 1.0}, "omega_ratio"),
    ],
)
def test_damper_from_nondim_validation(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        Damper.from_nondim(Block.reference(), **kwargs)


# --- ranges (issue 10): declared once in RANGES, refused with the range and its reason ----------


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"H": 1e-300}, r"^H must be in \[0\.001, 1000\] m \(got 1e-300\): from a 1 mm"),
        ({"H": 1e4}, r"^H must be in \[0\.001, 1000\] m"),
        ({"B": 5e-324}, r"^B must be in"),
        ({"H": 200.0, "B": 1.0}, r"^H / B must be in \[0\.01, 100\] \(got 200\.0\): slenderness"),
        ({"M": 1e-300}, r"^M must be in \[1e-06, 1e\+12\] kg"),
        ({"M": True}, r"^M must be a real number \(got True\), in \[1e-06, 1e\+12\] kg: "),
        ({"I_G": 1e300}, r"^I_G must be in \(0, 4 M R\^2\] = \(0, "),
        ({"g": 1e-300}, r"^g must be in \[0\.1, 10000\] m/s\^2"),
        ({"g": "9.81"}, r"^g must be a real number"),
    ],
)
def test_block_ranges(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        Block(**{"H": 2.0, "B": 0.5, "M": 1000.0, **kwargs})


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"p": 1e-300, "lam": 4.0}, r"^p must be in \[0\.01, 10000\] rad/s"),
        ({"p": 0.02, "lam": 4.0}, r"^p = 0\.02 rad/s with g = 9\.81 m/s\^2 gives R = .*: H must be in"),
        ({"p": 2.0, "lam": 1e4}, r"^lam must be in \[0\.01, 100\]"),
        ({"p": 2.0, "alpha": 1e-6}, r"^alpha must be in \[atan\(0\.01\), atan\(100\)\]"),
        ({"p": True, "lam": 4.0}, r"^p must be a real number"),
    ],
)
def test_block_from_nondim_ranges(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        Block.from_nondim(**kwargs)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"m": 1e-300, "k_m": 200.0}, r"^m must be 0 or in \[1e-16, 1e\+13\] kg \(got 1e-300\): a subnormal"),
        ({"m": 50.0, "k_m": 1e300}, r"^k_m must be in \[0, 1e\+30\] N/m"),
        ({"m": 50.0, "k_m": 200.0, "c": 1e300}, r"^c must be in \[0, 1e\+30\] N s/m"),
        ({"m": 50.0, "k_m": 200.0, "h": 1e4}, r"^h must be in \[0, 1000\] m"),
        ({"m": 50.0, "k_m": False}, r"^k_m must be a real number"),
    ],
)
def test_damper_ranges(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        Damper(**kwargs)


@pytest.mark.parametrize(
    "damper, message",
    [
        (Damper(m=1e-9, k_m=1e-8), r"^m must be 0 or in \[1e-10 M, 10 M\] = \[1e-07, 10000\] kg"),
        (Damper(m=50.0, k_m=1e12), r"^omega_m must be in \[1e-3 p, 1e4 p\] = .* rad/s .*between a free mass"),
        (Damper(m=50.0, k_m=200.0, c=1e12), r"^zeta must be in \[0, 10\] .*stiff for the explicit integrator"),
    ],
)
def test_damper_on_its_block(damper, message):
    with pytest.raises(ParameterError, match=message):
        damper.check_on(Block.reference())


def test_a_valid_damper_passes_on_its_block():
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    assert damper.check_on(block) is damper
    assert Damper(m=0.0, k_m=0.0).check_on(block).m == 0.0


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"gamma": 1e-300, "T_m": 1.0}, r"^gamma must be 0 or in \[1e-10, 10\]"),
        ({"gamma": 0.05, "omega_ratio": 1e6}, r"^omega_ratio must be in \[0\.001, 10000\]"),
        ({"gamma": 0.05, "T_m": 1e-6}, r"^T_m must be in \[2 pi/\(1e4 p\), 2 pi/\(1e-3 p\)\] = \[0\.000235"),
        ({"gamma": 0.05, "T_m": 1.0, "zeta": 1e6}, r"^zeta must be in \[0, 10\]"),
        ({"gamma": "0.05", "T_m": 1.0}, r"^gamma must be a real number"),
    ],
)
def test_damper_from_nondim_ranges(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        Damper.from_nondim(Block.reference(), **kwargs)


@pytest.mark.parametrize("block", [None, "reference", 3.0])
def test_from_nondim_needs_a_block(block):
    with pytest.raises(ParameterError, match=r"^block must be a rocking\.Block"):
        Damper.from_nondim(block, gamma=0.05, T_m=1.0)


def test_the_amplitude_scaling_is_one_function_both_ways_and_vectorised():
    """a_g = beta g tan(alpha) (docs/model.md section 9), typed here: the reference block's g tan(alpha) is
    9.81 x 0.5 / 2."""
    block = Block.reference()
    beta = np.array([0.5, 1.0, 7.25])
    np.testing.assert_allclose(block.a_g(beta), beta * 9.81 * 0.25, rtol=1e-15)
    np.testing.assert_array_equal(block.beta(block.a_g(beta)), beta)
    assert (
        isinstance(block.a_g(2.0), float)
        and block.a_g(2.0) == rocking.OneSinePulse.from_nondim(block, beta=2.0, Omega=3.0).a_g
    )


def test_the_tuned_damper_is_one_function_for_scalars_and_grids():
    from rocking.model.params import tuned_damper

    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.3, zeta=0.07, h=0.0)
    m, k_m, c = tuned_damper(block.M, np.array([0.05, 0.1]), 1.3 * block.p, 0.07)
    assert (m[0], k_m[0], c[0]) == (damper.m, damper.k_m, damper.c)
    assert m[1] == 100.0 and k_m[1] == pytest.approx(100.0 * (1.3 * block.p) ** 2, rel=1e-15)
