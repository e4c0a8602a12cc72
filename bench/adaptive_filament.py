"""The map of issue 35 whose adaptive refinement missed a thin filament: adaptive against full, per class.

``rocking map --pulse mp --gamma-mp 2.5 --Omega 1 10 N --beta 1 10 N --directions negative``: the reference block
(docs/model.md section 9) alone and with the default damper of ``rocking map`` (gamma = 0.05, omega_m = p, zeta =
0.05, h = 0.05 m, the paper's unlimited guide), rtol = 1e-8, under Mavroeidis-Papageorgiou pulses of negative sign;
computed in process on the C back end, adaptive (the defaults of rocking.study.overturning_map) and with every
cell, each on fresh tiles with the same local workers. Prints the responses, wall and CPU time (the process's,
worker threads included) of each, the cells whose outcome class differs per part and per class of the full map,
the summary counts of both (overturned, saved, lost) and, where the map says them, the counts of cells inferred
rather than computed.

The figures are read from the maps' data only (``computed``, the outcomes), so the same script measures
an earlier version's adaptive map when run from its checkout.

    python bench/adaptive_filament.py -n 400 --json bench/adaptive-filament.json     # minutes on 2 cores
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time

import numpy as np
from machine import command_line, ended, machine

from rocking import Block
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import PARTS, envelope, outcome, overturning_map
from rocking.study.tiles import Execution

#: The pulse of the map: the Mavroeidis-Papageorgiou pulse of gamma_mp = 2.5, negative sign (issue 35).
GAMMA_MP, SIGN = 2.5, "negative"
#: The counts of a map's summary compared.
COUNTS = ("bare_overturned", "damper_overturned", "saved", "lost")


def classes(data) -> dict:
    """The outcome class of every cell, per part: :func:`rocking.study.overturning_map.outcome` of the envelope."""
    env = envelope(data)
    return {p: outcome(env["overturned"].sel(part=p).values, env["impacts"].sel(part=p).values) for p in PARTS}


def differences(adaptive, full) -> dict:
    """Per part, the cells whose class differs, by the full map's class (``"safe"``, ``"k impacts"``)."""
    got, want = classes(adaptive), classes(full)
    out = {}
    for p in PARTS:
        wrong = got[p] != want[p]
        values, counts = np.unique(want[p][wrong], return_counts=True)
        out[p] = {("safe" if v < 0 else f"{v} impacts"): int(c) for v, c in zip(values, counts)}
    effect = [envelope(d)["effect"].values for d in (adaptive, full)]
    out["effect"] = int((effect[0] != effect[1]).sum())
    return out


def compare(n: int, workers: int) -> dict:
    """The adaptive and the full map of ``n x n``, each on fresh tiles."""
    setting = Setting(Block.reference(), rtol=1e-8, pulse="mp", gamma_mp=GAMMA_MP)
    tuning = Tuning(0.05, 1.0, 0.05, 0.05)
    grids = Grid("Omega", 1.0, 10.0, n), Grid("beta", 1.0, 10.0, n)
    execution = Execution(workers=workers, progress=False)
    maps, out = {}, {"n": n, "workers": workers}
    with tempfile.TemporaryDirectory() as tmp:
        for name, how in (("adaptive", {}), ("full", {"full": True})):
            start, cpu = time.perf_counter(), time.process_time()
            study = overturning_map(setting, tuning, *grids, execution, runs=f"{tmp}/{name}", directions=SIGN, **how)
            maps[name] = study
            out[name] = {
                "seconds": time.perf_counter() - start,
                "cpu": time.process_time() - cpu,
                "responses": study.run["responses"],
                "rounds": study.run["rounds"],
                **{k: study.summary[k] for k in COUNTS},
                "inferred": {k: v for k, v in study.summary.items() if "inferred" in k or "possible" in k},
            }
    out["differences"] = differences(maps["adaptive"].data, maps["full"].data)
    return out


def report(r: dict) -> None:
    print(f"map of issue 35, {r['n']} x {r['n']}, MP pulse gamma_mp {GAMMA_MP}, {SIGN} ({r['workers']} workers):")
    for name in ("full", "adaptive"):
        m = r[name]
        counts = ", ".join(f"{k} {m[k]}" for k in COUNTS)
        print(
            f"  {name:8s} {m['responses']:8d} responses {m['seconds']:7.1f} s ({m['cpu']:.1f} s CPU) "
            f"{m['rounds']:3d} rounds; {counts}"
        )
    if r["adaptive"]["inferred"]:
        print(f"  adaptive, inferred: {r['adaptive']['inferred']}")
    d = r["differences"]
    print(f"  cells whose class differs: bare {d['bare']}, damper {d['damper']}; effect differs at {d['effect']}")


def table(result: dict) -> str:
    """The adaptive and the full map, one row each, and the cells whose class differs, as a Markdown table: the
    README's (bench/readme.py)."""
    rows = [
        "| map | responses | wall / CPU (s) | overturned alone / with the damper | saved | lost | cells differ |",
        "|---|---|---|---|---|---|---|",
    ]
    d = result["differences"]
    differ = sum(sum(d[p].values()) for p in PARTS)
    for name in ("adaptive", "full"):
        m = result[name]
        inferred = m["inferred"]
        lost = f"{m['lost']:,}"
        if name == "adaptive" and inferred:
            lost += f" ({m['lost'] - inferred['lost_inferred']:,} computed, up to {inferred['lost_possible']:,} more)"
        rows.append(
            f"| {name} | {m['responses']:,} | {m['seconds']:.1f} / {m['cpu']:.1f} | {m['bare_overturned']:,} / "
            f"{m['damper_overturned']:,} | {m['saved']:,} | {lost} | {differ if name == 'adaptive' else ''} |"
        )
    return "\n".join(rows)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=400, help="values of Omega and of beta (default 400)")
    parser.add_argument("--workers", type=int, default=2, help="local workers of both maps (default 2)")
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    started = machine()
    result = compare(args.n, args.workers)
    report(result)
    if args.json:
        result["command"] = command_line("adaptive_filament.py", argv)
        result["machine"] = started | ended()
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
