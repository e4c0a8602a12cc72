"""The C path of an earlier commit against this tree's, in paired runs of one process.

`python bench/compare.py REV`: builds the C library of commit REV (its sim.c
and its generated omd model, checked out in a temporary git worktree) and
this tree's, then times both on the 50 x 50 map of `make bench`, one after
the other, several times. On a shared machine the absolute speed drifts
within minutes; the ratio of runs taken side by side does much less. Also
says how far the results of the two differ. REV must speak the same C API as
this tree (rocking/c_backend.py refuses another).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))

from run import map_cases  # noqa: E402

from rocking.sim import cbuild  # noqa: E402
from rocking.sim import c_backend  # noqa: E402
from rocking.sim.cases import run_cases  # noqa: E402
from rocking.model.loading import load_model  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def library_of(rev: str, worktree: Path, cache: Path):
    """The loaded C library of the omd model at commit ``rev``."""
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(worktree), rev], check=True)
    model = load_model(worktree / "generated" / "omd")
    return c_backend._Library(model, cbuild.build(model, cache=cache, csrc=worktree / "rocking" / "csrc"))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rev", help="the earlier commit, e.g. HEAD~5 or a hash")
    parser.add_argument("--runs", type=int, default=6, help="paired runs (default 6)")
    args = parser.parse_args(argv)
    _, _, _, cases = map_cases(50)
    now = c_backend.library("omd")
    key = (now.model.folder, now.model.c_prefix)
    with tempfile.TemporaryDirectory() as tmp:
        worktree = Path(tmp) / "then"
        try:
            then = library_of(args.rev, worktree, Path(tmp) / "cache")
            seconds, results = {args.rev: [], "this tree": []}, {}
            for _ in range(args.runs):
                for name, lib in ((args.rev, then), ("this tree", now)):
                    c_backend._LIBRARIES[key] = lib
                    start = time.process_time()
                    results[name] = run_cases(cases, "c", 1)
                    seconds[name].append(time.process_time() - start)
        finally:
            c_backend._LIBRARIES[key] = now
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(worktree)], check=False)
    n = len(cases)
    for name, s in seconds.items():
        print(f"{name:>12}: best {n / min(s):7.0f}, median {n / np.median(s):7.0f} responses per CPU second")
    then_s, now_s = (np.array(s) for s in seconds.values())
    print(f"this tree / {args.rev}: {np.median(then_s / now_s):.2f}x (median of {args.runs} paired runs)")
    old, new = results.values()
    for k in ("overturned", "impacts", "uplifts", "status"):
        print(f"{k:>12}: {'identical' if np.array_equal(old[k], new[k]) else f'{np.sum(old[k] != new[k])} differ'}")
    for k in ("theta_max", "x_max", "t_end"):
        rel = np.abs(old[k] - new[k]) / np.maximum(np.abs(old[k]), np.finfo(float).tiny)
        print(f"{k:>12}: largest relative difference {rel.max():.2g} ({np.sum(rel > 1e-6)} cases above 1e-6)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
