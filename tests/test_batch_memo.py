"""A C batch keeps what a run prepares from its parameters (sim.c's memo_prepared: the constants about either
pivot, E(0), the normal force's bound, the base's width) from one run to the next of the same parameters. A batch
whose cases alternate between dampers gives each case what it gives alone, bit for bit, in lanes or not."""

from __future__ import annotations

import numpy as np
import pytest

from rocking import Block
from rocking.sim.cases import pulse_cases, run_cases

BLOCK = Block.reference()
FIELDS = ("status", "overturned", "impacts", "uplifts", "flights", "theta_max", "x_max", "t_end", "jump_max")


@pytest.mark.parametrize("lanes", [False, True], ids=["scalar", "lanes"])
def test_cases_of_alternating_parameters_run_in_one_batch_as_alone(lanes):
    Omega = np.array([1.5, 2.0, 3.0, 4.5, 1.5, 2.0, 6.0, 2.5])
    beta = np.array([14.5, 12.5, 3.0, 5.0, 14.5, 12.5, 9.0, 1.5])
    gamma = np.array([0.05, 0.2, 0.05, 0.2, 0.2, 0.05, 0.02, 0.2])  # each run's damper differs from the last's
    batch = run_cases(pulse_cases(BLOCK, Omega, beta, gamma=gamma), "c", 1, lanes=lanes)
    for i in range(len(Omega)):
        alone = run_cases(
            pulse_cases(BLOCK, Omega[i : i + 1], beta[i : i + 1], gamma=gamma[i : i + 1]), "c", 1, lanes=lanes
        )
        for name in FIELDS:
            assert batch[name][i] == alone[name][0], (i, name)
    assert batch["flights"].sum() >= 1  # the normal force's bound decided somewhere
