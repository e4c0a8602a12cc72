"""The attacks of issue 36 items 2 and 3 on a saved study, each run as ``rocking.load`` and ``rocking redraw`` in its
own process: refused in one line, traceback, hang, time and memory, the study's files unchanged.

Each attack is a copy of a small saved map (of the omd damper, or of a model variant for the attacks on the saved
model's name) changed as the issue says: NetCDF files with a dataset the record does not list (2.5e8 or 1e11
doubles never written; stored in an external file that is a FIFO or /dev/zero; virtual), a listed variable stored in
/dev/zero; records whose configuration (its hash made again) holds a model name of 100 kB or 1 MB or of nested
``$\\sqrt{...}$`` of depth 400, a vertical component without its phase, with a text phase or as a list, or pulse
directions ``[1, -1, 7]``. Each process is killed after ``--timeout`` seconds (a hang).

Usage::

    python bench/saved_attacks.py [--timeout 120] [--json out.json]

It prints one row per attack and process: exit code, lines printed, traceback, hang, seconds, largest resident
memory, and whether the study's ``.nc``/``.json`` are unchanged.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the rocking of this checkout, not an installed one

import rocking  # noqa: E402
from rocking.study.config import config_hash  # noqa: E402
from rocking.study.overturning_map import overturning_map  # noqa: E402
from rocking.study.storage import summary_hash  # noqa: E402
from tests.crafted_hdf5 import add_dataset, zero_global_heap  # noqa: E402

SQRT_400 = "$" + "\\sqrt{" * 400 + "x" + "}" * 400 + "$"


def _save(folder: Path, damper) -> Path:
    grids = rocking.Grid("Omega", 2.0, 6.0, 2), rocking.Grid("beta", 1.0, 6.0, 3)
    execution = rocking.Execution(workers=1, progress=False)
    setting = rocking.Setting(rocking.Block.reference())
    study = overturning_map(setting, damper, *grids, execution, runs=folder / "runs", full=True)
    rocking.save(study, folder)
    return folder / "map"


def _config(where: tuple, value):
    def change(stem: Path) -> None:
        meta = stem.with_suffix(".json")
        record = json.loads(meta.read_text())
        node = record["config"]
        for key in where[:-1]:
            node = node[key]
        node[where[-1]] = value
        record["config_sha256"], record["summary_sha256"] = (
            config_hash(record["config"]),
            summary_hash(record["summary"]),
        )
        meta.write_text(json.dumps(record))

    return change


def _fifo(stem: Path) -> None:
    os.mkfifo(stem.parent / "fifo")
    add_dataset(stem.with_suffix(".nc"), "extra", 250_000_000, external=str(stem.parent / "fifo"))


#: Each attack: (item, the saved study it changes, change(stem)).
ATTACKS = {
    "unlisted variable of 2.5e8 doubles": (2, "omd", lambda s: add_dataset(s.with_suffix(".nc"), "extra", 250_000_000)),
    "unlisted variable of 1e11 doubles": (2, "omd", lambda s: add_dataset(s.with_suffix(".nc"), "extra", 10**11)),
    "unlisted dataset stored in a FIFO": (2, "omd", _fifo),
    "unlisted dataset stored in /dev/zero": (
        2,
        "omd",
        lambda s: add_dataset(s.with_suffix(".nc"), "extra", 250_000_000, external="/dev/zero"),
    ),
    "unlisted virtual dataset": (
        2,
        "omd",
        lambda s: add_dataset(s.with_suffix(".nc"), "extra", 4, virtual=(str(s.with_suffix(".nc")), "Omega")),
    ),
    "listed variable x_max stored in /dev/zero": (
        2,
        "omd",
        lambda s: add_dataset(s.with_suffix(".nc"), "x_max", 16, external="/dev/zero", replace=True),
    ),
    "global heap zeroed (HDF5 loops on it)": (2, "omd", lambda s: zero_global_heap(s.with_suffix(".nc"))),
    "damper.model of 100 kB": (3, "variant", _config(("damper", "model"), "m" * 100_000)),
    "damper.model of 1 MB": (3, "variant", _config(("damper", "model"), "m" * 1_000_000)),
    "damper.model nested $\\sqrt{}$ depth 400": (3, "variant", _config(("damper", "model"), SQRT_400)),
    'vertical {"ratio": 0.5}': (3, "omd", _config(("vertical",), {"ratio": 0.5})),
    'vertical phase "0"': (3, "omd", _config(("vertical",), {"ratio": 0.5, "phase": "0"})),
    "vertical a list": (3, "omd", _config(("vertical",), [0.5, 0.0])),
    "directions.signs [1, -1, 7]": (3, "omd", _config(("directions", "signs"), [1, -1, 7])),
}


def _run(argv: list[str], timeout: float) -> dict:
    """Run ``argv``: exit code, output, seconds, largest resident memory (MB); killed after ``timeout`` s."""
    with tempfile.TemporaryFile("w+") as out:
        start = time.perf_counter()
        process = subprocess.Popen(argv, cwd=ROOT, stdout=out, stderr=subprocess.STDOUT)
        while True:
            pid, status, usage = os.wait4(process.pid, os.WNOHANG)
            if pid:
                process.returncode = code = os.waitstatus_to_exitcode(status)
                break
            if time.perf_counter() - start > timeout:
                process.kill()
                _, status, usage = os.wait4(process.pid, 0)
                process.returncode, code = -9, "hang"
                break
            time.sleep(0.02)
        out.seek(0)
        text = out.read()
    return {
        "exit": code,
        "lines": text.count("\n"),
        "traceback": "Traceback" in text,
        "seconds": round(time.perf_counter() - start, 2),
        "rss_mb": round(usage.ru_maxrss / 1024),
        "said": text.strip().splitlines()[-1][:160] if text.strip() else "",
    }


def _digest(stem: Path) -> str:
    return hashlib.sha256(b"".join(stem.with_suffix(s).read_bytes() for s in (".nc", ".json"))).hexdigest()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args(argv)
    folder = Path(tempfile.mkdtemp(prefix="saved-attacks-"))
    rows = []
    try:
        pendulum = {"m": 50.0, "l": 0.5, "x_p": 0.0, "y_p": 2.55, "k_phi": 0.0, "c_phi": 1.0}
        sources = {
            "omd": _save(folder / "omd", rocking.Tuning(0.05)),
            "variant": _save(folder / "variant", rocking.Variant("pendulum", pendulum)),
        }
        for i, (name, (item, source, change)) in enumerate(ATTACKS.items()):
            stem = folder / f"attack-{i}" / "map"
            stem.parent.mkdir()
            for suffix in (".nc", ".json"):
                shutil.copy(sources[source].with_suffix(suffix), stem.with_suffix(suffix))
            change(stem)
            before = _digest(stem)
            load = f"import rocking\ntry: rocking.load({str(stem)!r})\nexcept rocking.ParameterError as e: print(e)"
            for how, command in (
                ("rocking.load", [sys.executable, "-c", load]),
                ("rocking redraw", [sys.executable, "-m", "rocking", "redraw", str(stem)]),
            ):
                row = {"attack": name, "item": item, "process": how, **_run(command, args.timeout)}
                row["files_unchanged"] = _digest(stem) == before
                rows.append(row)
                print(
                    f"{name} | {how} | exit {row['exit']} | {row['lines']} line(s) | traceback {row['traceback']} | "
                    f"{row['seconds']} s | {row['rss_mb']} MB | files unchanged {row['files_unchanged']} | "
                    f"{row['said']}",
                    flush=True,
                )
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
