"""Adaptive against full beta scans: the bench spectrum, the block alone and with its damper, both directions.

The spectrum of ``rocking spectrum`` on its default grids (Omega 0.5 to 15, 59 values; the beta scan 0.5 to 15,
117 amplitudes), of the bench block and damper of bench/adaptive.py (the reference block of docs/model.md
section 9, gamma = 0.05, omega_m = p, zeta = 0.05, h = 0.05 m, rtol = 1e-8), computed with adaptive scans
(rocking.study.adaptive.refine_scan, each coarse step asked for) and with full ones (the default), each on fresh tiles
with the same local workers. Prints, per coarse step, the responses computed (the scans' and in all, with the
bisections), the wall time, the ratios to the full scans', and whether the results are identical: every
column's scan outcomes, beta_min, beta_safe, flag, impacts and responses without a verdict, per direction and
their envelope, and the safe windows.

    python bench/adaptive_spectrum.py                       # the coarse step 4; seconds on 2 cores
    python bench/adaptive_spectrum.py --coarse 4 8 16 --json out/adaptive_spectrum.json
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
from rocking.cli.study import SPECTRUM_BETA, SPECTRUM_OMEGA
from rocking.study.adaptive import narrowest_feature
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.spectrum import COLUMN_FIELDS, envelope, minimum_overturning_spectrum, safe_windows
from rocking.study.tiles import Execution

GAMMA, OMEGA_RATIO, ZETA, H_MASS = 0.05, 1.0, 0.05, 0.05
#: The second block of --slender: slender and smaller, eccentric the other way (tests/test_adaptive.py's).
SLENDER = {"p": 2.0, "alpha": 0.2, "e_ratio": -0.04}
#: The coarse step measured by default: the one to ask for (rocking.study.spectrum.SCAN_COARSE).
ASKED = 4


def _unequal(a, b) -> np.ndarray:
    """Where two arrays differ, NaN equal to NaN."""
    a, b = np.asarray(a), np.asarray(b)
    both_nan = np.isnan(a) & np.isnan(b) if a.dtype.kind == "f" else False
    return (a != b) & ~both_nan


def differences(adaptive, full, coarse: int) -> dict:
    """What differs between a spectrum of adaptive scans and one of full scans (their data), counted in columns
    (part, Omega, direction) or in Omega values (the envelopes, the windows), and whether every column whose scan
    differs holds a feature narrower than the coarse step (a run of one class touching neither end of the scan,
    :func:`rocking.study.adaptive.narrowest_feature`): the only kind the adaptive scan may miss."""
    out = {
        "scan_columns": 0,
        "beta_min_columns": 0,
        "other_columns": 0,
        "envelope_beta_min": 0,
        "windows": 0,
        "narrow_columns": 0,
        "unexplained_columns": 0,
    }
    envelopes = [envelope(data) for data in (adaptive, full)]
    for part in ("bare", "damper"):
        a, f = (data.sel(part=part) for data in (adaptive, full))
        scan_a, scan_f = a["scan_outcome"].values, f["scan_outcome"].values
        differ = (scan_a != scan_f).any(axis=-1)
        narrow = (narrowest_feature(scan_f.reshape(-1, scan_f.shape[-1])) < coarse).reshape(differ.shape)
        out["scan_columns"] += int(differ.sum())
        out["narrow_columns"] += int(narrow.sum())
        out["unexplained_columns"] += int((differ & ~narrow).sum())
        unequal = {k: _unequal(a[k].values, f[k].values) for k in COLUMN_FIELDS}
        out["beta_min_columns"] += int(unequal.pop("beta_min").sum())
        out["other_columns"] += int(np.logical_or.reduce(list(unequal.values())).sum())
        beta_min = [e["beta_min"].sel(part=part).values for e in envelopes]
        out["envelope_beta_min"] += int((beta_min[0] != beta_min[1]).sum())
        windows = [{tuple(w) for w in safe_windows(e, part)} for e in envelopes]
        out["windows"] += len(windows[0] ^ windows[1])
    out["identical"] = not any(v for k, v in out.items() if k != "narrow_columns")
    return out


def compare(coarse_steps: list[int], workers: int, block: Block, n_beta: int) -> dict:
    """The spectrum with full scans, then with adaptive scans of each coarse step, each on fresh tiles."""
    setting, tuning = Setting(block, rtol=1e-8), Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS)
    beta = (*SPECTRUM_BETA[:2], n_beta)
    grids = Grid("Omega", *SPECTRUM_OMEGA), Grid("beta", *beta)
    execution = Execution(workers=workers, progress=False)
    out = {
        "block": setting.record()["block"],
        "Omega": list(SPECTRUM_OMEGA),
        "beta": list(beta),
        "workers": workers,
        "runs": [],
    }
    studies = {}
    with tempfile.TemporaryDirectory() as tmp:
        for coarse in [1, *coarse_steps]:
            start = time.perf_counter()
            study = minimum_overturning_spectrum(
                setting, tuning, *grids, execution, runs=f"{tmp}/{coarse}", coarse=coarse
            )
            seconds = time.perf_counter() - start
            studies[coarse] = study
            counts = {k: study.run[k] for k in ("responses", "scan_responses", "scan_responses_full")}
            out["runs"].append({"coarse": coarse, "seconds": seconds, **counts})
    full = out["runs"][0]
    for r in out["runs"]:
        r["response_ratio"] = full["responses"] / r["responses"]
        r["scan_response_ratio"] = full["scan_responses"] / r["scan_responses"]
        r["speedup"] = full["seconds"] / r["seconds"]
        r["differences"] = differences(studies[r["coarse"]].data, studies[1].data, r["coarse"])
    return out


def report(result: dict, block_name: str) -> None:
    om, be = result["Omega"], result["beta"]
    print(
        f"adaptive beta scans, {block_name} (Omega {om[0]:g}-{om[1]:g} x {om[2]}, beta {be[0]:g}-{be[1]:g} x "
        f"{be[2]}; block alone + damper, both directions; {result['workers']} workers):"
    )
    for r in result["runs"]:
        name = "full" if r["coarse"] == 1 else f"coarse {r['coarse']}"
        print(
            f"  {name:10s} {r['scan_responses']:7d} scan + {r['responses'] - r['scan_responses']:5d} bisection "
            f"responses  {r['seconds']:6.1f} s",
            end="",
        )
        if r["coarse"] == 1:
            print()
            continue
        d = r["differences"]
        verdict = (
            "identical"
            if d["identical"]
            else (
                f"scan outcome differs in {d['scan_columns']} columns "
                f"(of {d['narrow_columns']} with a feature narrower than the step; {d['unexplained_columns']} others), "
                f"beta_min in {d['beta_min_columns']} columns "
                f"(beta_safe, flag, impacts or undetermined in {d['other_columns']}), "
                f"their envelope at {d['envelope_beta_min']} Omega, {d['windows']} windows"
            )
        )
        print(
            f"   {r['scan_response_ratio']:.1f}x fewer scan responses, {r['response_ratio']:.1f}x fewer in all, "
            f"{r['speedup']:.1f}x faster; {verdict}"
        )


def table(result: dict) -> str:
    """One row per coarse step, as a Markdown table: the README's (bench/readme.py)."""
    rows = [
        "| coarse step | scan responses | fewer | with the bisections | wall (s) | envelope beta_min and windows | "
        "one direction's beta_min |",
        "|---|---|---|---|---|---|---|",
    ]
    columns = 2 * result["Omega"][2] * 2  # both parts, both directions
    for r in result["runs"]:
        d = r["differences"]
        same = (
            "identical"
            if not (d["envelope_beta_min"] or d["windows"])
            else (f"differ at {d['envelope_beta_min']} Omega, {d['windows']} windows")
        )
        rows.append(
            f"| {'every amplitude' if r['coarse'] == 1 else r['coarse']} | {r['scan_responses']:,} | "
            f"{r['scan_response_ratio']:.1f}x | {r['responses']:,} | {r['seconds']:.1f} | {same} | "
            f"differs in {d['beta_min_columns']} of {columns} columns |"
        )
    return "\n".join(rows)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--coarse", type=int, nargs="+", default=[ASKED], help=f"coarse steps of the adaptive scans (default {ASKED})"
    )
    parser.add_argument(
        "--beta",
        type=int,
        default=SPECTRUM_BETA[2],
        help=f"amplitudes of the scan (default {SPECTRUM_BETA[2]}, rocking spectrum's)",
    )
    parser.add_argument("--workers", type=int, default=2, help="local workers (default 2)")
    parser.add_argument(
        "--slender", action="store_true", help=f"a second block instead: Block.from_nondim(**{SLENDER})"
    )
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    started = machine()
    block = Block.from_nondim(**SLENDER) if args.slender else Block.reference()
    result = compare(args.coarse, args.workers, block, args.beta)
    report(result, "second block" if args.slender else "bench spectrum")
    if args.json:
        result["command"] = command_line("adaptive_spectrum.py", argv)
        result["machine"] = started | ended()
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
            f.write("\n")
    # Only a difference that no feature narrower than the coarse step explains is a failure.
    return 0 if not any(r["differences"]["unexplained_columns"] for r in result["runs"]) else 1


if __name__ == "__main__":
    sys.exit(main())
