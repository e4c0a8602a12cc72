"""The C path of an earlier commit against this tree's, in paired runs, with the differences of their results.

`python bench/compare.py REV`: checks commit REV out into a temporary git
worktree and copies this tree (uncommitted changes included) beside it; each
copy then runs the 50 x 50 map of `make bench` with its own code (its own
simulator, C sources and generated models, whatever their API), in its own
process, several times in turn. On a shared machine the absolute speed drifts
within minutes; the ratio of runs taken side by side does much less. Then says
how far the results of the two differ (`identical` means bit for bit).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

#: Run inside a copy of a tree: the bench map, with that tree's own code. Older trees
#: kept run_cases in rocking.batch.
RUN = """
import sys, time
import numpy as np
sys.path.insert(0, "bench")
from run import map_cases
try:
    from rocking.sim.cases import run_cases
except ImportError:
    from rocking.batch import run_cases
cases = map_cases(50)[3]
run_cases(cases, "c", 1)  # build and load outside the timing
seconds = []
for _ in range(int(sys.argv[2])):
    start = time.process_time()
    result = run_cases(cases, "c", 1)
    seconds.append(time.process_time() - start)
np.savez(sys.argv[1], seconds=np.array(seconds), n=len(cases), **result)
"""

#: Folders a copy needs to import ``rocking`` without installing it.
PACKAGES = {"derive": "derive", "generated": "generated"}


def importable(tree: Path) -> None:
    """Make ``tree``'s ``rocking`` importable from ``tree`` itself: link its installed subpackages in."""
    for package, folder in PACKAGES.items():
        link = tree / "rocking" / package
        if (tree / folder).is_dir() and not link.exists():
            link.symlink_to(tree / folder, target_is_directory=True)


def copy_of_this_tree(target: Path) -> Path:
    ignore = shutil.ignore_patterns(".venv", ".git", "out", "__pycache__", "*.egg-info", "build")
    for name in ("rocking", "derive", "generated", "bench"):
        shutil.copytree(ROOT / name, target / name, ignore=ignore, symlinks=True)
    return target


def run_tree(tree: Path, output: Path, cache: Path, runs: int) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree), "ROCKING_CACHE_DIR": str(cache)}
    subprocess.run([sys.executable, "-c", RUN, str(output), str(runs)], cwd=tree, env=env, check=True)
    with np.load(output) as z:
        return {k: z[k] for k in z.files}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rev", help="the earlier commit, e.g. HEAD~5 or a hash")
    parser.add_argument("--runs", type=int, default=6, help="paired runs (default 6)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        then = tmp / "then"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(then), args.rev], check=True)
        try:
            trees = {args.rev: then, "this tree": copy_of_this_tree(tmp / "now")}
            for tree in trees.values():
                importable(tree)
            seconds, last = {name: [] for name in trees}, {}
            for i in range(args.runs):
                for name, tree in trees.items():
                    last[name] = run_tree(tree, tmp / f"{tree.name}{i}.npz", tmp / "cache", 1)
                    seconds[name].append(float(last[name]["seconds"][0]))
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(then)], check=False)
    n = int(last["this tree"]["n"])
    for name, s in seconds.items():
        print(f"{name:>12}: best {n / min(s):7.0f}, median {n / np.median(s):7.0f} responses per CPU second")
    then_s, now_s = (np.array(s) for s in seconds.values())
    print(f"this tree / {args.rev}: {np.median(then_s / now_s):.2f}x (median of {args.runs} paired runs)")
    old, new = last[args.rev], last["this tree"]
    for k in ("overturned", "impacts", "uplifts", "status", "theta_max", "x_max", "t_critical", "t_end"):
        floats = old[k].dtype.kind == "f"
        if np.array_equal(old[k], new[k], equal_nan=floats):
            print(f"{k:>12}: identical")
            continue
        differ = old[k] != new[k]
        text = f"{k:>12}: {np.sum(differ)} of {n} differ"
        if floats:
            with np.errstate(invalid="ignore", divide="ignore"):
                rel = np.abs(new[k] - old[k]) / np.maximum(np.abs(old[k]), np.abs(new[k]))
            text += f", by at most {np.nanmax(rel[differ]):.2g} (relative), median {np.nanmedian(rel[differ]):.2g}"
        print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
