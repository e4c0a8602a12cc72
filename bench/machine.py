"""Where and when a bench run measured, recorded beside its figures."""

from __future__ import annotations

import datetime
import os
import platform
import sys

#: The vector instruction sets the C batch's lanes choose from (rocking/sim/csrc/lanes.h), widest first.
VECTOR_FLAGS = ("avx512f", "avx2", "sse2")


def machine() -> dict:
    """Where and when this run measured: the date (UTC), the CPU, its cores and vector instruction sets, the load
    on them, Python."""
    info = open("/proc/cpuinfo").read().splitlines() if os.path.exists("/proc/cpuinfo") else []
    model = next(
        (line.split(":", 1)[1].strip() for line in info if line.startswith("model name")),
        platform.processor() or platform.machine(),
    )
    flags = next((set(line.split(":", 1)[1].split()) for line in info if line.startswith("flags")), set())
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "cpu": model,
        "cpu_vector_flags": [f for f in VECTOR_FLAGS if f in flags],
        "cores": os.cpu_count(),
        "load_average_1min": os.getloadavg()[0],
        "python": platform.python_version(),
    }


def command_line(script: str, argv: list[str] | None) -> str:
    """The command that ran ``script`` with ``argv`` (default: this process's arguments), to quote beside its
    figures."""
    return " ".join([f"python bench/{script}", *(sys.argv[1:] if argv is None else argv)])


def ended() -> dict:
    """The load when a run ended, beside :func:`machine`'s at its start."""
    return {"load_average_1min_after": os.getloadavg()[0]}
