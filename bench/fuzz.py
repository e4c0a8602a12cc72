"""Fuzz the public Python API: no input may hang, crash, or escape as a traceback (issue 10).

Hypothesis draws ``N`` inputs (blocks, dampers and pulses in SI and non-dimensionally, dampers
as objects and as mappings, models by name, every option of ``rocking.simulate``), with NaN,
+-inf, 0, negative, subnormal and 1e+-300 values, wrong types, bools, strings and None. Each
input is built and simulated on each back end in a worker process with a time limit; it ends
as one of:

- ``clean_error``: an error of the project's own (a class of ``rocking.__all__``) before the run;
- ``failed_run``: ``SimulationError`` (a run that started and failed: a bug for a valid input);
- ``result``: a ``Response``, whose numbers are checked (only ``t_overturn`` and ``t_critical``
  may be NaN, meaning "never"); a NaN elsewhere is a ``nan_result``;
- ``other_exception``: anything else (a traceback a user would see);
- ``hang``: no answer within the time limit (the worker is killed and restarted);
- ``crash``: the worker died (a signal, a C fault).

Usage::

    python bench/fuzz.py [-n 10000] [--backends c numpy] [--workers 2] [--timeout 10]
                         [--seed 20240610] [--json out/fuzz.json]

The inputs are drawn once from ``--seed`` and are the same for every back end and every run.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import sys
import time
from collections import Counter
from pathlib import Path

from hypothesis import HealthCheck, Phase, given, seed, settings
from hypothesis import strategies as st

#: Values that break naive checks: NaN, infinities, zeros, subnormals, the extremes of a double.
SPECIAL = [0.0, -0.0, -1.0, 5e-324, 1e-300, 1e-12, 1e12, 1e300, -1e300, math.nan, math.inf, -math.inf]
WRONG = st.one_of(st.none(), st.booleans(), st.text(max_size=4), st.just("1.0"), st.just([1.0]))
#: The project's own error types that a refused input may raise (SimulationError is counted apart).
CLEAN = ("ParameterError", "ModelError", "CBuildError")
#: Result fields allowed to be NaN: "never" (docs/simulation.md).
NAN_ALLOWED = {"t_overturn", "t_critical"}
MODELS = ["omd", "block", "pendulum", "omd2", "nosuch", 3, None, ""]
OWN = ["m", "k_m", "c", "h", "l", "x_p", "y_p", "k_phi", "c_phi", "m1", "k1", "c1", "m2", "k2", "c2", "e", "M", "foo"]


#: Percent of drawn values that are hostile; with about ten values per input, a fair share of inputs stays valid.
HOSTILE_PERCENT = 6
HOSTILE = st.one_of(
    st.sampled_from(SPECIAL), st.floats(allow_nan=True, allow_infinity=True), st.integers(-10, 10**6), WRONG
)


def number(lo: float, hi: float) -> st.SearchStrategy:
    """Mostly a plausible value in ``[lo, hi]`` (so that many runs are valid), sometimes a hostile one."""
    plausible = st.floats(lo, hi)
    # Hypothesis starts from the smallest draws: the plausible value is the smallest.
    return st.integers(0, 99).flatmap(lambda k: HOSTILE if k >= 100 - HOSTILE_PERCENT else plausible)


def optional(strategy: st.SearchStrategy, percent: int = 50) -> st.SearchStrategy:
    """A value, or ``"<missing>"`` (the keyword is not passed) ``percent`` % of the time."""
    return st.integers(0, 99).flatmap(lambda k: st.just("<missing>") if k < percent else strategy)


def mostly(good: st.SearchStrategy, other: st.SearchStrategy, percent: int) -> st.SearchStrategy:
    """``other`` ``percent`` % of the time, else ``good``."""
    return st.integers(0, 99).flatmap(lambda k: other if k >= 100 - percent else good)


def kwargs(**fields) -> st.SearchStrategy:
    """A dict of keyword arguments, those drawn as missing left out."""
    return st.fixed_dictionaries(fields).map(lambda d: {k: v for k, v in d.items() if v != "<missing>"})


def rare(strategy: st.SearchStrategy) -> st.SearchStrategy:
    """An option given in one input of five."""
    return optional(strategy, 80)


BLOCKS = st.one_of(
    st.just({"kind": "reference"}),
    st.builds(
        lambda a: {"kind": "si", "args": a},
        kwargs(
            H=number(0.2, 5.0),
            B=number(0.1, 2.0),
            M=number(10.0, 1e4),
            e=optional(number(-0.05, 0.05)),
            I_G=optional(st.one_of(st.none(), number(1.0, 1e4)), 80),
            g=optional(number(1.0, 20.0)),
        ),
    ),
    st.builds(
        lambda a: {"kind": "nondim", "args": a},
        kwargs(
            p=number(0.5, 10.0),
            lam=optional(number(1.0, 10.0)),
            alpha=optional(number(0.05, 1.0)),
            M=optional(number(10.0, 1e4)),
            e_ratio=optional(number(-0.2, 0.2)),
            g=optional(number(1.0, 20.0)),
        ),
    ),
    st.builds(
        lambda slender, a: {"kind": "nondim", "args": {**slender, **a}},
        st.one_of(st.builds(lambda v: {"lam": v}, number(1.0, 10)), st.builds(lambda v: {"alpha": v}, number(0.05, 1))),
        kwargs(p=number(0.5, 10.0), M=optional(number(10.0, 1e4)), e_ratio=optional(number(-0.2, 0.2))),
    ),
)

DAMPERS = st.one_of(
    st.just({"kind": "none"}),
    st.builds(
        lambda a: {"kind": "si", "args": a},
        kwargs(m=number(1.0, 200.0), k_m=number(1.0, 1e5), c=optional(number(0.0, 1e3)), h=optional(number(0, 0.2))),
    ),
    st.builds(
        lambda tuning, a: {"kind": "nondim", "args": {**tuning, **a}},
        st.one_of(
            st.builds(lambda v: {"T_m": v}, number(0.5, 10.0)), st.builds(lambda v: {"omega_ratio": v}, number(0.2, 5))
        ),
        kwargs(gamma=number(0.01, 0.2), zeta=optional(number(0.0, 0.3)), h=optional(number(0.0, 0.2))),
    ),
    st.builds(
        lambda a: {"kind": "nondim", "args": a},
        kwargs(
            gamma=number(0.01, 0.2),
            T_m=optional(number(0.5, 10.0)),
            omega_ratio=optional(number(0.2, 5.0)),
            zeta=optional(number(0.0, 0.3)),
            h=optional(number(0.0, 0.2)),
        ),
    ),
    st.builds(
        lambda a: {"kind": "mapping", "args": a},
        kwargs(m=number(1.0, 200.0), k_m=number(1.0, 1e5), c=number(0.0, 1e3), h=number(0.0, 0.2)),
    ),
    st.builds(lambda a: {"kind": "mapping", "args": a}, st.dictionaries(st.sampled_from(OWN), number(0.0, 100.0))),
    st.builds(lambda v: {"kind": "object", "value": v}, WRONG),
)

PULSES = st.one_of(
    st.builds(
        lambda a: {"kind": "si", "args": a},
        kwargs(a_g=number(0.0, 20.0), omega_g=number(1.0, 40.0), psi=optional(number(0.0, 6.0))),
    ),
    st.builds(
        lambda a: {"kind": "nondim", "args": a},
        kwargs(beta=number(0.0, 15.0), Omega=number(0.5, 15.0), psi=optional(number(0.0, 6.0))),
    ),
    st.builds(lambda v: {"kind": "object", "value": v}, WRONG),
)
PULSES = mostly(st.one_of(*PULSES.original_strategies[:2]), PULSES, 10)

OPTIONS = kwargs(
    rtol=rare(number(1e-10, 1e-4)),
    t_max=rare(number(0.5, 20.0)),
    t_after=rare(number(0.5, 15.0)),
    dtheta_rest=rare(number(0.0, 0.01)),
    energy_rest=rare(number(0.0, 1.0)),
    max_events=rare(st.one_of(st.integers(-2, 10**5), WRONG, st.sampled_from(SPECIAL))),
    record_dt=rare(number(1e-3, 0.1)),
    early_rest=rare(st.one_of(st.booleans(), WRONG, st.integers(0, 2))),
    model=rare(st.sampled_from(MODELS)),
    record=rare(st.one_of(st.booleans(), WRONG, st.integers(0, 2))),
    phase0=rare(st.one_of(st.integers(-2, 2), WRONG)),
    y0=rare(st.one_of(st.lists(number(-0.1, 0.1), max_size=5), WRONG)),
)

INPUTS = st.fixed_dictionaries({"block": BLOCKS, "damper": DAMPERS, "pulse": PULSES, "options": OPTIONS})


def draw_inputs(n: int, seed_value: int) -> list[dict]:
    """``n`` inputs drawn by Hypothesis from ``seed_value``: the same list on every call."""
    out: list[dict] = []

    @seed(seed_value)
    @settings(
        max_examples=n,
        database=None,
        phases=[Phase.generate],
        deadline=None,
        suppress_health_check=list(HealthCheck),
    )
    @given(INPUTS)
    def collect(case):
        if len(out) < n:
            out.append(case)

    collect()
    return out


# --------------------------------------------------------------------------------------------- #
# One input, in a worker                                                                        #
# --------------------------------------------------------------------------------------------- #


def build(case: dict):
    """The block, damper, pulse and options of ``case`` (raises what the public API raises)."""
    import rocking

    b = case["block"]
    if b["kind"] == "reference":
        block = rocking.Block.reference()
    elif b["kind"] == "si":
        block = rocking.Block(**b["args"])
    else:
        block = rocking.Block.from_nondim(**b["args"])
    d = case["damper"]
    damper = {
        "none": lambda: None,
        "si": lambda: rocking.Damper(**d.get("args", {})),
        "nondim": lambda: rocking.Damper.from_nondim(block, **d.get("args", {})),
        "mapping": lambda: dict(d.get("args", {})),
        "object": lambda: d.get("value"),
    }[d["kind"]]()
    p = case["pulse"]
    if p["kind"] == "si":
        pulse = rocking.OneSinePulse(**p["args"])
    elif p["kind"] == "nondim":
        pulse = rocking.OneSinePulse.from_nondim(block, **p["args"])
    else:
        pulse = p["value"]
    return block, damper, pulse, dict(case["options"])


def nan_fields(response) -> list[str]:
    """Numeric fields of a response (its history included) holding NaN where none is allowed."""
    import numpy as np

    summary = response.summary()
    bad = [k for k, v in summary.items() if k not in NAN_ALLOWED and v is not None and v != v]
    bad += [k for k in ("theta_max", "x_max", "t_end") if summary[k] is None]  # summary() shows NaN as None
    for k, v in (response.history or {}).items():
        if np.issubdtype(np.asarray(v).dtype, np.floating) and not np.all(np.isfinite(v)):
            bad.append(f"history.{k}")
    return sorted(set(bad))


def classify(case: dict, backend: str) -> dict:
    """Build and simulate ``case`` on ``backend``: its outcome and, if notable, a sample."""
    import warnings

    import rocking

    try:
        block, damper, pulse, options = build(case)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = rocking.simulate(block, damper, pulse, backend=backend, **options)
    except Exception as exc:  # noqa: BLE001 - classifying every exception is the point
        name = type(exc).__name__
        if name == "SimulationError":
            return {"outcome": "failed_run", "type": name, "message": str(exc)[:300]}
        clean = name in CLEAN and name in rocking.__all__
        return {"outcome": "clean_error" if clean else "other_exception", "type": name, "message": str(exc)[:300]}
    bad = nan_fields(r)
    if bad:
        return {"outcome": "nan_result", "type": ",".join(bad), "message": r.status}
    return {"outcome": "result", "type": r.status, "message": ""}


def _worker(conn, backend: str) -> None:
    import rocking  # noqa: F401 - imported once, before the first input

    while True:
        case = conn.recv()
        if case is None:
            return
        conn.send(classify(case, backend))


# --------------------------------------------------------------------------------------------- #
# The pool: time limits, restarts                                                                #
# --------------------------------------------------------------------------------------------- #


class Slot:
    """One worker process and the input it runs."""

    def __init__(self, ctx, backend: str):
        self.ctx, self.backend = ctx, backend
        self.start()

    def start(self) -> None:
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=_worker, args=(child, self.backend), daemon=True)
        self.proc.start()
        child.close()
        self.index, self.since = None, 0.0

    def give(self, index: int, case: dict) -> None:
        self.index, self.since = index, time.monotonic()
        self.conn.send(case)

    def kill(self) -> None:
        self.proc.kill()
        self.proc.join()
        self.conn.close()

    def poll(self, timeout: float):
        """The outcome of the running input, ``None`` while it runs; restarts a hung or dead worker."""
        if self.conn.poll(0.0):
            try:
                outcome = self.conn.recv()
            except EOFError:
                outcome = None
            if outcome is not None:
                self.index = None
                return outcome
        if not self.proc.is_alive():
            code = self.proc.exitcode
            self.kill()
            self.start()
            return {"outcome": "crash", "type": f"exit code {code}", "message": ""}
        elapsed = time.monotonic() - self.since
        if elapsed > timeout:
            self.kill()
            self.start()
            return {"outcome": "hang", "type": f"> {timeout:g} s", "message": ""}
        return None


def run_backend(cases: list[dict], backend: str, workers: int, timeout: float, progress: bool = True) -> list[dict]:
    """The outcome of every input on ``backend``, in input order."""
    ctx = mp.get_context("fork" if sys.platform != "win32" else "spawn")
    slots = [Slot(ctx, backend) for _ in range(workers)]
    outcomes: list[dict | None] = [None] * len(cases)
    todo = list(range(len(cases)))[::-1]
    done, started = 0, time.monotonic()
    try:
        while done < len(cases):
            busy = False
            for slot in slots:
                if slot.index is None and todo:
                    i = todo.pop()
                    slot.give(i, cases[i])
                if slot.index is None:
                    continue
                busy = True
                index = slot.index
                outcome = slot.poll(timeout)
                if outcome is not None:
                    outcomes[index] = outcome
                    done += 1
                    if progress and done % 500 == 0:
                        rate = done / (time.monotonic() - started)
                        print(f"  {backend}: {done}/{len(cases)} ({rate:.0f}/s)", file=sys.stderr, flush=True)
            if busy:
                mp.connection.wait([s.conn for s in slots if s.index is not None], timeout=0.05)
    finally:
        for slot in slots:
            slot.kill()
    return outcomes


OUTCOMES = ("clean_error", "result", "other_exception", "hang", "crash", "nan_result", "failed_run")


def jsonable(value):
    """``value`` with non-finite floats as strings (strict JSON)."""
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    return value


def report(cases: list[dict], outcomes: list[dict], samples: int = 20) -> dict:
    """Counts by outcome, types of the other exceptions, and samples of every notable outcome."""
    counts = Counter(o["outcome"] for o in outcomes)
    out = {"counts": {k: counts.get(k, 0) for k in OUTCOMES}}
    out["statuses"] = dict(Counter(o["type"] for o in outcomes if o["outcome"] == "result"))
    out["other_exception_types"] = dict(Counter(o["type"] for o in outcomes if o["outcome"] == "other_exception"))
    out["samples"] = {}
    for kind in ("other_exception", "hang", "crash", "nan_result", "failed_run"):
        rows = [(c, o) for c, o in zip(cases, outcomes) if o["outcome"] == kind][:samples]
        out["samples"][kind] = [{"input": jsonable(c), **o} for c, o in rows]
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=10_000, help="inputs per back end (default 10000)")
    parser.add_argument("--backends", nargs="+", default=["c", "numpy"], choices=["c", "numpy"])
    parser.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds per input before it is a hang")
    parser.add_argument("--seed", type=int, default=20240610, help="seed of the inputs (default 20240610)")
    parser.add_argument("--json", default="out/fuzz.json", help="report file (default out/fuzz.json)")
    args = parser.parse_args(argv)
    t0 = time.monotonic()
    cases = draw_inputs(args.n, args.seed)
    print(f"{len(cases)} inputs drawn (seed {args.seed}) in {time.monotonic() - t0:.1f} s", file=sys.stderr)
    full = {"n": len(cases), "seed": args.seed, "timeout_s": args.timeout, "backends": {}}
    for backend in args.backends:
        t0 = time.monotonic()
        outcomes = run_backend(cases, backend, args.workers, args.timeout)
        full["backends"][backend] = {**report(cases, outcomes), "seconds": round(time.monotonic() - t0, 1)}
        counts = full["backends"][backend]["counts"]
        print(f"{backend:6s} " + ", ".join(f"{k} {v}" for k, v in counts.items()) + f" ({time.monotonic() - t0:.0f} s)")
    path = Path(args.json)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(full, indent=1), encoding="utf-8")
    print(f"report written to {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
