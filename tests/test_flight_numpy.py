"""Flight and landing in the NumPy back end (docs/model.md section 16, docs/simulation.md "Phases").

The closed forms: a flat drop on a floor that falls away at a constant rate (piecewise linear samples, integrated
exactly here), the centroid's parabola (F0) after the motion, Newton's restitution of a flat bounce; the laws of
``rocking.reference.flight`` (``landing_law``) for a jam.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np
import pytest

import rocking
from rocking import Block, Floor, OneSinePulse, SampledMotion, Vertical
from rocking.model.loading import load_model
from rocking.reference import flight as ref
from rocking.sim import numpy_backend as nb
from rocking.sim.problem import make_problem

#: A stocky block (tan(alpha) = 1): a vertical one-sine in phase pulls the floor away past g once beta > 1.
STOCKY = Block(1.0, 1.0, 1000.0)
REFERENCE = Block.reference()
DAMPER = rocking.Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)


def _thrown(block: Block, beta: float, ratio: float, **options) -> rocking.Response:
    pulse = OneSinePulse.from_nondim(block, Omega=2 * math.pi / (0.5 * block.p), beta=beta, vertical=Vertical(ratio))
    return rocking.simulate(block, options.pop("damper", None), pulse, backend="numpy", record=True, **options)


def _landings(history: dict) -> np.ndarray:
    """Rows just after a landing: flight before, the floor after or a bounce (two rows at one instant)."""
    fly, t, dv = history["fly"], history["t"], history["dv"]
    ends = (fly[:-1] == 1.0) & (t[1:] == t[:-1]) & ((fly[1:] == 0.0) | ((dv[:-1] < 0.0) & (dv[1:] > 0.0)))
    return np.flatnonzero(ends) + 1


@pytest.mark.parametrize(
    ("block", "beta", "ratio", "options"),
    [
        (STOCKY, 3.0, 1.0, {"mu": 0.3}),
        (STOCKY, 0.5, 3.0, {}),
        (REFERENCE, 6.0, 1.0, {"mu": 0.5, "damper": DAMPER}),
    ],
    ids=["stocky-mu0.3", "stocky-mu-inf", "omd-mu0.5"],
)
def test_a_block_thrown_by_a_vertical_pulse_takes_off_flies_and_lands(block, beta, ratio, options):
    """Past beta_f the floor falls away faster than gravity: the block flies and gets an answer, never flight."""
    r = _thrown(block, beta, ratio, **options)
    assert r.status in ("rest", "bounded", "overturned") and r.status != "flight"
    assert r.flights >= 1 and r.flight_time > 0.0 and r.jump_max > 0.0
    kinds = list(r.events()["kind"])
    assert "takeoff" in kinds and ("landing" in kinds or r.overturned)
    fly = r.history["fly"] == 1.0
    # In flight the floor holds nothing, and no base corner is below it (v and the other corner's height).
    assert np.all(r.history["N"][fly] == 0.0) and np.all(r.history["F"][fly] == 0.0)
    other = r.history["v"] + r.history["phase"] * block.B * np.sin(r.history["theta"])
    assert np.min(r.history["v"][fly]) > -1e-12 and np.min(other[fly]) > -1e-12
    # jump_max: the highest corner's peak in flight, at least every recorded height.
    assert r.jump_max >= np.max(np.maximum(r.history["v"], other)[fly])


def _drop(e_n: float = 0.0) -> tuple[rocking.Response, dict]:
    """The bare reference block on a floor that falls at 1.5 g for 0.09 s, back to 0 over the next sample."""
    dt, g = 0.01, REFERENCE.g
    a_v = np.zeros(60)
    a_v[:10] = -1.5 * g
    motion = SampledMotion(np.zeros_like(a_v), dt=dt, a_v=a_v)
    r = rocking.simulate(REFERENCE, None, motion, backend="numpy", record=True, floor=Floor(e_n=e_n), rtol=1e-12)
    return r, {"dt": dt, "g": g, "a_v": a_v}


def test_a_pure_vertical_drop_lands_flat_after_the_time_of_flight_in_closed_form():
    """No horizontal motion: the block leaves at t = 0 (g + ddy_g < 0 there), flies without turning and lands flat,
    at rest; its time of flight and landing speed from the relative acceleration -(g + ddy_g), piecewise linear
    (samples), integrated exactly, then the fall under g alone."""
    r, m = _drop()
    dt, g, a_v = m["dt"], m["g"], m["a_v"]
    v = dv = 0.0
    pieces = int(np.count_nonzero(a_v))  # the floor's fall ends at the sample after the last nonzero one
    for k in range(pieces):
        a0, a1 = -(g + a_v[k]), -(g + a_v[k + 1])
        v, dv = v + dv * dt + dt**2 * (2.0 * a0 + a1) / 6.0, dv + dt * (a0 + a1) / 2.0
    t1 = pieces * dt
    fall = (dv + math.sqrt(dv**2 + 2.0 * g * v)) / g  # then under g alone, before the motion's end
    assert r.status == "rest" and r.uplifts == 0 and r.flights == 1 and r.impacts == 0
    assert r.theta_max == 0.0 and np.all(r.history["theta"] == 0.0)
    assert r.flight_time == pytest.approx(t1 + fall, rel=1e-9)
    assert r.jump_max == pytest.approx(v + dv**2 / (2.0 * g), rel=1e-9)
    landed = _landings(r.history)
    assert len(landed) == 1 and r.history["phase"][landed[0]] == 0  # flat: full contact
    assert r.history["dv"][landed[0] - 1] == pytest.approx(-math.sqrt(dv**2 + 2.0 * g * v), rel=1e-9)
    assert list(r.events()["kind"])[:2] == ["takeoff", "landing"]


def test_a_bouncing_drop_loses_speed_by_e_n_and_ends_at_the_bounce_speed():
    """e_n > 0: each flat landing sends the block up at e_n times its landing speed (Newton), the next landing
    comes back at that speed (a parabola after the motion); below the bounce speed, a corner of the block turning
    at dtheta_rest, it stays down: a finite number of bounces, then rest (no Zeno)."""
    e_n = 0.5
    r, _ = _drop(e_n)
    landed = _landings(r.history)
    dv = r.history["dv"]
    before, after = dv[landed - 1], dv[landed]
    assert r.status == "rest" and len(landed) >= 3
    assert np.allclose(after[:-1], -e_n * before[:-1], rtol=1e-12, atol=0.0)
    assert np.allclose(-before[1:], after[:-1], rtol=1e-8)  # ballistic between bounces (rtol 1e-12)
    speed = r.inputs.settings["dtheta_rest"] * REFERENCE.B / 2
    assert after[-1] == 0.0 and -e_n * before[-1] <= speed < -e_n * before[-2]
    assert r.flights == 1  # one takeoff: the bounces are landings of the same flight


def test_the_centroid_flies_on_its_parabola():
    """(F0) after the motion: nothing but gravity acts on the flying bare block, which tumbles; its centroid,
    from the recorded (theta, u, v, s), is a line in x and a parabola of curvature -g in y, to 1e-10 m."""
    r = _thrown(STOCKY, 1.0, 2.0, rtol=1e-12)
    h, t_p = r.history, r.inputs.settings["t_p"]
    rows = (h["fly"] == 1.0) & (h["t"] > t_p)
    t = h["t"][rows]
    assert t.size > 20 and np.ptp(h["theta"][rows]) > 0.01  # a quarter of a second turning by 0.04 rad
    X, Y = ref.centroid(h["theta"][rows], h["u"][rows], h["v"][rows], h["phase"][rows], STOCKY.B, STOCKY.H, 0.0)
    for values in (X, Y + STOCKY.g * t**2 / 2):
        line = np.polyval(np.polyfit(t - t[0], values, 1), t - t[0])
        assert np.max(np.abs(values - line)) < 1e-10


@pytest.mark.parametrize("options", [{"mu": 0.3}, {}, {"mu": 0.5, "damper": DAMPER}])
def test_a_plastic_landing_never_adds_energy(options):
    """The energy in the ground frame (generated flight_energy, with the corner's height and rates) just before
    and just after each landing: never more after (docs/model.md section 16)."""
    block = REFERENCE if "damper" in options else STOCKY
    r = _thrown(block, 6.0 if "damper" in options else (3.0 if options else 0.5), 1.0 if options else 3.0, **options)
    model, p = r.inputs.model, [float(x) for x in r.inputs.p]
    h = r.history
    landed = _landings(h)
    assert len(landed) >= 1

    def energy(i: int) -> float:
        s = 1.0 if h["phase"][i] == 0 else float(h["phase"][i])
        state = [h[k][i] for k in model.state]
        return float(model.functions.flight_energy(s, *state, 0.0, 0.0, *p, h["v"][i], h["du"][i], h["dv"][i]))

    for i in landed:
        assert energy(i) <= energy(i - 1) + 1e-12 * abs(energy(i - 1))


def _jam_state():
    """A plastic landing of the bare block that no law holds (``landing_law`` of rocking.reference.flight), found
    on random states as bench/flight_landing.py counts them: its block, floor and flying state."""
    f = load_model("block").functions
    rng = np.random.default_rng(3)
    while True:
        B = rng.uniform(0.3, 1.5)
        H, M = B * rng.uniform(1.0, 6.0), rng.uniform(100.0, 2000.0)
        s, theta, dtheta = 1.0, rng.uniform(0.05, 1.2), rng.uniform(-3.0, 3.0)
        du, dv, mu_s = rng.normal(), -abs(rng.normal()), rng.uniform(0.5, 1.0)
        block = Block(H, B, M)
        args = (s, theta, dtheta, 0.0, 0.0, M, block.I_G, B, H, 0.0, block.g, du, dv, 0.0)
        _, law = ref.landing_law(partial(f.landing_stick, *args), partial(f.landing_slide, *args), du, mu_s, mu_s)
        if law == "":
            return block, Floor(mu_s, mu_s), (theta, dtheta, du, dv)


def test_a_landing_that_no_law_holds_ends_the_run_jammed():
    """Painleve's jam: the phase machine, started in flight just above the floor, lands there and ends jammed."""
    block, floor, (theta, dtheta, du, dv) = _jam_state()
    pulse = OneSinePulse(a_g=1e-3, omega_g=10.0)
    problem = make_problem(block, None, pulse, floor=floor)
    system = nb._System(problem)
    run = nb._Run(problem, system, t=1.0, y=np.array([theta, dtheta]), phase=1, history=None, safe_energy=None)
    run.flying, run.u, run.du, run.v, run.dv = True, 0.0, du, 1e-9, dv
    assert nb.phase_machine(run) == "jammed"
    assert run.flying and run.v == 0.0 and run.y[0] == pytest.approx(theta, abs=1e-6)


@pytest.mark.parametrize(
    ("model", "params"),
    [
        ("pendulum", dict(m=50.0, l=0.5, x_p=0.0, y_p=REFERENCE.H + 0.55, k_phi=0.0, c_phi=20.0)),
        ("omd2", dict(m1=40.0, h=0.05, k1=300.0, c1=11.0, m2=30.0, k2=500.0, c2=9.0)),
    ],
)
def test_models_without_flight_functions_still_end_in_flight(model, params):
    pulse = OneSinePulse.from_nondim(REFERENCE, beta=3.0, Omega=4.0, vertical=Vertical(3.0))
    r = rocking.simulate(REFERENCE, params, pulse, model=model, backend="numpy", record=True)
    assert r.status == "flight" and r.flights == 0 and "fly" not in r.history


@pytest.mark.parametrize("model", ["block", "omd", "omd_stops", "omd_stops_hc"])
def test_without_a_vertical_component_full_contact_bears_the_weight(model):
    """Why full contact does not watch its lift-off without a vertical component: its N, stuck or sliding, is the
    system's weight whatever the ground's acceleration and the damper's state (the damper moves horizontally in
    the block frame, its bumpers act along it)."""
    m = load_model(model)
    rng = np.random.default_rng(0)
    names = m.parameters
    from rocking.reference.verify import random_cases

    cases = random_cases(rng, 50, 1, damper=m.nq > 1, stops="stops" in model, hunt_crossley=model.endswith("hc"))
    params = [cases[k] for k in names]
    masses = cases["M"] + (cases["m"] if "m" in names else 0.0)
    state = [np.zeros(50) if k in ("theta", "dtheta") else cases[k] for k in m.state]
    regime = [np.zeros(50)] * int(m.manifest["functions"]["stop_gaps"]["outputs"])
    memory = [np.full(50, 0.1)] * len(m.manifest.get("stops", []) if model.endswith("hc") else ())
    stop_on = regime + memory if regime else None
    weight = masses * cases["g"]
    F, N = m.functions.contact_stick_force(1.0, *state, cases["ag"], 0.0, *params, stop_on=stop_on)
    assert np.allclose(N, weight, rtol=1e-12, atol=0.0)
    for mu in (0.3, -0.3):
        N = m.functions.contact_slide_accel(1.0, *state, cases["ag"], 0.0, *params, mu, stop_on=stop_on)[-1]
        assert np.allclose(N, weight, rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("damper", [None, DAMPER], ids=["bare", "omd"])
def test_the_paper_floor_without_vertical_motion_stays_on_the_floor_and_agrees_with_c(damper):
    """mu = inf, no vertical component, pulses that rock and return: no row in flight, and the results of the C
    back end (which the follow-up of flight leaves unchanged there) within 1e-8."""
    for beta, Omega in ((2.0, 3.0), (3.0, 6.0)):
        pulse = OneSinePulse.from_nondim(REFERENCE, beta=beta, Omega=Omega)
        r = rocking.simulate(REFERENCE, damper, pulse, backend="numpy", record=True, rtol=1e-10)
        c = rocking.simulate(REFERENCE, damper, pulse, backend="c", rtol=1e-10)
        assert not np.any(r.history["fly"]) and r.flights == 0 and r.flight_time == 0.0 and r.jump_max == 0.0
        assert (r.status, r.impacts, r.uplifts) == (c.status, c.impacts, c.uplifts)
        for name in ("theta_max", "x_max", "t_end"):
            assert getattr(r, name) == pytest.approx(getattr(c, name), rel=1e-8, abs=1e-12)


def test_on_a_floor_without_friction_a_landing_whose_sticking_impulse_would_pull_is_tangential_alone():
    """mu_s = inf: the floor's impulses fill the half-plane P_n >= 0. Where the sticking impulse would pull, the
    plastic landing is the tangential impulse alone (docs/model.md section 16), checked here by Newton and Euler
    for the bare block, not by the generated code: no vertical impulse, so the centroid's vertical velocity
    dv + Q dtheta is kept; M times the change of its horizontal velocity du - P dtheta and I_G / P times the change
    of dtheta are the same impulse P_t; the corner stops sliding and leaves the floor; energy is lost."""
    block = Block(H=2.0, B=0.5, M=1000.0, e=0.03)
    system = nb._System(make_problem(block, None, OneSinePulse.from_nondim(block, beta=2.0, Omega=3.0)))
    rng, found = np.random.default_rng(39), 0
    for _ in range(400):
        s = int(rng.choice((-1, 1)))
        y = np.array([s * rng.uniform(0.05, 1.2), rng.uniform(-3.0, 3.0)])
        du, dv = rng.uniform(-2.0, 2.0), -rng.uniform(0.01, 1.0)
        stick = [float(c) for c in system._flight("landing_stick", float(s), y, du, dv, 0.0)]
        if stick[-1] > 0.0:
            continue
        dq, du_after, dv_after, sigma = system.corner_landing(s, y, du, dv)
        found += 1
        d_s = s * block.B / 2 + block.e  # G from the corner s, horizontally, at theta = 0 (docs/model.md section 2)
        P = block.H / 2 * math.cos(y[0]) + d_s * math.sin(y[0])
        Q = d_s * math.cos(y[0]) - block.H / 2 * math.sin(y[0])
        impulse = block.M * ((du_after - P * dq[0]) - (du - P * y[1]))
        assert (du_after, sigma) == (0.0, 0) and dv_after > 0.0
        assert dv_after + Q * dq[0] == pytest.approx(dv + Q * y[1], rel=1e-12, abs=1e-12)
        assert block.I_G * (dq[0] - y[1]) == pytest.approx(P * impulse, rel=1e-10, abs=1e-9)
        energy = [
            0.5 * block.M * ((a - P * w) ** 2 + (b + Q * w) ** 2) + 0.5 * block.I_G * w**2
            for a, b, w in ((du, dv, y[1]), (du_after, dv_after, dq[0]))
        ]
        assert energy[1] < energy[0]
    assert found >= 20
