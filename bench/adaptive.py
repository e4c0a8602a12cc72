"""Adaptive against full: maps of the bench block and damper, both directions, computed both ways.

The map of `make bench` (Omega and beta in [1, 10], the reference block of docs/model.md section 9, a damper
with gamma = 0.05, omega_m = p, zeta = 0.05, h = 0.05 m, rtol = 1e-8), n x n (default 400), as
``rocking map`` computes it: adaptive (coarse step 16, verified from step 16, rocking.study.adaptive) and with
every cell (--full), each on fresh tiles with the same local workers; for each pulse family asked for (the
Mavroeidis-Papageorgiou pulse with gamma_mp = 2), with the paper's unlimited guide and/or with stops. Prints,
per map, the responses each computed, its wall time, the ratios, and the cells whose classification differs:
the outcome of every cell (the envelope of the directions and each direction), the responses without a
verdict and the damper's effect.

    python bench/adaptive.py                 # 400 x 400 one-sine map: a minute or two on 2 cores
    python bench/adaptive.py -n 200 --json out/adaptive.json
    python bench/adaptive.py --pulses sine cosine ricker ricker_anti mp --stops both   # the matrix
    python bench/adaptive.py --verify 16 0     # verified and not, against the same full map
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from itertools import product

from machine import command_line, ended, machine

from rocking import Block
from rocking.study.adaptive import COARSE
from rocking.study.config import PULSES, Grid, Setting, Tuning
from rocking.study.overturning_map import envelope, outcome, overturning_map, undetermined
from rocking.study.tiles import Execution

GAMMA, OMEGA_RATIO, ZETA, H_MASS = 0.05, 1.0, 0.05, 0.05
#: The oscillations of the Mavroeidis-Papageorgiou pulse of the matrix.
GAMMA_MP = 2.0
#: The guides of --stops: the paper's unlimited one, the stops at the block's edges.
GUIDES = {"no": (False,), "yes": (True,), "both": (False, True)}


def misclassified(adaptive, full) -> int:
    """Cells (per part and direction, and of the effect) whose class differs between two maps' data."""
    envelopes = [envelope(data) for data in (adaptive, full)]
    wrong = int((envelopes[0]["effect"] != envelopes[1]["effect"]).sum())
    for pair in ((adaptive, full), envelopes):
        got, want = (outcome(data["overturned"].values, data["impacts"].values) for data in pair)
        unknown = [undetermined(data["status"].values) for data in pair]
        wrong += int(((got != want) | (unknown[0] != unknown[1])).sum())
    return wrong


def setting_of(pulse: str) -> Setting:
    """The bench setting with the pulse family ``pulse``."""
    return Setting(Block.reference(), rtol=1e-8, pulse=pulse, **({"gamma_mp": GAMMA_MP} if pulse == "mp" else {}))


def compare(n: int, workers: int, coarse: int, verifies=(None,), pulse: str = "sine", stops: bool = False) -> list:
    """The full map of ``n x n`` and an adaptive one per verification step of ``verifies`` (None: the default),
    each on fresh tiles: per adaptive map, the responses, seconds and misclassified cells of both."""
    setting, tuning = setting_of(pulse), Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS, stops=stops)
    grids = Grid("Omega", 1.0, 10.0, n), Grid("beta", 1.0, 10.0, n)
    execution = Execution(workers=workers, progress=False)

    def timed(runs: str, **how) -> tuple:
        start = time.perf_counter()
        study = overturning_map(setting, tuning, *grids, execution, runs=runs, **how)
        return study, time.perf_counter() - start

    with tempfile.TemporaryDirectory() as tmp:
        full, full_seconds = timed(f"{tmp}/full", full=True)
        results = []
        for k, verify in enumerate(verifies):
            adaptive, seconds = timed(f"{tmp}/adaptive-{k}", coarse=coarse, verify=verify)
            out = {
                "n": n,
                "workers": workers,
                "coarse": coarse,
                "pulse": pulse,
                "stops": stops,
                "verify": adaptive.config["refinement"]["verify"],
                "rounds": adaptive.run["rounds"],
                "adaptive_seconds": seconds,
                "adaptive_responses": adaptive.run["responses"],
                "full_seconds": full_seconds,
                "full_responses": full.run["responses"],
            }
            out["response_ratio"] = out["full_responses"] / out["adaptive_responses"]
            out["speedup"] = out["full_seconds"] / out["adaptive_seconds"]
            out["misclassified"] = misclassified(adaptive.data, full.data)
            both = envelope(full.data)
            out["cells_overturned_bare"] = int(both["overturned"].sel(part="bare").sum())
            out["cells_saved"] = int((both["effect"] > 0).sum())
            results.append(out)
    return results


def report(r: dict) -> None:
    n, guide = r["n"], "stops" if r["stops"] else "unlimited guide"
    print(
        f"adaptive map, {n}x{n}, {r['pulse']} pulse, {guide} (block alone + damper, both directions, "
        f"{r['workers']} workers):"
    )
    print(f"  full          {r['full_responses']:10d} responses  {r['full_seconds']:8.1f} s")
    print(
        f"  adaptive      {r['adaptive_responses']:10d} responses  {r['adaptive_seconds']:8.1f} s   "
        f"(coarse step {r['coarse']}, verified from step {r['verify']}, {r['rounds']} rounds)"
    )
    print(
        f"  {r['response_ratio']:.1f}x fewer responses, {r['speedup']:.1f}x faster; "
        f"classification {'identical' if r['misclassified'] == 0 else 'DIFFERENT'} "
        f"({r['misclassified']} cells differ)",
        flush=True,
    )


def table(results: list[dict]) -> str:
    """One row per map, as a Markdown table: the README's (bench/readme.py)."""
    rows = [
        "| pulse | guide | verify | cells differ | responses adaptive / full | wall adaptive / full (s) |",
        "|---|---|---|---|---|---|",
    ]
    for r in results:
        guide = "stops" if r["stops"] else "unlimited"
        rows.append(
            f"| {r['pulse']} | {guide} | {r['verify']} | {r['misclassified']} | "
            f"{r['adaptive_responses']:,} / {r['full_responses']:,} ({r['response_ratio']:.1f}x fewer) | "
            f"{r['adaptive_seconds']:.1f} / {r['full_seconds']:.1f} ({r['speedup']:.1f}x) |"
        )
    return "\n".join(rows)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=400, help="values of Omega and of beta (default 400)")
    parser.add_argument("--workers", type=int, default=2, help="local workers of both maps (default 2)")
    parser.add_argument("--coarse", type=int, default=COARSE, help=f"coarse step (default {COARSE})")
    parser.add_argument(
        "--verify",
        type=int,
        nargs="+",
        default=[None],
        help="first steps of the verification, an adaptive map each, 0: none (default: coarse)",
    )
    parser.add_argument("--pulses", nargs="+", default=["sine"], choices=PULSES, help="pulse families (sine)")
    parser.add_argument("--stops", choices=GUIDES, default="no", help="with stops: no (default), yes or both")
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    started = machine()
    results = []
    for pulse, stops in product(args.pulses, GUIDES[args.stops]):
        for result in compare(args.n, args.workers, args.coarse, args.verify, pulse, stops):
            report(result)
            results.append(result)
    if len(results) > 1:
        print(f"\n{table(results)}")
    if args.json:
        command = command_line("adaptive.py", argv)
        with open(args.json, "w") as f:
            json.dump({"command": command, "machine": started | ended(), "maps": results}, f, indent=2)
            f.write("\n")
    return 0 if all(r["misclassified"] == 0 for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
