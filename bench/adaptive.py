"""Adaptive against full: the bench map, the block alone and with its damper, both directions, computed both ways.

The map of `make bench` (Omega and beta in [1, 10], the reference block of docs/model.md section 9, a damper
with gamma = 0.05, omega_m = p, zeta = 0.05, h = 0.05 m, rtol = 1e-8), n x n (default 400), as
``rocking map`` computes it: adaptive (coarse step 16, rocking.study.adaptive) and with every cell (--full),
each on fresh tiles with the same local workers. Prints the responses each computed, its wall time, the
ratios, and whether the classification is identical: the outcome of every cell (the envelope of the
directions and each direction), the responses without a verdict and the damper's effect.

    python bench/adaptive.py                 # 400 x 400: some minutes on 2 cores
    python bench/adaptive.py -n 200 --json out/adaptive.json
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time

from rocking import Block
from rocking.study.adaptive import COARSE
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import outcome, overturning_map, undetermined
from rocking.study.tiles import Execution

GAMMA, OMEGA_RATIO, ZETA, H_MASS = 0.05, 1.0, 0.05, 0.05


def misclassified(adaptive: dict, full: dict) -> int:
    """Cells (per part and direction, and of the effect) whose class differs between two maps' arrays."""
    wrong = int((adaptive["effect"] != full["effect"]).sum())
    for part in ("bare", "damper"):
        for suffix in ("", "_by_sign"):
            got, want = (outcome(a[f"{part}_overturned{suffix}"], a[f"{part}_impacts{suffix}"])
                         for a in (adaptive, full))  # fmt: skip
            unknown = [undetermined(a[f"{part}_status{suffix}"]) for a in (adaptive, full)]
            wrong += int(((got != want) | (unknown[0] != unknown[1])).sum())
    return wrong


def compare(n: int, workers: int, coarse: int) -> dict:
    """Both maps of ``n x n`` on fresh tiles: responses, seconds, misclassified cells."""
    setting, tuning = Setting(Block.reference(), rtol=1e-8), Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS)
    grids = Grid("Omega", 1.0, 10.0, n), Grid("beta", 1.0, 10.0, n)
    execution = Execution(workers=workers, progress=False)
    out = {"n": n, "workers": workers, "coarse": coarse}
    studies = {}
    with tempfile.TemporaryDirectory() as tmp:
        for kind, how in (("adaptive", {"coarse": coarse}), ("full", {"full": True})):
            start = time.perf_counter()
            studies[kind] = overturning_map(setting, tuning, *grids, execution, runs=f"{tmp}/{kind}", **how)
            out[f"{kind}_seconds"] = time.perf_counter() - start
            out[f"{kind}_responses"] = studies[kind].run["responses"]
    out["rounds"] = studies["adaptive"].run["rounds"]
    out["response_ratio"] = out["full_responses"] / out["adaptive_responses"]
    out["speedup"] = out["full_seconds"] / out["adaptive_seconds"]
    out["misclassified"] = misclassified(studies["adaptive"].arrays, studies["full"].arrays)
    out["cells_overturned_bare"] = int(studies["full"].arrays["bare_overturned"].sum())
    out["cells_saved"] = int((studies["full"].arrays["effect"] > 0).sum())
    return out


def report(r: dict) -> None:
    n = r["n"]
    print(f"adaptive map, {n}x{n} bench map (block alone + damper, both directions, {r['workers']} workers):")
    print(f"  full          {r['full_responses']:10d} responses  {r['full_seconds']:8.1f} s")
    print(f"  adaptive      {r['adaptive_responses']:10d} responses  {r['adaptive_seconds']:8.1f} s   "
          f"(coarse step {r['coarse']}, {r['rounds']} rounds)")  # fmt: skip
    print(f"  {r['response_ratio']:.1f}x fewer responses (target >= 10), {r['speedup']:.1f}x faster (target >= 8); "
          f"classification {'identical' if r['misclassified'] == 0 else 'DIFFERENT'} "
          f"({r['misclassified']} cells differ)")  # fmt: skip


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=400, help="values of Omega and of beta (default 400)")
    parser.add_argument("--workers", type=int, default=2, help="local workers of both maps (default 2)")
    parser.add_argument("--coarse", type=int, default=COARSE, help=f"coarse step (default {COARSE})")
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    result = compare(args.n, args.workers, args.coarse)
    report(result)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
    return 0 if result["misclassified"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
