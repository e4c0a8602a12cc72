"""The bench map of `make bench`: the cases bench/run.py times and bench/instructions.py counts.

Issue 3's 50 x 50 map by default: Omega and beta in [1, 10], the reference block of docs/model.md
section 9, a damper with gamma = 0.05, omega_m = p, zeta = 0.05, h = 0.05, rtol = 1e-8.
"""

from __future__ import annotations

import numpy as np

from rocking import Block, Vertical
from rocking.sim.cases import pulse_cases

GAMMA, OMEGA_RATIO, ZETA, H_MASS = 0.05, 1.0, 0.05, 0.05


def map_cases(n: int, vertical_ratio: float = 0.0, floor=None):
    """The ``n x n`` map: the block, the flat ``Omega`` and ``beta`` of its cells, and their cases; with
    ``vertical_ratio`` > 0, every pulse with an in-phase vertical component of that ratio (rocking.Vertical);
    ``floor``: a rocking.Floor (None: the paper's, mu = inf)."""
    block = Block.reference()
    Omega, beta = np.meshgrid(np.linspace(1, 10, n), np.linspace(1, 10, n), indexing="ij")
    vertical = Vertical(vertical_ratio) if vertical_ratio > 0 else None
    cases = pulse_cases(
        block,
        Omega,
        beta,
        gamma=GAMMA,
        omega_ratio=OMEGA_RATIO,
        zeta=ZETA,
        h=H_MASS,
        rtol=1e-8,
        vertical=vertical,
        floor=floor,
    )
    return block, Omega.ravel(), beta.ravel(), cases
