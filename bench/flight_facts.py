"""Every figure of flight's outside facts (issue 39, item 5; docs/model.md section 16).

    python bench/flight_facts.py [--cases 20] [--seed 39]

The yardstick is ``tests/flight_reference.py``: the block, bare or with its damper, on a floor it can leave, Newton and
Euler with contact forces and impulses typed by hand (independent of derive/, generated/ and rocking.sim). Printed:

1. the reference against the NumPy back end where nothing flies (horizontal pulses, mu = inf and finite);
2. its accelerations and impulses against ``rocking.reference.flight`` (typed apart);
3. the floor's drop at -1.5 g for 0.1 s: the closed form, the reference and both back ends; with restitution, the
   series of bounces; a fast rocking block that reaches N = 0 under a horizontal pulse and grazes;
4. Housner's restitution at a level landing on a corner (e_n = 0);
5. the energy at every landing of the random runs (reference, and both back ends' histories);
6. the random vertical pulses past the flight threshold, bare block and with random dampers: reference against both
   back ends (status, flights, impacts; theta_max, x_max, jump_max, flight_time).

A back end that does not follow flight yet (the floor's drop counts no flight) is said so and skipped.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import rocking  # noqa: E402
from tests import flight_reference as ref  # noqa: E402
from tests.flight_cases import (  # noqa: E402
    DROP_DT,
    Case,
    body,
    differences,
    drop_samples,
    history_energy,
    landings,
    project,
    random_cases,
    reference,
    typed_twice,
)

BACKENDS = ("numpy", "c")


def follows_flight(backend: str) -> bool:
    """Whether ``backend`` follows flight: the floor's drop takes off (counts a flight)."""
    a_v = drop_samples(rocking.Block.reference().g)
    motion = rocking.SampledMotion(np.zeros_like(a_v), dt=DROP_DT, a_v=a_v)
    return rocking.simulate(rocking.Block.reference(), None, motion, backend=backend, check="none").flights > 0


def ground_runs(n: int, seed: int, damper: bool) -> None:
    """1. Horizontal pulses, no flight in the reference: the reference and the NumPy back end at rtol 1e-10."""
    rng = np.random.default_rng(seed)
    worst, same, flown = {"theta_max": 0.0, "x_max": 0.0}, 0, 0
    for i in range(n):
        mu = math.inf if i % 2 else float(rng.uniform(0.2, 1.0))
        tuned = (("gamma", rng.uniform(0.02, 0.2)), ("omega_ratio", rng.uniform(0.5, 2)), ("zeta", 0.05), ("h", 0.05))
        beta, Omega, sign = rng.uniform(1.2, 4.0), rng.uniform(2.0, 12.0), int(rng.choice([-1, 1]))
        case = Case(beta, Omega, sign, 0.0, 0.0, mu, mu, tuned if damper else None)
        run = reference(case)
        if run.flights:  # a fast rocking block that lifts its pivot: the back ends end it (no flight yet)
            flown += 1
            continue
        got = project(case, "numpy")
        diff = differences(run, got)
        same += diff["same"]
        for name in worst:
            worst[name] = max(worst[name], diff[name])
    what = "with random dampers" if damper else "bare block"
    print(
        f"1. where nothing flies, {what}: {n} horizontal pulses (half at mu in [0.2, 1]), {flown} of which take off "
        f"in the reference;"
    )
    print(
        f"   the others: status and counts agree with NumPy (rtol 1e-10) in {same}/{n - flown}; largest relative "
        f"difference theta_max {worst['theta_max']:.2g}, x_max {worst['x_max']:.2g}"
    )


def impulses(n: int) -> None:
    """2. The reference against rocking.reference.flight (typed apart), on random flying states."""
    bare = max(typed_twice(n, 5, s) for s in (1, -1))
    damped = max(typed_twice(n, 7, s, damper=True) for s in (1, -1))
    print(f"2. Newton-Euler typed twice (reference vs rocking.reference.flight, {2 * n} random states per model):")
    print(f"   bare block, landing impulses at a corner and flat: largest difference {bare:.2g}")
    print(f"   with a damper, also the flight accelerations: {damped:.2g} (m/s, m/s^2, impulses per unit mass)")


def floor_drop() -> None:
    """3. The floor drops at -1.5 g for 0.1 s, sampled every 0.01 s."""
    blk = rocking.Block.reference()
    g, a_v = blk.g, drop_samples(blk.g)
    t0, t1, dv, peak = ref.free_flight(g, DROP_DT, a_v)
    ideal = 0.1 * (1 + (1 + math.sqrt(3)) / 2), math.sqrt(3) * g / 20
    print("3. the floor drops at -1.5 g for 0.1 s and stops; without ramps the flight lasts 0.1 (1 + (1 + sqrt 3) / 2)")
    print(f"   = {ideal[0]:.10f} s and lands at sqrt(3) g / 20 = {ideal[1]:.10f} m/s. Sampled every {DROP_DT} s with")
    print(f"   one-sample ramps, closed form: takeoff {t0:.10f} s, flight {t1 - t0:.12f} s, landing dv {dv:.12f} m/s,")
    print(f"   peak height {peak:.12f} m")
    for mu in (math.inf, 0.5):
        run = ref.simulate(body(blk), ref.Ground.sampled(DROP_DT, 0 * a_v, a_v), ref.Floor(mu, mu), 1.0, 1e-3)
        print(
            f"   reference mu={mu}: flight {run.flight_time:.12f} s ({run.flight_time / (t1 - t0) - 1:+.1e}), landing "
            f"dv {run.landings[0][6]:.12f} ({run.landings[0][6] / dv - 1:+.1e}), jump_max {run.jump_max:.12f} "
            f"({run.jump_max / peak - 1:+.1e}), {run.status}"
        )
        for backend in BACKENDS:
            motion = rocking.SampledMotion(np.zeros_like(a_v), dt=DROP_DT, a_v=a_v)
            floor = None if math.isinf(mu) else rocking.Floor(mu)
            got = rocking.simulate(
                blk, None, motion, backend=backend, rtol=1e-10, check="none", record=True, floor=floor
            )
            if not got.flights:
                print(
                    f"   {backend:5} mu={mu}: does not follow flight yet (status {got.status}, t_end {got.t_end:.9f} s)"
                )
                continue
            assert got.history is not None
            rows = landings(got.history)
            land = f"landing dv {got.history['dv'][rows[0][0]]:.12f}" if rows else "no landing row"
            print(
                f"   {backend:5} mu={mu}: flight {got.flight_time:.12f} s ({got.flight_time / (t1 - t0) - 1:+.1e}), "
                f"{land}, jump_max {got.jump_max:.12f} ({got.jump_max / peak - 1:+.1e}), {got.status}, "
                f"flights {got.flights}"
            )


def bounces() -> None:
    """3b. The drop landing with restitution: the geometric series of bounces; 3c. a fast rocking block that grazes."""
    blk = rocking.Block.reference()
    a_v, rest = drop_samples(blk.g), 1e-3 * blk.alpha * blk.p
    for e_n in (0.5, 0.8):
        k, series = ref.bounce_series(blk.g, DROP_DT, a_v, e_n, rest * blk.B / 2)
        run = ref.simulate(body(blk), ref.Ground.sampled(DROP_DT, 0 * a_v, a_v), ref.Floor(e_n=e_n), 3.0, rest)
        line = (
            f"   e_n={e_n}: {k} bounces, series {series:.12f} s; reference {run.flight_time:.12f} "
            f"({run.flight_time / series - 1:+.1e})"
        )
        for backend in BACKENDS:
            if follows_flight(backend):
                motion = rocking.SampledMotion(np.zeros_like(a_v), dt=DROP_DT, a_v=a_v)
                got = rocking.simulate(
                    blk,
                    None,
                    motion,
                    backend=backend,
                    rtol=1e-10,
                    check="none",
                    floor=rocking.Floor(e_n=e_n),
                    dtheta_rest=rest,
                )
                line += f"; {backend} {got.flight_time:.12f} ({got.flight_time / series - 1:+.1e}) {got.status}"
        print(line)
    case = Case(6.0, 2.0, -1, 0.0, 0.0, math.inf, math.inf)
    run, spec = reference(case), reference(case, lifts=False)
    line = (
        f"   a fast rocking block, horizontal one-sine beta 6, Omega 2, to the left: the reference grazes, {run.status}"
        f" at {run.t_end:.9f} s, {run.flights} flights, the floor pulling down to {run.least_N / weight(case):.2f} of "
        f"the weight (taking off at N = 0 instead, its pivot would go {-spec.lowest:.3f} m into the floor)"
    )
    for backend in BACKENDS:
        if follows_flight(backend):
            got = project(case, backend)
            line += f"; {backend} {got.status} at {got.t_end:.9f} s, {got.flights} flights"
    print(line)


def housner() -> None:
    """4. The corner -s lands at theta = 0 while the corner s is at rest: Housner's ratio."""
    blk = rocking.Block(H=2.0, B=0.5, M=1000.0)
    want = 1 - 1.5 * math.sin(blk.alpha) ** 2
    z = body(blk).centroid(1, 0.0, 0.0, 0.0, -0.7)
    for mu in (math.inf, 0.5):
        zp, law, k = ref.flat_law(body(blk), ref.Floor(mu, mu), z, 0.0)
        print(
            f"4. level landing on a corner, mu={mu}: lands on corner {k:+d} alone ({'stuck' if law == 0 else law}), "
            f"dtheta+/dtheta- = {zp[5] / -0.7:.15f}, Housner 1 - 3/2 sin^2 alpha = {want:.15f} "
            f"({zp[5] / -0.7 / want - 1:+.1e})"
        )


def weight(case: Case) -> float:
    """The weight of the case's block and damper [N]."""
    damper = case.the_damper
    return (case.block.M + (0.0 if damper is None else damper.m)) * case.block.g


def random_runs(n: int, seed: int, damper: bool) -> None:
    """5 and 6. The random vertical pulses: energy at landings and agreement with both back ends."""
    cases = random_cases(n, seed, damper)
    what = "with random dampers" if damper else "bare block"
    start = time.perf_counter()
    runs = [reference(case) for case in cases]
    took = time.perf_counter() - start
    laws = [law for run in runs for _, law, *_ in run.landings]
    rises = [after - before for run in runs for _, _, before, after, *_ in run.landings]
    print(
        f"5. {what}, energy at the landings of {n} random runs (reference, e_n = 0): {len(laws)} landings "
        f"({laws.count(0)} stuck, {laws.count(1) + laws.count(-1)} sliding, {laws.count(None)} jammed); "
        f"largest change {max(rises):.4g} J (never > 0)"
    )
    spec = [reference(case, lifts=False) for case in cases]
    changed = sum((a.status, a.flights, a.impacts) != (b.status, b.flights, b.impacts) for a, b in zip(runs, spec))
    sunk = [run.lowest for run in spec if run.lowest < -1e-9]
    pulls = [run.least_N / weight(case) for run, case in zip(runs, cases, strict=True)]
    statuses = [run.status for run in runs]
    print(
        f"6. {what}, {n} random vertical pulses past the flight threshold (reference {took:.1f} s): "
        f"{statuses.count('overturned')} overturn, {statuses.count('rest')} rest, {statuses.count('t_max')} t_max, "
        f"{sum(run.flights for run in runs)} flights, {sum(len(run.landings) for run in runs)} landings"
    )
    print(
        f"   a stuck corner of the paper's floor takes off where N <= 0 and the free flight lifts it, as the back ends"
        f" decided: no corner below the floor in flight (lowest {min(run.lowest for run in runs):.1e} m), the floor"
        f" pulling meanwhile in {sum(p < -1e-9 for p in pulls)} runs, down to {min(pulls):.2g}"
        f" of the weight. Where N alone"
        f" reaches 0 (the spec's rule) {changed} of the {n} runs end otherwise, and in {len(sunk)} a corner goes"
        f" through the floor in flight, down to {min(sunk, default=0.0):.2g} m"
    )
    for backend in BACKENDS:
        if not follows_flight(backend):
            print(f"   {backend:5}: does not follow flight yet")
            continue
        rows, same, changes = [], 0, []
        worst = dict.fromkeys(("theta_max", "x_max", "jump_max", "flight_time"), 0.0)
        for case, run in zip(cases, runs, strict=True):
            got = project(case, backend, record=True)
            diff = differences(run, got)
            same += diff["same"]
            for name in worst:
                worst[name] = max(worst[name], diff[name])
            if not diff["same"]:
                rows.append(
                    f"     differs: {case} reference {(run.status, run.flights, run.impacts, run.uplifts, run.slides)} "
                    f"{backend} {(got.status, got.flights, got.impacts, got.uplifts, got.slides)}"
                )
            assert got.history is not None
            for before, after in landings(got.history):
                e0, e1 = (history_energy(case.block, case.the_damper, got.history, i) for i in (before, after))
                changes.append((e1 - e0) / abs(e0))
        print(
            f"   {backend:5} (rtol 1e-10): status and counts agree in {same}/{n}; largest relative difference "
            + ", ".join(f"{k} {v:.2g}" for k, v in worst.items())
        )
        print(
            f"          energy at its {len(changes)} landings: largest relative change {max(changes, default=0):+.2g}"
        )
        for row in rows:
            print(row)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=20, help="random vertical pulses (default 20)")
    parser.add_argument("--seed", type=int, default=39, help="their seed (default 39, the tests')")
    args = parser.parse_args(argv)
    ground_runs(12, 1, damper=False)
    ground_runs(12, 2, damper=True)
    impulses(1000)
    floor_drop()
    bounces()
    housner()
    random_runs(args.cases, args.seed, damper=False)
    random_runs(args.cases, args.seed + 1, damper=True)


if __name__ == "__main__":
    main()
