"""What a stochastic motion costs to make, against what its responses cost on C (issue 28, target 4).

For ``N`` motions of the default site model (rocking.model.stochastic.DEFAULT_SITE, one seed): the CPU
time to make each (``Suite.motion``: the noise, its time-varying filter, the modulating function and the
high-pass filter), and the CPU time of the responses a fragility level asks of it (the reference block
with the README's damper, both directions, scaled to a PGA of 3 g tan(alpha), ``check="none"``, C back
end). The first motion is made apart: it builds the site's kernel, kept for the others. Process CPU
time (``time.process_time``), so a busy machine slows both sides alike.

Usage::

    python bench/motions.py [N]
"""

from __future__ import annotations

import sys
import time

import numpy as np

import rocking
from rocking.model.stochastic import DEFAULT_SITE
from rocking.study.suite import Suite


def main(n: int = 20) -> None:
    block = rocking.Block.reference()
    damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    suite = Suite.stochastic(DEFAULT_SITE, n + 1, seed=1)
    start = time.process_time()
    suite.motion(0)
    first = time.process_time() - start
    making, running = [], []
    for i in range(1, n + 1):
        start = time.process_time()
        motion = suite.motion(i)
        making.append(time.process_time() - start)
        motion = motion.scaled_to_pga(3 * block.g * block.tan_alpha)
        start = time.process_time()
        for directed in (motion, _mirrored(motion)):
            rocking.simulate(block, damper, directed, check="none")
        running.append(time.process_time() - start)
    make, run = float(np.median(making)), float(np.median(running))
    print(
        f"{n} stochastic motions of {DEFAULT_SITE.times.size} samples: the first (the site's kernel) "
        f"{first * 1e3:.1f} ms; each other {make * 1e3:.2f} ms (median) to make, {run * 1e3:.2f} ms for its two "
        f"responses on C; making / running = {make / run:.2f}"
    )


def _mirrored(motion: rocking.SampledMotion) -> rocking.SampledMotion:
    """The motion in the other direction."""
    return rocking.SampledMotion(motion.a, dt=motion.dt, scale=motion.scale, sign=-motion.sign)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20)
