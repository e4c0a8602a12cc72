"""How many responses to records depend on the tolerance, and what the check costs (issue 25, item 1).

For a stochastic suite (the default site model, ``N`` motions of one seed) scaled to PGAs of 1.5, 3
and 6 times the uplift threshold ``g tan(alpha)``, in both directions, with and without the README's
damper, on the reference block and on the issue's eccentric one: at each ``rtol``, the fraction of
responses that the tolerance check marks sensitive (docs/simulation.md, "Sensitivity to the
tolerance"), and the wall time of the whole set with ``check="none"`` and with
``check="tolerance"`` (one run of each, on the C back end). Then the white-noise case of the issue
at each tolerance, on both back ends; and a fragility of 20 stochastic motions at 4 PGA levels with
and without the check.

Usage::

    python bench/sensitivity.py [N]
"""

from __future__ import annotations

import dataclasses
import sys
import tempfile
import time

import numpy as np

import rocking
from rocking.model.stochastic import DEFAULT_SITE
from rocking.study import ida
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.suite import Suite
from rocking.study.tiles import Execution

PGA_OVER_UPLIFT = (1.5, 3.0, 6.0)
TOLERANCES = (1e-6, 1e-8, 1e-10)
#: The eccentric block of the issue's white-noise case.
ISSUE_BLOCK = rocking.Block(H=3.1597847506851258, B=0.9313975019469038, M=131.3667739110528, e=-0.16218004607891312)


def responses(motions, block, dampers, rtol: float, check: str) -> tuple[list, float]:
    """Every response of ``motions`` (both signs) with every damper, and the wall time they took."""
    start = time.perf_counter()
    out = [
        rocking.simulate(block, damper, dataclasses.replace(motion, sign=sign), backend="c", rtol=rtol, check=check)
        for motion in motions
        for sign in (1, -1)
        for damper in dampers
    ]
    return out, time.perf_counter() - start


def suite_figures(n: int, block, name: str) -> None:
    """The fraction sensitive and the cost of the check on ``n`` stochastic motions, at each tolerance."""
    damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    suite = Suite.stochastic(DEFAULT_SITE, n, seed=1)
    uplift = block.g * block.tan_alpha
    motions = [suite.motion(i).scaled_to_pga(k * uplift) for i in range(n) for k in PGA_OVER_UPLIFT]
    print(
        f"{n} stochastic motions x {len(PGA_OVER_UPLIFT)} PGAs x 2 signs x (bare, damper) = {4 * len(motions)} "
        f"responses; {name} block, C back end"
    )
    for rtol in TOLERANCES:
        plain, t_plain = responses(motions, block, (None, damper), rtol, "none")
        checked, t_checked = responses(motions, block, (None, damper), rtol, "tolerance")
        sensitive = np.array([r.sensitive for r in checked])
        moved = np.array([a.overturned != b.overturned for a, b in zip(plain, checked, strict=True)])
        impacts = np.array([r.impacts for r in plain])
        print(
            f"rtol {rtol:.0e}: sensitive {sensitive.mean():.1%} ({sensitive.sum()}), verdict changed "
            f"{moved.mean():.1%}; among > 100 impacts {sensitive[impacts > 100].mean():.1%} of "
            f"{(impacts > 100).sum()}; time {t_plain:.2f} s without the check, {t_checked:.2f} s with "
            f"(x{t_checked / t_plain:.1f})"
        )


def white_noise() -> None:
    """The issue's case at each tolerance, on both back ends: theta_max [rad], sensitive, time [s]."""
    block = ISSUE_BLOCK
    rng = np.random.default_rng(36630)
    motion = rocking.SampledMotion(rng.normal(0, 2.0, 1000), dt=0.02, scale=1.1631753337122157, sign=-1)
    for backend in ("c", "numpy"):
        for rtol in (1e-6, 1e-7, 1e-8, 1e-9, 1e-10):
            start = time.perf_counter()
            plain = rocking.simulate(block, None, motion, backend=backend, rtol=rtol, check="none")
            middle = time.perf_counter()
            checked = rocking.simulate(block, None, motion, backend=backend, rtol=rtol)
            end = time.perf_counter()
            print(
                f"white noise, {backend}, rtol {rtol:.0e}: theta_max {plain.theta_max:.4f} rad unchecked, "
                f"{checked.theta_max:.4f} checked, sensitive {checked.sensitive}; "
                f"{middle - start:.3f} s / {end - middle:.3f} s"
            )


def fragility_cost(n: int = 20) -> None:
    """Wall time of a fragility of ``n`` stochastic motions at 4 PGA levels, with the check and without."""
    block = rocking.Block.reference()
    uplift = block.g * block.tan_alpha
    levels = Grid("pga", 1.5 * uplift, 6.0 * uplift, 4)
    suite = Suite.stochastic(DEFAULT_SITE, n, seed=1)
    for label in ("with", "without"):
        if label == "without":
            # The study has no switch: a tighter tolerance equal to rtol is what skips the second run.
            ida.tighter_rtol = lambda rtol: rtol
        with tempfile.TemporaryDirectory() as runs:
            start = time.perf_counter()
            study = ida.incremental_dynamic_analysis(
                Setting(block),
                Tuning(0.05),
                suite,
                levels,
                Execution(workers=1, progress=False),
                measure_name="pga",
                runs=runs,
            )
            elapsed = time.perf_counter() - start
        counts = {part: int(study.data["sensitive_responses"].sel(part=part).sum()) for part in ("bare", "damper")}
        print(f"fragility, {study.run['responses']} responses, {label} the check: {elapsed:.2f} s; sensitive {counts}")


if __name__ == "__main__":
    for block, name in ((rocking.Block.reference(), "reference"), (ISSUE_BLOCK, "the issue's eccentric")):
        suite_figures(int(sys.argv[1]) if len(sys.argv) > 1 else 30, block, name)
    white_noise()
    fragility_cost()
