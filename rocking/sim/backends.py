"""The simulator's back ends by name, each behind one interface: run one problem, run a batch, stop.

:data:`BACKENDS` holds ``"c"`` (:mod:`rocking.sim.c_backend`: compiled, fast) and ``"numpy"``
(:mod:`rocking.sim.numpy_backend`: SciPy's ``solve_ivp``, the reference). Both follow the phase
machine of ``docs/simulation.md``. :func:`simulate` adds the choice ``"auto"`` (:data:`AUTO`): C,
or NumPy with a :class:`BackendWarning` when C cannot be built for the model.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from contextlib import AbstractContextManager, ExitStack, contextmanager, nullcontext
from typing import Protocol

import numpy as np

from ..model.floor import check_model_floor
from ..model.loading import Model
from ..model.params import ParameterError
from . import c_backend
from .batch import Cases
from .boundary import STATUS
from .cbuild import CBuildError
from .problem import RESULT_FIELDS, Problem, Response, RunInputs, vertical_of


class BackendWarning(UserWarning):
    """The C back end could not be built; the NumPy back end ran instead."""


class Backend(Protocol):
    """What a back end does; every one gives the same results to the tolerance of its integrator."""

    #: Its phase machine follows a floor with friction (docs/model.md section 15); else it runs only ``mu = inf``.
    friction: bool

    def simulate(self, model: Model, p, settings: dict, record: bool = False) -> Response:
        """One run given as :func:`rocking.sim.problem.resolve` gives it (checked: not checked again)."""

    def simulate_cases(self, cases: Cases, threads: int = 1, lanes: bool = True) -> dict[str, np.ndarray]:
        """Every case of ``cases`` from rest, without history: one array per field of ``RESULT_FIELDS``; ``lanes``:
        several cases at once over vectors where the back end can (the C batch's lanes), else ignored."""

    def request_stop(self) -> None:
        """Stop the runs of this back end running now in this process, if it can stop them from outside."""

    def halted(self) -> AbstractContextManager[None]:
        """Inside the ``with``, the runs running now and those that start are stopped."""


class _C:
    """:mod:`rocking.sim.c_backend`."""

    friction = True

    def simulate(self, model: Model, p, settings: dict, record: bool = False) -> Response:
        return c_backend.simulate_settings(model, p, settings, record)

    def simulate_cases(self, cases: Cases, threads: int = 1, lanes: bool = True) -> dict[str, np.ndarray]:
        return c_backend.simulate_cases(cases, threads=threads, lanes=lanes)

    def request_stop(self) -> None:
        c_backend.request_stop()

    def halted(self) -> AbstractContextManager[None]:
        return c_backend.halted()


class _NumPy:
    """:mod:`rocking.sim.numpy_backend`, imported at its first run: ``import rocking`` loads no SciPy.

    Its runs hold the GIL, one case at a time: Ctrl-C interrupts them as any Python code, and a study
    runs them in worker processes, which it terminates; nothing else stops them from outside.
    """

    friction = True

    def simulate(self, model: Model, p, settings: dict, record: bool = False) -> Response:
        from . import numpy_backend

        return numpy_backend.simulate(Problem(model=model, p=p, **settings), record)

    def simulate_cases(self, cases: Cases, threads: int = 1, lanes: bool = True) -> dict[str, np.ndarray]:
        from . import numpy_backend

        out = {k: np.zeros(len(cases), dtype=t) for k, t in RESULT_FIELDS.items()}
        for i in range(len(cases)):
            r = numpy_backend.simulate(cases.problem(i))
            for k in RESULT_FIELDS:
                out[k][i] = STATUS.index(r.status) if k == "status" else getattr(r, k)
        return out

    def request_stop(self) -> None:
        """Nothing to stop: see the class."""

    def halted(self) -> AbstractContextManager[None]:
        return nullcontext()


#: The back ends by name.
BACKENDS: dict[str, Backend] = {"c": _C(), "numpy": _NumPy()}
#: The choice of C, or NumPy where C cannot be built.
AUTO = "auto"
#: Every choice of :func:`simulate`.
NAMES = (AUTO, *BACKENDS)
#: Each back end's name in a sentence.
LABELS = {"c": "C", "numpy": "NumPy"}


def for_floor(name: str, mu_s, model: Model) -> str:
    """The back end that runs on a floor of static friction ``mu_s`` what was asked of ``name`` (of :data:`NAMES`).

    ``name`` itself for ``mu_s = inf`` (every element of a batch's column), or when it follows friction
    (:attr:`Backend.friction`); for ``"auto"``, the first back end that does.

    Raises
    ------
    ParameterError
        A finite ``mu_s`` on a model without the phases of a floor with friction (its spec does not say
        ``[ground] friction = true``), or on a back end that does not follow friction, naming one that does.
    """
    mu_s = np.asarray(mu_s, dtype=float)
    if np.all(np.isinf(mu_s)):
        return name
    check_model_floor(mu_s, model)
    able = [other for other, backend in BACKENDS.items() if backend.friction]
    if name in able or (name == AUTO and able):
        return name if name != AUTO else able[0]
    who = "no back end follows" if name == AUTO or not able else f"the {LABELS[name]} back end does not follow"
    hint = f"backend={able[0]!r}" if able else "give mu = inf (the default), the paper's floor"
    shown_mu = float(mu_s[np.isfinite(mu_s)].ravel()[0])
    raise ParameterError(f"{who} a floor with friction yet (mu_s = {shown_mu:g}): {hint}")


def simulate(name: str, model: Model, p, settings: dict, record: bool = False) -> Response:
    """One run on the back end ``name`` of :data:`NAMES`, as :meth:`Backend.simulate`, with its
    :class:`~rocking.sim.problem.RunInputs`.

    ``"auto"`` runs C, or NumPy with a :class:`BackendWarning` when C cannot be built (the warning
    points at the caller of :func:`rocking.simulate`).
    """
    name = for_floor(name, settings["mu_s"], model)
    if name == AUTO:
        try:
            return _with_inputs(BACKENDS["c"].simulate(model, p, settings, record), model, p, settings, "c")
        except CBuildError as exc:
            warnings.warn(f"C back end unavailable, using NumPy: {exc}", BackendWarning, stacklevel=4)
        name = "numpy"
    return _with_inputs(BACKENDS[name].simulate(model, p, settings, record), model, p, settings, name)


def _with_inputs(response: Response, model: Model, p, settings: dict, name: str) -> Response:
    response.inputs = RunInputs(model, p, settings, name)
    if response.history is not None and settings.get("a_v", 0.0) != 0.0:
        # The vertical ground acceleration at the recorded samples: the loads of the history read it.
        response.history["agy"] = vertical_of(settings, response.history["t"])
    return response


def request_stop() -> None:
    """Stop every run of every back end running now in this process (:meth:`Backend.request_stop`)."""
    for backend in BACKENDS.values():
        backend.request_stop()


@contextmanager
def halted() -> Iterator[None]:
    """Every back end halted inside the ``with`` (:meth:`Backend.halted`)."""
    with ExitStack() as stack:
        for backend in BACKENDS.values():
            stack.enter_context(backend.halted())
        yield
