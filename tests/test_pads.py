"""A pad's state follows the mass (docs/simulation.md, rule 6; issue 35): its regime and a Hunt-Crossley pad's
memory are read again from ``x``, ``dx`` after every jump of the velocities, on both back ends.

The yardstick is :mod:`tests.pads_reference`, a plain integration of the documented law (the equations
typed by hand in ``rocking.reference.paper``) that keeps no regime: each evaluation reads the pads' force
from the state. The runs land the block while the mass is inside a pad: the impact turns ``dx`` so that the
Kelvin-Voigt bracket ``k_b delta + c_b ddelta`` is negative (the pad lets go at once), or, Hunt-Crossley,
strikes the pad faster than the contact's approach speed.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import rocking
from rocking.sim.history import quantities
from rocking.sim.problem import make_problem
from rocking.sim.run import run
from tests.pads_reference import applied_force, plain_run

BACKENDS = ("c", "numpy")
FLOOR = rocking.load_model("omd_stops_hc").manifest["stops"][0]["approach_floor"]


def issue_35() -> tuple:
    """The issue's reproducer: one sine, the mass 0.4 mm into the upper pad when the block lands at t = 1.575 s."""
    block = rocking.Block(H=2.3305955442978417, B=0.5236264825219002, M=1000.0, e=-0.009219500585065626)
    stops = rocking.Stops(L=0.12083501974507288, k_b=403358.5227038746, c_b=6351.051272851406)
    damper = rocking.Damper(m=100.0, k_m=448.17613633763847, c=69.60603287455568, h=0.08673335518424147, stops=stops)
    pulse = rocking.OneSinePulse(a_g=3.3410146273091357, omega_g=9.09120139618359, sign=-1)
    return block, damper, pulse, {"t_max": 2 * math.pi / 9.09120139618359 + 10}


def harder_strike() -> tuple:
    """Hunt-Crossley pads (e_b 0.86): the block lands at t = 1.98 s with the mass in the upper pad, which it then
    strikes at 0.165 m/s, faster than the contact's approach speed, 0.156 m/s (found by a random search)."""
    block = rocking.Block(H=2.947142713313032, B=0.4906504253436547, M=1000.0, e=0.007561085485942733)
    stops = rocking.Stops(L=0.08504141468824233, k_b=278115.37572207337, law="hunt-crossley", e_b=0.8563001612409546)
    w_m = 2.3326450183467977
    damper = rocking.Damper(m=100.0, k_m=100.0 * w_m**2, c=10.0 * w_m, h=0.08, stops=stops)
    pulse = rocking.OneSinePulse(a_g=1.9975633207883088, omega_g=10.27651885944, sign=-1)
    return block, damper, pulse, {"t_max": 2.1}


CASES = {"kelvin-voigt": issue_35, "hunt-crossley": harder_strike}


@pytest.fixture(scope="module", params=list(CASES))
def landing(request):
    """A case, its responses on both back ends (recorded) and the plain integration to the same end."""
    block, damper, pulse, settings = CASES[request.param]()
    settings = {**settings, "rtol": 1e-10, "early_verdict": False}
    responses = {b: rocking.simulate(block, damper, pulse, backend=b, record=True, **settings) for b in BACKENDS}
    problem = make_problem(block, damper, pulse, **settings)
    reference = plain_run(problem, responses["c"].t_end, floor=FLOOR)
    return problem, responses, reference


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_landing_inside_a_pad_follows_the_documented_law(landing, backend):
    """Counts and maxima of the run are those of the law integrated plainly, to the integrators' tolerance, and
    the run does land with the mass inside a pad, whose force changes there."""
    problem, responses, reference = landing
    r = responses[backend]
    assert (r.stop_contacts, r.impacts, r.overturned) == (reference.stop_contacts, reference.impacts, False)
    for name in ("theta_max", "x_max"):
        assert getattr(r, name) == pytest.approx(getattr(reference, name), rel=1e-6), name
    assert r.bumper_force_max == pytest.approx(reference.bumper_force_max, rel=1e-6)
    h = r.history
    L = problem.p[problem.model.parameters.index("L")]
    jumps = np.flatnonzero((h["t"][1:] == h["t"][:-1]) & (h["dx"][1:] != h["dx"][:-1])) + 1
    inside = jumps[np.abs(h["x"][jumps]) > L]
    assert inside.size > 0
    forces = quantities(problem.model, problem.p, h, np.arange(len(h["t"])))["F_b"]
    assert np.any(forces[inside] != forces[inside - 1])


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_force_a_run_applies_is_the_pads_and_never_pulls(landing, backend):
    """The pads' force the recorded motion shows (its acceleration less that of the free guide, by central
    differences of the recorded velocities) is the law's at the state, F_b >= 0, within the differences'
    error; bumper_force_max is the peak of F_b over the recorded rows, to the spacing of the samples."""
    problem, responses, _ = landing
    rerun = run(dataclasses.replace(problem, record_dt=2e-4), backend=backend, record=True)
    applied, law = applied_force(problem, rerun.history, FLOOR)
    peak = max(rerun.bumper_force_max, 1.0)
    assert applied.size > 1000 and np.all(law >= 0.0)
    assert np.max(np.abs(applied - law)) < 2e-3 * peak
    forces = quantities(problem.model, problem.p, rerun.history, np.arange(len(rerun.history["t"])))["F_b"]
    assert forces.min() == 0.0 and forces.max() <= rerun.bumper_force_max * (1 + 1e-9)
    assert forces.max() > rerun.bumper_force_max * (1 - 1e-3)
