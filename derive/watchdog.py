"""A derivation in a child process, stage by stage, each under a time limit.

The static bounds of a spec (:mod:`rocking.derive.cost`) refuse most
expressions that would keep SymPy busy for hours, but not every one: the work
of a stage depends on how the entries combine. The derivation therefore runs
in a child process that tells its parent when each stage begins
(:func:`rocking.derive.build.build`'s ``stage``); the parent prints the
stages' times and kills the child when a stage runs past its limit. The child
hands back the generated files as text: what is written does not depend on
where it was derived.
"""

from __future__ import annotations

import multiprocessing
import sys
import time
from dataclasses import dataclass

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
    stream: object = None

    def _print(self, text: str) -> None:
        print(f"derive {self.model}: {text}", file=self.stream or sys.stderr, flush=True)

    def finished(self, stage: str, seconds: float) -> None:
        """A stage ended after ``seconds``."""
        if self.verbose or seconds >= SLOW_STAGE:
            self._print(f"{stage} ... {seconds:.1f} s")

    def running(self, stage: str, seconds: float, limit: float | None) -> None:
        """A stage has been running for ``seconds``."""
        bound = f" (limit {limit:g} s)" if limit else ""
        self._print(f"{stage} ... still running after {seconds:.0f} s{bound}")


def failure(exc: BaseException) -> str:
    """The message of a derivation that broke on a spec that passed every check: one line, no traceback."""
    return f"the derivation failed ({type(exc).__name__}: {' '.join(str(exc).split())[:200]})"


def _child(spec, options: dict, writer) -> None:
    """Derive ``spec`` and send the parent each stage as it begins, then the result or the error."""
    try:
        built = build(spec, options, lambda name: writer.send(("stage", name)))
        writer.send(("done", built))
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


def timeout_message(spec, stage: str, limit: float) -> str:
    """The one-line error of a stage that ran past ``limit``: the stage, and the spec's costliest expression."""
    entry = costliest_entry(spec)
    suspect = f"; its costliest expression is {entry[0]} {quote(str(entry[1]))}" if entry else ""
    return (
        f"derive {spec.name}: stage {stage!r} ran past its limit of {limit:g} s{suspect}; "
        "simplify the spec, or allow more time with --stage-limit SECONDS"
    )


def _receive(reader, child, spec, stage: str):
    """The child's next message; a child that ended without one failed."""
    try:
        return reader.recv()
    except EOFError:
        child.join()
        raise DerivationFailed(
            f"derive {spec.name}: the derivation process ended in stage {stage!r} (exit code {child.exitcode})"
        ) from None


def _watch(reader, child, spec, limit: float | None, log: StageLog) -> Built:
    """Follow the child's stages, printing them, until it sends its result; kill it at a stage's limit."""
    stage, began, heartbeat = "start", time.monotonic(), HEARTBEAT
    while True:
        elapsed = time.monotonic() - began
        if limit and elapsed >= limit:
            raise DerivationFailed(timeout_message(spec, stage, limit))
        if elapsed >= heartbeat:
            log.running(stage, elapsed, limit)
            heartbeat += HEARTBEAT
        wake = min(heartbeat, limit) if limit else heartbeat
        if not reader.poll(max(wake - elapsed, 0.0)):
            continue
        kind, value = _receive(reader, child, spec, stage)
        now = time.monotonic()
        log.finished(stage, now - began)
        if kind == "done":
            return value
        if kind == "refused":
            raise SpecError(value)
        if kind == "failed":
            raise DerivationFailed(value)
        stage, began, heartbeat = value, now, HEARTBEAT


def build_bounded(spec, options: dict | None = None, limit: float | None = STAGE_LIMIT, log: StageLog | None = None):
    """:func:`rocking.derive.build.build` in a child process, each stage under ``limit`` seconds.

    Parameters
    ----------
    spec : Spec
        The model.
    options : dict, optional
        Derivation options.
    limit : float or None
        Seconds a stage may take; None or 0: no limit.
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
    child = context.Process(target=_child, args=(spec, options, writer), daemon=True)
    child.start()
    writer.close()  # the child holds the only writer: its end is the reader's end of file
    try:
        return _watch(reader, child, spec, limit, log or StageLog(spec.name))
    finally:
        if child.is_alive():
            child.kill()
        child.join()
        reader.close()
