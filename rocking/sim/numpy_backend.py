"""NumPy/SciPy reference back end: the phase machine of ``docs/simulation.md``.

:func:`simulate` runs one :class:`~rocking.sim.problem.Problem` with
``scipy.integrate.solve_ivp`` (``RK45``, Dormand-Prince 5(4)) on the generated
NumPy functions of ``problem.model``. It is the readable reference that the C
back end (``rocking/sim/csrc/sim.c``) must reproduce, so it does exactly what
the contract says and nothing clever:

- one ``solve_ivp`` call per *segment*: a phase (full contact, rocking about
  ``A``, rocking about ``A'``) between two events or breakpoints;
- the contract's events are ``solve_ivp`` events (located by SciPy on the dense
  output with Brent's method to ``4 eps``), built by the small factories of the
  section "Event functions" and kept apart from the phase logic;
- what happens at an event (impact map, rest, uplift, end) is decided by the
  phase machine, segment by segment.

The phase machine is split as in sim.c, with the same names where the role is
the same; the state of a run lives in :class:`_Run`, sim.c's ``struct run``:

- :func:`simulate`: ``simulate_one``;
- :func:`_initial_state`: ``initial_state``;
- :class:`_Run`: ``struct run``;
- :func:`phase_machine`: ``phase_machine``;
- :func:`contact_start`: the ``phase == 0`` block at the top of its loop;
- :func:`uplift_at_start`: ``uplift_at_start``;
- :func:`end_at_start`: the ``t >= t_p`` checks of that block;
- :func:`verdict_final`: ``verdict_final``; ``_System.verdict_bound``: ``verdict_bound``
  (:func:`status_at_t_max` and ``_System.barrier_bound``: ``safe_at_t_max``)
  (with ``least_at_tilt``, ``least_on_arcs``, ``stops_out_of_reach`` and ``least_at_bumpers``);
- :func:`settled_at_once`: ``settled_at_once``;
- :func:`run_segment`: ``run_segment``;
- :func:`integrate_segment`: ``run_segment``'s loop of ``dopri_step`` and
  ``events_scan``;
- :func:`lift_off_step`: ``run_segment``'s ``lifting`` retry;
- :func:`watched_events`: ``watched_events``;
- :func:`segment_end`: the ``switch`` on ``run_segment``'s result;
- :func:`uplift`: its ``EV_UPLIFT_A`` and ``EV_UPLIFT_A_PRIME`` cases, and the
  uplift at the start of full contact;
- :func:`impact`: ``impact`` and the ``events_exhausted`` check after it;
- :func:`events_exhausted`: ``events_exhausted``;
- :func:`record`: ``record``; ``_History.add_samples``: ``record_samples``;
- ``_Tally.see_state``: ``see_state``; ``_Tally.see_segment``:
  ``pass_event`` and ``see_state`` over a whole segment;
- :func:`finish`: the end of ``simulate_one``;
- ``_System.safe_energy``: ``safe_energy``; ``_System.energy_above_rest``:
  ``energy_above_rest``.

The state is ``y = (q, dq)`` in manifest order with ``theta = q[0]``; the
damper coordinate (if any) is ``q[1]``. Nothing here knows a coordinate's or a
parameter's name: another generated model runs unchanged.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import RK45, OdeSolution, solve_ivp

from ..model.motion import FAMILIES, SHAPES, interpolate, sample_piece
from ..model.params import ParameterError
from .boundary import (
    ARC_STEP,
    BARRIER_TILTS,
    CONTACT,
    FIRST_STEP_FRACTION,
    FLAT_LANDING,
    SAFE_MARGIN,
    STATUS,
    TAKEOFF_PROBE,
)
from .history import FLIGHT_COLUMNS, FLOOR_COLUMNS, first_sample_after
from .phases import ENDS, next_phase
from .phases import of as phase_of
from .phases import phase as table_phase
from .problem import Problem, Response, SimulationError

__all__ = ["simulate"]

#: ``(t, y) -> value``: the signature of right-hand sides and event functions.
StateFunction = Callable[[float, np.ndarray], float]

#: Terminal events: their names, as :func:`simulate` dispatches on them.
UPLIFT_A, UPLIFT_A_PRIME, IMPACT, OVERTURN, REST = "uplift A", "uplift A'", "impact", "overturn", "rest"

#: Terminal events of the early rest (docs/simulation.md, rule 4): the energy falls
#: below the uplift energy; once safe, the damper's next extremum ends the run.
SAFE, SETTLED = "safe", "settled"

#: Non-terminal events: reported values only, the run goes on.
CRITICAL, EXTREMUM = "critical angle", "extremum"

#: How a rocking segment from ``theta = 0`` ends when the block cannot rise at all.
NO_LIFT = "no lift"
#: A slip that cannot start: even the shortest first step turns the slip speed back (sim.c's SEG_NO_SLIP).
NO_SLIP = "no slip"
#: A takeoff whose corner cannot rise: even the shortest first step of the flight leaves it on or below the floor.
NO_TAKEOFF = "no takeoff"
#: The events of a floor with friction (rocking.sim.phases.EVENTS).
SLIP, STOP, LIFT_OFF = "slip", "stop", "lift-off"
#: The event ``landing`` of the flight phase (docs/model.md section 16) at the reference corner ``s``, at ``-s``.
LANDING, LANDING_OTHER = "landing", "landing -s"
#: The terminal events that end the run through the table's exit: overturning, rest, and the settling's last
#: extremum of the damper below the uplift energy (a rest, rule 4).
TABLE_ENDS = {OVERTURN: "overturn", REST: "rest", SETTLED: "rest"}
#: Non-terminal events of flight: a corner's height peaks (for ``jump_max``).
HEIGHT_PEAK = "height peak"
#: What a history's row holds after the state on a floor with friction: the slip [m], its speed [m/s], its
#: direction (the floor's forces are computed at the end, :func:`floor_forces`).
SLIP_COLUMNS = ("u", "du", "slide")
#: A sliding base's uplift margin below this fraction of the weight's moment about the corner is rounding.
SLIDE_UPLIFT_ROUNDING = 64 * np.finfo(float).eps

#: Terminal events of the end stops (rule 6): a side's bumper starts pushing (its gap closes, or a released
#: pad's force turns positive again), or stops (its force falls to 0, or the gap opens).
GAP_CLOSE, GAP_OPEN = "gap closes", "gap opens"


class _MaxSteps(Exception):
    """The work of the run passed ``max_steps`` (docs/simulation.md, rule 5): raised out of a segment."""


@dataclass
class _Work:
    """The work of a run (rule 5): right-hand-side evaluations plus recorded samples, against ``max_steps``."""

    max_steps: int
    done: int = 0

    def add(self, amount: int) -> None:
        self.done += amount
        if self.done > self.max_steps:
            raise _MaxSteps

    def counted(self, rhs: StateFunction) -> StateFunction:
        """``rhs`` counting its evaluations (what sim.c's ``dopri.evaluations`` counts)."""

        def counted_rhs(t, y):
            self.add(1)
            return rhs(t, y)

        return counted_rhs


#: The time of one restart of a segment on this back end, in right-hand-side evaluations: ``solve_ivp``'s
#: set-up, Hairer's initial step and the events' first values. A sampled motion restarts at every sample
#: (docs/simulation.md, rule 3): measured 1.2 - 1.8 ms a sample, at 20 - 25 us an evaluation.
RESTART_WORK = 60
#: The time of one recorded sample on this back end, in evaluations: 2 - 13 us (the dense output, a row).
SAMPLE_WORK = 0.25
#: The most planned work (:func:`planned_work`) this back end takes on: 2 - 3 s of CPU at 20 - 40 us an
#: evaluation (bench/numpy_bound.py). Rule 5's ``max_steps`` bounds the evaluations of both back ends, not
#: this back end's restarts, which cost ten times as much each: a 20,000-sample record took 21 - 36 s within it.
PLANNED_WORK_LIMIT = 75_000


def planned_work(problem: Problem, record: bool) -> dict[str, int]:
    """The work ``problem``'s settings plan for this back end, if the block stays in full contact to ``t_max``.

    Each part in the time of right-hand-side evaluations on this back end, a run's dynamics aside:
    the steps of at most ``contact_max_step`` through the motion (6 evaluations each) and, with
    ``record``, the history's samples (:data:`SAMPLE_WORK` each), and the restarts at the samples of a
    sampled motion (:data:`RESTART_WORK` each). Rule 5 ends a run once its evaluations and samples
    (1 each there) pass ``max_steps``: the steps and samples are cut there, the steps first (the
    heavier: the most time the run can take).
    """
    t_p = min(float(problem.t_p), float(problem.t_max))
    step = float(problem.contact_max_step)
    if FAMILIES[problem.motion] == "sampled":
        pulse_dt = float(problem.pulse_dt)
        pieces = math.ceil(t_p / pulse_dt)
        steps, restarts = pieces * math.ceil(pulse_dt / step), pieces
    else:
        steps, restarts = math.ceil(t_p / step), 0
    record_dt = float(problem.record_dt)
    samples = math.floor(float(problem.t_max) / record_dt) if record and record_dt > 0.0 else 0
    max_steps = int(problem.max_steps)
    evaluations = min(6 * steps, max_steps)
    return {
        "contact steps": evaluations,
        "recorded samples": math.ceil(SAMPLE_WORK * min(samples, max_steps - evaluations)),
        "restarts at samples": RESTART_WORK * restarts,
    }


def check_planned_work(problem: Problem, record: bool) -> None:
    """Refuse, before any step, a run whose :func:`planned_work` passes :data:`PLANNED_WORK_LIMIT`.

    Raises
    ------
    ParameterError
        One line: the planned work, its parts, the limit, and what to do instead.
    """
    parts = planned_work(problem, record)
    total = sum(parts.values())
    if total > PLANNED_WORK_LIMIT:
        shown = ", ".join(f"{work:,} for the {part}" for part, work in parts.items() if work)
        raise ParameterError(
            f"the NumPy back end plans the work of {total:,} right-hand-side evaluations for this run ({shown}), "
            f"at most {PLANNED_WORK_LIMIT:,}: run it on the C back end (backend='c'), or shorten it (a shorter "
            "motion or t_max, a larger record_dt)"
        )


# --------------------------------------------------------------------------- #
# The generated model with the run's parameters bound                          #
# --------------------------------------------------------------------------- #


class _System:
    """The generated functions of one problem, called with a bound parameter tuple.

    Every generated function takes ``(s, *q, *dq, ag, *params)``; this class
    fixes ``params`` once per run (a tuple of Python floats: cheaper to unpack
    and to compute with than NumPy scalars) and exposes the few calls the
    phase machine needs, with a state vector ``y`` instead of unpacked
    arguments.

    Parameters
    ----------
    problem : Problem
        The run.
    """

    def __init__(self, problem: Problem):
        self.n = problem.model.nq
        self.functions = problem.model.functions
        self.params = tuple(float(v) for v in problem.p)
        self.problem = problem
        self.family = FAMILIES[problem.motion]
        # Each coordinate's impact law (docs/model.md section 6; "momentum" unless the manifest says otherwise).
        laws = problem.model.manifest.get("options", {}).get("impact_laws", {})
        self.impact_laws = tuple(laws.get(name, "momentum") for name in problem.model.coordinates)
        self.n_stops = int(problem.model.manifest["functions"]["stop_gaps"]["outputs"])
        self.gravity = problem.model.parameters.index("g")
        # Per stop side, the least approach speed of a Hunt-Crossley pad (None: no memory, Kelvin-Voigt).
        sides = problem.model.manifest.get("stops", [])
        self.floors = [side["approach_floor"] if side["law"] == "hunt-crossley" else None for side in sides]
        # The memory v_in of each Hunt-Crossley side: the approach speed of its contact (docs/model.md section 11).
        self.memory = [floor for floor in self.floors if floor is not None]
        # Energy of the rest state, the zero of "energy above rest". In full
        # contact (theta = dtheta = 0) the energy does not depend on the pivot.
        self.energy_at_rest = self.energy(np.zeros(2 * self.n))
        # With stops, the energy above rest below which the mass, upright, can no longer reach a pad (rule 4).
        self.pad_reach = self._pad_reach() if self.n_stops else math.inf
        self.safe_energy = self._safe_energy()
        # Rest (rule 4) with stops also needs the mass out of every pad's reach (NaN: no bound, energy_rest alone).
        reach = problem.energy_rest if math.isnan(self.pad_reach) else self.pad_reach
        self.rest_energy = min(problem.energy_rest, reach)
        # A floor with friction (docs/model.md section 15): mu_s = inf keeps the contact stuck, as the paper's.
        self.mu_s, self.mu_k = float(problem.mu_s), float(problem.mu_k)
        self.friction = math.isfinite(self.mu_s)
        # Where mu_k = tan(alpha_s) a sliding base's uplift margin is 0 up to rounding for as long as it slides: a
        # margin within rounding of the weight's moment about the corner is no uplift (docs/simulation.md).
        zeros = np.zeros(2 * self.n)
        self.slide_uplift_floor = (
            {s: SLIDE_UPLIFT_ROUNDING * abs(float(self._call("uplift", s, zeros, 0.0))) for s in (1, -1)}
            if self.friction
            else {}
        )
        # A model with flight functions follows flight on every floor (docs/model.md section 16); its history
        # holds the floor's columns then, mu_s = inf included.
        self.flies = bool(problem.model.manifest.get("flight", False))
        self.floor_columns = self.friction or self.flies
        self.e_n = float(problem.e_n)
        # A landing whose corner leaves at more than the speed of a corner of the block turning at dtheta_rest
        # bounces (the spec of issue 39, point 4): below it, the block stays on the floor.
        half_base = 0.5 * self.params[problem.model.parameters.index("B")] if self.flies else math.nan
        self.bounce_speed = float(problem.dtheta_rest) * half_base
        # Without a vertical component a full contact's N is the weight of the system, constant (the damper and
        # the bumpers act horizontally in the block frame; tests/test_flight_numpy.py checks it): not watched there.
        self.constant_contact_normal = float(problem.a_v) == 0.0

    def _safe_energy(self) -> float | None:
        """The early rest's bound: the least energy above rest at which the attached bodies can lift the block,
        less the margin, and with stops at most :attr:`pad_reach` (rule 4).

        ``min(U_{+1}, U_{-1}) (1 - SAFE_MARGIN)`` of the generated
        ``uplift_energy`` (constant per run); ``None`` when no bound applies
        (0 or NaN about either pivot, or no room below the pads). ``inf`` for the bare block.
        """
        zeros = np.zeros(2 * self.n)
        a, b = (float(self._call("uplift_energy", s, zeros, 0.0)) for s in (1.0, -1.0))
        if not (a > 0.0 and b > 0.0 and self.pad_reach > 0.0):
            return None
        return min(min(a, b) * (1.0 - SAFE_MARGIN), self.pad_reach)

    def _pad_reach(self) -> float:
        """The energy above rest below which the mass of the upright block, inside every gap, can never reach a
        pad: the least potential where a gap closes at ``theta = 0`` less ``E(0)`` and the margin (NaN: no bound)."""
        least, zero = self.least_at_bumpers(0.0), self.energy_at_rest
        return least - zero - SAFE_MARGIN * (abs(least) + abs(zero))

    def _call(self, name: str, s: float, y: np.ndarray, ag: float, stop_on: tuple | None = None, params=None, agy=0.0):
        # y.tolist(): Python floats, not NumPy scalars, in the generated arithmetic. stop_on: the regime
        # of the stops as 0.0 / 1.0 per side, what sim.c prepares its constants with; None: that of y.
        params = self.params if params is None else params
        return getattr(self.functions, name)(s, *y[: 2 * self.n].tolist(), ag, agy, *params, stop_on=stop_on)

    def _friction(self, name: str, s: float, y: np.ndarray, ag: float, stop_on: tuple, agy: float, *inputs):
        """A generated function of the floor with friction at the first ``2 n`` components of ``y`` (the
        slip ``u``, ``du`` after them are its inputs, not its state), in the regime ``stop_on``."""
        return getattr(self.functions, name)(
            s, *y[: 2 * self.n].tolist(), ag, agy, *self.params, *inputs, stop_on=self.regime(stop_on)
        )

    def floor_force(self, phase: int, y: np.ndarray, ag: float, stop_on: tuple, agy: float) -> tuple[float, float]:
        """``(F, N)``: the force the floor must hold on the stuck contact of ``phase`` (``CONTACT`` or ``s``),
        from the function the phase table names."""
        entry = phase_of(phase != CONTACT, False)
        return self._friction(entry.force, _pivot(phase), y, ag, stop_on, agy)

    def slide_accel(self, phase: int, sigma: int, y: np.ndarray, ag: float, stop_on: tuple, agy: float) -> tuple:
        """``(ddq..., ddu, N)`` of the sliding phase of ``phase`` with the slip's direction ``sigma``, from the
        function the phase table names."""
        entry = phase_of(phase != CONTACT, True)
        return self._friction(entry.accel, _pivot(phase), y, ag, stop_on, agy, self.mu_k * sigma)

    def floor_normal(self, phase: int, sigma: int, y: np.ndarray, ag: float, stop_on: tuple, agy: float) -> float:
        """The floor's normal force ``N`` [N] on the contact of ``phase`` with the slip ``sigma`` (the state ``y``
        with ``u``, ``du`` after ``2 n`` components when sliding): the force function of the phase table."""
        if sigma:
            return float(self.slide_accel(phase, sigma, y, ag, stop_on, agy)[-1])
        return float(self.floor_force(phase, y, ag, stop_on, agy)[1])

    def watches_lift_off(self, phase: int) -> bool:
        """The phase on the floor watches its ``lift-off``: every phase of a model with flight (any floor), or of a
        floor with friction; full contact only where its ``N`` can change (a vertical component)."""
        if not (self.flies or self.friction):
            return False
        return phase != CONTACT or not self.constant_contact_normal

    def _flight(self, name: str, s: float, y: np.ndarray, *inputs, ag: float = 0.0, agy: float = 0.0):
        """A generated function of flight at the rocking state ``y[:2 n]`` with the ``inputs`` of its manifest
        (the regime of the stops that of the state: none of these functions depends on it)."""
        return getattr(self.functions, name)(s, *y[: 2 * self.n].tolist(), ag, agy, *self.params, *inputs)

    def flight_corner(self, s: int, y: np.ndarray, u: float, v: float, du: float, dv: float) -> tuple:
        """``(u, v, du, dv)`` of the corner ``-s``: the flying state taken about the other corner."""
        return tuple(float(c) for c in self._flight("flight_corner", float(s), y, u, v, du, dv))

    def flight_rhs(self, s: int, ground, stop_on: tuple, vertical) -> StateFunction:
        """``(dq, ddq, du, ddu, dv, ddv)`` of the flight about the reference corner ``s`` on the state with ``u``,
        ``du``, ``v``, ``dv`` after the ``2 n`` components (generated ``flight_accel``, in the regime ``stop_on``)."""
        n, regime, accel = self.n, self.regime(stop_on), self.functions.flight_accel

        def rhs(t, y):
            dy = np.empty_like(y)
            dy[:n] = y[n : 2 * n]
            out = accel(float(s), *y[: 2 * n].tolist(), ground(t), vertical(t), *self.params, stop_on=regime)
            dy[n : 2 * n] = out[:n]
            dy[2 * n], dy[2 * n + 1] = y[2 * n + 1], out[n]
            dy[2 * n + 2], dy[2 * n + 3] = y[2 * n + 3], out[n + 1]
            return dy

        return rhs

    def takeoff_margin(self, phase: int, sigma: int, y: np.ndarray, ag: float, stop_on: tuple, agy: float) -> float:
        """What the ``lift-off`` of ``phase`` with the slip ``sigma`` watches: > 0 while the contact holds.

        The floor's normal force ``N`` (:meth:`floor_normal`), save on a stuck corner of a floor without friction
        (``mu_s = inf``): there ``N`` can reach 0 while the floor holds a tangential force ``F`` (a finite floor
        slides first, and its ``F`` vanishes with ``N``), and letting go of ``F`` may drive the corner into the
        floor. The block takes off where ``N <= 0`` and the free flight lifts the corner: the larger of ``N`` and
        minus the corner's vertical acceleration in flight (``flight_accel``'s ``ddv``) falls to 0 (its sign
        alone matters: where either is > 0, the floor holds). Elsewhere ``N`` alone: a full contact's ``N``
        reaches 0 with ``F = 0`` (an uplift comes first where ``ag`` is not 0).
        """
        N = self.floor_normal(phase, sigma, y, ag, stop_on, agy)
        if N > 0.0 or self.friction or phase == CONTACT:
            return N
        out = self.functions.flight_accel(
            float(phase), *y[: 2 * self.n].tolist(), ag, agy, *self.params, stop_on=self.regime(stop_on)
        )
        return max(N, -float(out[self.n + 1]))

    def corner_sinks(self, t: float, phase: int, sigma: int, y: np.ndarray, pulse_on: bool, stop_on: tuple) -> bool:
        """At a takeoff of a stuck corner of a floor without friction: the free flight does not lift the corner.

        The margin's zero where ``-ddv`` reaches 0 leaves ``ddv = 0`` up to rounding, and whether the flight rises
        is then the sign of its own rate of change, which differs from the one along the phase on the floor: ``ddv``
        is read :data:`TAKEOFF_PROBE` along the flight (one Euler step of the rocking state), at either zero of the
        margin alike (at ``N``'s, ``ddv > 0`` there too). True where it is not positive: the takeoff grazes, the
        pivot is held (docs/simulation.md, "Flight").
        """
        if self.friction or phase == CONTACT or sigma:
            return False
        n, ground, vertical = self.n, self.ground(pulse_on, t), self.vertical(pulse_on, t)

        def accel(at: float, state: np.ndarray) -> np.ndarray:
            return self.functions.flight_accel(
                float(phase), *state.tolist(), ground(at), vertical(at), *self.params, stop_on=self.regime(stop_on)
            )

        out = accel(t, y[: 2 * n])
        rates = [float(v) for v in y[n : 2 * n]] + [float(a) for a in out[:n]]
        probe = np.array([float(y[j]) + TAKEOFF_PROBE * rates[j] for j in range(2 * n)])
        return not float(accel(t + TAKEOFF_PROBE, probe)[n + 1]) > 0.0

    def corner_landing(self, s: int, y: np.ndarray, du: float, dv: float) -> tuple | None:
        """The corner ``s`` lands alone (docs/model.md section 16, :func:`rocking.reference.flight.landing_law`).

        Returns
        -------
        tuple or None
            ``(dq, du, dv, sigma)`` after it, ``sigma`` 0 when the corner sticks (``P_n > 0``,
            ``|P_t| <= mu_s P_n``), else the direction it slides in; ``None``: no law holds (a jam).
        """
        n = self.n
        out = [float(c) for c in self._flight("landing_stick", float(s), y, du, dv, self.e_n)]
        P_t, P_n = out[-2], out[-1]
        if P_n > 0.0 and abs(P_t) <= self.mu_s * P_n:
            return out[:n], 0.0, out[n + 1], 0
        if not self.friction:
            return self.tangential_landing(s, y, du, dv, out)
        for sigma in _slide_directions(du, P_t):
            out = [float(c) for c in self._flight("landing_slide", float(s), y, du, dv, self.e_n, sigma * self.mu_k)]
            if out[-1] > 0.0 and sigma * du >= 0.0 and sigma * out[n] >= 0.0:
                return out[:n], out[n], out[n + 1], sigma
        return None

    def tangential_landing(self, s: int, y: np.ndarray, du: float, dv: float, stick: list) -> tuple | None:
        """The corner ``s`` lands on a floor without friction (``mu_s = inf``) where the sticking impulse ``stick``
        (``landing_stick``'s outputs) would pull, ``P_n <= 0``.

        The cone of the floor's impulses is then the half-plane ``P_n >= 0``, and the plastic landing is the
        tangential impulse alone: it stops the slip (``du = 0`` after) and lifts the corner, ``dv`` after it
        ``dv - W_nt du / W_tt > 0`` exactly where the sticking ``P_n < 0`` (docs/model.md section 16). Built from
        the sticking and the frictionless landings (``landing_slide`` at ``mu_slip = 0``): the velocities after a
        landing are linear in its impulse. The operations of sim.c's ``tangential_landing``.

        Returns
        -------
        tuple or None
            ``(dq, du, dv, 0)`` after it, as :meth:`corner_landing`; ``None`` where it does not lift the corner.
        """
        n = self.n
        free = [float(c) for c in self._flight("landing_slide", float(s), y, du, dv, self.e_n, 0.0)]
        before = [float(c) for c in y[n : 2 * n]] + [du, dv]
        P_t, P_n, P_0 = stick[n + 2], stick[n + 3], free[n + 3]
        if not P_0 > 0.0 or P_t == 0.0:
            return None
        a_n = [(free[j] - before[j]) / P_0 for j in range(n + 2)]
        a_t = [(stick[j] - before[j] - a_n[j] * P_n) / P_t for j in range(n + 2)]
        p_t = -du / a_t[n]
        after = [before[j] + a_t[j] * p_t for j in range(n + 2)]
        return (after[:n], 0.0, after[n + 1], 0) if after[n + 1] >= 0.0 else None

    def flat_landing(self, s: int, y: np.ndarray, du: float, dv: float) -> tuple:
        """The base lands flat on both corners (``theta = 0`` in ``y``; docs/model.md section 16).

        Returns
        -------
        tuple
            ``("flat", (dq, du, dv, sigma))`` when both corners push (``P_s, P_o >= 0``) under the law the floor
            allows (stuck if ``|P_t| <= mu_s (P_s + P_o)``, else sliding as :meth:`corner_landing`);
            ``("corner", c)`` where under that law the corner ``-c`` would pull: the corner ``c`` lands alone;
            ``("jam", None)`` where no law holds.
        """
        n = self.n
        out = [float(c) for c in self._flight("flat_landing_stick", float(s), y, du, dv, self.e_n)]
        P_t = out[-3]
        law = out if abs(P_t) <= self.mu_s * (out[-2] + out[-1]) else None
        sigma = 0
        if law is None and self.friction:
            for sigma in _slide_directions(du, P_t):
                slide = self._flight("flat_landing_slide", float(s), y, du, dv, self.e_n, sigma * self.mu_k)
                slide = [float(c) for c in slide]
                if sigma * du >= 0.0 and sigma * slide[n] >= 0.0:
                    law = slide
                    break
        if law is None:
            return "jam", None
        P_s, P_o = law[-2], law[-1]
        if P_s >= 0.0 and P_o >= 0.0:
            return "flat", (law[:n], law[n], law[n + 1], sigma)
        if P_s < 0.0 and P_o < 0.0:
            return "jam", None
        return "corner", s if P_o < 0.0 else -s

    def phase_rhs(self, phase: int, sigma: int, ground, stop_on: tuple, vertical, flying: bool = False):
        """The right-hand side of the phase of the table with the pivot ``phase`` (``CONTACT`` or ``s``) and the
        slip ``sigma``: :meth:`stuck_rhs`, :meth:`slide_rhs`, or in flight :meth:`flight_rhs`."""
        if flying:
            return self.flight_rhs(phase, ground, stop_on, vertical)
        if sigma:
            return self.slide_rhs(phase, sigma, ground, stop_on, vertical)
        return self.stuck_rhs(phase, ground, stop_on, vertical)

    def slide_rhs(self, phase: int, sigma: int, ground, stop_on: tuple, vertical) -> StateFunction:
        """``(dq, ddq, du, ddu)`` of the sliding phase of ``phase`` (``CONTACT`` or ``s``) on the state with
        the slip ``u``, ``du`` after the ``2 n`` components; ``sigma`` the slip's direction (the segment's)."""
        n = self.n

        def rhs(t, y):
            dy = np.empty_like(y)
            dy[:n] = y[n : 2 * n]
            dy[2 * n] = y[2 * n + 1]
            out = self.slide_accel(phase, sigma, y, ground(t), stop_on, vertical(t))
            dy[n : 2 * n] = out[:n]
            dy[2 * n + 1] = out[n]
            return dy

        return rhs

    def slip_energy(self, y: np.ndarray, du: float) -> float:
        """The kinetic energy the slip speed ``du`` adds to the energy in the ground frame (0 when stuck)."""
        if du == 0.0:
            return 0.0
        return float(self._friction("slip_energy", 1.0, y, 0.0, (False,) * self.n_stops, 0.0, du))

    def friction_impact(self, s: int, y: np.ndarray, du: float, stop_on: tuple) -> tuple[np.ndarray, float, int]:
        """The impact that ends rocking about ``s`` on a floor with friction (docs/model.md section 15).

        Returns
        -------
        y : ndarray
            The state after it (``theta = 0``).
        du : float
            The slip speed after it.
        sigma : int
            0 when the new corner holds (``|P_t| <= mu_s P_n``), else the direction it slides in.
        """
        n = self.n
        after = np.array(y[: 2 * n], dtype=float)
        after[0] = 0.0
        out = self._friction("impact_stick", float(s), after, 0.0, stop_on, 0.0, du)
        P_t, P_n = float(out[n + 1]), float(out[n + 2])
        if abs(P_t) <= self.mu_s * P_n:
            if du == 0.0:
                # From a stuck pivot the stuck map is section 6's: the same operations as without friction.
                return self.impact(s, y, 0.0), 0.0, 0
            after[n:] = out[:n]
            return after, 0.0, 0
        sigma = -1 if P_t > 0.0 else 1
        out = self._friction("impact_slide", float(s), after, 0.0, stop_on, 0.0, du, self.mu_k * sigma)
        after[n:] = out[:n]
        return after, float(out[n]), sigma

    def _at(self, theta: float, x: float = 0.0) -> np.ndarray:
        """The state at rest velocities with ``theta`` and ``q[1] = x``, the other coordinates 0."""
        y = np.zeros(2 * self.n)
        y[0] = theta
        if self.n > 1:
            y[1] = x
        return y

    def _least(self, name: str, s: float, y: np.ndarray, params=None) -> float:
        """A generated least potential. Both branches of its ``Piecewise`` are evaluated: the one not
        taken may divide 0 by 0 where a stiffness is 0, and is not read."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return float(self._call(name, s, y, 0.0, params=params))

    def least_at_tilt(self, theta_m: float) -> float:
        """The least potential at ``|theta| = theta_m`` about either pivot (generated ``least_potential``)."""
        a = self._least("least_potential", 1.0, self._at(theta_m))
        b = self._least("least_potential", -1.0, self._at(-theta_m))
        return _lower(a, b)

    def least_on_arcs(self, theta_m: float, x_m: float) -> float:
        """The least potential with ``|q[1]| = x_m`` over the tilts ``|theta| <= theta_m`` about either pivot.

        The generated ``least_stroke_potential`` at the corners of the triangle that holds each arc of
        width at most :data:`ARC_STEP`: the arc's ends, and its middle tilt under gravity ``g / cos(w / 2)``
        (docs/simulation.md, rule 4).
        """
        n = math.ceil(theta_m / ARC_STEP) if theta_m > 0.0 else 1
        w = theta_m / n
        outer = list(self.params)
        outer[self.gravity] /= math.cos(0.5 * w)
        least = math.inf
        for s in (1.0, -1.0):
            for x in (x_m, -x_m):
                for i in range(n + 1):
                    least = _lower(least, self._least("least_stroke_potential", s, self._at(s * w * i, x)))
                for i in range(n):
                    y = self._at(s * w * (i + 0.5), x)
                    least = _lower(least, self._least("least_stroke_potential", s, y, outer))
        return least

    def stops_out_of_reach(self, x_m: float) -> bool:
        """No bumper can act while ``|q[1]| <= x_m``: every gap (affine in ``q[1]`` alone) is <= 0 at both ends."""
        return all(self.stop_gap(i, self._at(0.0, x)) <= 0.0 for x in (x_m, -x_m) for i in range(self.n_stops))

    def least_at_bumpers(self, theta_m: float) -> float:
        """The least potential where a stop side's gap closes, over the tilts ``|theta| <= theta_m``.

        A mass inside every gap with less energy can never reach a bumper. Each gap is affine in ``q[1]``
        alone (derive checks it): its root from its values at ``q[1] = 0`` and 1.
        """
        least = math.inf
        for i in range(self.n_stops):
            at0, at1 = self.stop_gap(i, self._at(0.0, 0.0)), self.stop_gap(i, self._at(0.0, 1.0))
            least = _lower(least, self.least_on_arcs(theta_m, abs(at0 / (at0 - at1))))
        return least

    def barrier_bound(self) -> float:
        """The energy above rest below which the block can never overturn: the greatest least potential at
        :data:`BARRIER_TILTS` tilts below ``pi/2`` about either pivot (every run that overturns passes them all),
        less ``E(0)`` and the margin; ``-inf`` when no bound applies (rule 4)."""
        least = -math.inf
        for i in range(1, BARRIER_TILTS):
            at = self.least_at_tilt(0.5 * math.pi * i / BARRIER_TILTS)
            if at > least:  # a NaN is no bound
                least = at
        zero = self.energy_at_rest
        bound = least - zero - SAFE_MARGIN * (abs(least) + abs(zero))
        return -math.inf if math.isnan(bound) else bound

    def verdict_bound(self, theta_m: float, x_m: float) -> float:
        """The energy above rest below which ``|theta|`` can no longer reach ``theta_m``, ``|q[1]|`` ``x_m``,
        nor, where ``x_m`` is past a bumper's gap, the mass that gap.

        The least potential there less ``E(0)`` and the margin; ``-inf`` when no bound applies (rule 4).
        """
        least = self.least_at_tilt(theta_m)
        if self.n > 1:
            least = _lower(least, self.least_on_arcs(theta_m, x_m))
            if not self.stops_out_of_reach(x_m):
                least = _lower(least, self.least_at_bumpers(theta_m))
        zero = self.energy_at_rest
        bound = least - zero - SAFE_MARGIN * (abs(least) + abs(zero))
        return -math.inf if math.isnan(bound) else bound

    def ground(self, pulse_on: bool, t0: float) -> Callable[[float], float]:
        """Ground acceleration of the segment that starts at ``t0``.

        A segment never straddles the motion's end ``t_p`` (a breakpoint), so
        it sees either the motion or zero, never the kink: the integrator's
        stages (which may land an ulp beyond ``t_p``) then all see one smooth
        function. A segment of a sampled motion lies within one sample
        interval (rule 3): it sees that interval's linear piece.

        Parameters
        ----------
        pulse_on : bool
            The segment lies in ``[0, t_p]``.
        t0 : float
            Its start.

        Returns
        -------
        callable
            ``ag(t)``.
        """
        if not pulse_on:
            return lambda t: 0.0
        p = self.problem
        a_g = float(p.a_g)
        if self.family == "sampled":
            samples, dt = p.samples, float(p.pulse_dt)
            if samples is None:
                raise SimulationError("a sampled motion without its samples (rocking.sim.cases builds them)")
            k = sample_piece(t0, dt, p.n_samples)
            return lambda t: a_g * float(interpolate(samples, dt, k, t))
        shape, omega_g, phase, t_c, gamma = SHAPES[self.family], float(p.omega_g), float(p.psi), p.t_c, p.shape
        return lambda t: a_g * shape(t, omega_g, phase, t_c, gamma, math)

    def vertical(self, pulse_on: bool, t0: float) -> Callable[[float], float]:
        """Vertical ground acceleration ``agy(t)`` of the segment that starts at ``t0``, as :meth:`ground`
        (docs/model.md section 14: the shape ``psi_v / omega_g`` ahead, or the vertical samples)."""
        p = self.problem
        a_v = float(p.a_v)
        if not pulse_on or a_v == 0.0:
            return lambda t: 0.0
        if p.v_samples is not None:  # a sampled motion's vertical samples
            samples, dt = p.v_samples, float(p.pulse_dt)
            k = sample_piece(t0, dt, p.n_samples)
            return lambda t: a_v * float(interpolate(samples, dt, k, t))
        shape, omega_g, phase, t_c, gamma = SHAPES[self.family], float(p.omega_g), float(p.psi), p.t_c, p.shape
        lead = float(p.psi_v) / omega_g
        return lambda t: a_v * shape(t + lead, omega_g, phase, t_c, gamma, math)

    def stuck_rhs(self, phase: int, ground: Callable[[float], float], stop_on: tuple, vertical) -> StateFunction:
        """``y' = (dq, ddq)`` of a stuck phase, ``ddq`` from the function the phase table names: rocking about the
        pivot ``s = phase`` (fixed for the phase), ``f_s(y, ag)``, or in full contact (``phase = CONTACT``),
        ``c(y, ag)``, in the regime ``stop_on`` of the segment.

        The regime is that of the segment (rule 6): a gap event ends it, so its steps never see a bumper's
        force switch on or off. In full contact the whole state is integrated, ``theta`` and ``dtheta``
        included: the generated ``contact_accel`` returns ``ddtheta = 0`` and ``dtheta = 0``, so both stay
        exactly 0, and the error norm runs over the same ``2 n`` components in every phase.
        """
        n = self.n
        regime = self.regime(stop_on)
        accel, s = phase_of(phase != CONTACT, False).accel, _pivot(phase)

        def rhs(t, y):
            dy = np.empty_like(y)
            dy[:n] = y[n:]
            dy[n:] = self._call(accel, s, y, ground(t), regime, agy=vertical(t))
            return dy

        return rhs

    def stop_gap(self, i: int, y: np.ndarray) -> float:
        """Penetration of stop side ``i``: its bumper can act only while it is > 0 (it does not depend on the pivot)."""
        return float(self._call("stop_gaps", 1.0, y, 0.0)[i])

    def stop_contact(self, i: int, y: np.ndarray) -> float:
        """Contact of stop side ``i``: its bumper pushes while it is > 0 (neither pivot nor indicators enter it,
        a Hunt-Crossley pad's memory does)."""
        return float(self._call("stop_contact", 1.0, y, 0.0, self._memory_regime())[i])

    def _memory_regime(self) -> tuple | None:
        """A regime that carries the memory of the run, for the functions that read only it (None: no memory)."""
        return self.regime((False,) * self.n_stops) if self.memory else None

    def regime(self, stop_on) -> tuple:
        """The regime of the stops as the generated functions take it: 1.0 where a side's bumper acts, else 0.0,
        then the memory ``v_in`` of each Hunt-Crossley side."""
        return tuple(1.0 if on else 0.0 for on in stop_on) + tuple(self.memory)

    def start_memory(self, y: np.ndarray) -> None:
        """The memory at the run's start: a contact in progress there is taken to start there (v_in at its floor
        at least)."""
        rates = self._call("stop_approach", 1.0, y, 0.0) if self.memory else ()
        self.memory = [max(float(v), f) for v, f in zip(rates, self.floors) if f is not None]

    def record_approach(self, i: int, y: np.ndarray) -> None:
        """Stop side ``i``'s pad starts pushing at ``y``: a new contact if its penetration rises (then its v_in
        is recorded, at its floor at least), else a released pad of the same contact pushes again (kept)."""
        floor = self.floors[i]
        if floor is None:
            return
        rate = float(self._call("stop_approach", 1.0, y, 0.0)[i])
        if rate >= 0.0:
            self.memory[sum(f is not None for f in self.floors[:i])] = max(rate, floor)

    def jump_memory(self, before: np.ndarray, after: np.ndarray) -> None:
        """A jump of the velocities (an impact and its rest snap) with the mass in a Hunt-Crossley pad: where its
        ``ddelta`` changed, the contact goes on at ``v_in = max(v_in, ddelta)`` (rule 6)."""
        if not self.memory:
            return
        gaps = self._call("stop_gaps", 1.0, after, 0.0)
        rates = zip(self._call("stop_approach", 1.0, before, 0.0), self._call("stop_approach", 1.0, after, 0.0))
        j = 0
        for gap, (old, new), floor in zip(gaps, rates, self.floors):
            if floor is None:
                continue
            if gap > 0.0 and new != old:
                self.memory[j] = max(self.memory[j], float(new))
            j += 1

    def bumper_force(self, y: np.ndarray) -> float:
        """The largest force of any bumper at the state ``y`` (a pad's force from its state and memory)."""
        forces = self._call("stop_forces", 1.0, y, 0.0, self._memory_regime())
        return float(max(forces))

    def bumper_peak(self, sol, best: float) -> float:
        """The largest bumper force over a segment whose pads push, ``best`` the largest before it (rule 6).

        Each step's dense output at its middle; where the largest of that and of the step's ends
        reaches ``best``, :func:`step_peak` finds the step's maximum.
        """
        t = sol.t
        h = np.diff(t)
        inner = (t[:-1, None] + h[:, None] * PEAK_SAMPLES[None, 1:-1]).ravel()
        states = np.asarray(sol.sol(inner), dtype=float)[: 2 * self.n]
        forces = self.functions.stop_forces(1.0, *states, 0.0, 0.0, *self.params, stop_on=self._memory_regime())
        inner = np.max(np.asarray(forces, dtype=float), axis=0).reshape(len(h), -1)
        ends = sol.y[: 2 * self.n]
        forces = self.functions.stop_forces(1.0, *ends, 0.0, 0.0, *self.params, stop_on=self._memory_regime())
        ends = np.max(np.asarray(forces, dtype=float), axis=0)
        samples = np.column_stack([ends[:-1], inner, ends[1:]])
        for j in range(len(h)):
            row = samples[j]
            # At the maximum so far too: a step that starts at it (the last one's end) may climb past it.
            if row.max() >= best and row.max() > 0.0:
                t0, step = float(t[j]), float(h[j])

                def force(x: float, t0: float = t0, step: float = step) -> float:
                    return self.bumper_force(sol.sol(t0 + x * step))

                best = step_peak(force, row, quartic=not self.memory)
        return best

    def largest_bumper_force(self, states: np.ndarray) -> float:
        """The largest force of any bumper against its penetration over ``states`` (rows), 0 without stops."""
        if self.n_stops == 0 or len(states) == 0:
            return 0.0
        states = np.asarray(states, dtype=float)[:, : 2 * self.n].T
        forces = self.functions.stop_forces(1.0, *states, 0.0, 0.0, *self.params, stop_on=self._memory_regime())
        return float(max(np.max(f) for f in forces))

    def uplift(self, s: int, y: np.ndarray, ag: float, stop_on: tuple, agy: float = 0.0, sigma: int = 0) -> float:
        """Uplift function ``u_s`` in the regime ``stop_on``: the block leaves full contact about ``s`` when it
        turns positive (``agy``: the vertical ground acceleration; ``sigma``: the direction of the base's slip,
        0 when it sticks)."""
        if sigma:
            margin = float(self._friction("slide_uplift", s, y, ag, stop_on, agy, self.mu_k * sigma))
            return margin - self.slide_uplift_floor[s]
        return float(self._call("uplift", s, y, ag, self.regime(stop_on), agy=agy))

    def critical_angle(self, s: int, y: np.ndarray, ag: float) -> float:
        """Static critical angle ``theta_cr_s(y)`` (with the sign of ``s``)."""
        return float(self._call("critical_angle", s, y, ag))

    def energy(self, y: np.ndarray, s: int = 1, stop_on: tuple | None = None) -> float:
        """Mechanical energy ``E_s(y)`` in the regime ``stop_on`` (None: that of ``y``; ``ag`` does not enter it)."""
        return float(self._call("energy", s, y, 0.0, None if stop_on is None else self.regime(stop_on)))

    def energy_above_rest(self, y: np.ndarray, stop_on: tuple, s: int = 1) -> float:
        """``E(y) - E(0)``, ``E(y)`` about ``s`` (full contact: either) in the regime ``stop_on``."""
        return self.energy(y, s, stop_on) - self.energy_at_rest

    def mass_matrix(self, s: int, y: np.ndarray):
        """The mass matrix about ``s`` at ``y``, row-major (``n * n`` values)."""
        return self._call("mass_matrix", s, y, 0.0)

    def impact(self, s: int, y: np.ndarray, ag: float) -> np.ndarray:
        """State right after an impact that ends rocking about ``s``: ``theta = 0``, ``dq = J_s(y)``."""
        after = np.array(y, dtype=float)
        after[0] = 0.0
        after[self.n :] = self._call("impact", s, after, ag)
        return after


#: Where a step's dense output is looked at for the peak of a bumper's force, in fractions of the step (rule 6).
PEAK_SAMPLES = np.linspace(0.0, 1.0, 3)
#: Where it is looked at too when the peak is searched for on a Kelvin-Voigt pad's quartic.
PEAK_QUARTERS = (0.25, 0.75)
#: A Hunt-Crossley pad's search for that peak narrows its bracket to this width, in fractions of the step.
PEAK_WIDTH = 1e-5
#: The Newton iteration for the crest of a Kelvin-Voigt pad's quartic stops at this width, in fractions of the step.
PEAK_ROOT_WIDTH = 1e-9


def step_peak(force: Callable[[float], float], samples: np.ndarray, quartic: bool = False) -> float:
    """The largest ``force(x)`` over a step, ``x`` in ``[0, 1]``, from its values at :data:`PEAK_SAMPLES`.

    The largest sample, or at an end of the step the end itself where the parabola through it and its two
    neighbours still climbs there; otherwise, with ``quartic`` (every pad Kelvin-Voigt: the force
    ``k_b delta + c_b ddelta`` is affine in the state and the dense output a quartic in ``x``, so the force is the
    quartic through the ends, :data:`PEAK_QUARTERS` and the middle), the force at :func:`quartic_peak`; else
    :func:`peak_search` between the largest sample's neighbours (sim.c's ``step_peak``, the same operations).
    """
    k = int(np.argmax(samples))
    n = len(samples) - 1
    best = float(samples[k])
    if k == n and 3.0 * samples[n] - 4.0 * samples[n - 1] + samples[n - 2] > 0.0:
        return best
    if k == 0 and -3.0 * samples[0] + 4.0 * samples[1] - samples[2] < 0.0:
        return best
    if quartic:
        quarter, three = force(PEAK_QUARTERS[0]), force(PEAK_QUARTERS[1])
        x = quartic_peak((float(samples[0]), quarter, float(samples[1]), three, float(samples[2])))
        best = max(best, quarter, three)
        return max(best, force(x)) if 0.0 < x < 1.0 else best
    if k == 1:  # the middle, best of three: the ends bracket it and give the first parabola
        ends = ((0.0, float(samples[0])), (1.0, float(samples[2])))
        (w, fw), (v, fv) = ends if samples[0] > samples[2] else ends[::-1]
        return max(best, peak_search(force, 0.0, 1.0, (0.5, best), (w, fw), (v, fv)))
    return max(best, peak_search(force, 0.0 if k == 0 else 0.5, 0.5 if k == 0 else 1.0))


def peak_search(
    force: Callable[[float], float],
    a: float,
    b: float,
    *known: tuple[float, float],
) -> float:
    """The largest ``force(x)`` over ``[a, b]``, which brackets a crest: Brent's search for a minimum (Brent 1973,
    "localmin") on the force's negative, a parabola through the three best points where it falls well inside the
    bracket, else a golden section of its larger part, until the bracket is :data:`PEAK_WIDTH` wide about the best
    point. ``known``: none (a golden point is read first), or the best point in ``(a, b)`` and two others (the
    bracket's ends), each ``(x, force(x))`` (sim.c's ``peak_search``, the same operations).
    """
    golden, tol = 0.5 * (3.0 - math.sqrt(5.0)), 0.25 * PEAK_WIDTH
    if known:
        (x, fx), (w, fw), (v, fv) = known
        d = e = b - a  # the known points' parabola is tried at once
    else:
        x = w = v = a + golden * (b - a)
        fx = fw = fv = force(x)
        d = e = 0.0
    for _ in range(100):
        m = 0.5 * (a + b)
        if abs(x - m) <= 2.0 * tol - 0.5 * (b - a):
            break
        if abs(e) > tol:  # the parabola's vertex u = x + p / q through (x, -fx), (w, -fw), (v, -fv)
            s = (x - w) * (fv - fx)
            q = (x - v) * (fw - fx)
            p = (x - v) * q - (x - w) * s
            q = 2.0 * (q - s)
            if q > 0.0:
                p = -p
            q = abs(q)
            s, e = e, d
            if abs(p) >= abs(0.5 * q * s) or p <= q * (a - x) or p >= q * (b - x):
                e = a - x if x >= m else b - x
                d = golden * e
            else:
                d = p / q
                if (x + d) - a < 2.0 * tol or b - (x + d) < 2.0 * tol:
                    d = tol if m > x else -tol
        else:
            e = a - x if x >= m else b - x
            d = golden * e
        u = x + d if abs(d) >= tol else x + (tol if d >= 0.0 else -tol)
        fu = force(u)
        if fu >= fx:
            if u >= x:
                a = x
            else:
                b = x
            v, fv, w, fw, x, fx = w, fw, x, fx, u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu >= fw or w == x:
                v, fv, w, fw = w, fw, u, fu
            elif fu >= fv or v == x or v == w:
                v, fv = u, fu
    return fx


def _quartic_slope(c: tuple[float, ...], s: float, second: bool = False) -> float:
    """The derivative of the quartic ``c[0] + c[1] s + ... + c[4] s^4`` at ``s``, or its second derivative."""
    if second:
        return 2.0 * c[2] + s * (6.0 * c[3] + s * 12.0 * c[4])
    return c[1] + s * (2.0 * c[2] + s * (3.0 * c[3] + s * 4.0 * c[4]))


def _quartic_crest(c: tuple[float, ...], lo: float, hi: float) -> float:
    """The root in ``[lo, hi]`` of the quartic's derivative, > 0 at ``lo``, < 0 at ``hi`` and monotone between:
    Newton's iteration kept inside the shrinking bracket, bisection where it leaves it, to :data:`PEAK_ROOT_WIDTH`
    (sim.c's ``quartic_crest``)."""
    s = 0.5 * (lo + hi)
    for _ in range(64):
        slope = _quartic_slope(c, s)
        if slope > 0.0:
            lo = s
        elif slope < 0.0:
            hi = s
        else:
            return s
        curve = _quartic_slope(c, s, second=True)
        step = slope / curve if curve != 0.0 else math.nan
        nxt = s - step
        if not lo < nxt < hi:  # NaN too
            nxt = 0.5 * (lo + hi)
        if abs(nxt - s) < PEAK_ROOT_WIDTH or hi - lo < PEAK_ROOT_WIDTH:
            return nxt
        s = nxt
    return s


def quartic_peak(f: tuple[float, ...]) -> float:
    """Where in ``[0, 1]`` the quartic through ``f`` at ``x = 0, 1/4, 1/2, 3/4, 1`` is largest.

    At a crest (a root of its cubic derivative where that falls through 0; the derivative is monotone between
    the roots of the quadratic second derivative) or at an end (sim.c's ``quartic_peak``, the same operations).
    """
    # The quartic in s = 2 x - 1 on the nodes -1, -1/2, 0, 1/2, 1: its even and odd parts.
    far, near = 0.5 * (f[0] + f[4]), 0.5 * (f[1] + f[3])
    rise, step = 0.5 * (f[4] - f[0]), 0.5 * (f[3] - f[1])
    c4 = (4.0 / 3.0) * (far - 4.0 * near + 3.0 * f[2])
    c3 = (4.0 / 3.0) * (rise - 2.0 * step)
    c = (f[2], rise - c3, far - f[2] - c4, c3, c4)
    best_s, best = (1.0, f[4]) if f[4] > f[0] else (-1.0, f[0])
    # The roots of the second derivative 12 c4 s^2 + 6 c3 s + 2 c2 in (-1, 1) cut [-1, 1] where the slope turns.
    cuts = [-1.0]
    a, b = 6.0 * c4, 3.0 * c3
    q = b * b - 4.0 * a * c[2]
    if a != 0.0 and q >= 0.0:
        r = -0.5 * (b + math.copysign(math.sqrt(q), b))
        one, two = (c[2] / r if r != 0.0 else 0.0), r / a
        lo, hi = min(one, two), max(one, two)
        cuts += [lo] if -1.0 < lo < 1.0 else []
        cuts += [hi] if -1.0 < hi < 1.0 and hi != lo else []
    elif a == 0.0 and b != 0.0 and -1.0 < -c[2] / b < 1.0:
        cuts.append(-c[2] / b)
    cuts.append(1.0)
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        if not (_quartic_slope(c, lo) > 0.0 and _quartic_slope(c, hi) < 0.0):
            continue
        root = _quartic_crest(c, lo, hi)
        value = c[0] + root * (c[1] + root * (c[2] + root * (c[3] + root * c[4])))
        if value > best:
            best_s, best = root, value
    return 0.5 * (best_s + 1.0)


def _slide_directions(du: float, P_t: float) -> tuple[int, int]:
    """The directions a landing's slide is tried in: that of the slip before it first, or with none, against the
    sticking impulse ``P_t`` (the spec of issue 39)."""
    first = (1 if du > 0.0 else -1) if du != 0.0 else (-1 if P_t > 0.0 else 1)
    return first, -first


def _lower(a: float, b: float) -> float:
    """The lesser of two values, NaN if either is (sim.c's ``lower``)."""
    return a if (a < b or math.isnan(a)) else b


# --------------------------------------------------------------------------- #
# Event functions (what solve_ivp watches; no phase logic here)                #
# --------------------------------------------------------------------------- #


#: The smallest double above 0: an exact 0 of an event function moved to one side of it.
_TINY = 5e-324


def _pivot(phase: int) -> float:
    """The ``s`` a generated function takes in ``phase``: the pivot, or +1 in full contact (where it is ignored)."""
    return 1.0 if phase == CONTACT else float(phase)


def _zero_below(function: StateFunction) -> StateFunction:
    """``function`` with an exact 0 read as just below 0.

    ``solve_ivp`` fires a rising event when its function goes from ``<= 0`` to ``>= 0``,
    so a function that only touches 0 fires; sim.c's "turns positive" needs ``> 0``
    after (``is_before``). Moving an exact 0 below makes the two the same rule.
    """

    def strict(t, y):
        value = function(t, y)
        return -_TINY if value == 0.0 else value

    return strict


def _zero_above(function: StateFunction) -> StateFunction:
    """``function`` with an exact 0 read as just above 0: a falling event then needs ``< 0`` after, as in sim.c."""

    def strict(t, y):
        value = function(t, y)
        return _TINY if value == 0.0 else value

    return strict


@dataclass(frozen=True)
class _Event:
    """A ``solve_ivp`` event: ``function(t, y)`` with its name, ``terminal`` and ``direction``.

    ``direction`` follows ``solve_ivp``: ``+1`` catches the function rising
    through 0, ``-1`` falling, ``0`` both.
    """

    name: str
    function: StateFunction
    terminal: bool
    direction: int
    side: int = -1  # the stop side of a gap event

    def __call__(self, t, y):
        return self.function(t, y)


def uplift_event(
    system: _System, s: int, ground: Callable[[float], float], stop_on: tuple, vertical, sigma: int = 0
) -> _Event:
    """Full contact: ``u_s`` turns positive (uplift about ``A`` for ``s = +1``, ``A'`` for ``-1``); ``sigma``: the
    direction of the base's slip (0: it sticks)."""
    return _Event(
        UPLIFT_A if s == 1 else UPLIFT_A_PRIME,
        _zero_below(lambda t, y: system.uplift(s, y, ground(t), stop_on, vertical(t), sigma)),
        terminal=True,
        direction=+1,
    )


def slip_event(system: _System, phase: int, ground, stop_on: tuple, vertical) -> _Event:
    """A stuck contact: the force it must hold reaches ``mu_s N`` (docs/model.md section 15)."""

    def margin(t, y):
        F, N = system.floor_force(phase, y, ground(t), stop_on, vertical(t))
        return system.mu_s * float(N) - abs(float(F))

    return _Event(SLIP, _zero_above(margin), terminal=True, direction=-1)


def stop_event(system: _System, sigma: int) -> _Event:
    """A sliding contact: the slip speed ``du`` returns to 0."""
    n = system.n
    return _Event(STOP, lambda t, y: sigma * y[2 * n + 1], terminal=True, direction=-1)


def lift_off_event(
    system: _System, phase: int, sigma: int, ground, stop_on: tuple, vertical, grazed: float | None = None
) -> _Event:
    """The floor's normal force on the contact returns to 0 (:meth:`_System.takeoff_margin`): the block takes off
    (docs/model.md section 16).

    ``grazed``: the segment starts at this time where a takeoff grazed (``NO_TAKEOFF``), its margin 0 up to
    rounding: the event is armed only once the margin is positive after it (until then it reads -1), lest it
    find that root again.
    """
    armed = [grazed is None]

    def margin(t, y):
        value = system.takeoff_margin(phase, sigma, y, ground(t), stop_on, vertical(t))
        armed[0] = armed[0] or (t > grazed and value > 0.0)
        return value if armed[0] else -1.0

    return _Event(LIFT_OFF, _zero_above(margin), terminal=True, direction=-1)


def floor_events(
    system: _System, phase: int, sigma: int, ground, stop_on: tuple, vertical, grazed: float | None = None
) -> list:
    """The events of the floor that ``phase`` with the slip ``sigma`` watches (its exits in
    :data:`rocking.sim.phases.PHASES`): the lift-off (:meth:`_System.watches_lift_off`), and on a floor with
    friction the slip and its stop."""
    table = {e.event for e in phase_of(phase != CONTACT, sigma != 0).exits}
    watch = LIFT_OFF in table and system.watches_lift_off(phase)
    events = [lift_off_event(system, phase, sigma, ground, stop_on, vertical, grazed)] if watch else []
    if not system.friction:
        return events
    if SLIP in table:
        events.append(slip_event(system, phase, ground, stop_on, vertical))
    if STOP in table:
        events.append(stop_event(system, sigma))
    return events


def landing_event(system: _System, s: int, other: bool, y0: np.ndarray) -> _Event:
    """In flight about the reference corner ``s``: the height of the corner ``s`` (``other``: ``-s``) falls to 0.

    A corner on the floor where the segment starts (``y0``) without rising (a takeoff: ``dv = 0``) is armed only
    once its height is positive: until then the function reads 1, so the corner that just left the floor is not
    found landing at once (its height may dip by rounding). One that rises (a bounce) is armed at once: its 0 at
    the start reads as above the floor, and a short hop that lands within the first step is still found.
    """
    n = system.n
    u, du, v, dv = (float(c) for c in y0[2 * n : 2 * n + 4])
    _, v_o, _, dv_o = system.flight_corner(s, y0, u, v, du, dv) if other else (0.0, v, 0.0, dv)
    armed = [v_o > 0.0 or dv_o > 0.0]

    def height(t, y):
        h = float(system._flight("corner_heights", float(s), y, y[2 * n + 2])[1]) if other else float(y[2 * n + 2])
        armed[0] = armed[0] or h > 0.0
        return h if armed[0] else 1.0

    return _Event(LANDING_OTHER if other else LANDING, _zero_above(height), terminal=True, direction=-1)


def height_peak_event(system: _System, s: int, other: bool) -> _Event:
    """In flight: the vertical speed of the corner ``s`` (``other``: ``-s``) vanishes, where its height may peak
    (reported: ``jump_max``)."""
    n = system.n

    def rate(t, y):
        if not other:
            return y[2 * n + 3]
        return float(system.flight_corner(s, y, y[2 * n], y[2 * n + 2], y[2 * n + 1], y[2 * n + 3])[3])

    return _Event(HEIGHT_PEAK, rate, terminal=False, direction=-1)


def flight_events(system: _System, s: int, ground, want_critical: bool, y0: np.ndarray) -> list:
    """The events of a flight about the reference corner ``s`` but the stops' (docs/simulation.md, "Phases"):
    each corner's landing, the overturning, and the reported extrema (theta, q[1], each corner's height, the
    first critical-angle crossing); no rest, no settling, no early verdict. ``y0``: the flying state at the
    segment's start."""
    events = [landing_event(system, s, False, y0), landing_event(system, s, True, y0)]
    events.append(_Event(OVERTURN, lambda t, y: abs(y[0]) - math.pi / 2, terminal=True, direction=+1))
    events += [extremum_event(system.n, k) for k in range(min(system.n, 2))]
    events += [height_peak_event(system, s, False), height_peak_event(system, s, True)]
    if want_critical:
        events.append(critical_event(system, s, ground))
    return events


def impact_event(s: int) -> _Event:
    """Rocking about ``s``: ``s theta`` falls to 0.

    The phase starts at ``theta = 0`` with ``s theta`` rising, so that root
    is crossed upwards and a falling ``direction`` ignores it: only the
    return to the base is an impact. (That needs ``s theta > 0`` at the end
    of the first step: :func:`integrate_segment` sees to it.)
    """
    return _Event(IMPACT, lambda t, y: s * y[0], terminal=True, direction=-1)


def overturn_event(s: int) -> _Event:
    """Rocking about ``s``: ``|theta| = s theta`` reaches ``pi / 2``."""
    return _Event(OVERTURN, lambda t, y: s * y[0] - math.pi / 2, terminal=True, direction=+1)


def critical_event(system: _System, s: int, ground: Callable[[float], float]) -> _Event:
    """Rocking about ``s``: ``s theta - s theta_cr_s(y)`` turns positive (reported only)."""
    return _Event(
        CRITICAL,
        _zero_below(lambda t, y: s * y[0] - s * system.critical_angle(s, y, ground(t))),
        terminal=False,
        direction=+1,
    )


def extremum_event(n: int, coordinate: int) -> _Event:
    """The velocity of ``q[coordinate]`` vanishes: ``|q[coordinate]|`` may peak there (reported only)."""
    return _Event(EXTREMUM, lambda t, y: y[n + coordinate], terminal=False, direction=0)


def gap_event(system: _System, side: int, acting: bool) -> _Event:
    """Stop side ``side``: its contact turns positive (the bumper pushes), or, once it pushes, falls to 0."""
    # Closing: g <= 0 -> g > 0; opening: g > 0 -> g <= 0 (sim.c's rules): an exact 0 is below either way.
    return _Event(
        GAP_OPEN if acting else GAP_CLOSE,
        _zero_below(lambda t, y: system.stop_contact(side, y)),
        terminal=True,
        direction=-1 if acting else +1,
        side=side,
    )


def settled_event(n: int) -> _Event:
    """Full contact once safe: the next extremum of ``q[1]`` is the last one; it ends the run."""
    return _Event(SETTLED, lambda t, y: y[n + 1], terminal=True, direction=0)


def safe_event(system: _System, safe_energy: float, stop_on: tuple) -> _Event:
    """Full contact after the pulse: ``E(y) - E(0)`` falls below the uplift energy (less the margin)."""
    below = _zero_above(lambda t, y: system.energy_above_rest(y, stop_on) - safe_energy)
    return _Event(SAFE, below, terminal=True, direction=-1)


def rest_event(system: _System, energy_rest: float, stop_on: tuple) -> _Event:
    """Full contact after the pulse: ``E(y) - E(0)`` falls below ``energy_rest``."""
    below = _zero_above(lambda t, y: system.energy_above_rest(y, stop_on) - energy_rest)
    return _Event(REST, below, terminal=True, direction=-1)


def watched_events(
    system: _System,
    phase: int,
    ground,
    *,
    after_pulse: bool,
    want_critical: bool,
    energy_rest: float,
    safe_energy: float | None = None,
    settling: bool = False,
    stop_on: tuple = (),
    vertical=lambda t: 0.0,
    sigma: int = 0,
    flying: bool = False,
    y0: np.ndarray | None = None,
    grazed: float | None = None,
):
    """The events watched in one segment of ``phase`` (docs/simulation.md, "Phases", "End" and rule 6).

    Parameters
    ----------
    system : _System
        The model with its parameters.
    phase : int
        ``CONTACT`` (0) or the pivot ``s`` (``+1``, ``-1``).
    ground : callable
        The segment's ``ag(t)``.
    after_pulse : bool
        The segment lies after ``t_p`` (full contact may then end in rest).
    want_critical : bool
        ``t_critical`` is still unknown (the critical-angle event is only
        needed for its first crossing).
    energy_rest : float
        The rest threshold on the energy.
    safe_energy : float or None
        Watch the energy falling below this bound (full contact after the
        pulse, not yet safe); ``None``: not watched.
    settling : bool
        Full contact once safe: the next extremum of ``q[1]`` ends the run.
    stop_on : tuple of bool
        Whether each stop side's bumper acts (the segment's regime): its gap's opening is watched,
        else its closing.
    vertical : callable
        The segment's ``agy(t)``.
    sigma : int
        The direction of the base's slip, 0 while it sticks (docs/model.md section 15).
    flying : bool
        The block flies about the reference corner ``phase`` (docs/model.md section 16).
    y0 : ndarray or None
        In flight, the flying state at the segment's start (where its landings are armed).
    grazed : float or None
        The segment starts at this time where a takeoff grazed (:func:`lift_off_event`).

    Returns
    -------
    list of _Event
    """
    # q[1] is the damper's coordinate: its extrema give x_max, in every phase.
    damper = [extremum_event(system.n, 1)] if system.n > 1 else []
    # The stops' gaps and the floor's events may end any phase.
    gaps = [gap_event(system, i, acting) for i, acting in enumerate(stop_on)]
    if flying:
        assert y0 is not None  # a flight's landings are armed from its start
        return flight_events(system, phase, ground, want_critical, y0) + gaps
    gaps += floor_events(system, phase, sigma, ground, stop_on, vertical, grazed)
    if phase == CONTACT:
        if settling and system.n > 1:
            damper = [settled_event(system.n)]
        events = [uplift_event(system, s, ground, stop_on, vertical, sigma) for s in (+1, -1)] + damper
        if after_pulse and not sigma:
            events.append(rest_event(system, energy_rest, stop_on))
            if safe_energy is not None and not settling:
                events.append(safe_event(system, safe_energy, stop_on))
        return events + gaps
    s = phase
    events = [impact_event(s), overturn_event(s), extremum_event(system.n, 0)] + damper
    if want_critical:
        events.append(critical_event(system, s, ground))
    return events + gaps


# --------------------------------------------------------------------------- #
# One segment: a phase between two events or breakpoints                       #
# --------------------------------------------------------------------------- #


@dataclass
class _Segment:
    """What one ``solve_ivp`` call returned, sorted for the phase machine.

    Attributes
    ----------
    t, y : float, ndarray
        End of the segment: the terminal event, or ``t_bound``.
    event : str or None
        Name of the terminal event that ended it (``None``: ``t_bound`` reached).
    t_critical : float
        First critical-angle crossing in the segment (``nan`` if none).
    peaks : dict
        ``{coordinate: largest |q[coordinate]|}`` over the step ends and all
        event points of the segment.
    dense : OdeSolution or None
        The dense output (with ``record=True``).
    side : int
        The stop side of a gap event (-1 otherwise).
    bumper_force : float
        The largest bumper force of the segment (rule 6; sim.c's ``see_state`` and ``step_peak``).
    slip : tuple of float
        ``(u, du)`` at the end (docs/model.md section 15).
    lift : tuple of float
        ``(v, dv)`` at the end of a flight (docs/model.md section 16).
    step : float or None
        The size of its last step, whole (an event's step too), where it watched the lift-off.
    """

    t: float
    y: np.ndarray
    event: str | None
    t_critical: float
    peaks: dict
    dense: OdeSolution | None = None
    side: int = -1
    bumper_force: float = 0.0
    slip: tuple = (0.0, 0.0)
    lift: tuple = (0.0, 0.0)
    step: float | None = None


def lift_off_step(
    rhs: StateFunction,
    started: Callable[[np.ndarray], bool],
    t0: float,
    y0: np.ndarray,
    t_bound: float,
    first_step: float | None,
    work: _Work | None = None,
    **options,
) -> float | None:
    """A first step after which the phase has begun: the block has risen (``s theta > 0``) from ``theta = 0``,
    the slip has grown (``sign(du) du > 0``) from ``du = 0``.

    Tries ``first_step`` (``None``: SciPy's own, Hairer's heuristic), then ten
    times shorter each time, down to SciPy's smallest step (10 ulps of ``t0``).
    One step of ``RK45`` per try, the integrator ``solve_ivp`` then runs with.

    Parameters
    ----------
    rhs : callable
        Right-hand side of the phase.
    started : callable
        Whether the phase has begun at the state at a step's end.
    t0, y0 : float, ndarray
        Start of the phase.
    t_bound : float
        End of the segment.
    first_step : float or None
        The segment's first step.
    work : _Work or None
        Counts what sim.c evaluates for the same retries (rule 5): the first
        try repeats the step the segment already took (not counted again);
        each later one is sim.c's retry, its step attempts without the
        probe's own start.
    **options
        ``rtol``, ``atol``, ``max_step`` of the segment.

    Returns
    -------
    float or None
        The first step to give ``solve_ivp``; ``None`` if even the smallest
        step does not lift the block: it stays on its base.
    """
    repeat = True
    while True:
        probe = RK45(rhs, t0, y0, t_bound, first_step=first_step, **options)
        probe.step()
        if work is not None and not repeat:
            work.add(probe.nfev - 1)
        repeat = False
        if started(probe.y):
            return probe.step_size
        first_step = 0.1 * probe.step_size
        if first_step < 10 * (np.nextafter(t0, np.inf) - t0):
            return None


def _started(phase: int, sigma: int, y0: np.ndarray, n: int) -> Callable[[np.ndarray], bool]:
    """Whether a phase that starts at ``y0`` has begun at ``y``: what starts at 0 has moved its way, ``theta``
    about the pivot ``phase``, the slip ``du`` in its direction ``sigma``."""
    rising = phase != CONTACT and y0[0] == 0.0
    slipping = sigma != 0 and y0[2 * n + 1] == 0.0

    def started(y: np.ndarray) -> bool:
        return (not rising or phase * y[0] > 0.0) and (not slipping or sigma * y[2 * n + 1] > 0.0)

    return started


def _peaks(system: _System, phase: int, points: np.ndarray, extra: tuple, flying: bool, slip: tuple) -> dict:
    """The largest ``|theta|``, ``|q[1]|``, ``|u|`` (``"u"``) and in flight corner height (``"jump"``) over the
    ``points`` of a segment (rows: its step ends and located events)."""
    n = system.n
    peaks: dict[int | str, float] = {k: float(np.max(np.abs(points[:, k]))) for k in range(min(n, 2))}
    peaks["u"] = float(np.max(np.abs(points[:, 2 * n]))) if extra else abs(slip[0])
    if flying:
        # Each corner's height at every point, the located height peaks among them.
        heights = system.functions.corner_heights(
            float(phase), *points[:, : 2 * n].T, 0.0, 0.0, *system.params, points[:, 2 * n + 2]
        )
        peaks["jump"] = float(max(np.max(np.asarray(h, dtype=float)) for h in heights))
    return peaks


def _last_step(dense) -> float | None:
    """The whole size of the last step of a dense output (``None`` for none)."""
    if dense is None or not dense.interpolants:
        return None
    last = dense.interpolants[-1]
    return float(last.t - last.t_old)


def _launch_step(system, phase, flying, lift, rhs, t0, y0, t_bound, first_step, work, options) -> tuple:
    """``(first_step, grounded)`` of a segment: a flight from ``v = dv = 0`` (a takeoff) whose corner must rise in
    its first step (and the other one too where it starts on the floor, a flat base), or its landing, armed once
    its height is positive, would never be found: the first step that lifts it (:func:`lift_off_step`), or
    ``grounded`` where even the shortest does not. Other segments keep ``first_step``."""
    if not (flying and lift[0] == 0.0 and not lift[1] > 0.0):
        return first_step, False
    # The probe's retries count as work (rule 5); its first try stands for the step the solve then takes.
    first_step = lift_off_step(rhs, _launched(system, phase, y0), t0, y0, t_bound, first_step, work, **options)
    return first_step, first_step is None


def _launched(system: _System, s: int, y0: np.ndarray) -> Callable[[np.ndarray], bool]:
    """Whether a flight about ``s`` that starts with its corner on the floor (``y0``, ``v = dv = 0``) has left it
    at ``y``: its height is positive, and so is the other corner's where it starts at 0 too (a flat base)."""
    n = system.n
    flat = float(system._flight("corner_heights", float(s), y0, y0[2 * n + 2])[1]) == 0.0

    def launched(y: np.ndarray) -> bool:
        if not y[2 * n + 2] > 0.0:
            return False
        return not flat or float(system._flight("corner_heights", float(s), y, y[2 * n + 2])[1]) > 0.0

    return launched


def after_gap(system: _System, event: _Event, dense: OdeSolution, t: float, y: np.ndarray):
    """The state of a gap event on the side after its root: the next segment's regime from its first stage.

    ``solve_ivp`` locates a root to a few ulps on either side; sim.c returns the end
    of its final bracket on the side after it (``locate_event``). A bumper's dashpot
    force jumps at the root, so the state the next segment starts from must be on
    the new side, as in sim.c: ``t`` moves up by ulps until it is.
    """
    after = (lambda g: g > 0.0) if event.name == GAP_CLOSE else (lambda g: g <= 0.0)
    for _ in range(64):
        if after(system.stop_contact(event.side, y)):
            return t, y
        t = float(np.nextafter(t, np.inf))
        y = np.asarray(dense(t), dtype=float)
    # A slow mass: the contact stays at its root over more ulps of t than those. The step's end is on the side
    # after it (solve_ivp saw the sign change there): halved down to the first float after the root, as sim.c.
    lo, hi = t, float(dense.interpolants[-1].t)
    while np.nextafter(lo, np.inf) < hi:
        mid = lo + 0.5 * (hi - lo)
        if after(system.stop_contact(event.side, np.asarray(dense(mid), dtype=float))):
            hi = mid
        else:
            lo = mid
    return hi, np.asarray(dense(hi), dtype=float)


def integrate_segment(
    problem: Problem,
    system: _System,
    phase: int,
    t0: float,
    y0: np.ndarray,
    t_bound: float,
    *,
    want_critical: bool,
    record: bool,
    safe_energy: float | None = None,
    settling: bool = False,
    first_step: float | None = None,
    work: _Work | None = None,
    stop_on: tuple = (),
    bumper_best: float = 0.0,
    sigma: int = 0,
    slip: tuple = (0.0, 0.0),
    flying: bool = False,
    lift: tuple = (0.0, 0.0),
    grazed: bool = False,
) -> _Segment:
    """Integrate ``phase`` from ``(t0, y0)`` until a terminal event or ``t_bound``.

    Parameters
    ----------
    problem : Problem
        Tolerances, pulse, rest threshold, contact step bound.
    system : _System
        The model with its parameters.
    phase : int
        ``CONTACT`` or the pivot ``s``.
    t0, y0 : float, ndarray
        Start of the segment.
    t_bound : float
        The next breakpoint: ``min(t_p, t_max)`` during the pulse, ``t_max`` after.
    want_critical : bool
        Watch the critical angle (``t_critical`` still unknown).
    record : bool
        Keep the dense output for the history.
    safe_energy : float or None
        The uplift energy bound to watch in full contact after the pulse (see :func:`watched_events`).
    settling : bool
        Full contact once safe: the next extremum of ``q[1]`` ends the segment.
    first_step : float or None
        The first step (cut to the segment); ``None``: Hairer's heuristic.
    work : _Work or None
        Counts the evaluations of the right-hand side (rule 5).
    stop_on : tuple of bool
        Whether each stop side's bumper acts: the regime of the whole segment, for the right-hand
        side and the events (see :func:`watched_events`).
    bumper_best : float
        The largest bumper force before the segment (the steps that cannot pass it are not searched).
    sigma : int
        The direction of the base's slip, 0 while it sticks: a sliding phase integrates the slip ``u``, ``du``
        (``slip`` at the start) after the ``2 n`` components (docs/model.md section 15).
    slip : tuple of float
        ``(u, du)`` at the start.
    flying : bool
        The block flies about the reference corner ``phase``: ``u``, ``du`` and ``v``, ``dv`` (``lift`` at the
        start) are integrated after the ``2 n`` components (docs/model.md section 16).
    lift : tuple of float
        ``(v, dv)`` at the start.
    grazed : bool
        A takeoff grazed at ``t0`` (:func:`lift_off_event`).

    Returns
    -------
    _Segment

    Raises
    ------
    _MaxSteps
        When ``work`` passes its bound.
    """
    pulse_on = t0 < problem.t_p
    ground, vertical = system.ground(pulse_on, t0), system.vertical(pulse_on, t0)
    n = system.n
    rhs = system.phase_rhs(phase, sigma, ground, stop_on, vertical, flying)
    extra = (*slip, *lift) if flying else tuple(slip) if sigma else ()
    if extra:
        y0 = np.concatenate([y0, extra])
    # While the pulse acts, the uplift functions move with ag(t) even when the
    # state does not (the bare block: error estimate 0, so the step would grow
    # tenfold per step); a bounded step keeps an uplift from being stepped over.
    max_step = problem.contact_max_step if phase == CONTACT and pulse_on else np.inf
    plain_rhs = rhs
    if work is not None:
        rhs = work.counted(rhs)
    events = watched_events(
        system,
        phase,
        ground,
        after_pulse=not pulse_on,
        want_critical=want_critical,
        energy_rest=system.rest_energy,
        safe_energy=safe_energy,
        settling=settling,
        stop_on=stop_on,
        vertical=vertical,
        sigma=sigma,
        flying=flying,
        y0=y0,
        grazed=t0 if grazed else None,
    )
    # The slip's (and the height's) components take the tolerance of the first coordinate's (a length or an
    # angle, as u's scale).
    atol = np.concatenate([problem.atol, np.tile(problem.atol[[0, n]], len(extra) // 2)]) if extra else problem.atol
    options = {"rtol": problem.rtol, "atol": atol, "max_step": max_step}

    # A grazing takeoff starts the next segment with the last step's size (run_machine's takeoff): the dense
    # output's last piece spans that step whole.
    lifts = any(e.name == LIFT_OFF for e in events)

    def solve(first_step=None):
        sol = solve_ivp(
            rhs,
            (t0, t_bound),
            y0,
            method="RK45",
            events=events,
            # A gap event needs the dense output to step onto the side after the root (after_gap).
            dense_output=record or system.n_stops > 0 or lifts,
            first_step=first_step,
            **options,
        )
        if sol.status < 0:
            raise SimulationError(f"solve_ivp failed in phase {phase} at t = {sol.t[-1]:.17g}: {sol.message}")
        return sol

    if first_step is not None:
        first_step = min(first_step, t_bound - t0)
    first_step, grounded = _launch_step(
        system, phase, flying, lift, plain_rhs, t0, y0, t_bound, first_step, work, options
    )
    if grounded:
        return _Segment(
            t=t0, y=np.array(y0[: 2 * n]), event=NO_TAKEOFF, t_critical=math.nan, peaks={0: 0.0}, slip=tuple(slip)
        )
    sol = solve(first_step)
    fired = [e for e, times in zip(events, sol.t_events) if e.terminal and len(times)]
    if [e.name for e in fired] in ([IMPACT], [STOP]) and sol.t[-1] == t0:
        # A phase from theta = 0 whose first step ends with s theta <= 0 (from du = 0, sign(du) du <= 0):
        # solve_ivp sees "s theta falls to 0" at the start (Brent returns the bracket's end where the
        # function is exactly 0). Either the step was too long to see the block rise and fall back (the slip
        # grow and stop), or it does not rise at all (a grazing uplift).
        first_step = lift_off_step(
            plain_rhs, _started(phase, sigma, y0, n), t0, y0, t_bound, first_step, work, **options
        )
        if first_step is None:
            end = NO_LIFT if fired[0].name == IMPACT else NO_SLIP
            return _Segment(
                t=t0, y=np.array(y0[: 2 * n]), event=end, t_critical=math.nan, peaks={0: 0.0}, slip=tuple(slip)
            )
        if work is not None:
            # The new solve starts (1 evaluation) and repeats the step the last try
            # took (accepted at once: 6), which sim.c does not: not counted (rule 5).
            work.done -= 7
        sol = solve(first_step)
        fired = [e for e, times in zip(events, sol.t_events) if e.terminal and len(times)]

    t_end, y_end = float(sol.t[-1]), np.array(sol.y[:, -1])
    if [e.name for e in fired] == [IMPACT]:
        y_end[0] = 0.0  # the impact is at theta = 0; the located root is 0 only to the tolerance
    if [e.name for e in fired] == [STOP]:
        y_end[2 * n + 1] = 0.0  # likewise the slip speed at its stop
    if fired and fired[0].name in (GAP_CLOSE, GAP_OPEN):
        t_end, y_end = after_gap(system, fired[0], sol.sol, t_end, y_end)
    crossings = [float(min(times)) for e, times in zip(events, sol.t_events) if e.name == CRITICAL and len(times)]
    # Step ends (first and last included) and every located event point.
    points = np.vstack([sol.y.T] + [ys for ys in sol.y_events if len(ys)])
    peaks = _peaks(system, phase, points, extra, flying, slip)
    bumper = 0.0
    if system.n_stops:
        # The start, the step ends and the terminal event; while a pad pushes, each step's peak (rule 6).
        bumper = system.largest_bumper_force(sol.y.T)
        if any(stop_on):
            bumper = max(bumper, system.bumper_peak(sol, bumper_best))
    return _Segment(
        t=t_end,
        y=y_end[: 2 * n],
        slip=(float(y_end[2 * n]), float(y_end[2 * n + 1])) if extra else tuple(slip),
        lift=(float(y_end[2 * n + 2]), float(y_end[2 * n + 3])) if flying else (0.0, 0.0),
        event=fired[0].name if fired else None,
        t_critical=crossings[0] if crossings else math.nan,
        peaks=peaks,
        dense=sol.sol,
        side=fired[0].side if fired else -1,
        bumper_force=bumper,
        step=_last_step(sol.sol) if lifts else None,
    )


# --------------------------------------------------------------------------- #
# Bookkeeping: counters, maxima and the recorded history                       #
# --------------------------------------------------------------------------- #


@dataclass
class _History:
    """Recorded rows ``(t, y, phase)`` in time order, events included; on a floor with friction ``y`` ends with
    the slip ``u``, ``du`` and the slip's direction (``slide``: 0 stuck, +1 or -1)."""

    rows: list = field(default_factory=list)

    def add(self, t: float, y: np.ndarray, phase: int) -> None:
        """Append a row, unless it repeats the last one (a segment restarting at ``t_p``)."""
        y = np.array(y, dtype=float)
        if self.rows:
            last_t, last_y, last_phase = self.rows[-1]
            if last_t == t and last_phase == phase and np.array_equal(last_y, y):
                return
        self.rows.append((float(t), y, int(phase)))

    @staticmethod
    def sample_range(t0: float, t1: float, dt: float) -> tuple[int, int]:
        """``(lo, hi)``: the samples ``k dt``, ``lo <= k < hi``, strictly inside ``(t0, t1)``.

        The same multiples as sim.c's ``record_samples``.
        """
        if dt <= 0.0 or not t1 > t0:
            return 0, 0
        lo = first_sample_after(t0, dt)
        return lo, max(lo, first_sample_after(t1, dt, strict=False))

    def add_samples(self, dense, t0: float, t1: float, phase: int, dt: float, layout) -> None:
        """Append the dense output at the multiples of ``dt`` strictly inside ``(t0, t1)``, each made a row by
        ``layout`` (:func:`row_layout`)."""
        if dense is None or dt <= 0.0:  # events only, or a segment that did not integrate (no lift)
            return
        times = np.arange(*self.sample_range(t0, t1, dt)) * dt
        if times.size:
            for t, y in zip(times, dense(times).T):
                self.rows.append((float(t), layout(y), int(phase)))

    def as_dict(self, problem: Problem, system: _System) -> dict:
        """``t``, each state component by name, ``phase`` and ``ag`` as arrays, then the floor's columns."""
        t = np.array([row[0] for row in self.rows])
        y = np.array([row[1] for row in self.rows]).reshape(len(self.rows), -1)
        history = {"t": t}
        floor = list(SLIP_COLUMNS) if system.floor_columns else []
        names = list(problem.model.state) + floor + (list(FLIGHT_COLUMNS) if system.flies else [])
        for i, name in enumerate(names):
            history[name] = y[:, i]
        if "slide" in history:
            history["slide"] = history["slide"].astype(int)
        history["phase"] = np.array([row[2] for row in self.rows], dtype=int)
        history["ag"] = np.asarray(problem.ground_acceleration(t), dtype=float).reshape(t.shape)
        return history


@dataclass
class _Tally:
    """What the run has seen so far: the fields of :class:`Response` before the end."""

    impacts: int = 0
    uplifts: int = 0
    theta_max: float = 0.0
    x_max: float = 0.0
    t_critical: float = math.nan
    stop_contacts: int = 0
    bumper_force_max: float = 0.0
    u_max: float = 0.0
    slides: int = 0
    flights: int = 0
    flight_time: float = 0.0
    jump_max: float = 0.0

    def see_state(self, y: np.ndarray, system: _System) -> None:
        self.theta_max = max(self.theta_max, abs(float(y[0])))
        if system.n > 1:
            self.x_max = max(self.x_max, abs(float(y[1])))
        self.bumper_force_max = max(self.bumper_force_max, system.largest_bumper_force(np.asarray(y)[None, :]))

    def see_segment(self, segment: _Segment) -> None:
        self.theta_max = max(self.theta_max, segment.peaks[0])
        self.x_max = max(self.x_max, segment.peaks.get(1, 0.0))
        self.bumper_force_max = max(self.bumper_force_max, segment.bumper_force)
        self.u_max = max(self.u_max, segment.peaks.get("u", 0.0))
        self.jump_max = max(self.jump_max, segment.peaks.get("jump", 0.0))
        if math.isnan(self.t_critical):
            self.t_critical = segment.t_critical


# --------------------------------------------------------------------------- #
# The phase machine                                                            #
# --------------------------------------------------------------------------- #


def _first_step_after_impact(duration: float, dtheta_out: float, dtheta_in: float) -> float | None:
    """The first step of the half-cycle after an impact; ``None``: Hairer's heuristic.

    The next half-cycle lasts about the last one (``duration``) times
    ``|dtheta+ / dtheta-|`` (small rocking is nearly a parabola in time, whose
    length is proportional to its initial velocity); its first step is
    :data:`FIRST_STEP_FRACTION` of that.
    """
    if dtheta_in == 0.0:
        return None
    h = FIRST_STEP_FRACTION * duration * abs(dtheta_out / dtheta_in)
    return float(h) if math.isfinite(h) and h > 0 else None


@dataclass
class _Run:
    """The state of one run between segments (``struct run`` of sim.c).

    Attributes
    ----------
    problem : Problem
        The run's settings.
    system : _System
        The model with its parameters.
    t, y : float, ndarray
        The state between segments.
    phase : int
        ``CONTACT`` or the pivot ``s``.
    history : _History or None
        The recorded history (``record=True``).
    safe_energy : float or None
        Rule 4's bound on the energy above rest below which the block never
        lifts again; ``None``: no bound, or the early rest is off.
    tally : _Tally
        Counters and maxima so far.
    pulse_on : bool
        The current turn of the phase machine started before ``t_p``: its
        contact checks and its segment see the pulse. An impact at the
        segment's end is still evaluated with the segment's ground motion,
        even when it falls exactly on ``t_p``.
    safe : bool
        Full contact after the pulse below ``safe_energy``: settling.
    t_start : float
        When the current rocking phase started, at ``theta = 0``.
    first_step : float or None
        First step of the next segment; ``None``: Hairer's heuristic.
    skip_uplift_check : bool
        The next contact phase starts without the uplift check: after a
        lift-off that failed, ``u_s`` is still (barely) positive, and checking
        it again would lift the block again, forever.
    work : _Work or None
        The work so far against ``max_steps`` (rule 5).
    stop_on : list of bool
        Whether each stop side's bumper acts (rule 6).
    verdict : bool
        The early verdict of rule 4 applies (``early_verdict``).
    bound_at, bound : tuple, float
        The last bound of the early verdict, and the ``(theta_max, x_max)`` it is for.
    side : int
        The stop side whose gap event ended the last segment (-1: none).
    sigma : int
        The direction of the base's slip: 0 while the contact sticks, +1 or -1 while it slides (the phase is
        :func:`rocking.sim.phases.of` ``(phase != CONTACT, sigma != 0)``; docs/model.md section 15).
    u, du : float
        The slip of the base relative to the ground [m] and its speed [m/s].
    skip_slip_check : bool
        The next turn starts without the slip check: after a slip that could not start (``NO_SLIP``).
    flying : bool
        The block is off the floor (the phase ``flight``, docs/model.md section 16): ``phase`` is the reference
        corner ``s``, the slip ``u``, ``du`` and the height ``v``, ``dv`` are in the state.
    v, dv : float
        The reference corner's height above the floor [m] and its rate [m/s] (0 on the floor).
    takeoff_from : tuple
        ``(phase, sigma)`` of the phase the last takeoff left (a grazing takeoff returns there: ``NO_TAKEOFF``).
    grazed : bool
        The next segment starts where a takeoff grazed: no takeoff check at its start, and its lift-off is
        armed once its margin is positive (:func:`lift_off_event`).
    """

    problem: Problem
    system: _System
    t: float
    y: np.ndarray
    phase: int
    history: _History | None
    safe_energy: float | None
    tally: _Tally = field(default_factory=_Tally)
    pulse_on: bool = True
    safe: bool = False
    t_start: float = 0.0
    first_step: float | None = None
    skip_uplift_check: bool = False
    work: _Work | None = None
    stop_on: list = field(default_factory=list)
    verdict: bool = False
    bound_at: tuple = (math.nan, math.nan)
    bound: float = -math.inf
    side: int = -1
    sigma: int = 0
    u: float = 0.0
    du: float = 0.0
    skip_slip_check: bool = False
    flying: bool = False
    v: float = 0.0
    dv: float = 0.0
    takeoff_from: tuple = (CONTACT, 0)
    grazed: bool = False
    last_step: float | None = None


def record(run: _Run) -> None:
    """Append the current state to the history, if the run keeps one (with the floor's columns where it has them)."""
    if run.history is not None:
        y = np.concatenate([run.y, slip_row(run)]) if run.system.floor_columns else run.y
        run.history.add(run.t, y, run.phase)


def current_phase(run: _Run) -> str:
    """The name of the run's phase in :data:`rocking.sim.phases.PHASES`."""
    return phase_of(run.phase != CONTACT, run.sigma != 0 or run.flying, run.flying).name


def follow(run: _Run, event: str, guard: str, pivot: int = CONTACT, sigma: int = 0) -> str | None:
    """The exit of the phase table that ``event`` under ``guard`` takes from the run's phase: enter the next phase,
    rocking about ``pivot`` (in flight: its reference corner) if it rocks, the slip ``sigma`` if it slides on the
    floor (in flight the slip is in the state: 0), or end the run.

    Returns
    -------
    str or None
        The end of the run (one of :data:`rocking.sim.phases.ENDS`, a status), else ``None``.
    """
    to = next_phase(current_phase(run), event, guard)
    if to in ENDS:
        return to
    entry = table_phase(to)
    run.phase = pivot if entry.rocks else CONTACT
    run.flying = entry.flies
    run.sigma = sigma if entry.slides and not entry.flies else 0
    return None


def slip_row(run: _Run) -> tuple:
    """What a history's row ends with after the state where it has the floor's columns: ``(u, du, slide)``, and
    for a model with flight ``(v, dv, fly)``."""
    row = (run.u, run.du, float(run.sigma))
    return row + (run.v, run.dv, float(run.flying)) if run.system.flies else row


def row_layout(run: _Run) -> Callable[[np.ndarray], np.ndarray]:
    """How a segment's dense state becomes a history's row (:func:`slip_row`'s columns after the state): the
    dense output holds ``u``, ``du`` of a sliding segment and ``u``, ``du``, ``v``, ``dv`` of a flight."""
    n2, tail = 2 * run.system.n, slip_row(run)
    if not run.system.floor_columns:
        return lambda y: np.asarray(y)
    if run.flying:
        return lambda y: np.concatenate([y[: n2 + 2], [0.0], y[n2 + 2 : n2 + 4], [1.0]])
    if run.sigma:
        return lambda y: np.concatenate([y[: n2 + 2], tail[2:]])
    return lambda y: np.concatenate([y, tail])


def start_slip(run: _Run) -> None:
    """A stuck contact that must hold more than ``mu_s N`` slides, against the force it held (section 15); the
    history gets the instant in the sliding phase. Not checked once after a slip that could not start."""
    skip, run.skip_slip_check = run.skip_slip_check, False
    if not run.system.friction or run.sigma or skip or run.flying:
        return
    ground, vertical = run.system.ground(run.pulse_on, run.t), run.system.vertical(run.pulse_on, run.t)
    F, N = run.system.floor_force(run.phase, run.y, ground(run.t), tuple(run.stop_on), vertical(run.t))
    if abs(float(F)) > run.system.mu_s * float(N):
        slide_against(run, float(F))
        record(run)


def slide_against(run: _Run, F: float, event: str = SLIP, guard: str = "always") -> None:
    """The stuck contact starts to slide against the force ``F`` it held (the exit ``event`` under ``guard``): a
    new slip episode."""
    follow(run, event, guard, run.phase, -1 if F > 0.0 else 1)
    run.tally.slides += 1


def stop_slip(run: _Run) -> None:
    """The slip speed is back to 0: the contact sticks if it can hold the force, else the slip reverses."""
    run.du = 0.0
    ground, vertical = run.system.ground(run.pulse_on, run.t), run.system.vertical(run.pulse_on, run.t)
    F, N = run.system.floor_force(run.phase, run.y, ground(run.t), tuple(run.stop_on), vertical(run.t))
    if abs(float(F)) <= run.system.mu_s * float(N):
        follow(run, STOP, "holds", run.phase)
    else:
        # It stopped for an instant: the slip in the other direction is a new episode.
        slide_against(run, float(F), STOP, "slips")


def events_exhausted(run: _Run) -> bool:
    """``uplifts + impacts + flights`` has reached ``max_events``."""
    return run.tally.uplifts + run.tally.impacts + run.tally.flights >= run.problem.max_events


def uplift_at_start(run: _Run) -> int:
    """Pivot ``s`` whose ``u_s`` is already positive when full contact starts, else 0.

    A root-finding event only sees a sign change *during* a step; when the
    phase starts above a threshold (a pulse with ``psi > 0``, or a mass that
    is moving when the block comes to rest) the uplift is at that instant.
    """
    ground, vertical = run.system.ground(run.pulse_on, run.t), run.system.vertical(run.pulse_on, run.t)
    for s in (+1, -1):
        if run.system.uplift(s, run.y, ground(run.t), tuple(run.stop_on), vertical(run.t), run.sigma) > 0.0:
            return s
    return 0


def settled_at_once(run: _Run) -> bool:
    """Settling ends before it starts: nothing to settle without a damper, and ``dq[1] = 0`` is the extremum itself."""
    n = run.system.n
    return n == 1 or run.y[n + 1] == 0.0


def status_at_t_max(run: _Run) -> str:
    """Why a run that reached ``t_max`` ended: ``"below_barrier"`` after the pulse with an energy that can never
    carry the block to overturning (:meth:`_System.barrier_bound`: safe, its maxima those until ``t_max``), else
    ``"t_max"`` (no verdict)."""
    if run.t >= run.problem.t_p and not run.flying:  # in flight: no verdict (the spec of issue 39)
        s = -1 if run.phase < 0 else 1
        # A released pad may push again: its elastic energy counts wherever the mass is in it (rule 4).
        loaded = tuple(run.system.stop_gap(i, run.y) > 0.0 for i in range(run.system.n_stops))
        # The slip's kinetic energy counts: friction only dissipates it (docs/model.md section 15).
        energy = run.system.energy_above_rest(run.y, loaded, s) + run.system.slip_energy(run.y, run.du)
        if energy < run.system.barrier_bound():
            return "below_barrier"
    return "t_max"


def stops_clear(run: _Run) -> bool:
    """No bumper acts now and the mass is inside every gap (a released pad may push again)."""
    return not any(run.stop_on) and all(run.system.stop_gap(i, run.y) <= 0.0 for i in range(run.system.n_stops))


def read_regime(run: _Run) -> None:
    """Each stop side's regime read again from the state (rule 6), after a jump of the velocities and where a
    segment starts: never carried over. A side that starts pushing there is a contact."""
    for i in range(run.system.n_stops):
        on = run.system.stop_contact(i, run.y) > 0.0
        run.tally.stop_contacts += on and not run.stop_on[i]
        run.stop_on[i] = on


def verdict_final(run: _Run) -> bool:
    """After the pulse, the energy can no longer carry ``|theta|`` or ``|q[1]|`` to their maxima (rule 4).

    The verdict, the maxima, ``t_critical`` and the bumpers' results are then final (no bumper may act now).
    The bound is kept until a maximum grows.
    """
    # On a floor with friction the energy bounds theta and q[1], not the slip, which may go on: no early verdict.
    if not (run.verdict and run.t >= run.problem.t_p and stops_clear(run)) or run.system.friction:
        return False
    at = (run.tally.theta_max, run.tally.x_max)
    if at != run.bound_at:
        run.bound_at, run.bound = at, run.system.verdict_bound(*at)
    s = -1 if run.phase < 0 else 1
    return run.system.energy_above_rest(run.y, tuple(run.stop_on), s) < run.bound


def end_at_start(run: _Run) -> str | None:
    """Rule 4 when full contact starts after the pulse: the status if the run ends here.

    Below ``energy_rest``, at rest; with the early verdict, bounded. Below
    the uplift energy the block can never lift again: only the damper's
    stroke is left to settle, up to the next extremum of ``q[1]``; the run
    is then marked safe unless that extremum is now.
    """
    energy = run.system.energy_above_rest(run.y, tuple(run.stop_on))
    # For the bare block E(y) = E(0) in full contact: rest at once.
    if energy < run.system.rest_energy:
        return "rest"
    if verdict_final(run):
        return "bounded"
    if run.safe_energy is not None and (run.safe or (energy < run.safe_energy and stops_clear(run))):
        if settled_at_once(run):
            return "rest"
        run.safe = True
    return None


def uplift(run: _Run, s: int) -> str | None:
    """The block leaves full contact about ``s`` (rule 1).

    Returns
    -------
    str or None
        ``"max_events"`` if this uplift exhausts ``max_events``, else ``None``.
    """
    run.tally.uplifts += 1
    follow(run, "uplift", "always", s, run.sigma)
    run.safe = False  # not reached below the uplift energy; kept consistent if it were
    return "max_events" if events_exhausted(run) else None


def periodic_extremum(w: float, phase: float, t: float) -> float:
    """The first extremum of a periodic shape after ``t``: ``w t + phase = pi/2 + k pi``.

    The one-sine has ``phase = psi``, the one-cosine ``pi / 2``. The same
    operations as sim.c's ``next_periodic_extremum``.
    """
    k = (w * t + phase - math.pi / 2) / math.pi
    k = float(math.ceil(k) if w > 0.0 else math.floor(k))
    for _ in range(4):  # rounding: the first or the second candidate
        tk = (math.pi / 2 + k * math.pi - phase) / w
        if tk > t:
            return tk
        k += 1.0 if w > 0.0 else -1.0
    return math.inf  # pragma: no cover - not reached


def next_extremum(problem: Problem, t: float) -> float:
    """The first extremum of ``ag`` after ``t`` (rule 3).

    Closed forms for the one-sine and the one-cosine (and with a vertical lead those of the listed
    offsets: docs/model.md section 14); the listed extrema
    (phase units ``omega_g (t - t_c)``) of the Ricker wavelets and the
    Mavroeidis-Papageorgiou pulse; ``inf`` for a constant ground acceleration
    and for a sampled motion (its segments end at every sample time). The
    same operations as sim.c's ``next_extremum``.
    """
    w, family = float(problem.omega_g), FAMILIES[problem.motion]
    if not w != 0.0 or problem.a_g == 0.0 or family == "sampled":
        return math.inf
    if family in ("sine", "cosine"):
        phase = float(problem.psi) if family == "sine" else math.pi / 2
        # A vertical lead lists the uplift margins' extrema as offsets of the sine's argument, mod pi.
        offsets = () if problem.extrema is None else problem.extrema[: problem.n_extrema]
        return min(
            [periodic_extremum(w, phase, t)] + [periodic_extremum(w, phase + math.pi / 2 - d, t) for d in offsets]
        )
    offsets = () if problem.extrema is None else problem.extrema[: problem.n_extrema]
    later = [tk for tk in (problem.t_c + float(phi) / w for phi in offsets) if tk > t]
    return later[0] if later else math.inf


def next_sample(problem: Problem, t: float) -> float:
    """The first sample time of a sampled motion after ``t`` (``inf`` for an analytic one): a kink of ``ag``."""
    if FAMILIES[problem.motion] != "sampled":
        return math.inf
    dt = float(problem.pulse_dt)
    return (sample_piece(t, dt, problem.n_samples) + 1.0) * dt


def rest_snap(run: _Run, pivot: int) -> None:
    """The rest snap after an impact (rule 2): ``dtheta = 0``, each other velocity keeping what its law keeps.

    A coordinate with the ``velocity`` impact law keeps its velocity; those
    with the ``momentum`` law (manifest ``options.impact_laws``, the default)
    keep their generalised momenta ``(M dq)_j``, ``M`` the mass matrix about
    the new ``pivot``: the momentum-law block ``m`` of the velocities moves by
    ``delta``, ``M_mm delta = M_m0 dtheta``. Gauss elimination without
    pivoting (``M_mm`` is symmetric positive definite), the operations of
    sim.c's ``rest_snap``, so that both give the same bits.
    """
    system, y = run.system, run.y
    n, dtheta = system.n, float(run.y[system.n])
    mm = [float(v) for v in system.mass_matrix(pivot, y)]
    idx = [j for j in range(1, n) if system.impact_laws[j] != "velocity"]
    a = [[mm[i * n + j] for j in idx] for i in idx]
    b = [mm[i * n] * dtheta for i in idx]
    m = len(idx)
    for k in range(m):
        for i in range(k + 1, m):
            f = a[i][k] / a[k][k]
            for j in range(k, m):
                a[i][j] -= f * a[k][j]
            b[i] -= f * b[k]
    delta = [0.0] * m
    for i in reversed(range(m)):
        total = b[i]
        for j in range(i + 1, m):
            total -= a[i][j] * delta[j]
        delta[i] = total / a[i][i]
    for i, j in enumerate(idx):
        y[n + j] = float(y[n + j]) + delta[i]
    y[n] = 0.0


def impact(run: _Run) -> str | None:
    """The impact that ends rocking about ``s``: ``theta = 0`` already, ``dq = J_s(y)`` (rule 2).

    The block rests on its base if the outgoing ``|dtheta|`` is below
    ``dtheta_rest``; otherwise it rocks on about ``-s``, the corner that
    just hit the ground.

    Returns
    -------
    str or None
        ``"max_events"`` if this impact exhausts ``max_events``; ``"bounded"`` if the block rocks on and
        the early verdict ends the run (rule 4); else ``None``.
    """
    n = run.system.n
    s, dtheta_in, before = run.phase, run.y[n], run.y
    sigma = 0
    if run.system.friction:
        run.y, run.du, sigma = run.system.friction_impact(s, run.y, run.du, tuple(run.stop_on))
        run.tally.slides += bool(sigma) and not run.sigma
    else:
        run.y = run.system.impact(s, run.y, run.system.ground(run.pulse_on, run.t)(run.t))
    run.tally.impacts += 1
    rests = abs(run.y[n]) < run.problem.dtheta_rest
    follow(run, IMPACT, ("rests" if rests else "rocks") + ("-sliding" if sigma else ""), -s, sigma)
    if rests:
        rest_snap(run, -s)
    else:
        run.first_step = _first_step_after_impact(run.t - run.t_start, run.y[n], dtheta_in)
    if run.system.n_stops:
        # The velocities jumped: the pads' memory and regime follow the state (rule 6).
        run.system.jump_memory(before, run.y)
        read_regime(run)
    if events_exhausted(run):
        return "max_events"
    return "bounded" if run.phase != CONTACT and verdict_final(run) else None


def lifts_at_start(run: _Run) -> bool:
    """A phase on the floor of a model with flight starts below its takeoff margin (``N < 0``,
    :meth:`_System.takeoff_margin`): it takes off at once (an event sees only a sign change inside a step), as the
    slip check does at a start."""
    system = run.system
    if run.flying or run.grazed or not system.flies or not system.watches_lift_off(run.phase):
        return False
    ground, vertical = system.ground(run.pulse_on, run.t), system.vertical(run.pulse_on, run.t)
    return system.takeoff_margin(run.phase, run.sigma, run.y, ground(run.t), tuple(run.stop_on), vertical(run.t)) < 0.0


def takeoff(run: _Run, step: float | None = None) -> str | None:
    """The floor's normal force reached 0: the block flies (docs/model.md section 16), or, on a model without
    flight functions, the run ends with the status ``flight`` (section 14).

    The reference corner is the pivot, ``+1`` from full contact; ``u``, ``du`` go on, ``v = dv = 0``. A grazing
    takeoff stays on the floor; the next segment then starts with ``step``, the size of the step in which the
    lift-off fired (``None``: at a phase's start, SciPy's own), as sim.c's ``takeoff`` does.

    Returns
    -------
    str or None
        ``"flight"`` on a model without flight; ``"max_events"`` if this takeoff exhausts ``max_events``.
    """
    if not run.system.flies:
        return "flight"
    if run.system.corner_sinks(run.t, run.phase, run.sigma, run.y, run.pulse_on, tuple(run.stop_on)):
        run.grazed = True  # no flight: the pivot is held, its lift-off armed again once its margin is positive
        run.first_step = step
        return None
    run.takeoff_from = (run.phase, run.sigma)
    follow(run, LIFT_OFF, "always", run.phase if run.phase != CONTACT else 1)
    run.v = run.dv = 0.0
    run.safe = False
    run.tally.flights += 1
    return "max_events" if events_exhausted(run) else None


def landing(run: _Run, other: bool) -> str | None:
    """A base corner reached the floor moving down: the landing map of docs/model.md section 16, then the phase
    the table's guard names (the spec of issue 39, "Landing").

    The corner that lands becomes the reference (``other``: the corner ``-s``); within :data:`FLAT_LANDING` of
    ``theta = 0`` the base lands flat on both corners unless one would pull, then the other lands alone. A corner
    that leaves the floor faster than :attr:`_System.bounce_speed` bounces: the flight goes on.

    Returns
    -------
    str or None
        ``"jammed"`` where no landing law holds, else ``None``.
    """
    system, n = run.system, run.system.n
    before = run.y.copy()
    s, u, du, dv = run.phase, run.u, run.du, run.dv
    if other:
        u, _, du, dv = system.flight_corner(s, run.y, u, run.v, du, dv)
        s = -s
    y = run.y.copy()
    flat = abs(math.sin(float(y[0]))) <= FLAT_LANDING
    if flat:
        y[0] = 0.0
        kind, outcome = system.flat_landing(s, y, du, dv)
        if kind == "corner":
            if outcome != s:  # at theta = 0 the other corner's u, v are the same, its rates are not
                u, _, du, dv = system.flight_corner(s, y, u, 0.0, du, dv)
                s = outcome
            outcome = system.corner_landing(s, y, du, dv)
            flat = False
    else:
        outcome = system.corner_landing(s, y, du, dv)
    run.y, run.u = y, u
    run.v = 0.0
    if outcome is None:
        run.phase = s
        return follow(run, "landing", "jams")
    dq, run.du, dv_after, sigma = outcome
    run.y[n:] = dq
    if dv_after > system.bounce_speed:
        run.dv = dv_after
        follow(run, "landing", "bounces", s)
    else:
        run.dv = 0.0
        rests = y[0] == 0.0 and (flat or abs(run.y[n]) < run.problem.dtheta_rest)
        guard = ("rests" if rests else "rocks") + ("-sliding" if sigma else "")
        follow(run, "landing", guard, s, sigma)
        if rests and not flat:
            rest_snap(run, s)  # a corner's landing at theta = 0 below dtheta_rest: at rest on the base (rule 2)
    if system.n_stops:
        # The velocities jumped: the pads' memory and regime follow the state (rule 6).
        system.jump_memory(before, run.y)
        read_regime(run)
    return None


def contact_start(run: _Run) -> str | None:
    """Rules 1 and 4 as a full-contact phase starts: is it already over?

    An uplift at this very instant leaves ``run`` rocking; after the pulse,
    :func:`end_at_start` may end the run.

    Returns
    -------
    str or None
        The status if the run ends here, else ``None``.
    """
    s = 0 if run.skip_uplift_check else uplift_at_start(run)
    run.skip_uplift_check = False
    if s:
        return uplift(run, s)
    return None if run.pulse_on or run.sigma else end_at_start(run)


def run_segment(run: _Run, t_bound: float) -> str | None:
    """Integrate the current phase from ``(run.t, run.y)`` until ``t_bound`` or a terminal event.

    ``(run.t, run.y)`` is then the segment's end; the tally and the history's
    samples have seen the segment.

    Returns
    -------
    str or None
        The terminal event's name, or ``NO_LIFT``; ``None``: ``t_bound`` reached.

    Raises
    ------
    _MaxSteps
        The work passed ``max_steps`` inside the segment: ``run`` is left at
        the segment's start, untouched (rule 5).
    """
    if run.phase != CONTACT and run.y[0] == 0.0 and not run.flying:
        run.t_start = run.t  # a half-cycle starts (not a restart at the pulse's end)
    segment = integrate_segment(
        run.problem,
        run.system,
        run.phase,
        run.t,
        run.y,
        t_bound,
        want_critical=math.isnan(run.tally.t_critical),
        record=run.history is not None,
        safe_energy=run.safe_energy,
        settling=run.safe and run.phase == CONTACT,
        first_step=run.first_step,
        work=run.work,
        stop_on=tuple(run.stop_on),
        bumper_best=run.tally.bumper_force_max,
        sigma=run.sigma,
        slip=(run.u, run.du),
        flying=run.flying,
        lift=(run.v, run.dv),
        grazed=run.grazed,
    )
    run.grazed = False
    run.first_step = None
    run.last_step = segment.step
    run.side = segment.side
    if run.history is not None and segment.dense is not None and run.work is not None:
        # Rule 5: recorded samples count as work, before any of them is kept.
        lo, hi = _History.sample_range(run.t, segment.t, run.problem.record_dt)
        run.work.add(hi - lo)
    run.tally.see_segment(segment)
    if run.flying:
        run.tally.flight_time += segment.t - run.t
    if run.history is not None:
        run.history.add_samples(segment.dense, run.t, segment.t, run.phase, run.problem.record_dt, row_layout(run))
    run.t, run.y = segment.t, segment.y
    run.u, run.du = segment.slip
    if run.flying:
        run.v, run.dv = segment.lift
    return segment.event


def grazing(run: _Run, event: str) -> None:
    """A phase that could not start: back to the one before it, not counted.

    ``NO_SLIP``: a grazing slip, the base cannot move against ``F``: the contact stays stuck (not a slip
    episode); ``|F|`` is still barely above ``mu_s N``, so the start check would slip it again, forever: skipped
    once. ``NO_TAKEOFF``: a grazing takeoff, ``N`` touched 0 but the free flight cannot lift the corner: the block
    stays in the phase it took off from (not a flight); its lift-off is armed again once its margin is positive.
    """
    if event == NO_SLIP:
        run.sigma = 0
        run.tally.slides -= 1
        run.skip_slip_check = True
        return
    run.tally.flights -= 1
    run.flying, run.phase, run.sigma, run.dv = False, run.takeoff_from[0], run.takeoff_from[1], 0.0
    run.grazed = True


def segment_end(run: _Run, event: str | None, t_bound: float) -> str | None:
    """What the end of a segment does: the event of :func:`run_segment`, or its bound.

    Returns
    -------
    str or None
        The status if the run ends here, else ``None``.
    """
    if event is None:
        if t_bound == run.problem.t_max:
            return status_at_t_max(run)
        run.t = t_bound  # exactly the breakpoint (rule 3); the same phase restarts from here
    elif event in (UPLIFT_A, UPLIFT_A_PRIME):
        # theta and dtheta are exactly 0 in full contact: the state carries over.
        return uplift(run, 1 if event == UPLIFT_A else -1)
    elif event == IMPACT:
        return impact(run)
    elif event == SLIP:
        F, _ = run.system.floor_force(
            run.phase,
            run.y,
            run.system.ground(run.pulse_on, run.t)(run.t),
            tuple(run.stop_on),
            run.system.vertical(run.pulse_on, run.t)(run.t),
        )
        slide_against(run, float(F))
    elif event == STOP:
        stop_slip(run)
    elif event in (NO_SLIP, NO_TAKEOFF):
        grazing(run, event)
    elif event == LIFT_OFF:
        return takeoff(run, run.last_step)
    elif event in (LANDING, LANDING_OTHER):
        return landing(run, event == LANDING_OTHER)
    elif event == NO_LIFT:
        # The block never rose: back to full contact (the uplift stays counted).
        run.y[0] = run.y[run.system.n] = 0.0
        run.phase = CONTACT
        run.skip_uplift_check = True
    elif event in TABLE_ENDS:
        return follow(run, TABLE_ENDS[event], "always")
    elif event == SAFE:
        run.safe = stops_clear(run)  # the next contact phase settles (not rechecked: E is at the bound)
    elif event in (GAP_CLOSE, GAP_OPEN):
        # A breakpoint: the same phase restarts from here with the side's bumper on or off (rule 6).
        run.stop_on[run.side] = event == GAP_CLOSE
        if event == GAP_CLOSE:
            run.system.record_approach(run.side, run.y)
        run.tally.stop_contacts += event == GAP_CLOSE
    else:  # pragma: no cover - every terminal event is handled above
        raise AssertionError(f"unhandled event {event!r}")
    return None


def phase_machine(run: _Run) -> str:
    """The whole run: docs/simulation.md, "Phases" and "End".

    Parameters
    ----------
    run : _Run
        At its initial state; at its end on return.

    Returns
    -------
    str
        Why the run ended (one of ``STATUS``).
    """
    problem = run.problem
    while True:
        record(run)
        if run.t >= problem.t_flight:  # the base may leave the ground: out of scope (docs/model.md section 14)
            return "flight"
        if run.t >= problem.t_max:
            return status_at_t_max(run)
        run.pulse_on = run.t < problem.t_p
        read_regime(run)
        if lifts_at_start(run):
            status = takeoff(run)
            if status is not None:
                return status
            continue  # flies from this very instant: recorded in flight first
        start_slip(run)
        if run.phase == CONTACT and not run.flying:
            status = contact_start(run)
            if status is not None:
                return status
            if run.phase != CONTACT:
                continue  # lifted at this very instant: the new phase starts from here
        # Rule 3: no segment straddles the motion's end or a sample time, nor, in full contact, an extremum of ag.
        t_bound = (
            min(problem.t_p, problem.t_max, next_sample(problem, run.t), problem.t_flight)
            if run.pulse_on
            else problem.t_max
        )
        if run.phase == CONTACT and run.pulse_on and not run.flying:
            t_bound = min(t_bound, next_extremum(problem, run.t))
        try:
            event = run_segment(run, t_bound)
        except _MaxSteps:
            return "max_steps"  # at the segment's start, with the results before it
        # The segment's end: the pulse's end, t_max, or an event (an impact's "before").
        record(run)
        status = segment_end(run, event, t_bound)
        if status is not None:
            return status


def finish(run: _Run, status: str) -> Response:
    """The :class:`Response` of a run that :func:`phase_machine` ended with ``status``.

    The end state is the history's last row.
    """
    assert status in STATUS
    record(run)
    tally, history = run.tally, run.history
    return Response(
        overturned=status == "overturned",
        t_overturn=run.t if status == "overturned" else math.nan,
        t_critical=tally.t_critical,
        theta_max=tally.theta_max,
        x_max=tally.x_max,
        impacts=tally.impacts,
        uplifts=tally.uplifts,
        t_end=run.t,
        status=status,
        stop_contacts=tally.stop_contacts,
        bumper_force_max=tally.bumper_force_max,
        u_max=max(tally.u_max, abs(run.u)),
        u_end=run.u,
        slides=tally.slides,
        flights=tally.flights,
        flight_time=tally.flight_time,
        jump_max=tally.jump_max,
        history=None if history is None else floor_forces(run.system, history.as_dict(run.problem, run.system)),
    )


def floor_forces(system: _System, history: dict) -> dict:
    """``history`` with the floor's normal force ``N`` and tangential force ``F`` on the block [N] at each row,
    on a floor with friction (as sim.c records them): the stuck phase's from its force function, the sliding
    one's ``N`` from its accelerations and ``F = -mu_k slide N``."""
    if not system.floor_columns:
        return history
    t_p, n = system.problem.t_p, system.n
    flying = history["fly"] if system.flies else np.zeros(len(history["t"]))
    normal, tangential = np.empty(len(history["t"])), np.empty(len(history["t"]))
    names = system.problem.model.state
    for i, t in enumerate(history["t"]):
        y = np.array([history[name][i] for name in names])
        phase, sigma, on = int(history["phase"][i]), int(history["slide"][i]), t < t_p
        ag, agy = history["ag"][i], system.vertical(on, t)(t)
        regime = tuple(system.stop_contact(j, y) > 0.0 for j in range(system.n_stops))
        if flying[i]:
            normal[i] = tangential[i] = 0.0  # no floor under a flying block
        elif sigma:
            normal[i] = float(system.slide_accel(phase, sigma, y, ag, regime, agy)[n + 1])
            tangential[i] = -system.mu_k * sigma * normal[i]
        else:
            force = system.floor_force(phase, y, ag, regime, agy)
            tangential[i], normal[i] = float(force[0]), float(force[1])
    columns = {**history, "N": normal, "F": tangential}
    flight = FLIGHT_COLUMNS if system.flies else ()
    return {k: columns[k] for k in ("t", *names, "phase", "ag", *FLOOR_COLUMNS, *flight)}


def simulate(problem: Problem, record: bool = False) -> Response:
    """Simulate one problem with SciPy's Dormand-Prince 5(4), following docs/simulation.md.

    Parameters
    ----------
    problem : Problem
        The run (see :func:`rocking.sim.problem.make_problem`), its initial
        state ``y0``, ``phase0`` included (``None``: at rest in full contact,
        checked for uplift at once).
    record : bool
        Keep the history: samples every ``problem.record_dt`` from the dense
        output plus every event (uplift, impact before and after, rest, pulse
        end, overturning, end), in time order.

    Returns
    -------
    Response
        With ``history`` (``t``, each state component by name, ``phase``,
        ``ag``) when ``record`` is true.

    Raises
    ------
    ParameterError
        The run plans more work than this back end takes on (:func:`check_planned_work`).
    SimulationError
        If ``solve_ivp`` fails (step size too small, e.g. on a non-finite
        right-hand side).
    """
    check_planned_work(problem, record)
    system = _System(problem)
    y = np.zeros(2 * system.n) if problem.y0 is None else np.array(problem.y0, dtype=float)
    system.start_memory(y)
    run = _Run(
        problem=problem,
        system=system,
        t=0.0,
        y=y,
        phase=int(problem.phase0),
        history=_History() if record else None,
        # The uplift energy bounds a stuck contact's lifting: a sliding one may lift below it (rule 4).
        safe_energy=system.safe_energy if problem.early_rest and not system.friction else None,
        work=_Work(int(problem.max_steps)),
        stop_on=[system.stop_contact(i, y) > 0.0 for i in range(system.n_stops)],
        verdict=bool(problem.early_verdict),
    )
    run.tally.see_state(run.y, system)
    return finish(run, phase_machine(run))
