"""The figures of docs/model.md section 16 (flight and landing), measured on the generated NumPy functions.

1. The closed forms (L1), (L2) of the bare block's landing against Newton and Euler solved by hand
   (``rocking.reference.flight.block_landing``): the largest relative difference on random states.
2. The law of a plastic landing (``rocking.reference.flight.landing_law``) on random states of the block and of the
   block with its damper (``rocking.reference.verify.random_cases``), a floor of ``mu_s`` in [0.05, 1]: how many
   stick, slide, or have no consistent law, and the largest change of energy over the kinetic energy.
3. Newton's restitution with a sticking corner: the kinetic energy after over before, ``e_n = 1``, for the block
   tilted by 0.6 rad landing at ``dv = -1`` m/s with the spin and slip of least energy.

Prints each::

    .venv/bin/python bench/flight_landing.py
"""

from __future__ import annotations

from functools import partial

import numpy as np
from scipy.optimize import minimize

from rocking import load_model
from rocking.reference import flight as ref
from rocking.reference.verify import random_cases, rel_error

CASES = 2000


def closed_forms(seed: int = 0) -> float:
    """Largest relative difference of (L1), (L2) and Newton-Euler, both corners, both laws."""
    worst = 0.0
    for s in (1, -1):
        rng = np.random.default_rng(seed + (s > 0))
        v = random_cases(rng, CASES, s, damper=False)
        M, I_G, B, H, e, th, w = (v[k] for k in ("M", "I_G", "B", "H", "e", "theta", "dtheta"))
        du, dv = rng.normal(0.0, 1.0, CASES), -np.abs(rng.normal(0.0, 1.0, CASES))
        e_n, mu = rng.uniform(0.0, 1.0, CASES), rng.uniform(-1.0, 1.0, CASES)
        d = s * B / 2 + e
        P, Q = H / 2 * np.cos(th) + d * np.sin(th), d * np.cos(th) - H / 2 * np.sin(th)
        I_s = I_G + M * (d**2 + H**2 / 4)
        delta = (1 + e_n) * Q * dv - P * du
        stick = (w + M * delta / I_s, -M * du - M**2 * P * delta / I_s, -M * (1 + e_n) * dv + M**2 * Q * delta / I_s)
        P_n = -(1 + e_n) * dv / (1 / M + Q * (Q + mu * P) / I_G)
        slide = (w - (Q + mu * P) * P_n / I_G, du - (mu / M + P * (Q + mu * P) / I_G) * P_n, P_n)
        for law, mine in (("stick", stick), ("slide", slide)):
            hand = ref.block_landing(s, th, w, du, dv, M, I_G, B, H, e, e_n, mu, law == "stick")
            picked = (hand[0], hand[3], hand[4]) if law == "stick" else (hand[0], hand[1], hand[4])
            worst = max(worst, *(rel_error(a, b) for a, b in zip(mine, picked)))
    return worst


def plastic_landings(name: str, seed: int = 18) -> tuple[dict, float]:
    """Counts of each law and the largest energy change over the kinetic energy, ``e_n = 0``."""
    model = load_model(name)
    f, nq = model.functions, model.nq
    rng = np.random.default_rng(seed)
    laws = {"stick": 0, "slide": 0, "": 0}
    worst = -np.inf

    def energy(args, dq, dc):
        return f.flight_energy(*args[: 1 + nq], *dq, *args[1 + 2 * nq :], 0.0, *dc)

    for s in (1, -1):
        v = random_cases(rng, CASES, s, damper=name == "omd")
        du, dv = rng.normal(0.0, 1.0, CASES), -np.abs(rng.normal(0.0, 1.0, CASES))
        columns = [v["s"], *(v[k] for k in model.state), v["ag"], v["agy"], *(v[p] for p in model.parameters)]
        for i in range(CASES):
            args = [c[i] for c in columns]
            mu_s = rng.uniform(0.05, 1.0)
            dc = (du[i], dv[i])
            out, law = ref.landing_law(
                partial(f.landing_stick, *args, *dc, 0.0),
                partial(f.landing_slide, *args, *dc, 0.0),
                du[i],
                mu_s,
                mu_s * rng.uniform(0.5, 1.0),
            )
            laws[law] += 1
            if law:
                before = energy(args, args[1 + nq : 1 + 2 * nq], dc)
                kinetic = before - energy(args, [0.0] * nq, (0.0, 0.0))
                worst = max(worst, (energy(args, out[:nq], out[nq:-2]) - before) / kinetic)
    return laws, worst


def bounce() -> float:
    """Kinetic energy after over before of a sticking landing at ``e_n = 1`` (docstring, item 3)."""
    model = load_model("block")
    f = model.functions
    p = dict(M=1000.0, B=0.5, H=2.0, e=0.0, g=9.81, I_G=1000.0 * (0.25 + 4.0) / 12)
    params = [p[k] for k in model.parameters]

    def kinetic(dtheta, du, dv):
        state = [1.0, 0.6, dtheta, 0.0, 0.0, *params]
        return f.flight_energy(*state, 0.0, du, dv) - f.flight_energy(1.0, 0.6, 0.0, 0.0, 0.0, *params, 0.0, 0.0, 0.0)

    w, du = minimize(lambda z: kinetic(z[0], z[1], -1.0), [0.0, 0.0], method="BFGS").x
    after = f.landing_stick(1.0, 0.6, w, 0.0, 0.0, *params, du, -1.0, 1.0)
    return kinetic(*after[:3]) / kinetic(w, du, -1.0)


def main() -> None:
    print(
        f"(L1), (L2) against Newton-Euler by hand, {2 * CASES} states per law: largest relative difference "
        f"{closed_forms():.1e}"
    )
    for name in ("block", "omd"):
        laws, worst = plastic_landings(name)
        print(
            f"{name}: {2 * CASES} plastic landings: stick {laws['stick']}, slide {laws['slide']}, no consistent law "
            f"{laws['']}; largest energy change over the kinetic energy {worst:.1e}"
        )
    print(f"e_n = 1, sticking: kinetic energy after / before = {bounce():.3f}")


if __name__ == "__main__":
    main()
