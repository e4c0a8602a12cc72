"""Many responses at once: arrays of ground motions and dampers for one block.

:func:`pulse_cases` (analytic pulses over ``Omega`` and ``beta``) and :func:`sampled_cases`
(one sampled motion at many scales: an incremental dynamic analysis) build the per-case
arrays with the same rules as :func:`rocking.sim.problem.make_problem`, without a Python
object per case, as :class:`~rocking.sim.batch.Cases`, and :func:`run_cases` runs them on a
back end of :data:`rocking.sim.backends.BACKENDS`: C's batch entry point, or, as the reference,
case by case on NumPy/SciPy.
"""

from __future__ import annotations

import numpy as np

from ..model.floor import Floor, floor_of
from ..model.loading import Model, ModelError
from ..model.motion import FAMILIES, SampledMotion, listed_extrema, timing
from ..model.params import (
    BUMPER_DEPTH,
    RANGES,
    STOP_PARAMETERS,
    Block,
    ParameterError,
    check_block,
    check_in_range,
    check_interval,
    check_real,
    edge_stops,
    tuned_damper,
)
from ..model.pulse import check_signs
from ..model.vertical import Vertical, check_vertical
from . import boundary
from .backends import BACKENDS, for_floor
from .batch import Cases, Packed
from .boundary import MOTION
from .problem import (
    check_integer,
    default_settings,
    flight_settings,
    margin_settings,
    own_parameters,
    resolve_model,
)

__all__ = ["Cases", "Packed", "pulse_cases", "run_cases", "sampled_cases"]


def _array(name: str, value, key: str | None = None) -> np.ndarray:
    """``value`` as a float array, every element within ``RANGES[key or name]`` (bool and str refused)."""
    a = np.asarray(value)
    if a.dtype.kind not in "iuf":
        raise ParameterError(f"{name} must be a number or an array of numbers (got {value!r})")
    a = a.astype(float)
    valid = RANGES[key or name]
    bad = ~valid.holds(a)
    if np.any(bad):
        raise ParameterError(f"{name} must be {valid.text()} (got {a[bad].ravel()[0]!r}): {valid.why}")
    return a


def _derived(name: str, a: np.ndarray, given: str, key: str | None = None) -> None:
    """Refuse a derived array (``omega_g = Omega p``, ...) out of its range (``RANGES[key or name]``), saying what
    gave it."""
    valid = RANGES[key or name]
    bad = ~valid.holds(a)
    if np.any(bad):
        raise ParameterError(
            f"{given} gives {name} = {float(a[bad].ravel()[0])!r}, but {name} must be {valid.text()}: {valid.why}"
        )


def _fixed_params(model: Model, block: Block, params) -> dict[str, float]:
    """``params`` checked once: the model's own parameters only, all of them, within the model's ranges."""
    if not isinstance(params, dict):
        raise ParameterError(f"params must be a dict of parameter values by name (got {type(params).__name__})")
    return own_parameters(model, params, block)


#: The analytic families of :func:`pulse_cases` (``motion``).
ANALYTIC = tuple(f for f in FAMILIES if f != "sampled")


def pulse_cases(
    block: Block,
    Omega,
    beta,
    *,
    gamma=None,
    omega_ratio=1.0,
    zeta=0.05,
    h=0.05,
    psi=0.0,
    rtol: float = 1e-8,
    t_after: float = 15.0,
    max_events: int = 10_000,
    model: str | Model | None = None,
    params: dict | None = None,
    sign=1,
    stops: bool = False,
    stroke: float | None = None,
    motion: str = "sine",
    gamma_mp: float | None = None,
    nu: float = 0.0,
    vertical: object = None,
    floor: Floor | None = None,
) -> Cases:
    """Cases for pulses ``(Omega, beta)`` and dampers ``(gamma, omega_ratio, zeta, h)``.

    ``motion`` is the pulse's family (docs/model.md section 12): ``"sine"`` (default; its phase
    ``psi``), ``"cosine"``, ``"ricker"``, ``"ricker_anti"`` or ``"mp"`` (with ``gamma_mp`` and
    ``nu``, one shape for the batch: its extrema are located once); ``Omega = omega_g / p`` and
    ``beta = a_g / (g tan alpha)`` as for :meth:`rocking.OneSinePulse.from_nondim`.
    ``sign`` (+1 or -1, or an array of them) is the direction of each pulse (:class:`rocking.OneSinePulse`).
    ``stops``: the dampers' guides end in the stops of :meth:`rocking.Stops.at_edges`
    (model ``"omd_stops"``); with ``gamma`` only. ``stroke``: their half-stroke ``L``, m, in
    ``(0, B/2)`` (default ``B/2`` minus the pads' depth, :data:`rocking.model.params.BUMPER_DEPTH`).
    ``vertical``: every pulse's vertical component, a :class:`rocking.Vertical` or None, checked (docs/model.md
    section 14):
    ``ddy_g = ratio a_g f(t + phase / omega_g)``, > 0 up, unsigned by ``sign``; a case where ``g + ddy_g``
    reaches 0 ends there with the status ``flight``. Default None: none (``ratio = 0`` is the same).
    ``floor``: the floor of every case, a :class:`rocking.Floor` (docs/model.md section 15); default None: the
    paper's, on which the base never slides.

    All array arguments broadcast together (docs/model.md section 9 for their
    meaning); the result is flattened in C order. ``gamma = 0`` everywhere
    (or not given) means the bare block (model ``"block"``); otherwise every
    ``gamma`` must be > 0 and the model is ``"omd"`` unless given.

    ``params`` instead gives fixed values of the model's own parameters by
    name (those not set by the block), for any generated ``model`` (default
    ``"omd"``); it excludes ``gamma`` (``omega_ratio``, ``zeta`` and ``h``
    are then unused). The values are checked once against the model's ranges.
    """
    if motion not in ANALYTIC:
        raise ParameterError(f"motion must be one of {', '.join(ANALYTIC)} (got {motion!r}); sampled: sampled_cases")
    check_block(block)
    sign = check_signs(sign)
    Omega, beta, psi = _array("Omega", Omega), _array("beta", beta), _array("psi", psi)
    if motion != "sine" and np.any(psi != 0.0):
        raise ParameterError(f"psi is the phase of the one-sine pulse: not of motion {motion!r}")
    if motion == "mp":
        if gamma_mp is None:
            raise ParameterError("motion 'mp' needs gamma_mp, its oscillations (> 1)")
        gamma_mp = check_in_range("gamma_mp", gamma_mp)
        nu = check_in_range("nu", nu, "psi", label="[0, 2 pi)")
    elif gamma_mp is not None or nu != 0.0:
        raise ParameterError(f"gamma_mp and nu shape the Mavroeidis-Papageorgiou pulse: not motion {motion!r}")
    damper, shape = _damper_arrays(gamma, omega_ratio, zeta, h, Omega, beta, psi, sign)
    Omega, beta, psi, sign = (np.broadcast_to(a, shape).ravel() for a in (Omega, beta, psi, sign))
    _derived("omega_g", Omega * block.p, "Omega p")
    _derived("a_g", block.a_g(beta), "beta g tan(alpha)")
    omega_g = Omega * block.p
    phase = psi if motion == "sine" else np.full(omega_g.shape, nu if motion == "mp" else 0.0)
    t_c, t_p = timing(motion, omega_g, phase, gamma_mp or 0.0)
    extrema = listed_extrema(motion, gamma_mp or 0.0, nu)
    columns: dict = {
        "motion": MOTION[motion],
        "a_g": sign * block.a_g(beta),
        "omega_g": omega_g,
        "psi": phase,
        "t_c": t_c,
        "shape": gamma_mp or 0.0,
        "t_p": t_p,
        "n_extrema": 0 if extrema is None else len(extrema),
        "extrema": extrema,
    }
    checked = check_vertical(vertical)
    if checked is not None and checked.ratio > 0.0:
        columns.update(_vertical_columns(block, columns, checked, block.a_g(beta)))
        columns.update(margin_settings(motion, gamma_mp or 0.0, nu, checked, block))
    columns.update(floor_of(floor).settings())
    return _cases(block, columns, 2 * np.pi / omega_g, damper, rtol, t_after, max_events, model, params, stops, stroke)


def _vertical_columns(block: Block, columns: dict, vertical: Vertical, a_g: np.ndarray) -> dict:
    """``a_v``, ``psi_v`` and ``t_flight`` of the pulses of ``columns`` (flat arrays) with ``vertical``.

    ``a_v = ratio a_g`` is unsigned by the direction (docs/model.md section 14). Every shape has ``|f| <= 1``, so
    ``g + ddy_g >= g - a_v > 0`` where ``a_v < g``: only the other cases are scanned for their flight time.
    """
    a_v = vertical.ratio * a_g
    t_flight = np.full(a_v.shape, np.inf)
    for i in np.flatnonzero(a_v >= block.g):
        case = {k: v if np.ndim(v) == 0 or k == "extrema" else v[i] for k, v in columns.items()}
        case.update(a_v=a_v[i], psi_v=vertical.phase, pulse_dt=0.0)
        t_flight[i] = flight_settings(case, block)["t_flight"]
    return {"a_v": a_v, "psi_v": vertical.phase, "t_flight": t_flight}


def sampled_cases(
    block: Block,
    motion: SampledMotion,
    scale=1.0,
    *,
    sign=1,
    gamma=None,
    omega_ratio=1.0,
    zeta=0.05,
    h=0.05,
    rtol: float = 1e-8,
    t_after: float = 15.0,
    max_events: int = 10_000,
    model: str | Model | None = None,
    params: dict | None = None,
    stops: bool = False,
    stroke: float | None = None,
    floor: Floor | None = None,
) -> Cases:
    """Cases for one sampled motion at the factors ``scale`` (as ``motion.scaled(scale)``) and dampers.

    Every case shares ``motion``'s samples (one buffer, not a copy per case). ``sign`` (+1 or -1,
    or an array of them) keeps (+1) or mirrors (-1) the motion's direction; a vertical component
    (``SampledMotion(a_v=...)``) is scaled with the horizontal one and unsigned (docs/model.md
    section 14), and a case where ``g + ddy_g`` reaches 0 ends there with the status ``flight``. ``scale`` (>= 0),
    ``sign`` and the damper arrays broadcast together, flattened in C order; the damper, ``model``,
    ``params``, ``stops``, ``stroke`` and ``floor`` as for :func:`pulse_cases`.
    """
    check_block(block)
    if type(motion) is not SampledMotion:
        raise ParameterError(f"motion must be a rocking.SampledMotion (got {type(motion).__name__})")
    sign = check_signs(sign)
    scale = np.asarray(scale)
    if scale.dtype.kind not in "iuf" or not np.all(np.isfinite(scale) & (scale >= 0)):
        raise ParameterError(f"scale must be finite and >= 0, or an array of such (got {scale!r})")
    damper, shape = _damper_arrays(gamma, omega_ratio, zeta, h, scale.astype(float), sign)
    scale, sign = (np.broadcast_to(a, shape).ravel() for a in (scale.astype(float), sign))
    _derived("a_g", scale * motion.pga, f"scale max|a| (max|a| = {motion.pga / motion.scale:g} m/s^2)")
    columns = {
        "motion": MOTION["sampled"],
        "a_g": sign * motion.sign * (motion.scale * scale),
        "omega_g": 0.0,
        "psi": 0.0,
        "t_p": motion.t_p,
        "pulse_dt": motion.dt,
        "n_samples": motion.n,
        "samples": motion.a,
    }
    if motion.a_v is not None:
        columns.update(_vertical_samples(block, motion, motion.a_v, motion.scale * scale))
    columns.update(floor_of(floor).settings())
    return _cases(block, columns, np.inf, damper, rtol, t_after, max_events, model, params, stops, stroke)


def _vertical_samples(block: Block, motion: SampledMotion, samples: np.ndarray, a_v: np.ndarray) -> dict:
    """``a_v``, the vertical ``samples`` of ``motion`` and ``t_flight`` of its cases at the vertical scales ``a_v``
    (the motion's scale times the case's, unsigned: docs/model.md section 14).

    ``g + a_v v(t) <= 0`` first between the two samples where it changes sign (linear there), at the least scale
    ``a_v >= g / max(-v)`` only: the flight time of each distinct scale is found once.
    """
    t_flight = np.full(a_v.shape, np.inf)
    lowest = -float(np.min(samples))
    if lowest > 0.0:
        settings = {"motion": MOTION["sampled"], "a_v": 0.0, "pulse_dt": motion.dt, "v_samples": samples}
        settings.update(t_p=motion.t_p, omega_g=0.0, psi=0.0, t_c=0.0, shape=0.0)
        flying = a_v * lowest >= block.g
        for scale in np.unique(a_v[flying]):
            t_flight[a_v == scale] = flight_settings({**settings, "a_v": scale}, block)["t_flight"]
    return {"a_v": a_v, "n_v_samples": samples.size, "v_samples": samples, "t_flight": t_flight}


def _damper_arrays(gamma, omega_ratio, zeta, h, *motion_arrays):
    """The damper's arrays, checked and broadcast with the motion's; ``(dict of flat arrays, the shape)``."""
    gamma = _array("gamma", 0.0 if gamma is None else gamma)
    named = {
        "gamma": gamma,
        "omega_ratio": _array("omega_ratio", omega_ratio),
        "zeta": _array("zeta", zeta),
        "h": _array("h", h),
    }
    try:
        shape = np.broadcast_shapes(*(a.shape for a in (*named.values(), *motion_arrays)))
    except ValueError:
        raise ParameterError(
            "the motion's arrays (Omega, beta, psi, scale, sign) and gamma, omega_ratio, zeta, h must broadcast "
            "together"
        ) from None
    return {k: np.broadcast_to(a, shape).ravel() for k, a in named.items()}, shape


def _cases(block, columns, T_g, damper, rtol, t_after, max_events, model, params, stops, stroke) -> Cases:
    """The batch of the motion's ``columns`` on ``block`` with ``damper``'s arrays (the rules of make_problem)."""
    gamma, omega_ratio, zeta, h = damper["gamma"], damper["omega_ratio"], damper["zeta"], damper["h"]
    if params is not None and np.any(gamma > 0):
        raise ParameterError(
            "give either gamma (the omd damper relative to its block) or params (a model's own parameters), not both"
        )
    if not isinstance(stops, (bool, np.bool_)):
        raise ParameterError(f"stops must be True or False (got {stops!r})")
    rtol = float(boundary.check("rtol", check_real("rtol", rtol)))
    t_after = check_in_range("t_after", t_after)
    max_events = check_integer("max_events", max_events)
    bare = params is None and not np.any(gamma > 0)
    if not bare and params is None and np.any(gamma == 0):
        raise ParameterError("gamma must be > 0 in every case of a batch with a damper (use a separate bare batch)")
    if stroke is not None and not stops:
        raise ParameterError("stroke is the half-stroke of the stops: give it with stops=True")
    depth = BUMPER_DEPTH
    if stroke is not None:
        depth = block.B / 2 - check_interval("stroke", stroke, 0.0, block.B / 2, "m", label="(0, B/2)")
    if stops and (bare or params is not None):
        raise ParameterError(
            "stops=True puts the stops of Stops.at_edges on the omd damper of gamma > 0: "
            "give the damper by gamma (a model's params set their own stops)"
        )
    try:
        model = resolve_model(model, "block" if bare else "omd_stops" if stops else "omd")
    except ModelError as exc:
        raise ParameterError(str(exc)) from None
    if np.any(columns.get("a_v", 0.0) != 0.0) and not model.manifest.get("vertical", False):
        raise ParameterError(
            f"model {model.name!r} takes no vertical ground motion: its energies hold g beside the weights "
            "(docs/model.md section 14); give the pulses no vertical component"
        )
    if model.manifest.get("flight", False) and "t_flight" in columns:
        columns = {**columns, "t_flight": np.full(np.shape(columns["t_flight"]), np.inf)}  # flight followed
    shape = gamma.shape
    values = {k: np.full(shape, v) for k, v in block.as_params().items()}
    T_m = np.full(shape, np.inf)
    if params is not None:
        fixed = _fixed_params(model, block, params)
        values.update({k: np.full(shape, v) for k, v in fixed.items()})
    elif not bare:
        omega_m = omega_ratio * block.p
        m, k_m, c = tuned_damper(block.M, gamma, omega_m, zeta)
        values.update(m=m, k_m=k_m, c=c, h=h)
        T_m = 2 * np.pi / omega_m
        if stops:
            values.update(zip(STOP_PARAMETERS, edge_stops(block, m, depth)))
            _derived("L", values["L"], "B/2 minus the pads' depth of Stops.at_edges")
            _derived("omega_b", np.sqrt(values["k_b"] / m) / block.p, "the bumpers' frequency over p", "omega_b_ratio")
    missing = [name for name in model.parameters if name not in values]
    if missing:
        raise ParameterError(
            f"model {model.name!r} needs parameter(s) {', '.join(missing)} that pulse_cases cannot set"
        )
    settings = default_settings(block, T_g, T_m, rtol, model.nq)
    t_p = np.broadcast_to(columns["t_p"], shape)
    return Cases(
        model,
        np.column_stack([values[k] for k in model.parameters]),
        {
            **{k: v for k, v in columns.items() if k not in ("extrema", "samples")},
            "extrema": columns.get("extrema"),
            "samples": columns.get("samples"),
            "t_max": t_p + t_after,
            "rtol": rtol,
            "atol": settings["atol"],
            "contact_max_step": settings["contact_max_step"],
            "dtheta_rest": settings["dtheta_rest"],
            "energy_rest": settings["energy_rest"],
            "max_events": max_events,
            "record_dt": settings["contact_max_step"],
        },
    )


def run_cases(cases: Cases, backend: str = "c", threads: int = 1, lanes: bool = True) -> dict[str, np.ndarray]:
    """Simulate every case on ``backend`` (a name of :data:`rocking.sim.backends.BACKENDS`); a dict of arrays keyed
    by :data:`rocking.sim.problem.RESULT_FIELDS`. ``lanes``: the C batch's lanes (rocking.sim.c_backend.simulate_cases),
    False for its scalar path.

    ``status`` holds indices into :data:`rocking.sim.boundary.STATUS`.
    """
    if not isinstance(backend, str) or backend not in BACKENDS:
        raise ParameterError(f"backend must be {' or '.join(map(repr, BACKENDS))} (got {backend!r})")
    return BACKENDS[for_floor(backend, cases.settings["mu_s"], cases.model)].simulate_cases(cases, threads, lanes)
