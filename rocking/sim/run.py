"""The public call: the response of a block, with or without its damper, to a pulse."""

from __future__ import annotations

import warnings

from ..model.params import ParameterError
from .problem import Problem, Response, make_problem

BACKENDS = ("auto", "c", "numpy")


class BackendWarning(UserWarning):
    """The C back end could not be built; the NumPy back end ran instead."""


def run(problem: Problem, backend: str = "auto", record: bool = False) -> Response:
    """Simulate a resolved :class:`Problem` on a back end.

    ``"auto"`` uses C and falls back to NumPy with a :class:`BackendWarning`
    when C cannot be built; ``"c"`` raises the build error instead.
    """
    if backend not in BACKENDS:
        raise ParameterError(f"backend must be one of {', '.join(BACKENDS)} (got {backend!r})")
    if backend != "numpy":
        from . import c_backend
        from .cbuild import CBuildError

        try:
            return c_backend.simulate(problem, record=record)
        except CBuildError as exc:
            if backend == "c":
                raise
            warnings.warn(f"C back end unavailable, using NumPy: {exc}", BackendWarning, stacklevel=3)
    from . import numpy_backend

    return numpy_backend.simulate(problem, record=record)


def simulate(
    block,
    damper,
    pulse,
    *,
    backend: str = "auto",
    rtol: float = 1e-8,
    t_max: float | None = None,
    record: bool = False,
    **settings,
) -> Response:
    """Response of ``block`` (with ``damper``, or ``None``) to ``pulse``.

    Parameters
    ----------
    block : Block
        The rocking block.
    damper : Damper or None
        The oscillating mass damper; ``None`` for the bare block.
    pulse : OneSinePulse
        The ground acceleration.
    backend : {"auto", "c", "numpy"}
        ``"c"``: compiled (fast); ``"numpy"``: SciPy's ``solve_ivp`` (the
        reference); ``"auto"``: C, or NumPy with a warning if C cannot be built.
    rtol : float
        Relative tolerance of the integrator.
    t_max : float, optional
        End of the run [s]; default 15 s after the pulse.
    record : bool
        Keep the time history (``Response.history``).
    **settings
        Further options of :func:`rocking.sim.problem.make_problem` (``model``,
        ``t_after``, ``dtheta_rest``, ``energy_rest``, ``max_events``, ``record_dt``).

    Returns
    -------
    Response
    """
    problem = make_problem(block, damper, pulse, rtol=rtol, t_max=t_max, **settings)
    return run(problem, backend=backend, record=record)
