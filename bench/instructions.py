"""Instructions per response of the bench map under callgrind: a figure the machine's load does not change.

The map of `make bench` (bench/bench_map.py ``map_cases``: 50 x 50, Omega and beta in [1, 10], the
reference block and damper, rtol = 1e-8) runs on the C batch entry point, one thread, under
``valgrind --tool=callgrind``, which counts the instructions executed inside sim.c's
``simulate_one`` only (``--collect-atstart=no --toggle-collect=simulate_one``: not Python, not the
set-up of the cases, not the build). Printed as one line::

    python bench/instructions.py            # the whole map: about a minute
    python bench/instructions.py -n 20      # a 20 x 20 map
    python bench/instructions.py --vertical-ratio 0.5   # every pulse with an in-phase vertical component
    python bench/instructions.py --mu 0.3   # on a floor with friction mu_s = mu_k = 0.3 (docs/model.md section 15)
    python bench/instructions.py --lanes    # the batch in lanes (rocking/sim/csrc/lanes.h), AVX2 vectors

The scalar path is counted with the lanes off (``ROCKING_LANES=0``); the lanes inside sim.c's ``lanes_batch``
(lanes.c), which holds the vector stages, the scheduler and each run (``simulate_one`` on the lanes' own
stacks). Under valgrind, which runs no AVX-512, the lanes are AVX2's (4 doubles per vector);
``--isa sse2`` counts SSE2's.

A change to sim.c or to the generated model is judged by the change of this figure on a busy
machine, where times vary by tens of percent from one run to the next.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from bench_map import map_cases  # noqa: E402

from rocking import Floor  # noqa: E402
from rocking.sim.cases import run_cases  # noqa: E402

#: The C function whose instructions are counted (with its callees): sim.c's one run, which the batch entry
#: point calls per case. callgrind does not see the exported ``rocking_simulate_batch`` entered from libffi.
ENTRY = "simulate_one"
#: The function of the lanes' count: the batch in lanes, which calls the vector stages outside any one run.
LANES_ENTRY = "lanes_batch"


def floor_of(mu: float):
    """The floor of friction ``mu`` (static and kinetic), None for ``inf`` (the paper's)."""
    return None if mu == float("inf") else Floor(mu)


def run_map(n: int, vertical_ratio: float = 0.0, mu: float = float("inf")) -> int:
    """Run the ``n x n`` bench map on the C batch, one thread; the number of responses."""
    cases = map_cases(n, vertical_ratio, floor_of(mu))[-1]
    run_cases(cases, "c", 1)
    return len(cases)


def measure(
    n: int, vertical_ratio: float = 0.0, mu: float = float("inf"), lanes: bool = False, isa: str = "avx2"
) -> dict | None:
    """The instructions per response of the ``n x n`` bench map under callgrind; ``None`` without valgrind.
    ``lanes``: the batch in lanes, its vectors capped at ``isa`` (ROCKING_LANES_ISA); else the scalar path.

    Raises
    ------
    RuntimeError
        If valgrind fails or reports no instructions inside :data:`ENTRY` (a build that inlined it).
    """
    valgrind = shutil.which("valgrind")
    if valgrind is None:
        return None
    run_cases(map_cases(1, 0.0, floor_of(mu))[-1], "c", 1)  # the library built and cached outside valgrind
    entry = LANES_ENTRY if lanes else ENTRY
    env = {**os.environ, "ROCKING_LANES": "1" if lanes else "0", "ROCKING_LANES_ISA": isa}
    with tempfile.TemporaryDirectory() as tmp:
        command = [
            valgrind,
            "--tool=callgrind",
            "--collect-atstart=no",
            f"--toggle-collect={entry}",
            f"--callgrind-out-file={tmp}/callgrind.out",
            sys.executable,
            os.path.abspath(__file__),
            "--inside",
            "-n",
            str(n),
            "--vertical-ratio",
            repr(vertical_ratio),
            "--mu",
            repr(mu),
        ]
        done = subprocess.run(command, capture_output=True, text=True, env=env)
        collected = re.search(r"Collected : (\d+)", done.stderr)
        responses = re.search(r"^responses (\d+)$", done.stdout, re.M)
        if done.returncode != 0 or not (collected and responses) or int(collected.group(1)) == 0:
            raise RuntimeError(f"callgrind run failed ({done.returncode}): {done.stderr.strip()[-500:]}")
        count = int(responses.group(1))
        split = by_part(f"{tmp}/callgrind.out", count)
        width = re.search(r"^lanes (\d+)$", done.stdout, re.M)
    return {
        "responses": count,
        "instructions_per_response": int(collected.group(1)) / count,
        "entry": entry,
        "lanes": int(width.group(1)) if (lanes and width) else 0,
        "vertical_ratio": vertical_ratio,
        "mu": mu,
        "by_part": split,
    }


#: One line of ``callgrind_annotate --inclusive=no``: the instructions, the share, ``file:function [object]``.
_ANNOTATED = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*):([^:\s]+)(?: \[(.*)\])?$")

#: The parts of :func:`by_part`, in the order printed.
PARTS = ("libm sin and cos", "libm pow", "libm other", "generated model", "integrator (sim.c)", "lanes' vector stages")


def part_of(function: str, where: str, model_prefix: str) -> str:
    """Which of :data:`PARTS` a function's instructions count for: libm's by name, the generated model's by its
    prefix (``omd_...``), the rest sim.c's (its static functions, inlined or not, have no prefix)."""
    if "libm" in where or "sysdeps" in where:
        if "sin" in function or "cos" in function:
            return "libm sin and cos"
        return "libm pow" if "pow" in function else "libm other"
    if function.startswith(("stages_", "refresh_")):  # lanes_kernel.h's (right-hand side, sin/cos inlined)
        return "lanes' vector stages"
    return "generated model" if function.startswith(model_prefix + "_") else "integrator (sim.c)"


def by_part(profile: str, responses: int) -> dict | None:
    """The instructions per response of each of :data:`PARTS` (self cost, from ``callgrind_annotate``): the
    libm calls and the generated functions are what a bit-identical change of sim.c cannot remove (the same
    calls at the same arguments, the same generated arithmetic); ``None`` without ``callgrind_annotate``."""
    annotate = shutil.which("callgrind_annotate")
    if annotate is None:
        return None
    text = subprocess.run(
        [annotate, "--inclusive=no", "--threshold=100", profile], capture_output=True, text=True, check=True
    ).stdout
    lines = [m.groups() for m in map(_ANNOTATED.match, text.splitlines()) if m]
    library = next((os.path.basename(obj) for *_, obj in lines if obj and obj.endswith(".so") and "libm" not in obj))
    prefix = library.split("-")[0]
    split = dict.fromkeys(PARTS, 0.0)
    for count, where, function, obj in lines:
        split[part_of(function, f"{where} {obj or ''}", prefix)] += int(count.replace(",", "")) / responses
    return split


def line(result: dict | None) -> str:
    """The line `make bench` prints."""
    if result is None:
        return "bench map: instructions per response skipped (valgrind not found; apt-get install valgrind)"
    vertical = f", in-phase vertical ratio {result['vertical_ratio']:g}" if result.get("vertical_ratio") else ""
    if result.get("mu", float("inf")) != float("inf"):
        vertical += f", floor mu = {result['mu']:g}"
    path = f" in lanes ({result['lanes']} doubles per vector)" if result.get("lanes") else ""
    text = (
        f"bench map{vertical}{path}: {result['instructions_per_response']:,.0f} instructions per response "
        f"(callgrind, {result['responses']:,} responses, {result['entry']})"
    )
    if result.get("by_part"):
        parts = [(part, count) for part, count in result["by_part"].items() if count or part in PARTS[:5]]
        text += ": " + ", ".join(f"{part} {count:,.0f}" for part, count in parts)
    return text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=50, help="grid size per axis (default 50, the bench map)")
    parser.add_argument(
        "--vertical-ratio", type=float, default=0.0, help="in-phase vertical component of every pulse (default 0)"
    )
    parser.add_argument(
        "--mu", type=float, default=float("inf"), help="the floor's friction, static = kinetic (default inf)"
    )
    parser.add_argument("--lanes", action="store_true", help="the batch in lanes (default: the scalar path)")
    parser.add_argument(
        "--isa", choices=["avx2", "sse2"], default="avx2", help="the lanes' widest vectors (default avx2)"
    )
    parser.add_argument("--inside", action="store_true", help=argparse.SUPPRESS)  # the run callgrind watches
    args = parser.parse_args(argv)
    if args.inside:
        from rocking.sim import c_backend

        print(f"responses {run_map(args.n, args.vertical_ratio, args.mu)}")
        print(f"lanes {c_backend.lanes(map_cases(1)[-1].model)}")
        return 0
    print(line(measure(args.n, args.vertical_ratio, args.mu, args.lanes, args.isa)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
