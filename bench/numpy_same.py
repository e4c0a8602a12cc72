"""The NumPy back end against itself across a change: every result and history column, bit for bit (hex).

Runs 18 cases (the bare block, omd and omd_stops on the paper's floor and on mu 0.3 - 0.4, one-sines of beta 1.5
to 5 that rock, rest and overturn, and omd under a vertical component below gravity) recorded, and writes their
results and histories as hex floats (``--save FILE``), or compares them with a file saved before (``--against
FILE``): the columns a history had before are compared, new ones listed. On the tree before a change::

    .venv/bin/python bench/numpy_same.py --save /tmp/before.json

and after it::

    .venv/bin/python bench/numpy_same.py --against /tmp/before.json
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

import rocking
from rocking import Vertical


def cases() -> dict:
    block = rocking.Block(2.0, 0.5, 1000.0)
    Omega = 2 * math.pi / (0.5 * block.p)

    def pulse(beta, vertical=None):
        return rocking.OneSinePulse.from_nondim(block, Omega=Omega, beta=beta, vertical=vertical)

    damper = rocking.Damper(100.0, 100.0 * (0.9 * block.p) ** 2, 20.0)
    stops = rocking.Damper(100.0, 100.0 * (0.9 * block.p) ** 2, 20.0, stops=rocking.Stops(0.05, 1e6, 100.0))
    out = {}
    for beta in (1.5, 2.2, 3.0, 5.0):
        out[f"bare {beta}"] = (block, None, pulse(beta), {})
        out[f"bare {beta} mu 0.3"] = (block, None, pulse(beta), {"mu": 0.3})
    for beta in (2.2, 4.0):
        out[f"omd {beta}"] = (block, damper, pulse(beta), {})
        out[f"omd {beta} mu 0.4"] = (block, damper, pulse(beta), {"mu": 0.4})
        out[f"stops {beta}"] = (block, stops, pulse(beta), {})
        out[f"stops {beta} mu 0.4"] = (block, stops, pulse(beta), {"mu": 0.4})
        out[f"omd {beta} vertical 0.3"] = (block, damper, pulse(beta, Vertical(0.3)), {})
    return out


def hexed() -> dict:
    out = {}
    for name, (block, damper, pulse, options) in cases().items():
        r = rocking.simulate(block, damper, pulse, backend="numpy", record=True, **options)
        row = {k: float(v).hex() if isinstance(v, float) else v for k, v in r.summary().items()}
        row["history"] = {k: [float(x).hex() for x in np.asarray(v, float)] for k, v in r.history.items()}
        out[name] = row
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = parser.add_mutually_exclusive_group(required=True)
    group.add_argument("--save", help="write the results here")
    group.add_argument("--against", help="compare with the results saved here")
    args = parser.parse_args()
    now = hexed()
    if args.save:
        with open(args.save, "w") as file:
            json.dump(now, file, sort_keys=True)
        print(f"{len(now)} cases saved to {args.save}")
        return
    with open(args.against) as file:
        before = json.load(file)
    same = 0
    for name, old in before.items():
        new = now[name]
        results = [k for k in old if k != "history" and old[k] != new.get(k)]
        columns = [k for k in old["history"] if old["history"][k] != new["history"].get(k)]
        added = [k for k in new["history"] if k not in old["history"]]
        same += not (results or columns)
        print(f"{name}: {'identical' if not (results or columns) else f'differ {results + columns}'}", end="")
        print(f" (new columns {', '.join(added)})" if added else "")
    print(f"{same} of {len(before)} cases identical in every result and every column they had")


if __name__ == "__main__":
    main()
