"""What a simulation is asked (:class:`Problem`) and what it answers (:class:`Response`).

Both back ends (``rocking.sim.numpy_backend`` and ``rocking.sim.c_backend``) take the
same :class:`Problem` and follow the same phase machine, documented in
``docs/simulation.md``; they differ only in the language they run in.

Units SI. The state is ``y = (q, dq)`` in the model's manifest order, with the
rocking angle ``theta`` first.
"""

from __future__ import annotations

from dataclasses import MISSING, field, make_dataclass

import numpy as np

from ..model.loading import Model, load_model
from ..model.params import Block, ParameterError
from ..model.pulse import OneSinePulse
from . import boundary
from .boundary import CASE, CONTACT, DOUBLE, DOUBLES, PIVOT_A, PIVOT_A_PRIME, RESULT, STATUS

__all__ = [
    "CONTACT",
    "PIVOT_A",
    "PIVOT_A_PRIME",
    "RESULT_FIELDS",
    "STATUS",
    "Problem",
    "Response",
    "SimulationError",
    "default_settings",
    "make_problem",
]

class SimulationError(RuntimeError):
    """A back end failed mid-run: its step size underflowed (a non-finite right-hand side, ...)."""


#: Python type of each kind of field.
_PYTHON = {DOUBLE: float, boundary.INT64: int, boundary.INT32: int, DOUBLES: np.ndarray}

#: Fields whose Python value is not their C number: a name of :data:`STATUS`, truth values.
_NAMED_PYTHON = {"status": str, "overturned": bool, "early_rest": bool}


def _python(f) -> type:
    """The Python type of a field of :data:`~rocking.sim.boundary.CASE` or :data:`~rocking.sim.boundary.RESULT`."""
    return _NAMED_PYTHON.get(f.name, _PYTHON[f.kind])


def _result_dtype(f):
    if _python(f) is bool:
        return bool
    return np.float64 if f.kind == DOUBLE else np.int64


#: Scalar results of a run, as arrays of a batch: field -> dtype (``status`` indexes :data:`STATUS`).
RESULT_FIELDS = {f.name: _result_dtype(f) for f in RESULT}


def _attributes(fields, python) -> str:
    lines = []
    for f in fields:
        unit = f" [{f.unit}]" if f.unit else ""
        lines += [f"    {f.name} : {python(f).__name__}", f"        {f.doc[0].upper()}{f.doc[1:]}{unit}."]
    return "\n".join(lines)


# --------------------------------------------------------------------------- #
# Problem: what a run is given                                                 #
# --------------------------------------------------------------------------- #


def _initial_state(model: Model, y0, phase0: int):
    """``y0`` as a state vector (or ``None``) if it and ``phase0`` obey docs/simulation.md, "Initial state"."""
    if y0 is None:
        if phase0 != CONTACT:
            raise ParameterError(f"phase0 = {phase0:+d} (rocking) needs an initial state y0 with s theta >= 0")
        return None
    n = model.nq
    try:
        y = np.array(y0, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ParameterError(f"y0 must hold {2 * n} finite numbers {model.state} (got {y0!r})") from None
    if y.shape != (2 * n,) or not np.all(np.isfinite(y)):
        raise ParameterError(f"y0 must hold {2 * n} finite numbers {model.state} (got {y0!r})")
    if phase0 == CONTACT and (y[0] != 0.0 or y[n] != 0.0):
        raise ParameterError(
            f"y0: full contact (phase0 = 0) needs theta = dtheta = 0 "
            f"(got theta = {float(y[0])!r}, dtheta = {float(y[n])!r})"
        )
    if phase0 != CONTACT and phase0 * y[0] < 0.0:
        raise ParameterError(
            f"y0: rocking about phase0 = {phase0:+d} needs phase0 * theta >= 0 (got theta = {float(y[0])!r})"
        )
    if phase0 != CONTACT and y[0] == 0.0 and phase0 * y[n] < 0.0:
        raise ParameterError(
            f"y0: rocking about phase0 = {phase0:+d} from theta = 0 needs phase0 * dtheta >= 0 "
            f"(got dtheta = {float(y[n])!r})"
        )
    return y


def _state_vector(name: str, value, model: Model) -> np.ndarray:
    ny = 2 * model.nq
    a = np.ascontiguousarray(value, dtype=float).reshape(-1)
    if a.shape != (ny,) or not np.all(np.isfinite(a) & (a >= 0)):
        raise ParameterError(f"{name} must hold {ny} finite numbers >= 0 {model.state} (got {value!r})")
    return a


def _problem_post_init(self) -> None:
    """Check every setting against its range in :data:`~rocking.sim.boundary.CASE` and store it typed."""
    for f in CASE:
        value = getattr(self, f.name)
        if f.kind != DOUBLES:
            boundary.check(f.name, value)
            object.__setattr__(self, f.name, _python(f)(value))
    p = np.ascontiguousarray(self.p, dtype=float).reshape(-1)
    if p.shape != (len(self.model.parameters),):
        raise ParameterError(f"p must hold {len(self.model.parameters)} numbers {self.model.parameters}")
    object.__setattr__(self, "p", p)
    object.__setattr__(self, "atol", _state_vector("atol", self.atol, self.model))
    object.__setattr__(self, "y0", _initial_state(self.model, self.y0, self.phase0))


def _ground_acceleration(self, t):
    """``ddx_g(t)``, vectorised."""
    t = np.asarray(t, dtype=float)
    a = np.where((t >= 0) & (t <= self.t_p), self.a_g * np.sin(self.omega_g * t + self.psi), 0.0)
    return a if a.ndim else float(a)


def _problem_settings(self) -> dict:
    """The settings by name (every field of :data:`~rocking.sim.boundary.CASE`)."""
    return {f.name: getattr(self, f.name) for f in CASE}


Problem = make_dataclass(
    "Problem",
    [("model", Model), ("p", np.ndarray)]
    + [(f.name, _python(f), field(default=MISSING if f.required else f.default)) for f in CASE],
    frozen=True,
    namespace={
        "__post_init__": _problem_post_init,
        "ground_acceleration": _ground_acceleration,
        "settings": _problem_settings,
        "__module__": __name__,
    },
)
Problem.__doc__ = f"""A fully resolved simulation: numbers only, nothing left to default but the initial state.

Built by :func:`make_problem`; its fields are the table
:data:`rocking.sim.boundary.CASE` (checked on construction: a value out of
range raises :class:`~rocking.ParameterError` naming it and its range).

Attributes
----------
    model : Model
        The generated model.
    p : ndarray
        Parameters in the model's order.
{_attributes(CASE, _python)}
"""


# --------------------------------------------------------------------------- #
# Response: what a run answers                                                 #
# --------------------------------------------------------------------------- #


def _summary(self) -> dict:
    """The scalar results as a plain dict (JSON-ready; NaN times as ``None``)."""
    out = {}
    for f in RESULT:
        value = _python(f)(getattr(self, f.name))
        out[f.name] = None if isinstance(value, float) and np.isnan(value) else value
    return out


def _from_record(cls, record, history: dict | None = None):
    """A response from a C ``rocking_result`` (or a row of a NumPy record array) and a history."""
    values = {f.name: getattr(record, f.name) if hasattr(record, f.name) else record[f.name] for f in RESULT}
    values["status"] = STATUS[int(values["status"])]
    return cls(**{f.name: _python(f)(values[f.name]) for f in RESULT}, history=history)


Response = make_dataclass(
    "Response",
    [(f.name, _python(f)) for f in RESULT] + [("history", dict, field(default=None, repr=False))],
    namespace={"summary": _summary, "from_record": classmethod(_from_record), "__module__": __name__},
)
Response.__doc__ = f"""The response of the block to one pulse.

Its fields are the table :data:`rocking.sim.boundary.RESULT`.

Attributes
----------
{_attributes(RESULT, _python)}
    history : dict of ndarray, optional
        With ``record=True``: ``t``, every state component by name (``theta``,
        ``x``, ``dtheta``, ``dx``, ...), ``phase`` (:data:`CONTACT`,
        :data:`PIVOT_A`, :data:`PIVOT_A_PRIME`) and ``ag``.
"""


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
    early_rest: bool = True,
    y0=None,
    phase0: int = CONTACT,
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
        Relative tolerance, in [1e-12, 0.01].

    Every setting is checked against its range in
    :data:`rocking.sim.boundary.CASE`; a :class:`ParameterError` names it.
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
        History spacing [s]; default ``min(T_g, 2 pi / p) / 100``; ``<= 0``:
        events only.
    early_rest : bool
        End a run that can no longer uplift at the next extremum of the
        damper's stroke (docs/simulation.md, rule 4); ``False``: follow it to
        ``energy_rest``.
    y0 : array_like, optional
        State at ``t = 0`` in manifest order; default at rest.
    phase0 : int
        Phase at ``t = 0``: 0 (full contact), +1 or -1 (rocking about ``A``
        or ``A'``); the rule is docs/simulation.md, "Initial state".
    """
    if not isinstance(block, Block):
        raise ParameterError(f"block must be a rocking.Block (got {type(block).__name__})")
    if not isinstance(pulse, OneSinePulse):
        raise ParameterError(f"pulse must be a rocking.OneSinePulse (got {type(pulse).__name__})")
    rtol = float(boundary.check("rtol", rtol))
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
        dtheta_rest=defaults["dtheta_rest"] if dtheta_rest is None else dtheta_rest,
        energy_rest=defaults["energy_rest"] if energy_rest is None else energy_rest,
        max_events=max_events,
        record_dt=min(pulse.T_g, 2 * np.pi / block.p) / 100 if record_dt is None else record_dt,
        early_rest=early_rest,
        y0=y0,
        phase0=phase0,
    )
