"""The NumPy/SciPy back end against facts from outside the code (model.md, section 10).

Every expected value here is computed from the hand-written physics of
``/work/shared/model.md`` (uplift thresholds, Housner's rocking, the linearised
overturning boundary, the damped oscillator in full contact), never from the
generated functions the back end runs on.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rocking.sim.numpy_backend import simulate
from rocking.model.params import Block, Damper
from rocking.sim.problem import CONTACT, STATUS, make_problem
from rocking.model.pulse import OneSinePulse


def slender_block(alpha: float = 0.02, p: float = 2.0) -> Block:
    """Bare symmetric homogeneous block, the linearised theory's subject."""
    return Block.from_nondim(p=p, alpha=alpha)


def no_pulse(block: Block, Omega: float = 1.0) -> OneSinePulse:
    """Zero ground motion (the pulse's length still sets the breakpoint ``t_p``)."""
    return OneSinePulse.from_nondim(block, beta=0.0, Omega=Omega)


def rocking_start(theta: float, dtheta: float, pivot: int) -> dict:
    """Keywords of :func:`simulate` that start the bare block rocking about ``pivot``."""
    return {"y0": [theta, dtheta], "phase0": pivot}


def transitions(history: dict) -> list[tuple[int, int]]:
    """Index pairs ``(j - 1, j)`` of consecutive history rows where the phase changes."""
    phase = history["phase"]
    return [(j - 1, j) for j in range(1, len(phase)) if phase[j] != phase[j - 1]]


def first_uplift(history: dict) -> tuple[float, int]:
    """Time and pivot of the first row that is not full contact."""
    j = int(np.nonzero(history["phase"] != CONTACT)[0][0])
    return float(history["t"][j]), int(history["phase"][j])


# --------------------------------------------------------------------------- #
# Uplift (model.md 10.2)                                                       #
# --------------------------------------------------------------------------- #


def test_uplift_about_A_when_ground_acceleration_reaches_g_B_plus_2e_over_H():
    block = Block.reference()  # e = 0.025 m: the two corners have different thresholds
    pulse = OneSinePulse.from_nondim(block, beta=3.0, Omega=2.0)
    response = simulate(make_problem(block, None, pulse, rtol=1e-8), record=True)
    threshold = block.g * (block.B + 2 * block.e) / block.H
    expected = math.asin(threshold / pulse.a_g) / pulse.omega_g
    t, pivot = first_uplift(response.history)
    assert pivot == 1
    assert abs(t - expected) < 1e-7
    assert response.uplifts >= 1


def test_uplift_about_A_prime_for_a_pulse_starting_negative():
    block = Block.reference()
    pulse = OneSinePulse.from_nondim(block, beta=3.0, Omega=2.0, psi=math.pi)  # ag = -a_g sin(omega_g t)
    response = simulate(make_problem(block, None, pulse, rtol=1e-8), record=True)
    threshold = block.g * (block.B - 2 * block.e) / block.H
    expected = math.asin(threshold / pulse.a_g) / pulse.omega_g
    t, pivot = first_uplift(response.history)
    assert pivot == -1
    assert abs(t - expected) < 1e-7


def test_a_pulse_starting_above_the_threshold_uplifts_at_once():
    block = Block.reference()
    pulse = OneSinePulse.from_nondim(block, beta=3.0, Omega=2.0, psi=math.pi / 2)  # ag(0) = a_g > threshold
    response = simulate(make_problem(block, None, pulse, rtol=1e-8), record=True)
    assert first_uplift(response.history) == (0.0, 1)


def test_no_uplift_below_the_threshold():
    block = Block.reference()
    threshold = block.g * (block.B - 2 * block.e) / block.H  # the lower of the two
    pulse = OneSinePulse(a_g=0.99 * threshold, omega_g=5.0)
    response = simulate(make_problem(block, None, pulse, rtol=1e-8))
    assert (response.uplifts, response.impacts, response.theta_max) == (0, 0, 0.0)
    assert response.status == "rest" and response.t_end == pytest.approx(pulse.t_p, rel=1e-12)


# --------------------------------------------------------------------------- #
# Free rocking of the bare block (model.md 10.1, 10.3; Housner's equation)     #
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.9])
def test_first_impact_of_a_slender_block_released_at_rest(ratio):
    block = slender_block()
    theta0 = ratio * block.alpha
    problem = make_problem(block, None, no_pulse(block), rtol=1e-10, t_max=20.0, max_events=1)
    response = simulate(problem, **rocking_start(theta0, 0.0, +1))
    expected = math.acosh(1 / (1 - theta0 / block.alpha)) / block.p
    # The formula is linearised (sin(alpha - theta) ~ alpha - theta): its relative
    # error is O(alpha^2) = 4e-4, well inside the 1 % the theory is quoted to.
    assert response.status == "max_events" and response.impacts == 1
    assert response.t_end == pytest.approx(expected, rel=block.alpha**2)
    assert response.theta_max == pytest.approx(theta0, rel=1e-12)  # released at rest: the start is the peak


def test_impacts_follow_housners_restitution():
    block = slender_block(alpha=0.2)  # a stockier block: a restitution visibly below 1
    problem = make_problem(block, None, no_pulse(block), rtol=1e-10, t_max=30.0)
    response = simulate(problem, record=True, **rocking_start(0.5 * block.alpha, 0.0, +1))
    h = response.history
    r = 1 - 1.5 * math.sin(block.alpha) ** 2
    impacts = [(i, j) for i, j in transitions(h) if h["phase"][i] != CONTACT]
    assert len(impacts) == response.impacts > 3
    for i, j in impacts:
        assert h["t"][i] == h["t"][j] and h["theta"][i] == h["theta"][j] == 0.0
        if h["phase"][j] == CONTACT:  # the last one: at rest
            assert abs(r * h["dtheta"][i]) < problem.dtheta_rest and h["dtheta"][j] == 0.0
        else:
            assert h["phase"][j] == -h["phase"][i]
            assert h["dtheta"][j] == pytest.approx(r * h["dtheta"][i], rel=1e-12)
    assert response.status == "rest" and h["phase"][-1] == CONTACT


def test_theta_max_is_the_exact_peak_of_a_free_rocking_arc():
    # Housner, energy from theta = 0 to the peak: cos(alpha - theta_max) = cos(alpha) + v^2 / (2 p^2).
    block = slender_block(alpha=0.2)
    v = 0.5 * block.alpha * block.p
    problem = make_problem(block, None, no_pulse(block), rtol=1e-10, t_max=10.0, max_events=1)
    response = simulate(problem, **rocking_start(0.0, v, +1))
    expected = block.alpha - math.acos(math.cos(block.alpha) + v**2 / (2 * block.p**2))
    assert response.impacts == 1
    assert response.theta_max == pytest.approx(expected, rel=1e-8)


def test_critical_angle_and_overturning_of_a_fast_start():
    # Linearised: theta = alpha - alpha cosh(p t) + (v / p) sinh(p t) reaches alpha at tanh(p t) = alpha p / v.
    block = slender_block()
    v = 1.5 * block.alpha * block.p
    problem = make_problem(block, None, no_pulse(block), rtol=1e-10, t_max=20.0)
    response = simulate(problem, **rocking_start(0.0, -v, -1))  # about A', mirrored
    assert response.t_critical == pytest.approx(math.atanh(1 / 1.5) / block.p, rel=block.alpha**2)
    assert response.overturned and response.status == "overturned" and response.impacts == 0
    assert response.t_overturn == response.t_end > response.t_critical
    assert response.theta_max == pytest.approx(math.pi / 2, rel=1e-12)


def test_a_block_set_on_its_corner_without_velocity_stays_on_its_base():
    # Gravity pulls it back at once: the rocking phase cannot start (no impact).
    block = slender_block()
    pulse = no_pulse(block)
    response = simulate(make_problem(block, None, pulse), record=True, **rocking_start(0.0, 0.0, +1))
    assert (response.status, response.impacts, response.uplifts, response.theta_max) == ("rest", 0, 0, 0.0)
    assert response.t_end == pulse.t_p
    phase = response.history["phase"]
    assert phase[0] == 1 and np.all(phase[1:] == CONTACT)


def test_a_grazing_uplift_at_the_pulse_start_changes_nothing_else():
    # ag(0) a hair above (or below) the uplift threshold g B / H: above, the block
    # lifts by almost nothing and falls back at once (the first step of the
    # rocking phase, too long to see that, is retried shorter); the rest of the
    # run (uplift about A' in the negative half, overturning) is the same.
    block = slender_block()
    runs = {}
    for eps in (-1e-9, 1e-9):
        psi = math.pi / 2 + math.acos((1 + eps) / 2)  # beta = 2: ag(0) = (1 + eps) g tan(alpha)
        pulse = OneSinePulse.from_nondim(block, beta=2.0, Omega=1.0, psi=psi)
        runs[eps] = simulate(make_problem(block, None, pulse, rtol=1e-8, max_events=20))
    below, above = runs[-1e-9], runs[1e-9]
    assert (below.status, below.uplifts, below.impacts) == ("overturned", 1, 0)
    assert (above.status, above.uplifts, above.impacts) == ("overturned", 2, 1)
    assert above.t_overturn == pytest.approx(below.t_overturn, rel=1e-6)


# --------------------------------------------------------------------------- #
# Overturning without impact under the one-sine pulse (model.md 10.4)          #
# --------------------------------------------------------------------------- #


def overturns_without_impact(block: Block, beta: float, Omega: float) -> bool:
    """The predicate of the boundary: overturned, and no impact before."""
    pulse = OneSinePulse.from_nondim(block, beta=beta, Omega=Omega)
    # Once the pulse is over the free block's fate is sealed; 20 / p lets runs
    # near the separatrix decide. max_events = 2 stops at the first impact.
    problem = make_problem(block, None, pulse, rtol=1e-8, t_max=pulse.t_p + 20 / block.p, max_events=2)
    response = simulate(problem)
    return response.overturned and response.impacts == 0


@pytest.mark.parametrize("Omega, beta_min", [(1, 1.418), (2, 2.350), (4, 5.239), (6, 9.417)])
def test_smallest_amplitude_that_overturns_without_impact(Omega, beta_min):
    block = slender_block()
    low, high = 0.95 * beta_min, 1.05 * beta_min
    assert not overturns_without_impact(block, low, Omega)
    assert overturns_without_impact(block, high, Omega)
    while high - low > 0.002 * beta_min:
        mid = 0.5 * (low + high)
        if overturns_without_impact(block, mid, Omega):
            high = mid
        else:
            low = mid
    assert 0.5 * (low + high) == pytest.approx(beta_min, rel=1e-2)


# --------------------------------------------------------------------------- #
# The phase machine                                                            #
# --------------------------------------------------------------------------- #


def check_history(response, problem) -> None:
    """Facts every history must satisfy: time order, consistent phases, samples, ends."""
    h = response.history
    assert set(h) == {"t", "phase", "ag", *problem.model.state}
    t, phase, n = h["t"], h["phase"], problem.model.nq
    theta, dtheta = h[problem.model.state[0]], h[problem.model.state[n]]
    assert t[0] == 0.0 and t[-1] == response.t_end
    assert np.all(np.diff(t) >= 0)
    assert np.max(np.diff(t)) <= problem.record_dt * (1 + 1e-9)  # samples every record_dt at least
    assert set(np.unique(phase)) <= {CONTACT, 1, -1}
    contact = phase == CONTACT
    assert np.all(theta[contact] == 0.0) and np.all(dtheta[contact] == 0.0)
    assert np.all(phase[~contact] * theta[~contact] >= -1e-12)
    np.testing.assert_array_equal(h["ag"], problem.ground_acceleration(t))
    assert np.max(np.abs(theta)) <= response.theta_max


def test_moderate_pulse_rocks_and_comes_to_rest():
    block = Block.reference()
    problem = make_problem(block, None, OneSinePulse.from_nondim(block, beta=1.3, Omega=4.0), rtol=1e-8)
    response = simulate(problem, record=True)
    assert response.status == "rest" and response.status in STATUS
    assert not response.overturned and math.isnan(response.t_overturn)
    assert response.uplifts == 1 and response.impacts > 10
    assert problem.t_p < response.t_end < problem.t_max
    assert 0 < response.theta_max < block.alpha and math.isnan(response.t_critical)
    assert response.x_max == 0.0
    check_history(response, problem)
    h = response.history
    pairs = transitions(h)
    assert sum(h["phase"][i] != CONTACT for i, _ in pairs) == response.impacts
    assert sum(h["phase"][i] == CONTACT for i, _ in pairs) == response.uplifts
    assert h["phase"][-1] == CONTACT
    assert np.isclose(h["t"], problem.t_p, rtol=0, atol=1e-12).any()  # the pulse's end is a row


def test_summary_and_status_of_an_overturning_run():
    block = Block.reference()
    problem = make_problem(block, None, OneSinePulse.from_nondim(block, beta=3.0, Omega=2.0), rtol=1e-8)
    response = simulate(problem, record=True)
    assert response.overturned and response.status == "overturned"
    assert response.t_overturn == response.t_end
    assert response.t_critical < response.t_overturn
    assert abs(response.history["theta"][-1]) == pytest.approx(math.pi / 2, rel=1e-12)
    check_history(response, problem)
    summary = response.summary()
    assert summary["status"] == "overturned" and isinstance(summary["t_critical"], float)


def test_max_events_ends_the_run():
    block = Block.reference()
    pulse = OneSinePulse.from_nondim(block, beta=1.3, Omega=4.0)
    problem = make_problem(block, None, pulse, rtol=1e-8, max_events=3)
    response = simulate(problem, record=True)
    assert response.status == "max_events"
    assert response.uplifts + response.impacts == 3
    check_history(response, problem)


def test_t_max_ends_a_run_with_a_lightly_damped_damper():
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.0, h=0.05)
    pulse = OneSinePulse.from_nondim(block, beta=1.3, Omega=4.0)
    problem = dataclasses.replace(make_problem(block, damper, pulse, rtol=1e-8, t_after=3.0), early_rest=False)
    response = simulate(problem, record=True)
    assert response.status == "t_max" and response.t_end == problem.t_max
    assert response.x_max > 0 and response.x_max >= np.max(np.abs(response.history["x"]))
    check_history(response, problem)


# --- the damper in full contact: model.md (C1) and (U1), (U2) in closed form ---


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


def test_the_damper_lifts_the_block_from_rest_and_again_after_it_came_back_to_rest():
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.2, omega_ratio=5.0, zeta=0.02, h=0.05)
    # A short, empty pulse: the run is after the pulse almost at once, where the
    # bare block would be at rest; the moving mass must still be able to lift it.
    pulse = no_pulse(block, Omega=15.0)
    problem = make_problem(block, damper, pulse, rtol=1e-10, t_max=3.0, dtheta_rest=0.05 * block.alpha * block.p)
    v0 = 0.6
    response = simulate(problem, record=True, y0=[0.0, 0.0, 0.0, v0], phase0=CONTACT)
    check_history(response, problem)
    h = response.history

    # First uplift: from the initial state.
    t_up, pivot = first_uplift(h)
    expected_t, expected_pivot = predicted_uplift(block, damper, 0.0, v0, horizon=1.0)
    assert pivot == expected_pivot and abs(t_up - expected_t) < 1e-7

    # The block comes back to rest (an impact into full contact) with the mass
    # moving, and the mass lifts it again: predicted from the state at rest.
    pairs = transitions(h)
    rests = [j for i, j in pairs if h["phase"][i] != CONTACT and h["phase"][j] == CONTACT]
    assert rests and response.uplifts >= 2
    j = rests[0]
    t_rest, x_rest, dx_rest = h["t"][j], h["x"][j], h["dx"][j]
    relift = [(i, k) for i, k in pairs if h["phase"][i] == CONTACT and h["t"][i] > t_rest]
    assert relift
    t_relift, pivot = h["t"][relift[0][1]], h["phase"][relift[0][1]]
    expected_dt, expected_pivot = predicted_uplift(block, damper, x_rest, dx_rest, horizon=1.0)
    assert pivot == expected_pivot
    assert abs(t_relift - t_rest - expected_dt) < 1e-7


def least_uplift_energy(block: Block, damper: Damper) -> float:
    """Least damper energy ``k x^2/2 + m dx^2/2`` on which (U1) or (U2) can hold without ground motion.

    Both read ``u0 + a_x x + a_v dx > 0`` (see :func:`predicted_uplift`); on the
    line ``u = 0`` the least energy is ``u0^2 / (2 (a_x^2 / k + a_v^2 / m))``.
    """
    M, B, e, g = block.M, block.B, block.e, block.g
    m, k, c, eta = damper.m, damper.k_m, damper.c, block.H + damper.h
    a_x, a_v = eta * k + m * g, eta * c
    u0 = [g * (M * (B / 2 + s * e) + m * B / 2) for s in (1, -1)]
    return min(u**2 / (2 * (a_x**2 / k + a_v**2 / m)) for u in u0)


def test_early_rest_settles_the_damper_to_its_next_extremum():
    # docs/simulation.md rule 4: below the least uplift energy after the pulse the
    # block can never lift again; the run ends at the mass's next extremum.
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    pulse = no_pulse(block, Omega=15.0)  # short and empty: full contact after it at once
    problem = make_problem(block, damper, pulse, rtol=1e-10, t_max=pulse.t_p + 6.0)
    v0 = math.sqrt(0.5 * least_uplift_energy(block, damper) * 2 / damper.m)  # half the least uplift energy
    start = {"y0": [0.0, 0.0, 0.0, v0], "phase0": CONTACT}
    early = simulate(problem, record=True, **start)
    check_history(early, problem)
    # x = v0 / wd exp(-zeta w t) sin(wd t) peaks first where tan(wd t) = wd / (zeta w).
    w, zeta = damper.omega_m, damper.zeta
    wd = w * math.sqrt(1 - zeta**2)
    t_peak = math.atan2(wd, zeta * w) / wd
    motion = contact_motion(damper, 0.0, v0)
    assert pulse.t_p < t_peak and abs(motion(pulse.t_p)[0]) < 0.5 * abs(motion(t_peak)[0])
    assert (early.status, early.uplifts, early.theta_max) == ("rest", 0, 0.0)
    assert early.t_end == pytest.approx(t_peak, abs=1e-8)
    assert early.x_max == pytest.approx(abs(motion(t_peak)[0]), rel=1e-8)
    full = simulate(dataclasses.replace(problem, early_rest=False), **start)
    assert full.status == "t_max" and full.uplifts == 0
    assert early.x_max == pytest.approx(full.x_max, rel=1e-9)


def test_early_rest_keeps_verdict_and_maxima_after_rocking():
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.1, h=0.05)
    problem = make_problem(block, damper, OneSinePulse.from_nondim(block, beta=1.3, Omega=4.0), rtol=1e-8, t_after=4.0)
    early = simulate(problem, record=True)
    full = simulate(dataclasses.replace(problem, early_rest=False))
    check_history(early, problem)
    assert early.status == "rest" and early.impacts > 0 and early.t_end < full.t_end
    assert abs(early.history["dx"][-1]) < 1e-9 * damper.omega_m * early.x_max  # at an extremum of x
    assert (early.overturned, early.theta_max, early.impacts, early.uplifts) == (
        full.overturned,
        full.theta_max,
        full.impacts,
        full.uplifts,
    )
    assert early.x_max == pytest.approx(full.x_max, rel=1e-9)


def test_energy_rest_in_full_contact_after_the_pulse():
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.3, h=0.05)
    problem = make_problem(block, damper, OneSinePulse.from_nondim(block, beta=1.3, Omega=4.0), rtol=1e-8)
    problem = dataclasses.replace(problem, early_rest=False)  # energy_rest alone
    response = simulate(problem, record=True)
    assert response.status == "rest" and problem.t_p < response.t_end < problem.t_max
    h = response.history
    check_history(response, problem)
    # The run ends at the instant the damper's energy (model.md section 2 in
    # full contact: spring plus kinetic) falls to energy_rest.
    x, dx = h["x"][-1], h["dx"][-1]
    energy = 0.5 * damper.k_m * x**2 + 0.5 * damper.m * dx**2
    assert h["phase"][-1] == CONTACT
    assert energy == pytest.approx(problem.energy_rest, rel=1e-6)


def test_mirror_symmetry_with_an_eccentric_block_and_a_damper():
    # model.md 10.6: (e, x, theta, ddx_g) -> (-e, -x, -theta, -ddx_g) maps solutions onto solutions.
    results = []
    for sign in (1, -1):
        block = Block(H=2.0, B=0.5, M=1000.0, e=sign * 0.025)
        damper = Damper.from_nondim(block, gamma=0.1, omega_ratio=2.0, zeta=0.05, h=0.05)
        problem = make_problem(block, damper, no_pulse(block), rtol=1e-10, t_max=4.0)
        y0 = sign * np.array([0.0, 0.02, 0.6 * block.alpha * block.p, -0.1])
        results.append(simulate(problem, y0=y0, phase0=sign))
    plus, minus = results
    assert (plus.impacts, plus.uplifts, plus.status) == (minus.impacts, minus.uplifts, minus.status)
    assert plus.impacts > 2
    assert minus.theta_max == pytest.approx(plus.theta_max, rel=1e-6)
    assert minus.x_max == pytest.approx(plus.x_max, rel=1e-6)


def test_invalid_initial_states_are_refused():
    block = slender_block()
    problem = make_problem(block, None, no_pulse(block))
    with pytest.raises(ValueError, match="y0"):
        simulate(problem, y0=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="phase0"):
        simulate(problem, y0=[0.0, 0.0], phase0=2)
    with pytest.raises(ValueError, match="full contact"):
        simulate(problem, y0=[0.01, 0.0], phase0=CONTACT)
    with pytest.raises(ValueError, match="s theta"):
        simulate(problem, y0=[0.01, 0.0], phase0=-1)
