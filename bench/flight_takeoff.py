"""Why a stuck corner on a floor without friction takes off only where the free flight lifts it (docs/simulation.md,
"Flight"): a slender block falling over after a one-sine, where the floor's N reaches 0 while it holds F.

Runs the block (H = 2 m, B = 0.5 m, 1000 kg) under a one-sine of beta 5 and Omega = 2 pi / (p / 2) on the NumPy back
end, recorded every 0.1 ms, and prints at the first recorded N <= 0 (the first row past the root): theta, the
tangential force F the floor holds there, and the vertical acceleration of the pivot in free flight
(``flight_accel``), which would drive it into the floor::

    .venv/bin/python bench/flight_takeoff.py
"""

from __future__ import annotations

import math

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


if __name__ == "__main__":
    main()
