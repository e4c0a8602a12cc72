"""The C and NumPy back ends agree, and the C path meets docs/model.md section 10 too."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import rocking
from rocking.model.motion import OneCosinePulse
from rocking.model.params import Block, Damper
from rocking.model.pulse import OneSinePulse
from rocking.sim import c_backend, numpy_backend
from rocking.sim.cases import Cases, pulse_cases
from rocking.sim.problem import STATUS, make_problem

N_CASES = 200
#: A verdict may differ only where the overturning boundary lies within this
#: relative distance of the case's amplitude: there the two integrators, each
#: right to its tolerance, may fall on either side.
BOUNDARY = 2e-3


def random_case(rng: np.random.Generator, i: int):
    """A random block (eccentric, any slenderness), a damper on every other case, a pulse of any phase."""
    B = rng.uniform(0.3, 1.0)
    block = Block(H=B * rng.uniform(2.5, 6.0), B=B, M=1000.0, e=B * rng.uniform(-0.2, 0.2))
    damper = None
    if i % 2 == 0:
        damper = Damper.from_nondim(
            block,
            gamma=rng.uniform(0.01, 0.2),
            omega_ratio=rng.uniform(0.3, 3.0),
            zeta=rng.uniform(0.0, 0.3),
            h=rng.uniform(0.0, 0.2),
        )
    psi = 0.0 if i % 3 else rng.uniform(0.0, 2 * math.pi)
    beta = rng.uniform(1.0, 8.0)
    Omega = rng.uniform(0.5, 10.0)
    return block, damper, psi, beta, Omega


def run_both(block, damper, psi, beta, Omega):
    pulse = OneSinePulse.from_nondim(block, beta=beta, Omega=Omega, psi=psi)
    problem = make_problem(block, damper, pulse, rtol=1e-8, t_after=6.0)
    return c_backend.simulate(problem), numpy_backend.simulate(problem)


def c_verdict(block, damper, psi, beta, Omega) -> bool:
    pulse = OneSinePulse.from_nondim(block, beta=beta, Omega=Omega, psi=psi)
    return c_backend.simulate(make_problem(block, damper, pulse, rtol=1e-8, t_after=6.0)).overturned


def test_back_ends_agree_on_random_cases():
    rng = np.random.default_rng(2026)
    verdicts_differ, compared, critical = [], 0, 0
    for i in range(N_CASES):
        case = random_case(rng, i)
        c, n = run_both(*case)
        if c.overturned != n.overturned:
            block, damper, psi, beta, Omega = case
            below = c_verdict(block, damper, psi, beta * (1 - BOUNDARY), Omega)
            above = c_verdict(block, damper, psi, beta * (1 + BOUNDARY), Omega)
            verdicts_differ.append((i, below != above))
            continue
        if c.impacts != n.impacts:
            continue
        # The C path's cheap bound below the critical angle must not move the crossing.
        assert c.t_critical == pytest.approx(n.t_critical, rel=1e-6, nan_ok=True), (i, case)
        critical += not math.isnan(c.t_critical)
        if c.overturned:
            assert c.t_overturn == pytest.approx(n.t_overturn, rel=1e-6), (i, case)
            continue
        compared += 1
        assert c.theta_max == pytest.approx(n.theta_max, rel=1e-6), (i, case)
        assert c.uplifts == n.uplifts, (i, case)
        # The end (rest, early rest at the damper's extremum, t_max) is the same rule in both.
        assert c.status == n.status, (i, case)
        assert c.x_max == pytest.approx(n.x_max, rel=1e-6), (i, case)
        assert c.t_end == pytest.approx(n.t_end, rel=1e-6), (i, case)
    assert all(near for _, near in verdicts_differ), verdicts_differ
    assert len(verdicts_differ) <= N_CASES // 20
    assert compared >= N_CASES // 4
    assert critical >= N_CASES // 10, critical


def test_early_rest_keeps_verdicts_and_maxima_on_random_cases():
    """docs/simulation.md rule 4 only ends runs sooner: verdict, theta_max, counts and x_max are unchanged."""
    rng = np.random.default_rng(7)
    shortened, numpy_checked = 0, 0
    for i in range(N_CASES):
        block, damper, psi, beta, Omega = random_case(rng, 2 * i)  # every case with a damper
        pulse = OneSinePulse.from_nondim(block, beta=beta, Omega=Omega, psi=psi)
        problem = make_problem(block, damper, pulse, rtol=1e-8, t_after=6.0, early_verdict=False)
        backends = [c_backend] + ([numpy_backend] if i % 20 == 0 else [])  # NumPy on a few: it is slow
        for backend in backends:
            early = backend.simulate(problem)
            full = backend.simulate(dataclasses.replace(problem, early_rest=False))
            case = (i, backend.__name__)
            # Identical until the energy falls below the bound, in full contact (theta = 0) after the pulse.
            assert (early.overturned, early.theta_max, early.impacts, early.uplifts) == (
                full.overturned,
                full.theta_max,
                full.impacts,
                full.uplifts,
            ), case
            assert early.t_critical == full.t_critical or (math.isnan(early.t_critical) and math.isnan(full.t_critical))
            assert early.x_max == pytest.approx(full.x_max, rel=1e-9), case
            assert early.t_end <= full.t_end, case
            if early.status != full.status:
                assert early.status == "rest" and full.status in ("t_max", "below_barrier", "rest"), case
            shortened += backend is c_backend and early.t_end < full.t_end
            numpy_checked += backend is numpy_backend
    assert shortened >= N_CASES // 10 and numpy_checked >= 10


@pytest.mark.parametrize("Omega, beta_min", [(1, 1.418), (2, 2.350), (4, 5.239), (6, 9.417)])
def test_c_path_overturning_without_impact_boundary(Omega, beta_min):
    """docs/model.md 10.4 on the C path: slender bare symmetric block, alpha = 0.02."""
    block = Block.from_nondim(p=2.0, alpha=0.02)

    def overturns_without_impact(beta):
        pulse = OneSinePulse.from_nondim(block, beta=beta, Omega=Omega)
        r = c_backend.simulate(
            make_problem(block, None, pulse, rtol=1e-9, t_max=pulse.t_p + 20 / block.p, max_events=2)
        )
        return r.overturned and r.impacts == 0

    lo, hi = 0.9 * beta_min, 1.1 * beta_min
    assert not overturns_without_impact(lo) and overturns_without_impact(hi)
    while hi - lo > 1e-3 * beta_min:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if overturns_without_impact(mid) else (mid, hi)
    assert 0.5 * (lo + hi) == pytest.approx(beta_min, rel=0.01)


#: The linearised bare symmetric block under the one-cosine pulse overturns without impact from
#: beta = (1 + Omega^2) / (1 - exp(-2 pi / Omega)) (beta = a_p / (g alpha)). Derived by hand for this check
#: (psi = -theta / alpha obeys psi'' - psi = -1 + beta cos(Omega tau); with c = beta / (1 + Omega^2) > 1 there is no
#: impact during the pulse, and the block escapes when psi - 1 + psi' > 0 at its end), the analogue of
#: docs/model.md 10.4 for the one-sine; not a published value.
COSINE_NO_IMPACT = {Omega: (1 + Omega**2) / (1 - math.exp(-2 * math.pi / Omega)) for Omega in (1.0, 2.0, 3.0)}


@pytest.mark.parametrize("Omega", sorted(COSINE_NO_IMPACT))
def test_c_path_one_cosine_overturning_without_impact_boundary(Omega):
    """The one-cosine analogue of docs/model.md 10.4 (COSINE_NO_IMPACT): slender bare symmetric block, alpha = 0.02."""
    block = Block.from_nondim(p=2.0, alpha=0.02)
    beta_ni = COSINE_NO_IMPACT[Omega] * block.alpha / block.tan_alpha  # to a_p / (g tan alpha)

    def overturns_without_impact(beta):
        pulse = OneCosinePulse.from_nondim(block, beta=beta, Omega=Omega)
        r = c_backend.simulate(
            make_problem(block, None, pulse, rtol=1e-9, t_max=pulse.t_p + 20 / block.p, max_events=2)
        )
        return r.overturned and r.impacts == 0

    assert not overturns_without_impact(0.99 * beta_ni) and overturns_without_impact(1.01 * beta_ni)


def test_c_path_one_cosine_threshold_of_an_outside_simulation():
    """An outside value (not peer reviewed): the bare symmetric block of p = 2 rad/s and alpha = 15 degrees, under
    a_g = a_p cos(pi t) on [0, 2 s] (Omega = pi / 2), overturns from a_p = 0.315034034 g: a personal study of the
    rocking block (GitHub wshwwl/wshwwl.github.com, 2020/02/rock.md, section 4, and its MATLAB code
    nonlinearrock.m: Housner's equation, restitution 1 - 1.5 sin^2 alpha), in the text "below 0.315 g the block
    does not overturn; at 0.316 g it overturns". Held here to 1e-4 relative."""
    block = Block.from_nondim(p=2.0, alpha=math.radians(15.0))
    outcomes = [
        rocking.simulate(block, None, OneCosinePulse(a_g=factor * 0.315034034 * block.g, omega_g=math.pi), rtol=1e-10)
        for factor in (1 - 1e-4, 1 + 1e-4)
    ]
    assert [r.overturned for r in outcomes] == [False, True]


@pytest.mark.parametrize("psi, pivot", [(0.0, 1), (math.pi, -1)])
def test_c_path_uplift_at_the_static_threshold(psi, pivot):
    """docs/model.md 10.2: uplift about A at g (B + 2e)/H, about A' at -g (B - 2e)/H."""
    block = Block.reference()
    pulse = OneSinePulse.from_nondim(block, beta=3.0, Omega=2.0, psi=psi)
    r = c_backend.simulate(make_problem(block, None, pulse), record=True)
    j = int(np.nonzero(r.history["phase"] != 0)[0][0])
    threshold = block.g * (block.B + 2 * pivot * block.e) / block.H
    expected = (math.asin(threshold / pulse.a_g) - psi + (math.pi if pivot < 0 else 0.0)) / pulse.omega_g
    assert r.history["phase"][j] == pivot
    assert r.history["t"][j] == pytest.approx(expected, abs=1e-7)


def test_both_back_ends_count_the_same_work():
    """Rule 5: the work of a run is counted alike: the least max_steps a run needs is the same on both.

    Found on C by bisection (a batch per step), then checked on NumPy: with that
    bound the run ends as without it, with one less it ends with "max_steps".
    """
    rng = np.random.default_rng(5)
    block = Block.reference()
    n = 4
    cases = pulse_cases(
        block,
        rng.uniform(1.0, 8.0, n),
        rng.uniform(1.2, 4.0, n),
        gamma=rng.uniform(0.02, 0.2, n),
        omega_ratio=rng.uniform(0.3, 3.0, n),
        zeta=rng.uniform(0.0, 0.3, n),
        h=0.05,
        t_after=4.0,
    )
    hit = STATUS.index("max_steps")
    low, high = np.zeros(n, dtype=np.int64), np.full(n, 1 << 20, dtype=np.int64)
    while np.any(high - low > 1):
        mid = (low + high) // 2
        status = c_backend.simulate_cases(Cases(cases.model, cases.p, {**cases.settings, "max_steps": mid}))["status"]
        low, high = np.where(status == hit, mid, low), np.where(status == hit, high, mid)
    assert np.all(high < 1 << 20)
    for i in range(n):
        problem = cases.problem(i)
        enough = numpy_backend.simulate(dataclasses.replace(problem, max_steps=int(high[i])))
        assert enough.status == numpy_backend.simulate(problem).status != "max_steps"
        assert numpy_backend.simulate(dataclasses.replace(problem, max_steps=int(high[i]) - 1)).status == "max_steps"


def test_the_least_rest_threshold_still_ends_both_back_ends_alike():
    """dtheta_rest has a floor, 1e-9 alpha p: the fuzzer's input #4694 (seed 20240610) at 1e-38 rad/s made C
    cycle to max_events while NumPy came to rest; at the floor both come to rest after the same 194 impacts."""
    block = rocking.Block(B=0.9971758928651336, H=4.1156196565800345, M=7052.253032291311, I_G=1e4, e=-0.0289080609)
    damper = rocking.Damper.from_nondim(block, gamma=0.19704431117544555, zeta=0.0, omega_ratio=0.99999, h=0.0148766)
    pulse = rocking.OneSinePulse.from_nondim(block, Omega=13.932483677482987, psi=4.860474897626126, beta=11.68481444)
    floor = 1e-9 * block.alpha * block.p
    c, n = (
        rocking.simulate(block, damper, pulse, backend=b, rtol=1e-5, dtheta_rest=floor, early_verdict=False)
        for b in ("c", "numpy")
    )
    assert (c.status, c.impacts) == (n.status, n.impacts) and c.status == "rest" and c.impacts > 100
    with pytest.raises(rocking.ParameterError, match=r"^dtheta_rest must be >= 1e-9 alpha p"):
        rocking.simulate(block, damper, pulse, dtheta_rest=0.5 * floor)


def test_batch_cases_of_either_sign_are_the_single_runs():
    """pulse_cases(sign=-1) gives, case by case, what rocking.simulate gives for OneSinePulse(..., sign=-1)."""
    block = Block.reference()
    Omega, beta = np.array([2.0, 4.0, 7.5]), np.array([1.5, 3.0, 10.0])
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    for sign in (1, -1):
        batch = c_backend.simulate_cases(pulse_cases(block, Omega, beta, gamma=0.05, h=0.05, sign=sign), threads=1)
        for i in range(3):
            pulse = OneSinePulse.from_nondim(block, beta=beta[i], Omega=Omega[i], sign=sign)
            one = rocking.simulate(block, damper, pulse, backend="c", t_after=15.0)
            assert (bool(batch["overturned"][i]), int(batch["impacts"][i])) == (one.overturned, one.impacts)
            assert batch["theta_max"][i] == pytest.approx(one.theta_max, rel=1e-12)
    with pytest.raises(rocking.ParameterError, match=r"^sign must be \+1 or -1"):
        pulse_cases(block, Omega, beta, sign=0)


def test_batch_stops_are_refused_where_the_pads_do_not_fit():
    """pulse_cases(stops=True) on a block narrower than the pads: a one-line error naming L and its range."""
    with pytest.raises(rocking.ParameterError, match=r"gives L = -0.005.*but L must be in \(0, 1000\] m"):
        pulse_cases(Block(H=0.1, B=0.03, M=1.0), [2.0], [2.0], gamma=0.05, stops=True)


#: Random cases per family of docs/model.md section 12 beyond the one-sine.
N_MOTION_CASES = 16


def random_motion(rng: np.random.Generator, family: str, block: Block, beta: float, Omega: float):
    """A motion of ``family`` with amplitude ratio ``beta`` and frequency ratio ``Omega`` (a record: its mean)."""
    if family == "sampled":
        dt = 2 * math.pi / (Omega * block.p) / rng.integers(12, 40)
        a = np.convolve(rng.standard_normal(rng.integers(60, 200)), np.hanning(7), "same")
        return rocking.SampledMotion(a / np.max(np.abs(a)), dt=dt, scale=beta * block.g * block.tan_alpha)
    cls, shape = {
        "cosine": (rocking.OneCosinePulse, {}),
        "ricker": (rocking.RickerWavelet, {}),
        "ricker_anti": (rocking.RickerWavelet, {"antisymmetric": True}),
        "mp": (rocking.MavroeidisPapageorgiou, {"gamma_mp": rng.uniform(1.5, 3.0), "nu": rng.uniform(0, 2 * math.pi)}),
    }[family]
    return cls.from_nondim(block, beta=beta, Omega=Omega, sign=int(rng.choice([-1, 1])), **shape)


@pytest.mark.parametrize("family", ["cosine", "ricker", "ricker_anti", "mp", "sampled"])
def test_back_ends_agree_on_random_cases_of_every_motion(family):
    """C = NumPy on random blocks, dampers and motions of each family: verdict, impacts, theta_max, x_max."""
    rng = np.random.default_rng(["cosine", "ricker", "ricker_anti", "mp", "sampled"].index(family))
    # A sampled motion's steps differ between the back ends (C clamps them to the sample times, NumPy restarts
    # a segment there): they agree to the global error (rtol 1e-8: a few 1e-6 on x_max at overturning).
    rel = 1e-5 if family == "sampled" else 1e-6
    same_verdict, compared = 0, 0
    for i in range(N_MOTION_CASES):
        block, damper, _, beta, Omega = random_case(rng, i)
        motion = random_motion(rng, family, block, beta / 2 if family == "sampled" else beta, Omega)
        problem = make_problem(block, damper, motion, rtol=1e-8, t_after=4.0)
        c, n = c_backend.simulate(problem), numpy_backend.simulate(problem)
        same_verdict += c.overturned == n.overturned
        if c.overturned != n.overturned or c.impacts != n.impacts:
            continue
        compared += 1
        assert c.theta_max == pytest.approx(n.theta_max, rel=rel), (i, family)
        assert c.x_max == pytest.approx(n.x_max, rel=rel, abs=1e-9), (i, family)
        assert c.uplifts == n.uplifts, (i, family)
    assert same_verdict >= N_MOTION_CASES - 1 and compared >= N_MOTION_CASES * 3 // 4, (same_verdict, compared)
