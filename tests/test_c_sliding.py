"""The C back end on a floor with friction (docs/model.md section 15, issue 37): the phase table followed by sim.c.

Held to facts from outside sim.c: a floor that never slips is the paper's (mu = inf, and a large finite mu);
pure sliding under the one-sine pulse is its closed form (rocking.reference.sliding.one_sine_sliding); the bare
block's slide-rock is the reference simulator typed by hand (rocking.reference.sliding.slide_rock).
"""

import math

import numpy as np
import pytest

import rocking
from rocking.reference.sliding import one_sine_sliding, slide_rock
from rocking.sim import c_backend, cbuild

G = 9.81
#: The block of issue 37's table: H = 2 m, B = 0.5 m (B/H = 0.25), M = 1000 kg.
BLOCK = rocking.Block(H=2.0, B=0.5, M=1000.0)
#: Its pulse period T = 0.5 s.
OMEGA = 2 * math.pi / 0.5

pytestmark = pytest.mark.skipif(not c_backend.available("block"), reason="the C back end cannot be built here")


def run(block, damper, pulse, **options):
    return rocking.simulate(block, damper, pulse, backend="c", **options)


def results(r) -> tuple:
    """The scalar results, NaN as None (so that equal runs compare equal)."""
    return tuple(None if isinstance(v, float) and math.isnan(v) else v for v in r.summary().values())


@pytest.mark.parametrize("with_damper", [False, True])
@pytest.mark.parametrize("a_g", [0.3, 0.45])
def test_a_floor_that_never_slips_is_the_papers(with_damper, a_g):
    """mu = inf (Floor()) is the default floor bit for bit; mu = 1e3, where |F| < mu_s N throughout, gives the
    same response to 1e-12 (section 15, fact a), once the paper's floor too is followed without the early
    verdict and rule 4's settling (a floor with friction takes neither: docs/simulation.md, "Phases"). Not a
    run that overturns: N falls to 0 as the block tips over, and any finite mu lets it slip there."""
    block = rocking.Block.reference()
    damper = (
        rocking.Damper(m=0.05 * block.M, k_m=0.05 * block.M * (0.9 * block.p) ** 2, c=100.0) if with_damper else None
    )
    pulse = rocking.OneSinePulse(a_g=a_g * G, omega_g=5 * block.p)
    assert results(run(block, damper, pulse, floor=rocking.Floor())) == results(run(block, damper, pulse))
    paper = run(block, damper, pulse, early_verdict=False, early_rest=False)
    rough = run(block, damper, pulse, mu=1e3, early_verdict=False, early_rest=False)
    assert (rough.status, rough.impacts, rough.uplifts) == (paper.status, paper.impacts, paper.uplifts)
    for name in ("theta_max", "x_max", "t_end"):
        assert getattr(rough, name) == pytest.approx(getattr(paper, name), rel=1e-12, abs=1e-300)
    assert (rough.u_max, rough.u_end, rough.slides) == (0.0, 0.0, 0)


@pytest.mark.parametrize(("mu_s", "mu_k", "sign"), [(0.2, 0.2, 1), (0.2, 0.15, 1), (0.2, 0.2, -1)])
def test_pure_sliding_is_the_closed_form(mu_s, mu_k, sign):
    """Below mu_s = B/H the block slides without lifting: peak and residual slip of the closed form to 1e-8
    (section 15, fact b; 31.45 mm and 1.57 mm at mu = 0.2, issue 37's figures)."""
    pulse = rocking.OneSinePulse(a_g=0.4 * G, omega_g=OMEGA, sign=sign)
    r = run(BLOCK, None, pulse, mu=mu_s, mu_k=mu_k, rtol=1e-10)
    exact = one_sine_sliding(0.4 * G, OMEGA, mu_s, mu_k, g=G, sign=sign)
    assert r.status == "rest" and r.uplifts == 0 and r.theta_max == 0.0
    assert r.u_max == pytest.approx(exact.u_max, rel=1e-8)
    assert r.u_end == pytest.approx(exact.u_end, rel=1e-8)
    assert r.slides >= 1


@pytest.mark.parametrize(("a_g", "mu"), [(0.3, 0.255), (0.4, 0.26), (0.5, 0.3)])
def test_slide_rock_is_the_reference_simulators(a_g, mu):
    """The bare block that slides and rocks (slip, uplift, a slipping pivot, impacts) against the hand-typed
    reference simulator: theta_max and u_max to 1e-5 (relative)."""
    pulse = rocking.OneSinePulse(a_g=a_g * G, omega_g=OMEGA)
    r = run(BLOCK, None, pulse, mu=mu, rtol=1e-10, t_max=1.5, early_verdict=False)
    ref = slide_rock(BLOCK.M, BLOCK.I_G, BLOCK.B, BLOCK.H, BLOCK.e, G, a_g * G, OMEGA, mu, t_after=1.0)
    assert r.uplifts >= 1 and r.u_max > 0.0
    assert r.theta_max == pytest.approx(ref.theta_max, rel=1e-5)
    assert r.u_max == pytest.approx(ref.u_max, rel=1e-5)


@pytest.mark.parametrize(
    ("block", "with_damper", "a_g", "omega", "mu", "mu_k"),
    [
        (BLOCK, False, 0.4, OMEGA, 0.26, None),  # slide, uplift, a slipping pivot, impacts that slip
        (BLOCK, False, 0.5, OMEGA, 0.3, 0.25),  # mu_k < mu_s
        (rocking.Block.reference(), True, 0.5, 3.0, 0.1, None),  # the damper: sliding only
        (rocking.Block.reference(), True, 0.4, 3.0, 0.3, None),  # the damper: slides, rocks, overturns
    ],
)
def test_c_follows_the_floor_as_numpy_does(block, with_damper, a_g, omega, mu, mu_k):
    """The two back ends follow the same phase table (rocking.sim.phases): the same phases, events and counts,
    and their results to the integrators' error (rtol = 1e-10; never bit for bit across libm and NumPy)."""
    damper = (
        rocking.Damper(m=0.05 * block.M, k_m=0.05 * block.M * (0.9 * block.p) ** 2, c=100.0) if with_damper else None
    )
    pulse = rocking.OneSinePulse(a_g=a_g * G, omega_g=omega if block is BLOCK else omega * block.p)
    c, numpy = (rocking.simulate(block, damper, pulse, backend=b, mu=mu, mu_k=mu_k, rtol=1e-10) for b in ("c", "numpy"))
    assert (c.status, c.slides, c.uplifts, c.impacts) == (numpy.status, numpy.slides, numpy.uplifts, numpy.impacts)
    for name in ("theta_max", "x_max", "u_max", "u_end"):
        assert getattr(c, name) == pytest.approx(getattr(numpy, name), rel=1e-6, abs=1e-12), name


def test_the_history_follows_the_floor():
    """u, du, N, F and the slip's sign in the history: a stuck contact holds |F| <= mu_s N, a sliding one feels
    F = -mu_k sigma N; u_max is the largest |u| recorded, u_end the last u."""
    mu_s, mu_k = 0.26, 0.2
    pulse = rocking.OneSinePulse(a_g=0.4 * G, omega_g=OMEGA)
    r = run(BLOCK, None, pulse, mu=mu_s, mu_k=mu_k, record=True)
    h = r.history
    for name in ("u", "du", "N", "F", "slide"):
        assert np.all(np.isfinite(h[name])), name
    stuck, sliding = h["slide"] == 0, h["slide"] != 0
    assert sliding.any() and stuck.any()
    assert np.all(h["du"][stuck] == 0.0)
    assert np.all(np.abs(h["F"][stuck]) <= mu_s * h["N"][stuck] * (1 + 1e-9))
    np.testing.assert_allclose(h["F"][sliding], -mu_k * h["slide"][sliding] * h["N"][sliding], rtol=1e-12)
    assert np.all(h["N"] > 0.0)
    assert np.max(np.abs(h["u"])) == pytest.approx(r.u_max, rel=1e-12)
    assert h["u"][-1] == r.u_end
    assert set(np.unique(h["phase"])) <= {-1, 0, 1}


def test_the_damper_on_a_slipping_floor():
    """With the damper: the run slides (episodes counted), its energy bound is kept while stuck only, and its
    history has the same columns."""
    block = rocking.Block.reference()
    damper = rocking.Damper(m=0.05 * block.M, k_m=0.05 * block.M * (0.9 * block.p) ** 2, c=100.0)
    pulse = rocking.OneSinePulse(a_g=0.5 * G, omega_g=3 * block.p)
    r = run(block, damper, pulse, mu=0.1, record=True)
    assert r.slides >= 1 and r.u_max > 0.0 and abs(r.u_end) <= r.u_max
    assert r.status in ("rest", "bounded", "below_barrier", "t_max", "overturned")
    assert {"u", "du", "N", "F", "slide"} <= set(r.history)


def test_the_library_ships_the_phase_table():
    """phases.h is compiled into the library: a source of its cache key, staged with sim.c."""
    model = rocking.load_model("block")
    assert "phases.h" in cbuild._sources(model, cbuild.CSRC)
