"""A 400 x 400 ``rocking map`` from the command line, everything included, against its simulation alone.

Runs ``rocking map --Omega 1 10 N --beta 1 10 N --workers W --no-progress`` as a subprocess, adaptive (the
default) and with ``--full``, each with a fresh output folder (its tiles in ``OUT/runs``, so no tile is
reused): the wall time and the children's CPU time of each run. The command's defaults are the bench's
(bench/adaptive.py): the reference block of docs/model.md section 9, a sine pulse, a damper with gamma = 0.05,
omega_m = p, zeta = 0.05, h = 0.05 m, rtol = 1e-8, both directions (the block is eccentric), coarse step 16
verified from step 16. Alternating with the commands, in each run: the same maps in this process, the
computation only (``overturning_map`` on fresh tiles, as bench/adaptive.py times it), and the whole command on
a 2 x 2 map (its fixed cost). Then each file the command writes, written here from the adaptive map by the
functions it calls (rocking.study.storage.save's writers, the figure of rocking.plot.figures.draw laid out and
written by its write_figure, and the PDF it writes on request, --pdf, with that layout), and the
start of the command (``rocking --version``: its imports and its parser), and the CPU of the commands that answer
at once (``rocking --help``, a one-response ``rocking simulate``). First, rocking's bytecode is compiled where
missing, as ``make setup`` does (a user's commands after the first do not recompile rocking, unless Python is told
not to write bytecode, PYTHONDONTWRITEBYTECODE, and nothing compiled it). Every time is the best of the runs
(the commands' and simulations' medians are recorded too); a file's is then written by libraries already
loaded, whose loading is part of the fixed cost.

    python bench/cli_map.py                            # 5 runs of each: about 4 minutes on 2 cores
    python bench/cli_map.py -n 200 --runs 1 --json out/cli-200.json
    python bench/cli_map.py --coarse 32 --verify 16 --json out/cli-400-32.json   # another refinement
    python bench/cli_map.py --fixed --runs 20          # the fixed cost alone: about a minute
"""

from __future__ import annotations

import argparse
import compileall
import importlib.util
import json
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from adaptive import GAMMA, H_MASS, OMEGA_RATIO, ZETA, setting_of
from machine import command_line, ended, machine

from rocking.plot.figures import DPI, FIGURES, save_figure, write_figure
from rocking.study.adaptive import line_mask
from rocking.study.config import Grid, Tuning, versions
from rocking.study.overturning_map import overturning_map
from rocking.study.storage import _data_files, save
from rocking.study.tiles import Execution

#: The installed command, beside this Python.
ROCKING = str(Path(sys.executable).parent / "rocking")
#: The side of the map whose command (with --full: 4 cells) measures the command's fixed cost: its start, the
#: first use of its libraries, its figure and files, with next to no simulation.
FIXED = 2
#: The targets of the speed issues: the command at most this many times its simulation ...
COMMAND_OVER_SIMULATION = 3.0
#: ... adaptive at least this many times faster than --full from the command line (issue 40) ...
SPEEDUP = 5.0
#: ... and the command on the 2 x 2 map within this many seconds of CPU (issue 40) ...
FIXED_CPU_S = 1.2
#: ... and the commands that answer at once, their arguments: the help, and one response without a figure ...
QUICK = (["--help"], ["simulate", "--beta", "3", "--Omega", "4"])
#: ... each within this many seconds of CPU (issue 40).
QUICK_CPU_S = 0.35
#: rocking's packages, whose bytecode the bench compiles as `make setup` does.
PACKAGES = ("rocking", "rocking.derive", "rocking.generated")


def bytecode() -> None:
    """Compile rocking's bytecode where it is missing or stale, as `make setup` does, and as a user's first command
    does where Python writes bytecode: where PYTHONDONTWRITEBYTECODE is set and nothing compiled it, every command
    would recompile rocking (0.1 s of CPU), which no user's second command does."""
    for package in PACKAGES:
        for folder in importlib.util.find_spec(package).submodule_search_locations:
            compileall.compile_dir(folder, quiet=1)


def command(n: int, workers: int, full: bool, out: str, refine: dict | None = None) -> list[str]:
    """The ``rocking map`` command line of an ``n x n`` map into the folder ``out``; ``refine``: the adaptive map's
    ``coarse`` and ``verify`` if not the default."""
    grids = ["--Omega", "1", "10", str(n), "--beta", "1", "10", str(n)]
    steps = ["--full"] if full else [f"--{key}={value}" for key, value in (refine or {}).items()]
    return [ROCKING, "map", *grids, "--workers", str(workers), "--no-progress", "--out", out, *steps]


def cpu(who: int) -> float:
    """The CPU time (user + system) so far of this process (its threads too) or of its finished children."""
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def timed_command(argv: list[str]) -> dict:
    """Run ``argv``: its wall time and the CPU time of the process and its children."""
    before, start = cpu(resource.RUSAGE_CHILDREN), time.perf_counter()
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
    return {"wall_s": time.perf_counter() - start, "cpu_s": cpu(resource.RUSAGE_CHILDREN) - before}


def simulation(n: int, workers: int, full: bool, runs: str, refine: dict | None = None):
    """The map of the command computed in this process on fresh tiles ``runs``: the study, and its wall and CPU
    times (of every thread of this process, its workers')."""
    grids = Grid("Omega", 1.0, 10.0, n), Grid("beta", 1.0, 10.0, n)
    before, start = cpu(resource.RUSAGE_SELF), time.perf_counter()
    study = overturning_map(
        setting_of("sine"),
        Tuning(GAMMA, OMEGA_RATIO, ZETA, H_MASS),
        *grids,
        Execution(workers=workers, progress=False),
        runs=runs,
        full=full,
        **(refine or {}),
    )
    return study, {"wall_s": time.perf_counter() - start, "cpu_s": cpu(resource.RUSAGE_SELF) - before}


def seconds(write, *args, **options) -> float:
    """Seconds of ``write(*args, **options)``."""
    start = time.perf_counter()
    write(*args, **options)
    return time.perf_counter() - start


def outputs(study, folder: Path) -> dict:
    """Seconds to write each file the command writes of ``study`` into ``folder``, one writer at a time, and
    the whole of the command's two steps (the data files and their JSON record; the figures)."""
    times = {}
    # The writers save() calls in turn, file by file (its JSON record aside, timed with them below).
    for file, write in _data_files(study, "map", versions()).items():
        times[file] = seconds(write, folder / file)
    times["save (NetCDF, CSV, JSON)"] = seconds(save, study, folder / "saved")
    start = time.perf_counter()
    figure = FIGURES["map"](study)
    times["figure (built)"] = time.perf_counter() - start
    # As draw(): the figure laid out once and written as a PNG; with --pdf, the PDF too, with the same layout.
    times["map.png"] = seconds(write_figure, figure, folder, "map", ("png",))
    times["map.pdf"] = seconds(save_figure, figure, folder / "map.pdf", DPI)
    return times


def edge_responses(study) -> int:
    """The responses of an adaptive map on the edges of its coarse blocks (every ``coarse``-th row and column of
    the grid, and its last), which its verification computes whole (rocking.study.adaptive.line_mask): the price of
    its guarantee, ``2 / coarse`` of the grid's cells whatever the map."""
    computed = study.data["computed"].transpose("part", "Omega", "beta").values
    edges = line_mask(computed.shape[1:], study.config["refinement"]["coarse"])
    return len(study.config["directions"]["signs"]) * int((computed & edges).sum())


def rows(path: Path) -> int:
    """The rows of the CSV file ``path``, its header aside."""
    with open(path) as f:
        return sum(1 for _ in f) - 1


def start_up(runs: int) -> float:
    """The best wall time of ``rocking --version``: the command's imports, its parser, the interpreter."""
    return min(timed_command([ROCKING, "--version"])["wall_s"] for _ in range(runs))


def quick(runs: int) -> dict:
    """The least CPU time of each command of :data:`QUICK` in ``runs`` runs, by its command line."""
    best = {}
    for argv in QUICK:
        best[" ".join(["rocking", *argv])] = min(timed_command([ROCKING, *argv])["cpu_s"] for _ in range(runs))
    return best


def measure(n: int, workers: int, runs: int, refine: dict | None = None) -> dict:
    """Every figure of the bench: each command and simulation ``runs`` times, alternating, and the best of each
    (the shortest: on a shared machine, the other loads only add to a time); their medians too."""
    bytecode()
    samples: dict = {key: [] for key in ("adaptive", "full", "adaptive_simulation", "full_simulation", "fixed")}
    for _ in range(runs):
        with tempfile.TemporaryDirectory() as out:
            samples["fixed"].append(timed_command(command(FIXED, workers, True, out)))
        for full, name in ((False, "adaptive"), (True, "full")):
            with tempfile.TemporaryDirectory() as out:
                samples[name].append(timed_command(command(n, workers, full, out, refine)))
            with tempfile.TemporaryDirectory() as tmp:
                study, times = simulation(n, workers, full, tmp, refine)
                samples[f"{name}_simulation"].append(times | {"responses": study.run["responses"]})
    with tempfile.TemporaryDirectory() as tmp:
        study, _ = simulation(n, workers, False, f"{tmp}/runs", refine)
        # Each round into a new folder: the writers refuse to replace a file (storage.save publishes by renames).
        each = [outputs(study, Path(tempfile.mkdtemp(dir=tmp))) for _ in range(runs)]
        written = {file: min(times[file] for times in each) for file in each[0]}
        csv_rows = rows(next(Path(tmp).glob("*/map.csv")))
    result = {"n": n, "workers": workers, "runs": runs, "samples": samples, "outputs": written, "csv_rows": csv_rows}
    result["adaptive_edge_responses"] = edge_responses(study)
    for name, values in samples.items():
        result[name] = {key: min(v[key] for v in values) for key in values[0]}
        result[f"{name}_median"] = {key: statistics.median(v[key] for v in values) for key in values[0]}
    result["start_up_s"] = start_up(max(runs, 3))
    result["quick_cpu_s"] = quick(max(runs, 3))
    return result | ratios(result)


def measure_fixed(workers: int, runs: int) -> dict:
    """The command's fixed cost alone: the 2 x 2 map's command ``runs`` times (its best and median) and the commands
    that answer at once (their best of ``runs``)."""
    bytecode()
    samples = []
    for _ in range(runs):
        with tempfile.TemporaryDirectory() as out:
            samples.append(timed_command(command(FIXED, workers, True, out)))
    result = {"workers": workers, "runs": runs, "samples": {"fixed": samples}}
    result["fixed"] = {key: min(v[key] for v in samples) for key in samples[0]}
    result["fixed_median"] = {key: statistics.median(v[key] for v in samples) for key in samples[0]}
    return result | {"quick_cpu_s": quick(runs)}


def fixed_line(r: dict) -> str:
    """The fixed cost's figures (:func:`measure_fixed`) against issue 40's targets, as one sentence."""
    best, median = r["fixed"], r["fixed_median"]
    return (
        f"The command on a {FIXED} x {FIXED} map (--full, {r['workers']} workers), best of {r['runs']} runs: "
        f"wall {best['wall_s']:.2f} s, CPU {best['cpu_s']:.2f} s (median {median['cpu_s']:.2f} s; "
        f"at most {FIXED_CPU_S:g} s)."
    ) + quick_text(r["quick_cpu_s"])


def ratios(result: dict) -> dict:
    """The ratios of the best times of ``result``, of the wall times and of the CPU's: each command over its
    simulation, full over adaptive; what the command adds to the adaptive map and may add for the target."""
    out = {}
    for time_s in ("wall_s", "cpu_s"):
        ratio = time_s.replace("_s", "")  # the wall time's ratios, then the CPU's
        for name in ("adaptive", "full"):
            out[f"{name}_over_simulation_{ratio}"] = result[name][time_s] / result[f"{name}_simulation"][time_s]
        for name in ("", "_simulation"):
            out[f"speedup{name}_{ratio}"] = result[f"full{name}"][time_s] / result[f"adaptive{name}"][time_s]
    # What the command adds to the adaptive map's simulation (start, figures, files), and what it may add at
    # most for the speed-up target: the adaptive command within the full one's time over SPEEDUP.
    out["adaptive_added_s"] = result["adaptive"]["wall_s"] - result["adaptive_simulation"]["wall_s"]
    out["added_for_target_s"] = result["full"]["wall_s"] / SPEEDUP - result["adaptive_simulation"]["wall_s"]
    return out


def table(r: dict) -> str:
    """The command lines against their simulations, as a Markdown table: the README's (bench/readme.py)."""
    rows = [
        f"| map (best of {r['runs']} runs, {r['workers']} workers) | command line, wall / CPU (s) | "
        "simulation only, wall / CPU (s) | command / simulation, wall / CPU |",
        "|---|---|---|---|",
    ]
    for name in ("adaptive", "full"):
        cli, sim = r[name], r[f"{name}_simulation"]
        rows.append(
            f"| {name} ({sim['responses']:,.0f} responses) | {cli['wall_s']:.1f} / {cli['cpu_s']:.1f} | "
            f"{sim['wall_s']:.1f} / {sim['cpu_s']:.1f} | {r[f'{name}_over_simulation_wall']:.2f}x / "
            f"{r[f'{name}_over_simulation_cpu']:.2f}x |"
        )
    rows.append(
        f"| adaptive over full | {r['speedup_wall']:.1f}x / {r['speedup_cpu']:.1f}x | "
        f"{r['speedup_simulation_wall']:.1f}x / {r['speedup_simulation_cpu']:.1f}x | |"
    )
    return "\n".join(rows)


def files_line(r: dict) -> str:
    """The seconds of each file the command writes, and of its start, as one sentence."""
    o = r["outputs"]
    return (
        f"Each file the command writes of the adaptive map, written in-process by the functions it calls, their "
        f"libraries loaded: the "
        f"figure built {o['figure (built)']:.2f} s, then map.png {o['map.png']:.2f} s (and map.pdf "
        f"{o['map.pdf']:.2f} s, written with --pdf only); map.nc {o['map.nc']:.2f} s, map.csv ({r['csv_rows']:,} rows) "
        f"{o['map.csv']:.2f} s; "
        f"the three with the JSON record {o['save (NetCDF, CSV, JSON)']:.2f} s. The command's start "
        f"(`rocking --version`: the interpreter, the imports, the parser) {r['start_up_s']:.2f} s; the whole "
        f"command on a {FIXED} x {FIXED} map (its fixed cost: the start, the libraries' first use, the figure and "
        f"files) {r['fixed']['wall_s']:.2f} s, {r['fixed']['cpu_s']:.2f} s of CPU."
    ) + (quick_text(r["quick_cpu_s"]) if "quick_cpu_s" in r else "")


def quick_text(cpu_s: dict) -> str:
    """The CPU of the commands that answer at once, as a sentence."""
    each = ", ".join(f"`{line}` {seconds:.2f} s" for line, seconds in cpu_s.items())
    return f" CPU of the commands that answer at once (at most {QUICK_CPU_S:g} s): {each}."


def targets_line(r: dict) -> str:
    """The two targets of the speed issue against the figures measured, as one sentence."""
    added, room, within = r["adaptive_added_s"], r["added_for_target_s"], r["full"]["wall_s"] / SPEEDUP
    room_text = (
        f"{room:.1f} s beyond its simulation for the {added:.1f} s the command adds"
        if room >= 0
        else f"less than its simulation alone, before the {added:.1f} s the command adds"
    )
    return (
        f"Targets: the adaptive command takes {r['adaptive_over_simulation_wall']:.2f}x its simulation's wall time "
        f"(at most {COMMAND_OVER_SIMULATION:g}x); adaptive is {r['speedup_wall']:.1f}x faster than `--full` from the "
        f"command line (at least {SPEEDUP:g}x), which needs the adaptive command within {within:.1f} s: {room_text} "
        f"(its start, figures and files; the command takes {r['fixed']['wall_s']:.1f} s on a {FIXED} x {FIXED} map, "
        f"{r['fixed']['cpu_s']:.2f} s of CPU: at most {FIXED_CPU_S:g} s)."
    ) + (limit_text(r) if "adaptive_edge_responses" in r else "")


def limit_text(r: dict) -> str:
    """What bounds the command's speed-up: the simulation's own, and the share of it the guarantee takes; the
    command's own CPU (its start, libraries, figure and files), which no refinement saves."""
    edges, adaptive = r["adaptive_edge_responses"], r["adaptive_simulation"]["responses"]
    full = r["full_simulation"]["responses"]
    own = r["adaptive"]["cpu_s"] - r["adaptive_simulation"]["cpu_s"]
    return (
        f" In CPU, adaptive is {r['speedup_cpu']:.1f}x faster from the command line and "
        f"{r['speedup_simulation_cpu']:.1f}x in its simulation alone, the most the command can reach: {edges:,} of "
        f"its {adaptive:,} responses ({100 * edges / full:.1f} % of the full map's {full:,}) are the edges of its "
        f"coarse blocks, computed whole for its guarantee. The command's own CPU beside its simulation ({own:.1f} s: "
        f"its start, libraries, figure and files) would hold the ratio to {r['full']['cpu_s'] / own:.1f}x were the "
        "adaptive map to compute no response at all."
    )


def report(r: dict) -> None:
    print(f"rocking map, {r['n']} x {r['n']}, {r['workers']} workers, best of {r['runs']} runs:")
    print(table(r))
    print(files_line(r))
    print(targets_line(r))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=400, help="values of Omega and of beta (default 400)")
    parser.add_argument("--workers", type=int, default=2, help="local workers of every map (default 2)")
    parser.add_argument("--runs", type=int, default=5, help="runs of each command and simulation (default 5)")
    parser.add_argument("--coarse", type=int, help="coarse step of the adaptive map (default: the command's)")
    parser.add_argument("--verify", type=int, help="first verification step of the adaptive map (default: --coarse)")
    parser.add_argument("--json", help="also write the figures to this file")
    parser.add_argument(
        "--fixed", action="store_true", help="only the fixed cost: the 2 x 2 map and the commands that answer at once"
    )
    args = parser.parse_args(argv)
    started = machine()
    if args.fixed:
        result = measure_fixed(args.workers, args.runs)
        print(fixed_line(result))
        if args.json:
            record = {"command": command_line("cli_map.py", argv), "machine": started | ended()}
            with open(args.json, "w") as f:
                json.dump(record | result, f, indent=2)
                f.write("\n")
        return 0
    refine = {key: value for key in ("coarse", "verify") if (value := getattr(args, key)) is not None}
    result = measure(args.n, args.workers, args.runs, refine)
    report(result)
    if args.json:
        commands = {
            name: " ".join(["rocking", *command(args.n, args.workers, full, "FRESH_FOLDER", refine)[1:]])
            for full, name in ((False, "adaptive"), (True, "full"))
        }
        record = {"command": command_line("cli_map.py", argv), "commands": commands, "machine": started | ended()}
        with open(args.json, "w") as f:
            json.dump(record | result, f, indent=2)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
