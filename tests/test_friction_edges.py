"""Edges of a floor with friction that once looped without end (the NumPy back end; docs/simulation.md, Phases)."""

import numpy as np
import pytest

import rocking
from rocking.sim.backends import BACKENDS

FRICTION_BACKENDS = tuple(name for name, backend in BACKENDS.items() if backend.friction)
BLOCK = rocking.Block(2.0, 0.5, 1000.0)  # tan(alpha) = 0.25


def _pulse(beta: float):
    return rocking.OneSinePulse.from_nondim(BLOCK, Omega=2 * np.pi / (0.5 * BLOCK.p), beta=beta)


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
def test_a_slip_that_starts_with_a_rocking_phase_gets_a_first_step_short_enough_to_grow(backend):
    """After an impact the stuck corner cannot hold (|F| > mu_s N) and slides; the rocking half-cycle's first step
    is too long for the slip, which would seem to stop at once: the step is shortened until it grows, as a lift-off
    (once: 37,475 slip episodes at one instant, then max_steps)."""
    r = rocking.simulate(BLOCK, None, _pulse(2.249231651376147), mu=0.2875, backend=backend, record=True)
    assert r.status == "rest" and r.slides == 2 and r.impacts >= 3
    kinds = list(r.events()["kind"])
    assert kinds[:6] == ["uplift", "slip", "stick", "impact", "slip", "stick"]


@pytest.mark.parametrize("backend", FRICTION_BACKENDS)
def test_a_base_sliding_on_mu_equal_to_tan_alpha_does_not_lift_on_rounding(backend):
    """mu_k = tan(alpha): a sliding base's uplift margin is 0 up to rounding for the whole slip; it is no uplift
    (once: uplift, no lift, uplift... at one instant, then max_steps)."""
    r = rocking.simulate(BLOCK, None, _pulse(2.34919750254842), mu=0.25, backend=backend)
    assert r.status == "rest" and r.theta_max < 1e-12 and r.u_max > 0.05


def test_both_back_ends_record_the_same_floor_columns():
    """The floor's N and F at each row: the same columns, in the same order, the same values to the tolerance."""
    runs = {
        backend: rocking.simulate(BLOCK, None, _pulse(2.2), mu=0.26, backend=backend, rtol=1e-10, record=True)
        for backend in ("c", "numpy")
    }
    c, n = runs["c"].history, runs["numpy"].history
    assert list(c) == list(n) and list(c)[-8:] == ["u", "du", "N", "F", "slide", "v", "dv", "fly"]
    assert np.array_equal(c["slide"], n["slide"])
    scale = float(np.max(np.abs(n["N"])))
    assert np.max(np.abs(c["N"] - n["N"])) < 1e-6 * scale and np.max(np.abs(c["F"] - n["F"])) < 1e-6 * scale


@pytest.mark.parametrize(
    "ground, message",
    [
        ({"friction": "yes"}, r"^spec: ground friction must be true or false"),
        ({"friction": 1}, r"^spec: ground friction must be true or false"),
        ({"frictoin": True}, r"frictoin"),
        ("friction", r"ground"),
    ],
)
def test_a_specs_ground_table_takes_booleans_and_known_keys_only(ground, message):
    """A spec from a stranger: a wrong [ground] entry is refused in one line (nothing derived)."""
    from rocking.derive.spec import SpecError, parse_spec

    with pytest.raises(SpecError, match=message):
        parse_spec({"name": "floored", "ground": ground})


def test_a_finite_floor_on_a_model_without_its_phases_is_refused_in_one_line():
    with pytest.raises(rocking.ParameterError, match=r"has no phases of a floor with friction"):
        pendulum = {"m": 20.0, "l": 0.5, "x_p": 0.0, "y_p": 1.5, "k_phi": 10.0, "c_phi": 1.0}
        rocking.simulate(BLOCK, pendulum, _pulse(2.0), mu=0.3, model="pendulum")
