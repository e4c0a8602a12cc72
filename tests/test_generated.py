"""The generated NumPy and C code against the hand-written equations and outside facts."""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from rocking import load_model
from rocking.reference.verify import BY_HAND, TOLERANCE, random_cases, verify
from tests.test_flight_derivation import FLIGHT


@pytest.mark.parametrize("name", BY_HAND)
def test_generated_numpy_matches_model_md(name):
    """Every generated function on both pivots: the paper's 20, a floor with friction's 8 (section 15) and flight's
    8 (section 16)."""
    model = load_model(name)
    checks = verify(model, n=1000, seed=1)
    bad = [c for c in checks if not c.ok]
    assert {c.function for c in checks} == set(model.manifest["functions"]) >= set(FLIGHT)
    assert len(checks) == 2 * len(model.manifest["functions"]) == 72 and not bad, bad


@pytest.mark.parametrize("name", BY_HAND)
def test_generated_c_matches_model_md(name, c_model):
    """Compiled with -std=c99 -Wall -Wextra -Werror -pedantic, 1000 cases per pivot."""
    model = load_model(name)
    checks = verify(model, n=1000, seed=2, evaluate=c_model(name))
    bad = [c for c in checks if not c.ok]
    assert len(checks) == 2 * len(model.manifest["functions"]) == 72 and not bad, bad


def _reference_params(**over):
    p = dict(M=1000.0, I_G=None, B=0.5, H=2.0, e=0.025, g=9.81, m=50.0, h=0.05, k_m=2000.0, c=30.0)
    p.update(over)
    if p["I_G"] is None:
        p["I_G"] = p["M"] * (p["B"] ** 2 + p["H"] ** 2) / 12
    return p


def _call(model, fn, s, state, ag, params, agy=0.0):
    return getattr(model.functions, fn)(s, *state, ag, agy, *(params[k] for k in model.parameters))


@pytest.mark.parametrize("H, B", [(2.0, 0.5), (1.0, 1.0), (3.0, 0.3)])
def test_housner_restitution_for_bare_symmetric_block(H, B, c_model):
    """docs/model.md 10.1: m = 0, e = 0 gives dtheta+/dtheta- = 1 - 1.5 sin^2(alpha)."""
    alpha = np.arctan(B / H)
    expected = 1 - 1.5 * np.sin(alpha) ** 2
    params = _reference_params(H=H, B=B, e=0.0, m=0.0, k_m=0.0, c=0.0)
    for name in ("omd", "block"):
        model = load_model(name)
        state = (0.0,) * model.nq + (-0.7,) + (0.0,) * (model.nq - 1)
        for s in (1.0, -1.0):
            numpy_ratio = _call(model, "impact", s, state, 0.0, params)[0] / -0.7
            c_ratio = c_model(name)("impact", dict(params, s=s, ag=0.0, **dict(zip(model.state, state))))[0] / -0.7
            assert numpy_ratio == pytest.approx(expected, rel=1e-13)
            assert float(c_ratio) == pytest.approx(expected, rel=1e-13)


@pytest.mark.parametrize("e", [0.0, 0.04, -0.06])
def test_bare_block_uplift_thresholds(e):
    """docs/model.md 10.2: uplift about A at g (B + 2e)/H, about A' at -g (B - 2e)/H."""
    params = _reference_params(e=e, m=0.0, k_m=0.0, c=0.0)
    B, H, g = params["B"], params["H"], params["g"]
    thresholds = {1.0: g * (B + 2 * e) / H, -1.0: -g * (B - 2 * e) / H}
    for name in ("omd", "block"):
        model = load_model(name)
        rest = (0.0,) * (2 * model.nq)
        for s, a_up in thresholds.items():
            assert abs(_call(model, "uplift", s, rest, a_up, params)) < 1e-9
            assert _call(model, "uplift", s, rest, a_up * 1.001, params) > 0
            assert _call(model, "uplift", s, rest, a_up * 0.999, params) < 0


def test_mirror_symmetry():
    """docs/model.md 10.6: (e, x, theta, ddx_g) -> (-e, -x, -theta, -ddx_g) maps solutions onto solutions."""
    model = load_model("omd")
    rng = np.random.default_rng(5)
    for s in (1, -1):
        v = random_cases(rng, 300, s)
        mirror = dict(
            v, s=-v["s"], e=-v["e"], x=-v["x"], theta=-v["theta"], dx=-v["dx"], dtheta=-v["dtheta"], ag=-v["ag"]
        )

        def f(name, vals):
            return getattr(model.functions, name)(
                vals["s"],
                *(vals[k] for k in model.state),
                vals["ag"],
                vals["agy"],
                *(vals[k] for k in model.parameters),
            )

        for name, sign in (("rocking_accel", -1), ("impact", -1), ("contact_accel", -1)):
            np.testing.assert_allclose(f(name, mirror), np.multiply(sign, f(name, v)), rtol=1e-10, atol=1e-9)
        for name, sign in (("energy", 1), ("power", 1), ("uplift", 1), ("critical_angle", -1)):
            np.testing.assert_allclose(f(name, mirror), sign * f(name, v), rtol=1e-10, atol=1e-8)


def _energy_drift(model, params, y0, s, t_end, ag=lambda t: 0.0):
    p = [params[k] for k in model.parameters]
    n = model.nq

    def rhs(t, y):
        acc = model.functions.rocking_accel(s, *y, ag(t), 0.0, *p)
        return np.concatenate([y[n:], np.asarray(acc, float)])

    def power(t, y):
        return model.functions.power(s, *y, ag(t), 0.0, *p)

    def rhs_with_work(t, y):
        return np.append(rhs(t, y[:-1]), power(t, y[:-1]))

    sol = solve_ivp(
        rhs_with_work, (0, t_end), np.append(y0, 0.0), method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True
    )
    ts = np.linspace(0, t_end, 200)
    ys = sol.sol(ts)
    E = np.array([model.functions.energy(s, *ys[:-1, i], 0.0, 0.0, *p) for i in range(ts.size)])
    return E, ys[-1, -1]


def test_energy_conserved_without_damping_or_ground_motion():
    """docs/model.md 10.5: c = 0 and no ground motion keep the energy constant along a tight integration."""
    model = load_model("omd")
    params = _reference_params(c=0.0)
    E, _ = _energy_drift(model, params, np.array([0.05, 0.03, 0.0, -0.1]), 1.0, 3.0)
    scale = params["M"] * params["g"] * params["H"]
    assert np.ptp(E) / scale < 1e-10
    assert np.ptp(E) > 0 or np.all(E == E[0])


def test_energy_balance_with_damping_and_ground_motion():
    """E(t) - E(0) equals the integral of the generated power (dissipation + ground work)."""
    model = load_model("omd")
    params = _reference_params()
    E, work = _energy_drift(
        model, params, np.array([0.05, 0.03, 0.2, -0.1]), 1.0, 2.0, ag=lambda t: 3.0 * np.sin(4 * t)
    )
    scale = params["M"] * params["g"] * params["H"]
    assert abs((E[-1] - E[0]) - work) / scale < 1e-9
    assert abs(work) / scale > 1e-4


@settings(max_examples=300, deadline=None)
@given(
    s=st.sampled_from([1.0, -1.0]),
    slender=st.floats(1.0, 8.0),
    e_ratio=st.floats(-0.45, 0.45),
    inertia=st.floats(0.5, 1.5),
    gamma=st.floats(0.0, 0.3),
    h=st.floats(0.0, 0.5),
    x_ratio=st.floats(-0.45, 0.45),
    dtheta=st.floats(-5.0, 5.0),
    dx=st.floats(-5.0, 5.0),
)
def test_no_impact_increases_the_energy(s, slender, e_ratio, inertia, gamma, h, x_ratio, dtheta, dx):
    """docs/model.md 10.5 with the default impact law: E after (about -s) <= E before (about s)."""
    gain, rounding = _energy_gain(s, slender, e_ratio, inertia, gamma, h, x_ratio, dtheta, dx, "momentum")
    assert gain <= 1e-12 + rounding


def test_velocity_impact_law_can_add_energy():
    """The option that keeps dx continuous needs an impulse along the frictionless guide,
    and that impulse can do positive work: the option is not dissipative in general."""
    gain, rounding = _energy_gain(1.0, 1.0, 0.0, 1.0, 0.25, 0.0, 0.0, 0.5, 1.0, "velocity")
    assert gain > 1e-3 > 1e3 * rounding


def _energy_gain(s, slender, e_ratio, inertia, gamma, h, x_ratio, dtheta, dx, law):
    """Energy after an impact minus before, relative to max(kinetic energy, 1 J), and the rounding error of that.

    Both energies hold the potential energy of the weights (some 1e4 J here),
    written differently about each pivot: their difference is only known to a
    few ulps of it, more than 1e-12 J when the block barely moves.
    """
    mod = _impact_module(law)
    B, M = 0.5, 1000.0
    H = slender * B
    params = dict(
        M=M,
        I_G=inertia * M * (B**2 + H**2) / 12,
        B=B,
        H=H,
        e=e_ratio * B,
        g=9.81,
        m=gamma * M,
        h=h,
        k_m=gamma * M * 20.0,
        c=0.0,
    )
    p = [params[k] for k in mod.PARAMETERS]
    x = x_ratio * B
    before = mod.energy(s, 0.0, x, dtheta, dx, 0.0, 0.0, *p)
    dth_plus, dx_plus = mod.impact(s, 0.0, x, dtheta, dx, 0.0, 0.0, *p)
    after = mod.energy(-s, 0.0, x, dth_plus, dx_plus, 0.0, 0.0, *p)
    kinetic = before - mod.energy(s, 0.0, x, 0.0, 0.0, 0.0, 0.0, *p)
    scale = max(kinetic, 1.0)
    return (after - before) / scale, 8 * np.finfo(float).eps * abs(before) / scale


@functools.cache
def _impact_module(law):
    """The omd model derived with the impact law ``law``."""
    from rocking.derive.spec import variant_spec
    from tests.test_derive import _numpy_module

    return _numpy_module(variant_spec("omd"), {"impact": law})[1]


def test_rocking_acceleration_stays_finite_as_the_mass_vanishes(c_model):
    """The bare block is the limit m -> 0: ddtheta of omd tends to the block model's."""
    omd, block = load_model("omd"), load_model("block")
    params = _reference_params(m=0.0, k_m=0.0, c=0.0)
    bare = _call(block, "rocking_accel", 1.0, (0.1, 0.3), 2.0, params)[0]
    values = dict(params, s=1.0, ag=2.0, theta=0.1, x=0.0, dtheta=0.3, dx=0.0)
    c_ddtheta = c_model("omd")("rocking_accel", values)[0]
    assert np.isfinite(c_ddtheta) and float(c_ddtheta) == pytest.approx(float(bare), rel=1e-14)
    for m in (1e-3, 1e-6, 1e-9):
        light = _reference_params(m=m, k_m=m * 100.0, c=m * 2.0)
        ddtheta = _call(omd, "rocking_accel", 1.0, (0.1, 0.0, 0.3, 0.0), 2.0, light)[0]
        assert float(ddtheta) == pytest.approx(float(bare), rel=10 * m / params["M"] + TOLERANCE)
