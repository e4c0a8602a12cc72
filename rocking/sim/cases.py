"""Many responses at once: arrays of one-sine pulses and dampers for one block.

:func:`pulse_cases` builds the per-case arrays with the same rules as
:func:`rocking.sim.problem.make_problem`, without a Python object per case, and
:func:`run_cases` runs them on the C batch entry point (or, as the reference,
case by case on NumPy/SciPy).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.loading import Model, ModelError
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
)
from ..model.pulse import check_signs
from . import boundary
from .boundary import CASE, DOUBLES
from .problem import RESULT_FIELDS, STATUS, Problem, check_integer, default_settings, own_parameters, resolve_model


@dataclass(frozen=True)
class Cases:
    """Resolved inputs of ``n`` runs of one model, from rest: one row per run.

    Attributes
    ----------
    model : Model
        The generated model.
    p : ndarray, shape (n, np)
        Parameters in the model's order.
    settings : dict of ndarray
        Every field of :data:`rocking.sim.boundary.CASE` but ``y0`` by name:
        shape ``(n,)``, or ``(n, ny)`` for ``atol``. A field with a default
        may be left out. Checked on construction against the table's ranges.
    """

    model: Model
    p: np.ndarray
    settings: dict

    def __post_init__(self) -> None:
        p = np.asarray(self.p, dtype=float)
        width = len(self.model.parameters)
        if p.ndim != 2 or p.shape[1] != width:
            raise ParameterError(
                f"cases: p must have shape (n, {width}), one column per parameter "
                f"{tuple(self.model.parameters)} (got shape {p.shape})"
            )
        n = len(p)
        columns = {}
        for f in CASE:
            if f.name == "y0":
                continue
            value = self.settings.get(f.name, None if f.required else f.default)
            if value is None:
                raise ParameterError(f"cases: the setting {f.name} is missing")
            shape = (n, len(self.model.state)) if f.kind == DOUBLES else (n,)
            try:
                column = np.ascontiguousarray(np.broadcast_to(np.asarray(value, dtype=float), shape))
            except ValueError:
                raise ParameterError(
                    f"cases: {f.name} must broadcast to shape {shape} (got {np.shape(value)})"
                ) from None
            columns[f.name] = boundary.check(f.name, column)
        unknown = sorted(set(self.settings) - set(columns))
        if unknown:
            raise ParameterError(f"cases: unknown setting(s) {', '.join(unknown)}")
        if np.any(~np.isfinite(columns["atol"]) | (columns["atol"] < 0)):
            raise ParameterError("atol must be finite and >= 0")
        object.__setattr__(self, "p", np.ascontiguousarray(p))
        object.__setattr__(self, "settings", columns)

    def __len__(self) -> int:
        return len(self.p)

    def problem(self, i: int) -> Problem:
        """Case ``i`` as a :class:`Problem` (for the NumPy back end)."""
        return Problem(model=self.model, p=self.p[i], **{k: v[i] for k, v in self.settings.items()})

    @classmethod
    def of(cls, problems) -> Cases:
        """The problems of one model, from rest, as one batch.

        Raises
        ------
        ParameterError
            If the list is empty, the problems differ in model, or one starts
            elsewhere than at rest.
        """
        problems = list(problems)
        if not problems:
            raise ParameterError("no problems given")
        folders = {pr.model.folder for pr in problems}
        if len(folders) > 1:
            raise ParameterError(f"a batch needs one model for all problems (got {sorted(str(f) for f in folders)})")
        if any(pr.y0 is not None for pr in problems):
            raise ParameterError("a batch runs from rest: y0 must be None in every problem")
        settings = {f.name: np.array([getattr(pr, f.name) for pr in problems]) for f in CASE if f.name != "y0"}
        return cls(problems[0].model, np.array([pr.p for pr in problems]), settings)


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
) -> Cases:
    """Cases for pulses ``(Omega, beta)`` and dampers ``(gamma, omega_ratio, zeta, h)``.

    ``sign`` (+1 or -1, or an array of them) is the direction of each pulse (:class:`rocking.OneSinePulse`).
    ``stops``: the dampers' guides end in the stops of :meth:`rocking.Stops.at_edges`
    (model ``"omd_stops"``); with ``gamma`` only. ``stroke``: their half-stroke ``L``, m, in
    ``(0, B/2)`` (default ``B/2`` minus the pads' depth, :data:`rocking.model.params.BUMPER_DEPTH`).

    All array arguments broadcast together (docs/model.md section 9 for their
    meaning); the result is flattened in C order. ``gamma = 0`` everywhere
    (or not given) means the bare block (model ``"block"``); otherwise every
    ``gamma`` must be > 0 and the model is ``"omd"`` unless given.

    ``params`` instead gives fixed values of the model's own parameters by
    name (those not set by the block), for any generated ``model`` (default
    ``"omd"``); it excludes ``gamma`` (``omega_ratio``, ``zeta`` and ``h``
    are then unused). The values are checked once against the model's ranges.
    """
    if params is not None and gamma is not None:
        raise ParameterError(
            "give either gamma (the omd damper relative to its block) or params (a model's own parameters), not both"
        )
    check_block(block)
    sign = check_signs(sign)
    if not isinstance(stops, (bool, np.bool_)):
        raise ParameterError(f"stops must be True or False (got {stops!r})")
    rtol = float(boundary.check("rtol", check_real("rtol", rtol)))
    t_after = check_in_range("t_after", t_after)
    max_events = check_integer("max_events", max_events)
    Omega, beta, gamma = _array("Omega", Omega), _array("beta", beta), _array("gamma", 0.0 if gamma is None else gamma)
    omega_ratio, zeta = _array("omega_ratio", omega_ratio), _array("zeta", zeta)
    h, psi = _array("h", h), _array("psi", psi)
    try:
        arrays = np.broadcast_arrays(Omega, beta, gamma, omega_ratio, zeta, h, psi, sign)
    except ValueError:
        raise ParameterError("Omega, beta, gamma, omega_ratio, zeta, h, psi and sign must broadcast together") from None
    Omega, beta, gamma, omega_ratio, zeta, h, psi, sign = (a.ravel() for a in arrays)
    bare = params is None and not np.any(gamma > 0)
    if not bare and params is None and np.any(gamma == 0):
        raise ParameterError("gamma must be > 0 in every case of a batch with a damper (use a separate bare batch)")
    if stroke is not None and not stops:
        raise ParameterError("stroke is the half-stroke of the stops: give it with stops=True")
    depth = BUMPER_DEPTH
    if stroke is not None:
        depth = block.B / 2 - check_interval("stroke", stroke, 0.0, block.B / 2, "m", label="(0, B/2)")
    if stops and (bare or params is not None):
        raise ParameterError("stops=True puts the stops of Stops.at_edges on the omd damper of gamma > 0: "
                             "give the damper by gamma (a model's params set their own stops)")  # fmt: skip
    try:
        model = resolve_model(model, "block" if bare else "omd_stops" if stops else "omd")
    except ModelError as exc:
        raise ParameterError(str(exc)) from None
    _derived("omega_g", Omega * block.p, "Omega p")
    _derived("a_g", beta * block.g * block.tan_alpha, "beta g tan(alpha)")

    omega_g = Omega * block.p
    psi = psi + 0 * Omega
    t_p = (2 * np.pi - psi) / omega_g
    values = {k: np.full(Omega.shape, v) for k, v in block.as_params().items()}
    T_m = np.full(Omega.shape, np.inf)
    if params is not None:
        fixed = _fixed_params(model, block, params)
        values.update({k: np.full(Omega.shape, v) for k, v in fixed.items()})
    elif not bare:
        m = gamma * block.M
        omega_m = omega_ratio * block.p
        values.update(m=m, k_m=m * omega_m**2, c=2 * zeta * m * omega_m, h=h)
        T_m = 2 * np.pi / omega_m
        if stops:
            values.update(zip(STOP_PARAMETERS, edge_stops(block, m, omega_m, depth)))
            _derived("L", values["L"], "B/2 minus the pads' depth of Stops.at_edges")
            _derived("omega_b", np.sqrt(values["k_b"] / m) / block.p, "the bumpers' frequency over p", "omega_b_ratio")
    missing = [name for name in model.parameters if name not in values]
    if missing:
        raise ParameterError(
            f"model {model.name!r} needs parameter(s) {', '.join(missing)} that pulse_cases cannot set"
        )
    settings = default_settings(block, 2 * np.pi / omega_g, T_m, rtol, model.nq)
    return Cases(
        model,
        np.column_stack([values[k] for k in model.parameters]),
        {
            "a_g": sign * beta * block.g * block.tan_alpha,
            "omega_g": omega_g,
            "psi": psi,
            "t_p": t_p,
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


def run_cases(cases: Cases, backend: str = "c", threads: int = 1) -> dict[str, np.ndarray]:
    """Simulate every case; a dict of arrays keyed by :data:`RESULT_FIELDS`.

    ``status`` holds indices into :data:`rocking.sim.boundary.STATUS`.
    """
    if backend == "c":
        from . import c_backend

        return c_backend.simulate_cases(cases, threads=threads)
    if backend != "numpy":
        raise ParameterError(f"backend must be 'c' or 'numpy' (got {backend!r})")
    from . import numpy_backend

    out = {k: np.zeros(len(cases), dtype=t) for k, t in RESULT_FIELDS.items()}
    for i in range(len(cases)):
        r = numpy_backend.simulate(cases.problem(i))
        for k in RESULT_FIELDS:
            out[k][i] = STATUS.index(r.status) if k == "status" else getattr(r, k)
    return out
