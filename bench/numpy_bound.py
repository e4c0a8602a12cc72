"""The NumPy back end's bound on its work (docs/simulation.md, rule 5; issue 23, item 3).

Times, on both back ends, the runs of the issue that the NumPy back end now refuses up front (a
one-cosine of period 1,000 s, a 20,000-sample record) and the slowest runs it still takes on: for
two blocks, with and without the damper, recorded or not, the longest one-cosine (below the uplift
threshold: full contact throughout, the most contact steps) and the longest record of 0.01 s samples
whose planned work (``numpy_backend.planned_work``) is within ``PLANNED_WORK_LIMIT``.

Usage::

    python bench/numpy_bound.py
"""

from __future__ import annotations

import time

import numpy as np

import rocking
from rocking.sim import numpy_backend
from rocking.sim.problem import make_problem


def timed(block, damper, motion, backend: str, record: bool) -> tuple[float, float, str]:
    """Wall and CPU seconds of one run, and its status (or the refusal)."""
    wall, cpu = time.perf_counter(), time.process_time()
    try:
        status = rocking.simulate(block, damper, motion, backend=backend, record=record).status
    except rocking.ParameterError:
        status = "refused"
    return time.perf_counter() - wall, time.process_time() - cpu, status


def longest_accepted(make, low: float, high: float, record: bool) -> float:
    """The largest length ``x`` in ``[low, high]`` whose run ``make(x)`` the NumPy back end takes on (bisection)."""
    for _ in range(40):
        middle = 0.5 * (low + high)
        try:
            numpy_backend.check_planned_work(make_problem(*make(middle)), record)
            low = middle
        except rocking.ParameterError:
            high = middle
    return low


def _runs(block, damper, record: bool):
    """The longest one-cosine and record of ``block`` (with ``damper``) that the NumPy back end takes on."""
    noise = np.random.default_rng(1).normal(0.0, 1.0, 20_000)
    a_g = 0.3 * block.g * block.tan_alpha  # below the uplift: full contact throughout, the most contact steps

    def cosine(T):
        return block, damper, rocking.OneCosinePulse.from_period(a_g, T)

    def sampled(n):
        return block, damper, rocking.SampledMotion(a_g * noise[: int(n)], dt=0.01)

    T = longest_accepted(cosine, 1.0, 1000.0, record)
    n = int(longest_accepted(sampled, 2, noise.size, record))
    return (f"one-cosine T_g = {T:.0f} s", cosine(T)), (f"record of {n} samples", sampled(n))


def cases():
    """``(name, (block, damper, motion), record)`` of the runs to time."""
    reference = rocking.Block.reference()
    long_cosine = rocking.OneCosinePulse.from_period(2.0, 1e3)
    long_record = rocking.SampledMotion(np.random.default_rng(1).normal(0.0, 1.0, 20_000), dt=0.01)
    yield "issue: one-cosine T_g = 1000 s, recorded", (reference, None, long_cosine), True
    yield "issue: record of 20,000 samples", (reference, None, long_record), False
    for H, B in ((2.0, 0.5), (0.2, 0.1)):
        block = rocking.Block(H=H, B=B, M=1000.0)
        for damper in (None, rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, h=0.05)):
            for record in (True, False):
                what = f"H={H} B={B} {'damper' if damper else 'bare'}{', recorded' if record else ''}"
                for name, args in _runs(block, damper, record):
                    yield f"{what}: {name}", args, record


def main() -> int:
    worst = (0.0, 0.0)
    for name, args, record in cases():
        c_wall, _, c_status = timed(*args, "c", record)
        wall, cpu, status = timed(*args, "numpy", record)
        if status != "refused":
            worst = max(worst, (wall, cpu))
        numpy = f"NumPy {wall:6.2f} s (CPU {cpu:5.2f} s) {status}"
        print(f"{name:55s} C {c_wall:6.3f} s {c_status:10s} {numpy}", flush=True)
    print(f"slowest NumPy run taken on: {worst[0]:.2f} s (CPU {worst[1]:.2f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
