"""What a simulation is asked (:class:`Problem`) and what it answers (:class:`Response`).

Both back ends (``rocking.sim.numpy_backend`` and ``rocking.sim.c_backend``) take the
same :class:`Problem` and follow the same phase machine, documented in
``docs/simulation.md``; they differ only in the language they run in.

Units SI. The state is ``y = (q, dq)`` in the model's manifest order, with the
rocking angle ``theta`` first.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..model.floor import Floor, check_model_floor, check_pair, floor_of
from ..model.loading import Model, ModelError, load_model
from ..model.motion import FAMILIES, SHAPES, describe, interpolate, margin_extrema, real_array, sample_piece
from ..model.params import (
    DAMPER_PARAMETERS,
    HC_STOP_PARAMETERS,
    RANGES,
    STOP_PARAMETERS,
    Block,
    Damper,
    ParameterError,
    Stops,
    check_block,
    check_in_range,
    check_real,
    hunt_crossley_restitution,
    shown,
)
from ..model.vertical import flight_time
from . import boundary
from .boundary import (
    CASE,
    CONTACT,
    DOUBLE,
    DOUBLES,
    MOTION,
    PIVOT_A,
    PIVOT_A_PRIME,
    RESULT,
    SERIES,
    STATUS,
    STATUSES,
    SUMMARY,
    python_type,
)
from .fields import ProblemFields, ResponseFields
from .history import RunInputs, events, to_dataframe, to_dataset

__all__ = [
    "CONTACT",
    "PIVOT_A",
    "PIVOT_A_PRIME",
    "RESULT_FIELDS",
    "STATUS",
    "Problem",
    "Response",
    "RunInputs",
    "SimulationError",
    "default_settings",
    "make_problem",
]


class SimulationError(RuntimeError):
    """A back end failed mid-run: its step size underflowed (a non-finite right-hand side, ...)."""


def _result_dtype(f):
    if python_type(f) is bool:
        return bool
    return np.float64 if f.kind == DOUBLE else np.int64


#: Scalar results of a run, as arrays of a batch: field -> dtype (``status`` indexes :data:`STATUS`).
RESULT_FIELDS = {f.name: _result_dtype(f) for f in RESULT}

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
    y = _flat_reals(y0)
    if y is None or y.shape != (2 * n,) or not np.all(np.isfinite(y)):
        raise ParameterError(f"y0 must hold {2 * n} finite numbers {model.state} (got {shown(y0)})")
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


def _flat_reals(value) -> np.ndarray | None:
    """``value`` as a contiguous 1-D float array, or ``None`` if any element is no real number."""
    try:
        return np.ascontiguousarray(real_array("value", value)).reshape(-1)
    except ParameterError:
        return None


def _state_vector(name: str, value, model: Model) -> np.ndarray:
    ny = 2 * model.nq
    a = _flat_reals(value)
    if a is None or a.shape != (ny,) or not np.all(np.isfinite(a) & (a >= 0)):
        raise ParameterError(f"{name} must hold {ny} finite numbers >= 0 {model.state} (got {shown(value)})")
    return a


def _series(name: str, value, count: int) -> np.ndarray | None:
    """A :data:`~rocking.sim.boundary.SERIES` setting: ``None`` (with a count of 0) or at least ``count`` finite
    values."""
    if value is None:
        if count:
            raise ParameterError(f"{name}: {count} values are counted but none given")
        return None
    a = _flat_reals(value)
    if a is None or a.size < count or not np.all(np.isfinite(a[:count])):
        got = shown(value) if a is None else a.size
        raise ParameterError(f"{name} must hold at least {count} finite values (got {got})")
    return a


def check_motion(family: str, n_samples, pulse_dt, n_extrema) -> None:
    """What a motion's family needs besides its fields' ranges (broadcasts over a batch's columns).

    A sampled motion needs at least 2 samples and ``pulse_dt > 0``; a listed family (Ricker,
    Mavroeidis-Papageorgiou) its extrema.
    """
    if family == "sampled" and np.any((np.asarray(n_samples) < 2) | ~(np.asarray(pulse_dt) > 0)):
        raise ParameterError("a sampled motion needs n_samples >= 2 samples and pulse_dt > 0")
    if family in ("ricker", "ricker_anti", "mp") and np.any(np.asarray(n_extrema) < 1):
        raise ParameterError(f"a {family} motion needs its extrema (n_extrema >= 1)")


#: The number settings of a Problem with their Python types, and the series with the field that counts them.
_SCALAR_SETTINGS = tuple((f.name, python_type(f)) for f in CASE if f.kind not in (DOUBLES, SERIES))
_SERIES_SETTINGS = tuple((f.name, f.count) for f in CASE if f.count is not None)  # a SERIES has a count (Field)


def ground_shape(problem: Problem, t):
    """``f(t)`` of the problem's motion (docs/model.md section 12), vectorised, on its whole definition."""
    family = FAMILIES[problem.motion]
    if family == "sampled":
        dt, samples = problem.pulse_dt, problem.samples
        assert samples is not None  # a sampled Problem holds its samples (check_motion, _series)
        return interpolate(samples, dt, sample_piece(t, dt, problem.n_samples), t)
    return SHAPES[family](t, problem.omega_g, problem.psi, problem.t_c, problem.shape, np)


def vertical_of(settings: Mapping, t) -> np.ndarray:
    """``ddy_g(t)`` of a run's settings (docs/model.md section 14), vectorised: ``a_v f_v(t)`` on ``[0, t_p]``."""
    t = np.asarray(t, dtype=float)
    family = FAMILIES[settings["motion"]]
    if settings["a_v"] == 0.0:
        f = 0.0 * t
    elif family == "sampled":
        dt, samples = settings["pulse_dt"], settings["v_samples"]
        f = interpolate(samples, dt, sample_piece(t, dt, len(samples)), t)
    else:
        lead = settings["psi_v"] / settings["omega_g"]
        f = SHAPES[family](t + lead, settings["omega_g"], settings["psi"], settings["t_c"], settings["shape"], np)
    return np.where((t >= 0) & (t <= settings["t_p"]), settings["a_v"] * f, 0.0)


@dataclass(frozen=True, kw_only=True)
class Problem(ProblemFields):
    """A fully resolved simulation: numbers only, nothing left to default but the initial state.

    Built by :func:`make_problem`; its fields, typed and documented in
    :class:`~rocking.sim.fields.ProblemFields`, are the model, its parameters and the table
    :data:`rocking.sim.boundary.CASE` (checked on construction: a value out of range raises
    :class:`~rocking.ParameterError` naming it and its range).
    """

    def __post_init__(self) -> None:
        """Check every setting against its range in :data:`~rocking.sim.boundary.CASE` and store it typed."""
        for name, python in _SCALAR_SETTINGS:
            value = getattr(self, name)
            boundary.check(name, value)
            object.__setattr__(self, name, python(value))
        for name, count in _SERIES_SETTINGS:
            object.__setattr__(self, name, _series(name, getattr(self, name), getattr(self, count)))
        check_motion(FAMILIES[self.motion], self.n_samples, self.pulse_dt, self.n_extrema)
        check_pair(self.mu_s, self.mu_k)
        check_model_floor(self.mu_s, self.model)
        p = np.ascontiguousarray(self.p, dtype=float).reshape(-1)
        if p.shape != (len(self.model.parameters),):
            raise ParameterError(f"p must hold {len(self.model.parameters)} numbers {self.model.parameters}")
        object.__setattr__(self, "p", p)
        object.__setattr__(self, "atol", _state_vector("atol", self.atol, self.model))
        object.__setattr__(self, "y0", _initial_state(self.model, self.y0, self.phase0))

    def ground_acceleration(self, t):
        """``ddx_g(t)``, vectorised: ``a_g f(t)`` on ``[0, t_p]``, 0 outside."""
        t = np.asarray(t, dtype=float)
        a = np.where((t >= 0) & (t <= self.t_p), self.a_g * ground_shape(self, t), 0.0)
        return a if a.ndim else float(a)

    def settings(self) -> dict:
        """The settings by name (every field of :data:`~rocking.sim.boundary.CASE`)."""
        return {f.name: getattr(self, f.name) for f in CASE}


# --------------------------------------------------------------------------- #
# Response: what a run answers                                                 #
# --------------------------------------------------------------------------- #


#: Each result's name and the function from its C number to its Python value, in the order of RESULT.
_RESULT_VALUES: tuple[tuple[str, Callable[[Any], Any]], ...] = tuple(
    (f.name, (lambda code: STATUS[int(code)]) if f.name == "status" else python_type(f)) for f in RESULT
)


@dataclass
class Response(ResponseFields):
    """The response of the block to one pulse.

    Its fields, typed and documented in :class:`~rocking.sim.fields.ResponseFields`, are the table
    :data:`rocking.sim.boundary.RESULT`, then the tolerance check's
    (:data:`rocking.sim.boundary.SENSITIVE`; ``False`` when no check ran), then:

    Attributes
    ----------
    history : dict of ndarray, optional
        With ``record=True``: ``t``, every state component by name (``theta``,
        ``x``, ``dtheta``, ``dx``, ...), ``phase`` (:data:`CONTACT`,
        :data:`PIVOT_A`, :data:`PIVOT_A_PRIME`) and ``ag``, the events as extra
        rows; :meth:`to_dataset` gives it on a uniform grid, :meth:`events` the events.
    inputs : RunInputs, optional
        What the run was given and the back end that ran it (``None`` for a batch's rows and
        for a back end called directly): :meth:`to_dataset` derives the loads from them, and
        :func:`rocking.sim.run.rerecord` runs it again recorded at another spacing.
    """

    history: dict[str, np.ndarray] | None = field(default=None, repr=False)
    inputs: RunInputs | None = field(default=None, repr=False, compare=False)

    @classmethod
    def from_record(cls, record, history: dict | None = None) -> Response:
        """A response from a C ``rocking_result`` (or a row of a NumPy record array) and a history."""
        get = record.__getitem__ if isinstance(record, np.void) else record.__getattribute__
        return cls(**{name: value(get(name)) for name, value in _RESULT_VALUES}, history=history)

    def summary(self) -> dict:
        """The scalar results as a plain dict (JSON-ready; NaN times as ``None``, a zero as 0.0, never -0.0)."""
        out = {}
        for f in SUMMARY:
            value = python_type(f)(getattr(self, f.name))
            if isinstance(value, float):  # -0.0 + 0.0 is +0.0: a force that never acted reads 0, not -0
                value = None if np.isnan(value) else value + 0.0
            out[f.name] = value
        return out

    def _repr_html_(self) -> str:
        """The scalar results as an HTML table for Jupyter: each value rounded, with its unit and meaning in the
        words of the docs (the status by its name and reason, the damper's coordinate by its model's name)."""
        from html import escape

        rows = "".join(
            f"<tr><td>{f.name}</td><td>{escape(_shown(value))}</td><td>{escape(f.unit)}</td>"
            f"<td>{escape(self._meaning(f))}</td></tr>"
            for f, value in zip(SUMMARY, self.summary().values(), strict=True)
        )
        recorded = "a history is recorded: to_dataset()" if self.history is not None else "no history recorded"
        return (
            f"<div><strong>rocking Response</strong> ({recorded})<table><tr><th>field</th><th>value</th>"
            f"<th>unit</th><th>meaning</th></tr>{rows}</table></div>"
        )

    def plot(self, ax=None):
        """Draw the recorded rotation ``theta / alpha`` over time, as pandas and xarray draw their data.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw; default a new ``matplotlib.pyplot`` figure (shown in a notebook).

        Returns
        -------
        matplotlib.figure.Figure
            The figure of ``ax``.

        Raises
        ------
        ParameterError
            A response without a history (run it with ``record=True``) or without its inputs (a batch's row).
        """
        if self.history is None or self.inputs is None:
            raise ParameterError("plot needs a recorded response: rocking.simulate(..., record=True)")
        from ..plot.response import rotation_axes

        if ax is None:
            import matplotlib.pyplot as plt

            ax = plt.figure(figsize=(7, 3), layout="constrained").add_subplot()
        named = dict(zip(self.inputs.model.parameters, self.inputs.p))
        rotation_axes(ax, self, math.atan2(named["B"], named["H"]))
        return ax.figure

    def _meaning(self, field) -> str:
        """A field's meaning for a reader: the status's reason, ``q[1]`` by the name its model gives it (``x``, the
        name ``x_max`` carries, for the block alone and a run whose model is not known)."""
        names: list[str] = self.inputs.model.manifest["coordinates"] if self.inputs is not None else []
        doc = f"why the run ended: {STATUSES[STATUS.index(self.status)].doc}" if field.name == "status" else field.doc
        return doc.replace("q[1]", names[1] if len(names) > 1 else "x")

    def to_dataset(self, dt: float | None = None):
        """The recorded history on the uniform grid ``t = k dt`` as an ``xarray.Dataset``, with the loads of the model.

        Parameters
        ----------
        dt : float, optional
            Spacing [s]: the run's ``record_dt`` (the default). The values are exact samples of the
            integrator's dense output, which only a run recorded every ``dt`` holds: for another
            spacing, simulate with ``record=True, record_dt=dt``, or call
            :func:`rocking.sim.run.rerecord`. The events are not rows: see :meth:`events`.

        Returns
        -------
        xarray.Dataset
            Over ``t`` [s]: the coordinates and velocities by the model's names (``theta``, ``x``,
            ``dtheta``, ``dx``; ``phi`` for the pendulum), their accelerations (``ddtheta``, ...),
            ``phase``, ``a_g``, ``a_top``, ``a_cm``, ``V_b``, ``N_b``, ``M_b``, the force of each
            damper coordinate's elements (``F_x``), the bumpers' ``F_b`` (models with end stops),
            ``E_kinetic``, ``E_potential``, ``E_total``; each with ``units`` and ``long_name``
            (docs/model.md section 13).

        Raises
        ------
        ParameterError
            A bad ``dt``; a response not recorded every ``dt`` (the message says how to record it);
            a response without its inputs (a batch's row).
        """
        return to_dataset(self, dt)

    def to_dataframe(self, dt: float | None = None):
        """:meth:`to_dataset` as a ``pandas.DataFrame`` indexed by ``t`` [s]; ``attrs`` hold ``units`` and
        ``long_name``."""
        return to_dataframe(self, dt)

    def events(self):
        """The events of the recorded run as a ``pandas.DataFrame``: ``t`` [s], ``kind``, ``phase_before``,
        ``phase_after``.

        Kinds: ``uplift``, ``impact`` (``phase_after`` 0: the block came to rest), ``contact`` (a
        lift-off that fell back without an impact), ``bumper_contact``, ``bumper_release``,
        ``pulse_end``, ``overturn``; phases as in :data:`~rocking.sim.boundary.PHASES`. A response
        without a history (``record=False``) raises :class:`~rocking.ParameterError`, which says how
        to record it.
        """
        return events(self)


#: Default rest criteria, relative to the block (see :func:`make_problem`).
DTHETA_REST = 1e-3
#: Least dtheta_rest accepted, over alpha p: below, the impacts of a block coming to rest follow each
#: other closer than double precision tells apart, and a run may never end (the fuzzer found C cycling
#: to max_events at dtheta_rest = 1e-233 where NumPy came to rest).
DTHETA_REST_FLOOR = 1e-9
ENERGY_REST = 1e-8
#: Steps per shortest period in full contact while the pulse acts.
CONTACT_STEPS_PER_PERIOD = 64


def default_settings(block: Block, T_g, T_m, rtol: float, nq: int) -> dict:
    """Tolerances, contact step and rest thresholds of a run; broadcasts over ``T_g``, ``T_m``.

    ``T_m`` is ``inf`` without a damper. Returned keys: ``atol`` (shape
    ``(..., 2 nq)``; a list of floats for one run), ``contact_max_step``, ``dtheta_rest``, ``energy_rest``.
    """
    alpha, p = block.alpha, block.p
    scale = [alpha] * nq + [alpha * p] * nq
    atol: list[float] | np.ndarray
    if type(T_g) is float and type(T_m) is float:  # one run: the same numbers without NumPy's cost per call
        shortest, atol = min(T_g, 2 * math.pi / p, T_m), [rtol * x for x in scale]
    else:
        shortest = np.minimum(np.minimum(T_g, 2 * np.pi / p), T_m)
        shape = np.shape(shortest)
        atol = rtol * (np.broadcast_to(scale, shape + (len(scale),)) if shape else np.array(scale))
    return {
        "atol": atol,
        "contact_max_step": shortest / CONTACT_STEPS_PER_PERIOD,
        "dtheta_rest": DTHETA_REST * alpha * p,
        "energy_rest": ENERGY_REST * block.M * block.g * block.B / 2,
    }


def check_integer(name: str, value: object) -> int:
    """``value`` as an int within ``RANGES[name]``; bool and float are refused (``max_events=True`` is no count)."""
    if not isinstance(value, numbers.Integral) or isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} must be an integer (got {shown(value)})")
    return int(check_in_range(name, int(value)))


def check_flag(name: str, value: object) -> bool:
    """``value`` if it is a bool (``"no"`` is a true string, 1 an int: both refused)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} must be True or False (got {shown(value)})")
    return bool(value)


def _optional_real(name: str, value: object) -> object:
    """``None`` or a finite real number (bool and str refused); the range is the boundary table's."""
    return None if value is None else check_real(name, value)


def resolve_model(model: object, default: str) -> Model:
    """The :class:`Model` of ``model`` (a name, a folder or a Model; ``None``: ``default``).

    Raises
    ------
    ParameterError
        If ``model`` is of another type.
    ModelError
        If no such model exists or it cannot be loaded.
    """
    if model is None:
        model = default
    if not isinstance(model, (str, os.PathLike, Model)):
        raise ParameterError(f"model must be a model name, a folder or a rocking.Model (got {type(model).__name__})")
    return load_model(model)


def _damper_mapping(damper: object) -> dict | None:
    """The attached bodies' parameters of ``damper`` by name (``None``: the bare block)."""
    if damper is None:
        return None
    if isinstance(damper, Damper):
        return damper.as_params()
    if not isinstance(damper, Mapping):
        as_params = getattr(damper, "as_params", None)
        if callable(as_params):
            damper = as_params()
    if not isinstance(damper, Mapping):
        raise ParameterError(
            f"damper must be a rocking.Damper, a mapping of the model's own parameters by name, or None "
            f"(got {type(damper).__name__})"
        )
    return dict(damper)


def own_parameters(model: Model, values: Mapping, block: Block, damper: Damper | None = None) -> dict[str, float]:
    """``values`` checked as the parameters of ``model``'s attached bodies on ``block``.

    The keys must be exactly the model's own parameters (``Model.parameters`` minus
    ``Model.block_parameters``, the rule of :class:`rocking.Variant`): a damper never sets
    the block. The values are real numbers (bool and str refused) within the model's
    ranges; those of the ``omd`` and ``omd_stops`` models (a :class:`Damper`'s, with its
    :class:`Stops`) must also pass :meth:`Damper.check_on` (that of ``damper``, the object
    ``values`` came from, if given: its stops may allow a guide beyond the block's edges, and
    its values, checked when it was built, are not checked again);
    a mass of another model (unit kg) has the mass ratio range of ``gamma``, a length
    (unit m) the range of ``h`` in absolute value.

    Raises
    ------
    ParameterError
        Naming the parameters set by the block, unknown, missing or out of range.
    """
    own = model.own_parameters
    if values.keys() != set(own):
        _refuse_names(model, values, own)
    if damper is not None:  # its values were checked when it was built: only against the block now
        damper.check_on(block)
        return {k: values[k] for k in own}
    checked = {k: check_real(k, values[k]) for k in own}
    if set(own) == set(DAMPER_PARAMETERS):
        Damper(**checked, stops=None).check_on(block)
        return checked
    if set(own) == set(DAMPER_PARAMETERS + STOP_PARAMETERS):
        stops = Stops(checked["L"], checked["k_b"], checked["c_b"])
        Damper(**{k: checked[k] for k in DAMPER_PARAMETERS}, stops=stops).check_on(block)
        return checked
    if set(own) == set(DAMPER_PARAMETERS + HC_STOP_PARAMETERS):
        e_b = hunt_crossley_restitution(checked["chi_b"])  # the pads' restitution, which Stops checks
        stops = Stops(checked["L"], checked["k_b"], law="hunt-crossley", n=checked["n_b"], e_b=e_b)
        Damper(**{k: checked[k] for k in DAMPER_PARAMETERS}, stops=stops).check_on(block)
        return checked
    units = {p["name"]: p.get("unit", "") for p in model.manifest["parameters"]}
    for k, v in checked.items():
        _check_by_unit(k, v, units.get(k, ""), block)
    try:
        model.param_vector({**block.as_params(), **checked})
    except ModelError as exc:
        raise ParameterError(str(exc)) from None
    return checked


def _refuse_names(model: Model, values: Mapping, own: tuple[str, ...]) -> None:
    """Raise the error of :func:`own_parameters` for keys of ``values`` other than ``own``."""
    by_block = sorted(str(k) for k in values if k in model.block_parameters)
    if by_block:
        raise ParameterError(f"damper: {', '.join(by_block)} set by the block, not by the damper")
    unknown = sorted(str(k) for k in values if k not in own)
    if unknown:
        raise ParameterError(
            f"model {model.name!r} has no parameter(s) {', '.join(unknown)} of its own; give "
            f"{', '.join(own) or 'none'} (the block sets {', '.join(model.block_parameters)})"
        )
    missing = [k for k in own if k not in values]
    raise ParameterError(f"model {model.name!r} needs parameter(s) {', '.join(missing)}")


#: Magnitude of a parameter of another unit than kg or m: far from overflow in any product of two.
LARGEST = 1e30


def _check_by_unit(name: str, value: float, unit: str, block: Block) -> None:
    """The generic range of a variant's parameter, by its unit (the models say no more of their physics)."""
    if unit == "kg":
        # No zero mass here: a massless body on a spring is an infinitely fast mode (the bare block is model "block").
        if value == 0.0 or value / block.M not in RANGES["gamma"]:
            valid = RANGES["gamma"]
            raise ParameterError(
                f"{name} must be in [{valid.low:g} M, {valid.high:g} M] = "
                f"[{valid.low * block.M:g}, {valid.high * block.M:g}] kg (got {value!r}): mass ratio to the block"
            )
    elif unit == "m":
        if abs(value) > RANGES["h"].high:
            raise ParameterError(f"{name} must be in [-1000, 1000] m (got {value!r}): a body within 1 km of the block")
    elif abs(value) > LARGEST:
        raise ParameterError(f"{name} must be in [-1e30, 1e30] {unit} (got {value!r}): beyond, products overflow")


def default_record_dt(motion, block: Block) -> float:
    """The default spacing of a history, s, for the :func:`~rocking.model.motion.describe` of a motion: a
    hundredth of the shorter of the pulse's period and the block's ``2 pi / p``, and at most a record's own
    spacing, so that a plot shows every peak of the motion (a pulse's within 0.2 %: ``1 - cos(pi / 100)``;
    a record's exactly, at its samples)."""
    step = min(motion.T_g, 2 * math.pi / block.p) / 100
    return min(step, motion.dt) if motion.dt > 0 else step


def _record_dt(record_dt: object, t_max: float, default: float) -> float:
    """The spacing of a history: at most ``RANGES["record_samples"]`` samples over ``t_max``."""
    most = RANGES["record_samples"].high
    if record_dt is None:
        return max(default, t_max / most)  # the default's rule, capped like a given spacing
    record_dt = check_real("record_dt", record_dt)
    if record_dt > 0.0 and t_max / record_dt > most:
        raise ParameterError(
            f"record_dt must be <= 0 (events only) or >= t_max / {most:g} = {t_max / most:g} s "
            f"(got {record_dt!r}): {RANGES['record_samples'].why} at most {most:g}"
        )
    return record_dt


def _dtheta_rest(dtheta_rest: float, block: Block) -> float:
    """``dtheta_rest`` if it is at least :data:`DTHETA_REST_FLOOR` ``alpha p``."""
    floor = DTHETA_REST_FLOOR * block.alpha * block.p
    if not dtheta_rest >= floor:
        raise ParameterError(
            f"dtheta_rest must be >= 1e-9 alpha p = {floor:g} rad/s (got {dtheta_rest!r}): below, the impacts of a "
            "block coming to rest follow each other closer than double precision tells apart"
        )
    return dtheta_rest


def _run_length(t_max: object, t_after: object, t_p: float) -> float:
    """``t_max``, or ``t_p + t_after``: bounded, since a run's work grows with its length."""
    if t_max is None:
        return t_p + check_in_range("t_after", t_after)
    return check_in_range("t_max", t_max)


def motion_settings(motion) -> dict:
    """The fields of :data:`~rocking.sim.boundary.CASE` that describe a ground motion, from its
    :class:`~rocking.model.motion.Description` (the arrays are shared, not copied)."""
    extrema, samples, v_samples = motion.extrema, motion.samples, motion.v_samples
    return {
        "motion": MOTION[motion.family],
        "a_g": motion.a_g,
        "omega_g": motion.omega_g,
        "psi": motion.phase,
        "t_c": motion.t_c,
        "shape": motion.shape,
        "t_p": motion.t_p,
        "n_extrema": 0 if extrema is None else len(extrema),
        "extrema": extrema,
        "pulse_dt": motion.dt,
        "n_samples": 0 if samples is None else len(samples),
        "samples": samples,
        "a_v": motion.a_v,
        "psi_v": motion.phase_v,
        "n_v_samples": 0 if v_samples is None else len(v_samples),
        "v_samples": v_samples,
    }


def flight_settings(settings: Mapping, block: Block, flies: bool = False) -> dict:
    """``t_flight`` of :data:`~rocking.sim.boundary.CASE` for the motion of ``settings``: where ``g + ddy_g``
    first reaches 0 (docs/model.md section 14), ``inf`` without a vertical component, and for a model that
    follows flight (``flies``: its manifest's ``flight``; docs/model.md section 16), whose runs go on there."""
    if settings["a_v"] == 0.0 or flies:
        return {"t_flight": math.inf}
    t = flight_time(
        lambda t: vertical_of(settings, t), block.g, settings["t_p"], settings["omega_g"], settings["pulse_dt"]
    )
    return {"t_flight": t}


def margin_settings(family: str, gamma: float, nu: float, vertical, block: Block) -> dict:
    """``extrema`` and ``n_extrema`` of :data:`~rocking.sim.boundary.CASE` for a pulse whose vertical component
    leads (``vertical``: a :class:`~rocking.model.vertical.Vertical` or ``None``): the extrema of its shape and of
    both uplift margins, where full contact's segments end (docs/model.md section 14); empty otherwise, the
    shape's own extrema kept. ``tan(alpha)`` of each pivot is the bare block's, ``(B -+ e) / H``."""
    if vertical is None:
        return {}
    tans = ((block.B - block.e) / block.H, (block.B + block.e) / block.H)
    extrema = margin_extrema(family, gamma, nu, vertical.ratio, vertical.phase, tans)
    return {} if extrema is None else {"extrema": extrema, "n_extrema": len(extrema)}


def make_problem(
    block: Block,
    damper=None,
    pulse=None,
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
    early_verdict: bool = True,
    y0=None,
    phase0: int = CONTACT,
    floor: Floor | None = None,
) -> Problem:
    """Resolve the physical description of a run into a :class:`Problem`.

    Parameters
    ----------
    block : Block
        The rocking block.
    damper : Damper or mapping or None
        Anything with ``as_params()`` (or a mapping) giving the attached
        bodies' parameters by name; ``None`` for the bare block.
    pulse : OneSinePulse, OneCosinePulse, RickerWavelet, MavroeidisPapageorgiou or SampledMotion
        The ground motion (docs/model.md section 12): exactly one of these types, a subclass is
        refused (the back ends evaluate the registered families, not a Python ``acceleration``).
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
        Rest criterion on ``|dtheta|`` after an impact [rad/s], at least
        ``1e-9 alpha p``; default ``1e-3 alpha p``: the next half-cycle would
        rise less than about 0.1 % of ``alpha``.
    energy_rest : float, optional
        Rest criterion on the energy above rest in full contact after the
        pulse [J]; default ``1e-8 M g B / 2``.
    max_events : int
        Bound on uplifts plus impacts.
    record_dt : float, optional
        History spacing [s]; default ``min(T_g, 2 pi / p) / 100``, at most a record's ``dt``; ``<= 0``:
        events only.
    early_rest : bool
        End a run that can no longer uplift at the next extremum of the
        damper's stroke (docs/simulation.md, rule 4); ``False``: follow it to
        ``energy_rest``.
    early_verdict : bool
        End a run once, after the pulse, its energy can no longer carry
        ``|theta|`` or the damper's ``|q[1]|`` past their maxima: verdict and
        maxima are then final, status ``"bounded"`` (docs/simulation.md,
        rule 4); ``False``: follow it to rest.
    y0 : array_like, optional
        State at ``t = 0`` in manifest order; default at rest.
    phase0 : int
        Phase at ``t = 0``: 0 (full contact), +1 or -1 (rocking about ``A``
        or ``A'``); the rule is docs/simulation.md, "Initial state".
    floor : Floor, optional
        The floor's Coulomb friction (docs/model.md section 15); default ``None``, ``Floor()``: the
        paper's floor, on which the base never slides (``mu_s = mu_k = inf``).
    """
    options = {
        "model": model,
        "rtol": rtol,
        "t_max": t_max,
        "t_after": t_after,
        "dtheta_rest": dtheta_rest,
        "energy_rest": energy_rest,
        "max_events": max_events,
        "record_dt": record_dt,
        "early_rest": early_rest,
        "early_verdict": early_verdict,
        "y0": y0,
        "phase0": phase0,
        "floor": floor,
    }
    model, p, settings = resolve(block, damper, pulse, options)
    return Problem(model=model, p=np.asarray(p, dtype=float), **settings)


def _check_phase0(value: object) -> int:
    if not isinstance(value, numbers.Integral) or isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"phase0 must be -1, 0 or +1 (got {shown(value)})")
    return int(value)


def _check_rtol(value: object) -> float:
    return float(boundary.check("rtol", check_real("rtol", value)))


#: The options of :func:`make_problem` with their defaults, and the check of each when a caller gives it
#: (in the order a call checks them; ``model``, ``t_max``, ``t_after``, ``y0`` need the run, see :func:`resolve`).
#: Each checks the type here; the values lie in the entry of ``RANGES`` of the option's name, or in the range
#: or code set of its field of :data:`~rocking.sim.boundary.CASE` (tests/test_checks.py): no bound restated.
OPTIONS = {
    name: parameter.default
    for name, parameter in inspect.signature(make_problem).parameters.items()
    if parameter.kind is inspect.Parameter.KEYWORD_ONLY
}
_OPTION_CHECKS: dict[str, Callable[[Any], object]] = {
    "rtol": _check_rtol,
    "dtheta_rest": functools.partial(_optional_real, "dtheta_rest"),
    "energy_rest": functools.partial(_optional_real, "energy_rest"),
    "max_events": functools.partial(check_integer, "max_events"),
    "early_rest": functools.partial(check_flag, "early_rest"),
    "early_verdict": functools.partial(check_flag, "early_verdict"),
    "phase0": _check_phase0,
    "floor": floor_of,
}
#: The options that are fields of :data:`~rocking.sim.boundary.CASE`: when given, checked by the table as a
#: :class:`Problem` checks them (in the table's order); the fields a run derives from checked objects are not.
_CASE_OPTIONS = tuple(f.name for f in CASE if f.name in OPTIONS and f.valid is not None)


def _bodies(block: Block, damper, model: object) -> tuple[Model, tuple | np.ndarray, float]:
    """The model, parameter vector and damper period (``inf``: none) of ``damper`` on ``block``, checked.

    The last block and :class:`Damper` (or ``None``) of a call without a ``model`` are remembered, by
    identity: a loop over pulses does not check the same frozen objects against each other again. Their
    models are built in, whatever the working directory (:func:`load_model`).
    """
    global _LAST_BODIES
    objects = model is None and (damper is None or type(damper) is Damper)
    if objects:
        last_block, last_damper, bodies = _LAST_BODIES
        if last_block is block and last_damper is damper:
            return bodies
    own = _damper_mapping(damper)
    is_damper = isinstance(damper, Damper)
    model = resolve_model(model, damper.model if is_damper else "omd" if own else "block")
    values = block.as_params()
    if own is not None:
        values.update(own_parameters(model, own, block, damper if is_damper else None))
    elif model.nq > 1:
        # Zeros for the bodies' parameters would be massless bodies on springs (a degenerate mode), except
        # on omd where m = 0 is refused below with its own message.
        if set(model.own_parameters) != set(DAMPER_PARAMETERS):
            raise ParameterError(
                f"damper=None is the bare block (model 'block'); model {model.name!r} needs its own "
                f"parameters as a damper mapping ({', '.join(k for k in model.parameters if k not in values)})"
            )
        values.update({name: 0.0 for name in model.parameters if name not in values})
    # The objects' own model takes their values, checked when they were built, without the spec's checks again.
    p = tuple([values[k] for k in model.parameters]) if objects else model.param_vector(values)
    if model.nq > 1 and values.get("m", 1.0) == 0.0:
        raise ParameterError("a damper with m = 0 kg has no dynamics: pass damper=None for the bare block")
    # Only a damper that knows its period shortens the contact step (a mapping never did: results unchanged).
    T_m = damper.T_m if is_damper and damper.m > 0 and damper.k_m > 0 else math.inf
    if objects:
        _LAST_BODIES = (block, damper, (model, p, T_m))
    return model, p, T_m


_LAST_BODIES: tuple = (None, None, None)


def resolve(block: Block, damper, pulse, given: Mapping) -> tuple[Model, tuple | np.ndarray, dict]:
    """The model, parameter vector and settings (every field of :data:`~rocking.sim.boundary.CASE`) of a run.

    What :func:`make_problem` does before it builds the :class:`Problem`, and what
    :func:`rocking.simulate` hands the C back end directly. ``block``, ``damper`` and ``pulse``
    were checked when they were built: here only the damper against its block (and a mapping's
    values against its model); of the options (:data:`OPTIONS`), only those in ``given`` are
    checked, the defaults being valid. The arguments are those of :func:`make_problem`, with the
    options in ``given`` (only names of :data:`OPTIONS`).

    Returns
    -------
    tuple
        ``(model, p, settings)``: the :class:`Model`; the parameters in its order (a tuple of
        floats for a :class:`Block` and :class:`Damper` on their own model, else an ndarray);
        every field of ``CASE`` by name (``atol`` a list of floats, the motion's arrays as
        :func:`motion_settings` gives them).

    Raises
    ------
    ParameterError
        The messages of :func:`make_problem`.
    """
    check_block(block)
    motion = describe(pulse)
    options = dict(OPTIONS)
    for name, check in _OPTION_CHECKS.items() if given else ():
        if name in given:
            options[name] = check(given[name])
    model, p, T_m = _bodies(block, damper, given.get("model"))
    if "t_max" in given or "t_after" in given:
        t_max = _run_length(given.get("t_max"), given.get("t_after", OPTIONS["t_after"]), motion.t_p)
    else:
        t_max = motion.t_p + OPTIONS["t_after"]
    defaults = default_settings(block, motion.T_g, T_m, options["rtol"], model.nq)
    dtheta_rest, energy_rest = options["dtheta_rest"], options["energy_rest"]
    if motion.a_v != 0.0 and not model.manifest.get("vertical", False):
        raise ParameterError(
            f"model {model.name!r} takes no vertical ground motion: its energies hold g beside the weights "
            "(docs/model.md section 14); give the motion no vertical component"
        )
    settings = motion_settings(motion)
    settings.update(flight_settings(settings, block, bool(model.manifest.get("flight", False))))
    if motion.family != "sampled":
        settings.update(margin_settings(motion.family, motion.shape, motion.phase, pulse.vertical, block))
    settings.update(
        t_max=t_max,
        rtol=options["rtol"],
        atol=defaults["atol"],
        contact_max_step=defaults["contact_max_step"],
        dtheta_rest=defaults["dtheta_rest"] if dtheta_rest is None else _dtheta_rest(dtheta_rest, block),
        energy_rest=defaults["energy_rest"] if energy_rest is None else energy_rest,
        max_events=options["max_events"],
        max_steps=boundary.MAX_STEPS_DEFAULT,
        record_dt=_record_dt(given.get("record_dt"), t_max, default_record_dt(motion, block)),
        y0=None,
        phase0=options["phase0"],
        early_rest=options["early_rest"],
        early_verdict=options["early_verdict"],
        **floor_of(options["floor"]).settings(),
    )
    for name in _CASE_OPTIONS if given else ():
        if name in given:
            boundary.check(name, settings[name])
    if "y0" in given or "phase0" in given:
        settings["y0"] = _initial_state(model, given.get("y0"), settings["phase0"])
    return model, p, settings


def _shown(value) -> str:
    """A result for a reader: four significant digits, yes/no, a dash for "did not happen" (NaN)."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if value is None:
        return "-"
    return f"{value:.4g}" if isinstance(value, float) else str(value)
