"""What following a run to rest costs ``rocking simulate``: one response with the early verdict and followed to
rest, on the C back end, for the reference block (docs/model.md section 9) alone and with the reference damper
(gamma = 0.05, omega_m = p, zeta = 0.05, h = 0.05 m) under a few one-sine pulses.

Prints, per case and way, the status, the impacts, t_end and the mean wall time of one call of
``rocking.simulate`` (Python's overhead included) over ``--repeat`` calls after one warm-up call.

    python bench/simulate_to_rest.py
"""

from __future__ import annotations

import argparse
import time

import rocking

#: The pulses (beta, Omega): overturning, and safe with many impacts after the early verdict.
PULSES = ((5.0, 4.0), (2.0, 4.0), (1.5, 8.0))


def timed(block, damper, pulse, early_verdict: bool, repeat: int) -> tuple[rocking.Response, float]:
    """The response and the mean wall time of one call, s."""
    rocking.simulate(block, damper, pulse, early_verdict=early_verdict)
    start = time.perf_counter()
    for _ in range(repeat):
        response = rocking.simulate(block, damper, pulse, early_verdict=early_verdict)
    return response, (time.perf_counter() - start) / repeat


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=50, help="calls timed per case (default 50)")
    args = parser.parse_args()
    block = rocking.Block.reference()
    damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    for label, d in (("block alone", None), ("with damper", damper)):
        for beta, Omega in PULSES:
            pulse = rocking.OneSinePulse.from_nondim(block, beta=beta, Omega=Omega)
            cells = []
            for early in (True, False):
                r, seconds = timed(block, d, pulse, early, args.repeat)
                way = "early verdict" if early else "to rest"
                cells.append(f"{way}: {r.status} {r.impacts} impacts t_end {r.t_end:.3f} s {seconds * 1e3:.3f} ms")
            print(f"{label}, beta {beta:g}, Omega {Omega:g}: " + " | ".join(cells))


if __name__ == "__main__":
    main()
