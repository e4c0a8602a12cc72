"""What each coarse and verification step of an adaptive map costs and misses, on every map of the benches.

Each map is computed once with every cell (``--full``, on the C back end, in process); then the refinement of
rocking.study.adaptive (``refine``) runs on each part's classes of that map for each pair of steps asked for, as
``rocking map --coarse C --verify V`` would: a response's class does not depend on which cells are computed with
it, so the cells the refinement asks for, and the classes it fills in, are those of the adaptive map. Prints per
map and pair the responses (parts and directions), the full map's over them, the share that are the edges of the
coarse blocks (rocking.study.adaptive.line_mask, the price of the guarantee) and the cells whose class differs
from the full map's (per part, any direction: the misclassified cells of bench/adaptive.py); then per pair, over
all maps, the fewest-fold saving and the cells that differ.

The maps: those of bench/adaptive.py (the bench block and damper, 400 x 400, the five pulse families, with the
paper's unlimited guide and with stops, both directions), of its 1000 x 1000 run (sine, Ricker) and of
bench/adaptive_filament.py (issue 35's Mavroeidis-Papageorgiou map, negative direction).

    python bench/adaptive_steps.py --cache out/full-classes --json bench/adaptive-steps.json   # ~15 min on 2 cores
    python bench/adaptive_steps.py --maps 400 --steps 16/16 32/16     # some maps, some steps
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from adaptive import GAMMA, GAMMA_MP, H_MASS, OMEGA_RATIO, ZETA
from machine import command_line, ended, machine

from rocking import Block
from rocking.study.adaptive import check_coarse, check_verify, line_mask, refine
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import overturning_map, response_classes
from rocking.study.tiles import Execution

#: The maps, by group: (name, n, pulse, gamma_mp, stops, directions).
MAPS = {
    "400": [
        (f"{pulse}{'-stops' if stops else ''}-400", 400, pulse, GAMMA_MP, stops, "auto")
        for pulse in ("sine", "cosine", "ricker", "ricker_anti", "mp")
        for stops in (False, True)
    ],
    "1000": [(f"{pulse}-1000", 1000, pulse, GAMMA_MP, False, "auto") for pulse in ("sine", "ricker")],
    "filament": [("filament-mp-2.5-negative-400", 400, "mp", 2.5, False, "negative")],
}


#: The pairs of steps measured by default: the map's default (16 / 16), coarser ones, and no verification.
STEPS = ("16/16", "32/16", "32/32", "64/32", "16/0")


def full_classes(n: int, pulse: str, gamma_mp: float, stops: bool, directions: str, workers: int) -> tuple:
    """The classes (``(part, Omega, beta, sign)``) of every cell of the map, computed whole; and its seconds."""
    setting = Setting(Block.reference(), rtol=1e-8, pulse=pulse, **({"gamma_mp": gamma_mp} if pulse == "mp" else {}))
    tuning = Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS, stops=stops)
    grids = Grid("Omega", 1.0, 10.0, n), Grid("beta", 1.0, 10.0, n)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        study = overturning_map(
            setting,
            tuning,
            *grids,
            Execution(workers=workers, progress=False),
            runs=tmp,
            full=True,
            directions=directions,
        )
    data = study.data.transpose("part", "Omega", "beta", "sign")
    arrays = [data[k].values for k in ("overturned", "impacts", "status")]
    classes = np.stack([response_classes(*(a[p] for a in arrays)) for p in range(arrays[0].shape[0])])
    return classes, time.perf_counter() - start


def steps_of(text: str) -> tuple[int, int]:
    """``"C/V"`` as the coarse step and the first verification step, checked as the map checks them."""
    coarse, verify = (int(v) for v in text.split("/"))
    coarse = check_coarse(coarse)
    return coarse, check_verify(verify, coarse)


def adaptive(classes: np.ndarray, coarse: int, verify: int) -> dict:
    """The adaptive refinement of each part of the full map's ``classes``: responses, edges, cells that differ."""
    responses = edges = differ = 0
    signs = classes.shape[-1]
    for part in classes:
        got, computed, _ = refine(lambda rows, cols, part=part: part[rows, cols], part.shape, coarse, verify)
        responses += signs * int(computed.sum())
        edges += signs * int((computed & line_mask(computed.shape, coarse)).sum()) if verify else 0
        differ += int((got != part).any(axis=-1).sum())
    full = classes.size
    return {"responses": responses, "ratio": full / responses, "edge_responses": edges, "differ": differ}


def promise(coarse: int, verify: int) -> str:
    """What a map of these steps guarantees to find, whole (rocking.study.adaptive.guarantee, in cells)."""
    if not verify:
        return "nothing (unverified)"
    held = "" if verify == coarse else f", or holding {verify} x {verify} cells"
    return f"every region extending over {coarse} cells along an axis{held}"


def table(results: list[dict]) -> str:
    """Per pair of steps, over all the maps: what it guarantees, the responses it saves (the fewest-fold, on which
    map; the median) and the cells that differ from the full maps, as a Markdown table: the README's
    (bench/readme.py)."""
    rows = [
        "| coarse / verify | found whole, whatever the map | fewer responses than full: least (map), median | "
        "cells that differ, all maps |",
        "|---|---|---|---|",
    ]
    for pair in dict.fromkeys((r["coarse"], r["verify"]) for r in results):
        chosen = [r for r in results if (r["coarse"], r["verify"]) == pair]
        worst = min(chosen, key=lambda r: r["ratio"])
        median = float(np.median([r["ratio"] for r in chosen]))
        rows.append(
            f"| {pair[0]} / {pair[1]} | {promise(*pair)} | {worst['ratio']:.1f}x ({worst['map']}), {median:.1f}x | "
            f"{sum(r['differ'] for r in chosen)} |"
        )
    return "\n".join(rows)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--steps", nargs="+", default=["16/16", "32/16", "32/32", "64/32", "16/0"], help="coarse/verify pairs"
    )
    parser.add_argument("--maps", nargs="+", choices=MAPS, default=list(MAPS), help="groups of maps (all)")
    parser.add_argument("--workers", type=int, default=2, help="local workers of the full maps (default 2)")
    parser.add_argument("--cache", help="a folder keeping each full map's classes: a rerun reads them")
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    started, pairs = machine(), [steps_of(text) for text in args.steps]
    results = []
    for name, n, pulse, gamma_mp, stops, directions in (m for group in args.maps for m in MAPS[group]):
        cached = Path(args.cache, f"{name}.npy") if args.cache else None
        if cached is not None and cached.exists():
            classes, seconds = np.load(cached), 0.0
        else:
            classes, seconds = full_classes(n, pulse, gamma_mp, stops, directions, args.workers)
            if cached is not None:
                cached.parent.mkdir(parents=True, exist_ok=True)
                np.save(cached, classes)
        print(f"{name}: full map {classes.size:,} responses ({seconds:.0f} s)", flush=True)
        for coarse, verify in pairs:
            r = {"map": name, "coarse": coarse, "verify": verify} | adaptive(classes, coarse, verify)
            print(
                f"  coarse {coarse:3d} verify {verify:3d}: {r['responses']:9,} responses ({r['ratio']:5.1f}x fewer), "
                f"edges {r['edge_responses']:8,}, cells differ {r['differ']}",
                flush=True,
            )
            results.append(r)
    print(f"\n{table(results)}")
    if args.json:
        record = {"command": command_line("adaptive_steps.py", argv), "machine": started | ended(), "maps": results}
        with open(args.json, "w") as f:
            json.dump(record, f, indent=2)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
