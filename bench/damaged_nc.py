"""Damaged copies of a real saved map's NetCDF file: ``rocking.load`` and ``rocking redraw`` refuse each in one line
naming the file, or read it whole (issue 36, item 2).

A small map is saved from the command line (``rocking map``, 4 x 5 pulses, both directions); ``-n`` copies of its
``map.nc`` are damaged, each by one of: byte flips (1 to 16 bytes at random places), a truncation (at a random
length), a zeroed block (64 to 4096 bytes at a random place); its JSON record is kept. Each copy is loaded
(``rocking.load``) and redrawn (``rocking redraw``, in the same process), in worker processes of ``--batch`` copies,
each copy with a time limit. Each copy ends as one of:

- ``refused``: a ``ParameterError`` of one line naming the file, and ``redraw`` exits 2 printing that one line;
- ``loaded``: the damage hit bytes that hold no data (the checksum of the variables is the record's), and
  ``redraw`` draws it;
- ``foreign``: any other exception, or ``redraw`` printing more than one line (a traceback);
- ``hang``: no answer within ``--timeout`` seconds (the worker is killed);
- ``crash``: the worker died (a signal, a fault of the C library).

Usage::

    python bench/damaged_nc.py [-n 400] [--seed 36] [--batch 50] [--timeout 60] [--json out.json]

It prints the counts, and the copies that were not refused or loaded.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import selectors
import shutil
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the rocking of this checkout, not an installed one

#: The map saved and damaged: as small as a map of both directions gets, its file a real NetCDF-4 one.
MAP = ["map", "--Omega", "1", "6", "4", "--beta", "1", "6", "5", "--gamma", "0.04", "--no-progress", "--workers", "1"]

#: The damages, each ``damage(data, rng) -> bytes``.
DAMAGES = ("flip", "truncate", "zero")


def damage(data: bytes, kind: str, rng: np.random.Generator) -> bytes:
    """``data`` damaged by ``kind`` (one of :data:`DAMAGES`) at places drawn from ``rng``."""
    out = bytearray(data)
    if kind == "flip":
        for at in rng.integers(0, len(out), rng.integers(1, 17)):
            out[at] ^= int(rng.integers(1, 256))
    elif kind == "truncate":
        del out[int(rng.integers(0, len(out))) :]
    else:
        size = int(rng.integers(64, 4097))
        at = int(rng.integers(0, max(1, len(out) - size)))
        out[at : at + size] = bytes(len(out[at : at + size]))
    return bytes(out)


def copies(source: Path, folder: Path, n: int, seed: int) -> list[dict]:
    """``n`` damaged copies of the saved map ``source/map.{nc,json}`` in ``folder``: ``copy-<i>/map.*``."""
    rng = np.random.default_rng(seed)
    data, record = (source / "map.nc").read_bytes(), (source / "map.json").read_bytes()
    made = []
    for i in range(n):
        kind = DAMAGES[i % len(DAMAGES)]
        stem = folder / f"copy-{i}" / "map"
        stem.parent.mkdir()
        stem.with_suffix(".nc").write_bytes(damage(data, kind, rng))
        stem.with_suffix(".json").write_bytes(record)
        made.append({"copy": i, "damage": kind, "stem": str(stem)})
    return made


def check_one(stem: str) -> dict:
    """Load and redraw one copy (in this process): its outcome and what was seen."""
    import rocking
    from rocking.cli.main import main

    try:
        rocking.load(stem)
        outcome, text = "loaded", ""
    except rocking.ParameterError as exc:
        text = str(exc)
        outcome = "refused" if "\n" not in text and stem in text else "foreign"
    except Exception as exc:  # noqa: BLE001  (what the bench counts)
        outcome, text = "foreign", f"{type(exc).__name__}: {exc}"[:300]
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            code = main(["redraw", stem])
    except Exception as exc:  # noqa: BLE001
        code, text = -1, f"redraw: {type(exc).__name__}: {exc}"[:300]
    lines = err.getvalue().count("\n")
    expected = (0, 0) if outcome == "loaded" else (2, 1)
    if (code, lines) != expected:
        outcome, text = "foreign", f"redraw exit {code}, {lines} lines: {err.getvalue()[-300:]}"
    return {"outcome": outcome, "message": text[:300]}


def worker(stems: list[str]) -> None:
    """Check ``stems`` one by one, one JSON line each on stdout as it ends (the parent reads them)."""
    for stem in stems:
        print(json.dumps(check_one(stem)), flush=True)


def run_batches(made: list[dict], batch: int, timeout: float) -> None:
    """Check every copy of ``made`` in worker processes, ``batch`` at a time; a copy without an answer within
    ``timeout`` seconds is a ``hang`` (its worker is killed), a worker that dies marks its copy a ``crash``, and the
    next worker goes on after it."""
    start = 0
    while start < len(made):
        chunk = made[start : start + batch]
        argv = [sys.executable, __file__, "--worker", *(c["stem"] for c in chunk)]
        process = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        with selectors.DefaultSelector() as selector:
            selector.register(process.stdout, selectors.EVENT_READ)
            failed = None
            for c in chunk:
                if not selector.select(timeout):
                    process.kill()
                    failed = "hang"
                    break
                line = process.stdout.readline()
                if not line.startswith("{"):
                    failed = "crash"
                    break
                c.update(json.loads(line))
                start += 1
        process.kill()
        process.wait()
        process.stdout.close()
        if failed:
            made[start].update(outcome=failed, message=f"worker exit {process.returncode}")
            start += 1


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-n", type=int, default=400, help="damaged copies (default 400)")
    parser.add_argument("--seed", type=int, default=36)
    parser.add_argument("--batch", type=int, default=50, help="copies per worker process")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds a copy may take")
    parser.add_argument("--json", type=Path, help="write every copy's outcome there")
    parser.add_argument("--worker", nargs="+", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        worker(args.worker)
        return 0
    from rocking.cli.main import main as rocking

    folder = Path(tempfile.mkdtemp(prefix="damaged-nc-"))
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            assert rocking([*MAP, "--out", str(folder / "source")]) == 0
        made = copies(folder / "source", folder, args.n, args.seed)
        started = time.perf_counter()
        run_batches(made, args.batch, args.timeout)
        seconds = time.perf_counter() - started
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    counts = Counter(c.get("outcome", "not run") for c in made)
    by_damage = {kind: dict(Counter(c.get("outcome") for c in made if c["damage"] == kind)) for kind in DAMAGES}
    print(f"damaged copies of map.nc: {args.n} (seed {args.seed}) in {seconds:.0f} s: {dict(counts)}")
    print(f"by damage: {by_damage}")
    for c in made:
        if c.get("outcome") not in ("refused", "loaded"):
            print(f"  copy {c['copy']} ({c['damage']}): {c.get('outcome')}: {c.get('message', '')}")
    if args.json:
        args.json.write_text(json.dumps({"counts": dict(counts), "by_damage": by_damage, "copies": made}, indent=1))
    return 0 if set(counts) <= {"refused", "loaded"} else 1


if __name__ == "__main__":
    sys.exit(main())
