"""The sliding phases derived from the energies (derive/friction.py) against equations typed by hand."""

import numpy as np
import pytest
import sympy as sp

from rocking.derive.equations import derive
from rocking.derive.friction import du_before, friction_impact, mu_slip, sliding
from rocking.derive.spec import variant_spec
from rocking.reference import paper
from rocking.reference.sliding import contact_slide_frame_accel, corner_impact, slide_rock_frame_accel
from rocking.reference.verify import random_cases, rel_error


@pytest.fixture(scope="module")
def omd():
    eq = derive(variant_spec("omd"))
    return eq, sliding(eq)


@pytest.fixture(scope="module")
def block():
    eq = derive(variant_spec("block"))
    return eq, sliding(eq)


def _numeric(eq, exprs):
    """``exprs`` as a NumPy function of ``(s, q, dq, ag, agy, params, mu_slip)``."""
    sysm = eq.system
    args = [sp.Symbol("s", real=True), *sysm.q, *sysm.dq, sp.Symbol("ag", real=True), sp.Symbol("agy", real=True)]
    return sp.lambdify([*args, *sysm.params, mu_slip], exprs, "numpy")


def _cases(rng, n, s):
    v = random_cases(rng, n, s)
    v["mu"] = rng.uniform(-0.8, 0.8, n)
    return v


@pytest.mark.parametrize("s", [1, -1])
def test_bare_block_slide_rock_matches_the_hand_typed_balance(block, s):
    eq, sl = block
    f = _numeric(eq, sl.slide_accel)
    v = _cases(np.random.default_rng(5), 400, s)
    ddtheta, ddu = f(
        s, v["theta"], v["dtheta"], v["ag"], 0 * v["ag"], v["M"], v["I_G"], v["B"], v["H"], v["e"], v["g"], v["mu"]
    )
    a = slide_rock_frame_accel(
        s, v["theta"], v["dtheta"], v["ag"], v["mu"], v["M"], v["I_G"], v["B"], v["H"], v["e"], v["g"]
    )
    assert rel_error(v["ag"] + ddu, a) < 1e-11
    d = s * v["B"] / 2 + v["e"]
    I_s = v["I_G"] + v["M"] * (d**2 + v["H"] ** 2 / 4)
    housner = (
        v["M"]
        * (
            a * (v["H"] / 2 * np.cos(v["theta"]) + d * np.sin(v["theta"]))
            - v["g"] * (d * np.cos(v["theta"]) - v["H"] / 2 * np.sin(v["theta"]))
        )
        / I_s
    )
    assert rel_error(ddtheta, housner) < 1e-11


@pytest.mark.parametrize("s", [1, -1])
def test_damper_slide_rock_is_the_paper_equations_in_the_sliding_frame(omd, s):
    """(R1)-(R2) at ddx_g + ddu with V_b + mu_slip N_b = 0 (paper.rocking_accel, paper.base_reaction: by hand)."""
    eq, sl = omd
    f = _numeric(eq, sl.slide_accel)
    v = _cases(np.random.default_rng(6), 400, s)
    params = [v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c")]
    got = f(s, v["theta"], v["x"], v["dtheta"], v["dx"], v["ag"], 0 * v["ag"], *params, v["mu"])

    def balance(w):
        a = v["ag"] + w
        dd = paper.rocking_accel(s, v["theta"], v["x"], v["dtheta"], v["dx"], a, 0 * a, *params)
        V, N, _ = paper.base_reaction(s, v["theta"], v["x"], v["dtheta"], v["dx"], *dd, a, 0 * a, *params[:-2])
        return V + v["mu"] * N, dd

    r0, _ = balance(0.0)
    r1, _ = balance(1.0)
    w = -r0 / (r1 - r0)  # the balance is affine in ddu
    ref = balance(w)[1]
    assert rel_error(got[-1], w) < 1e-9
    assert rel_error(got[0], ref[0]) < 1e-9 and rel_error(got[1], ref[1]) < 1e-9


def test_damper_contact_slide_matches_the_hand_typed_balance(omd):
    eq, sl = omd
    f = _numeric(eq, sl.contact_slide_accel)
    v = _cases(np.random.default_rng(7), 400, 1)
    params = [v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c")]
    zero = 0 * v["x"]
    ddtheta, ddx, ddu = f(1, zero, v["x"], zero, v["dx"], v["ag"], zero, *params, v["mu"])
    a = contact_slide_frame_accel(v["x"], v["dx"], v["mu"], v["M"], v["g"], v["m"], v["k_m"], v["c"])
    assert np.all(ddtheta == 0)
    assert rel_error(v["ag"] + ddu, a) < 1e-11
    assert rel_error(ddx, paper.contact_accel(v["x"], v["dx"], a, v["m"], v["k_m"], v["c"])) < 1e-11


def test_no_friction_frees_the_centre_of_mass_and_the_stick_friction_holds_the_pivot(block):
    """mu_slip = 0: no horizontal force, the centre of mass keeps its horizontal velocity (V_b = 0); mu_slip equal
    to the friction the stick phase needs, -V_b / N_b of Housner's equation at a = ddx_g: the pivot holds, ddu = 0."""
    eq, sl = block
    f = _numeric(eq, sl.slide_accel)
    v = _cases(np.random.default_rng(8), 200, 1)
    M, I_G, B, H, e, g, th, dth, ag = (v[k] for k in ("M", "I_G", "B", "H", "e", "g", "theta", "dtheta", "ag"))
    d = B / 2 + e
    I_s = I_G + M * (d**2 + H**2 / 4)
    P, Q = H / 2 * np.cos(th) + d * np.sin(th), d * np.cos(th) - H / 2 * np.sin(th)

    def shear_normal(a, ddtheta):
        return M * (a - P * ddtheta - Q * dth**2), M * (g + Q * ddtheta - P * dth**2)

    ddtheta, ddu = f(1, th, dth, ag, 0 * ag, M, I_G, B, H, e, g, 0 * ag)
    V, N = shear_normal(ag + ddu, ddtheta)
    assert np.max(np.abs(V) / (M * (np.abs(ag) + g))) < 1e-12
    V, N = shear_normal(ag, M * (ag * P - g * Q) / I_s)  # the stick phase: Housner's equation, ddu = 0
    ddtheta, ddu = f(1, th, dth, ag, 0 * ag, M, I_G, B, H, e, g, -V / N)
    assert np.max(np.abs(ddu) / (np.abs(ag) + g)) < 1e-11


@pytest.fixture(scope="module")
def block_impact(block):
    eq, _ = block
    return eq, friction_impact(eq)


@pytest.mark.parametrize("s", [1, -1])
@pytest.mark.parametrize("stick", [True, False])
def test_bare_block_impact_with_friction_matches_newton_euler_impulses(block_impact, s, stick):
    eq, fi = block_impact
    sysm = eq.system
    f = sp.lambdify(
        [sp.Symbol("s", real=True), *sysm.dq, du_before, *sysm.params, mu_slip], fi.stick if stick else fi.slide
    )
    rng = np.random.default_rng(9)
    for _ in range(50):
        M, H = rng.uniform(10, 1e4), rng.uniform(0.2, 5)
        B = H * rng.uniform(0.05, 1.5)
        e, I_G = rng.uniform(-0.4, 0.4) * B, M * (B**2 + H**2) / 12 * rng.uniform(0.5, 2)
        dtheta, du, mu = rng.normal(0, 1), rng.normal(0, 0.5), rng.uniform(-0.9, 0.9)
        got = f(s, dtheta, du, M, I_G, B, H, e, 9.81, mu)
        ref = corner_impact(s, dtheta, du, mu, M, I_G, B, H, e, stick=stick)
        scale = [
            abs(dtheta) + abs(du),
            abs(dtheta) * B + abs(du),
            M * (abs(dtheta) * B + abs(du)),
            M * (abs(dtheta) * B + abs(du)),
        ]
        assert all(abs(g - r) <= 1e-12 * c for g, r, c in zip(got, ref, scale))


@pytest.mark.parametrize("s", [1, -1])
def test_a_sticking_impact_from_rest_is_section_6s_with_the_damper(omd, s):
    """du = 0 before and the corner sticking: (I1)-(I2) (paper.impact, by hand), with no slip after and a normal
    impulse that pushes (P_n > 0 for an impact that ends a rocking phase)."""
    eq, _ = omd
    fi = friction_impact(eq)
    sysm = eq.system
    f = sp.lambdify([sp.Symbol("s", real=True), *sysm.q, *sysm.dq, du_before, *sysm.params], fi.stick)
    v = random_cases(np.random.default_rng(10), 300, s)
    args = [v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c")]
    dth = -s * np.abs(v["dtheta"])  # s theta falls to 0: an impact
    dtheta, dx, du, P_t, P_n = f(s, 0 * v["x"], v["x"], dth, v["dx"], 0 * v["x"], *args)
    ref = paper.impact(s, v["x"], dth, v["dx"], v["M"], v["I_G"], v["B"], v["H"], v["e"], v["m"], v["h"])
    assert rel_error(dtheta, ref[0]) < 1e-12 and rel_error(dx, ref[1]) < 1e-12
    assert np.all(du == 0) and np.all(P_n > 0)
