"""Outside facts of flight and landing (issue 39, item 5; docs/model.md section 16): the yardstick itself.

:mod:`tests.flight_reference` follows the block, bare or with its damper, through contact, rocking, flight, impacts
and landings with Newton and Euler typed by hand, independent of ``derive/``, ``generated/`` and ``rocking.sim``.
Here it is held to facts from outside the code before the back ends are held to it (``tests/test_flight_backends.py``):
the project's runs where nothing flies, Newton and Euler typed a second time (``rocking.reference.flight``), the
floor's drop in closed form and its bounces, Housner's restitution at a level landing on a corner, and the energy at
every landing of random runs. ``python bench/flight_facts.py`` prints every figure.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rocking
from tests import flight_reference as ref
from tests.flight_cases import Case, body, differences, drop_samples, project, random_cases, reference, typed_twice

TUNED = (("gamma", 0.1), ("omega_ratio", 1.0), ("zeta", 0.05), ("h", 0.05))


@pytest.mark.parametrize(
    ("beta", "Omega", "sign", "mu", "damper"),
    [
        (3.3, 7.0, -1, math.inf, None),
        (2.0, 6.0, 1, 0.5, None),
        (2.6, 5.0, 1, 0.96, None),
        (2.64, 4.0, -1, 0.82, None),
        (3.0, 5.0, 1, math.inf, TUNED),
        (2.5, 6.0, -1, 0.6, TUNED),
    ],
)
def test_reference_is_the_project_where_nothing_flies(beta, Omega, sign, mu, damper):
    """A horizontal pulse that never lifts the block off the floor: the reference and the NumPy back end (rtol
    1e-10, no flight yet) agree on the status and every count, and on theta_max and x_max to 1e-7 relative (measured:
    at most 3.3e-9 on 12 random pulses of the bare block, 8.1e-8 with random dampers, bench/flight_facts.py)."""
    case = Case(beta, Omega, sign, 0.0, 0.0, mu, mu, damper)
    run, got = reference(case), project(case, "numpy")
    diff = differences(run, got)
    assert diff["same"]
    assert max(diff["theta_max"], diff["x_max"]) < 1e-7
    assert run.flights == 0 and (run.impacts > 0 or run.slides > 0)


@pytest.mark.parametrize("s", [1, -1])
def test_impulses_are_newton_euler_typed_twice(s):
    """The reference's impulses at a corner (stick, slide, any e_n) and on both corners at theta = 0 are
    ``rocking.reference.flight``'s block_landing and block_flat_landing, typed apart: velocities and impulses per
    unit mass to 1e-12 m/s on random flying states (measured 2.8e-14, bench/flight_facts.py)."""
    assert typed_twice(100, 5, s) < 1e-12


@pytest.mark.parametrize("s", [1, -1])
def test_damper_is_newton_euler_typed_twice(s):
    """With a damper: the reference's accelerations in flight and its impulses at a corner and on both corners are
    ``rocking.reference.flight``'s omd_flight_accel, omd_landing and omd_flat_landing, typed apart (the mass and its
    guide's normal force and impulse): to 1e-11 in m/s^2, rad/s^2, m/s and impulses per unit mass (measured 3.2e-14)."""
    assert typed_twice(50, 7, s, damper=True) < 1e-11


def test_floor_drop_reference():
    """The floor drops at -1.5 g for 0.1 s (sampled every 0.01 s, ramps of one sample): the reference's flight time,
    landing speed and peak height are the closed form's (:func:`tests.flight_reference.free_flight`) to 1e-12;
    without the ramps the closed form is ``0.1 (1 + (1 + sqrt 3) / 2)`` s and ``sqrt(3) g / 20`` m/s."""
    blk = rocking.Block.reference()
    a_v = drop_samples(blk.g)
    t0, t1, dv, peak = ref.free_flight(blk.g, 0.01, a_v)
    for mu in (math.inf, 0.5):
        run = ref.simulate(body(blk), ref.Ground.sampled(0.01, 0 * a_v, a_v), ref.Floor(mu, mu), 1.0, 1e-3)
        assert (run.status, run.flights, len(run.landings)) == ("rest", 1, 1)
        assert run.flight_time == pytest.approx(t1 - t0, rel=1e-12)
        assert run.landings[0][6] == pytest.approx(dv, rel=1e-12)
        assert run.jump_max == pytest.approx(peak, rel=1e-12)
    fine = 1e-4
    t0, t1, dv, _ = ref.free_flight(blk.g, fine, np.r_[np.full(round(0.1 / fine) + 1, -1.5 * blk.g), 0.0])
    assert t1 - t0 == pytest.approx(0.1 * (1 + (1 + math.sqrt(3)) / 2), abs=2 * fine)
    assert -dv == pytest.approx(math.sqrt(3) * blk.g / 20, rel=10 * fine)


@pytest.mark.parametrize("e_n", [0.5, 0.8])
def test_floor_drop_bounces(e_n):
    """The same drop landing with a normal restitution e_n: the base bounces at e_n^k times the first landing's
    speed, each flight 2 e_n^k |dv| / g long, until the speed is below dtheta_rest B / 2 (docs/model.md section 16,
    step 4); the total flight time of that series to 1e-12, one takeoff, rest."""
    blk = rocking.Block.reference()
    a_v, rest = drop_samples(blk.g), 1e-3 * blk.alpha * blk.p
    bounces, total = ref.bounce_series(blk.g, 0.01, a_v, e_n, rest * blk.B / 2)
    run = ref.simulate(body(blk), ref.Ground.sampled(0.01, 0 * a_v, a_v), ref.Floor(e_n=e_n), 3.0, rest)
    assert (run.status, run.flights, len(run.landings)) == ("rest", 1, bounces + 1)
    assert run.flight_time == pytest.approx(total, rel=1e-12)


@pytest.mark.parametrize("e", [0.0, 0.025])
@pytest.mark.parametrize("s", [1, -1])
def test_housner_at_a_level_landing(s, e):
    """e_n = 0: the corner -s lands at theta = 0 while the corner s is at rest on the floor. Both corners together
    would pull at s, so -s lands alone: Housner's ``dtheta+ / dtheta- = 1 - 3/2 sin^2 alpha`` for the symmetric
    block (docs/model.md 10.1), section 6's (I1) with m = 0 for an eccentric one, to 1e-13; a mu = 0.5 floor
    holds it (the same)."""
    blk = rocking.Block(H=2.0, B=0.5, M=1000.0, e=e)
    omega = -s * 0.7  # swinging back to theta = 0 about s
    z = body(blk).centroid(s, 0.0, 0.0, 0.0, omega)
    d_s, d_o = s * blk.B / 2 + e, -s * blk.B / 2 + e
    I_o = blk.I_G + blk.M * (d_o**2 + blk.H**2 / 4)
    ratio = (blk.I_G + blk.M * (blk.H**2 / 4 + d_s * d_o)) / I_o
    if e == 0.0:
        assert ratio == pytest.approx(1 - 1.5 * math.sin(blk.alpha) ** 2, rel=1e-15)
    for mu in (math.inf, 0.5):
        zp, law, k = ref.flat_law(body(blk), ref.Floor(mu, mu), z, 0.0)
        assert (law, k) == (0, -s)
        assert zp[5] / omega == pytest.approx(ratio, rel=1e-13)


@pytest.mark.parametrize(("n", "seed", "damper"), [(12, 39, False), (8, 40, True)])
def test_energy_never_rises_at_a_plastic_landing(n, seed, damper):
    """Every landing of random vertical pulses past the flight threshold (the first 12 of the 20 of
    ``tests/test_flight_backends.py``; 8 with random dampers), stuck and sliding both ways, e_n = 0, takes energy,
    none adds any (bench/flight_facts.py gives the figures over 20 and 20); no corner goes below the floor in flight
    (to 1 nm)."""
    runs = [reference(case) for case in random_cases(n, seed, damper)]
    assert min(run.lowest for run in runs) > -1e-9  # no corner below the floor in flight
    landings = [landing for run in runs for landing in run.landings]
    assert len(landings) >= 10 and {law for _, law, *_ in landings} == {0, 1, -1}
    assert max(after - before for _, _, before, after, *_ in landings) < 0.0


@pytest.mark.parametrize("damper", [False, True])
def test_tangential_landing_where_sticking_would_pull(damper):
    """mu_s = inf: where the sticking impulse of a corner landing would pull (P_n < 0), the floor's impulse is the
    tangential one alone (docs/model.md section 16): the slip stops, the corner leaves the floor (dv+ > 0), and the
    energy falls by du-^2 / (2 W_tt), W_tt the corner's slip speed per unit tangential impulse; where sticking pushes
    (P_n > 0) the tangential impulse alone would drive the corner into the floor (the same inequality)."""
    rng = np.random.default_rng(11)
    blk = rocking.Block.reference()
    tuned = rocking.Damper.from_nondim(blk, gamma=0.1, omega_ratio=1.0, zeta=0.05, h=0.05) if damper else None
    b, pulled = body(blk, tuned), 0
    for _ in range(400):
        s = int(rng.choice([-1, 1]))
        theta, omega = s * rng.uniform(0.05, 1.4), rng.uniform(-6, 6)
        z = b.centroid(s, theta, 0.0, rng.uniform(-3, 3), omega, 0.0, rng.uniform(-1, -0.01), x=0.1 * damper)
        du, before = b.corner(s, z)[1][0], b.energy(z)
        _, _, P_n = ref.impulse(b, s, z, 0.0, None)
        zt, P_t, P_0 = ref.impulse(b, s, z, 0.0, None, normal=False)
        du_t, dv_t = b.corner(s, zt)[1]
        assert P_0 == 0.0 and abs(du_t) < 1e-12 * (1 + abs(du))
        assert (dv_t > 0) == (P_n < 0)
        if P_n < 0:
            pulled += 1
            law_z, law = ref.corner_law(b, ref.Floor(), s, z, 0.0)
            assert law == 0 and np.array_equal(law_z, zt)
            assert before - b.energy(zt) == pytest.approx(du**2 / (2 * (-du / P_t)), rel=1e-9)
    assert pulled >= 10
