"""The contract of docs/simulation.md, held on both back ends with the same inputs and assertions.

Every test takes the ``backend`` fixture (``"numpy"``, ``"c"``) and runs the
same :class:`~rocking.sim.problem.Problem` through
:func:`rocking.sim.run.run` (or the public :func:`rocking.simulate`; one test
calls each back end's own ``simulate(problem)``); a test that fails on one
back end only is a drift between them. The sections follow
docs/simulation.md: "Initial state", "Phases" rules 1 to 4, "Integration",
"History", and the settings of its table.

Expected values come from outside the code, as cited at each test:
docs/model.md section 10 (10.1 Housner's restitution, 10.2 uplift
thresholds, 10.3 free rocking, 10.4 overturning without impact, 10.6 mirror
symmetry), the closed forms of docs/model.md sections 2 (energy in full
contact), 4 (C1, the damper in full contact), 5 (U1, U2 and the uplift
energy) and 7 (critical angle), the exact solution of the damper's linear
oscillator (its eigenvectors) and SciPy's DOP853 at tight tolerance.
Nothing expected is read from either back end.

What only one back end has (the C build, batches, threads, shortcuts, the
history buffer) is in ``tests/test_c_backend.py``; the two back ends on random
cases against each other are in ``tests/test_agreement.py``.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import rocking
from rocking import Block, Damper, OneSinePulse, ParameterError, load_model
from rocking.sim import c_backend, numpy_backend
from rocking.sim.history import FLIGHT_COLUMNS, FLOOR_COLUMNS
from rocking.sim.problem import CONTACT, STATUS, default_settings, make_problem
from rocking.sim.run import run

BACKENDS = ("numpy", "c")

REFERENCE = Block.reference()  # H = 2 m, B = 0.5 m, e = 0.025 m: the two corners' thresholds differ
DAMPER = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)


@pytest.fixture(params=BACKENDS)
def backend(request) -> str:
    return request.param


def simulate(backend: str, problem, record: bool = False):
    """``problem`` on ``backend``: the one way every test of this module runs a problem."""
    return run(problem, backend=backend, record=record)


def slender_block(alpha: float = 0.02, p: float = 2.0) -> Block:
    """Bare symmetric homogeneous block: the subject of the linearised theory (docs/model.md 10.3, 10.4)."""
    return Block.from_nondim(p=p, alpha=alpha)


def no_pulse(block: Block, Omega: float = 1.0) -> OneSinePulse:
    """Zero ground motion (the pulse's length still sets the breakpoint ``t_p``)."""
    return OneSinePulse.from_nondim(block, beta=0.0, Omega=Omega)


def reference_problem(beta, Omega, damper=None, psi=0.0, **settings):
    """A one-sine pulse on the reference block, with or without a damper."""
    pulse = OneSinePulse.from_nondim(REFERENCE, beta=beta, Omega=Omega, psi=psi)
    return make_problem(REFERENCE, damper, pulse, **settings)


def transitions(history: dict) -> list[tuple[int, int]]:
    """Index pairs ``(j - 1, j)`` of consecutive history rows where the phase changes."""
    phase = history["phase"]
    return [(j - 1, j) for j in range(1, len(phase)) if phase[j] != phase[j - 1]]


def first_uplift(history: dict) -> tuple[float, int]:
    """Time and pivot of the first row that is not full contact."""
    j = int(np.nonzero(history["phase"] != CONTACT)[0][0])
    return float(history["t"][j]), int(history["phase"][j])


def same(a, b) -> bool:
    """Bitwise-equal values, NaN included."""
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


#: Units in the last place of a pulse's amplitude within which C's libm and NumPy's vectorised sin, cos and exp
#: agree: which of the two rounds a last bit differently depends on the CPU (seen: 8.9e-16 m/s^2 on an AMD EPYC).
ULPS = 8


def assert_same_pulse(ag, problem, t) -> None:
    """``ag`` recorded by a back end at ``t`` is the pulse NumPy evaluates, to :data:`ULPS` of its amplitude."""
    expected = np.asarray(problem.ground_acceleration(t), float)
    scale = max(float(np.max(np.abs(expected), initial=0.0)), abs(float(problem.a_g)))
    np.testing.assert_allclose(ag, expected, rtol=0, atol=ULPS * np.spacing(scale))


def check_history(response, problem) -> None:
    """What every history must satisfy (docs/simulation.md, "History"; rules 1 to 3)."""
    h = response.history
    model = problem.model
    # The floor's columns on a floor with friction, and on every floor for a model with flight (its v, dv, fly too).
    flies = bool(model.manifest.get("flight", False))
    floor = [*FLOOR_COLUMNS, *(FLIGHT_COLUMNS if flies else ())] if flies or math.isfinite(problem.mu_s) else []
    assert list(h) == ["t", *model.state, "phase", "ag", *floor]
    n = len(h["t"])
    assert all(len(v) == n for v in h.values())
    t, phase = h["t"], h["phase"]
    theta, dtheta = h[model.state[0]], h[model.state[model.nq]]
    assert t[0] == 0.0 and t[-1] == response.t_end
    assert np.all(np.diff(t) >= 0)  # time order
    if problem.record_dt > 0:  # samples every record_dt at least
        assert np.max(np.diff(t)) <= problem.record_dt * (1 + 1e-9)
    assert set(np.unique(phase)) <= {CONTACT, 1, -1}
    contact = phase == CONTACT
    assert np.all(theta[contact] == 0.0) and np.all(dtheta[contact] == 0.0)  # rule 1: held
    assert np.all(phase[~contact] * theta[~contact] >= -1e-12)  # rule 2: s theta >= 0 about s
    assert_same_pulse(h["ag"], problem, t)  # ag is the pulse
    assert np.max(np.abs(theta)) <= response.theta_max
    if model.nq > 1:
        assert np.max(np.abs(h[model.state[1]])) <= response.x_max
    if response.t_end > problem.t_p:
        assert problem.t_p in t  # rule 3: the pulse's end is a breakpoint, an exact row


def impact_rows(history: dict) -> list[int]:
    """Rows ``i`` recorded just before an impact: ``(i, i + 1)`` at one instant, out of a rocking phase (not a
    takeoff or a landing: a history of a model with flight marks its rows in flight, ``fly``)."""
    t, phase = history["t"], history["phase"]
    fly = history.get("fly", np.zeros_like(t))
    return [i for i in np.flatnonzero(np.diff(t) == 0) if phase[i] != CONTACT and fly[i] == fly[i + 1] == 0.0]


# --------------------------------------------------------------------------- #
# The damper in full contact: docs/model.md (C1), (U1), (U2) and 5 in closed form   #
# --------------------------------------------------------------------------- #


def contact_motion(damper: Damper, x0: float, v0: float):
    """``(x(t), dx(t))`` of (C1) without ground motion: the free damped oscillator."""
    w, zeta = damper.omega_m, damper.zeta
    wd = w * math.sqrt(1 - zeta**2)
    a, b = x0, (v0 + zeta * w * x0) / wd

    def motion(t):
        decay = math.exp(-zeta * w * t)
        x = decay * (a * math.cos(wd * t) + b * math.sin(wd * t))
        dx = -zeta * w * x + decay * wd * (-a * math.sin(wd * t) + b * math.cos(wd * t))
        return x, dx

    return motion


def predicted_uplift(block: Block, damper: Damper, x0: float, v0: float, horizon: float) -> tuple[float, int]:
    """First time (U1) or (U2) holds for the mass oscillating on the block at rest (ag = 0)."""
    motion = contact_motion(damper, x0, v0)
    M, B, e, g = block.M, block.B, block.e, block.g
    m, k, c, eta = damper.m, damper.k_m, damper.c, block.H + damper.h

    def margins(t):
        x, dx = motion(t)
        moment = -eta * (k * x + c * dx)  # Mo with ddx_g = 0
        return (moment - g * (M * (B / 2 + e) + m * (B / 2 + x)), -moment - g * (M * (B / 2 - e) + m * (B / 2 - x)))

    grid = np.linspace(0.0, horizon, 4001)
    values = np.array([margins(t) for t in grid])  # column 0: about A, column 1: about A'
    assert np.all(values[0] < 0), "the block must start at rest"
    first = []
    for index, pivot in ((0, 1), (1, -1)):
        above = np.nonzero(values[:, index] > 0)[0]
        if above.size:
            i = above[0]
            t_up = brentq(lambda t, index=index: margins(t)[index], grid[i - 1], grid[i], xtol=1e-14)
            first.append((t_up, pivot))
    return min(first)


def least_uplift_energy(block: Block, damper: Damper) -> float:
    """Least damper energy ``k x^2/2 + m dx^2/2`` on which (U1) or (U2) can hold without ground motion.

    docs/model.md section 5: both read ``u0 + a_x x + a_v dx > 0``; on the line
    ``u = 0`` the least energy is ``u0^2 / (2 (a_x^2 / k + a_v^2 / m))``.
    """
    M, B, e, g = block.M, block.B, block.e, block.g
    m, k, c, eta = damper.m, damper.k_m, damper.c, block.H + damper.h
    a_x, a_v = eta * k + m * g, eta * c
    u0 = [g * (M * (B / 2 + s * e) + m * B / 2) for s in (1, -1)]
    return min(u**2 / (2 * (a_x**2 / k + a_v**2 / m)) for u in u0)


def damper_energy(damper: Damper, x, dx):
    """docs/model.md section 2: in full contact the energy above rest is the damper's own."""
    return 0.5 * damper.k_m * x**2 + 0.5 * damper.m * dx**2


def extremum_times(damper: Damper, count: int) -> list[float]:
    """The first ``count`` extrema of ``x = v0 / wd exp(-zeta w t) sin(wd t)``: ``tan(wd t) = wd / (zeta w)``."""
    w, zeta = damper.omega_m, damper.zeta
    wd = w * math.sqrt(1 - zeta**2)
    return [(math.atan2(wd, zeta * w) + k * math.pi) / wd for k in range(count)]


# =========================================================================== #
# Initial state                                                                #
# =========================================================================== #

#: Every refused initial state and its message: (damper, y0, phase0, message).
REFUSED_INITIAL_STATES = {
    "rocking without y0": (None, None, 1, "phase0 = +1 (rocking) needs an initial state y0 with s theta >= 0"),
    "rocking about A' without y0": (
        None,
        None,
        -1,
        "phase0 = -1 (rocking) needs an initial state y0 with s theta >= 0",
    ),
    "phase0 2": (None, [0.0, 0.0], 2, "phase0 must be -1, 0 or +1 (got 2)"),
    "phase0 not an integer": (None, [0.0, 0.0], 0.5, "phase0 must be -1, 0 or +1 (got 0.5)"),
    "y0 too long": (
        None,
        [0.0, 0.0, 0.0],
        0,
        "y0 must hold 2 finite numbers ('theta', 'dtheta') (got [0.0, 0.0, 0.0])",
    ),
    "y0 too short with a damper": (
        DAMPER,
        [0.0, 0.0],
        0,
        "y0 must hold 4 finite numbers ('theta', 'x', 'dtheta', 'dx') (got [0.0, 0.0])",
    ),
    "y0 not finite": (
        DAMPER,
        [0.0, math.nan, 0.0, 0.0],
        0,
        "y0 must hold 4 finite numbers ('theta', 'x', 'dtheta', 'dx') (got [0.0, nan, 0.0, 0.0])",
    ),
    "y0 infinite": (None, [math.inf, 0.0], 1, "y0 must hold 2 finite numbers ('theta', 'dtheta') (got [inf, 0.0])"),
    "y0 not numbers": (None, "ab", 0, "y0 must hold 2 finite numbers ('theta', 'dtheta') (got 'ab')"),
    "contact with theta": (
        None,
        [0.01, 0.0],
        0,
        "y0: full contact (phase0 = 0) needs theta = dtheta = 0 (got theta = 0.01, dtheta = 0.0)",
    ),
    "contact with dtheta": (
        DAMPER,
        [0.0, 0.1, -0.2, 0.3],
        0,
        "y0: full contact (phase0 = 0) needs theta = dtheta = 0 (got theta = 0.0, dtheta = -0.2)",
    ),
    "about A' with theta > 0": (
        None,
        [0.01, 0.0],
        -1,
        "y0: rocking about phase0 = -1 needs phase0 * theta >= 0 (got theta = 0.01)",
    ),
    "about A with theta < 0": (
        DAMPER,
        [-0.01, 0.0, 0.5, 0.0],
        1,
        "y0: rocking about phase0 = +1 needs phase0 * theta >= 0 (got theta = -0.01)",
    ),
    "about A from 0 falling": (
        None,
        [0.0, -0.1],
        1,
        "y0: rocking about phase0 = +1 from theta = 0 needs phase0 * dtheta >= 0 (got dtheta = -0.1)",
    ),
    "about A' from 0 rising": (
        DAMPER,
        [0.0, 0.0, 0.1, 0.0],
        -1,
        "y0: rocking about phase0 = -1 from theta = 0 needs phase0 * dtheta >= 0 (got dtheta = 0.1)",
    ),
}


@pytest.mark.parametrize("case", list(REFUSED_INITIAL_STATES), ids=list(REFUSED_INITIAL_STATES))
def test_initial_state_refused_before_the_run(backend, case, monkeypatch):
    """docs/simulation.md "Initial state": refused before the run starts, with the same message on both back ends."""
    damper, y0, phase0, message = REFUSED_INITIAL_STATES[case]

    def never(*args, **kwargs):
        raise AssertionError("a back end ran on a refused initial state")

    monkeypatch.setattr(c_backend, "simulate", never)
    monkeypatch.setattr(numpy_backend, "simulate", never)
    pulse = OneSinePulse.from_nondim(REFERENCE, beta=2.0, Omega=3.0)
    with pytest.raises(ParameterError) as info:
        rocking.simulate(REFERENCE, damper, pulse, backend=backend, y0=y0, phase0=phase0)
    assert str(info.value) == message


#: Edge cases the rule accepts: (damper, y0, phase0).
ACCEPTED_INITIAL_STATES = {
    "at rest": (None, [0.0, 0.0], 0),
    "contact, damper moving": (DAMPER, [0.0, 0.05, 0.0, -0.1], 0),
    "about A from 0 at rest": (None, [0.0, 0.0], 1),
    "about A' from 0 at rest": (DAMPER, [0.0, 0.0, 0.0, 0.2], -1),
    "about A from 0 rising": (None, [0.0, 0.05], 1),
    "about A' from 0 rising": (DAMPER, [0.0, 0.01, -0.05, 0.0], -1),
    "about A falling": (None, [0.02, -0.3], 1),
    "about A' falling": (DAMPER, [-0.02, 0.0, 0.3, 0.1], -1),
}


@pytest.mark.parametrize("case", list(ACCEPTED_INITIAL_STATES), ids=list(ACCEPTED_INITIAL_STATES))
def test_a_run_starts_from_y0_in_phase0(backend, case):
    """docs/simulation.md "Initial state": a run starts at t = 0 from y0 in phase0 (the history's first row)."""
    damper, y0, phase0 = ACCEPTED_INITIAL_STATES[case]
    pulse = OneSinePulse.from_nondim(REFERENCE, beta=0.5, Omega=3.0)
    problem = make_problem(REFERENCE, damper, pulse, t_after=1.0, y0=y0, phase0=phase0)
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    h = r.history
    assert h["t"][0] == 0.0 and h["phase"][0] == phase0
    assert [h[name][0] for name in problem.model.state] == list(y0)
    if phase0 != CONTACT and y0[0] != 0.0:  # falling towards the ground: an impact first, not an uplift
        i = impact_rows(h)[0]
        assert h["phase"][i] == phase0 and h["theta"][i] == h["theta"][i + 1] == 0.0


def test_each_back_end_reads_the_initial_state_from_the_problem(backend):
    """docs/simulation.md: both back ends take the same Problem, its y0 and phase0 included.

    The back end's own ``simulate(problem)`` must start where the problem
    says, as :func:`rocking.sim.run.run` does.
    """
    block = slender_block()
    problem = make_problem(block, None, no_pulse(block), t_max=20.0, max_events=1, y0=[0.01, 0.0], phase0=1)
    module = {"numpy": numpy_backend, "c": c_backend}[backend]
    direct, through_run = module.simulate(problem), simulate(backend, problem)
    assert direct.summary() == through_run.summary()
    assert (direct.status, direct.impacts, direct.theta_max) == ("max_events", 1, 0.01)


# =========================================================================== #
# Rule 1: full contact                                                         #
# =========================================================================== #


def _linear_flow(A: np.ndarray):
    """``(t, z) -> exp(A t) z`` for an array of times, by the eigenvectors of ``A`` (distinct eigenvalues).

    One decomposition instead of a matrix exponential per time: exact to rounding, and fast.
    """
    lam, V = np.linalg.eig(A)
    assert np.min(np.abs(lam[:, None] - lam[None, :]) + np.eye(len(lam))) > 1e-6 * np.max(np.abs(lam))
    Vinv = np.linalg.inv(V)

    def flow(t, z):
        return np.real(V @ (np.exp(np.outer(lam, t)) * (Vinv @ z)[:, None]))

    return flow


@functools.cache
def _exact_contact_oscillator(a_g, omega_g, psi, t_p, t_max):
    """The damper of :data:`DAMPER` in full contact under ag (docs/model.md (C1)), solved exactly (a linear system).

    Returns ``(state at the times t, largest |x| on a fine grid)``.
    """
    m, k, c = DAMPER.m, DAMPER.k_m, DAMPER.c

    def system(a):  # z = (x, dx, sin(w t + psi), cos(w t + psi))
        return np.array([[0, 1, 0, 0], [-k / m, -c / m, -a, 0], [0, 0, 0, omega_g], [0, 0, -omega_g, 0]], dtype=float)

    pulse, free = _linear_flow(system(a_g)), _linear_flow(system(0.0))
    z0 = np.array([0.0, 0.0, math.sin(psi), math.cos(psi)])
    z_p = pulse(np.array([t_p]), z0)[:, 0]

    def state(t):
        t = np.asarray(t, dtype=float)
        return np.where(t <= t_p, pulse(np.minimum(t, t_p), z0), free(np.maximum(t - t_p, 0.0), z_p))

    # The largest |x| lies between samples: the exact one on a fine grid (error ~ x'' dt^2 / 2).
    fine = np.arange(0.0, t_max, 1e-4)
    return state, np.max(np.abs(state(fine)[0]))


def test_contact_phase_damper_is_the_exact_oscillator(backend):
    """Rule 1: theta = dtheta = 0 held, the damper follows (C1) (docs/model.md section 4); extrema of q[1] exact."""
    # Below both uplift thresholds (docs/model.md 10.2); early_rest=False: followed to t_max.
    problem = reference_problem(0.5, 3.0, DAMPER, psi=0.4, rtol=1e-9, t_after=4.0, early_rest=False)
    r = simulate(backend, problem, record=True)
    assert (r.uplifts, r.impacts, r.status, r.theta_max) == (0, 0, "below_barrier", 0.0)
    check_history(r, problem)
    h = r.history
    assert np.all(h["phase"] == CONTACT) and np.all(h["theta"] == 0) and np.all(h["dtheta"] == 0)
    state, x_max = _exact_contact_oscillator(problem.a_g, problem.omega_g, problem.psi, problem.t_p, problem.t_max)
    exact = state(h["t"])
    scale = np.max(np.abs(exact[0]))
    assert np.max(np.abs(h["x"] - exact[0])) < 1e-6 * scale
    assert np.max(np.abs(h["dx"] - exact[1])) < 1e-6 * scale * DAMPER.omega_m
    assert r.x_max == pytest.approx(x_max, rel=1e-6)  # the extremum located on the dense output
    assert r.x_max > scale  # ... between the samples


#: (beta, psi, pivot, ag phase of the uplift): docs/model.md 10.2, uplift about A at ag = g (B + 2e) / H,
#: about A' at ag = -g (B - 2e) / H; ag = a_g sin(phi), phi = omega_g t + psi.
UPLIFTS = {
    "A, first half": (3.0, 0.0, 1, lambda r: math.asin(r)),
    "A', pulse starting negative": (3.0, math.pi, -1, lambda r: math.pi + math.asin(r)),
    "A, lower amplitude": (2.0, 0.0, 1, lambda r: math.asin(r)),
    # beta = 1: a_g = g B / H is below the threshold about A, above the one about A': in the second half.
    "A', second half": (1.0, 0.0, -1, lambda r: math.pi + math.asin(r)),
}


@pytest.mark.parametrize("case", list(UPLIFTS), ids=list(UPLIFTS))
def test_uplift_time_of_the_bare_block_is_analytic(backend, case):
    """Rule 1: u_s turning positive is an uplift about s (docs/model.md 10.2), located to 4 eps t (Integration)."""
    beta, psi, pivot, phase_at = UPLIFTS[case]
    problem = reference_problem(beta, 2.0, psi=psi, max_events=1)
    r = simulate(backend, problem, record=True)
    assert (r.status, r.uplifts, r.impacts) == ("max_events", 1, 0)
    g, B, H, e = REFERENCE.g, REFERENCE.B, REFERENCE.H, REFERENCE.e
    threshold = g * (B + 2 * pivot * e) / H
    t_up = (phase_at(threshold / problem.a_g) - psi) / problem.omega_g
    # Integration: located to |dt| <= 4 eps t; twice that for the rounding of ag and of the formula.
    assert abs(r.t_end - t_up) <= 8 * np.finfo(float).eps * t_up
    assert first_uplift(r.history) == (r.t_end, pivot)
    assert r.history["t"][-1] == r.t_end and r.history["phase"][-1] == pivot


def test_the_contact_step_is_at_most_contact_max_step_while_the_pulse_acts(backend):
    """Rule 1: in full contact the step is at most contact_max_step while t < t_p.

    The bare block in full contact has nothing to integrate (theta = dtheta = 0
    held), so only this bound keeps the steps short. ag exceeds the threshold
    about A (docs/model.md 10.2) during a window W a little longer than the bound:
    some step ends inside it, so the uplift is found, at the analytic time.
    """
    threshold = REFERENCE.g * (REFERENCE.B + 2 * REFERENCE.e) / REFERENCE.H
    pulse = OneSinePulse(a_g=threshold * (1 + 1e-3), omega_g=0.5 * REFERENCE.p)
    r_up = math.asin(threshold / pulse.a_g)
    window = (math.pi - 2 * r_up) / pulse.omega_g
    problem = make_problem(REFERENCE, None, pulse, max_events=1)
    problem = dataclasses.replace(problem, contact_max_step=0.9 * window)
    assert window < 0.02 * pulse.t_p  # without the bound the steps would be far longer than the window
    r = simulate(backend, problem)
    assert (r.status, r.uplifts) == ("max_events", 1)
    assert r.t_end == pytest.approx(r_up / pulse.omega_g, rel=1e-12)


@pytest.mark.parametrize("rtol", [1e-6, 1e-10])
@pytest.mark.parametrize("beta, Omega", [(1 + 1e-4, 1.0), (1 + 1e-6, 0.1)])
def test_a_threshold_exceeded_briefly_is_not_stepped_over(backend, beta, Omega, rtol):
    """Rules 1 and 3: an uplift is found however briefly u_s is positive (breakpoints at the extrema of ag).

    The bare symmetric block uplifts about A while ag > g tan(alpha) (docs/model.md
    10.2, beta > 1), here for a window shorter than contact_max_step (0.29 of it, at
    any Omega: the window scales with the pulse's period), and about A' while
    ag < -g tan(alpha). The rocking each time is
    tiny: an impact brings the block back to rest within the window's neighbourhood,
    so each half-sine lifts it exactly once, inside its window.
    """
    block = Block(H=2.0, B=0.5, M=1000.0)
    pulse = OneSinePulse.from_nondim(block, beta=beta, Omega=Omega)
    problem = make_problem(block, None, pulse, rtol=rtol)
    half = math.acos(1 / beta) / pulse.omega_g  # ag beyond the threshold for |t - t_peak| < half
    assert 2 * half < 0.3 * problem.contact_max_step
    r = simulate(backend, problem, record=True)
    ups = [
        (float(r.history["t"][j]), int(r.history["phase"][j]))
        for i, j in transitions(r.history)
        if r.history["phase"][i] == CONTACT
    ]
    assert r.uplifts == 2 and len(ups) == 2
    for (t_up, pivot), peak, expected in zip(ups, (0.25, 0.75), (1, -1)):
        t_peak = peak * pulse.t_p
        assert pivot == expected and t_peak - half * (1 + 1e-9) <= t_up <= t_peak
    check_history(r, problem)


@pytest.mark.parametrize("psi, pivot", [(math.pi / 2, 1), (3 * math.pi / 2, -1)])
def test_a_pulse_starting_above_the_threshold_lifts_at_once(backend, psi, pivot):
    """Rule 1: when a contact phase starts both u_s are evaluated first; one > 0 is an uplift at that instant."""
    problem = reference_problem(3.0, 2.0, psi=psi, max_events=1)  # |ag(0)| = a_g, above both thresholds
    r = simulate(backend, problem, record=True)
    assert (r.status, r.uplifts, r.t_end) == ("max_events", 1, 0.0)
    assert first_uplift(r.history) == (0.0, pivot)


def test_no_uplift_below_the_threshold(backend):
    """Rule 1 (docs/model.md 10.2) and rule 4: below the lower threshold nothing lifts; the bare block rests at t_p."""
    threshold = REFERENCE.g * (REFERENCE.B - 2 * REFERENCE.e) / REFERENCE.H  # the lower of the two
    pulse = OneSinePulse(a_g=0.99 * threshold, omega_g=5.0)
    problem = make_problem(REFERENCE, None, pulse, rtol=1e-8)
    r = simulate(backend, problem, record=True)
    assert (r.uplifts, r.impacts, r.theta_max, r.x_max) == (0, 0, 0.0, 0.0)
    # Rule 4: "for the bare block full contact after the pulse is rest at once".
    assert r.status == "rest" and r.t_end == pulse.t_p
    check_history(r, problem)
    assert math.isnan(r.t_critical) and math.isnan(r.t_overturn) and not r.overturned


def test_the_damper_lifts_the_block_from_rest_and_again_after_it_came_back_to_rest(backend):
    """Rules 1 and 2: uplift by the mass alone (docs/model.md (U1), (U2)), a rest impact, and a new uplift."""
    block = REFERENCE
    damper = Damper.from_nondim(block, gamma=0.2, omega_ratio=5.0, zeta=0.02, h=0.05)
    # A short, empty pulse: the run is after the pulse almost at once, where the
    # bare block would be at rest; the moving mass must still be able to lift it.
    pulse = no_pulse(block, Omega=15.0)
    v0 = 0.6
    problem = make_problem(
        block, damper, pulse, rtol=1e-10, t_max=3.0, dtheta_rest=0.05 * block.alpha * block.p, y0=[0.0, 0.0, 0.0, v0]
    )
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    h = r.history

    # First uplift: from the initial state.
    t_up, pivot = first_uplift(h)
    expected_t, expected_pivot = predicted_uplift(block, damper, 0.0, v0, horizon=1.0)
    assert pivot == expected_pivot and abs(t_up - expected_t) < 1e-7

    # The block comes back to rest (an impact into full contact) with the mass
    # moving, and the mass lifts it again: predicted from the state at rest.
    pairs = transitions(h)
    rests = [(i, j) for i, j in pairs if h["phase"][i] != CONTACT and h["phase"][j] == CONTACT]
    assert rests and r.uplifts >= 2
    i, j = rests[0]
    # Rule 2: at rest dtheta = 0 and the mass keeps its absolute horizontal velocity
    # dx - eta dtheta through the impact and the rest snap (docs/model.md (I2), eta = H + h).
    eta = block.H + damper.h
    assert h["t"][i] == h["t"][j] and h["dtheta"][j] == 0.0 and h["x"][j] == h["x"][i]
    assert h["dx"][j] == pytest.approx(h["dx"][i] - eta * h["dtheta"][i], rel=1e-12)
    t_rest, x_rest, dx_rest = h["t"][j], h["x"][j], h["dx"][j]
    relift = [(a, b) for a, b in pairs if h["phase"][a] == CONTACT and h["t"][a] > t_rest]
    assert relift
    t_relift, pivot = h["t"][relift[0][1]], h["phase"][relift[0][1]]
    expected_dt, expected_pivot = predicted_uplift(block, damper, x_rest, dx_rest, horizon=1.0)
    assert pivot == expected_pivot
    assert abs(t_relift - t_rest - expected_dt) < 1e-7


# =========================================================================== #
# Rule 2: rocking about s                                                      #
# =========================================================================== #


def test_moderate_pulse_rocks_and_comes_to_rest(backend):
    """Rule 2 impacts (recorded before and after at one instant, theta exactly 0, pivot -s or rest) and rule 4 rest."""
    problem = reference_problem(1.3, 4.0, rtol=1e-8, early_verdict=False)
    r = simulate(backend, problem, record=True)
    assert r.status == "rest" and r.status in STATUS
    assert not r.overturned and math.isnan(r.t_overturn)
    assert r.uplifts == 1 and r.impacts > 10
    assert problem.t_p < r.t_end < problem.t_max
    assert 0 < r.theta_max < REFERENCE.alpha and math.isnan(r.t_critical)
    assert r.x_max == 0.0
    check_history(r, problem)
    h = r.history
    pairs = transitions(h)
    assert sum(h["phase"][i] != CONTACT for i, _ in pairs) == r.impacts
    assert sum(h["phase"][i] == CONTACT for i, _ in pairs) == r.uplifts
    impacts = impact_rows(h)
    assert len(impacts) == r.impacts
    for i in impacts:
        assert h["theta"][i] == 0.0 and h["theta"][i + 1] == 0.0
        assert h["phase"][i + 1] in (CONTACT, -h["phase"][i])  # always -s, or rest
        assert abs(h["dtheta"][i + 1]) < abs(h["dtheta"][i])  # the impact dissipates (docs/model.md 10.5)
    # The last impact was slower than dtheta_rest: full contact with dtheta = 0.
    last = impacts[-1]
    assert h["phase"][last + 1] == CONTACT and h["dtheta"][last + 1] == 0.0 and h["phase"][-1] == CONTACT


def test_impacts_follow_housners_restitution(backend):
    """Rule 2 impact map and rest (docs/model.md 10.1: dtheta+ / dtheta- = 1 - 1.5 sin^2 alpha)."""
    block = slender_block(alpha=0.2)  # a stockier block: a restitution visibly below 1
    problem = make_problem(
        block, None, no_pulse(block), rtol=1e-10, t_max=30.0, y0=[0.5 * block.alpha, 0.0], phase0=1, early_verdict=False
    )
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    h = r.history
    restitution = 1 - 1.5 * math.sin(block.alpha) ** 2
    impacts = [(i, j) for i, j in transitions(h) if h["phase"][i] != CONTACT]
    assert len(impacts) == r.impacts > 3
    for i, j in impacts:
        assert h["t"][i] == h["t"][j] and h["theta"][i] == h["theta"][j] == 0.0
        if h["phase"][j] == CONTACT:  # the last one: at rest
            assert abs(restitution * h["dtheta"][i]) < problem.dtheta_rest and h["dtheta"][j] == 0.0
        else:
            assert h["phase"][j] == -h["phase"][i]
            assert h["dtheta"][j] == pytest.approx(restitution * h["dtheta"][i], rel=1e-12)
    assert r.status == "rest" and h["phase"][-1] == CONTACT and r.uplifts == 0


@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.9])
def test_first_impact_of_a_slender_block_released_at_rest(backend, ratio):
    """Rule 2 (the start at theta0 > 0 is not an impact) against docs/model.md 10.3; extrema: the start is the peak."""
    block = slender_block()
    theta0 = ratio * block.alpha
    problem = make_problem(
        block, None, no_pulse(block), rtol=1e-10, t_max=20.0, max_events=1, y0=[theta0, 0.0], phase0=1
    )
    r = simulate(backend, problem)
    expected = math.acosh(1 / (1 - theta0 / block.alpha)) / block.p
    # The formula is linearised (sin(alpha - theta) ~ alpha - theta): its relative
    # error is O(alpha^2) = 4e-4, well inside the 1 % the theory is quoted to.
    assert (r.status, r.impacts, r.uplifts) == ("max_events", 1, 0)
    assert r.t_end == pytest.approx(expected, rel=block.alpha**2)
    assert r.theta_max == theta0  # released at rest: the start is the peak, exactly


def test_theta_max_is_the_exact_peak_of_a_free_rocking_arc(backend):
    """Rule 2 extrema: dtheta = 0 located, theta_max exact to the tolerance.

    Housner, energy from theta = 0 to the peak: cos(alpha - theta_max) = cos(alpha) + v^2 / (2 p^2).
    The rocking phase starts at theta = 0: that root is not an impact, the next one is.
    """
    block = slender_block(alpha=0.2)
    v = 0.5 * block.alpha * block.p
    problem = make_problem(block, None, no_pulse(block), rtol=1e-10, t_max=10.0, max_events=1, y0=[0.0, v], phase0=1)
    r = simulate(backend, problem)
    expected = block.alpha - math.acos(math.cos(block.alpha) + v**2 / (2 * block.p**2))
    assert (r.status, r.impacts, r.uplifts) == ("max_events", 1, 0)
    assert r.theta_max == pytest.approx(expected, rel=1e-8)


def test_critical_angle_and_overturning_of_a_fast_start(backend):
    """Rule 2 critical angle (alpha for the bare symmetric block, docs/model.md section 7) and overturning.

    Linearised: theta = alpha - alpha cosh(p t) + (v / p) sinh(p t) reaches alpha at tanh(p t) = alpha p / v.
    """
    block = slender_block()
    v = 1.5 * block.alpha * block.p
    problem = make_problem(block, None, no_pulse(block), rtol=1e-10, t_max=20.0, y0=[0.0, -v], phase0=-1)  # about A'
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    assert r.t_critical == pytest.approx(math.atanh(1 / 1.5) / block.p, rel=block.alpha**2)
    assert r.overturned and r.status == "overturned" and r.impacts == 0
    assert r.t_overturn == r.t_end > r.t_critical
    assert r.theta_max == pytest.approx(math.pi / 2, abs=1e-12)
    assert r.history["theta"][-1] == pytest.approx(-math.pi / 2, abs=1e-12)


@pytest.mark.parametrize("damper", [None, DAMPER], ids=["bare", "damper"])
def test_strong_pulse_overturns(backend, damper):
    """Rule 2 overturning: |theta| reaches pi/2, the run ends there; the critical angle was passed before."""
    problem = reference_problem(3.0, 2.0, damper, rtol=1e-8)
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    assert r.status == "overturned" and r.overturned
    assert r.t_end == r.t_overturn and r.t_critical < r.t_overturn
    assert r.theta_max == pytest.approx(math.pi / 2, abs=1e-12)
    assert abs(r.history["theta"][-1]) == pytest.approx(math.pi / 2, abs=1e-12)
    summary = r.summary()
    assert summary["status"] == "overturned" and isinstance(summary["t_critical"], float)


def _overturns_without_impact(backend: str, block: Block, beta: float, Omega: float) -> bool:
    """The predicate of docs/model.md 10.4: overturned, and no impact before."""
    pulse = OneSinePulse.from_nondim(block, beta=beta, Omega=Omega)
    # Once the pulse is over the free block's fate is sealed; 20 / p lets runs
    # near the separatrix decide. max_events = 2 stops at the first impact.
    problem = make_problem(block, None, pulse, rtol=1e-8, t_max=pulse.t_p + 20 / block.p, max_events=2)
    r = simulate(backend, problem)
    return r.overturned and r.impacts == 0


@pytest.mark.parametrize("Omega, beta_min", [(1, 1.418), (2, 2.350), (4, 5.239), (6, 9.417)])
def test_smallest_amplitude_that_overturns_without_impact(backend, Omega, beta_min):
    """Rule 2 overturning against docs/model.md 10.4: within 1 % of the linearised boundary (alpha = 0.02)."""
    block = slender_block()
    low, high = 0.95 * beta_min, 1.05 * beta_min
    assert not _overturns_without_impact(backend, block, low, Omega)
    assert _overturns_without_impact(backend, block, high, Omega)
    while high - low > 1e-3 * beta_min:
        mid = 0.5 * (low + high)
        low, high = (low, mid) if _overturns_without_impact(backend, block, mid, Omega) else (mid, high)
    assert 0.5 * (low + high) == pytest.approx(beta_min, rel=1e-2)


def test_a_block_set_on_its_corner_without_velocity_stays_on_its_base(backend):
    """Rule 2 grazing lift-off: a rocking phase that cannot rise goes back to full contact, no impact counted."""
    block = slender_block()
    pulse = no_pulse(block)
    problem = make_problem(block, None, pulse, y0=[0.0, 0.0], phase0=1)
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    assert (r.status, r.impacts, r.uplifts, r.theta_max) == ("rest", 0, 0, 0.0)
    assert r.t_end == pulse.t_p
    phase = r.history["phase"]
    assert phase[0] == 1 and np.all(phase[1:] == CONTACT)


def test_a_grazing_uplift_at_the_pulse_start_changes_nothing_else(backend):
    """Rule 2 grazing lift-off, at the pulse's start.

    ag(0) a hair above (or below) the uplift threshold g B / H: above, the block
    lifts by almost nothing and falls back at once (the first step of the
    rocking phase, too long to see that, is retried shorter); the rest of the
    run (uplift about A' in the negative half, overturning) is the same.
    """
    block = slender_block()
    runs = {}
    for eps in (-1e-9, 1e-9):
        psi = math.pi / 2 + math.acos((1 + eps) / 2)  # beta = 2: ag(0) = (1 + eps) g tan(alpha)
        pulse = OneSinePulse.from_nondim(block, beta=2.0, Omega=1.0, psi=psi)
        runs[eps] = simulate(backend, make_problem(block, None, pulse, rtol=1e-8, max_events=20))
    below, above = runs[-1e-9], runs[1e-9]
    assert (below.status, below.uplifts, below.impacts) == ("overturned", 1, 0)
    assert (above.status, above.uplifts, above.impacts) == ("overturned", 2, 1)
    assert above.t_overturn == pytest.approx(below.t_overturn, rel=1e-6)


# =========================================================================== #
# Rule 3: breakpoints                                                          #
# =========================================================================== #


@pytest.mark.parametrize(
    "problem, rocking_at_t_p",
    [
        (reference_problem(1.3, 4.0, rtol=1e-8), True),
        (reference_problem(0.5, 3.0, DAMPER, psi=0.4, t_after=1.0), False),
    ],
    ids=["rocking", "full contact"],
)
def test_every_phase_stops_at_the_pulse_end(backend, problem, rocking_at_t_p):
    """Rule 3: t_p is one row of the history in whichever phase the pulse ends; ag = 0 after it."""
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    h = r.history
    (j,) = np.flatnonzero(h["t"] == problem.t_p)
    assert (h["phase"][j] != CONTACT) == rocking_at_t_p
    assert_same_pulse(h["ag"][j], problem, problem.t_p)
    assert np.all(h["ag"][h["t"] > problem.t_p] == 0.0)


# =========================================================================== #
# Rule 4: end                                                                  #
# =========================================================================== #


def test_max_events_ends_the_run(backend):
    """Rule 4: the run ends when uplifts + impacts reaches max_events."""
    problem = reference_problem(1.3, 4.0, rtol=1e-8, max_events=3)
    r = simulate(backend, problem, record=True)
    assert r.status == "max_events" and r.uplifts + r.impacts == 3
    check_history(r, problem)


def _kinetic_energy(block: Block, damper: Damper, s: float, x: float, dtheta: float, dx: float) -> float:
    """T about the pivot s at theta = 0 (docs/model.md section 2): V is continuous through an impact."""
    d_s, xi_s, eta = s * block.B / 2 + block.e, s * block.B / 2 + x, block.H + damper.h
    I_s = block.I_G + block.M * (d_s**2 + block.H**2 / 4)
    return 0.5 * I_s * dtheta**2 + 0.5 * damper.m * (dtheta**2 * (xi_s**2 + eta**2) + dx**2 - 2 * eta * dtheta * dx)


def _impact_map(block: Block, damper: Damper, s: float, x: float, dtheta: float, dx: float) -> tuple[float, float]:
    """(dtheta+, dx+) of docs/model.md (I1), (I2): the momentum law, typed from the document."""
    d_s, d_o = s * block.B / 2 + block.e, -s * block.B / 2 + block.e
    xi_s, xi_o, eta = s * block.B / 2 + x, -s * block.B / 2 + x, block.H + damper.h
    I_o = block.I_G + block.M * (d_o**2 + block.H**2 / 4)
    ratio = (block.I_G + block.M * (block.H**2 / 4 + d_s * d_o) + damper.m * xi_s * xi_o) / (I_o + damper.m * xi_o**2)
    dtheta_plus = dtheta * ratio
    return dtheta_plus, dx + eta * (dtheta_plus - dtheta)


def test_no_impact_and_no_rest_snap_adds_energy(backend):
    """Rule 2: the momentum law never adds energy (docs/model.md 10.5), nor does the rest snap that follows it.

    At an impact theta = 0 and x are continuous, so V is too: the kinetic energy
    of section 2 about the old pivot before, about the new one after, must not
    grow; nor, at rest, from the state the impact law (I1)-(I2) gives to the
    state after the snap. Tolerance: 1e-12 of the energy before, plus 1e-9 J: the
    impact map and the snap are a few roundings of velocities of order 1
    (relative errors ~1e-15), far below what keeping dx at the snap adds (up to
    0.1 J here: m eta dtheta+ dx+ with dtheta+ up to dtheta_rest).
    """
    rng = np.random.default_rng(7)
    snaps = impacts = 0
    for _ in range(12):
        damper = Damper.from_nondim(
            REFERENCE,
            gamma=rng.uniform(0.01, 0.2),
            omega_ratio=rng.uniform(0.3, 3.0),
            zeta=rng.uniform(0.0, 0.3),
            h=0.05,
        )
        problem = reference_problem(
            rng.uniform(1.2, 2.5),
            rng.uniform(2.0, 8.0),
            damper,
            rtol=1e-8,
            t_after=5.0,
            dtheta_rest=0.1 * REFERENCE.alpha * REFERENCE.p,
            early_verdict=False,
        )
        h = simulate(backend, problem, record=True).history
        for i in impact_rows(h):
            j = i + 1
            s_before = float(h["phase"][i])
            s_after = float(h["phase"][j]) or -s_before
            x = h["x"][i]
            before = _kinetic_energy(REFERENCE, damper, s_before, x, h["dtheta"][i], h["dx"][i])
            after = _kinetic_energy(REFERENCE, damper, s_after, x, h["dtheta"][j], h["dx"][j])
            assert h["theta"][i] == h["theta"][j] == 0.0 and h["x"][j] == x
            assert after <= before * (1 + 1e-12) + 1e-9, (i, before, after)
            if h["phase"][j] == CONTACT:  # the snap alone, from the state of (I1)-(I2)
                plus = _impact_map(REFERENCE, damper, s_before, x, h["dtheta"][i], h["dx"][i])
                impacted = _kinetic_energy(REFERENCE, damper, -s_before, x, *plus)
                assert after <= impacted * (1 + 1e-12) + 1e-9, (i, impacted, after)
            impacts += 1
            snaps += h["phase"][j] == CONTACT
    assert impacts > 30 and snaps > 5


def test_max_steps_ends_a_run_that_cannot_be_integrated(backend):
    """Rule 5: a degenerate damper (a stiff oscillator of period ~1e-150 s) ends with status "max_steps"."""
    # Below the public checks (Damper refuses m = 1e-300): the bound must hold for any Problem.
    problem = reference_problem(3.0, 4.0, DAMPER)
    p = problem.p.copy()
    p[problem.model.parameters.index("m")], p[problem.model.parameters.index("k_m")] = 1e-300, 200.0
    T_m = 2 * math.pi * math.sqrt(1e-300 / 200.0)  # the contact step follows the damper, as in make_problem
    T_g = 2 * math.pi / problem.omega_g
    step = default_settings(REFERENCE, T_g, T_m, problem.rtol, problem.model.nq)["contact_max_step"]
    problem = dataclasses.replace(problem, p=p, contact_max_step=float(step), max_steps=5000)
    r = simulate(backend, problem, record=True)
    assert r.status == "max_steps" and r.t_end < problem.t_max and not r.overturned
    assert r.history["t"][-1] == r.t_end


def test_recorded_samples_count_as_work(backend):
    """Rule 5: a history sampled every 1e-9 s ends with status "max_steps" at the first segment's start."""
    # Below the public checks (make_problem refuses record_dt = 1e-9 s): the bound must hold for any Problem.
    problem = dataclasses.replace(reference_problem(3.0, 4.0, DAMPER), record_dt=1e-9, max_steps=100_000)
    r = simulate(backend, problem, record=True)
    assert (r.status, r.t_end, r.uplifts, r.theta_max, r.x_max) == ("max_steps", 0.0, 0, 0.0, 0.0)
    assert len(r.history["t"]) == 1
    assert simulate(backend, problem).status == "overturned"  # without a history, far below the bound


@pytest.mark.parametrize("max_steps", [100, 300, 500])
def test_max_steps_ends_the_run_at_the_start_of_a_segment(backend, max_steps):
    """Rule 5: the run ends where the segment in which the work passed max_steps started, with the results so far."""
    problem = reference_problem(1.6, 3.0, DAMPER, rtol=1e-8)
    full = simulate(backend, problem, record=True)
    assert full.status in ("rest", "overturned")
    cut = simulate(backend, dataclasses.replace(problem, max_steps=max_steps), record=True)
    assert cut.status == "max_steps" and cut.t_end < full.t_end
    # The history up to the cut is the full run's (same steps, same samples), and ends
    # at the start of a segment: a breakpoint or an event of the full run, where the
    # full history holds two rows at one instant or changes phase.
    h, n = full.history, len(cut.history["t"])
    for name in ("t", *problem.model.state, "phase"):
        assert same(cut.history[name], h[name][:n])
    assert cut.history["t"][-1] == cut.t_end
    phase_of_ag = (problem.omega_g * cut.t_end + problem.psi - math.pi / 2) / math.pi  # an integer at an extremum
    assert (
        h["t"][n - 2] == cut.t_end  # an event: two rows at one instant
        or cut.t_end in (0.0, problem.t_p)
        or abs(phase_of_ag - round(phase_of_ag)) < 1e-12
    )
    assert cut.uplifts <= full.uplifts and cut.impacts <= full.impacts
    assert cut.theta_max <= full.theta_max and cut.x_max <= full.x_max


@pytest.mark.parametrize("t_max", [2.0, None], ids=["while rocking", "after the pulse"])
def test_t_max_ends_the_run(backend, t_max):
    """Rule 4: at t_max, t_end exactly t_max (an undamped damper never rests); after the pulse, with far too
    little energy to overturn, status "below_barrier"."""
    damper = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, zeta=0.0, h=0.05)
    problem = reference_problem(1.3, 4.0, damper, rtol=1e-8, t_max=t_max, t_after=3.0, early_rest=False)
    r = simulate(backend, problem, record=True)
    assert r.status == "below_barrier" and r.t_end == problem.t_max
    assert r.x_max > 0 and r.x_max >= np.max(np.abs(r.history["x"]))
    check_history(r, problem)


def test_energy_rest_in_full_contact_after_the_pulse(backend):
    """Rule 4 energy_rest: located as an event, E(y) - E(0) = energy_rest at the end (docs/model.md section 2)."""
    damper = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, zeta=0.3, h=0.05)
    problem = reference_problem(1.3, 4.0, damper, rtol=1e-8, early_rest=False, early_verdict=False)  # energy_rest alone
    r = simulate(backend, problem, record=True)
    assert r.status == "rest" and problem.t_p < r.t_end < problem.t_max
    check_history(r, problem)
    h = r.history
    assert h["phase"][-1] == CONTACT and r.impacts > 0 and r.x_max > 0
    # The rest event is located: the energy above rest is at the threshold, not below it by a step.
    assert damper_energy(damper, h["x"][-1], h["dx"][-1]) == pytest.approx(problem.energy_rest, rel=1e-6)


# --- early rest ------------------------------------------------------------- #


def test_early_rest_at_the_pulse_end_settles_the_damper_to_its_next_extremum(backend):
    """Rule 4 early rest, checked when the contact phase restarts at t_p: the run ends at the next extremum of x.

    The damper starts with half the least uplift energy (docs/model.md section 5), the
    pulse is short and empty: safe at t_p, and x = v0 / wd exp(-zeta w t) sin(wd t)
    (docs/model.md (C1)) ends the run at its first peak.
    """
    block, damper = REFERENCE, DAMPER
    pulse = no_pulse(block, Omega=15.0)
    v0 = math.sqrt(0.5 * least_uplift_energy(block, damper) * 2 / damper.m)
    problem = make_problem(block, damper, pulse, rtol=1e-10, t_max=pulse.t_p + 6.0, y0=[0.0, 0.0, 0.0, v0])
    early = simulate(backend, problem, record=True)
    check_history(early, problem)
    t_peak = extremum_times(damper, 1)[0]
    motion = contact_motion(damper, 0.0, v0)
    assert pulse.t_p < t_peak and abs(motion(pulse.t_p)[0]) < 0.5 * abs(motion(t_peak)[0])
    assert (early.status, early.uplifts, early.impacts, early.theta_max) == ("rest", 0, 0, 0.0)
    assert early.t_end == pytest.approx(t_peak, abs=1e-8)
    assert early.x_max == pytest.approx(abs(motion(t_peak)[0]), rel=1e-8)
    h = early.history
    assert h["phase"][-1] == CONTACT and abs(h["dx"][-1]) < 1e-9 * damper.omega_m * early.x_max
    assert abs(h["x"][-1]) == pytest.approx(early.x_max, rel=1e-12)
    full = simulate(backend, dataclasses.replace(problem, early_rest=False))
    assert (full.status, full.uplifts) == ("below_barrier", 0)
    assert early.x_max == pytest.approx(full.x_max, rel=1e-9)


def test_early_rest_located_during_a_contact_phase(backend):
    """Rule 4 early rest, located as a terminal event: E_a falls below U (1 - 1e-9) between two extrema of x.

    The damper starts with 1.3 times the least uplift energy and never lifts
    the block; its energy (docs/model.md section 2) falls below the bound after its
    first peak, so the run ends at the second extremum, not the first.
    """
    block, damper = REFERENCE, DAMPER
    pulse = no_pulse(block, Omega=15.0)
    U = least_uplift_energy(block, damper)
    v0 = -math.sqrt(1.3 * U * 2 / damper.m)
    problem = make_problem(block, damper, pulse, rtol=1e-10, t_max=pulse.t_p + 6.0, y0=[0.0, 0.0, 0.0, v0])
    motion = contact_motion(damper, 0.0, v0)
    t_first, t_second = extremum_times(damper, 2)
    t_safe = brentq(lambda t: damper_energy(damper, *motion(t)) - U * (1 - 1e-9), t_first, t_second, xtol=1e-14)
    assert damper_energy(damper, *motion(t_first)) > U > damper_energy(damper, *motion(t_second))
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    assert (r.status, r.uplifts, r.impacts, r.theta_max) == ("rest", 0, 0, 0.0)
    assert t_safe < r.t_end
    assert r.t_end == pytest.approx(t_second, abs=1e-8)
    assert r.x_max == pytest.approx(abs(motion(t_first)[0]), rel=1e-8)  # the first peak is the largest
    full = simulate(backend, dataclasses.replace(problem, early_rest=False))
    assert (full.status, full.uplifts) == ("below_barrier", 0)  # it could indeed never lift again
    assert r.x_max == pytest.approx(full.x_max, rel=1e-9)


def test_early_rest_after_a_pulse_below_the_thresholds(backend):
    """Rule 4 early rest after a pulse: safe from t_p on, the run ends within half a damped period after it."""
    problem = reference_problem(0.5, 3.0, DAMPER, rtol=1e-9, t_after=4.0)  # below both uplift thresholds
    early = simulate(backend, problem, record=True)
    full = simulate(backend, dataclasses.replace(problem, early_rest=False))
    assert (early.status, full.status) == ("rest", "below_barrier")
    wd = DAMPER.omega_m * math.sqrt(1 - DAMPER.zeta**2)
    assert problem.t_p < early.t_end < problem.t_p + math.pi / wd
    # ... at an extremum of x, which here is the largest |x| of the whole run (settling matters).
    h = early.history
    check_history(early, problem)
    assert h["t"][-1] == early.t_end and h["phase"][-1] == CONTACT
    assert abs(h["dx"][-1]) < 1e-9 * DAMPER.omega_m * early.x_max
    assert abs(h["x"][-1]) == pytest.approx(early.x_max, rel=1e-12)
    assert early.x_max == pytest.approx(full.x_max, rel=1e-9)
    assert (early.theta_max, early.uplifts, early.impacts) == (full.theta_max, full.uplifts, full.impacts) == (0, 0, 0)


def test_early_rest_after_rocking_keeps_the_verdict_and_the_maxima(backend):
    """Rule 4 early rest: verdict, counts, theta_max and t_critical are final; x_max as the full run's."""
    damper = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, zeta=0.1, h=0.05)
    problem = reference_problem(1.3, 4.0, damper, rtol=1e-8, t_after=4.0, early_verdict=False)
    early = simulate(backend, problem, record=True)
    full = simulate(backend, dataclasses.replace(problem, early_rest=False))
    check_history(early, problem)
    assert early.status == "rest" and early.impacts > 0 and early.t_end < full.t_end
    assert abs(early.history["dx"][-1]) < 1e-9 * damper.omega_m * early.x_max  # at an extremum of x
    for name in ("overturned", "theta_max", "t_critical", "impacts", "uplifts"):
        assert same(getattr(early, name), getattr(full, name)), name
    assert early.x_max == pytest.approx(full.x_max, rel=1e-9)


# =========================================================================== #
# Mirror symmetry (docs/model.md 10.6)                                              #
# =========================================================================== #


def _assert_mirrored(a, b, state) -> None:
    assert (a.status, a.impacts, a.uplifts, a.overturned) == (b.status, b.impacts, b.uplifts, b.overturned)
    assert b.theta_max == pytest.approx(a.theta_max, rel=1e-6)
    assert b.x_max == pytest.approx(a.x_max, rel=1e-6)
    for name in ("t_critical", "t_overturn", "t_end"):
        va, vb = getattr(a, name), getattr(b, name)
        assert same(va, vb) or vb == pytest.approx(va, rel=1e-6), name
    ha, hb = a.history, b.history
    assert len(ha["t"]) == len(hb["t"])
    np.testing.assert_allclose(hb["t"], ha["t"], rtol=1e-6, atol=1e-9)
    assert np.array_equal(hb["phase"], -ha["phase"])
    for name in state:  # every coordinate and velocity flips: (x, theta) -> (-x, -theta)
        scale = np.max(np.abs(ha[name])) + 1e-300
        np.testing.assert_allclose(hb[name], -ha[name], rtol=0, atol=1e-5 * scale)


def test_mirror_symmetry_under_a_pulse(backend):
    """docs/model.md 10.6: (e, x, theta, ag) -> (-e, -x, -theta, -ag) maps the response onto its mirror image."""
    problem = reference_problem(2.5, 5.0, DAMPER, t_after=5.0)
    p = problem.p.copy()
    p[list(problem.model.parameters).index("e")] *= -1
    mirror = dataclasses.replace(problem, p=p, a_g=-problem.a_g)
    a, b = simulate(backend, problem, record=True), simulate(backend, mirror, record=True)
    assert a.uplifts >= 1 and a.impacts >= 1 and a.overturned
    _assert_mirrored(a, b, problem.model.state)


@pytest.mark.parametrize("stops", [False, True], ids=["unlimited guide", "stops at the edges"])
def test_a_pulse_of_the_other_sign_is_the_mirror_image(backend, stops):
    """OneSinePulse(sign=-1) on the block of eccentricity e is the mirror image of the pulse of sign +1 on the
    block of -e (docs/model.md 10.6), through the public API; symmetric stops keep the symmetry."""
    damper = dataclasses.replace(DAMPER, stops=rocking.Stops.at_edges(REFERENCE, DAMPER)) if stops else DAMPER
    mirrored = dataclasses.replace(REFERENCE, e=-REFERENCE.e)
    pulse = OneSinePulse.from_nondim(REFERENCE, beta=2.5, Omega=5.0)
    a = rocking.simulate(REFERENCE, damper, pulse, backend=backend, record=True, t_after=5.0)
    b = rocking.simulate(
        mirrored, damper, dataclasses.replace(pulse, sign=-1), backend=backend, record=True, t_after=5.0
    )
    assert a.uplifts >= 1
    _assert_mirrored(a, b, load_model(damper.model).state)
    assert (a.stop_contacts, a.bumper_force_max == pytest.approx(b.bumper_force_max)) == (b.stop_contacts, True)


def test_mirror_symmetry_of_an_initial_state(backend):
    """docs/model.md 10.6 from a mirrored initial state and phase0, eccentric block with a damper, no ground motion."""
    runs = []
    for sign in (1, -1):
        block = Block(H=2.0, B=0.5, M=1000.0, e=sign * 0.025)
        damper = Damper.from_nondim(block, gamma=0.1, omega_ratio=2.0, zeta=0.05, h=0.05)
        y0 = sign * np.array([0.0, 0.02, 0.6 * block.alpha * block.p, -0.1])
        problem = make_problem(block, damper, no_pulse(block), rtol=1e-10, t_max=4.0, y0=y0, phase0=sign)
        runs.append(simulate(backend, problem, record=True))
    plus, minus = runs
    assert plus.impacts > 2
    _assert_mirrored(plus, minus, problem.model.state)


# =========================================================================== #
# Integration                                                                  #
# =========================================================================== #


@functools.cache
def _free_rocking_reference(p: tuple, theta0: float):
    """First impact of free rocking about A from rest at theta0: DOP853 at rtol 1e-13 on the generated NumPy model."""
    functions = load_model("block").functions

    def rhs(t, y):
        return [y[1], functions.rocking_accel(1.0, y[0], y[1], 0.0, 0.0, *p)[0]]

    def impact(t, y):
        return y[0]

    impact.terminal, impact.direction = True, -1
    sol = solve_ivp(
        rhs, (0.0, 10.0), [theta0, 0.0], method="DOP853", rtol=1e-13, atol=1e-15, events=impact, dense_output=True
    )
    return sol.t_events[0][0], sol.sol


@pytest.mark.parametrize("theta0", [0.05, 0.2])
def test_free_rocking_first_impact_converges_with_rtol(backend, theta0):
    """Integration: the error follows rtol (DOPRI5 error norm); recorded samples are as accurate as the steps."""
    errors = {}
    for rtol in (1e-6, 1e-8, 1e-10):
        problem = reference_problem(0.0, 1.0, rtol=rtol, max_events=1, t_max=10.0, y0=[theta0, 0.0], phase0=1)
        t_ref, dense = _free_rocking_reference(tuple(problem.p), theta0)
        r = simulate(backend, problem, record=True)
        assert (r.status, r.impacts, r.uplifts) == ("max_events", 1, 0)
        errors[rtol] = abs(r.t_end - t_ref)
        h = r.history
        inside = h["t"] < r.t_end
        assert np.max(np.abs(h["theta"][inside] - dense(h["t"][inside])[0])) < 100 * rtol * REFERENCE.alpha
        assert r.theta_max == theta0
    # Global error proportional to the tolerance: ~100x smaller per 100x smaller rtol.
    assert errors[1e-8] < 1e-7
    assert errors[1e-8] < errors[1e-6] / 30 and errors[1e-10] < errors[1e-8] / 30


# =========================================================================== #
# History                                                                      #
# =========================================================================== #


def test_history_layout(backend):
    """History: samples at the multiples of record_dt plus every event, in time order; fields; ag is the pulse."""
    problem = reference_problem(2.0, 6.0, DAMPER, t_after=3.0)
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    h = r.history
    n = len(h["t"])
    assert n > problem.t_max / problem.record_dt
    assert r.impacts > 0 and r.status == "below_barrier"
    assert len(impact_rows(h)) == r.impacts  # impacts: before and after at one instant
    assert len(np.flatnonzero(np.diff(h["t"]) == 0)) >= r.impacts + r.uplifts
    k = h["t"] / problem.record_dt
    grid = h["t"][(h["t"] > 0) & (np.abs(k - np.round(k)) < 1e-9)]
    assert len(grid) >= int(problem.t_max / problem.record_dt) - 1
    assert h["phase"].dtype.kind == "i" and all(h[name].dtype == float for name in ("t", "ag", *problem.model.state))
    without = simulate(backend, problem)
    assert without.history is None and without.summary() == r.summary()


@pytest.mark.parametrize("record_dt", [0.0, -1.0])
def test_history_of_events_only(backend, record_dt):
    """Table: record_dt <= 0 records the events only (start, uplift, impacts before and after, t_p, end)."""
    problem = dataclasses.replace(reference_problem(1.3, 4.0, rtol=1e-8), record_dt=record_dt)
    r = simulate(backend, problem, record=True)
    check_history(r, problem)
    h = r.history
    pairs = np.flatnonzero(np.diff(h["t"]) == 0)
    in_pair = np.zeros(len(h["t"]), dtype=bool)
    in_pair[pairs] = in_pair[pairs + 1] = True
    single = h["t"][~in_pair]
    assert set(single.tolist()) <= {0.0, problem.t_p, r.t_end}
    assert len(pairs) == r.uplifts + r.impacts
    assert r.summary() == simulate(backend, reference_problem(1.3, 4.0, rtol=1e-8)).summary()


# =========================================================================== #
# Settings out of their range (the table of docs/simulation.md)                #
# =========================================================================== #

#: A change of the settings of a valid problem (with a damper) and the message that refuses it.
REFUSED_SETTINGS = {
    "contact_max_step 0": ({"contact_max_step": 0.0}, "contact_max_step must be finite and > 0 (got 0)"),
    "contact_max_step nan": ({"contact_max_step": math.nan}, "contact_max_step must be finite and > 0 (got nan)"),
    "t_max inf": ({"t_max": math.inf}, "t_max must be in (0, 30000] s (got inf)"),
    "t_p nan": ({"t_p": math.nan}, "t_p must be finite (got nan)"),
    "a_g inf": ({"a_g": -math.inf}, "a_g must be finite (got -inf)"),
    "omega_g nan": ({"omega_g": math.nan}, "omega_g must be finite (got nan)"),
    "psi inf": ({"psi": math.inf}, "psi must be finite (got inf)"),
    "rtol 0": ({"rtol": 0.0}, "rtol must be in [1e-12, 0.01] (got 0)"),
    "rtol negative": ({"rtol": -1e-8}, "rtol must be in [1e-12, 0.01] (got -1e-08)"),
    "dtheta_rest negative": ({"dtheta_rest": -1.0}, "dtheta_rest must be finite and >= 0 (got -1)"),
    "energy_rest negative": ({"energy_rest": -1.0}, "energy_rest must be finite and >= 0 (got -1)"),
    "energy_rest inf": ({"energy_rest": math.inf}, "energy_rest must be finite and >= 0 (got inf)"),
    "max_events 0": ({"max_events": 0}, "max_events must be an integer in [1, 1e+08] (got 0)"),
    "max_events 1.5": ({"max_events": 1.5}, "max_events must be an integer in [1, 1e+08] (got 1.5)"),
    "max_steps 0": ({"max_steps": 0}, "max_steps must be an integer >= 1 (got 0)"),
    "record_dt nan": ({"record_dt": math.nan}, "record_dt must be finite (got nan)"),
    "early_rest 2": ({"early_rest": 2}, "early_rest must be 0 or 1 (got 2)"),
    "atol negative": (
        {"atol": [-1.0, 0.0, 0.0, 0.0]},
        "atol must hold 4 finite numbers >= 0 ('theta', 'x', 'dtheta', 'dx') (got [-1.0, 0.0, 0.0, 0.0])",
    ),
    "atol too short": (
        {"atol": [1e-8, 1e-8]},
        "atol must hold 4 finite numbers >= 0 ('theta', 'x', 'dtheta', 'dx') (got [1e-08, 1e-08])",
    ),
}


@pytest.mark.parametrize("case", list(REFUSED_SETTINGS), ids=list(REFUSED_SETTINGS))
def test_settings_out_of_range_are_refused(backend, case, monkeypatch):
    """Table: a setting out of its range is refused before the run, with the same message on both back ends."""
    change, message = REFUSED_SETTINGS[case]

    def never(*args, **kwargs):
        raise AssertionError("a back end ran on a refused setting")

    monkeypatch.setattr(c_backend, "simulate", never)
    monkeypatch.setattr(numpy_backend, "simulate", never)
    problem = reference_problem(2.0, 2.0, DAMPER)
    with pytest.raises(ParameterError) as info:
        simulate(backend, dataclasses.replace(problem, **change))
    assert str(info.value) == message


def test_a_function_that_only_touches_zero_fires_no_event(backend):
    """The strict rules of docs/simulation.md hold at an exact 0 on both back ends (the fuzzer found NumPy
    firing there): beta = 1 on a symmetric block brings u_s exactly to 0 at the peaks of ag, which is no
    uplift ("turns positive"); with energy_rest = 0 an energy exactly at rest is not below it ("below")."""
    block = Block.from_nondim(alpha=0.14842172548849247, p=0.5, M=10.0)
    r = simulate(backend, make_problem(block, None, OneSinePulse.from_nondim(block, beta=1.0, Omega=1.0)))
    assert (r.status, r.uplifts, r.theta_max) == ("rest", 0, 0.0)
    block = Block.from_nondim(alpha=0.1054658490165491, p=0.5)
    still = OneSinePulse(a_g=0.0, omega_g=1.0)
    r = simulate(backend, make_problem(block, None, still, t_after=0.5, energy_rest=0.0, early_rest=False))
    assert (r.status, r.t_end) == ("below_barrier", still.t_p + 0.5)


# =========================================================================== #
# Other ground motions (docs/model.md section 12; rules 1 and 3)               #
# =========================================================================== #


def _record(block: Block) -> rocking.SampledMotion:
    """A short record: a smoothed random series of 160 samples, 2 pi / p / 40 apart, peak 1.6 g tan(alpha)."""
    rng = np.random.default_rng(11)
    a = np.convolve(rng.standard_normal(160), np.hanning(9), "same")
    return rocking.SampledMotion(a / np.max(np.abs(a)) * 1.6 * block.g * block.tan_alpha, dt=2 * np.pi / block.p / 40)


#: One motion of each family beyond the one-sine, on the reference block, strong enough to rock it.
MOTIONS = {
    "cosine": lambda b: rocking.OneCosinePulse.from_nondim(b, beta=2.5, Omega=5.0),
    "ricker": lambda b: rocking.RickerWavelet.from_nondim(b, beta=3.0, Omega=4.0),
    "ricker_anti": lambda b: rocking.RickerWavelet.from_nondim(b, beta=3.0, Omega=4.0, antisymmetric=True),
    "mp": lambda b: rocking.MavroeidisPapageorgiou.from_nondim(b, beta=3.0, Omega=4.0, gamma_mp=2.0, nu=0.6),
    "sampled": _record,
}


@pytest.mark.parametrize("family", list(MOTIONS))
def test_mirror_symmetry_of_every_motion(backend, family):
    """docs/model.md 10.6 for every family: (e, x, theta, ag) -> (-e, -x, -theta, -ag) mirrors the response;
    the history's ag is the motion's (rule 3: its end t_p is a row)."""
    problem = make_problem(REFERENCE, DAMPER, MOTIONS[family](REFERENCE), t_after=3.0)
    p = problem.p.copy()
    p[list(problem.model.parameters).index("e")] *= -1
    mirror = dataclasses.replace(problem, p=p, a_g=-problem.a_g)
    a, b = simulate(backend, problem, record=True), simulate(backend, mirror, record=True)
    assert a.uplifts >= 1 and a.impacts >= 1
    _assert_mirrored(a, b, problem.model.state)
    check_history(a, problem)


@pytest.mark.parametrize("family", ["ricker", "mp"])
def test_a_brief_uplift_of_a_wavelet_is_not_stepped_over(backend, family):
    """Rules 1 and 3: the contact phase stops at the extrema of ag (the listed ones of a Ricker wavelet and of the
    Mavroeidis-Papageorgiou pulse), so a peak 1e-6 above the uplift threshold of the bare symmetric block
    (docs/model.md 10.2: |ag| > g tan(alpha)) lifts it, within the short window around that peak."""
    block = Block(H=2.0, B=0.5, M=1000.0)
    threshold = block.g * block.tan_alpha
    unit = (
        rocking.RickerWavelet(1.0, block.p)
        if family == "ricker"
        else rocking.MavroeidisPapageorgiou(1.0, block.p, gamma_mp=2.5, nu=0.3)
    )
    t = np.linspace(0.0, unit.t_p, 400_001)
    f = unit.acceleration(t)
    k = int(np.argmax(np.abs(f)))
    peak, t_peak = abs(f[k]), t[k]
    motion = dataclasses.replace(unit, a_g=threshold * (1 + 1e-6) / peak)
    problem = make_problem(block, None, motion, rtol=1e-8, max_events=1)
    window = 2 * math.sqrt(2e-6 / (abs(np.gradient(np.gradient(f, t), t)[k]) / peak))  # f ~ peak (1 - c (t - t_k)^2)
    assert window < 0.05 * problem.contact_max_step  # steps of contact_max_step alone would step over it
    r = simulate(backend, problem)
    assert (r.status, r.uplifts) == ("max_events", 1)
    assert abs(r.t_end - t_peak) < window + 2 * (t[1] - t[0])
