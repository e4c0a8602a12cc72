"""A response's time history on a uniform grid, with the loads derived from the model, and its events.

:meth:`Response.to_dataset`, :meth:`Response.to_dataframe` and :meth:`Response.events` are
built here, from the response's recorded history and its inputs; nothing here runs the
simulator. The grid ``t_k = k dt`` holds exact samples of the integrator's dense output: the
run was recorded every ``dt`` (for another spacing, :func:`rocking.sim.run.rerecord` runs it
again), and a back end samples the multiples of ``record_dt`` on the dense output of the step that holds them
(docs/simulation.md, "History"), never across an impact. The events, which a recorded
history holds as extra rows (twice at an impact, before and after), go to their own table.

The loads come from generated functions (docs/model.md section 13): the accelerations
``ddq`` of the sample's phase (``contact_accel`` or ``rocking_accel``), then
``block_accelerations`` and ``base_reaction``, affine in ``ddq``, ``element_forces``,
``stop_forces`` and ``energy``. Units SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..model.loading import Model
from ..model.params import RANGES, ParameterError
from .boundary import CONTACT
from .pad_memory import WithMemory, memory

#: The conventions of the project's NetCDF files (histories and studies): CF 1.10 attributes.
CONVENTIONS = "CF-1.10"


@dataclass(frozen=True)
class RunInputs:
    """What a response was computed from: its loads are derived from them, and it can be run again from them.

    Attributes
    ----------
    model : Model
        The generated model.
    p : tuple or ndarray
        Parameters in the model's order.
    settings : dict
        Every field of :data:`~rocking.sim.boundary.CASE` by name, as :func:`~rocking.sim.problem.resolve` gives them.
    backend : str
        The back end that ran it (``"c"`` or ``"numpy"``).
    """

    model: Model
    p: tuple | np.ndarray
    settings: dict
    backend: str


#: Kinds of the rows of :func:`events`.
EVENT_KINDS = {
    "uplift": "the block leaves full contact (phase_after: the pivot)",
    "impact": "theta reaches 0 falling: rocking goes on about the other corner, or rest (phase_after 0)",
    "contact": "back to full contact without an impact (a lift-off that could not rise)",
    "bumper_contact": "an end stop's bumper starts to push (its gap closes, or a released pad pushes again)",
    "bumper_release": "an end stop's bumper stops pushing (its force falls to 0, or its gap opens)",
    "pulse_end": "the ground motion ends (t_p)",
    "overturn": "|theta| reaches pi/2: the run ends",
    "slip": "the contact starts to slide (a floor with friction, docs/model.md section 15)",
    "stick": "the slip stops and the floor holds the contact",
    "reverse": "the slip stops and goes on the other way",
    "takeoff": "the floor's normal force reaches 0: the block flies (section 16; phase_after: its reference corner)",
    "landing": "a base corner reaches the floor: the block rocks, stands, or bounces on (phase_after 0: flat)",
}

#: What the quantities of every model are: name -> (unit, long name). Coordinates come from the manifest.
_LOADS = {
    "a_g": ("m/s^2", "ground acceleration, > 0 to the right"),
    "a_gy": (
        "m/s^2",
        "vertical ground acceleration ddy_g, > 0 up: the block feels gravity g + a_gy; unsigned by the motion's "
        "direction, 0 without a vertical component (docs/model.md section 14)",
    ),
    "a_top": ("m/s^2", "absolute horizontal acceleration of the centre of the block's top side"),
    "a_cm": ("m/s^2", "absolute horizontal acceleration of the block's centroid G"),
    "V_b": ("N", "base shear: horizontal force of the ground on the block and its bodies, > 0 to the right"),
    "N_b": ("N", "vertical force of the ground on the block and its bodies, > 0 up"),
    "M_b": (
        "N m",
        "overturning moment about the centre of the base (minus the ground reaction's moment there), "
        "> 0 counter-clockwise: it tips the block about A",
    ),
    "F_b": ("N", "force of the end stops' bumpers against their penetration (0 while clear)"),
    "E_kinetic": ("J", "kinetic energy, velocities relative to the ground"),
    "E_potential": ("J", "potential energy above rest (weights, springs, bumpers)"),
    "E_total": ("J", "mechanical energy above rest, E_kinetic + E_potential"),
    "phase": ("1", "phase: 0 full contact, +1 rocking about A, -1 rocking about A'"),
}
#: The columns a history holds after the state, ``phase`` and ``ag`` on a floor with friction, both back ends, in
#: this order: the slip u [m], its speed du [m/s], the floor's normal and tangential forces N and F on the block
#: [N], and the slip's sign (0 stuck, +1 / -1 sliding).
FLOOR_COLUMNS = ("u", "du", "N", "F", "slide")
#: The columns a history of a model with flight holds after :data:`FLOOR_COLUMNS` (on every floor, both back
#: ends, in this order): the reference corner's height v above the floor [m] ("y of the base"), its rate dv [m/s],
#: and 1.0 in flight, else 0.0 (docs/model.md section 16; in flight N = F = 0 and phase is the reference corner).
FLIGHT_COLUMNS = ("v", "dv", "fly")
#: The slip of the base on a floor with friction (docs/model.md section 15): V_b and N_b are then the floor's
#: tangential and normal forces F and N on the contact.
_SLIP = {
    "u": ("m", "slip of the base relative to the ground, > 0 to the right (in flight: the reference corner's)"),
    "du": ("m/s", "slip speed of the base"),
    "slide": ("1", "slip: 0 the contact sticks, +1 or -1 it slides that way"),
    "v": ("m", "height of the reference corner above the floor (y of the base; 0 on the floor)"),
    "dv": ("m/s", "vertical speed of the reference corner"),
    "fly": ("1", "1 in flight (the block off the floor; phase: its reference corner), else 0"),
}


def default_dt(settings: dict) -> float:
    """The run's ``record_dt`` [s]; for a run recorded at events only, a hundredth of the pulse's period
    (a sampled motion: its spacing), at most ``RANGES["record_samples"]`` samples over ``t_max``."""
    if settings["record_dt"] > 0.0:
        return float(settings["record_dt"])
    period = 2 * math.pi / settings["omega_g"] / 100 if settings["omega_g"] > 0 else settings["pulse_dt"]
    return max(period, settings["t_max"] / RANGES["record_samples"].high)


def check_dt(dt: object, t_max: float) -> float:
    """``dt`` as a float if it is a real number with at most ``RANGES["record_samples"]`` samples over ``t_max``."""
    most = RANGES["record_samples"].high
    if isinstance(dt, (bool, np.bool_)) or not isinstance(dt, (int, float, np.integer, np.floating)):
        raise ParameterError(f"dt must be a number of seconds > 0 (got {dt!r})")
    dt = float(dt)
    if not (math.isfinite(dt) and dt >= t_max / most and dt > 0.0):
        raise ParameterError(
            f"dt must be in [t_max / {most:g}, inf) = [{t_max / most:g}, inf) s (got {dt!r}): at most {most:g} samples"
        )
    return dt


def run_inputs(response) -> RunInputs:
    """The :class:`~rocking.sim.problem.RunInputs` of ``response``, which its loads and a run again need."""
    if response.inputs is None:
        raise ParameterError(
            "this response has no inputs (a batch's row, or a back end called directly): "
            "simulate it with rocking.simulate(..., record=True) to get its history"
        )
    return response.inputs


def recorded(response, dt: float | None) -> tuple[dict, float]:
    """The history of ``response`` if it was recorded every ``dt`` (default: its ``record_dt``), and ``dt``.

    Raises
    ------
    ParameterError
        A bad ``dt``; a response not recorded every ``dt``: the message says how to record it (the
        history is exact samples of the dense output, which only such a run holds).
    """
    settings = run_inputs(response).settings
    dt = default_dt(settings) if dt is None else check_dt(dt, settings["t_max"])
    if response.history is not None and settings["record_dt"] == dt:
        return response.history, dt
    was = "has no history" if response.history is None else f"was recorded every {settings['record_dt']:g} s"
    raise ParameterError(
        f"dt = {dt:g} s: this response {was}; record its run every dt: rocking.simulate(..., record=True, "
        f"record_dt={dt!r}), or rocking.sim.run.rerecord(response, {dt!r})"
    )


def first_sample_after(t: float, dt: float, strict: bool = True) -> int:
    """The least index ``k >= 0`` whose sample time ``k dt`` is ``> t`` (``>= t`` unless ``strict``).

    Every sample time is the product ``k dt`` rounded once, never a sum, and is monotone in
    ``k``; ``floor(t / dt)`` rounds the ratio too, and may land one index off either way (``t / dt``
    can round up to an integer ``k`` where ``k dt > t``): corrected both ways on the products
    themselves, as sim.c's ``record_first_sample``.
    """
    k = max(math.floor(t / dt) + 1, 0)
    while k > 0 and ((k - 1) * dt > t if strict else (k - 1) * dt >= t):
        k -= 1
    while (k * dt <= t) if strict else (k * dt < t):
        k += 1
    return k


def _grid_rows(history: dict, dt: float, t_end: float) -> np.ndarray:
    """Index of the row of ``history`` at each ``k dt <= t_end``: the last one at that instant (after an event)."""
    grid = np.arange(first_sample_after(t_end, dt)) * dt  # k dt <= t_end: the back ends' products
    rows = np.searchsorted(history["t"], grid, side="right") - 1
    if not np.array_equal(history["t"][rows], grid):
        raise RuntimeError(f"the history recorded every {dt!r} s lacks samples at some multiples of it")
    return rows


def vertical(history: dict) -> np.ndarray:
    """The vertical ground acceleration of a recorded history (0 where the motion has none)."""
    return history["agy"] if "agy" in history else np.zeros_like(history["ag"])


def _evaluate(function, s, y, ag, agy, p) -> list[np.ndarray]:
    """A generated NumPy function's outputs on the rows, as a list of arrays."""
    out = function(s, *y, ag, agy, *p)
    return [np.asarray(o, dtype=float) for o in (out if isinstance(out, tuple) else (out,))]


def _affine(outputs: list, ddq: list, quantities: int) -> list[np.ndarray]:
    """The quantities of a generated function affine in ``ddq``: ``out[0] + sum_j out[1 + j] ddq_j`` each."""
    n = len(ddq) + 1
    rows = [outputs[i * n : (i + 1) * n] for i in range(quantities)]
    return [row[0] + sum(c * a for c, a in zip(row[1:], ddq)) for row in rows]


def _sliding(fn, s, y, ag, agy, p, contact, slide, mu_k: float) -> tuple[list, np.ndarray]:
    """``(ddq, ddu)`` of the sliding rows (``slide != 0``; the others' are NaN, not read), from the phase's
    generated accelerations with ``mu_slip = mu_k slide`` (docs/model.md section 15)."""
    mu_slip = mu_k * slide.astype(float)
    both = [
        _evaluate(getattr(fn, name), s, y, ag, agy, p + [mu_slip]) for name in ("contact_slide_accel", "slide_accel")
    ]
    accel = [np.where(contact, c, r) for c, r in zip(*both)]
    return accel[: len(accel) - 2], accel[-2]


def quantities(model, p, history: dict, rows: np.ndarray, mu_k: float = math.inf) -> dict[str, np.ndarray]:
    """Every variable of the dataset on ``rows`` of ``history``, by name (``t`` first); on a floor with friction
    (kinetic ``mu_k``, the history's ``slide`` column) the sliding rows' accelerations and the floor's forces are
    those of the sliding phases, in the frame of the base (``a_g + ddu``)."""
    n = model.nq
    phase = history["phase"][rows]
    y = [history[name][rows] for name in model.state]
    ag = history["ag"][rows]
    agy = vertical(history)[rows]
    s = np.where(phase == CONTACT, 1.0, phase.astype(float))  # the functions at theta = 0 hold for either pivot
    p = [float(v) for v in p]
    # Hunt-Crossley pads: their forces need the approach speed of each contact, found again on the history.
    fn = WithMemory(model, [v_in[rows] for v_in in memory(model, p, history)])
    contact = phase == CONTACT
    ddq = [
        np.where(contact, c, r)
        for c, r in zip(_evaluate(fn.contact_accel, s, y, ag, agy, p), _evaluate(fn.rocking_accel, s, y, ag, agy, p))
    ]
    base = ag  # the acceleration of the base: the ground's while the contact sticks
    slip = {name: history[name][rows] for name in ("u", "du", "slide", *FLIGHT_COLUMNS) if name in history}
    if slip and np.any(slip["slide"]):
        sliding = slip["slide"] != 0
        with np.errstate(all="ignore"):  # the stuck rows' sliding accelerations are not read
            slid, ddu = _sliding(fn, s, y, ag, agy, p, contact, slip["slide"], mu_k)
        ddq = [np.where(sliding, a, b) for a, b in zip(slid, ddq)]
        base = np.where(sliding, ag + ddu, ag)
    flying = slip["fly"] != 0.0 if "fly" in slip else np.zeros(ag.shape, dtype=bool)
    if np.any(flying):
        # In flight (docs/model.md section 16): the accelerations of flight_accel, the reference corner's horizontal
        # acceleration ag + ddu (its vertical one does not enter the horizontal accelerations of a_top and a_cm).
        flown = _evaluate(fn.flight_accel, s, y, ag, agy, p)
        ddq = [np.where(flying, a, b) for a, b in zip(flown[:n], ddq)]
        base = np.where(flying, ag + flown[n], base)
    out = {"t": history["t"][rows]}
    out.update(zip(model.state[:n], y[:n]))
    out.update(zip(model.state[n:], y[n:]))
    out.update({"dd" + q: a for q, a in zip(model.coordinates, ddq)})
    out["phase"] = phase
    out.update(slip)
    out["a_g"] = ag
    out["a_gy"] = agy
    out["a_top"], out["a_cm"] = _affine(_evaluate(fn.block_accelerations, s, y, base, agy, p), ddq, 2)
    # No floor under a flying block: its reactions are 0.
    reactions = _affine(_evaluate(fn.base_reaction, s, y, base, agy, p), ddq, 3)
    out["V_b"], out["N_b"], out["M_b"] = (np.where(flying, 0.0, r) for r in reactions)
    out.update({"F_" + q: f for q, f in zip(model.coordinates[1:], _evaluate(fn.element_forces, s, y, ag, agy, p))})
    bumpers = _evaluate(fn.stop_forces, s, y, ag, agy, p)
    if bumpers:
        out["F_b"] = sum(bumpers)
    energy = _evaluate(fn.energy, s, y, ag, agy, p)[0]
    zero = np.zeros_like(ag)
    # At rest velocities in the regime of the state: a released pad's potential has left the mass.
    pushing = [(c > 0.0).astype(float) for c in _evaluate(fn.stop_contact, s, y, ag, agy, p)]
    potential = np.asarray(fn.energy(s, *y[:n], *[zero] * n, ag, agy, *p, stop_on=pushing or None), dtype=float)
    rest = _evaluate(fn.energy, 1.0, [zero] * (2 * n), zero, zero, p)[0]
    if slip:  # the slip's kinetic energy, in the ground frame as the rest
        energy = energy + _evaluate(fn.slip_energy, s, y, ag, agy, p + [slip["du"]])[0]
    if np.any(flying):  # in flight: with the corner's velocity and height (generated flight_energy)
        heights = [slip["v"], slip["du"], slip["dv"]]
        energy = np.where(flying, _evaluate(fn.flight_energy, s, y, ag, agy, p + heights)[0], energy)
        lifted = np.asarray(
            fn.flight_energy(s, *y[:n], *[zero] * n, ag, agy, *p, slip["v"], zero, zero, stop_on=pushing or None),
            dtype=float,
        )
        potential = np.where(flying, lifted, potential)
    out["E_kinetic"] = energy - potential
    out["E_potential"] = potential - rest
    out["E_total"] = energy - rest
    return out


def attributes(model) -> dict[str, tuple[str, str]]:
    """``(units, long_name)`` of every variable :func:`quantities` gives for ``model``, in its order."""
    units = model.manifest["units"]
    attrs = {"t": ("s", "time")}
    for q in model.coordinates:
        attrs[q] = (units[q], "rocking angle, > 0 tilting about A" if q == "theta" else f"coordinate {q} of the damper")
    attrs.update({"d" + q: (units["d" + q], f"velocity of {q}") for q in model.coordinates})
    attrs.update({"dd" + q: (units[q] + "/s^2", f"acceleration of {q}") for q in model.coordinates})
    attrs["phase"] = _LOADS["phase"]
    attrs.update(_SLIP)  # those a history holds (quantities gives the dataset's, in this order)
    attrs.update({k: _LOADS[k] for k in ("a_g", "a_gy", "a_top", "a_cm", "V_b", "N_b", "M_b")})
    for q in model.coordinates[1:]:
        force = "N m" if units[q] == "rad" else "N"
        attrs["F_" + q] = (
            force,
            f"force of the springs, dashpots and bumpers of {q} on the block along {q}, "
            f"minus theirs on the damper (omd: the guide force)",
        )
    if int(model.manifest["functions"]["stop_forces"]["outputs"]):
        attrs["F_b"] = _LOADS["F_b"]
    attrs.update({k: _LOADS[k] for k in ("E_kinetic", "E_potential", "E_total")})
    return attrs


def to_dataset(response, dt: float | None = None):
    """:meth:`Response.to_dataset`: the history every ``dt`` as an ``xarray.Dataset`` over ``t``."""
    import xarray as xr

    history, dt = recorded(response, dt)
    inputs = run_inputs(response)
    model = inputs.model
    values = quantities(model, inputs.p, history, _grid_rows(history, dt, response.t_end), inputs.settings["mu_k"])
    attrs = attributes(model)
    t = values.pop("t")
    variables = {k: ("t", v, {"units": attrs[k][0], "long_name": attrs[k][1]}) for k, v in values.items()}
    return xr.Dataset(
        variables,
        coords={"t": ("t", t, {"units": "s", "long_name": "time", "standard_name": "time"})},
        attrs={
            "model": model.name,
            "backend": inputs.backend,
            "dt": dt,
            "status": response.status,
            "t_end": response.t_end,
            "Conventions": CONVENTIONS,
            "comment": "SI units; signs and the point of M_b as docs/model.md sections 1 and 13",
        },
    )


def to_dataframe(response, dt: float | None = None):
    """:meth:`Response.to_dataframe`: the dataset of :func:`to_dataset` as a ``pandas.DataFrame`` indexed by ``t``.

    Its ``attrs`` hold ``units`` and ``long_name`` by column.
    """
    ds = to_dataset(response, dt)
    frame = ds.to_dataframe()
    frame.attrs = {
        "units": {k: ds[k].attrs["units"] for k in ("t", *frame.columns)},
        "long_name": {k: ds[k].attrs["long_name"] for k in ("t", *frame.columns)},
        **ds.attrs,
    }
    return frame


def events(response):
    """:meth:`Response.events`: one row per event, in time order (``t``, ``kind``, ``phase_before``, ``phase_after``).

    Read from the recorded history (the response's own, or the run recorded again at
    its events and the default spacing): the phase codes tell uplifts, impacts and the
    lift-offs that fall back without one; the stops' contacts (generated ``stop_contact``)
    where their bumpers start and stop pushing. The kinds are :data:`EVENT_KINDS`.
    """
    import pandas as pd

    inputs = run_inputs(response)
    model, p, settings = inputs.model, inputs.p, inputs.settings
    if response.history is None:
        raise ParameterError(
            "this response has no history: simulate it with rocking.simulate(..., record=True), "
            "or run it again recorded with rocking.sim.run.rerecord(response)"
        )
    history = response.history
    t, phase, theta, dtheta = (history[k] for k in ("t", "phase", "theta", "dtheta"))
    rows = []
    flying = history["fly"] != 0.0 if "fly" in history else np.zeros(t.shape, dtype=bool)
    # A row pair that enters or leaves flight, or lands within it (a bounce): the flight's events, not the floor's.
    aloft = np.concatenate([[False], flying[1:] | flying[:-1]])
    for i in np.flatnonzero(flying[1:] != flying[:-1]) + 1:
        rows.append((float(t[i]), "takeoff" if flying[i] else "landing", int(phase[i - 1]), int(phase[i])))
    if np.any(flying):
        dv = history["dv"]
        bounce = flying[1:] & flying[:-1] & (t[1:] == t[:-1]) & (dv[:-1] < 0.0) & (dv[1:] > 0.0)
        rows += [(float(t[i]), "landing", int(phase[i - 1]), int(phase[i])) for i in np.flatnonzero(bounce) + 1]
    for i in np.flatnonzero((phase[1:] != phase[:-1]) & ~aloft[1:]) + 1:
        before, after = int(phase[i - 1]), int(phase[i])
        if before == CONTACT:
            kind = "uplift"
        else:
            kind = "impact" if theta[i - 1] == 0.0 and before * dtheta[i - 1] < 0.0 else "contact"
        rows.append((float(t[i]), kind, before, after))
    state = [history[k] for k in model.state]
    # A Hunt-Crossley pad pushes by the approach speed of its contact, found again on the history.
    fn = WithMemory(model, memory(model, [float(v) for v in p], history))
    contacts = _evaluate(fn.stop_contact, 1.0, state, history["ag"], vertical(history), list(p))
    for contact in contacts:
        for i in np.flatnonzero((contact[1:] > 0.0) != (contact[:-1] > 0.0)) + 1:
            kind = "bumper_contact" if contact[i] > 0.0 else "bumper_release"
            rows.append((float(t[i]), kind, int(phase[i]), int(phase[i])))
    if "slide" in history:
        slide = history["slide"]
        for i in np.flatnonzero((slide[1:] != slide[:-1]) & (flying[1:] == flying[:-1])) + 1:
            kind = "slip" if slide[i - 1] == 0 else "stick" if slide[i] == 0 else "reverse"
            rows.append((float(t[i]), kind, int(phase[i]), int(phase[i])))
    if settings["t_p"] <= response.t_end:
        i = min(np.searchsorted(t, settings["t_p"]), len(t) - 1)
        rows.append((float(settings["t_p"]), "pulse_end", int(phase[i]), int(phase[i])))
    if response.overturned:
        rows.append((float(response.t_overturn), "overturn", int(phase[-1]), int(phase[-1])))
    frame = pd.DataFrame(rows, columns=["t", "kind", "phase_before", "phase_after"])
    frame = frame.sort_values("t", kind="stable", ignore_index=True)
    frame.attrs = {"units": {"t": "s", "kind": "", "phase_before": "1", "phase_after": "1"}}
    return frame


#: The files :func:`write` writes, by extension.
HISTORY_FORMATS = (".csv", ".nc")


def write(response, path, dt: float | None = None) -> None:
    """Write the history of ``response`` every ``dt`` to ``path``: CSV (units in the column names,
    ``theta [rad]``) or NetCDF (xarray, engine netcdf4), by the extension :data:`HISTORY_FORMATS`."""
    suffix = Path(path).suffix.lower()
    if suffix not in HISTORY_FORMATS:
        raise ParameterError(f"history file must end in {' or '.join(HISTORY_FORMATS)} (got {str(path)!r})")
    from ..model.outputs import atomic_write, replace_file, write_netcdf  # as every output

    ds = to_dataset(response, dt)
    if suffix == ".nc":
        replace_file(Path(path), lambda tmp: write_netcdf(ds, tmp))
        return
    frame = ds.to_dataframe()
    frame.index.name = "t [s]"
    frame.columns = [f"{k} [{ds[k].attrs['units']}]" for k in frame.columns]
    atomic_write(Path(path), lambda file: frame.to_csv(file, float_format="%.17g"), mode="w")
