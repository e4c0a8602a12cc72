"""The shipped variants (block, omd, pendulum, omd2) and a user's own spec.

- the generated NumPy and C of ``pendulum`` and ``omd2`` against the equations
  derived by hand in ``tests/handwritten_variants.py``;
- the limits: no attached mass gives the bare block; a locked damper gives the
  rigid block carrying the mass;
- every variant on both back ends; a spec of one's own from the command line to
  ``rocking.simulate``; inconsistent specs refused before any derivation.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rocking
from rocking import load_model
from rocking.reference import paper
from rocking.reference.verify import TOLERANCE, random_cases, rel_error
from rocking.sim.problem import DTHETA_REST
from tests.handwritten_variants import HANDWRITTEN, Rigid

ROOT = Path(__file__).resolve().parent.parent
N = 500  # random states and parameter sets per pivot
BLOCK_PARAMS = ("M", "I_G", "B", "H", "e", "g")


# ----------------------------------------------------------------------------- random cases
def random_variant_cases(name: str, rng: np.random.Generator, n: int, s: int) -> dict[str, np.ndarray]:
    """``n`` random states and parameter sets of variant ``name`` rocking about ``s``.

    The block part is :func:`rocking.reference.verify.random_cases`; attached bodies from light
    to heavy (up to 30 % of the block), soft to stiff, damped up to 50 % critical.
    """
    v = random_cases(rng, n, s, damper=False)
    u = rng.uniform
    M, B, H = v["M"], v["B"], v["H"]
    if name == "pendulum":
        m, rod, omega = M * u(0.001, 0.3, n), H * u(0.05, 0.5, n), u(0.5, 30.0, n)
        v.update(
            m=m,
            l=rod,
            x_p=B * u(-0.5, 0.5, n),
            y_p=H * u(0.1, 1.3, n),
            k_phi=m * rod**2 * omega**2 * u(0.0, 1.0, n),
            c_phi=2 * m * rod**2 * omega * u(0.0, 0.5, n),
            phi=u(-2.5, 2.5, n),
            dphi=u(-5.0, 5.0, n),
        )
    elif name == "omd2":
        v["h"] = u(0.0, 0.5, n)
        for i in "12":
            m, omega = M * u(0.001, 0.2, n), u(0.5, 30.0, n)
            v.update(
                {
                    f"m{i}": m,
                    f"k{i}": m * omega**2,
                    f"c{i}": 2 * m * omega * u(0.0, 0.5, n),
                    f"x{i}": B * u(-0.4, 0.4, n),
                    f"dx{i}": u(-3.0, 3.0, n),
                }
            )
    elif name == "omd":
        v = random_cases(rng, n, s, damper=True)
    return v


#: The state each generated function is defined at (as in rocking.reference.verify).
_STATE_OF = {"contact_accel": "contact", "uplift": "contact", "impact": "impact"}


def _at(kind: str, v: dict) -> dict:
    zero = 0 * v["theta"]
    if kind == "contact":
        return dict(v, theta=zero, dtheta=zero)
    if kind == "impact":
        return dict(v, theta=zero)
    return v


def _numpy(name: str):
    model = load_model(name)

    def evaluate(function, v):
        fn = getattr(model.functions, function)
        return fn(v["s"], *(v[k] for k in model.state), v["ag"], v["agy"], *(v[k] for k in model.parameters))

    return evaluate


def _outputs(x) -> tuple:
    return x if isinstance(x, tuple) else (x,)


# ----------------------------------------------------------------------------- generated vs by hand
#: Generated functions with no hand-written counterpart, and why.
NOT_BY_HAND = {
    # The uplift function of the pendulum is not linear in (phi, dphi): the derivation
    # gives no bound and says so with 0 (the runtime then skips the early rest). Its potential
    # has cos(phi): not quadratic in phi, so no least potential either (-inf: no early verdict).
    "pendulum": {"uplift_energy", "least_potential", "least_stroke_potential"},
    "omd2": set(),
}


def _hand_errors(name: str, evaluate, seed: int) -> dict[tuple[str, int], float]:
    """Largest relative error of every generated function against the hand derivation, per pivot."""
    hand = HANDWRITTEN[name]
    functions = load_model(name).manifest["functions"]
    assert set(functions) - {f for f in functions if hasattr(hand, f)} == NOT_BY_HAND[name]
    rng = np.random.default_rng(seed)
    errors = {}
    for s in (1, -1):
        v = random_variant_cases(name, rng, N, s)
        for function in functions:
            if function in NOT_BY_HAND[name]:
                continue
            case = _at(_STATE_OF.get(function, "rocking"), v)
            # The reference in extended precision: the error measured is the generated code's.
            ref = _outputs(getattr(hand, function)({k: np.asarray(a, np.longdouble) for k, a in case.items()}))
            got = _outputs(evaluate(function, case))
            assert len(got) == len(ref), function
            errors[function, s] = max((rel_error(a, b) for a, b in zip(got, ref)), default=0.0)
    return errors


@pytest.mark.parametrize("name", ["pendulum", "omd2"])
def test_generated_numpy_matches_hand_derivation(name):
    errors = _hand_errors(name, _numpy(name), seed=11)
    bad = {k: f"{e:.2e}" for k, e in errors.items() if not e <= TOLERANCE}
    assert not bad, bad


@pytest.mark.parametrize("name", ["pendulum", "omd2"])
def test_generated_c_matches_hand_derivation(name, c_model):
    """The generated C, compiled with -std=c99 -Wall -Wextra -Werror -pedantic."""
    errors = _hand_errors(name, c_model(name), seed=12)
    bad = {k: f"{e:.2e}" for k, e in errors.items() if not e <= TOLERANCE}
    assert not bad, bad


def test_hand_derivation_matches_the_sketch_of_the_pendulum():
    """The energy written from absolute velocities equals the issue's closed form of T_bob, Y_bob."""
    from tests.handwritten_variants import Pendulum

    rng = np.random.default_rng(3)
    for s in (1, -1):
        v = {k: np.asarray(a, np.longdouble) for k, a in random_variant_cases("pendulum", rng, 200, s).items()}
        a, b = v["x_p"] + s * v["B"] / 2, v["y_p"]
        th, phi, dth, w = v["theta"], v["phi"], v["dtheta"], v["dtheta"] + v["dphi"]
        kappa = a * np.sin(phi) - b * np.cos(phi)
        T_bob = v["m"] / 2 * (dth**2 * (a**2 + b**2) + v["l"] ** 2 * w**2 + 2 * v["l"] * dth * w * kappa)
        Y_bob = a * np.sin(th) + b * np.cos(th) - v["l"] * np.cos(th + phi)
        d = s * v["B"] / 2 + v["e"]
        I_s = v["I_G"] + v["M"] * (d**2 + v["H"] ** 2 / 4)
        E = I_s * dth**2 / 2 + T_bob + v["g"] * (v["M"] * (d * np.sin(th) + v["H"] / 2 * np.cos(th)) + v["m"] * Y_bob)
        assert rel_error(Pendulum.energy(v), E + v["k_phi"] * phi**2 / 2) < 1e-15


# ----------------------------------------------------------------------------- vanishing masses
#: Parameters that remove every attached body (springs and dashpots too: a massless
#: body on a spring has no dynamics).
MASSLESS = {
    "omd": dict(m=0.0, k_m=0.0, c=0.0),
    "pendulum": dict(m=0.0, k_phi=0.0, c_phi=0.0),
    "omd2": dict(m1=0.0, k1=0.0, c1=0.0, m2=0.0, k2=0.0, c2=0.0),
}
#: (function, kind of state, output compared): everything that concerns theta.
BLOCK_OUTPUTS = [
    ("rocking_accel", "rocking", 0),
    ("uplift", "contact", 0),
    ("impact", "impact", 0),
    ("energy", "rocking", 0),
    ("power", "rocking", 0),
    ("critical_angle", "rocking", 0),
    ("critical_tangent", "rocking", 0),
]


@pytest.mark.parametrize("name", ["omd", "pendulum", "omd2"])
def test_variant_without_attached_mass_is_the_bare_block(name, c_model):
    """omd at m = 0, pendulum at m = 0, omd2 at m1 = m2 = 0 (any position and speed of the
    massless bodies) give the block model's ddtheta, uplift, impact, energy, power, critical angle."""
    rng = np.random.default_rng(21)
    block = _numpy("block")
    for s in (1, -1):
        v = dict(random_variant_cases(name, rng, N, s), **{k: np.zeros(N) for k in MASSLESS[name]})
        for evaluate in (_numpy(name), c_model(name)):
            for function, kind, i in BLOCK_OUTPUTS:
                case = _at(kind, v)
                got = _outputs(evaluate(function, case))[i]
                ref = _outputs(block(function, case))[i]
                assert np.all(np.isfinite(got)), (name, function, s)
                assert rel_error(got, ref) <= TOLERANCE, (name, function, s, rel_error(got, ref))


# ----------------------------------------------------------------------------- locked damper
BLOCK = rocking.Block(H=2.0, B=0.5, M=1000.0, e=0.025)
MASS, H_GUIDE, ROD, ZETA = 50.0, 0.05, 0.3, 0.2


def _locked_dampers(omega: float) -> dict[str, dict]:
    """The omd mass at (0, H + h) and a pendulum hinged at (0, H + h + l), its bob hanging
    at (0, H + h), both with the horizontal stiffness m omega^2 and damping ratio ZETA."""
    k, c = MASS * omega**2, 2 * MASS * omega * ZETA
    return {
        "omd": dict(m=MASS, h=H_GUIDE, k_m=k, c=c),
        # A tip displacement l phi stretches the rotational spring as k (l phi)^2 / 2.
        "pendulum": dict(m=MASS, l=ROD, x_p=0.0, y_p=BLOCK.H + H_GUIDE + ROD, k_phi=k * ROD**2, c_phi=c * ROD**2),
    }


def simulate_rigid(block, m, x_m, y_m, pulse, t_max, dtheta_rest):
    """The block carrying ``m`` rigidly at ``(x_m, y_m)`` under ``pulse``: an event-driven
    integration of the hand-written :class:`Rigid` equations (full contact until the uplift
    function turns positive, rocking until theta = 0, impact, rest when ``|dtheta+| <
    dtheta_rest``, overturning at ``|theta| = pi/2``). Returns ``(overturned, theta_max)``."""
    M, I_G, B, H, e, g = block.M, block.I_G, block.B, block.H, block.e, block.g

    def ag(t):
        return pulse.a_g * math.sin(pulse.omega_g * t + pulse.psi) if 0.0 <= t <= pulse.t_p else 0.0

    def uplift(s, a):
        return Rigid.uplift(s, a, M, B, H, e, g, m, x_m, y_m)

    def accel(s, theta, dtheta, a):
        return Rigid.rocking_accel(s, theta, dtheta, a, M, I_G, B, H, e, g, m, x_m, y_m)

    t, s, dth, theta_max = 0.0, 0, 0.0, 0.0
    while True:
        if s == 0:  # full contact: the rigid body has no dynamics, only the uplift watch
            first = _first_uplift(t, pulse, ag, uplift) if t < pulse.t_p else None
            if first is None:
                return False, theta_max
            (t, s), dth = first, 0.0
        sol, peak = _rocking_phase(s, t, dth, [x for x in (pulse.t_p, t_max) if x > t], ag, accel)
        theta_max = max(theta_max, peak)
        if sol is None:
            return False, theta_max
        if sol.t_events[1].size:
            return True, math.pi / 2
        t = sol.t_events[0][0]
        dth = Rigid.impact(s, sol.y_events[0][0][1], M, I_G, B, H, e, m, x_m, y_m)
        s = 0 if abs(dth) < dtheta_rest else -s
        if t >= t_max:
            return False, theta_max


def _first_uplift(t0, pulse, ag, uplift):
    """``(time, pivot)`` of the first uplift in full contact from ``t0`` to the pulse's end, or None:
    ``uplift(s, ag)`` scanned on a fine grid, its first positive value refined by bisection."""
    ts = np.linspace(t0, pulse.t_p, 20001)
    ag_ts = pulse.a_g * np.sin(pulse.omega_g * ts + pulse.psi)
    first = None
    for s in (1, -1):
        hit = np.flatnonzero(uplift(s, ag_ts) > 0)
        if not hit.size:
            continue
        j = hit[0]
        tu = ts[0]
        if j > 0:
            lo, hi = ts[j - 1], ts[j]
            for _ in range(60):
                mid = (lo + hi) / 2
                lo, hi = (lo, mid) if uplift(s, ag(mid)) > 0 else (mid, hi)
            tu = hi
        if first is None or tu < first[0]:
            first = (tu, s)
    return first


def _rocking_phase(s, t, dtheta, stops, ag, accel):
    """Rocking about ``s`` from ``theta = 0``, ``dtheta`` at ``t``, integrated through the breakpoints ``stops``.

    Returns the solution that ended on landing or overturning (None when the last stop came
    first) and the largest ``|theta|`` of its peaks."""

    def rhs(tt, y):
        return [y[1], accel(s, y[0], y[1], ag(tt))]

    def land(tt, y):
        return s * y[0]

    def over(tt, y):
        return abs(y[0]) - math.pi / 2

    def peak(tt, y):
        return y[1]

    land.terminal, land.direction = True, -1
    over.terminal, over.direction = True, 1
    y, theta_max = [0.0, dtheta], 0.0
    for t_stop in stops:
        sol = solve_ivp(rhs, (t, t_stop), y, method="DOP853", rtol=1e-11, atol=1e-13, events=(land, over, peak))
        theta_max = max([theta_max] + [abs(ye[0]) for ye in sol.y_events[2]])
        if sol.status == 1:
            return sol, theta_max
        t, y = sol.t[-1], sol.y[:, -1]
    return None, theta_max


def test_rigid_reference_is_the_omd_equations_with_the_mass_held():
    """The locked-rigid equations are omd's (R1) at x = dx = ddx = 0, the velocity impact law of
    docs/model.md section 6 at x = 0, and omd's critical angle at x = 0."""
    rng = np.random.default_rng(4)
    for s in (1, -1):
        v = random_cases(rng, 200, s)
        M, I_G, B, H, e, g, m, h = (v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h"))
        x0 = np.zeros_like(M)
        (m11, _), _ = paper.mass_matrix(s, v["theta"], x0, M, I_G, B, H, e, m, h)
        f1, _ = paper.forcing(s, v["theta"], x0, v["dtheta"], x0, v["ag"], x0, M, B, H, e, g, m, h, x0, x0)
        got = Rigid.rocking_accel(s, v["theta"], v["dtheta"], v["ag"], M, I_G, B, H, e, g, m, x0, H + h)
        assert rel_error(got, f1 / m11) < 1e-13
        ref = paper.impact(s, x0, v["dtheta"], x0, M, I_G, B, H, e, m, h, law="velocity")[0]
        assert rel_error(Rigid.impact(s, v["dtheta"], M, I_G, B, H, e, m, x0, H + h), ref) < 1e-13
        ref = paper.critical_angle(s, x0, M, B, H, e, m, h)
        assert rel_error(Rigid.critical_angle(s, M, B, H, e, m, x0, H + h), ref) < 1e-13
        # Uplift: -s times the moment the ground must add to hold theta = 0, the mass held
        # (omd's own uplift differs: there the mass slides in full contact).
        f1, _ = paper.forcing(s, x0, x0, x0, x0, v["ag"], x0, M, B, H, e, g, m, h, x0, x0)
        assert rel_error(Rigid.uplift(s, v["ag"], M, B, H, e, g, m, x0, H + h), s * f1) < 1e-13


OMEGAS = (30.0, 300.0, 3000.0)  # rad/s: the stiffness grows 100x per step (omega_p / p ~ 11, 110, 1100)


def test_locked_pendulum_and_omd_tend_to_the_rigid_block_carrying_the_mass():
    """theta_max of the pendulum and of omd, both locked by a stiff spring, converge to each
    other and to the hand-written rigid block with the mass: the difference shrinks more
    than 10x each time the stiffness grows 100x, on both back ends."""
    pulse = rocking.OneSinePulse.from_nondim(BLOCK, beta=2.0, Omega=6.0)  # rocks, 11 impacts, survives
    t_max = pulse.t_p + 5.0
    rest = DTHETA_REST * BLOCK.alpha * BLOCK.p
    over, rigid = simulate_rigid(BLOCK, MASS, 0.0, BLOCK.H + H_GUIDE, pulse, t_max, rest)
    assert not over and rigid > 0.3 * BLOCK.alpha
    theta = {}
    for omega in OMEGAS:
        for name, damper in _locked_dampers(omega).items():
            backends = ("c", "numpy") if omega < 1000 else ("c",)  # NumPy is slow on the stiffest
            runs = [rocking.simulate(BLOCK, damper, pulse, model=name, backend=b, t_max=t_max) for b in backends]
            for r in runs:
                assert not r.overturned
                assert r.theta_max == pytest.approx(runs[0].theta_max, rel=1e-6)
            theta[name, omega] = runs[0].theta_max
    to_rigid = {name: [abs(theta[name, w] - rigid) for w in OMEGAS] for name in ("omd", "pendulum")}
    between = [abs(theta["omd", w] - theta["pendulum", w]) for w in OMEGAS]
    for d in to_rigid.values():
        assert d[1] < d[0] / 10 and d[2] < d[1] / 10, to_rigid
    assert max(d[2] for d in to_rigid.values()) < 1e-5 * rigid
    # Between the two dampers, the stiffest pair is already at the integrators' tolerance.
    assert between[1] < between[0] / 10 and between[2] < max(between[1] / 10, 1e-8), between


def _threshold(overturns, lo: float, hi: float, tol: float = 1e-6) -> float:
    """The amplitude at which ``overturns(beta)`` switches, by bisection in ``[lo, hi]``."""
    assert not overturns(lo) and overturns(hi)
    while hi - lo > tol:
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if overturns(mid) else (mid, hi)
    return (lo + hi) / 2


def test_locked_dampers_converge_to_the_rigid_overturning_verdict():
    """The overturning threshold beta* (Omega = 6) of the locked pendulum and of the locked omd
    tends to the rigid block's: the distance shrinks more than 10x as the stiffness grows 100x.
    0.3 % above the rigid threshold, where the rigid block overturns, the softest locked
    dampers still save the block and the stiffer ones overturn like the rigid block."""
    Omega, t_after = 6.0, 5.0
    rest = DTHETA_REST * BLOCK.alpha * BLOCK.p

    def pulse(beta):
        return rocking.OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega)

    def rigid_over(beta):
        p = pulse(beta)
        return simulate_rigid(BLOCK, MASS, 0.0, BLOCK.H + H_GUIDE, p, p.t_p + t_after, rest)[0]

    def damper_over(name, omega, backend="c"):
        damper = _locked_dampers(omega)[name]
        return lambda beta: (
            rocking.simulate(BLOCK, damper, pulse(beta), model=name, backend=backend, t_after=t_after).overturned
        )

    rigid = _threshold(rigid_over, 2.7, 2.95)
    gaps = {
        name: [abs(_threshold(damper_over(name, w), 2.7, 2.95) - rigid) for w in OMEGAS] for name in ("omd", "pendulum")
    }
    for name, d in gaps.items():  # measured: 2.2e-2, 3.1e-4, 4e-6
        assert d[0] > 1e-2 and d[1] < d[0] / 10 and d[2] < max(d[1] / 10, 5e-6), (name, rigid, gaps)
    beta = rigid * 1.003
    assert rigid_over(beta)
    for name in ("omd", "pendulum"):
        verdicts = [damper_over(name, w, b)(beta) for w in OMEGAS[:2] for b in ("c", "numpy")]
        verdicts.append(damper_over(name, OMEGAS[2])(beta))
        assert verdicts == [False, False, True, True, True], (name, verdicts)


# ----------------------------------------------------------------------------- both back ends
#: A damper of each variant by parameter name (rocking.load_model(name).parameters).
DAMPERS = {
    "block": {},
    "omd": dict(m=50.0, h=0.05, k_m=350.0, c=13.0),
    "pendulum": dict(m=50.0, l=0.4, x_p=0.05, y_p=2.3, k_phi=60.0, c_phi=8.0),
    "omd2": dict(m1=40.0, h=0.05, k1=300.0, c1=11.0, m2=30.0, k2=500.0, c2=9.0),
}
#: (beta, Omega): rocking that survives, rocking close to the limit, overturning.
PULSES = [(1.5, 5.0), (2.5, 6.0), (3.0, 4.0)]


@pytest.mark.parametrize("name", sorted(DAMPERS))
def test_every_variant_runs_on_both_back_ends(name):
    model = load_model(name)
    assert set(DAMPERS[name]) == set(model.parameters) - set(BLOCK_PARAMS)
    verdicts = []
    for beta, Omega in PULSES:
        pulse = rocking.OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega)
        c, n = (
            rocking.simulate(BLOCK, DAMPERS[name], pulse, model=name, backend=b, t_after=6.0) for b in ("c", "numpy")
        )
        assert (c.overturned, c.impacts, c.uplifts, c.status) == (n.overturned, n.impacts, n.uplifts, n.status)
        assert c.theta_max == pytest.approx(n.theta_max, rel=1e-6)
        assert c.x_max == pytest.approx(n.x_max, rel=1e-5, abs=1e-9)
        assert c.impacts > 0  # every case rocks (the last overturns after an impact)
        verdicts.append(c.overturned)
    assert verdicts == [False, False, True]


# ----------------------------------------------------------------------------- specs
def _derive_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "rocking.derive", *args], cwd=ROOT, capture_output=True, text=True)


_GOOD_BODY = '[[bodies]]\nname = "mass"\nmass = "m"\nposition = ["x", "H/2"]\n'
_GOOD_SPRING = '[[springs]]\nstiffness = "k"\nstretch = "x"\nacts_on = "mass"\n'


@pytest.mark.parametrize(
    "coordinates, body, spring, message",
    [
        ('["x", "z"]', _GOOD_BODY, _GOOD_SPRING, "coordinate(s) z appear in no energy"),
        ('["x"]', _GOOD_BODY.replace('"m"', "-2"), _GOOD_SPRING, "body 'mass': mass must be >= 0, got -2"),
        ('["x"]', _GOOD_BODY, _GOOD_SPRING.replace('"mass"', '"bob"'), "acts on unknown body 'bob'; bodies are mass"),
    ],
    ids=["unused-coordinate", "negative-mass", "unknown-body"],
)
def test_command_line_rejects_an_inconsistent_spec_before_deriving(tmp_path, coordinates, body, spring, message):
    bad = tmp_path / "bad.toml"
    bad.write_text(f'name = "bad"\ncoordinates = {coordinates}\n[parameters.m]\n[parameters.k]\n{body}{spring}')
    out = tmp_path / "out"
    run = _derive_cli("--spec", str(bad), "--out", str(out))
    assert run.returncode == 2, run.stdout + run.stderr
    assert run.stderr.startswith("error: ") and message in run.stderr, run.stderr
    assert "derived in" not in run.stdout and not out.exists()


#: A user's own model: a mass on a guide through the middle of the block, inclined by incl.
#: The spring is preloaded by the mass's weight along the guide, so that u = 0 is the rest
#: state in full contact (the simulator measures the energy above rest from q = 0).
INCLINED = """\
name = "incline"
title = "Rigid block with a mass on an inclined guide at mid-height"
coordinates = ["u"]

[parameters.m]
unit = "kg"
doc = "sliding mass"
[parameters.k]
unit = "N/m"
doc = "spring along the guide"
[parameters.c]
unit = "N s/m"
doc = "dashpot along the guide"
[parameters.incl]
unit = "rad"
doc = "inclination of the guide (counter-clockwise from horizontal)"
valid = "any"

[[bodies]]
name = "slider"
mass = "m"
position = ["u*cos(incl)", "H/2 + u*sin(incl)"]

[[springs]]
stiffness = "k"
stretch = "u - m*g*sin(incl)/k"
acts_on = "slider"

[[dashpots]]
damping = "c"
rate_of = "u"
acts_on = "slider"
"""


def test_a_user_spec_is_built_and_simulated_from_its_folder(tmp_path):
    spec = tmp_path / "incline.toml"
    spec.write_text(INCLINED)
    folder = tmp_path / "models" / "incline"
    run = _derive_cli("--spec", str(spec), "--out", str(folder))
    assert run.returncode == 0, run.stderr
    assert "incline: derived in" in run.stdout
    assert {"manifest.json", "model.py", "incline.c", "incline.h", "EQUATIONS.md"} <= {p.name for p in folder.iterdir()}
    sections = re.findall(r"^## `(\w+)`$", (folder / "EQUATIONS.md").read_text(), re.M)
    assert sorted(sections) == sorted(load_model(folder).manifest["functions"])
    model = load_model(folder)
    assert model.coordinates == ("theta", "u") and model.parameters[-4:] == ("m", "k", "c", "incl")

    # A horizontal guide is the paper's omd with its guide at mid-height (h = -H/2).
    rng = np.random.default_rng(8)
    for s in (1, -1):
        v = random_cases(rng, 300, s)
        # Its preload holds g beside the weights: the model takes no vertical ground motion.
        assert not model.manifest["vertical"]
        v.update(u=v["x"], du=v["dx"], k=v["k_m"], incl=np.zeros(300), h=-v["H"] / 2, agy=np.zeros(300))
        L = {key: np.asarray(a, np.longdouble) for key, a in v.items()}
        args = (L["M"], L["I_G"], L["B"], L["H"], L["e"], L["g"], L["m"], L["h"], L["k_m"], L["c"])
        x, dth, dx, ag, agy, th = L["x"], L["dtheta"], L["dx"], L["ag"], L["agy"], L["theta"]
        M, I_G, B, H, e, g, m, h, k, c = args
        refs = {
            "rocking_accel": paper.rocking_accel(s, th, x, dth, dx, ag, agy, *args),
            "impact": paper.impact(s, x, dth, dx, M, I_G, B, H, e, m, h),
            "uplift": (paper.uplift_margin(s, x, dx, ag, agy, M, B, H, e, g, m, h, k, c),),
        }
        f = _numpy_model(model)
        for function, ref in refs.items():
            got = _outputs(f(function, _at(_STATE_OF.get(function, "rocking"), v)))
            assert max(rel_error(a, b) for a, b in zip(got, ref)) <= TOLERANCE, function

    # Inclined by 0.3 rad: the preload makes u = 0 the rest state, and the energy above it
    # quadratic, so the derivation finds the least energy that can lift the block.
    damper = dict(m=60.0, k=400.0, c=15.0, incl=0.3)
    p = model.param_vector(dict(BLOCK.as_params(), **damper))
    for s in (1.0, -1.0):
        assert model.call("contact_accel", s, np.zeros(4), 0.0, p)[1] == pytest.approx(0.0, abs=1e-12)
        assert 0 < model.call("uplift_energy", s, np.zeros(4), 0.0, p) < np.inf
    # Run from the folder on both back ends.
    for beta, Omega, overturns in ((1.5, 5.0, False), (3.0, 4.0, True)):
        pulse = rocking.OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega)
        c, n = (
            rocking.simulate(BLOCK, damper, pulse, model=str(folder), backend=b, t_after=6.0) for b in ("c", "numpy")
        )
        assert c.overturned == n.overturned == overturns
        assert (c.impacts, c.uplifts) == (n.impacts, n.uplifts) and c.impacts > 0
        assert c.theta_max == pytest.approx(n.theta_max, rel=1e-6)

    # Its preload holds g beside the weights: vertical ground motion is refused, not run wrong.
    shaken = rocking.OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0, vertical=rocking.Vertical(0.5))
    with pytest.raises(rocking.ParameterError, match="takes no vertical ground motion"):
        rocking.simulate(BLOCK, damper, shaken, model=str(folder))


def _numpy_model(model):
    def evaluate(function, v):
        return getattr(model.functions, function)(
            v["s"], *(v[k] for k in model.state), v["ag"], v["agy"], *(v[k] for k in model.parameters)
        )

    return evaluate
