"""The early verdict (docs/simulation.md, rule 4): a run ends once its energy bounds its maxima, and nothing it
reports as final changes."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import rocking
from derive.equations import derive
from derive.spec import variant_spec
from rocking.model.params import Block, Damper
from rocking.sim import c_backend, numpy_backend
from rocking.sim.cases import Cases, pulse_cases, run_cases
from rocking.sim.numpy_backend import _System
from rocking.sim.problem import STATUS, make_problem

#: What the early verdict keeps, bit for bit.
FINAL = ("overturned", "theta_max", "x_max", "t_critical", "t_overturn", "stop_contacts", "bumper_force_max")


def _random_cases(rng, n: int, kind: str) -> Cases:
    """Pulses on one random block: bare, with a damper, or with a damper between stops (``kind``)."""
    B = rng.uniform(0.3, 1.0)
    block = Block(H=B * rng.uniform(2.5, 6.0), B=B, M=1000.0, e=B * rng.uniform(-0.2, 0.2))
    damper = (
        {}
        if kind == "bare"
        else dict(
            gamma=rng.uniform(0.01, 0.2, n),
            omega_ratio=rng.uniform(0.3, 3.0, n),
            zeta=rng.uniform(0.0, 0.3, n),
            h=rng.uniform(0.0, 0.2, n),
            stops=kind == "stops",
        )
    )
    return pulse_cases(
        block,
        rng.uniform(0.5, 10.0, n),
        rng.uniform(1.0, 8.0, n),
        psi=rng.uniform(0, 2 * math.pi, n),
        sign=rng.choice([-1, 1], n),
        rtol=1e-8,
        t_after=6.0,
        **damper,
    )


def _without_verdict(cases: Cases) -> Cases:
    return Cases(cases.model, cases.p, {**cases.settings, "early_verdict": np.zeros(len(cases), np.int32)})


def _same(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return (a == b) | (np.isnan(a) & np.isnan(b)) if a.dtype.kind == "f" else a == b


@pytest.mark.parametrize("kind", ["bare", "damper", "stops"])
def test_the_verdict_and_the_maxima_are_those_of_the_run_followed_to_rest(kind):
    cases = _random_cases(np.random.default_rng({"bare": 1, "damper": 2, "stops": 3}[kind]), 300, kind)
    early, full = run_cases(cases), run_cases(_without_verdict(cases))
    for name in FINAL:
        assert _same(early[name], full[name]).all(), name
    bounded = early["status"] == STATUS.index("bounded")
    assert np.array_equal(early["status"][~bounded], full["status"][~bounded])
    # Followed to rest, they came to rest or reached t_max (with too little energy to overturn, or not).
    ends = [STATUS.index(status) for status in ("rest", "t_max", "below_barrier")]
    assert np.all(np.isin(full["status"][bounded], ends))
    assert np.all(early["impacts"] <= full["impacts"]) and np.all(early["t_end"] <= full["t_end"])
    # Most safe responses end early (with stops, only those whose mass never reached a bumper).
    safe = ~early["overturned"]
    assert bounded.sum() >= (0.1 if kind == "stops" else 0.6) * safe.sum() > 0
    assert early["impacts"].sum() < 0.8 * full["impacts"].sum()


@pytest.mark.parametrize("kind", ["bare", "damper", "stops"])
def test_both_back_ends_end_at_the_same_impact(kind):
    cases = _random_cases(np.random.default_rng(10 + len(kind)), 12, kind)
    c = run_cases(cases)
    n = run_cases(cases, backend="numpy")
    assert np.array_equal(c["status"], n["status"]) and np.array_equal(c["impacts"], n["impacts"])
    assert (c["status"] == STATUS.index("bounded")).any()
    np.testing.assert_allclose(n["theta_max"], c["theta_max"], rtol=1e-6)


def test_the_bounds_hold_below_the_potential_they_bound():
    """least_potential is the least V over the stroke, least_on_arcs a lower bound of V over the arc, close to it."""
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    pulse = rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=4.0)
    system = _System(make_problem(block, damper, pulse))
    strokes = np.linspace(-2.0, 2.0, 4001)
    for theta_m in (0.01, 0.1, 0.3, 1.0):
        for s in (1, -1):
            V = [system.energy(system._at(s * theta_m, x), s) for x in strokes]
            least = float(system._call("least_potential", s, system._at(s * theta_m), 0.0))
            assert least <= min(V) <= least + 1e-6 * abs(least)
        for x_m in (0.05, 0.4):
            tilts = np.linspace(0.0, theta_m, 2001)
            V = min(system.energy(system._at(s * t, x), s) for s in (1, -1) for t in tilts for x in (x_m, -x_m))
            bound = system.least_on_arcs(theta_m, x_m)
            # Below the least on the arc, by at most the gap between an arc of 0.05 rad and its triangle.
            assert bound <= V <= bound + 4e-4 * block.M * block.g * block.R


def test_no_bound_where_the_energy_can_grow_or_the_potential_is_not_quadratic():
    velocity = derive(variant_spec("omd"), {"impact": "velocity"})
    assert velocity.least_potential == velocity.least_stroke_potential == -math.inf
    pendulum = derive(variant_spec("pendulum"))
    assert pendulum.least_potential == -math.inf


def test_the_pendulum_is_followed_to_rest():
    block = Block.reference()
    pendulum = dict(m=0.05 * block.M, l=0.5, x_p=0.0, y_p=block.H + 0.55, k_phi=0.0, c_phi=20.0)
    pulse = rocking.OneSinePulse.from_nondim(block, beta=1.5, Omega=6.0)
    for backend in (c_backend, numpy_backend):
        r = backend.simulate(make_problem(block, pendulum, pulse, model="pendulum", t_after=3.0))
        assert not r.overturned and r.impacts > 0 and r.status in ("rest", "t_max")


def test_the_option_is_checked():
    block = Block.reference()
    pulse = rocking.OneSinePulse.from_nondim(block, beta=2.0, Omega=4.0)
    with pytest.raises(rocking.ParameterError, match="early_verdict"):
        make_problem(block, None, pulse, early_verdict=2)


def test_the_command_line_follows_to_rest_unless_asked_for_the_early_verdict(capsys):
    from rocking.cli.main import main

    args = ["simulate", "--gamma", "0.05", "--omega-ratio", "1", "--h", "0.05", "--beta", "5", "--Omega", "4", "--json"]
    runs = []
    for extra in (["--early-verdict"], []):
        assert main(args + extra) == 0
        (response,) = json.loads(capsys.readouterr().out)["responses"].values()
        runs.append(response)
    early, full = runs
    assert (early["status"], full["status"]) == ("bounded", "rest")
    assert early["theta_max"] == full["theta_max"] and early["impacts"] < full["impacts"]


# --- a run that reaches t_max: its energy against the least potential on the way to overturning -----------

#: A large slender block (lambda = 8, p = 1 rad/s, R = 7.4 m) and its damper: its small rocking and the damper's
#: slow decay (zeta = 0.05 at omega_m = p) outlast the default 15 s after the pulse.
BIG = Block.from_nondim(lam=8.0, p=1.0)
BIG_DAMPER = Damper.from_nondim(BIG, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)


def test_a_run_at_t_max_with_too_little_energy_to_overturn_is_safe_on_both_back_ends():
    pulse = rocking.OneSinePulse.from_nondim(BIG, beta=2.0, Omega=7.0)
    c, py = (rocking.simulate(BIG, BIG_DAMPER, pulse, backend=b) for b in ("c", "numpy"))
    assert c.status == py.status == "below_barrier" and not c.overturned
    assert py.theta_max == pytest.approx(c.theta_max, rel=1e-6)
    # Followed far longer, it ends with the early verdict, never overturning, at the same maximum.
    longer = rocking.simulate(BIG, BIG_DAMPER, pulse, t_after=200.0)
    assert longer.status == "bounded" and longer.theta_max == c.theta_max


def test_runs_below_the_barrier_never_overturn_when_followed_longer():
    Omega, beta = np.meshgrid(np.linspace(2.0, 12.0, 6), np.linspace(1.0, 8.0, 6), indexing="ij")
    short = run_cases(pulse_cases(BIG, Omega, beta, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05), "c", 1)
    status = np.asarray(short["status"])
    safe = status == STATUS.index("below_barrier")
    assert safe.sum() >= 3  # the check below is not empty
    longer = run_cases(
        pulse_cases(BIG, Omega.ravel()[safe], beta.ravel()[safe], gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05,
                    t_after=300.0),
        "c",
        1,
    )  # fmt: skip
    assert not np.any(longer["overturned"])
    assert np.all(np.asarray(longer["theta_max"]) >= np.asarray(short["theta_max"])[safe])


def test_a_run_cut_with_the_energy_to_overturn_has_no_verdict():
    block = Block.reference()
    pulse = rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=4.0)
    cut = rocking.simulate(block, None, pulse, t_max=1.0)
    assert cut.status == "t_max" and rocking.simulate(block, None, pulse).overturned
