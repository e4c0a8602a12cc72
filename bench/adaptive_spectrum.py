"""Why a spectrum scans every amplitude: what an exact scan must compute, against the full scan, per pulse family.

A spectrum reports each column's ``beta_min`` (the first overturning amplitude of its scan, then bisected) and the
safe windows above it. The overturning domain has bands of one or a few amplitudes amid safe ones, and a band
that no computed amplitude falls in leaves no trace in the outcomes around it: an exact ``beta_min`` needs the
outcome of every amplitude up to the first overturning one, and exact windows those of all the others. So the
most that any exact adaptive scan can skip is the amplitudes above the first overturning one, and then it gives
no windows. This script measures that ceiling on ``rocking spectrum``'s default grids (Omega 0.5 to 15, 59
values; beta 0.5 to 15, 117 amplitudes), for every pulse family (the Mavroeidis-Papageorgiou one with
gamma_mp = 2.5), both signs, the reference block alone, with the bench damper (gamma = 0.05, omega_m = p, zeta
= 0.05, h = 0.05 m, docs/model.md section 9) and with it between stops (``Tuning(stops=True)``), rtol = 1e-8,
in process on one thread of the C back end:

- the responses of the full scans and their CPU time (``time.process_time``, one ``respond`` call per family,
  part and sign),
- the responses up to each column's first overturning amplitude and their CPU time: the least an exact
  ``beta_min`` costs, hence the largest saving any exact scan could make,
- the columns whose first overturning band is narrower than 16 amplitudes and followed by a safe one: those
  where a scan of every 16th amplitude can step over the band and report a ``beta_min`` too high,
- and the full scan's ``beta_min`` of the columns of issue 35 that ``--coarse 16`` over-reported.

    python bench/adaptive_spectrum.py --json bench/adaptive-spectrum.json      # about 20 s
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np
from machine import command_line, ended, machine

from rocking import Block
from rocking.cli.study import SPECTRUM_BETA, SPECTRUM_OMEGA
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import respond
from rocking.study.spectrum import beta_min

#: The pulse families, with the shape of the Mavroeidis-Papageorgiou one.
FAMILIES = {"sine": None, "cosine": None, "ricker": None, "ricker_anti": None, "mp": 2.5}
#: The parts: the block alone, with the bench damper, with it between stops.
PARTS = ("bare", "damper", "stops")
#: The coarse step of the widest band counted (``rocking spectrum --coarse 16`` of earlier versions).
STEP = 16
#: The columns of issue 35 that ``--coarse 16`` over-reported: (family, part, Omega, sign, its beta_min).
ISSUE_CASES = (
    ("sine", "damper", 3.0, -1, 3.252),
    ("ricker_anti", "bare", 3.0, -1, 3.625),
    ("mp", "stops", 3.75, 1, 11.414),
)


def damper_of(part: str) -> dict | None:
    """The keyword arguments of the damper of ``part`` (None for the block alone)."""
    return None if part == "bare" else Tuning(0.05, 1.0, 0.05, 0.05, stops=part == "stops").case_args()


def setting_of(family: str) -> Setting:
    """The reference block under pulses of ``family``."""
    return Setting(Block.reference(), rtol=1e-8, pulse=family, gamma_mp=FAMILIES[family])


def narrow_first_bands(overturned: np.ndarray, step: int) -> int:
    """Columns (rows of ``overturned``) whose first run of overturning amplitudes is shorter than ``step`` and
    followed by a safe amplitude: a scan of every ``step``-th amplitude can fall on both sides of it."""
    count = 0
    for row in overturned:
        if not row.any():
            continue
        first = int(np.argmax(row))
        after = np.flatnonzero(~row[first:])
        count += int(bool(after.size) and after[0] < step)
    return int(count)


def measure(family: str, part: str, sign: int, Omega: np.ndarray, beta: np.ndarray) -> dict:
    """The full scans of one family, part and sign, and what an exact ``beta_min`` needs of them."""
    setting, damper = setting_of(family), damper_of(part)
    Om, B = np.meshgrid(Omega, beta, indexing="ij")
    start = time.process_time()
    over = respond(setting, Om, B, damper, sign)["overturned"]
    cpu_full = time.process_time() - start
    first = np.where(over.any(axis=1), np.argmax(over, axis=1), beta.size - 1)
    needed = np.arange(beta.size)[None, :] <= first[:, None]
    start = time.process_time()
    respond(setting, Om[needed], B[needed], damper, sign)
    cpu_needed = time.process_time() - start
    return {
        "family": family,
        "part": part,
        "sign": sign,
        "responses": int(over.size),
        "responses_needed": int(needed.sum()),
        "cpu": cpu_full,
        "cpu_needed": cpu_needed,
        "narrow_bands": narrow_first_bands(over, STEP),
    }


def issue_cases(beta: np.ndarray) -> list[dict]:
    """The full scan's ``beta_min`` of each column of :data:`ISSUE_CASES`."""
    out = []
    for family, part, Omega, sign, coarse in ISSUE_CASES:
        full = float(beta_min(setting_of(family), [Omega], beta, damper_of(part), sign=sign)["beta_min"][0])
        out.append({"family": family, "part": part, "Omega": Omega, "sign": sign, "full": full, "coarse_16": coarse})
    return out


def totals(rows: list[dict], family: str | None = None) -> dict:
    """The sums of ``rows`` (of one ``family``, or all)."""
    chosen = [r for r in rows if family in (None, r["family"])]
    return {
        k: sum(r[k] for r in chosen) for k in ("responses", "responses_needed", "cpu", "cpu_needed", "narrow_bands")
    }


def table(result: dict) -> str:
    """One row per pulse family and one for all, as a Markdown table: the README's (bench/readme.py)."""
    rows = [
        "| pulse | responses of the full scans | up to the first overturning amplitude | CPU (s) | of it up to the "
        f"first overturning amplitude | columns with a first overturning band under {STEP} amplitudes |",
        "|---|---|---|---|---|---|",
    ]
    columns = len(PARTS) * 2 * result["Omega"][2]
    for family in (*FAMILIES, None):
        t, n = totals(result["rows"], family), columns * (len(FAMILIES) if family is None else 1)
        rows.append(
            f"| {family or '**all**'} | {t['responses']:,} | {t['responses_needed']:,} "
            f"({t['responses_needed'] / t['responses']:.0%}) | {t['cpu']:.2f} | {t['cpu_needed']:.2f} "
            f"({t['cpu_needed'] / t['cpu']:.0%}) | {t['narrow_bands']} of {n} |"
        )
    return "\n".join(rows)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    started = machine()
    Omega, beta = Grid("Omega", *SPECTRUM_OMEGA).values(), Grid("beta", *SPECTRUM_BETA).values()
    rows = [measure(f, p, s, Omega, beta) for f in FAMILIES for p in PARTS for s in (1, -1)]
    result = {"Omega": list(SPECTRUM_OMEGA), "beta": list(SPECTRUM_BETA), "rows": rows, "issue": issue_cases(beta)}
    print(table(result))
    t = totals(rows)
    print(
        f"an exact beta_min needs {t['responses_needed'] / t['responses']:.0%} of the responses and "
        f"{t['cpu_needed'] / t['cpu']:.0%} of the CPU time of the full scans: any exact scan saves at most "
        f"{t['responses'] / t['responses_needed']:.2f}x responses, {t['cpu'] / t['cpu_needed']:.2f}x CPU, "
        "and gives no windows"
    )
    for c in result["issue"]:
        print(
            f"issue 35: {c['family']}, {c['part']}, Omega {c['Omega']:g}, sign {c['sign']:+d}: beta_min "
            f"{c['full']:.3f} (every amplitude; the issue found {c['coarse_16']:.3f} with --coarse 16)"
        )
    if args.json:
        result["command"] = command_line("adaptive_spectrum.py", argv)
        result["machine"] = started | ended()
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
