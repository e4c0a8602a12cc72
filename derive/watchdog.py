"""A derivation in a child process, stage by stage, each under a limit of CPU time.

The static bounds of a spec (:mod:`rocking.derive.cost`) refuse most
expressions that would keep SymPy busy for hours, but not every one: the work
of a stage depends on how the entries combine. The derivation therefore runs
in a child process that tells its parent when each stage begins
(:func:`rocking.derive.build.build`'s ``stage``), with the CPU time it has used;
the parent prints the stages' times. A stage's limit is CPU time, not the
clock's: a machine under load (a parallel test run, other users) slows the
clock's stages four times and more, never their CPU time, so a spec that
derives on a quiet machine derives under load too. The child enforces it on
itself (``RLIMIT_CPU``, set again as each stage begins: the kernel signals it
when the stage's CPU time is spent, and it exits with :data:`CPU_EXIT`); the
parent keeps a clock only as a backstop, :data:`WALL_FACTOR` times the limit,
for a child that waits without using the CPU. Where there is no
``RLIMIT_CPU`` (Windows) the limit is the clock's. The child hands back the
generated files as text: what is written does not depend on where it was
derived.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import signal
import sys
import time
from dataclasses import dataclass
from typing import Protocol

try:  # POSIX only; without it the limit is the clock's
    import resource
except ImportError:  # pragma: no cover - Windows
    resource = None  # type: ignore[assignment]

from .build import Built, build
from .cost import costliest_entry
from .names import SpecError, quote

#: Default time limit of one stage, in seconds (``--stage-limit``). The slowest stage of the shipped
#: variants takes 1.3 s (docs/variants.md, "Bounded derivations").
STAGE_LIMIT = 60.0
#: A stage that took this long gets its line even without ``--verbose``, in seconds.
SLOW_STAGE = 1.0
#: Seconds between the lines that say a stage is still running.
HEARTBEAT = 10.0
#: The clock's backstop of a stage, in multiples of its CPU limit: a child that waits (not computing) this long
#: is stopped too. Wide: two cores shared by seven processes slow a stage's clock some four times.
WALL_FACTOR = 10.0
#: Exit code of a child whose stage ran past its CPU time (its handler of SIGXCPU).
CPU_EXIT = 152


class TextStream(Protocol):
    """What :class:`StageLog` prints to: any object with ``write`` and ``flush``, as :func:`print` needs."""

    def write(self, text: str, /) -> object: ...

    def flush(self) -> object: ...


class DerivationFailed(SpecError):
    """The derivation of a spec that passed every check ran past a stage's time limit, or its process failed."""


@dataclass
class StageLog:
    """Where and how much of the stages' progress is printed.

    Attributes
    ----------
    model : str
        The model's name, at the start of each line.
    verbose : bool
        Every stage gets its line; otherwise only stages that take :data:`SLOW_STAGE` or longer.
    stream : file, optional
        Where the lines go (default: ``sys.stderr`` at the time of printing).
    """

    model: str
    verbose: bool = False
    stream: TextStream | None = None

    def _print(self, text: str) -> None:
        print(f"derive {self.model}: {text}", file=self.stream or sys.stderr, flush=True)

    def finished(self, stage: str, seconds: float) -> None:
        """A stage ended after ``seconds`` of CPU time."""
        if self.verbose or seconds >= SLOW_STAGE:
            self._print(f"{stage} ... {seconds:.1f} s")

    def running(self, stage: str, seconds: float, limit: float | None) -> None:
        """A stage has been running for ``seconds`` of the clock (its limit: ``limit`` s of CPU time)."""
        bound = f" (limit {limit:g} s of CPU time)" if limit else ""
        self._print(f"{stage} ... still running after {seconds:.0f} s{bound}")


def failure(exc: BaseException) -> str:
    """The message of a derivation that broke on a spec that passed every check: one line, no traceback."""
    return f"the derivation failed ({type(exc).__name__}: {' '.join(str(exc).split())[:200]})"


def cpu_limited() -> bool:
    """Whether a stage's limit is CPU time here (``RLIMIT_CPU`` and ``SIGXCPU`` exist), else the clock's."""
    return resource is not None and hasattr(signal, "SIGXCPU")


def _limit_cpu(limit: float | None) -> None:
    """Let the process use ``limit`` more seconds of CPU (``RLIMIT_CPU``, whole seconds up), then SIGXCPU."""
    if not limit or not cpu_limited():
        return
    soft, hard = math.ceil(time.process_time() + limit), resource.getrlimit(resource.RLIMIT_CPU)[1]
    resource.setrlimit(resource.RLIMIT_CPU, (soft if hard == resource.RLIM_INFINITY else min(soft, hard), hard))


def _child(spec, options: dict, writer, limit: float | None = None) -> None:
    """Derive ``spec`` and send the parent each stage as it begins (its name and the CPU time used so far), then
    the result or the error; each stage under ``limit`` seconds of CPU time (:func:`_limit_cpu`)."""
    if limit and cpu_limited():
        # Not the default action (a core dump): an exit the parent reads as the stage's limit.
        signal.signal(signal.SIGXCPU, lambda signum, frame: os._exit(CPU_EXIT))

    def stage(name: str) -> None:
        _limit_cpu(limit)
        writer.send(("stage", name, time.process_time()))

    try:
        built = build(spec, options, stage)
        writer.send(("done", built, time.process_time()))
    except SpecError as exc:
        writer.send(("refused", str(exc)))
    except Exception as exc:  # noqa: BLE001 - whatever SymPy raises on a spec past every check: one line in the parent
        writer.send(("failed", failure(exc)))
    finally:
        writer.close()


def _context():
    """Fork where there is fork (the child starts with SymPy imported), spawn elsewhere."""
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("fork" if "fork" in methods else "spawn")


def timeout_message(spec, stage: str, limit: float, clock: str = "CPU time") -> str:
    """The one-line error of a stage that ran past ``limit`` seconds of ``clock``: the stage, and the spec's
    costliest expression."""
    entry = costliest_entry(spec)
    suspect = f"; its costliest expression is {entry[0]} {quote(str(entry[1]))}" if entry else ""
    return (
        f"derive {spec.name}: stage {stage!r} ran past its limit of {limit:g} s of {clock}{suspect}; "
        "simplify the spec, or allow more time with --stage-limit SECONDS"
    )


def _receive(reader, child, spec, stage: str, limit: float | None):
    """The child's next message; a child that ended without one failed, or ran past its CPU limit."""
    try:
        return reader.recv()
    except EOFError:
        child.join()
        if limit and child.exitcode in (CPU_EXIT, -getattr(signal, "SIGXCPU", 0)):
            raise DerivationFailed(timeout_message(spec, stage, limit)) from None
        raise DerivationFailed(
            f"derive {spec.name}: the derivation process ended in stage {stage!r} (exit code {child.exitcode})"
        ) from None


def _watch(reader, child, spec, limit: float | None, log: StageLog) -> Built:
    """Follow the child's stages, printing them with their CPU time, until it sends its result; a stage past its
    CPU limit ends the child itself, and the clock's backstop (:data:`WALL_FACTOR`) kills it."""
    wall, clock = (limit * WALL_FACTOR, "wall-clock time") if limit and cpu_limited() else (limit, "time")
    stage, began, heartbeat, cpu = "start", time.monotonic(), HEARTBEAT, 0.0
    while True:
        elapsed = time.monotonic() - began
        if wall and elapsed >= wall:
            raise DerivationFailed(timeout_message(spec, stage, wall, clock))
        if elapsed >= heartbeat:
            log.running(stage, elapsed, limit)
            heartbeat += HEARTBEAT
        wake = min(heartbeat, wall) if wall else heartbeat
        if not reader.poll(max(wake - elapsed, 0.0)):
            continue
        kind, value, *used = _receive(reader, child, spec, stage, limit)
        if kind in ("stage", "done"):
            log.finished(stage, used[0] - cpu)
            cpu = used[0]
        if kind == "done":
            return value
        if kind == "refused":
            raise SpecError(value)
        if kind == "failed":
            raise DerivationFailed(value)
        stage, began, heartbeat = value, time.monotonic(), HEARTBEAT


def build_bounded(spec, options: dict | None = None, limit: float | None = STAGE_LIMIT, log: StageLog | None = None):
    """:func:`rocking.derive.build.build` in a child process, each stage under ``limit`` seconds of CPU time.

    Parameters
    ----------
    spec : Spec
        The model.
    options : dict, optional
        Derivation options.
    limit : float or None
        Seconds of CPU time a stage may take (of the clock where there is no ``RLIMIT_CPU``; the clock's backstop:
        :data:`WALL_FACTOR` times more); None or 0: no limit.
    log : StageLog, optional
        Where the stages are printed (default: slow stages, to stderr).

    Returns
    -------
    Built
        As :func:`rocking.derive.build.build` returns it.

    Raises
    ------
    SpecError
        For a spec or option the derivation refuses; :class:`DerivationFailed` when a
        stage runs past ``limit`` (the child is killed) or the derivation fails.
    """
    context = _context()
    reader, writer = context.Pipe(duplex=False)
    child = context.Process(target=_child, args=(spec, options, writer, limit), daemon=True)
    child.start()
    writer.close()  # the child holds the only writer: its end is the reader's end of file
    try:
        return _watch(reader, child, spec, limit, log or StageLog(spec.name))
    finally:
        if child.is_alive():
            child.kill()
        child.join()
        reader.close()
