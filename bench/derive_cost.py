"""CPU time of derivations of costly positions: the measurements behind the static bounds of rocking.derive.cost.

The omd spec with its position x changed to each expression of :data:`SHAPES` is derived with the static bounds
lifted, each stage under a limit of CPU time (``--limit``, the watchdog's own); one line per expression: its
cost, whether the bounds refuse it, and the CPU seconds its derivation took or the stage it was stopped in.

    python bench/derive_cost.py --limit 150
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from pathlib import Path

import sympy

from rocking.derive import spec as spec_module
from rocking.derive import watchdog
from rocking.derive.cost import LIMITS, expression_cost, over_limit
from rocking.derive.spec import VARIANTS_DIR as VARIANTS

#: Positions x of the mass of the omd spec: within the bounds of issue 23 (degree 6, nesting 2), slow (issue 36).
SHAPES = (
    "x + h*sin(x)**2*cos(x)**2",
    "x + h*(sin(x) + cos(x))**4",
    "x + h*sin(x)**3*cos(x)**3",
    "x + h*(sin(x) + cos(x))**6",
    "x + h*sin(atan(x))",
)


def _spec(text: str, folder: Path):
    """The omd spec with the position x of its mass ``text``, read without the static bounds."""
    omd = (VARIANTS / "omd.toml").read_text(encoding="utf-8")
    path = folder / "costly.toml"
    path.write_text(omd.replace('position = ["x", "H + h"]', f'position = ["{text}", "H + h"]'), encoding="utf-8")
    checks = spec_module.check_spec_cost
    spec_module.check_spec_cost = lambda spec: None
    try:
        return spec_module.load_spec(path)
    finally:
        spec_module.check_spec_cost = checks


def measure(text: str, limit: float, folder: Path) -> str:
    """One line: the expression, its cost, the bounds' verdict, and its derivation's CPU time or where it stopped."""
    spec = _spec(text, folder)
    expr = spec.bodies[0].position[0]
    cost = expression_cost(expr, frozenset({sympy.Symbol("x", real=True)}))
    verdict = over_limit(cost) or "within the bounds"
    stages: list[float] = []
    log = watchdog.StageLog(spec.name, verbose=True, stream=_Lines(stages))
    start = time.perf_counter()
    try:
        watchdog.build_bounded(spec, None, limit, log)
        outcome = f"derived in {sum(stages):.1f} s CPU"
    except watchdog.DerivationFailed as exc:
        stage = re.search(r"stage '([^']+)'", str(exc))
        outcome = f"stopped in stage {stage.group(1) if stage else '?'} after {limit:g} s CPU"
    wall = time.perf_counter() - start
    return f"{text}: {expr}, {cost}, {verdict}; {outcome} ({wall:.0f} s of the clock)"


class _Lines:
    """A stream that keeps the CPU seconds of each stage's line (``... 1.2 s``)."""

    def __init__(self, seconds: list) -> None:
        self.seconds = seconds

    def write(self, text: str) -> None:
        found = re.search(r"\.\.\. (\d+\.\d) s$", text.strip())
        if found:
            self.seconds.append(float(found.group(1)))

    def flush(self) -> None:
        pass


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=float, default=150.0, help="CPU seconds per stage (default 150)")
    args = parser.parse_args(argv)
    print(f"bounds: {LIMITS}", flush=True)
    with tempfile.TemporaryDirectory() as folder:
        for text in SHAPES:
            print(measure(text, args.limit, Path(folder)), flush=True)
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    sys.exit(main())
