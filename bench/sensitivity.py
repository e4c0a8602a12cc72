"""How often the tolerance check is fooled, and what it costs (issue 35, item 4).

A suite of responses to white noise and to stochastic records (:mod:`rocking.model.stochastic`,
the default site), on three blocks (the reference block, the eccentric block of issue 25 and a
slender one), in both directions, a third of them with the README's damper, at intensities from
below uplift to overturning. For each response, on the C back end:

- the checked answer, ``rocking.simulate(..., rtol=RTOL)`` (``check="tolerance"``, the default for a
  sampled motion: docs/simulation.md, "Sensitivity to the tolerance"), and its CPU time;
- the run at ``RTOL`` alone (``check="none"``) and its CPU time: the cost of the check is the ratio;
- the converged reference: runs at 1e-12 and 1e-11 (``check="none"``) that agree to 1 % (the verdict,
  ``theta_max`` and ``x_max``); where they do not, the response is *chaotic* and counted apart;
- the reference with the motion scaled by ``1 - 1e-9`` and ``1 - 2e-9`` (factors the check never
  runs): where either moves the answer by more than 10 %, the response is chaotic at its input, and
  flagging it is right whatever its answer; of a chaotic response, whether the check's spread of
  ``theta_max`` covers these two runs and the one at 1e-11 (runs it does not make);
- the run at ``RTOL / 100``: what the check of issue 25 (one rerun there) would have said.

Counted per ``RTOL``: the answers not flagged that are farther than 10 % from the converged reference
(or of another verdict; the target: 0), the answers flagged, the false positives (flagged, the answer
at ``RTOL`` within 10 % of a converged reference that no input perturbation moves), and the CPU time
of the checked call over that of one run (mean of the ratios, median, and total over total).

Usage::

    python bench/sensitivity.py [N] [FIRST] [OUT]

    python bench/sensitivity.py fragility [OUT]

Responses ``FIRST`` to ``FIRST + N - 1`` of the suite (default 3000 from 3000: the constants of
:mod:`rocking.sim.accuracy` were chosen on responses 0 to 2999, these are held out), with 2 worker
processes; the summary goes to ``OUT`` (default ``bench/sensitivity.json``). ``fragility``: the time of a
fragility of 20 stochastic motions at 4 PGA levels (320 responses, the reference block, one worker) with the
check and without, to ``OUT`` (default ``bench/sensitivity-fragility.json``).
"""

from __future__ import annotations

import dataclasses
import json
import platform
import sys
import tempfile
import time
from multiprocessing import Pool
from pathlib import Path

import numpy as np

import rocking
from rocking.model.stochastic import DEFAULT_SITE, record_rng, synthesize
from rocking.sim import accuracy
from rocking.study import ida
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.suite import Suite
from rocking.study.tiles import Execution

BLOCKS = {
    "reference": rocking.Block.reference(),
    # The eccentric block of issue 25's and issue 35's white-noise cases.
    "eccentric": rocking.Block(H=3.1597847506851258, B=0.9313975019469038, M=131.3667739110528, e=-0.16218004607891312),
    "slender": rocking.Block(H=1.0, B=0.15, M=200.0),
}
#: The tolerances checked: the default for records, and a looser one (a longer ladder).
TOLERANCES = (1e-8, 1e-6)
#: Agreement of the two reference runs [-]: the issue's definition of a converged reference.
CONVERGED = 0.01
#: Farther than this from the reference is a wrong answer (the check's own fraction).
FAR = accuracy.SENSITIVE_FRACTION
#: Input perturbations of the reference that the check never runs.
REFERENCE_FACTORS = (1 - 1e-9, 1 - 2e-9)
#: White noise: samples and spacing (20 s), and its standard deviation over g tan(alpha), log-uniform.
NOISE_SAMPLES, NOISE_DT, NOISE_LEVELS = 1000, 0.02, (0.4, 1.5)
#: Stochastic records (47 s of the default site): PGA over g tan(alpha), log-uniform.
RECORD_LEVELS = (1.0, 6.0)
#: Where the summary goes.
OUT = "bench/sensitivity.json"


def case(i: int):
    """Response ``i`` of the suite: its description, block, damper (or None) and motion."""
    rng = np.random.default_rng(1000 + i)
    name = list(BLOCKS)[i % 3]
    block = BLOCKS[name]
    kind = "noise" if (i // 3) % 2 == 0 else "stochastic"
    sign = 1 if (i // 6) % 2 == 0 else -1
    damped = (i // 12) % 3 == 2
    uplift = block.g * block.tan_alpha
    if kind == "noise":
        a = rng.normal(0.0, 1.0, NOISE_SAMPLES)
        level = float(np.exp(rng.uniform(*np.log(NOISE_LEVELS))))
        motion = rocking.SampledMotion(a, dt=NOISE_DT, scale=level * uplift, sign=sign)
    else:
        a = synthesize(DEFAULT_SITE, record_rng(7, i))
        level = float(np.exp(rng.uniform(*np.log(RECORD_LEVELS))))
        motion = rocking.SampledMotion(a, dt=DEFAULT_SITE.dt, scale=level * uplift / np.abs(a).max(), sign=sign)
    damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05) if damped else None
    described = {"i": i, "block": name, "kind": kind, "sign": sign, "damper": damped, "level": level}
    return described, block, damper, motion


def _answer(r) -> dict:
    return {"overturned": bool(r.overturned), "theta_max": float(r.theta_max), "x_max": float(r.x_max)}


def _timed(*args, **kwargs):
    start = time.process_time_ns()
    r = rocking.simulate(*args, backend="c", **kwargs)
    return r, (time.process_time_ns() - start) * 1e-9


def measure(i: int) -> dict:
    """Every run of response ``i``: the reference and, per tolerance, the checked and the plain answers."""
    described, block, damper, motion = case(i)
    fine = _answer(rocking.simulate(block, damper, motion, backend="c", rtol=1e-12, check="none"))
    coarse = _answer(rocking.simulate(block, damper, motion, backend="c", rtol=1e-11, check="none"))
    perturbed = [
        _answer(rocking.simulate(block, damper, dataclasses.replace(motion, scale=motion.scale * f), backend="c",
                                 rtol=1e-12, check="none"))
        for f in REFERENCE_FACTORS
    ]  # fmt: skip
    out = {**described, "reference": fine, "coarse": coarse, "perturbed": perturbed}
    out["converged"] = not _apart(fine, coarse, CONVERGED)
    out["input_chaotic"] = any(_apart(fine, p, FAR) for p in perturbed)
    for rtol in TOLERANCES:
        plain, t_plain = _timed(block, damper, motion, rtol=rtol, check="none")
        checked, t_checked = _timed(block, damper, motion, rtol=rtol, check="tolerance")
        once = rocking.simulate(block, damper, motion, backend="c", rtol=rtol / 100, check="none")
        out[f"{rtol:g}"] = {
            "plain": _answer(plain),
            "checked": _answer(checked),
            "sensitive": bool(checked.sensitive),
            "low": checked.theta_max_low,
            "high": checked.theta_max_high,
            "overturned_fraction": checked.overturned_fraction,
            "check_runs": int(checked.check_runs),
            "old_sensitive": bool(accuracy.sensitive(_answer(plain), _answer(once))),
            "cpu_plain": t_plain,
            "cpu_checked": t_checked,
        }
    return out


def _apart(a: dict, b: dict, fraction: float) -> bool:
    """Another verdict, or theta_max or x_max farther apart than ``fraction`` of the larger."""
    if a["overturned"] != b["overturned"]:
        return True
    return any(abs(a[k] - b[k]) > fraction * max(abs(a[k]), abs(b[k])) for k in ("theta_max", "x_max"))


def summary(rows: list[dict], rtol: float) -> dict:
    """The counts of the docstring at ``rtol``."""
    key = f"{rtol:g}"
    conv = [r for r in rows if r["converged"]]
    chaotic = [r for r in rows if not r["converged"]]

    def wrong(r, which="checked"):
        return _apart(r[key][which], r["reference"], FAR)

    missed = [r["i"] for r in conv if not r[key]["sensitive"] and wrong(r)]
    ratio = np.array([r[key]["cpu_checked"] / r[key]["cpu_plain"] for r in rows])
    runs = np.array([r[key]["check_runs"] for r in rows])
    # The runs of the reference that the check does not make: does its spread cover them?
    covered = [
        r
        for r in chaotic
        if all(r[key]["low"] <= a["theta_max"] <= r[key]["high"] for a in (r["coarse"], *r["perturbed"]))
    ]
    return {
        "rtol": rtol,
        "responses": len(rows),
        "converged": len(conv),
        "chaotic": len(chaotic),
        "input_chaotic": sum(r["input_chaotic"] for r in rows),
        "answer_at_rtol_far_from_reference": sum(wrong(r, "plain") for r in conv),
        "unflagged_far_from_reference": len(missed),
        "unflagged_far_cases": missed,
        "flagged": sum(r[key]["sensitive"] for r in rows),
        "flagged_converged": sum(r[key]["sensitive"] for r in conv),
        "flagged_answer_far_from_reference": sum(r[key]["sensitive"] and wrong(r) for r in conv),
        "false_positives": sum(r[key]["sensitive"] and not wrong(r, "plain") and not r["input_chaotic"] for r in conv),
        "chaotic_flagged": sum(r[key]["sensitive"] for r in chaotic),
        "chaotic_unflagged_far": sum(not r[key]["sensitive"] and wrong(r) for r in chaotic),
        "chaotic_spread_covers_other_runs": len(covered),
        "old_check_unflagged_far": sum(not r[key]["old_sensitive"] and wrong(r, "plain") for r in conv),
        "old_check_flagged": sum(r[key]["old_sensitive"] for r in rows),
        "cpu_ratio_mean": float(ratio.mean()),
        "cpu_ratio_median": float(np.median(ratio)),
        "cpu_ratio_total": float(sum(r[key]["cpu_checked"] for r in rows) / sum(r[key]["cpu_plain"] for r in rows)),
        "cpu_ratio_median_by_kind": {
            kind: float(np.median(ratio[[r["kind"] == kind for r in rows]])) for kind in ("noise", "stochastic")
        },
        "cpu_plain_median_s_by_kind": {
            kind: float(np.median([r[key]["cpu_plain"] for r in rows if r["kind"] == kind]))
            for kind in ("noise", "stochastic")
        },
        "check_runs_mean": float(runs.mean()),
        "stopped_at_first_rung": int((runs == 3).sum()),
    }


def main(n: int, first: int, out: Path) -> None:
    start = time.perf_counter()
    with Pool(2) as pool:
        rows = pool.map(measure, range(first, first + n), chunksize=16)
    wall = time.perf_counter() - start
    result = {
        "command": f"python bench/sensitivity.py {n} {first} {out}",
        "responses": [first, first + n - 1],
        "machine": platform.processor() or platform.machine(),
        "workers": 2,
        "wall_s": round(wall, 1),
        "suite": {
            "blocks": {k: dataclasses.asdict(b) for k, b in BLOCKS.items()},
            "noise": {"samples": NOISE_SAMPLES, "dt": NOISE_DT, "std_over_uplift": NOISE_LEVELS},
            "stochastic": {"site": DEFAULT_SITE.record(), "pga_over_uplift": RECORD_LEVELS, "seed": 7},
            "damper": {"gamma": 0.05, "omega_ratio": 1.0, "zeta": 0.05, "h": 0.05, "every": "third dozen"},
            "kinds": {k: sum(r["kind"] == k for r in rows) for k in ("noise", "stochastic")},
            "overturned_reference": sum(r["reference"]["overturned"] for r in rows),
        },
        "rule": {
            "ladder_step": accuracy.TIGHTEN,
            "floor": accuracy.RTOL_MIN,
            "perturbation": accuracy.PERTURBATION,
            "same_fraction": accuracy.SAME_FRACTION,
            "trajectory": accuracy.TRAJECTORY,
            "close": accuracy.CLOSE,
            "sensitive_fraction": accuracy.SENSITIVE_FRACTION,
        },
        "tolerances": [summary(rows, rtol) for rtol in TOLERANCES],
    }
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(json.dumps(result, indent=1))


def fragility_cost(out: Path, n: int = 20) -> None:
    """Wall and CPU time of a fragility of ``n`` stochastic motions at 4 PGA levels, with the check and without."""
    block = rocking.Block.reference()
    uplift = block.g * block.tan_alpha
    levels = Grid("pga", 1.5 * uplift, 6.0 * uplift, 4)
    suite = Suite.stochastic(DEFAULT_SITE, n, seed=1)
    result = {"command": f"python bench/sensitivity.py fragility {out}", "motions": n}
    for i in range(n):
        suite.motion(i)  # the synthesis's kernel is cached in the process: paid here, by neither of the two
    for check in ("none", "tolerance"):
        with tempfile.TemporaryDirectory() as runs:
            wall, cpu = time.perf_counter(), time.process_time()
            study = ida.incremental_dynamic_analysis(
                Setting(block), Tuning(0.05), suite, levels, Execution(workers=1, progress=False),
                measure_name="pga", runs=runs, check=check,
            )  # fmt: skip
            wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        sensitive = {part: int(study.data["sensitive_responses"].sel(part=part).sum()) for part in ("bare", "damper")}
        result[check] = {"responses": study.run["responses"], "wall_s": wall, "cpu_s": cpu, "sensitive": sensitive}
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    args = sys.argv[1:]
    if args[:1] == ["fragility"]:
        fragility_cost(Path(args[1] if len(args) > 1 else "bench/sensitivity-fragility.json"))
        raise SystemExit
    n, first = (int(args[k]) if len(args) > k else 3000 for k in (0, 1))
    main(n, first, Path(args[2] if len(args) > 2 else OUT))
