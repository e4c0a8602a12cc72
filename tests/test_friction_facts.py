"""The outside facts of a floor with friction (issue 37 item 5; docs/model.md section 15), each a test.

The runs are bench/friction_facts.py's (one definition of each measurement; the bench draws them on finer grids);
each fact is held to a figure from outside the code: a closed form, Shenton (1996)'s rule, Housner (1963)'s
restitution, the energy balance, issue 37's table of an independent sliding-only model. The facts on a finite
floor run on every back end that follows friction (``FRICTION_BACKENDS``, from rocking.sim.backends' flags).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from rocking.sim.backends import BACKENDS


def _load_bench():
    """bench/friction_facts.py as a module (bench/ is not a package)."""
    path = Path(__file__).parent.parent / "bench" / "friction_facts.py"
    spec = importlib.util.spec_from_file_location("bench_friction_facts", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


facts = _load_bench()
G = facts.G
FRICTION_BACKENDS = facts.FRICTION_BACKENDS


# --------------------------------------------------------------------------- (a)


@pytest.mark.parametrize("backend", sorted(BACKENDS))
@pytest.mark.parametrize("damper", [False, True], ids=["block", "omd"])
def test_an_infinite_mu_is_the_run_without_a_floor_bit_for_bit_history_included(backend, damper):
    plain, infinite = facts.paper_floor(backend, damper)
    # The paper's floor never slips (a model with flight records the floor's columns there too, all 0 on it).
    assert not np.any(plain.history.get("u", 0.0)) and not np.any(plain.history.get("fly", 0.0)) and plain.impacts >= 1
    assert facts.identical(plain, infinite)


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
@pytest.mark.parametrize("damper", [False, True], ids=["block", "omd"])
def test_a_floor_that_always_holds_is_the_paper_floor_to_1e_12(backend, damper):
    """mu = 1e3: the floor never needs more than mu_s N (no slip episode), so the run is mu = inf's."""
    paper, holding = facts.holding_floor(backend, damper, mu=1e3)
    assert (holding.slides, holding.u_max, holding.u_end) == (0, 0.0, 0.0)
    assert not np.any(holding.history["slide"]) and not np.any(holding.history["u"])
    assert paper.impacts >= 2 and (paper.x_max > 0.0) == damper  # the run rocks (and the damper moves)
    assert (holding.status, holding.impacts, holding.uplifts) == (paper.status, paper.impacts, paper.uplifts)
    for name in ("theta_max", "x_max", "t_end"):
        assert getattr(holding, name) == pytest.approx(getattr(paper, name), rel=1e-12, abs=1e-15), name


# --------------------------------------------------------------------------- (b)


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
@pytest.mark.parametrize(
    ("a_g", "omega_g", "mu_s", "mu_k", "sign"),
    [
        (0.4 * G, 4 * np.pi, 0.2, 0.2, 1),  # issue 37's pulse
        (0.4 * G, 4 * np.pi, 0.2, 0.15, -1),  # mu_k < mu_s, the pulse reversed
        (0.8 * G, 6.0, 0.2, 0.15, 1),  # slides on after the pulse
        (0.3 * G, 20.0, 0.1, 0.1, -1),
    ],
)
def test_pure_sliding_is_the_closed_form(backend, a_g, omega_g, mu_s, mu_k, sign):
    r, closed = facts.pure_sliding(backend, a_g, omega_g, mu_s, mu_k, sign)
    assert (r.uplifts, r.status) == (0, "rest") and r.slides == closed.slides >= 1
    assert r.u_max == pytest.approx(closed.u_max, rel=1e-8)
    assert r.u_end == pytest.approx(closed.u_end, rel=1e-8)
    t0 = facts.start_time(a_g, omega_g, mu_s)
    assert closed.t_start == pytest.approx(t0, rel=1e-15)
    # The first sliding row of the history is the slip event itself (located to the integrator's tolerance).
    assert facts.first_slip_time(r.history) == pytest.approx(t0, rel=1e-8)


# --------------------------------------------------------------------------- (c)

#: Slenderness ratios B/H and ratios mu_s / (B/H) of the initiation grid. Under a ramp from rest the first
#: threshold is exact: the floor must hold M ddx_g, which reaches mu_s M g at ddx_g = mu_s g, and the block lifts
#: at ddx_g = g B/H (section 5); a base already sliding is pushed at mu_k g <= mu_s g < g B/H, so it cannot lift
#: before B/H either. The band where the order may go either way is then the events' location error alone
#: (relative 1e-8 of the time at which the ramp crosses the thresholds); the grid comes within 1e-3 of the tie.
INITIATION_RATIOS = (0.7, 0.9, 0.999, 1.001, 1.1, 1.3)
INITIATION_SLENDERNESS = (0.15, 0.3, 0.5)


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
@pytest.mark.parametrize("b_over_h", INITIATION_SLENDERNESS)
def test_shenton_initiation_slides_first_below_b_over_h_and_rocks_first_above(backend, b_over_h):
    firsts = {
        ratio: facts.first_event(facts.initiation(backend, b_over_h, ratio).history) for ratio in INITIATION_RATIOS
    }
    assert firsts == {ratio: "slides" if ratio < 1 else "rocks" for ratio in INITIATION_RATIOS}


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
def test_below_b_over_h_a_sliding_block_never_lifts_and_just_above_it_slides_after_rocking(backend):
    below = facts.initiation(backend, 0.3, 0.9)
    assert below.uplifts == 0 and below.slides >= 1
    near = facts.initiation(backend, 0.3, 1.001)  # slide-rock: it lifts, then its pivot slips
    assert near.uplifts >= 1 and near.slides >= 1


# --------------------------------------------------------------------------- (d)


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
@pytest.mark.parametrize("b_over_h", [0.1, 0.25, 0.5])
def test_a_sticking_impact_has_housner_restitution(backend, b_over_h):
    r = facts.free_rocking(backend, b_over_h, mu=0.7)
    ratios = facts.restitutions(r.history)
    assert r.slides == 0 and ratios.size >= 2  # every impact sticks
    expected = facts.housner(facts.table_block(b_over_h).alpha)
    np.testing.assert_allclose(ratios, expected, rtol=1e-9)


# --------------------------------------------------------------------------- (e)

#: The energy may rise between rows by the integrator's error alone: 10 rtol of the largest |E| of the run (the
#: energy measured from the floor; the runs are at rtol = 1e-10, and the largest rise measured falls with rtol:
#: 6.6e-6, 6.2e-7, 1.9e-9 J at rtol 1e-8, 1e-10, 1e-12 on |E| ~ 1.05e4 J). A missing dissipation, or slip energy
#: counted wrong, would be of order 1 J.
ENERGY_TOLERANCE = 10 * facts.RTOL


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
@pytest.mark.parametrize("damper", [False, True], ids=["block", "omd"])
def test_the_ground_frame_energy_never_rises_after_the_pulse(backend, damper):
    runs = facts.slide_rock_runs(backend, damper)
    for name, r in runs.items():
        h = r.history
        assert r.slides >= 1 and r.uplifts >= 1 and np.any((h["slide"] != 0) & (h["phase"] != 0)), name
        rise, scale = facts.energy_rise(r)
        assert rise <= ENERGY_TOLERANCE * scale, (name, rise, scale)
    # The longer pulse slides while the block rocks after the pulse: the slip's energy is in the balance there.
    late = runs["T = 1 s, mu 0.3"]
    h = late.history
    assert np.any((h["slide"] != 0) & (h["phase"] != 0) & (h["t"] > facts.t_p(late)))
    # Without the slip's kinetic energy the balance fails (by several J): the fact tests it.
    assert facts.energy_rise(late, slip=False)[0] > 1.0


# --------------------------------------------------------------------------- (f)


@pytest.fixture(scope="module")
def no_slip():
    return {backend: facts.table_run(backend, None) for backend in FRICTION_BACKENDS}


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
def test_issue_table_slides_alone_at_0_2(backend):
    r = facts.table_run(backend, 0.2)
    # 31.45 mm: the independent sliding-only model of issue 37.
    assert r.uplifts == 0 and r.slides >= 1 and r.u_max * 1e3 == pytest.approx(31.45, rel=0.01)


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
def test_issue_table_slides_and_rocks_at_0_26(backend):
    r = facts.table_run(backend, 0.26)
    assert r.slides >= 1 and r.uplifts >= 1


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
@pytest.mark.parametrize("mu", [0.3, 0.4, 0.5])
def test_issue_table_rocks_as_the_paper_floor_from_0_3(backend, mu, no_slip):
    r = facts.table_run(backend, mu)
    assert r.uplifts >= 1 and r.theta_max == pytest.approx(no_slip[backend].theta_max, rel=0.005)


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
@pytest.mark.parametrize("mu", facts.TABLE_MUS)
def test_issue_table_is_the_hand_typed_slide_rock_reference(backend, mu):
    r, ref = facts.table_run(backend, mu), facts.table_reference(mu)
    assert (r.slides, r.uplifts, r.impacts) == (ref.slides, ref.uplifts, ref.impacts)
    assert r.theta_max == pytest.approx(ref.theta_max, rel=1e-6, abs=1e-12)
    assert r.u_max == pytest.approx(ref.u_max, rel=1e-6, abs=1e-12)
    assert r.u_end == pytest.approx(ref.u_end, rel=1e-6, abs=1e-12)
