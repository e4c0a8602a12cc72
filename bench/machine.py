"""Where and when a bench run measured, recorded beside its figures."""

from __future__ import annotations

import datetime
import os
import platform
import sys


def machine() -> dict:
    """Where and when this run measured: the date (UTC), the CPU, its cores, the load on them, Python."""
    model = next(
        (line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
        platform.processor() or platform.machine(),
    )
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "cpu": model,
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
