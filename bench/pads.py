"""The pads' force over random runs with end stops: never negative, and ``bumper_force_max`` its peak (issue 35).

Random blocks (``H`` 1.5-3 m, ``B`` 0.4-0.8 m, ``M`` 1,000 kg) with a 100 kg damper (``omega_m`` 1.5-3 rad/s,
``zeta`` 0-0.2) on a guide whose pads sit at ``L`` 0.08-0.2 m: Kelvin-Voigt (``k_b`` 1e5-3e6 N/m, ``zeta_b``
0.05-0.4) and Hunt-Crossley (``k_b`` 1e5-3e6 N/m^n, ``n`` 1 or 1.5, ``e_b`` 0.3-0.95) in turn, under one-sine,
one-cosine, symmetric and antisymmetric Ricker and Mavroeidis-Papageorgiou (``gamma_mp`` 2.5) pulses of
``a_g`` 1.2-3 times the uplift threshold and ``omega_g`` 4-12 rad/s, either sign; ``rtol`` 1e-10, no early
verdict, recorded every ``RECORD_DT``. For each run on each back end:

- ``F_b`` of the recorded rows (``rocking.sim.history.quantities``, the law at the state): its least value;
- the force the recorded motion shows (``tests/pads_reference.applied_force``: central differences of the
  recorded velocities less the free guide's accelerations): its least value, and its largest distance from
  ``F_b``, over the run's ``bumper_force_max``;
- ``bumper_force_max`` against the peak of ``F_b`` over the rows (``bumper_force_max`` may only be above it,
  by what falls between two samples);
- ``bumper_force_max`` of the C back end against NumPy's.

Run from the repository's root::

    .venv/bin/python bench/pads.py 200        # runs per law (NumPy on every fourth)
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import rocking  # noqa: E402
from rocking.sim.history import quantities  # noqa: E402
from rocking.sim.problem import make_problem  # noqa: E402
from rocking.sim.run import run  # noqa: E402
from tests.pads_reference import FAMILIES, applied_force, random_case  # noqa: E402

#: Spacing of the recorded histories [s]: the central differences' error is (omega_b RECORD_DT)^2 / 6 of the force.
RECORD_DT = 2e-4
FLOOR = rocking.load_model("omd_stops_hc").manifest["stops"][0]["approach_floor"]


def measure(problem, backend: str) -> dict:
    """What one run on ``backend`` gives of the checks above."""
    r = run(problem, backend=backend, record=True)
    h = r.history
    forces = quantities(problem.model, problem.p, h, np.arange(len(h["t"])))["F_b"]
    applied, law = applied_force(problem, h, FLOOR)
    scale = max(r.bumper_force_max, 1e-300)
    return {
        "bumper_force_max": r.bumper_force_max,
        "least_F_b": float(forces.min()),
        "least_applied": float(applied.min()) / scale if applied.size else 0.0,
        "applied_off": float(np.max(np.abs(applied - law))) / scale if applied.size else 0.0,
        "peak_gap": (r.bumper_force_max - float(forces.max())) / scale,
        "contacts": r.stop_contacts,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=int, nargs="?", default=40, help="runs per law (default 40)")
    parser.add_argument("--seed", type=int, default=35)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    start = time.perf_counter()
    rows, agreement = [], []
    for law in ("kelvin-voigt", "hunt-crossley"):
        for i in range(args.runs):
            block, damper, motion = random_case(rng, law, FAMILIES[i % len(FAMILIES)])
            settings = {"rtol": 1e-10, "early_verdict": False, "record_dt": RECORD_DT}
            problem = make_problem(block, damper, motion, t_after=4.0, **settings)
            c = measure(problem, "c")
            rows.append(c)
            if i % 4 == 0:
                n = measure(problem, "numpy")
                rows.append(n)
                if c["bumper_force_max"] > 0.0:
                    agreement.append(abs(n["bumper_force_max"] / c["bumper_force_max"] - 1.0))
    pushed = [r for r in rows if r["bumper_force_max"] > 0.0]
    print(f"runs: {len(rows)} ({args.runs} per law on C, every fourth on NumPy too), {len(pushed)} with a pad pushing")
    print(f"largest negative F_b of the recorded rows: {min(0.0, min(r['least_F_b'] for r in rows)):.3g} N")
    print(
        "force the recorded motion shows: least "
        f"{min(r['least_applied'] for r in pushed):.2g}, farthest from F_b {max(r['applied_off'] for r in pushed):.2g}"
        " (of bumper_force_max; the central differences' error)"
    )
    gaps = [r["peak_gap"] for r in pushed]
    print(f"bumper_force_max over the rows' peak of F_b: {min(gaps):.2g} to {max(gaps):.2g} (of bumper_force_max)")
    worst = max(agreement)
    print(f"bumper_force_max, NumPy against C: largest relative difference {worst:.2g} ({len(agreement)} runs)")
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
