"""Kelvin-Voigt against Hunt-Crossley pads of equal restitution: the same damper and pulses, the two laws of
Stops.at_edges.

The reference block, gamma = 0.05, omega_m = p, zeta = 0.05, h = 0.05 m, one-sine pulses on a
12 x 12 grid (beta in [2, 12], Omega in [2, 10]), C back end, default tolerances. The pads:
``Stops.at_edges(block, damper)`` (zeta_b = 0.2, a pad that only pushes) and
``Stops.at_edges(block, damper, law="hunt-crossley")`` (n = 1.5, the same force at full depth, and
e_b = BUMPER_RESTITUTION, the Kelvin-Voigt pad's restitution). Both restitutions are measured first, one
impact of a mass on each pad integrated by bench/hc_restitution.py's SciPy integration. Prints them, the
time of each pass and how the outcomes differ::

    .venv/bin/python bench/stops_laws.py
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from hc_restitution import hunt_crossley, kelvin_voigt

import rocking


def main() -> None:
    block = rocking.Block.reference()
    damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    laws = ("kelvin-voigt", "hunt-crossley")
    kv, hc = (rocking.Stops.at_edges(block, damper, law=law) for law in laws)
    zeta_b = kv.c_b / (2 * (kv.k_b * damper.m) ** 0.5)
    print(
        f"restitution of one impact, measured: Kelvin-Voigt pad (zeta_b = {zeta_b:g}) {kelvin_voigt(zeta_b):.6f}, "
        f"Hunt-Crossley pad (e_b = {hc.e_b:.6f}, chi_b = {hc.as_params()['chi_b']:.6f}) "
        f"{hunt_crossley(hc.as_params()['chi_b']):.6f}"
    )
    results = {}
    for law in laws:
        with_stops = dataclasses.replace(damper, stops=rocking.Stops.at_edges(block, damper, law=law))
        start, rows = time.perf_counter(), []
        for beta in np.linspace(2, 12, 12):
            for Omega in np.linspace(2, 10, 12):
                pulse = rocking.OneSinePulse.from_nondim(block, beta=beta, Omega=Omega)
                r = rocking.simulate(block, with_stops, pulse, backend="c")
                rows.append((r.overturned, r.theta_max, r.x_max, r.bumper_force_max))
        results[law] = np.array(rows, dtype=float)
        print(f"{law}: {len(rows)} responses in {time.perf_counter() - start:.2f} s")
    kv, hc = (results[law] for law in laws)
    print(
        f"verdicts differ: {int(np.sum(kv[:, 0] != hc[:, 0]))} of {len(kv)}; overturned {int(kv[:, 0].sum())} (KV)"
        f", {int(hc[:, 0].sum())} (HC)"
    )
    both = (kv[:, 0] == 0) & (hc[:, 0] == 0)
    change = np.abs(hc[both, 1] / kv[both, 1] - 1)
    print(f"theta_max where both survive: largest change {change.max():.3f}, median {np.median(change):.3f}")
    pushed = (kv[:, 3] > 0) & (hc[:, 3] > 0)
    print(f"bumper_force_max HC / KV: median {np.median(hc[pushed, 3] / kv[pushed, 3]):.2f}")
    print(f"x_max: largest {kv[:, 2].max():.4f} m (KV), {hc[:, 2].max():.4f} m (HC)")


if __name__ == "__main__":
    main()
