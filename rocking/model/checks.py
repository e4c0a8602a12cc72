"""The valid values of every input, declared once, and the checks that refuse anything else.

:data:`RANGES` holds the range of each input of the public API and of each setting of a run
(:data:`rocking.sim.boundary.CASE` names its entries), with the reason for its bounds; the
checks turn a value outside into a :class:`ParameterError` in one line naming the parameter,
its range and the offending value. A leaf module: it imports nothing of ``rocking``, so that
the model, the simulator and the studies read the same table.

Units SI.
"""

from __future__ import annotations

import math
import numbers
import sys
from dataclasses import dataclass, replace

import numpy as np

__all__ = [
    "RANGES",
    "TWO_PI",
    "ParameterError",
    "Range",
    "as_real",
    "check_in_range",
    "check_interval",
    "check_nonnegative",
    "check_positive",
    "check_real",
    "check_scaled",
    "shown",
]


class ParameterError(ValueError):
    """A model parameter is missing, non-numeric, non-finite or out of range."""


def _with_unit(text: str, unit: str) -> str:
    return f"{text} {unit}" if unit else text


#: Longest ``repr`` of a refused value that a message quotes (a string or an array may be any length).
SHOWN_CHARS = 60


def shown(value: object) -> str:
    """``value`` as a message quotes it: one line, at most :data:`SHOWN_CHARS` characters.

    An integer beyond the doubles is shown by its magnitude (``1e+400``): its ``repr`` has
    hundreds of digits, and Python refuses to print one of more than 4300.
    """
    if isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_)) and abs(int(value)) > _LARGEST:
        magnitude = abs(int(value))
        exponent = math.floor(math.log10(magnitude))  # log10 takes any int; float() overflows
        return f"{'-' if value < 0 else ''}{10 ** (math.log10(magnitude) - exponent):.6g}e+{exponent}"
    text = " ".join(repr(value).split())  # an array's repr spans lines
    return text if len(text) <= SHOWN_CHARS else text[: SHOWN_CHARS - 3] + "..."


_LARGEST = sys.float_info.max


def as_real(name: str, value: object, expected: str = "") -> float:
    """``value`` as a float if it is a real number, ``+-inf`` beyond the doubles; any other value refused.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        Python or NumPy real scalar (``int``, ``float``, ``numpy.float64``, ``fractions.Fraction``, ...).
    expected : str, optional
        The valid values, appended to the message (``"in [0.001, 1000] m: why"``).

    Returns
    -------
    float
        Possibly nan or infinite: the caller's range check refuses those with its own message.

    Raises
    ------
    ParameterError
        ``value`` is not a real number: a bool, str, None, complex, an array, ...
    """
    # bool is an Integral, but True as a length is almost surely a caller's mistake. A float is the common case,
    # checked first: the ABC check costs a microsecond.
    if type(value) is not float and (not isinstance(value, numbers.Real) or isinstance(value, (bool, np.bool_))):
        raise ParameterError(f"{name} must be a real number (got {shown(value)}){', ' + expected if expected else ''}")
    try:
        return float(value)
    except OverflowError:  # an int or a Fraction beyond the doubles: out of every range
        return -math.inf if value < 0 else math.inf


def _finite_or_refuse(name: str, value: object, x: float, expected: str = "") -> float:
    """``x`` if finite; a nan or infinite ``value`` (a huge int counts) refused, with ``expected`` after it."""
    if not math.isfinite(x):
        raise ParameterError(f"{name} must be finite (got {shown(value)}){', ' + expected if expected else ''}")
    return x


def check_real(name: str, value: object) -> float:
    """Return ``value`` as a finite float.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        Python or NumPy real scalar (``int``, ``float``, ``numpy.float64``, ...).

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        If ``value`` is not a real number (booleans included), is nan or infinite, or is an
        integer beyond the doubles.
    """
    return _finite_or_refuse(name, value, as_real(name, value))


def check_positive(name: str, value: object, unit: str = "") -> float:
    """Return ``value`` as a finite float, requiring ``value > 0``.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        Real scalar to check.
    unit : str, optional
        SI unit shown in the error message.

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        If ``value`` is not a finite real number or is not strictly positive.
    """
    expected = f"> {_with_unit('0', unit)}"
    x = _finite_or_refuse(name, value, as_real(name, value, expected), expected)
    if not x > 0.0:
        raise ParameterError(f"{name} must be > {_with_unit('0', unit)} (got {x!r})")
    return x


def check_nonnegative(name: str, value: object, unit: str = "") -> float:
    """Return ``value`` as a finite float, requiring ``value >= 0``.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        Real scalar to check.
    unit : str, optional
        SI unit shown in the error message.

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        If ``value`` is not a finite real number or is negative.
    """
    expected = f">= {_with_unit('0', unit)}"
    x = _finite_or_refuse(name, value, as_real(name, value, expected), expected)
    if x < 0.0:
        raise ParameterError(f"{name} must be >= {_with_unit('0', unit)} (got {x!r})")
    return x


def check_interval(
    name: str,
    value: object,
    low: float,
    high: float,
    unit: str = "",
    *,
    closed_low: bool = False,
    label: str | None = None,
) -> float:
    """Return ``value`` as a finite float, requiring ``low < value < high``.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        Real scalar to check.
    low, high : float
        Interval bounds; ``high`` is always excluded.
    unit : str, optional
        SI unit shown in the error message.
    closed_low : bool, optional
        Include ``low`` in the interval, i.e. ``[low, high)``.
    label : str, optional
        Symbolic form of the interval (e.g. ``"(-B/2, B/2)"``), shown before the
        numeric bounds so that the message explains where the numbers come from.

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        If ``value`` is not a finite real number or lies outside the interval.
    """
    numeric = f"{'[' if closed_low else '('}{low:g}, {high:g})"
    expected = "in " + _with_unit(f"{label} = {numeric}" if label else numeric, unit)
    x = _finite_or_refuse(name, value, as_real(name, value, expected), expected)
    above_low = x >= low if closed_low else x > low
    if not (above_low and x < high):
        raise ParameterError(f"{name} must be {expected} (got {x!r})")
    return x


@dataclass(frozen=True)
class Range:
    """The valid values of one input: a closed interval (0 may be allowed besides), and why.

    Attributes
    ----------
    low, high : float
        Bounds, both included unless ``open_low`` / ``open_high``.
    unit : str
        SI unit shown in messages.
    why : str
        The reason for the bounds, appended to every message.
    open_low, open_high : bool
        Exclude the bound.
    zero : bool
        ``0`` is valid too (``m = 0``: no damper).
    integer : bool
        Only whole numbers (a count).
    infinite : bool
        ``+inf`` is valid too, as the upper bound (a floor's friction: ``inf`` never lets the base slide).

    Notes
    -----
    A bound may be infinite (the side is unbounded); the values are finite numbers still, unless ``infinite``.
    """

    low: float
    high: float
    unit: str = ""
    why: str = ""
    open_low: bool = False
    open_high: bool = False
    zero: bool = False
    integer: bool = False
    infinite: bool = False

    def holds(self, x):
        """Elementwise: ``x`` lies in the range (NaN never does)."""
        if type(x) is float or type(x) is int:  # one number: no NumPy (a NumPy scalar's inf - inf warns)
            return self._holds(x)
        x = np.asarray(x, dtype=float)
        with np.errstate(invalid="ignore"):
            return self._holds(x)

    def _holds(self, x):
        above = x > self.low if self.open_low else x >= self.low
        below = x < self.high if self.open_high else x <= self.high
        inside = above & below & (x - x == 0)  # inf lies within an unbounded side, yet is no number
        if self.infinite:
            inside = inside | (x == math.inf)
        if self.integer:
            inside = inside & (x % 1 == 0)
        return inside | (x == 0.0) if self.zero else inside

    def __contains__(self, x: float) -> bool:
        return bool(self.holds(x))

    def text(self, label: str | None = None) -> str:
        """``"in [0.001, 1000] m"`` (``label``, a symbolic form of the bounds, before the numbers)."""
        opening = "(" if self.open_low or math.isinf(self.low) else "["
        closing = "]" if self.infinite else ")" if self.open_high or math.isinf(self.high) else "]"
        numeric = f"{opening}{self.low:g}, {self.high:g}{closing}"
        interval = f"{label} = {numeric}" if label else numeric
        return ("0 or in " if self.zero else "in ") + _with_unit(interval, self.unit)

    def rule(self) -> str:
        """The range as the check of a run's setting states it, without its reason.

        ``"finite"``, ``"finite and > 0"``, ``"an integer >= 1"`` for a range without an upper
        bound (whose unit the message does not need), else ``"in [1e-12, 0.01]"``,
        ``"an integer in [1, 1e+08]"``.
        """
        if math.isinf(self.high) and not self.infinite:
            if math.isinf(self.low):
                return "an integer" if self.integer else "finite"
            relation = f"{'>' if self.open_low else '>='} {self.low:g}"
            return f"an integer {relation}" if self.integer else f"finite and {relation}"
        return f"an integer {self.text()}" if self.integer else self.text()


TWO_PI = 2 * math.pi

#: The valid range of every input of the public API, declared once; the messages come from here.
#: Users are engineers checking cabinets, transformers, statues, machines and laboratory
#: specimens under ground-motion pulses of 0.1 - 10 s: every bound lies orders of magnitude
#: beyond them, and excludes what is degenerate in double precision (subnormal masses,
#: overflowing stiffnesses) or cannot be integrated within a bounded work (a rate of the
#: system far above the block's, a run of unbounded length).
RANGES: dict[str, Range] = {
    # --- the block (Block, Block.from_nondim)
    "H": Range(1e-3, 1e3, "m", "from a 1 mm laboratory specimen to a 1 km structure"),
    "B": Range(1e-3, 1e3, "m", "from a 1 mm laboratory specimen to a 1 km structure"),
    # Beyond, alpha or pi/2 - alpha nears the rounding of the tolerances scaled by alpha.
    "lam": Range(1e-2, 1e2, "", "slenderness H/B from a flat slab (0.01) to a mast (100)"),
    "alpha": Range(math.atan(1e-2), math.atan(1e2), "rad", "slenderness H/B in [0.01, 100]"),
    # Energies and the rest threshold M g B stay normal doubles.
    "M": Range(1e-6, 1e12, "kg", "from a 1 mg specimen to a 1 Gt structure"),
    # No mass inside the block's rectangle lies farther than 2 R from G: I_G <= M (2 R)^2.
    "I_G": Range(0.0, 4.0, "", "a radius of gyration above 2 R (I_G > 4 M R^2) puts mass outside the block", True),
    "g": Range(0.1, 1e4, "m/s^2", "from small planetary bodies to a geotechnical centrifuge at 1000 g"),
    # p = sqrt(3 g / (4 R)) of the blocks above spans [0.01, 3300] rad/s.
    "p": Range(1e-2, 1e4, "rad/s", "the frequency parameter of blocks of 1 mm to 1 km under 0.1 to 1e4 m/s^2"),
    "e_ratio": Range(-0.5, 0.5, "", "the centroid lies inside the base", True, True),
    # --- the damper (Damper: absolute bounds; relative to its block: gamma, omega_ratio, zeta)
    # Absolute bounds only keep k_m / m and c / m normal doubles; the physics is checked against the block.
    "m": Range(1e-16, 1e13, "kg", "a subnormal or astronomical mass makes k_m / m degenerate", zero=True),
    "k_m": Range(0.0, 1e30, "N/m", "the stiffness must keep k_m / m a normal double"),
    "c": Range(0.0, 1e30, "N s/m", "the dashpot must keep c / m a normal double"),
    "h": Range(0.0, 1e3, "m", "a guide at most 1 km above the block, as the block's own dimensions"),
    # Tuned mass dampers use 0.01 - 0.2; 1e-10 keeps a vanishing damper (the bare block as a limit)
    # well above rounding, 10 a damper ten times the block's mass.
    "gamma": Range(1e-10, 10.0, "", "mass ratio m/M; 0 is the bare block", zero=True),
    # A damper tuned 1000 times below p is a free mass within any run; 1e4 p is a locked damper (the
    # rigid limit the tests converge to, at about 1100 p); beyond, a run needs ~1e5 integrator steps
    # per second of motion, past any bound on its work (the studies: 0.1 - 10).
    "omega_ratio": Range(1e-3, 1e4, "", "damper frequency omega_m / p between a free mass and a locked damper"),
    # Dampers use 0 - 0.3, viscous devices a few; beyond 10 the dashpot's rate 2 zeta omega_m is a
    # stiff mode for the explicit integrator (and the mass hardly moves anyway).
    "zeta": Range(0.0, 10.0, "", "damping ratio of the damper, stiff for the explicit integrator above 10"),
    # --- the end stops of the guide (Stops: absolute bounds; on its damper and block, the ratios below)
    "L": Range(0.0, 1e3, "m", "the half-stroke, from the centre line to either bumper", open_low=True),
    "k_b": Range(0.0, 1e30, "N/m", "the stiffness must keep k_b / m a normal double", open_low=True),
    "c_b": Range(0.0, 1e30, "N s/m", "the dashpot must keep c_b / m a normal double"),
    # A contact lasts pi / omega_b: above 1e4 p the steps it needs pass a run's bound on work, as for omega_m.
    "omega_b_ratio": Range(1e-3, 1e4, "", "bumper frequency sqrt(k_b / m) / p, as the damper's (a run's work)"),
    # Hertzian contact is 1.5; beyond 10 delta^n underflows in a pad of a few mm.
    "n_b": Range(1.0, 10.0, "", "exponent of a Hunt-Crossley pad's force k_b delta^n (1: linear, 1.5: Hertzian)"),
    # Above 1 a pad would add energy; towards 0 it keeps the mass, and its damping factor chi_b ~ 1 / e_b makes a
    # contact a stiff mode: a run takes longer as e_b falls (bench/hc_restitution.py: at 1e-3 about 4 times as
    # long as at 0.57 on the NumPy back end), without bound as e_b -> 0.
    "e_b": Range(1e-3, 1.0, "", "restitution of a Hunt-Crossley pad, its damping a stiff mode below 1e-3"),
    # The damping factor chi(e_b) of those pads (Stops.as_params, model omd_stops_hc): 0 at e_b = 1, 1 / e_b to
    # the last bit for e_b <= 1e-2 (1 - chi e_b ~ e^(-1 / e_b)), so [0, 1e3] is the range of e_b.
    "chi_b": Range(0.0, 1e3, "", "damping factor chi(e_b) of a Hunt-Crossley pad, e_b in [1e-3, 1]"),
    # Rubber and elastomer pads restitute 0.3 - 0.7 (zeta_b 0.1 - 0.35); 10 as for the damper's zeta.
    "zeta_b": Range(0.0, 10.0, "", "damping ratio of a bumper, stiff for the explicit integrator above 10"),
    # --- the pulse (OneSinePulse, OneSinePulse.from_nondim)
    "a_g": Range(0.0, 1e5, "m/s^2", "up to 10,000 g, beyond any ground motion, shake table or centrifuge"),
    # Ground-motion pulses last 0.1 - 10 s; 1 ms to 1000 s bounds the pulse's share of a run.
    "omega_g": Range(TWO_PI / 1e3, TWO_PI / 1e-3, "rad/s", "sine periods from 1 ms to 1000 s"),
    "psi": Range(0.0, TWO_PI, "rad", "one sine cycle", open_high=True),
    # Near-fault records reach vertical-to-horizontal ratios of 1 - 2 (Bozorgnia and Campbell 2004).
    "vertical_ratio": Range(0.0, 10.0, "", "vertical amplitude over the horizontal, docs/model.md section 14"),
    "beta": Range(0.0, 1e4, "", "amplitude over the uplift threshold, a_g / (g tan alpha)"),
    "Omega": Range(1e-2, 1e3, "", "pulse frequency over the block's, omega_g / p (the studies: 0.5 - 15)"),
    # --- the other ground motions (rocking.model.motion, docs/model.md section 12)
    "gamma_mp": Range(
        1.0, 20.0, "", "oscillations of the Mavroeidis-Papageorgiou pulse (> 1; records: 1.5 - 3)", open_low=True
    ),
    "pulse_dt": Range(1e-6, 10.0, "s", "the spacing of a sampled motion, from 1 us to 10 s"),
    "record_length": Range(0.0, 1.1e4, "s", "a sampled motion lasts at most three hours"),
    # --- a run (make_problem, simulate, pulse_cases): its length bounds its work
    "t_after": Range(0.0, 1e4, "s", "a run follows the block at most 10^4 s after the pulse", open_low=True),
    # The longest motion is a Mavroeidis-Papageorgiou pulse of 20 cycles (gamma_mp) of 1000 s (omega_g): 2 10^4 s.
    "t_max": Range(0.0, 3e4, "s", "a run lasts at most the longest motion, 2 10^4 s, plus 10^4 s", open_low=True),
    "max_events": Range(1, 1e8, "", "uplifts plus impacts of one run (default 10,000)", integer=True),
    "record_samples": Range(0.0, 1e6, "", "samples of a recorded history, t_max / record_dt"),
    # --- the other settings of a run (rocking.sim.boundary.CASE names an entry for each it checks)
    # 1e-12 is a few thousand roundings of a double: the tighter run of the tolerance check stops there.
    "rtol": Range(1e-12, 1e-2, "", "relative tolerance of the integrator"),
    # --- the floor (rocking.Floor, docs/model.md section 15)
    "mu": Range(
        0.0,
        math.inf,
        "",
        "Coulomb friction of the floor, dimensionless: > 0 (a floor without friction holds no block), inf: the "
        "base never slides (the paper's floor)",
        open_low=True,
        infinite=True,
    ),
    "e_n": Range(0.0, 1.0, "", "normal restitution of a landing: 0 plastic (the default), 1 elastic"),
    "max_steps": Range(1, math.inf, "", "the bound on a run's work (docs/simulation.md, rule 5)", integer=True),
    "real": Range(-math.inf, math.inf, "", "a number: its range is checked where the motion or run is built"),
    "positive": Range(0.0, math.inf, "", "a step or a length of time", open_low=True),
    "nonnegative": Range(0.0, math.inf, "", "a threshold or a spacing, 0 for none"),
    "count": Range(0, math.inf, "", "a number of listed values", integer=True),
}


def check_in_range(
    name: str,
    value: object,
    key: str | None = None,
    *,
    label: str | None = None,
    nonzero: bool = False,
    derived: bool = False,
) -> float:
    """Return ``value`` as a float if it is a real number within ``RANGES[key or name]``.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        Python or NumPy real scalar; booleans and strings are refused.
    key : str, optional
        Entry of :data:`RANGES`, default ``name``.
    label : str, optional
        Symbolic form of the bounds for the message (``"(0, 4 M R^2]"``).
    nonzero : bool, optional
        Refuse 0 even where the range admits it (the studies' damper is never the bare block).
    derived : bool, optional
        ``value`` is computed from other inputs: passing a closed bound by rounding alone is no error
        (:func:`at_bound`).

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        ``"{name} must be in {range} (got {value}): {why}"`` (``0 or in`` where 0 is valid).
    """
    valid = RANGES[key or name]
    return _in_range(name, value, replace(valid, zero=False) if nonzero else valid, label, derived=derived)


#: A value computed from others (``zeta = c / (2 m omega_m)`` of a damper made from ``zeta``) may pass a bound it
#: was made at by this many units in the last place: rounding, not a value outside.
DERIVED_ULPS = 8


def at_bound(x: float, valid: Range) -> float:
    """``x``, or the closed bound of ``valid`` that ``x`` passes by at most :data:`DERIVED_ULPS` (rounding)."""
    for bound, is_open in ((valid.low, valid.open_low), (valid.high, valid.open_high)):
        if not is_open and math.isfinite(bound) and abs(x - bound) <= DERIVED_ULPS * math.ulp(bound):
            return bound
    return x


def _in_range(
    name: str, value: object, valid: Range, label: str | None = None, scale: float = 1.0, unit=None, derived=False
) -> float:
    """``value`` as a float if it is a real number and ``value / scale`` lies in ``valid``; if ``derived`` (a
    value computed from others), also one that passes a closed bound by rounding alone (:func:`at_bound`).

    Every message names the range with the bounds times ``scale`` (in ``unit``) and its reason:
    a value that is no real number, a nan or infinite one, and one outside (an integer beyond the
    doubles is outside every range).
    """
    unit = valid.unit if unit is None else unit
    bounds = (
        valid
        if scale == 1.0 and unit == valid.unit
        else replace(valid, low=valid.low * scale, high=valid.high * scale, unit=unit)
    )
    expected = f"{bounds.text(label)}: {bounds.why}"
    x = as_real(name, value, expected)
    if not math.isfinite(x) and not isinstance(value, numbers.Rational):  # nan or inf itself, not a huge int
        raise ParameterError(f"{name} must be finite (got {shown(value)}), {expected}")
    if (at_bound(x / scale, valid) if derived else x / scale) not in valid:
        got = repr(x) if math.isfinite(x) else shown(value)  # the float it was read as; a huge int by magnitude
        raise ParameterError(f"{name} must be {bounds.text(label)} (got {got}): {bounds.why}")
    return x


def check_scaled(name: str, value: object, key: str, scale: float, label: str, unit: str | None = None) -> float:
    """Return ``value`` as a float if ``value / scale`` lies in ``RANGES[key]`` (a range relative to the block),
    or passes a closed bound by rounding alone (:func:`at_bound`: ``m = gamma M`` made at ``gamma = 10``).

    The message gives the bounds times ``scale`` (in ``unit``, default the range's), after
    ``label`` (``"[1e-10 M, 10 M]"``).
    """
    return _in_range(name, value, RANGES[key], label, scale, unit, derived=True)
