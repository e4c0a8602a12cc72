"""Flight and landing on the C back end (docs/model.md section 16): facts from outside the code.

A floor that drops faster than gravity throws the block off it; relative to the floor the block then moves on a
parabola, so its flight time, landing speed and jump height have closed forms (Newton's second law with the
floor's acceleration as an inertial force, no more). The runs that fly on a one-sine pulse with a vertical
component are checked for what any flight must show.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rocking
from rocking import Block, Damper, Floor, OneSinePulse, SampledMotion, Vertical
from rocking.model.loading import available_models, load_model

BLOCK = Block.reference()
DAMPER = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
G = BLOCK.g
FLIGHT_MODELS = [name for name in available_models() if load_model(name).manifest.get("flight")]

#: The drop: the floor falls at DROP g for DROP_TIME, then its acceleration returns to 0 linearly over one sample
#: spacing SPACING (a sampled motion is linear between its samples) and stays 0.
DROP, DROP_TIME, SPACING = -1.5, 0.1, 0.05


def _drop_motion() -> SampledMotion:
    n = round(DROP_TIME / SPACING) + 1
    return SampledMotion(np.zeros(n + 1), dt=SPACING, a_v=np.array([DROP * G] * n + [0.0]))


def _drop_closed_form() -> tuple[float, float, float]:
    """``(flight time, landing speed dv, jump height)`` of a block at rest on the dropping floor.

    Relative to the floor the block accelerates by ``-(g + ddy_g)``: ``-(1 + DROP) g`` (up) while the floor falls,
    ``v = -(1 + DROP) g t^2 / 2`` (``g t^2 / 4`` at ``DROP = -1.5``); over the ramp ``ddy_g = DROP g (1 - tau / h)``,
    integrated exactly once for ``dv`` and twice for ``v``; then the parabola under ``g`` down to ``v = 0``.
    """
    up = -(1.0 + DROP) * G
    v1, dv1 = up * DROP_TIME**2 / 2, up * DROP_TIME
    h = SPACING
    # Over the ramp: ddv = -g - DROP g (1 - tau / h); dv and v integrated exactly.
    dv2 = dv1 - G * h - DROP * G * h / 2
    v2 = v1 + dv1 * h - G * h**2 / 2 - DROP * G * (h**2 / 2 - h**2 / 6)
    fall = math.sqrt(dv2**2 + 2 * G * v2)
    return DROP_TIME + h + (dv2 + fall) / G, -fall, v2 + max(dv2, 0.0) ** 2 / (2 * G)


def _landing_row(h: dict) -> int:
    """The history's last row in flight before it is on the floor again."""
    fly = h["fly"]
    return int(np.flatnonzero((fly[:-1] == 1.0) & (fly[1:] == 0.0))[0])


@pytest.mark.parametrize("name", FLIGHT_MODELS)
def test_in_full_contact_on_a_level_ground_the_floor_carries_a_constant_weight(name):
    """Why sim.c's stuck full contact does not watch the lift-off without a vertical component: its N is the
    system's weight whatever the attached bodies and the horizontal ground do (they move horizontally)."""
    model = load_model(name)
    rng = np.random.default_rng(39)
    p = rng.uniform(0.5, 2.0, size=len(model.parameters))
    n = 500
    state = {q: np.zeros(n) for q in model.state}
    for q in model.state:
        if q not in ("theta", "dtheta"):
            state[q] = rng.uniform(-3.0, 3.0, n)
    ag = rng.uniform(-30.0, 30.0, n)
    at_rest = model.call("contact_stick_force", 1.0, [np.zeros(1) for _ in model.state], 0.0, p)[1]
    N = np.broadcast_to(model.call("contact_stick_force", 1.0, [state[q] for q in model.state], ag, p)[1], (n,))
    assert float(at_rest[0]) > 0.0
    np.testing.assert_allclose(N, float(at_rest[0]), rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("damper", [None, DAMPER], ids=["bare", "damper"])
@pytest.mark.parametrize("mu", [math.inf, 0.5])
def test_a_pulse_that_lifts_the_ground_faster_than_gravity_makes_the_block_fly(damper, mu):
    """g + ddy_g < 0 for a while: the block leaves the floor (a flight counted, its time and height > 0) and the
    run goes on to a status of the model, never ``flight``."""
    pulse = OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0, vertical=Vertical(3.0))
    assert min(G + pulse.a_g * 3.0 * np.sin(np.linspace(0.0, 2 * np.pi, 101))) < 0.0
    r = rocking.simulate(BLOCK, damper, pulse, backend="c", floor=Floor(mu))
    assert r.status != "flight"
    assert r.flights >= 1 and r.flight_time > 0.0 and r.jump_max > 0.0
    assert r.flight_time <= r.t_end


def test_a_block_on_a_dropping_floor_flies_and_lands_as_newton_says():
    """The drop's closed form (_drop_closed_form): the flight's time, the landing speed and the jump height, to
    the integrator's tolerance; the bare block lands flat on both corners and rests."""
    t_flight, dv_land, jump = _drop_closed_form()
    r = rocking.simulate(BLOCK, None, _drop_motion(), backend="c", record=True, rtol=1e-12)
    h = r.history
    i = _landing_row(h)
    assert r.status == "rest" and r.flights == 1 and r.uplifts == 0 and r.impacts == 0
    assert r.flight_time == pytest.approx(t_flight, rel=1e-10)
    assert h["t"][i] == pytest.approx(t_flight, rel=1e-10)
    assert h["dv"][i] == pytest.approx(dv_land, rel=1e-10)
    assert r.jump_max == pytest.approx(jump, rel=1e-10)
    # A pure vertical motion: no tilt, a flat landing into full contact, the floor's N the weight again.
    assert np.all(h["theta"] == 0.0) and h["phase"][i + 1] == 0 and h["v"][i + 1] == 0.0
    assert h["N"][i + 1] == pytest.approx(BLOCK.M * G, rel=1e-12)


def test_an_elastic_floor_bounces_the_block_until_its_speed_is_spent():
    """With restitution e_n each landing sends the block up at e_n times its landing speed V: hops of
    2 e_n^k V / g (a parabola under g, the floor at rest), until the speed is at most the bounce threshold
    dtheta_rest B / 2; the bounces go on one flight (one takeoff)."""
    e_n = 0.5
    t_flight, dv_land, _ = _drop_closed_form()
    r = rocking.simulate(BLOCK, None, _drop_motion(), backend="c", floor=Floor(e_n=e_n), rtol=1e-12)
    threshold = r.inputs.settings["dtheta_rest"] * BLOCK.B / 2
    speeds = [-dv_land * e_n**k for k in range(1, 200)]
    bounces = [v for v in speeds if v > threshold]
    assert len(bounces) >= 3 and r.flights == 1 and r.status == "rest"
    assert r.flight_time == pytest.approx(t_flight + sum(2 * v / G for v in bounces), rel=1e-9)


@pytest.mark.parametrize("damper", [None, DAMPER], ids=["bare", "damper"])
@pytest.mark.parametrize("floor", [Floor(), Floor(0.5, e_n=0.6)], ids=["mu=inf", "mu=0.5, e_n=0.6"])
def test_no_corner_passes_below_the_floor_in_flight(damper, floor):
    """A flight ends where a corner reaches the floor: in flight neither corner is below it (to rounding), however
    the flight starts: a takeoff near overturning, a bounce that barely leaves the floor."""
    pulse = OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0, vertical=Vertical(3.0))
    r = rocking.simulate(BLOCK, damper, pulse, backend="c", floor=floor, record=True, record_dt=0.002)
    h = r.history
    flying = h["fly"] == 1.0
    # The other corner is at R(theta) (s B, 0) from the reference corner s (rocking.reference.flight.other_corner).
    other = h["v"] + BLOCK.B * h["phase"] * np.sin(h["theta"])
    assert r.flights >= 1 and np.any(flying)
    assert min(h["v"][flying].min(), other[flying].min()) > -1e-12


@pytest.mark.parametrize("damper", [None, DAMPER], ids=["bare", "damper"])
@pytest.mark.parametrize("mu", [math.inf, 0.5])
@pytest.mark.parametrize("beta, Omega", [(5.0, 4.0), (6.0, 10.0)])
@pytest.mark.parametrize("e_n", [0.0, 0.6])
def test_both_back_ends_fly_alike(damper, mu, beta, Omega, e_n):
    """The agreement of issue 39: C against NumPy at rtol 1e-10 on one-sine pulses with an in-phase vertical
    component of ratio 1 past beta_f = 1 / tan(alpha) (where g + ddy_g < 0), plastic and bouncing landings: the
    same status and counts, the flight's time and height and the maxima to 1e-8 (never bit equality across C and
    NumPy)."""
    pulse = OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega, vertical=Vertical(1.0))
    assert beta * BLOCK.tan_alpha > 1.0
    c, n = (
        rocking.simulate(BLOCK, damper, pulse, backend=backend, floor=Floor(mu, e_n=e_n), rtol=1e-10)
        for backend in ("c", "numpy")
    )
    assert c.flights >= 1
    assert (c.status, c.impacts, c.uplifts, c.flights, c.slides) == (
        n.status,
        n.impacts,
        n.uplifts,
        n.flights,
        n.slides,
    )
    for name in ("flight_time", "jump_max", "theta_max", "x_max", "u_max"):
        assert getattr(c, name) == pytest.approx(getattr(n, name), rel=1e-8, abs=1e-12), name


@pytest.mark.parametrize("damper", [None, DAMPER], ids=["bare", "damper"])
@pytest.mark.parametrize("beta, Omega", [(14.5, 1.5), (12.5, 2.0)])
def test_a_horizontal_pulse_lifts_the_pivot_where_the_exact_normal_force_says(damper, beta, Omega):
    """Without a vertical component sim.c skips the exact N of a rocking step where the system's vertical momentum
    bounds it above 0 (normal_bound: the generated base reaction costs a sixth of a run); the pivot still lifts
    where the NumPy back end, which evaluates N at every step, finds it: the same flight to 1e-8."""
    pulse = OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega)
    c, n = (rocking.simulate(BLOCK, damper, pulse, backend=b, rtol=1e-10) for b in ("c", "numpy"))
    assert c.flights >= 1 and (c.status, c.flights, c.impacts, c.uplifts) == (n.status, n.flights, n.impacts, n.uplifts)
    for name in ("flight_time", "jump_max", "theta_max", "t_end"):
        assert getattr(c, name) == pytest.approx(getattr(n, name), rel=1e-8), name


def test_random_strong_horizontal_pulses_lift_the_pivot_alike_on_both_back_ends():
    """sim.c reads a rocking step's N from two bounds before the generated N (normal_bound, then normal_bound_near
    with sin and cos between their Taylor bounds); neither may hide a takeoff. On strong one-sine pulses (beta 8 to 20,
    both signs, bare and damped) the C back end lifts the pivot, flies and lands where NumPy, which evaluates N
    at every step, does."""
    rng = np.random.default_rng(40)
    flew = 0
    for i in range(24):
        damper = DAMPER if i % 2 else None
        beta, Omega = rng.uniform(8.0, 20.0), rng.uniform(1.0, 4.0)
        pulse = OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega, sign=1 if i % 4 < 2 else -1)
        c, n = (rocking.simulate(BLOCK, damper, pulse, backend=b, rtol=1e-10) for b in ("c", "numpy"))
        case = f"case {i}: beta {beta:.3f}, Omega {Omega:.3f}"
        assert (c.status, c.flights, c.impacts, c.uplifts) == (n.status, n.flights, n.impacts, n.uplifts), case
        assert c.t_end == pytest.approx(n.t_end, rel=1e-7), case
        flew += c.flights > 0
    assert flew >= 6
