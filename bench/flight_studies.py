"""Studies past beta_f (issue 39): a vertical map's cells that flew and how they ended, and the vertical spectra.

``map`` (default): a full overturning map of the reference block alone and with the demo's damper (gamma = 0.05,
omega_m = p, zeta = 0.05, h = 0.05 m, stops at the block's edges: model omd_stops), one-sine pulses with a
vertical component in phase, ``ddy_g = r a_g sin(omega_g t)`` (> 0 up, the same for both signs), ``r = 1``
by default: ``beta_f = 1 / (r tan alpha) = 4`` on the reference block, above which ``g + ddy_g`` reaches 0 during
the pulse. Both directions of each pulse, their envelope (the governing direction's class). Prints, per part, the
cells and the responses (every direction) that flew, and how they ended: flew and landed without overturning, flew
and overturned, without a verdict (jammed, or a bound); and the same below and above beta_f::

    python bench/flight_studies.py map [--ratio 1] [--n 40] [--workers 2] [--backend c]

``spectra``: the demo's vertical spectra (``rocking demo`` draws them as docs/figures/spectrum-vertical.png: the
same grids, ratios 0, 0.5, 1, the damper with stops, both directions) into ``--out``, and per ratio and part the
frequencies whose ``beta_min`` lies above beta_f, and at how many the response overturning at ``beta_min`` flew, and
the ``beta_min`` of each direction at one ``Omega`` (``--at``, default 6.5)::

    python bench/flight_studies.py spectra --out build/flight-spectra [--at 6.5]

``horizontal``: the demo map's pulses without a vertical component: the responses whose pivot lifted off while
rocking (the floor's normal force reached 0, docs/model.md section 16) and how they ended::

    python bench/flight_studies.py horizontal
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from rocking import Block
from rocking.sim.problem import STATUS
from rocking.study.config import Grid, Setting, Tuning, flight_beta
from rocking.study.overturning_map import NO_VERDICT, envelope, overturning_map
from rocking.study.tiles import Execution

#: The demo's damper: the reference tuning with stops at the block's edges.
DAMPER = Tuning(0.05, stops=True)


def map_counts(data, beta_f: float) -> dict:
    """Per part, of the cells of a map's envelope and of every response (``data``: a vertical map's data): how many
    flew, flew and landed, flew and overturned, have no verdict; over the whole grid and above ``beta_f``."""
    env = envelope(data)
    above = data["beta"].values > beta_f
    verdictless = [STATUS.index(s) for s in NO_VERDICT]
    no_verdict = np.isin(data["status"].values, verdictless)
    jammed = data["status"].values == STATUS.index("jammed")
    out = {}
    for index, part in enumerate(("bare", "damper")):
        over = env["overturned"].sel(part=part).values
        flew = (env["flew"].sel(part=part).values == 1) & ~np.isin(env["status"].sel(part=part).values, verdictless)
        each_flew = data["flew"].values[index] == 1
        each_over = data["overturned"].values[index].astype(bool)
        for where, cells in (("all", np.ones_like(above)), ("above beta_f", above)):
            sel = np.broadcast_to(cells, flew.shape)
            each = np.broadcast_to(cells[None, :, None], each_flew.shape)
            out[(part, where)] = {
                "cells": int(sel.sum()),
                "cells flew": int((flew & sel).sum()),
                "cells flew, landed": int((flew & ~over & sel).sum()),
                "cells flew, overturned": int((flew & over & sel).sum()),
                "cells overturned": int((over & sel).sum()),
                "responses": int(each.sum()),
                "responses flew": int((each_flew & each).sum()),
                "responses flew, landed": int((each_flew & ~each_over & ~no_verdict[index] & each).sum()),
                "responses flew, overturned": int((each_flew & each_over & each).sum()),
                "responses no verdict": int((no_verdict[index] & each).sum()),
                "responses jammed": int((jammed[index] & each).sum()),
            }
    return out


def run_map(args) -> None:
    block = Block.reference()
    setting = Setting(block, vertical_ratio=args.ratio, backend=args.backend)
    Omega, beta = Grid("Omega", 0.5, 15.0, args.n), Grid("beta", 0.5, 15.0, args.n)
    beta_f = flight_beta(block, setting.record())
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as runs:
        study = overturning_map(
            setting, DAMPER, Omega, beta, Execution(workers=args.workers, progress=False), runs=runs, full=True
        )
    wall = time.perf_counter() - start
    print(
        f"vertical map: reference block, one-sine pulses with ddy_g = {args.ratio:g} a_g sin(omega_g t) (beta_f = "
        f"{beta_f:.4g}), Omega and beta {args.n} x {args.n} in [0.5, 15], both directions, full; {wall:.1f} s"
    )
    for (part, where), counts in map_counts(study.data, beta_f).items():
        cells, responses = counts["cells"], counts["responses"]

        def share(key: str, total: int, c=counts) -> str:
            return f"{c[key]} ({100.0 * c[key] / total:.1f} %)" if total else "0"

        print(
            f"  {part:6s} {where:12s}: cells {cells}: flew {share('cells flew', cells)}: landed "
            f"{share('cells flew, landed', cells)}, overturned {share('cells flew, overturned', cells)}; "
            f"overturned in all {share('cells overturned', cells)}"
        )
        print(
            f"  {'':6s} {'':12s}  responses {responses}: flew {share('responses flew', responses)}: landed "
            f"{share('responses flew, landed', responses)}, overturned {share('responses flew, overturned', responses)}"
            f"; no verdict {counts['responses no verdict']} (jammed {counts['responses jammed']})"
        )


def run_horizontal(args) -> None:
    """The demo map's pulses without a vertical component (kinds.MAP_OMEGA x MAP_BETA, both signs, the block alone
    and with the damper): the responses whose pivot lifted off (flights > 0), and how they ended, by status."""
    from rocking.sim.cases import pulse_cases, run_cases
    from rocking.study.kinds import MAP_BETA, MAP_OMEGA

    block = Block.reference()
    Omega, beta = Grid("Omega", *MAP_OMEGA).values(), Grid("beta", *MAP_BETA).values()
    start = time.perf_counter()
    print(f"horizontal pulses only: the demo map's grid, Omega {MAP_OMEGA}, beta {MAP_BETA}, both signs")
    for part, damper in (("bare", {"gamma": 0.0}), ("damper", DAMPER.case_args())):
        for sign in (1, -1):
            cases = pulse_cases(block, Omega[:, None], beta[None, :], sign=sign, **damper)
            result = run_cases(cases, backend=args.backend)
            flew = (result["flights"] > 0).reshape(Omega.size, beta.size)
            status = result["status"].reshape(flew.shape)
            ended = {STATUS[k]: int(np.sum(flew & (status == k))) for k in np.unique(status[flew])}
            lowest = float(np.min(np.broadcast_to(beta[None, :], flew.shape)[flew])) if flew.any() else np.nan
            print(
                f"  {part:6s} sign {sign:+d}: {flew.sum()} of {flew.size} responses flew (from beta = {lowest:.3g}); "
                f"their statuses {ended}"
            )
    print(f"  {time.perf_counter() - start:.1f} s")


def run_spectra(args) -> None:
    from rocking.cli.study import VERTICAL_BETA, VERTICAL_OMEGA, VERTICAL_RATIOS, _vertical_spectra

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    setting = Setting(Block.reference(), backend=args.backend)
    start = time.perf_counter()
    _vertical_spectra(setting, DAMPER, Execution(workers=args.workers, progress=False), out, out / "runs", ("png",))
    print(f"vertical spectra: Omega {VERTICAL_OMEGA}, beta {VERTICAL_BETA}; {time.perf_counter() - start:.1f} s")
    from rocking.study.storage import load

    for ratio in VERTICAL_RATIOS:
        study = load(out / f"spectrum-vertical-{ratio:g}".replace(".", "p"))
        data = study.data
        beta_f = flight_beta(Block.reference(), study.config)
        for part in ("bare", "damper"):
            cell = data.sel(part=part)
            beta_min = cell["beta_min"].values
            past = int(np.sum(beta_min > beta_f))
            flew = int(cell["beta_min_flew"].sum()) if "beta_min_flew" in cell else 0
            found = int(np.isfinite(beta_min).sum())
            print(
                f"  r = {ratio:g} (beta_f = {beta_f:.4g}), {part:6s}: beta_min found at {found}"
                f" of {beta_min.size} (Omega, sign) columns, above beta_f at {past}, its response flew at {flew}; "
                f"responses without a verdict {int(cell['undetermined'].sum())}"
            )
            at = cell.sel(Omega=args.at, method="nearest")
            print(
                f"  {'':{len(f'r = {ratio:g} (beta_f = {beta_f:.4g})')}s}  at Omega = {float(at['Omega']):g}: "
                + ", ".join(f"sign {int(sign):+d} beta_min {_value(at.sel(sign=sign))}" for sign in at["sign"].values)
            )


def _value(column) -> str:
    """A column's ``beta_min``, or its lower bound (``> x``) where the scan did not reach it."""
    beta = float(column["beta_min"])
    return f"{beta:.3g}" if np.isfinite(beta) else f"> {float(column['beta_min_lower_bound']):.3g}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("what", nargs="?", default="map", choices=("map", "spectra", "horizontal"))
    parser.add_argument("--ratio", type=float, default=1.0, help="vertical ratio r of the map (default 1)")
    parser.add_argument("--n", type=int, default=40, help="Omega and beta values of the map (default 40)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--backend", default="c", choices=("c", "numpy"))
    parser.add_argument("--out", default="build/flight-spectra", help="folder of the spectra and their figure")
    parser.add_argument("--at", type=float, default=6.5, help="the spectra's Omega whose beta_min are printed")
    args = parser.parse_args()
    {"map": run_map, "spectra": run_spectra, "horizontal": run_horizontal}[args.what](args)


if __name__ == "__main__":
    main()
