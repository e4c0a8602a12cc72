"""What a simulation is asked (:class:`Problem`) and what it answers (:class:`Response`).

Both back ends (``rocking.sim.numpy_backend`` and ``rocking.sim.c_backend``) take the
same :class:`Problem` and follow the same phase machine, documented in
``docs/simulation.md``; they differ only in the language they run in.

Units SI. The state is ``y = (q, dq)`` in the model's manifest order, with the
rocking angle ``theta`` first.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..model.loading import Model, load_model
from ..model.params import Block, ParameterError
from ..model.pulse import OneSinePulse

#: Phase codes in recorded histories: full contact, rocking about A, about A'.
CONTACT, PIVOT_A, PIVOT_A_PRIME = 0, 1, -1

#: Why a run ended.
STATUS = ("overturned", "rest", "t_max", "max_events")

#: Scalar results of a run, as arrays of a batch: field -> dtype (``status`` indexes :data:`STATUS`).
RESULT_FIELDS = {
    "overturned": bool,
    "t_overturn": np.float64,
    "t_critical": np.float64,
    "theta_max": np.float64,
    "x_max": np.float64,
    "impacts": np.int64,
    "uplifts": np.int64,
    "t_end": np.float64,
    "status": np.int64,
}


@dataclass(frozen=True)
class Problem:
    """A fully resolved simulation: numbers only, nothing left to default.

    Attributes
    ----------
    model : Model
        The generated model.
    p : ndarray
        Parameters in the model's order.
    a_g, omega_g, psi, t_p : float
        One-sine pulse ``a_g sin(omega_g t + psi)`` on ``[0, t_p]``, 0 after.
    t_max : float
        End of the run if nothing else ends it first.
    rtol : float
        Relative tolerance of the integrator.
    atol : ndarray
        Absolute tolerance per state component.
    contact_max_step : float
        Largest step in full contact while the pulse acts, so that no uplift
        can be stepped over (the bare block's contact phase has no dynamics).
    dtheta_rest : float
        An impact whose outgoing ``|dtheta|`` is below this ends rocking: the
        block is back in full contact (the rest criterion).
    energy_rest : float
        In full contact after the pulse, the run ends once the energy above
        the rest state is below this (the damper's motion has decayed).
    max_events : int
        Upper bound on uplifts plus impacts; the run ends with status
        ``"max_events"`` when reached.
    record_dt : float
        Spacing of the recorded history (events are recorded as well).
    early_rest : bool
        In full contact after the pulse, end the run once the energy above
        rest is below the least energy at which the attached bodies can lift
        the block (the generated ``uplift_energy``), at the next extremum of
        the damper's stroke: verdict, ``theta_max`` and ``x_max`` are then
        final (docs/simulation.md, rule 4). ``False``: only ``energy_rest``
        ends a run in full contact, as before.
    """

    model: Model
    p: np.ndarray
    a_g: float
    omega_g: float
    psi: float
    t_p: float
    t_max: float
    rtol: float
    atol: np.ndarray
    contact_max_step: float
    dtheta_rest: float
    energy_rest: float
    max_events: int
    record_dt: float
    early_rest: bool = True

    def ground_acceleration(self, t):
        """``ddx_g(t)``, vectorised."""
        t = np.asarray(t, dtype=float)
        a = np.where((t >= 0) & (t <= self.t_p), self.a_g * np.sin(self.omega_g * t + self.psi), 0.0)
        return a if a.ndim else float(a)


@dataclass
class Response:
    """The response of the block to one pulse.

    Attributes
    ----------
    overturned : bool
        ``|theta|`` reached ``pi/2``.
    t_overturn : float
        When it did (``nan`` if not).
    t_critical : float
        First time ``|theta|`` passed the static critical angle of the active
        pivot (``nan`` if never).
    theta_max : float
        Largest ``|theta|`` [rad].
    x_max : float
        Largest ``|q[1]|`` (the damper's stroke), 0 without a damper.
    impacts, uplifts : int
        Number of impacts and of uplifts from full contact.
    t_end : float
        When the run ended.
    status : str
        One of :data:`STATUS`.
    history : dict of ndarray, optional
        With ``record=True``: ``t``, every state component by name (``theta``,
        ``x``, ``dtheta``, ``dx``, ...), ``phase`` (:data:`CONTACT`,
        :data:`PIVOT_A`, :data:`PIVOT_A_PRIME`) and ``ag``.
    """

    overturned: bool
    t_overturn: float
    t_critical: float
    theta_max: float
    x_max: float
    impacts: int
    uplifts: int
    t_end: float
    status: str
    history: dict | None = field(default=None, repr=False)

    def summary(self) -> dict:
        """The scalar results as a plain dict (JSON-ready)."""
        return {
            "overturned": bool(self.overturned),
            "t_overturn": None if np.isnan(self.t_overturn) else float(self.t_overturn),
            "t_critical": None if np.isnan(self.t_critical) else float(self.t_critical),
            "theta_max": float(self.theta_max),
            "x_max": float(self.x_max),
            "impacts": int(self.impacts),
            "uplifts": int(self.uplifts),
            "t_end": float(self.t_end),
            "status": self.status,
        }


#: Default rest criteria, relative to the block (see :func:`make_problem`).
DTHETA_REST = 1e-3
ENERGY_REST = 1e-8
#: Steps per shortest period in full contact while the pulse acts.
CONTACT_STEPS_PER_PERIOD = 64


def default_settings(block: Block, T_g, T_m, rtol: float, nq: int) -> dict:
    """Tolerances, contact step and rest thresholds of a run; broadcasts over ``T_g``, ``T_m``.

    ``T_m`` is ``inf`` without a damper. Returned keys: ``atol`` (shape
    ``(..., 2 nq)``), ``contact_max_step``, ``dtheta_rest``, ``energy_rest``.
    """
    T_g, T_m = np.asarray(T_g, float), np.asarray(T_m, float)
    shortest = np.minimum(np.minimum(T_g, 2 * np.pi / block.p), T_m)
    scale = np.array([block.alpha] * nq + [block.alpha * block.p] * nq)
    return {
        "atol": rtol * np.broadcast_to(scale, shortest.shape + scale.shape),
        "contact_max_step": shortest / CONTACT_STEPS_PER_PERIOD,
        "dtheta_rest": DTHETA_REST * block.alpha * block.p,
        "energy_rest": ENERGY_REST * block.M * block.g * block.B / 2,
    }


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not (np.isfinite(value) and value > 0):
        raise ParameterError(f"{name} must be a finite number > 0 (got {value})")
    return value


def make_problem(
    block: Block,
    damper=None,
    pulse: OneSinePulse | None = None,
    *,
    model: str | Model | None = None,
    rtol: float = 1e-8,
    t_max: float | None = None,
    t_after: float = 15.0,
    dtheta_rest: float | None = None,
    energy_rest: float | None = None,
    max_events: int = 10_000,
    record_dt: float | None = None,
) -> Problem:
    """Resolve the physical description of a run into a :class:`Problem`.

    Parameters
    ----------
    block : Block
        The rocking block.
    damper : Damper or mapping or None
        Anything with ``as_params()`` (or a mapping) giving the attached
        bodies' parameters by name; ``None`` for the bare block.
    pulse : OneSinePulse
        The ground motion.
    model : str or Model, optional
        Model name or folder; default ``"omd"`` with a damper, ``"block"`` without.
    rtol : float
        Relative tolerance, in (0, 0.01].
    t_max : float, optional
        End time [s]; default ``t_p + t_after``.
    t_after : float
        Time followed after the pulse when ``t_max`` is not given [s].
    dtheta_rest : float, optional
        Rest criterion on ``|dtheta|`` after an impact [rad/s]; default
        ``1e-3 alpha p``: the next half-cycle would rise less than about
        0.1 % of ``alpha``.
    energy_rest : float, optional
        Rest criterion on the energy above rest in full contact after the
        pulse [J]; default ``1e-8 M g B / 2``.
    max_events : int
        Bound on uplifts plus impacts.
    record_dt : float, optional
        History spacing [s]; default ``min(T_g, 2 pi / p) / 100``.
    """
    if not isinstance(block, Block):
        raise ParameterError(f"block must be a rocking.Block (got {type(block).__name__})")
    if not isinstance(pulse, OneSinePulse):
        raise ParameterError(f"pulse must be a rocking.OneSinePulse (got {type(pulse).__name__})")
    rtol = _positive("rtol", rtol)
    if rtol > 1e-2:
        raise ParameterError(f"rtol must be in (0, 0.01] (got {rtol})")
    if not (isinstance(max_events, (int, np.integer)) and max_events > 0):
        raise ParameterError(f"max_events must be an integer > 0 (got {max_events!r})")
    values = dict(block.as_params())
    if damper is not None:
        values.update(damper.as_params() if hasattr(damper, "as_params") else dict(damper))
    model = load_model(model if model is not None else ("omd" if damper is not None else "block"))
    if damper is None and model.nq > 1:
        values.update({name: 0.0 for name in model.parameters if name not in values})
    p = model.param_vector(values)
    if model.nq > 1 and values.get("m", 1.0) == 0.0:
        raise ParameterError("a damper with m = 0 kg has no dynamics: pass damper=None for the bare block")

    t_p = pulse.t_p
    t_max = t_p + _positive("t_after", t_after) if t_max is None else _positive("t_max", t_max)
    T_m = damper.T_m if damper is not None and hasattr(damper, "T_m") and values.get("m", 0.0) > 0 else np.inf
    defaults = default_settings(block, pulse.T_g, T_m, rtol, model.nq)
    return Problem(
        model=model,
        p=p,
        a_g=pulse.a_g,
        omega_g=pulse.omega_g,
        psi=pulse.psi,
        t_p=t_p,
        t_max=t_max,
        rtol=rtol,
        atol=defaults["atol"],
        contact_max_step=float(defaults["contact_max_step"]),
        dtheta_rest=defaults["dtheta_rest"] if dtheta_rest is None else _positive("dtheta_rest", dtheta_rest),
        energy_rest=defaults["energy_rest"] if energy_rest is None else _positive("energy_rest", energy_rest),
        max_events=int(max_events),
        record_dt=min(pulse.T_g, 2 * np.pi / block.p) / 100 if record_dt is None else _positive("record_dt", record_dt),
    )
