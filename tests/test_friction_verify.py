"""`rocking verify` on the functions of a floor with friction (docs/model.md section 15, issue 37 item 1).

The generated functions are held against rocking.reference.sliding (typed by hand); here: every friction model's
16 checks pass, a wrong term in a generated output is caught, and the hand-typed references agree with each other
and with the paper where they meet.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocking import load_model
from rocking.reference import paper, sliding
from rocking.reference.verify import (
    BY_HAND,
    TOLERANCE,
    _numpy_eval,
    friction_inputs,
    random_cases,
    rel_error,
    report,
    verify,
)

#: The functions of a floor with friction, as derive/codegen.py names them.
FRICTION = (
    "slide_accel",
    "contact_slide_accel",
    "slide_uplift",
    "stick_force",
    "contact_stick_force",
    "slip_energy",
    "impact_stick",
    "impact_slide",
)
CASES = 300


@pytest.fixture(scope="module")
def models():
    return {name: load_model(name) for name in BY_HAND}


@pytest.mark.parametrize("name", BY_HAND)
def test_each_friction_function_passes_on_both_pivots(models, name):
    model = models[name]
    assert model.manifest["friction"]
    checks = verify(model, n=CASES, seed=3)
    friction = [c for c in checks if c.function in FRICTION]
    assert sorted((c.function, c.pivot) for c in friction) == sorted((f, s) for f in FRICTION for s in (1, -1))
    assert all(c.max_rel_error <= TOLERANCE for c in checks), [c for c in checks if not c.ok]
    text = report(model, checks)
    assert text.endswith(f"{len(checks)} passed, 0 failed (tolerance {TOLERANCE:g})")
    assert len({line.index(" pivot ") for line in text.splitlines()[1:-1]}) == 1  # the longest name keeps the columns


def _wrong(model, function, change):
    """An ``evaluate`` that is the generated NumPy but for ``function``, whose outputs are ``change(got, v, again)``,
    ``again(**values)`` the generated function at other values of its arguments."""

    def evaluate(name, v):
        got = _numpy_eval(model, name, v)
        return change(got, v, lambda **over: _numpy_eval(model, name, dict(v, **over))) if name == function else got

    return evaluate


def _scaled(i, factor):
    """Output ``i`` off by the relative ``factor - 1``."""
    return lambda got, v, again: tuple(o * factor if k == i else o for k, o in enumerate(got))


#: Wrong terms, each in one generated function: (model, function, change of its outputs).
WRONG = [
    # The slip's direction reversed in slide-rock: the friction pushes along the slip.
    ("omd", "slide_accel", lambda got, v, again: again(mu_slip=-v["mu_slip"])),
    # N off by a relative 1e-9.
    ("omd", "contact_slide_accel", _scaled(3, 1 + 1e-9)),
    ("block", "slide_accel", _scaled(2, 1 + 1e-9)),
    # The uplift margin of the sticking base, not the sliding one.
    ("omd_stops", "slide_uplift", lambda got, v, again: again(mu_slip=0 * v["mu_slip"])),
    # The slip's energy without (M + m) du^2 / 2.
    ("omd", "slip_energy", lambda got, v, again: got - (v["M"] + v["m"]) * v["du"] ** 2 / 2),
    # The floor's normal force taken as the static weight (M + m) g while rocking.
    ("omd_stops", "stick_force", lambda got, v, again: (got[0], (v["M"] + v["m"]) * (v["g"] + v["agy"]))),
    # The tangential impulse of a sliding impact of the wrong sign.
    ("block", "impact_slide", lambda got, v, again: (*got[:2], -got[2], got[3])),
    # The old pivot's slip speed ignored in a sticking impact.
    ("omd_stops_hc", "impact_stick", lambda got, v, again: again(du=0 * v["du"])),
    # The shear of full contact without the guide's force on the block.
    ("omd_stops_hc", "contact_stick_force", lambda got, v, again: (v["M"] * v["ag"], got[1])),
]


@pytest.mark.parametrize("name, function, change", WRONG, ids=[f"{n}-{f}" for n, f, _ in WRONG])
def test_a_wrong_term_is_caught(models, name, function, change):
    model = models[name]
    checks = verify(model, n=CASES, seed=4, evaluate=_wrong(model, function, change))
    assert {c.function for c in checks if not c.ok} == {function}


def test_the_bumpers_regime_matters(models):
    """The friction functions of omd_stops evaluated as if no bumper acted: caught where one does."""
    model = models["omd_stops"]

    def evaluate(name, v):
        if name not in FRICTION:
            return _numpy_eval(model, name, v)
        fn = getattr(model.functions, name)
        inputs = [v[k] for k in model.manifest["functions"][name]["inputs"]]
        args = [v[k] for k in ("s", *model.state, "ag", "agy", *model.parameters)]
        off = (np.zeros_like(v["x"]),) * 2
        return fn(*args, *inputs, stop_on=off)

    bad = {c.function for c in verify(model, n=CASES, seed=5, evaluate=evaluate) if not c.ok}
    assert bad == {"slide_accel", "contact_slide_accel", "slide_uplift", "stick_force", "contact_stick_force"}


def test_a_nan_is_caught_where_the_reference_is_finite(models):
    """The bare block's rocking_accel reference is Housner's (it was 0/0 = NaN, and a NaN passed any check)."""
    model = models["block"]
    v = random_cases(np.random.default_rng(6), 50, 1, damper=False)
    with np.errstate(divide="ignore", invalid="ignore"):  # ddx, the massless mass's, is 0 / 0
        ref = paper.rocking_accel(
            *(v[k] for k in ("s", "theta", "x", "dtheta", "dx", "ag", "agy")),
            *(v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c")),
        )[0]
    d = v["B"] / 2 + v["e"]
    I_s = v["I_G"] + v["M"] * (d**2 + v["H"] ** 2 / 4)
    P = v["H"] / 2 * np.cos(v["theta"]) + d * np.sin(v["theta"])
    Q = d * np.cos(v["theta"]) - v["H"] / 2 * np.sin(v["theta"])
    assert rel_error(ref, v["M"] * ((v["ag"]) * P - (v["g"] + v["agy"]) * Q) / I_s) < 1e-13
    assert rel_error(ref * np.nan, ref) == np.inf and rel_error(ref, ref * np.nan) == np.inf
    nan = _wrong(model, "rocking_accel", lambda got, v, again: (got[0] * np.nan,))
    checks = verify(model, n=CASES, seed=7, evaluate=nan)
    assert {c.function for c in checks if not c.ok} == {"rocking_accel"}


def _case(seed, n, s, damper=True, stops=False):
    v = random_cases(np.random.default_rng(seed), n, s, damper, stops)
    v.update(friction_inputs(np.random.default_rng(seed + 100), n))
    return v


@pytest.mark.parametrize("s", [1, -1])
def test_the_damper_references_reduce_to_the_bare_blocks_closed_forms(s):
    """m = 0: slide_rock_accel is slide_rock_frame_accel (docs/model.md section 15's closed form), friction_impact
    is corner_impact (Newton-Euler with impulses solved by LAPACK), contact_slide_accel's a is -mu_slip g."""
    v = _case(11, 200, s, damper=False)
    args = [v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c")]
    with np.errstate(divide="ignore", invalid="ignore"):
        ddtheta, _, ddu, N = sliding.slide_rock_accel(
            s, v["theta"], v["x"], v["dtheta"], v["dx"], v["ag"], 0 * v["ag"], v["mu_slip"], *args
        )
    a = sliding.slide_rock_frame_accel(
        s, v["theta"], v["dtheta"], v["ag"], v["mu_slip"], v["M"], v["I_G"], v["B"], v["H"], v["e"], v["g"]
    )
    assert rel_error(v["ag"] + ddu, a) < 1e-12
    d = s * v["B"] / 2 + v["e"]
    P = v["H"] / 2 * np.cos(v["theta"]) + d * np.sin(v["theta"])
    Q = d * np.cos(v["theta"]) - v["H"] / 2 * np.sin(v["theta"])
    assert rel_error(N, v["M"] * (v["g"] + Q * ddtheta - P * v["dtheta"] ** 2)) < 1e-12
    with np.errstate(divide="ignore", invalid="ignore"):
        contact = sliding.contact_slide_accel(
            v["x"], v["dx"], v["ag"], 0.0, v["mu_slip"], v["M"], v["g"], 0.0, 0.0, 0.0
        )
    assert rel_error(v["ag"] + contact[2], -v["mu_slip"] * v["g"]) < 1e-13  # ddu = a - ddx_g, back in doubles
    zero = 0 * v["x"]
    for stick in (True, False):
        got = sliding.friction_impact(
            s,
            zero,
            v["dtheta"],
            zero,
            v["du"],
            v["mu_slip"],
            v["M"],
            v["I_G"],
            v["B"],
            v["H"],
            v["e"],
            zero,
            zero,
            stick=stick,
        )
        for i in range(50):
            ref = sliding.corner_impact(
                s,
                v["dtheta"][i],
                v["du"][i],
                v["mu_slip"][i],
                v["M"][i],
                v["I_G"][i],
                v["B"][i],
                v["H"][i],
                v["e"][i],
                stick=stick,
            )
            scale = abs(v["dtheta"][i]) * v["B"][i] + abs(v["du"][i])
            assert abs(got[0][i] - ref[0]) * v["B"][i] <= 1e-12 * scale
            assert abs(got[2][i] - ref[1]) <= 1e-12 * scale
            assert abs(got[3][i] - ref[2]) <= 1e-12 * v["M"][i] * scale
            assert abs(got[4][i] - ref[3]) <= 1e-12 * v["M"][i] * scale


@pytest.mark.parametrize("s", [1, -1])
def test_a_sticking_impact_from_rest_is_the_papers_and_sliding_keeps_coulombs_ratio(s):
    """du = 0 before and the corner sticking: (I1)-(I2) (paper.impact); sliding: P_t = -mu_slip P_n, and the
    mass's absolute horizontal velocity is the same after either."""
    v = _case(12, 300, s)
    body = [v[k] for k in ("M", "I_G", "B", "H", "e", "m", "h")]
    zero = 0 * v["x"]
    w, dx, du, P_t, P_n = sliding.friction_impact(s, v["x"], v["dtheta"], v["dx"], zero, v["mu_slip"], *body)
    ref = paper.impact(s, v["x"], v["dtheta"], v["dx"], *body)
    assert rel_error(w, ref[0]) < 1e-13 and rel_error(dx, ref[1]) < 1e-12 and np.all(du == 0)
    eta = v["H"] + v["h"]
    before = v["du"] - eta * v["dtheta"] + v["dx"]  # the mass's horizontal velocity, its arm (xi_s, eta)
    for stick in (True, False):
        w, dx, du, P_t, P_n = sliding.friction_impact(
            s, v["x"], v["dtheta"], v["dx"], v["du"], v["mu_slip"], *body, stick=stick
        )
        assert rel_error(du - eta * w + dx, before) < 1e-12
        if not stick:
            assert rel_error(P_t, -v["mu_slip"] * P_n) < 1e-13


@pytest.mark.parametrize("s", [1, -1])
def test_the_slip_energy_is_the_kinetic_energy_the_slip_adds(s):
    """slip_energy against the kinetic energy written from the bodies' absolute velocities: the block's
    (G's velocity and its spin) and the mass's, each with du added to the horizontal (paper.energy's T without)."""
    v = _case(13, 300, s)
    th, x, dth, dx, du = (v[k] for k in ("theta", "x", "dtheta", "dx", "du"))
    M, I_G, B, H, e, m, h = (v[k] for k in ("M", "I_G", "B", "H", "e", "m", "h"))
    d, xi = paper.arms(s, x, B, e)
    eta = H + h
    sin, cos = np.sin(th), np.cos(th)
    G = (-dth * (d * sin + H / 2 * cos), dth * (d * cos - H / 2 * sin))
    mass = (-dth * (xi * sin + eta * cos) + dx * cos, dth * (xi * cos - eta * sin) + dx * sin)

    def kinetic(slip):
        return (
            M * ((G[0] + slip) ** 2 + G[1] ** 2) / 2 + I_G * dth**2 / 2 + m * ((mass[0] + slip) ** 2 + mass[1] ** 2) / 2
        )

    assert rel_error(kinetic(0 * du), paper.energy(s, th, x, dth, dx, M, I_G, B, H, e, 0, m, h, 0)) < 1e-12
    assert (
        rel_error(sliding.slip_energy(s, th, x, dth, dx, du, M, B, H, e, m, h), kinetic(du) - kinetic(0 * du)) < 1e-11
    )


def test_the_stick_forces_hold_the_contact_at_zero_slip(models):
    """mu_slip equal to the friction the stick phase needs, -F / N of stick_force (by hand): the sliding phases'
    ddu is 0 and their N is the stick phase's, rocking and in full contact (omd with bumpers)."""
    v = _case(14, 300, 1, stops=True)
    body = [v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c")]
    stops = {k: v[k] for k in ("L", "k_b", "c_b")}
    state = [v[k] for k in ("theta", "x", "dtheta", "dx", "ag", "agy")]
    F, N = sliding.stick_force(1, *state, *body, **stops)
    ddtheta, ddx, ddu, N_slide = sliding.slide_rock_accel(1, *state[:-1], v["agy"], -F / N, *body, **stops)
    scale = np.abs(v["ag"]) + v["g"] + np.abs(ddtheta) * v["H"]
    assert np.max(np.abs(ddu) / scale) < 1e-11 and rel_error(N_slide, N) < 1e-11
    F, N = sliding.contact_stick_force(v["x"], v["dx"], v["ag"], v["agy"], *body, **stops)
    _, _, ddu, N_slide = sliding.contact_slide_accel(
        v["x"], v["dx"], v["ag"], v["agy"], -F / N, v["M"], v["g"], v["m"], v["k_m"], v["c"], **stops
    )
    assert np.max(np.abs(ddu) / (np.abs(v["ag"]) + v["g"])) < 1e-12 and rel_error(N_slide, N) < 1e-15


def test_model_md_quotes_the_count_verify_gives(models):
    """docs/model.md section 16 states how many functions and checks `rocking verify` has per model."""
    from pathlib import Path

    text = " ".join((Path(__file__).resolve().parent.parent / "docs" / "model.md").read_text("utf-8").split())
    for model in models.values():
        checks = verify(model, n=2, seed=1)
        assert f"{len(checks) // 2} functions per model, {len(checks)} checks" in text


def test_a_reference_that_is_zero_everywhere_agrees_only_with_zero():
    """rel_error has no scale where the reference is exactly 0 in every case: any other value is an infinite
    error, not none (the bare block's ddtheta in flight, a sticking corner's du after a landing)."""
    from rocking.reference.verify import rel_error

    assert rel_error(np.zeros(4), np.zeros(4)) == 0.0
    assert rel_error(np.array([0.0, 0.0, 1e-300, 0.0]), np.zeros(4)) == math.inf


def test_the_papers_functions_compared_at_the_size_of_their_terms_still_catch_a_change_of_1e_11():
    """The paper's functions are compared at the size of their terms too (the impact's momenta cancel): a change
    of 1e-11 of any of them is still a mismatch, and nothing else is."""
    model = load_model("omd")
    changed = ("mass_matrix", "forcing", "rocking_accel", "impact", "energy", "uplift")

    def evaluate(name, v):
        out = _numpy_eval(model, name, v)
        if name not in changed:
            return out
        return tuple(o * (1 + 1e-11) for o in out) if isinstance(out, tuple) else out * (1 + 1e-11)

    assert {c.function for c in verify(model, n=300, seed=8, evaluate=evaluate) if not c.ok} == set(changed)
