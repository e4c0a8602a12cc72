"""Hold a generated model against the hand-written equations of :mod:`rocking.reference.paper`.

``rocking verify`` (and ``make verify``) runs :func:`verify` on random states
and parameter sets for both pivots and prints the largest relative error of
every generated function.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..model.checks import ParameterError, Range, shown
from ..model.loading import Model, ModelError
from . import flight, paper, sliding

#: Largest relative error accepted between generated and hand-written results.
TOLERANCE = 1e-12
#: Random cases per pivot: a case's arrays take about 10 kB at the peak (``rocking verify --cases 100000``, the
#: four models with the functions of a floor with friction: 0.95 GB and 119 s of CPU on a shared machine, measured),
#: so the bound keeps a check within a laptop's memory and a few minutes.
CASES = Range(1, 100_000, "", "a case takes about 10 kB: 1 GB at the bound", integer=True)
#: Seeds of the random cases: those of numpy.random.default_rng.
SEEDS = Range(0, math.inf, "", "the seeds of numpy.random.default_rng", integer=True)
#: The shipped models that :mod:`rocking.reference.paper` writes by hand (docs/model.md sections 3-7 and 11).
BY_HAND = ("omd", "omd_stops", "omd_stops_hc", "block")


@dataclass(frozen=True)
class Check:
    """Largest relative error of one generated function on one pivot."""

    function: str
    pivot: int
    cases: int
    max_rel_error: float

    @property
    def ok(self) -> bool:
        return bool(self.max_rel_error <= TOLERANCE)


def random_cases(
    rng: np.random.Generator, n: int, s: int, damper: bool = True, stops: bool = False, hunt_crossley: bool = False
) -> dict[str, np.ndarray]:
    """``n`` random states and parameter sets rocking about ``s``, by name.

    Blocks from stocky to slender, eccentric, with any inertia; dampers from
    light to heavy, soft to stiff. Without ``damper`` the mass and its state are 0.
    With ``stops``, bumpers at ``|x| = L`` from 5 % to 45 % of ``B``, 1 to 1000 times
    stiffer than the damper's spring: ``x`` lies inside the gap or beyond it. With ``hunt_crossley``,
    Hunt-Crossley pads of exponent 1 to 2.5 and damping factor 0 to 4 (restitution 1 to 0.24), as stiff at 10 mm.
    """
    u = rng.uniform
    M = u(50.0, 5000.0, n)
    B = u(0.2, 2.0, n)
    H = B * u(1.0, 8.0, n)
    v = {
        "s": np.full(n, float(s)),
        "M": M,
        "B": B,
        "H": H,
        "e": B * u(-0.45, 0.45, n),
        "I_G": M * (B**2 + H**2) / 12 * u(0.5, 1.5, n),
        "g": u(9.0, 10.0, n),
        "theta": s * u(-0.1, 1.5, n),
        "dtheta": u(-3.0, 3.0, n),
        "ag": u(-20.0, 20.0, n),
        "agy": u(-8.0, 8.0, n),
    }
    if damper:
        m = M * u(0.001, 0.3, n)
        omega = u(0.5, 30.0, n)
        v.update(
            m=m,
            h=u(0.0, 0.5, n),
            k_m=m * omega**2,
            c=2 * m * omega * u(0.0, 0.5, n),
            x=B * u(-0.4, 0.4, n),
            dx=u(-3.0, 3.0, n),
        )
    else:
        v.update({k: np.zeros(n) for k in ("m", "h", "k_m", "c", "x", "dx")})
    if stops:
        k_b = v["k_m"] * 10 ** u(0.0, 3.0, n)
        v.update(L=B * u(0.05, 0.45, n), k_b=k_b, c_b=2 * np.sqrt(k_b * v["m"]) * u(0.0, 0.5, n))
    if hunt_crossley:
        n_b = u(1.0, 2.5, n)
        v.update(k_b=v.pop("k_b") * 0.01 ** (1.0 - n_b), n_b=n_b, chi_b=u(0.0, 4.0, n))
        del v["c_b"]
    return v


#: Values smaller than this fraction of an output's median size are compared at
#: that size: there the result is a difference of much larger terms, and double
#: precision itself cannot give it to a relative 1e-12.
CANCELLATION_FLOOR = 1e-2
#: Unit roundoff of the doubles the generated code computes in: an argument's last bit, relative.
ROUNDOFF = 2.0**-53
#: Random roundings of the arguments over which :func:`spread` takes the reference's largest move.
ROUNDINGS = 2


def rel_error(got, ref, spread=None) -> float:
    """Largest relative error of ``got`` against the reference ``ref`` over the cases.

    The error is ``|got - ref| / max(|ref|, CANCELLATION_FLOOR * median |ref|, spread / ROUNDOFF)``. ``spread``
    (:func:`spread`) is how far the reference moves when its arguments move by their last bit: where it moves
    more than ``ROUNDOFF |ref|``, ``ref`` is the small difference of terms of about ``spread / ROUNDOFF``, and
    double precision itself gives it no better than that. A NaN on one side only is an infinite error (a NaN
    reference would otherwise compare equal to anything); NaN on both sides is none (the functions documented as
    NaN somewhere, ``critical_tangent``). Where the reference is 0 in every case (the bare block's ``ddtheta`` in
    flight, a sticking corner's ``du`` after it) only an exact 0 agrees: anything else is an infinite error.
    """
    got = np.asarray(got, dtype=np.longdouble)
    ref = np.broadcast_to(np.asarray(ref, dtype=np.longdouble), got.shape)
    if got.size == 0:
        return 0.0
    if np.any(np.isnan(got) != np.isnan(ref)):
        return math.inf
    size = np.abs(ref)
    scale = np.maximum(size, CANCELLATION_FLOOR * np.nanmedian(size))
    if spread is not None:
        scale = np.maximum(scale, np.asarray(spread, dtype=np.longdouble) / ROUNDOFF)
    same = (got == ref) | np.isnan(ref)  # equal infinities are no error
    with np.errstate(invalid="ignore"):  # inf - inf where both are inf: masked by `same`
        diff = np.abs(got - ref)
    err = np.divide(diff, scale, out=np.zeros_like(scale), where=(scale > 0) & ~same)
    # A reference that is exactly 0 in every case has no scale: there only 0 itself agrees with it.
    err[(scale == 0) & ~same] = np.inf
    return float(np.max(err))


#: Functions that only make sense at theta = 0 (and dtheta = 0 in full contact).
_STATE_OF = {
    "contact_accel": "contact",
    "uplift": "contact",
    "impact": "impact",
    "contact_slide_accel": "contact",
    "slide_uplift": "contact",
    "contact_stick_force": "contact",
    "impact_stick": "impact",
    "impact_slide": "impact",
}


def friction_inputs(rng: np.random.Generator, n: int) -> dict[str, np.ndarray]:
    """The arguments of a floor with friction for ``n`` cases: ``mu_slip`` in (-1, 1) (a kinetic coefficient up
    to 1, either slip direction) and the slip speed ``du`` in (-2, 2) m/s."""
    return {"mu_slip": rng.uniform(-1.0, 1.0, n), "du": rng.uniform(-2.0, 2.0, n)}


#: The arguments of flight and landing beside a floor with friction's (:func:`flight_inputs`).
FLIGHT_INPUTS = ("u", "v", "dv", "e_n")


def flight_inputs(rng: np.random.Generator, n: int) -> dict[str, np.ndarray]:
    """The arguments of flight and landing for ``n`` cases, beside a floor with friction's ``mu_slip`` and ``du``
    (:func:`friction_inputs`, which every flying model has): the corner's ``u`` in (-1, 1) m and height ``v`` in
    (0, 1) m, its vertical speed ``dv`` in (-2, 0) m/s (a corner lands moving down) and the restitution ``e_n`` in
    [0, 1]."""
    bounds = {"u": (-1.0, 1.0), "v": (0.0, 1.0), "dv": (-2.0, 0.0), "e_n": (0.0, 1.0)}
    return {k: rng.uniform(*bounds[k], n) for k in FLIGHT_INPUTS}


def _stops(v: dict, floor: float | None) -> dict:
    """The keywords of the end stops in :mod:`paper`'s functions: none, bumpers, or pads of least approach speed
    ``floor``."""
    stops = {k: v[k] for k in ("L", "k_b", "c_b", "n_b", "chi_b") if k in v}
    if "n_b" in stops:
        stops["floor"] = floor
    return stops


def _paper_results(v: dict, impact_law: str, floor: float | None = None) -> dict[str, tuple]:
    """The hand-written value of every generated function, by function name (bumpers if ``v`` has ``L``,
    Hunt-Crossley pads of least approach speed ``floor`` if it has ``n_b``)."""
    s, th, x, dth, dx, ag, agy = (v[k] for k in ("s", "theta", "x", "dtheta", "dx", "ag", "agy"))
    M, I_G, B, H, e, g, m, h, k_m, c = (v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c"))
    (m11, m12), (m21, m22) = paper.mass_matrix(s, th, x, M, I_G, B, H, e, m, h)
    zero, one = 0 * th, 0 * th + 1
    stops = _stops(v, floor)
    gaps = paper.stop_gaps(x, stops["L"]) if stops else ()
    forces = paper.stop_forces(x, dx, **stops) if stops else ()
    contacts = paper.stop_contact(x, dx, **stops) if stops else ()
    approaches = paper.stop_approach(x, dx, stops["L"]) if stops else ()
    # Without a damper (m = 0) the outputs of x are undefined and dropped by _select.
    with np.errstate(divide="ignore", invalid="ignore"):
        return {
            "mass_matrix": (m11, m12, m21, m22),
            "forcing": paper.forcing(s, th, x, dth, dx, ag, agy, M, B, H, e, g, m, h, k_m, c, **stops),
            "rocking_accel": paper.rocking_accel(s, th, x, dth, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c, **stops),
            "contact_accel": (zero, paper.contact_accel(x, dx, ag, m, k_m, c, **stops)),
            "uplift": (paper.uplift_margin(s, x, dx, ag, agy, M, B, H, e, g, m, h, k_m, c, **stops),),
            "impact": paper.impact(s, x, dth, dx, M, I_G, B, H, e, m, h, law=impact_law),
            "energy": (paper.energy(s, th, x, dth, dx, M, I_G, B, H, e, g, m, h, k_m, **stops),),
            "power": (paper.power(s, th, x, dth, dx, ag, agy, M, B, H, e, m, h, c, **stops),),
            "critical_angle": (paper.critical_angle(s, x, M, B, H, e, m, h),),
            "critical_tangent": (paper.critical_tangent(s, x, M, B, H, e, m, h),),
            "uplift_energy": (paper.uplift_energy_with_stops(s, M, B, H, e, g, m, h, k_m, c, **stops),),
            # Docs/simulation.md rule 4: the velocity law can add energy at an impact, hence no bound.
            "least_potential": (
                paper.least_potential(s, th, M, B, H, e, g, m, h, k_m) if impact_law == "momentum" else -np.inf * one,
            ),
            "least_stroke_potential": (
                paper.potential(s, th, x, M, B, H, e, g, m, h, k_m) if impact_law == "momentum" else -np.inf * one,
            ),
            "stop_gaps": gaps,
            "stop_forces": forces,
            "stop_contact": contacts,
            "stop_approach": approaches,
            "block_accelerations": _affine(
                lambda ddth, ddx: paper.block_accelerations(s, th, dth, ddth, ag, B, H, e), zero
            ),
            "base_reaction": _affine(
                lambda ddth, ddx: paper.base_reaction(s, th, x, dth, dx, ddth, ddx, ag, agy, M, I_G, B, H, e, g, m, h),
                zero,
            ),
            "element_forces": (paper.guide_force(x, dx, k_m, c, **stops),),
        }


def _friction_results(v: dict, floor: float | None = None) -> dict[str, tuple]:
    """The hand-typed value of each function of a floor with friction (docs/model.md section 15,
    :mod:`rocking.reference.sliding`), by name, at the arguments ``v`` (with ``mu_slip`` and ``du``)."""
    stops = _stops(v, floor)
    s, th, x, dth, dx, ag, agy, mu, du = (
        v[k] for k in ("s", "theta", "x", "dtheta", "dx", "ag", "agy", "mu_slip", "du")
    )
    M, I_G, B, H, e, g, m, h, k_m, c = (v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c"))
    body = (M, I_G, B, H, e, g, m, h, k_m, c)
    slid = sliding.contact_slide_frame_accel(x, dx, mu, M, g + agy, m, k_m, c, **stops)  # ddx_g + ddu
    hit = (s, x, dth, dx, du, mu, M, I_G, B, H, e, m, h)
    # Without a damper (m = 0) the outputs of x are undefined and dropped by _select.
    with np.errstate(divide="ignore", invalid="ignore"):
        return {
            "slide_accel": sliding.slide_rock_accel(s, th, x, dth, dx, ag, agy, mu, *body, **stops),
            "contact_slide_accel": sliding.contact_slide_accel(x, dx, ag, agy, mu, M, g, m, k_m, c, **stops),
            # Section 5's margin with the sliding base's acceleration ddx_g + ddu for ddx_g.
            "slide_uplift": (paper.uplift_margin(s, x, dx, slid, agy, M, B, H, e, g, m, h, k_m, c, **stops),),
            "stick_force": sliding.stick_force(s, th, x, dth, dx, ag, agy, *body, **stops),
            "contact_stick_force": sliding.contact_stick_force(x, dx, ag, agy, *body, **stops),
            "slip_energy": (sliding.slip_energy(s, th, x, dth, dx, du, M, B, H, e, m, h),),
            "impact_stick": sliding.friction_impact(*hit, stick=True),
            "impact_slide": sliding.friction_impact(*hit, stick=False),
        }


def _flight_results(v: dict, damper: bool, floor: float | None = None) -> dict[str, tuple]:
    """The hand-typed value of each function of flight and landing (docs/model.md section 16,
    :mod:`rocking.reference.flight`), by name, at the arguments ``v`` (with ``u``, ``v``, ``du``, ``dv``, ``e_n`` and
    ``mu_slip``), of the block with its ``damper`` or without, in the layout of the model with the damper
    (:func:`_select` keeps the bare block's)."""
    stops = _stops(v, floor)
    s, th, x, dth, dx, ag, agy = (v[k] for k in ("s", "theta", "x", "dtheta", "dx", "ag", "agy"))
    M, I_G, B, H, e, g, m, h, k_m, c = (v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c"))
    u, height, du, dv, e_n, mu = (v[k] for k in ("u", "v", "du", "dv", "e_n", "mu_slip"))
    zero = 0 * th
    corner = flight.other_corner(s, th, dth, u, height, du, dv, B)
    if not damper:
        ddth, ddu, ddv = flight.block_flight_accel(s, th, dth, ag, agy, M, I_G, B, H, e, g)
        accel = (ddth, zero, ddu, ddv)
        energy = flight.block_energy(s, th, dth, height, du, dv, M, I_G, B, H, e, g)
        stick = flight.block_landing(s, th, dth, du, dv, M, I_G, B, H, e, e_n, mu, stick=True)
        slide = flight.block_landing(s, th, dth, du, dv, M, I_G, B, H, e, e_n, mu, stick=False)
        stick, slide = ((w, zero, *rest) for w, *rest in (stick, slide))
        flat_stick = flight.block_flat_landing(s, dth, du, dv, M, I_G, B, H, e, e_n, mu, stick=True)
        flat_slide = flight.block_flat_landing(s, dth, du, dv, M, I_G, B, H, e, e_n, mu, stick=False)
        flats = {name: (zero, zero, *out) for name, out in (("stick", flat_stick), ("slide", flat_slide))}
    else:
        guide = paper.guide_force(x, dx, k_m, c, **stops)
        accel = flight.omd_flight_accel(s, th, x, dth, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c, guide=guide)
        pads = np.where(paper.pushes(x, dx, **stops), paper.pad(x, dx, **stops)[3], 0.0) if stops else 0.0
        energy = flight.omd_energy(
            s, th, x, dth, dx, height, du, dv, M, I_G, B, H, e, g, m, h, k_m, k_m * x**2 / 2 + pads
        )
        body = (s, th, x, dth, dx, du, dv, M, I_G, B, H, e, m, h, e_n, mu)
        stick, slide = flight.omd_landing(*body, stick=True), flight.omd_landing(*body, stick=False)
        flat = (s, x, dth, dx, du, dv, M, I_G, B, H, e, m, h, e_n, mu)
        flats = {law: (zero, *flight.omd_flat_landing(*flat, stick=law == "stick")) for law in ("stick", "slide")}
    # A sticking corner's slip after is 0 by definition: the reference's solve gives it to its rounding only.
    stick = (*stick[:2], zero, *stick[3:])
    results = {
        "flight_accel": accel,
        "corner_heights": (height, corner[1]),
        "flight_corner": corner,
        "flight_energy": (energy,),
        "landing_stick": stick,
        "landing_slide": slide,
    }
    flats["stick"] = (*flats["stick"][:2], zero, *flats["stick"][3:])
    results.update(flat_landing_stick=flats["stick"], flat_landing_slide=flats["slide"])
    return results


def _affine(loads, zero) -> tuple:
    """The layout of the generated functions affine in ``(ddtheta, ddx)``: per quantity of ``loads(ddtheta, ddx)``,
    its value at rest accelerations, then its coefficients (exact differences: ``loads`` is affine)."""
    free = loads(zero, zero)
    by_theta, by_x = loads(zero + 1, zero), loads(zero, zero + 1)
    return tuple(c for f, a, b in zip(free, by_theta, by_x) for c in (f, a - f, b - f))


def _select(model: Model, results: dict) -> dict:
    """Keep the outputs that exist in ``model``: the bare block has only ``theta``."""
    if model.coordinates == ("theta",):
        keep = {
            "mass_matrix": [0],
            "forcing": [0],
            "rocking_accel": [0],
            "contact_accel": [0],
            "impact": [0],
            "block_accelerations": [0, 1, 3, 4],
            "base_reaction": [0, 1, 3, 4, 6, 7],
            "element_forces": [],
            "slide_accel": [0, 2, 3],
            "contact_slide_accel": [0, 2, 3],
            "impact_stick": [0, 2, 3, 4],
            "impact_slide": [0, 2, 3, 4],
            "flight_accel": [0, 2, 3],
            "landing_stick": [0, 2, 3, 4, 5],
            "landing_slide": [0, 2, 3, 4, 5],
            "flat_landing_stick": [0, 2, 3, 4, 5, 6],
            "flat_landing_slide": [0, 2, 3, 4, 5, 6],
        }
        results = {k: tuple(val[i] for i in keep.get(k, range(len(val)))) for k, val in results.items()}
        if "energy" in results:  # the functions of the paper (not those of a floor with friction alone)
            # Without attached bodies nothing but the ground can lift the block.
            results["uplift_energy"] = (np.full_like(results["energy"][0], np.inf),)
            # Nothing to minimise over: the least potential is the block's own.
            results["least_potential"] = results["least_stroke_potential"]
    return results


def spread(results: Callable[[dict], dict], v: dict, rng: np.random.Generator) -> dict[str, tuple]:
    """How far each output of ``results(v)`` moves when the arguments ``v`` (but the pivot) are rounded the
    other way: its largest change over :data:`ROUNDINGS` draws of a relative ``+-ROUNDOFF`` on every argument
    of every case, by name as ``results`` gives them. ``v`` in extended precision, where that move is exact.
    """
    ref = results(v)
    moved = [
        results({k: a if k == "s" else a * (1 + rng.choice((-ROUNDOFF, ROUNDOFF), a.shape)) for k, a in v.items()})
        for _ in range(ROUNDINGS)
    ]
    return {
        name: tuple(np.max([np.abs(r[name][i] - out) for r in moved], axis=0) for i, out in enumerate(outs))
        for name, outs in ref.items()
    }


def _check_model_kind(model: Model) -> bool:
    """True for the omd model, False for the bare block; other models have no paper equations."""
    if model.coordinates == ("theta", "x"):
        return True
    if model.coordinates == ("theta",):
        return False
    raise ModelError(
        f"model {model.name!r}: the paper has no hand-written equations for coordinates {model.coordinates}"
    )


def check_count(name: str, value: object, valid: Range) -> int:
    """``value`` as an int within ``valid`` (:data:`CASES`, :data:`SEEDS`).

    Parameters
    ----------
    name : str
        What the message calls it: the keyword of :func:`verify`, or the command's flag.
    value : object
        An integer; bool and float are refused.
    valid : Range
        Its valid values.

    Returns
    -------
    int

    Raises
    ------
    ParameterError
        ``"{name} must be an integer in [1, 100000] (got 0): ..."``.
    """
    if not isinstance(value, numbers.Integral) or isinstance(value, (bool, np.bool_)) or int(value) not in valid:
        raise ParameterError(f"{name} must be {valid.rule()} (got {shown(value)}): {valid.why}")
    return int(value)


def verify(
    model: Model,
    n: int = 1000,
    seed: int = 0,
    evaluate: Callable | None = None,
) -> list[Check]:
    """Compare every generated function of ``model`` with :mod:`rocking.reference.paper`.

    Parameters
    ----------
    model : Model
        An ``omd``-like model (coordinates theta, x) or the bare block.
    n : int
        Random cases per pivot, in [1, 100000] (:data:`CASES`).
    seed : int
        Seed of the random cases, >= 0.
    evaluate : callable, optional
        ``evaluate(function_name, values) -> tuple of arrays`` to check another
        implementation of the model (the compiled C); default: the generated NumPy.

    Raises
    ------
    ParameterError
        ``n`` or ``seed`` out of its range, named.
    """
    n, seed = check_count("n", n, CASES), check_count("seed", seed, SEEDS)
    damper = _check_model_kind(model)
    stops = {"L", "k_b"} <= set(model.parameters)
    hunt_crossley = [side["approach_floor"] for side in model.manifest["stops"] if side["law"] == "hunt-crossley"]
    floor = hunt_crossley[0] if hunt_crossley else None
    law = model.manifest["options"]["impact_laws"].get("x", "momentum")
    rng = np.random.default_rng(seed)
    # Their own stream: the cases of the other functions are those of a model without friction.
    paper = np.random.default_rng((seed, 6))
    friction = np.random.default_rng((seed, 15)) if model.manifest.get("friction") else None
    flying = np.random.default_rng((seed, 16)) if model.manifest.get("flight") else None
    if evaluate is None:
        evaluate = lambda name, v: _numpy_eval(model, name, v)
    checks = []
    for s in (1, -1):
        v = random_cases(rng, n, s, damper, stops, bool(hunt_crossley))
        if friction is not None:
            v.update(friction_inputs(friction, n))
        if flying is not None:
            v.update(flight_inputs(flying, n))
        zero = np.zeros(n)
        cases = {
            "rocking": v,
            "contact": dict(v, theta=zero, dtheta=zero),
            "impact": dict(v, theta=zero),
        }
        # The hand-written reference runs in extended precision, so that the
        # error measured is the generated code's.
        exact = {kind: {k: a.astype(np.longdouble) for k, a in vals.items()} for kind, vals in cases.items()}
        refs = {kind: _select(model, _paper_results(vals, law, floor)) for kind, vals in exact.items()}
        # The slide phases divide by the slope of the floor's balance, which vanishes where sliding is singular
        # (Painlevé), and stiff bumpers load them with forces that cancel: compared at the size of their terms.
        # The paper's functions too (the impact's momenta cancel: omd impact at pivot A' 1.02e-12 of its value, 20000
        # cases, seed 0), the roundings from their own stream so that every other case and rounding stays.
        spreads: dict[str, dict] = {
            kind: spread(lambda w: _select(model, _paper_results(w, law, floor)), vals, paper)
            for kind, vals in exact.items()
        }
        if friction is not None:
            for kind, vals in exact.items():
                # Without flight's arguments: rounding them too would draw more from the stream, and move the cases.
                alone = {k: a for k, a in vals.items() if k not in FLIGHT_INPUTS}
                spreads[kind].update(spread(lambda w: _select(model, _friction_results(w, floor)), alone, friction))
                refs[kind].update(_select(model, _friction_results(vals, floor)))
        if flying is not None:
            # Stiff bumpers load flight_accel with forces that cancel, as they do the slide phases (2.6e-12 of it
            # otherwise, omd_stops, 20000 cases, seed 2): flight's functions are compared at the size of their
            # terms too, the roundings drawn from flight's own stream.
            flown = lambda w: _select(model, _flight_results(w, damper, floor))  # noqa: E731
            spreads["rocking"].update(spread(flown, exact["rocking"], flying))
            refs["rocking"].update(flown(exact["rocking"]))
        for name in refs["rocking"]:
            kind = _STATE_OF.get(name, "rocking")
            got = evaluate(name, cases[kind])
            got = got if isinstance(got, tuple) else (got,)
            moves = spreads[kind].get(name, (None,) * len(got))
            err = max((rel_error(a, b, d) for a, b, d in zip(got, refs[kind][name], moves, strict=True)), default=0.0)
            checks.append(Check(name, s, n, err))
    return checks


def _numpy_eval(model: Model, name: str, v: dict):
    fn = getattr(model.functions, name)
    inputs = model.manifest["functions"][name]["inputs"]  # a floor with friction's mu_slip, du
    return fn(
        v["s"],
        *(v[k] for k in model.state),
        v["ag"],
        v["agy"],
        *(v[k] for k in model.parameters),
        *(v[k] for k in inputs),
    )


def report(model: Model, checks: list[Check]) -> str:
    """A short human-readable report."""
    lines = [f"model {model.name}: generated code against the hand-written equations of docs/model.md"]
    width = max((len(c.function) for c in checks), default=0)
    for c in checks:
        pivot = "A " if c.pivot == 1 else "A'"
        status = "ok" if c.ok else "MISMATCH"
        error = f"max rel. error {c.max_rel_error:9.2e}"
        lines.append(f"  {c.function:<{width}} pivot {pivot}  {c.cases:>6} cases  {error}  {status}")
    bad = sum(not c.ok for c in checks)
    lines.append(f"{len(checks) - bad} passed, {bad} failed (tolerance {TOLERANCE:g})")
    return "\n".join(lines)
