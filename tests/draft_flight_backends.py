"""Outside facts of flight held against both back ends (issue 39, item 5; docs/model.md section 16).

A draft, not collected by pytest (its name is not ``test_*``) until both back ends fly: then it becomes
``tests/test_flight_backends.py``. The yardstick is :mod:`tests.flight_reference` (held to facts of its own in
``tests/test_flight_facts.py``) and closed forms; ``python bench/flight_facts.py`` prints every figure.
"""

from __future__ import annotations

import itertools
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

BACKENDS = ("numpy", "c")
#: theta_max, jump_max and flight_time of a back end at rtol 1e-10 against the reference at 1e-11, relative: to be
#: set from the figures of bench/flight_facts.py (the largest difference over the 20 runs, times 10 or so).
TOLERANCE = {"theta_max": 1e-6, "x_max": 1e-6, "jump_max": 1e-6, "flight_time": 1e-6}


@pytest.fixture(scope="module", params=[False, True], ids=["bare", "damper"])
def runs(request):
    """The 20 random vertical pulses past the flight threshold (with random dampers: 20 others), run by the
    reference."""
    return [(case, reference(case)) for case in random_cases(20, 39 + request.param, request.param)]


@pytest.mark.parametrize("backend", BACKENDS)
def test_random_vertical_pulses_are_the_reference(runs, backend):
    """(a) Each of the 20 runs: the same status and counts of flights and impacts, theta_max, x_max, jump_max and
    flight_time within :data:`TOLERANCE`."""
    for case, run in runs:
        got = project(case, backend)
        diff = differences(run, got)
        assert diff["same"], (case, (got.status, got.flights, got.impacts), (run.status, run.flights, run.impacts))
        for name, tol in TOLERANCE.items():
            assert diff[name] <= tol, (case, name, diff[name])
    assert sum(run.flights for _, run in runs) >= 20


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
    assert (got.status, got.flights, got.impacts, got.theta_max) == ("rest", 1, 0, 0.0)
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
    t0, t1, dv, _ = ref.free_flight(block.g, DROP_DT, a_v)
    bounces = list(itertools.takewhile(lambda k: e_n**k * abs(dv) > rest * block.B / 2, itertools.count(1)))
    motion = rocking.SampledMotion(np.zeros_like(a_v), dt=DROP_DT, a_v=a_v)
    got = rocking.simulate(
        block, None, motion, backend=backend, rtol=1e-10, check="none", floor=rocking.Floor(e_n=e_n), dtheta_rest=rest
    )
    assert got.status == "rest"
    assert got.flight_time == pytest.approx(t1 - t0 + sum(2 * e_n**k * abs(dv) / block.g for k in bounces), rel=1e-8)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_fast_rocking_block_takes_off(backend):
    """No vertical motion: the reference block rocking fast under a horizontal one-sine (beta 2.07, Omega 3) lifts
    its pivot where the rocking phase's N reaches 0 (docs/model.md section 16), flies once and overturns, as the
    reference does."""
    case = Case(2.07, 3.0, 1, 0.0, 0.0, math.inf, math.inf)
    run, got = reference(case), project(case, backend)
    diff = differences(run, got)
    assert diff["same"] and run.flights == 1
    assert max(diff["jump_max"], diff["flight_time"]) < TOLERANCE["jump_max"]


@pytest.mark.parametrize("backend", BACKENDS)
def test_energy_never_rises_at_a_landing(runs, backend):
    """(c) At every landing of the 20 runs' histories (e_n = 0), the energy computed from the history's own columns
    after is at most the one before (to 1e-12 of it)."""
    count = 0
    for case, _ in runs:
        got = project(case, backend, record=True)
        for before, after in landings(got.history):
            e0, e1 = (history_energy(case.block, case.the_damper, got.history, i) for i in (before, after))
            assert e1 <= e0 * (1 + 1e-12), (case, got.history["t"][before], e0, e1)
            count += 1
    assert count >= 20
