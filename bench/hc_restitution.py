"""The restitution of one impact on a pad, measured by integrating it here, for each damping law.

A mass strikes a fixed pad at ``v0`` with nothing else acting on it (the definition of a pad's
restitution ``e_b``, docs/model.md section 11); the ODE ``m ddelta = -F(delta, ddelta)`` is integrated
with SciPy (DOP853, rtol 1e-11), nothing of the project's simulator, until the mass leaves the pad
(``delta = 0``) or the pad lets go (its force falls to 0): the restitution is the speed it leaves with
over ``v0``. Hunt-Crossley pads ``k delta^n (1 + chi ddelta / v0)``: the damping factor
``chi = rocking.model.params.hunt_crossley_damping(e_b)`` (new), Lankarani & Nikravesh's
``3 (1 - e_b) / 2`` (the old one) and Flores et al.'s (2011) closed form ``8 (1 - e_b) / (5 e_b)``;
Kelvin-Voigt pads of damping ratio ``zeta_b`` that only push (the project's) and that pull too.
Then the same impacts through the project's simulator (both back ends), and the cost of a run as
``e_b`` falls (the NumPy back end, the README's response with
``--stops --bumper-law hunt-crossley --e-b E``). Prints each::

    .venv/bin/python bench/hc_restitution.py
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

import rocking
from rocking.model.params import (
    BUMPER_DAMPING_RATIO,
    BUMPER_RESTITUTION,
    hunt_crossley_damping,
    kelvin_voigt_restitution,
)

#: The restitutions of the table (issue 35) and those of the cost ladder.
TABLE = (0.1, 0.3, 0.5, 0.57, 0.7, 0.9, 0.99)
LADDER = (0.57, 0.1, 0.01, 1e-3)


def one_impact(force, v0: float = 1.0, m: float = 1.0, scale: float = 1.0) -> float:
    """The restitution of one impact at ``v0`` of a mass ``m`` on a pad of force ``force(delta, rate) >= 0``
    (``scale``: the contact's time scale, s)."""
    return impact(force, v0, m, scale)[0]


def impact(force, v0: float = 1.0, m: float = 1.0, scale: float = 1.0) -> tuple[float, float]:
    """``(restitution, duration)`` of the impact of :func:`one_impact`."""

    def law(t, y):
        return [y[1], -max(0.0, force(max(y[0], 0.0), y[1])) / m]

    def leaves(t, y):
        return y[0] if t > 0.0 else 1.0

    def lets_go(t, y):
        return force(max(y[0], 0.0), y[1]) if t > 0.0 else 1.0

    leaves.terminal = lets_go.terminal = True
    leaves.direction = lets_go.direction = -1
    sol = solve_ivp(law, (0.0, 1e3 * scale), [0.0, v0], "DOP853", rtol=1e-11, atol=1e-15, events=[leaves, lets_go])
    assert sol.status == 1, sol.message  # ended by an event: the mass left the pad
    return -sol.y[1, -1] / v0, sol.t[-1]


def hunt_crossley_force(chi: float, n: float = 1.5, k: float = 1.0, v0: float = 1.0):
    """The force ``k delta^n (1 + chi ddelta / v0)`` of a Hunt-Crossley pad met at ``v0``."""
    return lambda d, r: k * d**n * (1.0 + chi * r / v0)


def hunt_crossley(chi: float, n: float = 1.5, k: float = 1.0, v0: float = 1.0) -> float:
    """The measured restitution of a Hunt-Crossley pad of damping factor ``chi``."""
    return one_impact(hunt_crossley_force(chi, n, k, v0), v0)


def kelvin_voigt(zeta: float, pulls: bool = False) -> float:
    """The measured restitution of a Kelvin-Voigt pad (``k = m = 1``) of damping ratio ``zeta``; ``pulls``: the
    plain spring-dashpot, whose force may turn negative before the mass leaves."""
    if not pulls:
        return one_impact(lambda d, r: d + 2 * zeta * r)

    def law(t, y):
        return [y[1], -(y[0] + 2 * zeta * y[1])]

    def leaves(t, y):
        return y[0] if t > 0.0 else 1.0

    leaves.terminal, leaves.direction = True, -1
    sol = solve_ivp(law, (0.0, 1e3), [0.0, 1.0], "DOP853", rtol=1e-11, atol=1e-15, events=[leaves])
    return -sol.y[1, -1]


def restitution_table() -> None:
    columns = ("e_b", "chi (new)", "measured (new)", "3 (1 - e_b) / 2 (old)", "measured (old)")
    print("| " + " | ".join((*columns, "Flores 8 (1 - e_b) / (5 e_b)", "measured (Flores)")) + " |")
    print("|---|---|---|---|---|---|---|")
    for e_b in TABLE:
        chi, old, flores = hunt_crossley_damping(e_b), 1.5 * (1.0 - e_b), 8.0 * (1.0 - e_b) / (5.0 * e_b)
        print(
            f"| {e_b:g} | {chi:.6f} | {hunt_crossley(chi):.8f} | {old:.4f} | {hunt_crossley(old):.4f} "
            f"| {flores:.4f} | {hunt_crossley(flores):.4f} |"
        )
    worst = max(
        abs(hunt_crossley(hunt_crossley_damping(e), n, k, v0) - e)
        for e in np.linspace(0.1, 0.99, 12)
        for n, k, v0 in ((1.0, 1.0, 1.0), (1.5, 1e6, 0.3), (2.5, 10.0, 3.0))
    )
    print(f"\nnew: largest |measured - e_b| over 12 e_b in [0.1, 0.99], n = 1, 1.5, 2.5: {worst:.1e}")
    least = min(hunt_crossley(1.5 * (1.0 - e)) for e in np.linspace(1e-3, 1.0, 200))
    print(f"old: the least restitution of any e_b in [1e-3, 1]: {least:.4f}")


def simulator_table() -> None:
    """The same impacts through the project's simulator: a free 1 kg mass on the guide (no spring, no dashpot)
    of the reference block at rest strikes a pad of ``Stops(e_b=...)`` at 0.5 m/s, rtol 1e-11."""
    from rocking.sim.problem import make_problem
    from rocking.sim.run import run

    block, v0 = rocking.Block.reference(), 0.5
    print("\nThe simulator's rebound (free mass on the guide, block at rest, rtol 1e-11):")
    print("| e_b | numpy | c |\n|---|---|---|")
    for e_b in TABLE:
        stops = rocking.Stops(L=0.1, k_b=1e4, law="hunt-crossley", n=1.5, e_b=e_b)
        damper = rocking.Damper(m=1.0, k_m=0.0, c=0.0, h=0.05, stops=stops)
        still = rocking.OneSinePulse(a_g=0.0, omega_g=2 * math.pi)
        chi = stops.as_params()["chi_b"]
        _, tau = impact(hunt_crossley_force(chi, 1.5, 1e4, v0), v0)  # the contact's duration, by hand
        t_end = 0.1 / v0 + tau + 0.05
        y0 = np.array([0.0, 0.0, 0.0, v0])
        # No rest by energy: the mass must be followed until it coasts, one contact behind it.
        problem = make_problem(block, damper, still, rtol=1e-11, t_max=t_end, y0=y0, energy_rest=0.0, early_rest=False)
        rebounds = []
        for backend in ("numpy", "c"):
            r = run(problem, backend=backend, record=True)
            assert (r.status, r.uplifts, r.stop_contacts) == ("t_max", 0, 1), (r.status, r.uplifts, r.stop_contacts)
            rebounds.append(-r.history["dx"][-1] / v0)
        print(f"| {e_b:g} | {rebounds[0]:.8f} | {rebounds[1]:.8f} |")


def kelvin_voigt_table() -> None:
    z = BUMPER_DAMPING_RATIO
    print(f"\nKelvin-Voigt pad, zeta_b = {z:g} (Stops.at_edges):")
    print(
        f"  only pushes (the project's): measured {kelvin_voigt(z):.6f}, closed form {kelvin_voigt_restitution(z):.6f}"
    )
    print(
        f"  pulls too: measured {kelvin_voigt(z, pulls=True):.6f}, exp(-zeta_b pi / sqrt(1 - zeta_b^2)) "
        f"{math.exp(-z * math.pi / math.sqrt(1 - z * z)):.6f}"
    )
    chi = hunt_crossley_damping(BUMPER_RESTITUTION)
    print(f"  Hunt-Crossley default e_b = {BUMPER_RESTITUTION:.6f}: measured {hunt_crossley(chi):.6f}")


def cost_ladder() -> None:
    block = rocking.Block.reference()
    damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    pulse = rocking.OneSinePulse.from_nondim(block, beta=10, Omega=7.5)
    print("\nCost of a run (NumPy back end, best of 3) as e_b falls:")
    base = None
    for e_b in LADDER:
        stops = rocking.Stops.at_edges(block, damper, law="hunt-crossley", e_b=e_b)
        with_stops = dataclasses.replace(damper, stops=stops)
        best = math.inf
        for _ in range(3):
            start = time.perf_counter()
            r = rocking.simulate(block, with_stops, pulse, backend="numpy")
            best = min(best, time.perf_counter() - start)
        base = base or best
        print(
            f"  e_b = {e_b:g} (chi_b = {stops.as_params()['chi_b']:.4g}): {best:.3f} s, {best / base:.2f} x; "
            f"{r.stop_contacts} contact(s), bumper force max {r.bumper_force_max:.0f} N"
        )


if __name__ == "__main__":
    restitution_table()
    simulator_table()
    kelvin_voigt_table()
    cost_ladder()
