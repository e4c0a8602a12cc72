"""A plain integration of the block with a damper on a guide that ends in pads: the yardstick of the pads' state.

Independent of both back ends and of the generated code: the equations are those typed by hand in
:mod:`rocking.reference.paper` (docs/model.md sections 3-7 and 11), integrated with SciPy's ``solve_ivp``
(RK45, ``rtol`` 1e-11). It keeps no regime: every evaluation of the right-hand side reads each pad's force
from the state, ``max(0, k_b delta + c_b ddelta)`` (Hunt-Crossley: ``k_b delta^n (1 + chi ddelta / v_in)``,
``> 0`` only) where ``delta > 0``, so a pad's state can never be carried over a jump of ``dx``. The zeros of
each pad's contact ``min(delta, bracket)`` end an integration (the force has a kink or, Kelvin-Voigt, a jump
there), which restarts ``RESTART`` seconds later on the dense output (at the end of the step that found
it, if sooner: its stages past the zero saw the force change). The only memory is a Hunt-Crossley
pad's approach speed ``v_in`` (docs/simulation.md, rule 6): ``max(ddelta, v_f)`` where a gap closes and at
the start, and ``max(v_in, ddelta)`` after an impact that changes ``ddelta`` with the mass in the pad.

The phases are docs/simulation.md's: full contact (``theta = dtheta = 0``) until an uplift margin turns
positive (checked at once where a contact phase starts), rocking about ``s`` until ``s theta`` falls to 0
(the impact map of :func:`rocking.reference.paper.impact`, then the rest snap below ``dtheta_rest``, which
keeps the mass's generalised momentum) or ``|theta|`` reaches ``pi / 2``. No early verdict, no early rest:
the run goes on to ``t_end``. The maxima: ``|theta|`` and ``|x|`` at their located extrema, the pads' force
on a grid of the dense output (``GRID`` points a step) polished by Brent's method around each grid maximum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

import rocking
from rocking.reference import paper

#: The restart after a pad's zero: far below any time scale of the runs here, far above the located root's error.
RESTART = 1e-10
#: Points of the dense output per step where the pads' force is looked at before its maxima are polished.
GRID = 8
BODY = ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c")
#: The pulse families of :func:`random_case`.
FAMILIES = ("sine", "cosine", "ricker", "ricker_anti", "mp")


@dataclass
class Result:
    """What :func:`plain_run` found until its end."""

    theta_max: float = 0.0
    x_max: float = 0.0
    stop_contacts: int = 0
    bumper_force_max: float = 0.0
    impacts: int = 0
    uplifts: int = 0
    overturned: bool = False
    t_end: float = 0.0
    rows: list = field(default_factory=list)  # (t, theta, x, dtheta, dx, phase) at every event


def pad_law(p: dict, floor: float | None) -> dict:
    """The pads' keywords of :mod:`rocking.reference.paper` from the model's parameters by name: Kelvin-Voigt
    ``L, k_b, c_b``; Hunt-Crossley ``L, k_b, n_b`` and its damping (the model's own parameter) with ``floor``."""
    law = {k: p[k] for k in ("L", "k_b", "c_b", "n_b", "e_b", "chi_b") if k in p}
    return {**law, "floor": floor} if "n_b" in p else law


class _Plain:
    def __init__(self, problem, floor: float | None):
        p = dict(zip(problem.model.parameters, (float(v) for v in problem.p)))
        self.body = {k: p[k] for k in BODY}
        self.problem = problem
        self.hunt_crossley = "n_b" in p
        self.law = pad_law(p, floor)
        self.v_in = [floor, floor] if self.hunt_crossley else None

    def stops(self) -> dict:
        return {**self.law, "v_in": tuple(self.v_in)} if self.hunt_crossley else self.law

    def ag(self, t: float) -> float:
        return float(self.problem.ground_acceleration(t))

    def rhs(self, phase: int):
        b = self.body

        def f(t, y):
            theta, x, dtheta, dx = y
            if phase == 0:
                return [0.0, dx, 0.0, paper.contact_accel(x, dx, self.ag(t), b["m"], b["k_m"], b["c"], **self.stops())]
            ddtheta, ddx = paper.rocking_accel(phase, theta, x, dtheta, dx, self.ag(t), 0.0, **b, **self.stops())
            return [dtheta, dx, ddtheta, ddx]

        return f

    def pad_state(self, y) -> list[tuple[float, float]]:
        """Per side (upper, lower): ``(delta, contact)``, the raw penetration and ``min(delta, bracket)``."""
        out = []
        for side in (1, -1):
            delta = side * y[1] - self.law["L"]
            bracket = paper.pad(y[1], y[3], side=side, **self.stops())[1]
            out.append((delta, min(delta, float(bracket))))
        return out

    def pushing(self, y) -> list[bool]:
        return [contact > 0.0 for _, contact in self.pad_state(y)]

    def force(self, y) -> float:
        return float(max(paper.stop_forces(y[1], y[3], **self.stops())))

    def uplift(self, s: int, t: float, y) -> float:
        b = self.body
        keys = ("M", "B", "H", "e", "g", "m", "h", "k_m", "c")
        return float(paper.uplift_margin(s, y[1], y[3], self.ag(t), 0.0, *(b[k] for k in keys), **self.stops()))


def _events(plain: _Plain, phase: int):
    """The terminal events of a phase (pads' zeros, uplift or impact and overturning) and the extrema."""
    events = []
    for side in range(2):

        def pad(t, y, side=side):
            return plain.pad_state(y)[side][1]

        pad.terminal = True
        events.append(pad)
    if phase == 0:
        for s in (1, -1):

            def lift(t, y, s=s):
                return plain.uplift(s, t, y)

            lift.terminal, lift.direction = True, 1
            events.append(lift)
    else:

        def impact(t, y):
            return phase * y[0]

        def overturn(t, y):
            return phase * y[0] - math.pi / 2

        impact.terminal, impact.direction = True, -1
        overturn.terminal, overturn.direction = True, 1
        events += [impact, overturn]
    extrema = []
    for k in (2, 3):

        def extremum(t, y, k=k):
            return y[k]

        extrema.append(extremum)
    return events, extrema


def _force_peak(plain: _Plain, sol, best: float) -> float:
    """The largest pads' force on the dense output of ``sol``: a grid per step, polished where it leads."""
    ts = sol.sol.ts
    grid = (ts[:-1, None] + np.linspace(0.0, 1.0, GRID + 1)[None, :] * np.diff(ts)[:, None]).ravel()
    states = sol.sol(grid)
    forces = np.max(paper.stop_forces(states[1], states[3], **plain.stops()), axis=0).reshape(-1, GRID + 1)
    for step in np.flatnonzero(forces.max(axis=1) >= max(best, 1e-300)):
        k = int(np.argmax(forces[step]))
        times = grid.reshape(-1, GRID + 1)[step]
        lo, hi = times[max(k - 1, 0)], times[min(k + 1, GRID)]
        found = minimize_scalar(
            lambda t: -plain.force(sol.sol(t)), bounds=(lo, hi), method="bounded", options={"xatol": 1e-14}
        )
        best = max(best, float(forces[step, k]), -found.fun)
    return best


def _account(plain: _Plain, result: Result, sol, extrema_index: tuple[int, int]) -> None:
    points = [sol.y.T] + [np.atleast_2d(sol.y_events[i]) for i in extrema_index if len(sol.y_events[i])]
    points = np.vstack(points)
    result.theta_max = max(result.theta_max, float(np.max(np.abs(points[:, 0]))))
    result.x_max = max(result.x_max, float(np.max(np.abs(points[:, 1]))))
    result.bumper_force_max = _force_peak(plain, sol, result.bumper_force_max)


def _jump_memory(plain: _Plain, before, after) -> None:
    """A Hunt-Crossley pad's memory across a jump of ``dx`` with the mass in the pad: ``max(v_in, ddelta)``."""
    if not plain.hunt_crossley:
        return
    for i, side in enumerate((1, -1)):
        rate_before, rate_after = side * before[3], side * after[3]
        if side * after[1] - plain.law["L"] > 0.0 and rate_after != rate_before:
            plain.v_in[i] = max(plain.v_in[i], rate_after)


def _close_memory(plain: _Plain, before, after) -> None:
    """Where a gap closes, a new contact: its ``v_in`` is ``max(ddelta, v_f)``."""
    if not plain.hunt_crossley:
        return
    for i, side in enumerate((1, -1)):
        if side * before[1] - plain.law["L"] <= 0.0 < side * after[1] - plain.law["L"]:
            plain.v_in[i] = max(side * after[3], plain.law["floor"])


def _count(result: Result, was: list[bool], now: list[bool]) -> None:
    result.stop_contacts += sum(1 for a, b in zip(was, now) if b and not a)


def plain_run(problem, t_end: float, floor: float | None = None, rtol: float = 1e-11) -> Result:
    """Integrate ``problem`` (a :class:`~rocking.sim.problem.Problem` of ``omd_stops`` or ``omd_stops_hc``, no
    vertical motion) from rest to ``t_end`` by the documented law, with no regime carried.

    Parameters
    ----------
    problem : Problem
        The run: its parameters, motion, ``dtheta_rest`` and ``contact_max_step``.
    t_end : float
        Where the integration ends [s].
    floor : float, optional
        The Hunt-Crossley pads' least approach speed ``v_f`` (the manifest's ``approach_floor``).
    rtol : float
        The integrator's relative tolerance (its absolute one is ``rtol`` times 1e-3 of each component's unit).

    Returns
    -------
    Result
    """
    plain = _Plain(problem, floor)
    result = Result()
    t, y, phase = 0.0, np.zeros(4), 0
    if plain.hunt_crossley:
        plain.v_in = [max(float(y[3]), floor), max(float(-y[3]), floor)]
    t_p = float(problem.t_p)
    result.rows.append((t, *y, phase))
    while t < t_end:
        if phase == 0 and t >= 0.0:
            lifted = [s for s in (1, -1) if plain.uplift(s, t, y) > 0.0]
            if lifted:
                phase = lifted[0]
                result.uplifts += 1
                continue
        bound = min(t_p, t_end) if t < t_p else t_end
        events, extrema = _events(plain, phase)
        max_step = float(problem.contact_max_step) if phase == 0 and t < t_p else np.inf
        sol = solve_ivp(
            plain.rhs(phase),
            (t, bound),
            y,
            method="RK45",
            rtol=rtol,
            atol=rtol * 1e-3,
            events=events + extrema,
            dense_output=True,
            max_step=max_step,
        )
        if sol.status < 0:
            raise RuntimeError(sol.message)
        _account(plain, result, sol, (len(events), len(events) + 1))
        fired = [i for i, times in enumerate(sol.t_events[: len(events)]) if len(times)]
        t, y = float(sol.t[-1]), np.array(sol.y[:, -1])
        if not fired:
            t = bound
            continue
        kind = fired[0]
        if kind < 2:  # a pad's zero: restart just after it, on the dense output, within the step that found it
            before = sol.sol(t - RESTART)
            end = float(sol.sol.interpolants[-1].t)
            t = min(t + RESTART, end) if end > t else t + RESTART
            y = np.array(sol.sol(t))
            _close_memory(plain, before, y)
            _count(result, plain.pushing(before), plain.pushing(y))
            result.rows.append((t, *y, phase))
            continue
        if phase == 0:  # an uplift
            phase = 1 if kind == 2 else -1
            result.uplifts += 1
            continue
        if kind == 3:
            result.overturned = True
            break
        y[0] = 0.0
        before = y.copy()
        was = plain.pushing(y)
        b = plain.body
        keys = ("M", "I_G", "B", "H", "e", "m", "h")
        y[2], y[3] = paper.impact(phase, y[1], y[2], y[3], *(b[k] for k in keys))
        result.impacts += 1
        if abs(y[2]) < problem.dtheta_rest:  # the rest snap: the mass keeps its generalised momentum
            (_, _), (m21, m22) = paper.mass_matrix(-phase, 0.0, y[1], *(b[k] for k in keys))
            y[3] = y[3] + m21 * y[2] / m22
            y[2] = 0.0
            phase = 0
        else:
            phase = -phase
        _jump_memory(plain, before, y)
        _count(result, was, plain.pushing(y))
        result.bumper_force_max = max(result.bumper_force_max, plain.force(y))
        result.rows.append((t, *y, phase))
    result.t_end = t
    return result


def applied_force(problem, history: dict, floor: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The pads' force a recorded run applied, and the law's at the same rows.

    The applied force is read off the recorded motion: the accelerations by central differences of the
    recorded velocities on three consecutive rows equally spaced in one phase (samples with no event between
    them), less those of the free guide (``rocking.reference.paper`` without stops), give the generalised
    force on ``x``, ``-sign(x) F_b``. The law's is :func:`rocking.reference.paper.stop_forces` at the state,
    a Hunt-Crossley pad with the memory the history gives (``rocking.sim.pad_memory``).

    Returns
    -------
    applied, law : ndarray
        At each such row [N].
    """
    from rocking.sim.pad_memory import memory

    p = dict(zip(problem.model.parameters, (float(v) for v in problem.p)))
    b = {k: p[k] for k in BODY}
    t, phase, ag = history["t"], history["phase"], history["ag"]
    theta, x, dtheta, dx = (history[k] for k in ("theta", "x", "dtheta", "dx"))
    k = np.arange(1, len(t) - 1)
    before, after = t[k] - t[k - 1], t[k + 1] - t[k]
    even = (before > 0) & (np.abs(after - before) <= 1e-6 * before)
    k = k[even & (phase[k - 1] == phase[k]) & (phase[k + 1] == phase[k])]
    span = t[k + 1] - t[k - 1]
    ddtheta, ddx = (dtheta[k + 1] - dtheta[k - 1]) / span, (dx[k + 1] - dx[k - 1]) / span
    s = np.where(phase[k] == 0, 1.0, phase[k].astype(float))
    keys = ("M", "I_G", "B", "H", "e", "m", "h")
    (_, _), (m21, m22) = paper.mass_matrix(s, theta[k], x[k], *(b[n] for n in keys))
    rest = ("M", "B", "H", "e", "g", "m", "h", "k_m", "c")
    _, f2 = paper.forcing(s, theta[k], x[k], dtheta[k], dx[k], ag[k], 0.0, *(b[n] for n in rest))
    rocking_q = m21 * ddtheta + m22 * ddx - f2
    contact_q = b["m"] * ddx - b["m"] * paper.contact_accel(x[k], dx[k], ag[k], b["m"], b["k_m"], b["c"])
    applied = -np.sign(x[k]) * np.where(phase[k] == 0, contact_q, rocking_q)
    law = pad_law(p, floor)
    if "n_b" in p:
        law["v_in"] = tuple(v[k] for v in memory(problem.model, list(problem.p), history))
    return applied, np.max(paper.stop_forces(x[k], dx[k], **law), axis=0)


def pulse(rng, family: str, threshold: float):
    """A pulse of ``family`` of 1.2-3 times the uplift threshold, ``omega_g`` 4-12 rad/s, either sign."""
    a_g, omega_g, sign = threshold * rng.uniform(1.2, 3.0), rng.uniform(4.0, 12.0), int(rng.choice([-1, 1]))
    if family == "sine":
        return rocking.OneSinePulse(a_g=a_g, omega_g=omega_g, sign=sign)
    if family == "cosine":
        return rocking.OneCosinePulse(a_g=a_g, omega_g=omega_g, sign=sign)
    if family == "mp":
        return rocking.MavroeidisPapageorgiou(a_g=a_g, omega_g=omega_g, gamma_mp=2.5, sign=sign)
    return rocking.RickerWavelet(a_g=a_g, omega_g=omega_g, antisymmetric=family == "ricker_anti", sign=sign)


def random_case(rng, law: str, family: str):
    """A random block, damper with pads of ``law``, and pulse of ``family`` (the ranges of ``bench/pads.py``)."""
    H, B = rng.uniform(1.5, 3.0), rng.uniform(0.4, 0.8)
    block = rocking.Block(H=H, B=B, M=1000.0, e=rng.uniform(-0.02, 0.02))
    m, w_m = 100.0, rng.uniform(1.5, 3.0)
    L, k_b = rng.uniform(0.08, 0.2), 10 ** rng.uniform(5.0, 6.5)
    if law == "kelvin-voigt":
        stops = rocking.Stops(L=L, k_b=k_b, c_b=2 * rng.uniform(0.05, 0.4) * np.sqrt(k_b * m))
    else:
        stops = rocking.Stops(L=L, k_b=k_b, law=law, n=float(rng.choice([1.0, 1.5])), e_b=rng.uniform(0.3, 0.95))
    damper = rocking.Damper(m=m, k_m=m * w_m**2, c=2 * rng.uniform(0.0, 0.2) * m * w_m, h=0.08, stops=stops)
    return block, damper, pulse(rng, family, block.g * B / H)
