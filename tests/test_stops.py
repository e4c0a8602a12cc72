"""End stops on the guide (docs/model.md section 11, docs/simulation.md rule 6), on both back ends.

The outside fact: a mass that meets a linear Kelvin-Voigt bumper (stiffness ``k_b``,
damping ``c_b = 2 zeta_b sqrt(k_b m)``) with nothing else acting on it moves as a damped
oscillator from the moment the gap closes: its penetration is
``delta(t) = v0 / omega_d exp(-zeta_b omega_n t) sin(omega_d t)``. A pad only pushes: it
lets go where ``k_b delta + c_b ddelta`` falls to 0, at
``omega_d t_r = pi - atan2(2 zeta_b sqrt(1 - zeta_b^2), 1 - 2 zeta_b^2)``, and the mass leaves
at its velocity there, ``-e v0``, whatever ``k_b`` (without damping, ``t_r = pi / omega_d`` and
``e = 1``). A free mass on a block that stays on its base is such a mass: in full contact
(C1) reads ``m ddx + G(x, dx) = 0`` without ground motion.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rocking import Block, Damper, OneSinePulse, load_model
from rocking.sim.problem import make_problem
from rocking.sim.run import run

BACKENDS = ("numpy", "c")
REFERENCE = Block.reference()
#: One second without ground motion: t_p is only a breakpoint.
STILL = OneSinePulse(a_g=0.0, omega_g=2 * math.pi)
#: A free 1 kg mass (no spring, no dashpot) 0.1 m from either bumper, moving at V0.
FREE = {"m": 1.0, "h": 0.05, "k_m": 0.0, "c": 0.0, "L": 0.1}
V0 = 0.5


@pytest.fixture(params=BACKENDS)
def backend(request) -> str:
    return request.param


def bumper(k_b: float, zeta_b: float, m: float = 1.0) -> dict:
    """A bumper of stiffness ``k_b`` and damping ratio ``zeta_b`` for the mass ``m``."""
    return {"k_b": k_b, "c_b": 2 * zeta_b * math.sqrt(k_b * m)}


def free_mass(k_b: float, zeta_b: float, t_max: float, rtol: float = 1e-11):
    """The free mass at x = 0 moving at V0 towards the upper bumper, the block on its base, no ground motion."""
    return make_problem(
        REFERENCE,
        {**FREE, **bumper(k_b, zeta_b)},
        STILL,
        model="omd_stops",
        rtol=rtol,
        t_max=t_max,
        y0=np.array([0.0, 0.0, 0.0, V0]),
        energy_rest=0.0,
        early_rest=False,
    )


def flights(k_b: float, zeta_b: float) -> tuple[float, float, float]:
    """``(e, tau, t1)``: restitution, time from the gap's closing to its opening, and first closing of the
    free mass (the module's closed form: the pad lets go at ``t_r``, the mass then leaves it at ``-e v0``)."""
    omega_n = math.sqrt(k_b)
    root = math.sqrt(1 - zeta_b**2)
    omega_d = omega_n * root
    t_r = (math.pi - math.atan2(2 * zeta_b * root, 1 - 2 * zeta_b**2)) / omega_d
    decay = math.exp(-zeta_b * omega_n * t_r)
    delta_r = decay * math.sin(omega_d * t_r) / omega_d  # per unit v0
    e = -decay * (math.cos(omega_d * t_r) - zeta_b / root * math.sin(omega_d * t_r))
    return e, t_r + delta_r / e, FREE["L"] / V0


def position_after_two_contacts(t: float, k_b: float, zeta_b: float, rigid: bool = False) -> float:
    """``x(t)`` of the free mass after it left the lower bumper (``rigid``: contacts of no duration)."""
    e, tau, t1 = flights(k_b, zeta_b)
    tau = 0.0 if rigid else tau
    t_left_lower = t1 + tau + 2 * FREE["L"] / (e * V0) + tau
    return -FREE["L"] + e * e * V0 * (t - t_left_lower)


@pytest.mark.parametrize("zeta_b", [0.0, 0.1, 0.4])
def test_a_kelvin_voigt_contact_matches_its_closed_form(backend, zeta_b):
    """Two contacts: the rebound velocity is -e v0, and after the second the mass is where the closed form has it."""
    k_b = 1e4
    e, tau, t1 = flights(k_b, zeta_b)
    t_end = t1 + 2 * tau + 2 * FREE["L"] / (e * V0) + 0.05
    r = run(free_mass(k_b, zeta_b, t_end), backend=backend, record=True)
    assert (r.status, r.uplifts, r.stop_contacts) == ("t_max", 0, 2)
    h = r.history
    assert h["x"][-1] == pytest.approx(position_after_two_contacts(t_end, k_b, zeta_b), rel=1e-8)
    assert h["dx"][-1] == pytest.approx(e * e * V0, rel=1e-8)
    # Rule 6: each closing and each release is a breakpoint, recorded with |x| = L, or with the pad's
    # force k_b delta + c_b ddelta at 0 (the gap's opening instead, without damping).
    at_gap = np.flatnonzero(np.isclose(np.abs(h["x"]), FREE["L"], rtol=0.0, atol=1e-12))
    delta = np.abs(h["x"]) - FREE["L"]
    push = k_b * delta + bumper(k_b, zeta_b)["c_b"] * np.sign(h["x"]) * h["dx"]
    released = np.flatnonzero((delta > 1e-9) & np.isclose(push, 0.0, rtol=0.0, atol=1e-8 * V0 * math.sqrt(k_b)))
    assert len(at_gap) >= (2 if zeta_b else 4) and len(released) >= (2 if zeta_b else 0)
    # The largest force, at step ends: at most the oscillator's peak, k_b delta + c_b ddelta.
    kelvin_voigt = math.exp(-zeta_b * math.pi / math.sqrt(1 - zeta_b**2))
    assert 0.9 * V0 * math.sqrt(k_b) * kelvin_voigt ** (1 / 4) <= r.bumper_force_max <= V0 * math.sqrt(k_b) * 1.0001


def test_a_stiffer_bumper_tends_to_the_rigid_stop_at_order_one_half(backend):
    """The position after two contacts converges to the rigid stop's as k_b^(-1/2) (the contacts' duration)."""
    zeta_b, t_end = 0.2, 1.2
    stiffness = np.array([1e3, 1e4, 1e5, 1e6])
    errors = []
    for k_b in stiffness:
        r = run(free_mass(k_b, zeta_b, t_end), backend=backend, record=True)
        assert r.stop_contacts == 2
        errors.append(abs(r.history["x"][-1] - position_after_two_contacts(t_end, k_b, zeta_b, rigid=True)))
    order = -np.polyfit(np.log(stiffness), np.log(errors), 1)[0]
    assert order == pytest.approx(0.5, abs=0.01), (order, errors)


def test_energy_balance_across_stop_contacts(backend):
    """A spring, no dashpots: the energy (the bumpers' potential included) is constant across the contacts;
    with the bumpers' dashpots it falls by their dissipation, the integral of c_b dx^2 while they push, and at
    each release by the pad's potential k_b delta^2 / 2 there, which leaves with the pad: no event adds energy."""
    model = load_model("omd_stops")
    damper = {"m": 2.0, "h": 0.05, "k_m": 50.0, "c": 0.0, "L": 0.05}
    for c_b in (0.0, 40.0):
        params = {**damper, "k_b": 5e3, "c_b": c_b}
        problem = make_problem(
            REFERENCE,
            params,
            STILL,
            model="omd_stops",
            rtol=1e-11,
            t_max=3.0,
            record_dt=2e-5,
            y0=np.array([0.0, 0.0, 0.0, 0.6]),
            energy_rest=0.0,
            early_rest=False,
        )
        r = run(problem, backend=backend, record=True)
        assert r.uplifts == 0 and r.stop_contacts >= 3
        h = r.history
        state = [h[k] for k in model.state]
        at_rest = model.functions.energy(1.0, *np.zeros(len(state)), 0.0, 0.0, *problem.p)
        energy = model.functions.energy(1.0, *state, 0.0, 0.0, *problem.p) - at_rest  # the damper's, about 0.36 J
        if c_b == 0.0:
            # Only the integrator's error is left: 3e-9 J of 0.36 J over the run, at rtol 1e-11.
            assert np.max(np.abs(energy - energy[0])) < 1e-7 * energy[0]
            continue
        # Trapezoids of c_b dx^2 over the intervals where a bumper pushes: the closings and releases are
        # rows of the history (rule 6), so no interval straddles one, and its midpoint tells.
        x, dx = (h["x"][1:] + h["x"][:-1]) / 2, (h["dx"][1:] + h["dx"][:-1]) / 2
        delta = np.abs(x) - damper["L"]
        acting = (delta > 0) & (params["k_b"] * delta + c_b * np.sign(x) * dx > 0)
        power = h["dx"] ** 2
        dissipated = np.concatenate([[0.0], np.cumsum(acting * c_b * np.diff(h["t"]) * (power[1:] + power[:-1]) / 2)])
        # Each release is where an interval that pushes meets one that does not, beyond the gap.
        released = np.flatnonzero(acting[:-1] & ~acting[1:] & (delta[1:] > 0)) + 1
        lost = np.zeros(len(h["t"]))
        lost[released] = params["k_b"] * (np.abs(h["x"][released]) - damper["L"]) ** 2 / 2
        assert len(released) >= 3 and energy[-1] < 0.9 * energy[0]
        assert np.max(np.abs(energy + dissipated + np.cumsum(lost) - energy[0])) < 1e-4 * energy[0]


def test_c_and_numpy_agree_with_stops():
    """Random pulses, dampers and bumpers on the reference block: the same verdicts, counts and maxima."""
    rng = np.random.default_rng(7)
    for _ in range(12):
        damper = Damper.from_nondim(
            REFERENCE,
            gamma=rng.uniform(0.02, 0.2),
            omega_ratio=rng.uniform(0.5, 2.0),
            zeta=rng.uniform(0.0, 0.2),
            h=0.05,
        )
        k_b = damper.k_m * 10 ** rng.uniform(1, 3)
        params = {**damper.as_params(), "L": rng.uniform(0.05, 0.25), **bumper(k_b, rng.uniform(0, 0.3), damper.m)}
        pulse = OneSinePulse.from_nondim(REFERENCE, beta=rng.uniform(1.2, 8), Omega=rng.uniform(1, 10))
        problem = make_problem(REFERENCE, params, pulse, model="omd_stops", rtol=1e-8, t_after=6.0)
        c, n = (run(problem, backend=b) for b in ("c", "numpy"))
        case = (params, pulse)
        assert (c.status, c.overturned, c.impacts, c.uplifts, c.stop_contacts) == (
            n.status,
            n.overturned,
            n.impacts,
            n.uplifts,
            n.stop_contacts,
        ), case
        for field in ("theta_max", "x_max", "bumper_force_max"):
            assert getattr(c, field) == pytest.approx(getattr(n, field), rel=1e-6), (field, case)
        # The back ends locate a gap's root to a few ulps each, not the same ulps: their states differ by
        # about 1e-9 after a contact (1e-13 without stops), which a run of 65 impacts to rest grows to 5e-6 in t_end.
        assert c.t_end == pytest.approx(n.t_end, rel=1e-4), case


def test_a_gap_beyond_any_stroke_is_the_unlimited_damper(backend):
    """omd_stops with L = 100 m gives omd's responses: no contact, the same maxima and counts."""
    damper = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    for beta, Omega in ((1.5, 1.0), (3.0, 4.0), (7.5, 10.0)):
        pulse = OneSinePulse.from_nondim(REFERENCE, beta=beta, Omega=Omega)
        free = run(make_problem(REFERENCE, damper, pulse), backend=backend)
        far = dataclasses.replace(damper, stops=Stops(L=100.0, k_b=1e6, c_b=1e3, beyond_edges=True))
        stopped = run(make_problem(REFERENCE, far, pulse), backend=backend)
        assert (stopped.stop_contacts, stopped.bumper_force_max) == (0, 0.0)
        for field in ("status", "overturned", "impacts", "uplifts"):
            assert getattr(stopped, field) == getattr(free, field)
        for field in ("theta_max", "x_max", "t_end"):
            assert getattr(stopped, field) == pytest.approx(getattr(free, field), rel=1e-9)


def test_a_run_that_starts_inside_a_bumper_has_it_acting(backend):
    """The flags start from the initial state (rule 6): a mass released at rest 1 cm into the upper bumper
    is pushed out at once and leaves it with the oscillator's velocity, omega_n * 1 cm for zeta_b = 0."""
    params = {**FREE, **bumper(1e4, 0.0)}
    problem = make_problem(
        REFERENCE,
        params,
        STILL,
        model="omd_stops",
        rtol=1e-11,
        t_max=0.1,
        y0=np.array([0.0, 0.11, 0.0, 0.0]),
        energy_rest=0.0,
        early_rest=False,
    )
    r = run(problem, backend=backend, record=True)
    assert r.stop_contacts == 0  # it was already in contact: the gap never closed
    assert r.history["dx"][-1] == pytest.approx(-math.sqrt(1e4) * 0.01, rel=1e-8)
    assert r.bumper_force_max == pytest.approx(1e4 * 0.01, rel=1e-9)


def test_a_released_pad_pushes_again_where_its_force_turns_positive(backend):
    """A pad only pushes (docs/model.md section 11): a mass 1 mm into the upper pad, leaving it faster than the
    pad recovers (k_b delta + c_b ddelta = -10 N), is released; the ground slows it, and the pad pushes again
    where the bracket turns positive, the mass still in the pad (rule 6). In full contact the free mass has
    ddx = -ag = cos(2 pi t): the bracket is 10^4 (1e-3 - 0.02 t + (1 - cos(2 pi t)) / (2 pi)^2)
    + 10^3 (-0.02 + sin(2 pi t) / (2 pi)), whose root is 0.0116632321939 s (Brent's method)."""
    params = {**FREE, "k_b": 1e4, "c_b": 1e3}
    # ag = sin(2 pi t + 3 pi / 2) = -cos(2 pi t): about 1 m/s^2 into the pad, too little to lift the block.
    toward = OneSinePulse(a_g=1.0, omega_g=2 * math.pi, psi=1.5 * math.pi)
    problem = make_problem(
        REFERENCE,
        params,
        toward,
        model="omd_stops",
        rtol=1e-11,
        t_max=0.03,
        y0=np.array([0.0, FREE["L"] + 1e-3, 0.0, -0.02]),
        energy_rest=0.0,
        early_rest=False,
    )
    r = run(problem, backend=backend, record=True)
    h = r.history
    push = params["k_b"] * (h["x"] - FREE["L"]) + params["c_b"] * h["dx"]
    i = np.flatnonzero(push > 0.0)[0]  # the first row where the pad pushes: the event, on the side after its root
    assert (r.uplifts, r.stop_contacts) == (0, 1) and h["t"][i] == pytest.approx(0.0116632321939, abs=1e-9)
    assert h["x"][i] > FREE["L"] and push[i] < 1e-6 and np.all(push[:i] <= 0.0)
    assert 0.0 < r.bumper_force_max and np.all(
        load_model("omd_stops").functions.stop_forces(
            1.0, *(h[k] for k in ("theta", "x", "dtheta", "dx")), 0.0, 0.0, *problem.p
        )[0]
        >= 0.0
    )


def test_the_contact_counters_of_a_run_cut_by_max_steps_are_those_of_its_last_segment(backend):
    """Rule 5 with stops: the counts and the force maximum of a cut run are at most the full run's."""
    damper = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    params = {**damper.as_params(), "L": 0.1, **bumper(damper.k_m * 100, 0.1, damper.m)}
    pulse = OneSinePulse.from_nondim(REFERENCE, beta=3.0, Omega=4.0)
    problem = make_problem(REFERENCE, params, pulse, model="omd_stops")
    full = run(problem, backend=backend)
    cut = run(dataclasses.replace(problem, max_steps=400), backend=backend)
    assert cut.status == "max_steps" and full.stop_contacts > 0
    assert cut.stop_contacts <= full.stop_contacts and cut.bumper_force_max <= full.bumper_force_max


# --- the damper as built: Stops in the public API ---------------------------------------------------

from rocking import ParameterError, Stops  # noqa: E402
from rocking import simulate as public_simulate  # noqa: E402

TUNED = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)


def test_stops_at_the_edges_follow_the_documented_choice():
    """L = B/2 - 20 mm, a neoprene pad 20 mm thick of 50 x 50 mm and modulus 5 MPa (k_b = E A / t = 6.25e5 N/m,
    whatever the damper) with zeta_b = 0.2 (restitution 0.57)."""
    stops = Stops.at_edges(REFERENCE, TUNED)
    assert stops.L == pytest.approx(REFERENCE.B / 2 - 0.02)
    assert stops.k_b == 5e6 * 0.05 * 0.05 / 0.02 == pytest.approx(6.25e5)
    assert stops.c_b / (2 * math.sqrt(stops.k_b * TUNED.m)) == pytest.approx(0.2)
    damper = dataclasses.replace(TUNED, stops=stops)
    assert damper.model == "omd_stops" and TUNED.model == "omd"
    assert damper.as_params() == {**TUNED.as_params(), "L": stops.L, "k_b": stops.k_b, "c_b": stops.c_b}


def test_a_damper_the_unlimited_guide_saves_overturns_with_stops_at_the_edges(backend):
    """The issue's case (Omega = 7.5, beta = 10): the free mass saves the block only by running 1.1 m off
    a 0.5 m base; stopped at the edges, the block overturns."""
    pulse = OneSinePulse.from_nondim(REFERENCE, beta=10.0, Omega=7.5)
    free = public_simulate(REFERENCE, TUNED, pulse, backend=backend)
    stopped = public_simulate(
        REFERENCE, dataclasses.replace(TUNED, stops=Stops.at_edges(REFERENCE, TUNED)), pulse, backend=backend
    )
    assert not free.overturned and free.x_max > 2 * REFERENCE.B
    assert stopped.overturned and stopped.stop_contacts >= 1
    assert REFERENCE.B / 2 - 0.02 < stopped.x_max < REFERENCE.B / 2


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Stops(L=0.0, k_b=1e5), r"^L must be in \(0, 1000\] m \(got 0.0\)"),
        (lambda: Stops(L=-0.1, k_b=1e5), r"^L must be in \(0, 1000\] m"),
        (lambda: Stops(L=0.2, k_b=0.0), r"^k_b must be in \(0, 1e\+30\] N/m"),
        (lambda: Stops(L=0.2, k_b=1e5, c_b=-1.0), r"^c_b must be in \[0, 1e\+30\] N s/m"),
        (lambda: Stops(L=0.2, k_b=1e5, beyond_edges="yes"), r"^beyond_edges must be True or False"),
        (lambda: Damper(50.0, 200.0, stops=(0.2, 1e5)), r"^stops must be a rocking.Stops or None"),
        (lambda: Stops(L=0.3, k_b=1e5).check_on(REFERENCE, TUNED), r"^L must be in \(0, B/2\] = \(0, 0.25\] m"),
        (lambda: Stops(L=0.2, k_b=1e20).check_on(REFERENCE, TUNED), r"^omega_b must be in \[1e-3 p, 1e4 p\]"),
        (lambda: Stops(L=0.2, k_b=1e5, c_b=1e6).check_on(REFERENCE, TUNED), r"^zeta_b must be in \[0, 10\]"),
        (lambda: Stops.at_edges(REFERENCE, TUNED, depth=0.25), r"^depth must be in \(0, B/2\)"),
        (
            lambda: public_simulate(
                REFERENCE, {**TUNED.as_params(), "L": 0.3, "k_b": 1e5, "c_b": 0.0}, STILL, model="omd_stops"
            ),
            r"^L must be in \(0, B/2\]",
        ),
        (
            lambda: public_simulate(REFERENCE, dataclasses.replace(TUNED, stops=Stops(0.2, 1e5)), STILL, model="omd"),
            r"has no parameter\(s\) L, c_b, k_b of its own",
        ),
    ],
)
def test_bad_stops_are_refused_with_the_parameter_and_its_range(make, message):
    with pytest.raises(ParameterError, match=message):
        make()


def test_a_guide_beyond_the_edges_needs_the_explicit_override(backend):
    stops = Stops(L=0.3, k_b=1e5, c_b=100.0, beyond_edges=True)
    r = public_simulate(REFERENCE, dataclasses.replace(TUNED, stops=stops), STILL, backend=backend)
    assert r.status == "rest" and r.stop_contacts == 0


@pytest.mark.parametrize("zeta_b", [0.0, 0.2])
def test_a_stops_events_are_located_just_after_their_roots(backend, zeta_b):
    """Rule 6: each closing (delta turns > 0) and release (k_b delta + c_b ddelta falls to <= 0; delta itself without
    damping) is located to 4 eps t, and the next segment starts on the side after it: there the event's function
    is its rate times at most 4 eps t (16 eps t allowed, with the rounding of delta = |x| - L), of that side's
    sign."""
    k_b = 1e4
    e, tau, t1 = flights(k_b, zeta_b)
    r = run(free_mass(k_b, zeta_b, t1 + 2 * tau + 2 * FREE["L"] / (e * V0) + 0.05), backend=backend, record=True)
    h = r.history
    eps = np.finfo(float).eps
    delta = np.abs(h["x"]) - FREE["L"]
    ddelta = np.sign(h["x"]) * h["dx"]
    push = k_b * delta + bumper(k_b, zeta_b)["c_b"] * ddelta
    slack = 16 * eps * h["t"] * np.abs(ddelta) + 2 * eps * FREE["L"]  # in delta
    near = np.abs(delta) <= 1e-9 * FREE["L"]
    closing = near & (ddelta > 0.0) & (delta > 0.0)
    assert closing.sum() == r.stop_contacts == 2
    assert np.all(delta[closing] <= slack[closing])
    if zeta_b == 0.0:
        released = near & (ddelta < 0.0) & (delta <= 0.0)
        assert released.sum() == r.stop_contacts
        assert np.all(-delta[released] <= slack[released])
    else:  # the pad lets go inside its gap, where its force, hence the mass's acceleration, is 0: its rate k_b ddelta
        released = (delta > 1e-9 * FREE["L"]) & (ddelta < 0.0) & (np.abs(push) <= 1e-6 * V0 * math.sqrt(k_b))
        assert released.sum() == r.stop_contacts
        assert np.all((push[released] <= 0.0) & (-push[released] <= k_b * slack[released]))
