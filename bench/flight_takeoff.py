"""Why a stuck corner on a floor without friction takes off only where the free flight lifts it (docs/simulation.md,
"Flight"): a slender block falling over after a one-sine, where the floor's N reaches 0 while it holds F.

Runs the block (H = 2 m, B = 0.5 m, 1000 kg) under a one-sine of beta 5 and Omega = 2 pi / (p / 2) on the NumPy back
end, recorded every 0.1 ms, and prints at the first recorded N <= 0 (the first row past the root): theta, the
tangential force F the floor holds there, and the vertical acceleration of the pivot in free flight
(``flight_accel``), which would drive it into the floor::

    .venv/bin/python bench/flight_takeoff.py

``--map``: a 60 x 60 map of the reference block (Omega 0.5-15, beta 1-15, one-sines of sign +1, without and with the
demo's damper) on the C back end, on the paper's floor (mu_s = inf) and on floors of mu = 0.5, 0.8 and 2: the
responses that flew, ended jammed, overturned (docs/model.md section 16, "On a floor that never slides")::

    .venv/bin/python bench/flight_takeoff.py --map
"""

from __future__ import annotations

import math
import sys

import numpy as np

import rocking


def main() -> None:
    block = rocking.Block(2.0, 0.5, 1000.0)
    pulse = rocking.OneSinePulse.from_nondim(block, Omega=2 * math.pi / (0.5 * block.p), beta=5.0)
    r = rocking.simulate(block, None, pulse, backend="numpy", record=True, rtol=1e-10, record_dt=1e-4)
    h, model = r.history, r.inputs.model
    rocking_rows = np.flatnonzero((h["phase"] != 0) & (h["N"] <= 0.0))
    i = int(rocking_rows[0])
    state = [h[k][i] for k in model.state]
    p = [float(x) for x in r.inputs.p]
    ddv = model.functions.flight_accel(float(h["phase"][i]), *state, h["ag"][i], 0.0, *p)[model.nq + 1]
    print(
        f"status {r.status}, flights {r.flights}; N <= 0 first at t = {h['t'][i]:.4f} s: theta = {h['theta'][i]:.3f} "
        f"rad, F = {h['F'][i]:.0f} N held, the pivot's free-flight ddv = {float(ddv):.2f} m/s^2"
    )


def floors_map() -> None:
    from rocking.sim.cases import pulse_cases, run_cases
    from rocking.sim.problem import STATUS
    from rocking.study.config import Grid

    block = rocking.Block.reference()
    Omega, beta = Grid("Omega", 0.5, 15.0, 60).values(), Grid("beta", 1.0, 15.0, 60).values()
    damper = {"gamma": 0.05, "omega_ratio": 1.0, "zeta": 0.05, "h": 0.05}
    for mu in (math.inf, 2.0, 0.8, 0.5):
        floor = {} if math.isinf(mu) else {"floor": rocking.Floor(mu)}
        for name, args in (("bare", {}), ("damper", damper)):
            r = run_cases(pulse_cases(block, Omega[:, None], beta[None, :], sign=1, **args, **floor))
            status, flew = np.asarray(r["status"]), np.asarray(r["flights"]) > 0
            print(
                f"mu {mu:g} {name:6s}: {flew.sum()} of {status.size} flew, "
                f"{(status == STATUS.index('jammed')).sum()} jammed, {(status == 0).sum()} overturned"
            )


if __name__ == "__main__":
    floors_map() if "--map" in sys.argv[1:] else main()
