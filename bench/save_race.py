"""Two `rocking map` commands saving the study name `map` into one --out, ROUNDS rounds each, concurrently (issue 36,
item 1). After every save, under the lock on the name, the map.png there must be the picture of the map.json there:
each gamma's own picture is drawn first, alone. Prints the counts. Run from the checkout to measure:
    python bench/save_race.py ROUNDS
"""

import hashlib
import json
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

ROUNDS = int(sys.argv[1])
tmp = Path(tempfile.mkdtemp())
GRID = ["--Omega", "2", "6", "2", "--beta", "1", "6", "3", "--workers", "1"]


def run(gamma, out):
    return subprocess.run(
        [sys.executable, "-m", "rocking", "map", *GRID, "--gamma", str(gamma), "--out", str(out)],
        capture_output=True,
        text=True,
    )


def snapshot(out):
    try:
        from rocking.study.files import name_lock

        lock = name_lock(out, "map")
    except ImportError:  # main: no lock to take
        import contextlib

        lock = contextlib.nullcontext()
    with lock:
        record = json.loads((out / "map.json").read_text())
        png = (out / "map.png").read_bytes()
    return record["config"]["damper"]["gamma"], hashlib.sha256(png).hexdigest(), png.startswith(b"\x89PNG")


expected = {}
for gamma in (0.05, 0.2):
    alone = tmp / f"alone-{gamma}"
    assert run(gamma, alone).returncode == 0
    g, png, _ = snapshot(alone)
    expected[g] = png
out = tmp / "out"
results = {"saves": 0, "rc != 0": 0, "other study's picture": 0, "unreadable": 0}
guard = threading.Lock()


def loop(gamma):
    for _ in range(ROUNDS):
        proc = run(gamma, out)
        g, png, readable = snapshot(out)
        with guard:
            results["saves"] += 1
            results["rc != 0"] += proc.returncode != 0
            results["unreadable"] += not readable
            results["other study's picture"] += readable and expected[g] != png


threads = [threading.Thread(target=loop, args=(g,)) for g in (0.05, 0.2)]
for t in threads:
    t.start()
for t in threads:
    t.join()
print(results)
