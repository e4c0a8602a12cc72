"""rocking.simulate warns of implausible inputs as rocking simulate does: the same messages, from one place."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rocking
from rocking import PlausibilityWarning

BLOCK = rocking.Block.reference()
PULSE = rocking.OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0)
G = BLOCK.g


def _record(pga: float) -> rocking.SampledMotion:
    """A short record whose peak after scaling is ``pga`` (m/s^2)."""
    return rocking.SampledMotion(np.array([0.0, 2.0, -1.0, 0.0]), dt=0.01, scale=pga / 2.0)


def test_a_damper_heavier_than_half_the_block_warns():
    damper = rocking.Damper.from_nondim(BLOCK, gamma=0.6, omega_ratio=1.0, zeta=0.05, h=0.05)
    message = (
        "the damper's mass is 0.6 of the block's (gamma > 0.5): a damper heavier than half the block is a "
        "second body, not a damper; is m (or --gamma) right?"
    )
    with pytest.warns(PlausibilityWarning) as caught:
        rocking.simulate(BLOCK, damper, PULSE)
    assert [str(w.message) for w in caught] == [message]
    assert caught[0].filename == __file__  # attributed to the call of rocking.simulate, not to the package


def test_a_variant_damper_counts_every_mass_of_its_own():
    """A model's own parameters in kg are the damper's mass: the pendulum's m of 0.6 M warns."""
    params = {"m": 0.6 * BLOCK.M, "l": 0.5, "x_p": 0.0, "y_p": 2.55, "k_phi": 0.0, "c_phi": 5.5}
    with pytest.warns(PlausibilityWarning, match=r"^the damper's mass is 0\.6 of the block's"):
        rocking.simulate(BLOCK, params, PULSE, model="pendulum")


def test_a_record_scaled_past_the_largest_recorded_pga_warns():
    with pytest.warns(PlausibilityWarning) as caught:
        rocking.simulate(BLOCK, None, _record(5.1 * G), check="none")
    assert [str(w.message) for w in caught] == [
        "the motion's PGA is 5.1 g, above the largest ever recorded (4.36 g); is the scale right?"
    ]


def test_plausible_inputs_do_not_warn():
    """At the limits (gamma = 0.5, 4.36 g) and for a pulse, however strong: nothing to say."""
    damper = rocking.Damper.from_nondim(BLOCK, gamma=0.5, omega_ratio=1.0, zeta=0.05, h=0.05)
    strong = rocking.OneSinePulse.from_nondim(BLOCK, beta=100.0, Omega=4.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        rocking.simulate(BLOCK, damper, PULSE)
        rocking.simulate(BLOCK, None, _record(4.36 * G), check="none")
        rocking.simulate(BLOCK, None, strong)
