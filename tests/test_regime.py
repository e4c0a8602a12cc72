"""The regime of the end stops is an input of the generated functions (docs/model.md section 11)."""

from __future__ import annotations

import pytest

from rocking import load_model

#: The paper's reference block and damper with bumpers at x = +-0.2 m; the state is 5 mm into the lower one.
PARAMS = dict(M=1000.0, I_G=354.2, B=0.5, H=2.0, e=0.025, g=9.81, m=50.0, h=0.05, k_m=2000.0, c=30.0)
PARAMS.update(L=0.2, k_b=7.2e6, c_b=7.6e3)
STATE = dict(theta=0.01, x=-0.205, dtheta=0.3, dx=-0.4)
REGIME_FUNCTIONS = ("forcing", "rocking_accel", "contact_accel", "uplift", "energy", "power")


def _call(name, stop_on=None, **over):
    model = load_model("omd_stops")
    params = {**PARAMS, **over}
    out = getattr(model.functions, name)(
        1.0, *(STATE[k] for k in model.state), 2.0, 0.0, *(params[k] for k in model.parameters), stop_on=stop_on
    )
    return out if isinstance(out, tuple) else (out,)


@pytest.mark.parametrize("name", REGIME_FUNCTIONS)
def test_without_a_regime_a_function_takes_that_of_its_state(name):
    """The lower side (index 1) acts: its penetration -x - L is > 0."""
    assert _call(name) == _call(name, stop_on=(0.0, 1.0))


@pytest.mark.parametrize("name", REGIME_FUNCTIONS)
def test_a_clear_regime_is_the_free_guide(name):
    """With no side acting, the bumpers are gone wherever the mass is."""
    assert _call(name, stop_on=(0.0, 0.0)) == pytest.approx(_call(name, k_b=0.0, c_b=0.0), rel=1e-14, abs=1e-12)


def test_the_regime_does_not_reach_the_penetrations_and_forces():
    """stop_gaps and stop_forces read the state alone: a runtime decides the events and the force with them."""
    for name in ("stop_gaps", "stop_forces"):
        assert _call(name, stop_on=(1.0, 0.0)) == _call(name)
