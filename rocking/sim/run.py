"""The public call: the response of a block, with or without its damper, to a ground motion."""

from __future__ import annotations

from ..model.floor import floor_of
from ..model.params import ParameterError
from ..model.plausibility import check_run
from . import backends
from .accuracy import CHECKED, READ, check_choice, ladder, tolerance_check
from .backends import NAMES, BackendWarning
from .history import check_dt, default_dt, run_inputs
from .problem import OPTIONS, Problem, Response, check_flag, resolve

__all__ = ["NAMES", "BackendWarning", "rerecord", "run", "simulate"]

#: The options of :func:`simulate` passed on to :func:`~rocking.sim.problem.make_problem`.
SETTINGS = tuple(OPTIONS)


def _check_backend(backend: object) -> str:
    if not isinstance(backend, str) or backend not in NAMES:
        raise ParameterError(f"backend must be one of {', '.join(NAMES)} (got {backend!r})")
    return backend


def run(problem: Problem, backend: str = "auto", record: bool = False) -> Response:
    """Simulate a resolved :class:`Problem` on a back end.

    ``"auto"`` uses C and falls back to NumPy with a :class:`BackendWarning`
    when C cannot be built; ``"c"`` raises the build error instead.
    """
    _check_backend(backend)
    if not isinstance(problem, Problem):
        raise ParameterError(f"problem must be a rocking.sim.problem.Problem (got {type(problem).__name__})")
    record = check_flag("record", record)
    return _run(problem.model, problem.p, problem.settings(), backend, record)


def _run(model, p, settings: dict, backend: str, record: bool) -> Response:
    """The run of :func:`~rocking.sim.problem.resolve`'s ``(model, p, settings)`` on ``backend``."""
    return backends.simulate(backend, model, p, settings, record)


def rerecord(response: Response, dt: float | None = None) -> Response:
    """``response``'s run again, on the same back end, recorded every ``dt`` [s].

    What :meth:`Response.to_dataset` needs for a spacing the run was not recorded at: the same
    run (bit for bit on the same back end), with exact samples of the dense output at ``t = k dt``.

    Parameters
    ----------
    response : Response
        A response of :func:`simulate` or :func:`run` (it holds its :class:`~rocking.sim.problem.RunInputs`).
    dt : float, optional
        Spacing [s], at most 1e6 samples over ``t_max``; default the run's ``record_dt`` (for a run
        recorded at its events only, a hundredth of the pulse's period).

    Raises
    ------
    ParameterError
        A bad ``dt``, or one so small that the recorded run ends otherwise (its samples count as
        work, docs/simulation.md rule 5); a response without its inputs (a batch's row).
    """
    inputs = run_inputs(response)
    dt = default_dt(inputs.settings) if dt is None else check_dt(dt, inputs.settings["t_max"])
    again = _run(inputs.model, inputs.p, dict(inputs.settings, record_dt=dt), inputs.backend, True)
    ends = ("status", "t_end", "impacts", "uplifts")
    if any(getattr(again, k) != getattr(response, k) for k in ends):
        raise ParameterError(
            f"dt = {dt:g} s: recorded every dt the run ends otherwise ({again.status} at t = {again.t_end:g} s, "
            f"not {response.status} at {response.t_end:g} s): its samples count as work (max_steps); take a larger dt"
        )
    for f in CHECKED:
        setattr(again, f.name, getattr(response, f.name))
    return again


def simulate(
    block,
    damper,
    pulse,
    *,
    backend: str = "auto",
    rtol: float = 1e-8,
    t_max: float | None = None,
    record: bool = False,
    check: str | None = None,
    floor=None,
    mu=None,
    mu_k=None,
    **settings,
) -> Response:
    """Response of ``block`` (with ``damper``, or ``None``) to ``pulse``.

    Parameters
    ----------
    block : Block
        The rocking block.
    damper : Damper or None
        The oscillating mass damper; ``None`` for the bare block.
    pulse : OneSinePulse, OneCosinePulse, RickerWavelet, MavroeidisPapageorgiou or SampledMotion
        The ground acceleration (docs/model.md section 12); exactly one of these types.
    backend : {"auto", "c", "numpy"}
        ``"c"``: compiled (fast); ``"numpy"``: SciPy's ``solve_ivp`` (the
        reference); ``"auto"``: C, or NumPy with a warning if C cannot be built.
    rtol : float
        Relative tolerance of the integrator, in [1e-12, 0.01].
    t_max : float, optional
        End of the run [s], in (0, 3e4]; default ``t_after`` (15 s) after the pulse.
    record : bool
        Keep the time history (``Response.history``), sampled every ``record_dt`` (a setting below):
        :meth:`Response.to_dataset` reads it at that spacing, :func:`rerecord` runs it again at
        another; a bool, nothing else.
    check : {"tolerance", "none"}, optional
        ``"tolerance"``: run again down a ladder of tolerances (``rtol / 100``, at most
        1e-10, then by 100 to 1e-12), each rung as given and with the motion scaled by
        ``1 + 1e-9``, until a rung follows the trajectory above it
        (:func:`rocking.sim.accuracy.tolerance_check`); set ``Response.sensitive`` if a
        run's verdict differs or its ``theta_max`` or ``x_max`` by more than 10 %; a
        sensitive response is the tightest run's; ``theta_max_low``, ``theta_max_high``,
        ``overturned_fraction`` and ``check_runs`` give the spread of the runs
        (docs/simulation.md, "Sensitivity to the tolerance"). Default: ``"tolerance"``
        for a :class:`SampledMotion` (records, stochastic motions), ``"none"`` for a pulse.
    floor : Floor, optional
        The floor's Coulomb friction (docs/model.md section 15); default ``None``: the paper's floor,
        on which the base never slides (``mu_s = mu_k = inf``). Only a back end that follows friction
        runs a finite one (``backend="auto"`` picks it); the others refuse it.
    mu, mu_k : float, optional
        Shorthand for ``floor=Floor(mu, mu_k)``: static and kinetic friction (``mu_k`` default ``mu``),
        dimensionless; not beside ``floor``.
    **settings
        Further options of :func:`rocking.sim.problem.make_problem` (``model``,
        ``t_after``, ``dtheta_rest``, ``energy_rest``, ``max_events``, ``record_dt``,
        ``early_rest``, ``y0``, ``phase0``), with their types and ranges.

    Returns
    -------
    Response

    Warns
    -----
    PlausibilityWarning
        A valid input unlikely to be meant (:mod:`rocking.model.plausibility`): a damper heavier
        than half the block, a sampled motion whose peak, scaled, exceeds the largest recorded
        (4.36 g); the messages of ``rocking simulate``.

    Raises
    ------
    ParameterError
        A setting out of its range (named, with the range).
    CBuildError
        ``backend="c"`` and the C back end cannot be built.
    SimulationError
        The C integrator failed (a non-finite right-hand side).

    Examples
    --------
    The reference block (docs/model.md section 9) and a damper of 5 % of its
    mass tuned to its frequency parameter ``p``, under a one-sine pulse:

    >>> import rocking
    >>> block = rocking.Block.reference()
    >>> damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    >>> pulse = rocking.OneSinePulse.from_nondim(block, beta=5.0, Omega=4.0)
    >>> bare = rocking.simulate(block, None, pulse)
    >>> with_damper = rocking.simulate(block, damper, pulse)
    >>> bare.overturned, with_damper.overturned, with_damper.status
    (True, False, 'bounded')
    >>> round(with_damper.theta_max / block.alpha, 2)  # largest rotation over the slenderness angle
    1.18
    >>> round(with_damper.x_max, 2)  # the damper's stroke [m]: unlimited guide, on a 0.5 m base
    1.34

    Both back ends follow the same rules (docs/simulation.md):

    >>> r = rocking.simulate(block, damper, pulse, backend="numpy")
    >>> abs(r.theta_max - with_damper.theta_max) < 1e-6 * block.alpha
    True
    """
    # Checked before the run is resolved: a bad option is refused before any work.
    _check_backend(backend)
    record = check_flag("record", record)
    check = check_choice(check, pulse)
    if settings and settings.keys() - OPTIONS.keys():
        unknown = sorted(map(str, settings.keys() - OPTIONS.keys()))
        known = ", ".join(name for name in SETTINGS if name not in ("rtol", "t_max"))
        raise ParameterError(f"simulate: unknown option(s) {', '.join(unknown)}; known: {known}")
    # Only the options given are checked (the defaults are valid): rtol and t_max, named here, when not the defaults.
    if type(rtol) is not float or rtol != _RTOL:
        settings["rtol"] = rtol
    if t_max is not None:
        settings["t_max"] = t_max
    if floor is not None or mu is not None or mu_k is not None:
        settings["floor"] = floor_of(floor, mu, mu_k)
    model, p, case = resolve(block, damper, pulse, settings)
    check_run(block, model, p, pulse, stacklevel=2)
    # At the smallest valid rtol there is no tighter run to compare with: the response stands as it is.
    if check == "none" or len(ladder(case["rtol"])) == 1:
        return _run(model, p, case, backend, record)
    resolved = {case["rtol"]: (model, p, case)}

    def resolved_at(rtol: float) -> tuple:
        # Resolved again at each rung, not patched: the default atol scales with rtol.
        if rtol not in resolved:
            resolved[rtol] = resolve(block, damper, pulse, {**settings, "rtol": rtol})
        return resolved[rtol]

    return _checked(resolved_at, case["rtol"], backend, record)


def _checked(resolved_at, rtol: float, backend: str, record: bool) -> Response:
    """The response of :func:`rocking.sim.accuracy.tolerance_check` from ``rtol``: the run at ``rtol`` where it
    is not sensitive, else the tightest run as given; with the check's results. ``resolved_at(rtol)`` gives
    ``(model, p, case)`` at a rung's ``rtol``."""
    responses = []

    def run_at(rung: float, factor: float) -> dict:
        model, p, case = resolved_at(rung)
        # The amplitude of the horizontal motion alone: any motion's, sampled or a pulse.
        responses.append(_run(model, p, {**case, "a_g": case["a_g"] * factor}, backend, record))
        return {name: getattr(responses[-1], name) for name in READ}

    done = tolerance_check(run_at, rtol)
    response = responses[int(done.reported)]
    for f in CHECKED:
        setattr(response, f.name, done.results[f.name].item())
    return response


_RTOL = OPTIONS["rtol"]
