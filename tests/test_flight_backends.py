"""Outside facts of flight held against the back ends (issue 39, item 5; docs/model.md section 16).

The yardstick is :mod:`tests.flight_reference`, Newton and Euler typed by hand (held to facts of its own in
``tests/test_flight_facts.py``), and closed forms; ``python bench/flight_facts.py`` prints every figure, over 20 runs
with dampers too. Both sides take off by the back ends' rule on a stuck corner of the paper's floor (docs/simulation.md,
"Flight": only where the free flight lifts the corner); the bench says how many runs the spec's rule (``N`` alone)
would change.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

import rocking
from tests import flight_reference as ref
from tests.flight_cases import (
    DROP_DT,
    Case,
    differences,
    drop_samples,
    history_energy,
    landings,
    project,
    random_cases,
    reference,
)

#: The back ends that follow flight, each held to the reference run by run.
BACKENDS = ("numpy", "c")
#: theta_max, x_max, jump_max and flight_time of a back end at rtol 1e-10 against the reference at 1e-11, relative:
#: the largest measured over 20 + 20 runs is 9.5e-9 (bench/flight_facts.py), ten times it rounded up.
TOLERANCE = 1e-7


@functools.cache
def responses(backend: str) -> list:
    """The 20 random vertical pulses past the flight threshold of the bare block and 10 with random dampers, run by
    the reference and by ``backend`` (recorded): ``(case, run, response)``."""
    cases = random_cases() + random_cases(10, 40, damper=True)
    return [(case, reference(case), project(case, backend, record=True)) for case in cases]


@pytest.mark.parametrize("backend", BACKENDS)
def test_random_vertical_pulses_are_the_reference(backend):
    """(a) Each run: the same status and counts of flights, impacts, uplifts and slides; theta_max, x_max, jump_max
    and flight_time within :data:`TOLERANCE`; at least 20 flights of the bare block."""
    for case, run, got in responses(backend):
        diff = differences(run, got)
        assert diff["same"], (case, got.summary(), run)
        assert max(diff[name] for name in ("theta_max", "x_max", "jump_max", "flight_time")) < TOLERANCE, (case, diff)
    assert sum(run.flights for case, run, _ in responses(backend) if case.damper is None) >= 20


#: Damped runs of ``random_cases(20, 40, damper=True)`` whose highest point is the raised corner's at a takeoff:
#: the block leaves the floor while rocking back, so the corner ``-s`` only falls in flight (issue 39: C missed it).
TAKEOFF_PEAKS = (8, 11, 16)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_highest_point_at_a_takeoff(backend):
    """The runs of :data:`TAKEOFF_PEAKS`: jump_max is the reference's within :data:`TOLERANCE`, and it is the height
    of the corner ``-s``, ``B s sin(theta) + v``, in the first row of a flight of the back end's own history."""
    cases = random_cases(20, 40, damper=True)
    for case in (cases[i] for i in TAKEOFF_PEAKS):
        run, got = reference(case), project(case, backend, record=True)
        assert differences(run, got)["jump_max"] < TOLERANCE, (case, got.jump_max, run.jump_max)
        h = got.history
        fly = np.asarray(h["fly"])
        starts = np.flatnonzero(fly[1:] > fly[:-1]) + 1
        raised = case.block.B * h["phase"][starts] * np.sin(h["theta"][starts]) + h["v"][starts]
        assert np.max(raised) == pytest.approx(got.jump_max, rel=1e-12), (case, raised)


@pytest.mark.parametrize("backend", BACKENDS)
def test_energy_never_rises_at_a_landing(backend):
    """(c) At every landing of the runs' histories (e_n = 0), the energy computed from the history's own columns
    (:func:`tests.flight_cases.history_energy`) after is below the one before."""
    count = 0
    for case, _, got in responses(backend):
        for before, after in landings(got.history):
            e0, e1 = (history_energy(case.block, case.the_damper, got.history, i) for i in (before, after))
            assert e1 < e0, (case, got.history["t"][before], e0, e1)
            count += 1
    assert count >= 20


@pytest.mark.parametrize("mu", [math.inf, 0.5])
@pytest.mark.parametrize("backend", BACKENDS)
def test_floor_drop(backend, mu):
    """(b) The floor drops at -1.5 g for 0.1 s, then stops: the time of flight, the landing speed and the peak
    height of the closed form (the ramps between samples counted, :func:`tests.flight_reference.free_flight`), one
    flight, flat, and rest."""
    block = rocking.Block.reference()
    a_v = drop_samples(block.g)
    t0, t1, dv, peak = ref.free_flight(block.g, DROP_DT, a_v)
    motion = rocking.SampledMotion(np.zeros_like(a_v), dt=DROP_DT, a_v=a_v)
    floor = None if math.isinf(mu) else rocking.Floor(mu)
    got = rocking.simulate(block, None, motion, backend=backend, rtol=1e-10, check="none", record=True, floor=floor)
    assert (got.status, got.flights, got.impacts) == ("rest", 1, 0) and got.theta_max < 1e-12
    assert got.flight_time == pytest.approx(t1 - t0, rel=1e-8)
    assert got.jump_max == pytest.approx(peak, rel=1e-8)
    [(i, _)] = landings(got.history)
    assert got.history["t"][i] == pytest.approx(t1, rel=1e-8)
    assert got.history["dv"][i] == pytest.approx(dv, rel=1e-8)


@pytest.mark.parametrize("e_n", [0.5, 0.8])
@pytest.mark.parametrize("backend", BACKENDS)
def test_floor_drop_bounces(backend, e_n):
    """(b) with restitution: the base bounces at e_n^k times the first landing's speed until it is below
    dtheta_rest B / 2; the total flight time is the geometric series' (the reference's to 1e-12,
    tests/test_flight_facts.py)."""
    block = rocking.Block.reference()
    a_v, rest = drop_samples(block.g), 1e-3 * block.alpha * block.p
    _, total = ref.bounce_series(block.g, DROP_DT, a_v, e_n, rest * block.B / 2)
    motion = rocking.SampledMotion(np.zeros_like(a_v), dt=DROP_DT, a_v=a_v)
    got = rocking.simulate(
        block, None, motion, backend=backend, rtol=1e-10, check="none", floor=rocking.Floor(e_n=e_n), dtheta_rest=rest
    )
    assert got.status == "rest"
    assert got.flight_time == pytest.approx(total, rel=1e-8)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_fast_rocking_block_grazes(backend):
    """No vertical motion: the reference block rocking fast to overturning under a horizontal one-sine (beta 6,
    Omega 2, to the left) reaches N = 0 on its stuck pivot, and then the free flight's corner acceleration, but the
    free flight would drive the corner into the floor (1 us along it, -9.5e-6 m/s^2): it grazes, does not fly, and
    overturns on the floor with the floor pulling on it (down to -0.68 of the weight), at the reference's instant."""
    case = Case(6.0, 2.0, -1, 0.0, 0.0, math.inf, math.inf)
    run, got = reference(case), project(case, backend)
    assert differences(run, got)["same"] and (run.flights, run.status) == (0, "overturned")
    assert run.least_N < -0.6 * case.block.M * case.block.g
    assert got.t_end == pytest.approx(run.t_end, rel=TOLERANCE)
