"""Physical parameters of the rocking block and of the oscillating mass damper.

Notation follows ``docs/model.md`` (sections 1 and 9). All quantities are in SI units:
lengths in m, masses in kg, moments of inertia in kg m^2, times in s, angles in rad,
accelerations in m/s^2, stiffnesses in N/m and damping coefficients in N s/m.

Both parameter sets are frozen dataclasses that validate and convert their inputs to
``float`` on construction, so an invalid model can never reach the simulator. Every
validation failure raises :class:`ParameterError`, whose message names the parameter,
the valid range and the offending value; the ranges and the checks are those of
:mod:`rocking.model.checks`, re-exported here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import cached_property
from typing import cast, overload

import numpy as np

from .checks import (
    RANGES,
    TWO_PI,
    ParameterError,
    Range,
    _in_range,
    as_real,
    check_in_range,
    check_interval,
    check_nonnegative,
    check_positive,
    check_real,
    check_scaled,
    shown,
)

__all__ = [
    "RANGES",
    "Block",
    "Damper",
    "ParameterError",
    "Range",
    "as_real",
    "check_in_range",
    "check_interval",
    "check_nonnegative",
    "check_positive",
    "check_real",
    "shown",
]


def check_block(block: object, name: str = "block") -> Block:
    """``block`` if it is a :class:`Block`, else a :class:`ParameterError` naming ``name``."""
    if not isinstance(block, Block):
        raise ParameterError(f"{name} must be a rocking.Block (got {type(block).__name__})")
    return block


#: Significant digits of the floats of a repr: enough for any input typed, few enough to hide the last bit of a
#: sum (``B/2 - depth`` is 0.27999999999999997 for B = 0.6 m and 20 mm pads).
REPR_DIGITS = 12


def rounded_repr(obj) -> str:
    """``Name(field=value, ...)`` of a dataclass, as its generated repr but for floats, each the repr of its value
    rounded to :data:`REPR_DIGITS` significant digits (``L=0.28``, not ``L=0.27999999999999997``): what a user reads,
    not a bit-exact copy (``as_params()`` holds the exact values)."""
    values = (getattr(obj, f.name) for f in fields(obj) if f.repr)
    shown = (repr(float(f"{v:.{REPR_DIGITS}g}")) if isinstance(v, float) else repr(v) for v in values)
    names = (f.name for f in fields(obj) if f.repr)
    return f"{type(obj).__name__}({', '.join(f'{n}={v}' for n, v in zip(names, shown))})"


def _require_one(name_a: str, a: object, name_b: str, b: object) -> None:
    if (a is None) == (b is None):
        raise ParameterError(f"give exactly one of {name_a} or {name_b} (got {name_a}={shown(a)}, {name_b}={shown(b)})")


@dataclass(frozen=True)
class Block:
    """Rigid rectangular block rocking on its base corners (``docs/model.md`` section 1).

    Parameters
    ----------
    H : float
        Height of the block, m, in [1e-3, 1e3] (a 1 mm specimen to a 1 km structure).
    B : float
        Width of the base, m, in [1e-3, 1e3]; the slenderness ``H / B`` must lie in
        [0.01, 100] (a flat slab to a mast).
    M : float
        Mass of the block, kg, in [1e-6, 1e12].
    e : float, optional
        Horizontal eccentricity of the centroid ``G`` from the geometric centre, m;
        ``e > 0`` moves ``G`` towards the right corner ``A'``. Requires
        ``|e| < B/2``. Default 0.
    I_G : float or None, optional
        Centroidal moment of inertia, kg m^2, in ``(0, 4 M R^2]`` (no mass of the
        block lies farther than ``2 R`` from ``G``). ``None`` (default) stores the
        homogeneous value ``M (B^2 + H^2) / 12``.
    g : float, optional
        Gravitational acceleration, m/s^2, in [0.1, 1e4] (small planetary bodies to
        a centrifuge at 1000 g). Default 9.81.

    Raises
    ------
    ParameterError
        If any parameter is non-numeric, non-finite or out of range (the message
        names it, gives its range and the reason for the range).

    Notes
    -----
    Every range is an entry of :data:`RANGES`; bool and str are not numbers.
    """

    H: float
    B: float
    M: float
    e: float = 0.0
    I_G: float | None = None
    g: float = 9.81

    __repr__ = rounded_repr

    def __post_init__(self) -> None:
        H = check_in_range("H", self.H)
        B = check_in_range("B", self.B)
        _in_range("H / B", H / B, RANGES["lam"])
        M = check_in_range("M", self.M)
        e = check_interval("e", self.e, -B / 2, B / 2, "m", label="(-B/2, B/2)")
        R2 = (B**2 + H**2) / 4
        I_G = M * (B**2 + H**2) / 12 if self.I_G is None else self.I_G
        I_G = check_scaled("I_G", I_G, "I_G", M * R2, "(0, 4 M R^2]", "kg m^2")
        g = check_in_range("g", self.g)
        # Frozen dataclass: the normalised floats can only be stored this way.
        for field, value in (
            ("H", H),
            ("B", B),
            ("M", M),
            ("e", e),
            ("I_G", I_G),
            ("g", g),
        ):
            object.__setattr__(self, field, value)

    @property
    def lam(self) -> float:
        """Slenderness ``lambda = H / B``."""
        return self.H / self.B

    # Cached: the fields of a frozen block never change, and one simulate call reads alpha and p a dozen times.
    @cached_property
    def alpha(self) -> float:
        """Slenderness angle ``alpha = atan(B / H)``, rad."""
        return math.atan2(self.B, self.H)

    @property
    def tan_alpha(self) -> float:
        """``tan(alpha) = B / H``, the static uplift acceleration of the bare symmetric
        block in units of ``g``."""
        return self.B / self.H

    @overload
    def a_g(self, beta: float) -> float: ...
    @overload
    def a_g(self, beta: np.ndarray) -> np.ndarray: ...
    def a_g(self, beta):
        """The pulse amplitude ``a_g = beta g tan(alpha)``, m/s^2, of the amplitude ratio(s) ``beta``
        (docs/model.md section 9): the one place this scaling is written."""
        return beta * self.g * self.tan_alpha

    @overload
    def beta(self, a_g: float) -> float: ...
    @overload
    def beta(self, a_g: np.ndarray) -> np.ndarray: ...
    def beta(self, a_g):
        """The amplitude ratio ``beta = a_g / (g tan(alpha))`` of the amplitude(s) ``a_g`` (m/s^2): the
        inverse of :meth:`a_g`."""
        return a_g / (self.g * self.tan_alpha)

    @cached_property
    def R(self) -> float:
        """Half-diagonal ``R = sqrt(B^2 + H^2) / 2``, m."""
        return math.hypot(self.B, self.H) / 2

    @cached_property
    def I_O(self) -> float:
        """``I_O = I_G + M R^2``, kg m^2.

        This is the inertia about a base corner of the symmetric block; for ``e != 0``
        it is kept as the reference inertia of the non-dimensional presentation, not
        the pivot inertia ``I_s`` of the equations of motion.
        """
        assert self.I_G is not None  # __post_init__ stores the homogeneous value in place of None
        return self.I_G + self.M * self.R**2

    @cached_property
    def p(self) -> float:
        """Frequency parameter ``p = sqrt(M g R / I_O)``, rad/s.

        Equals ``sqrt(3 g / (4 R))`` for the homogeneous block.
        """
        return math.sqrt(self.M * self.g * self.R / self.I_O)

    def as_params(self) -> dict[str, float]:
        """Return the block parameters under the symbol names of the derivation.

        Returns
        -------
        dict
            Keys ``"M"``, ``"I_G"``, ``"B"``, ``"H"``, ``"e"``, ``"g"``.
        """
        assert self.I_G is not None  # __post_init__ stores the homogeneous value in place of None
        return {
            "M": self.M,
            "I_G": self.I_G,
            "B": self.B,
            "H": self.H,
            "e": self.e,
            "g": self.g,
        }

    @classmethod
    def from_nondim(
        cls,
        *,
        p: float,
        lam: float | None = None,
        alpha: float | None = None,
        M: float = 1.0,
        e_ratio: float = 0.0,
        g: float = 9.81,
    ) -> Block:
        """Build a homogeneous block from its non-dimensional description.

        Parameters
        ----------
        p : float
            Frequency parameter, rad/s, in [0.01, 1e4]; with ``g`` it must give
            dimensions within the ranges of :class:`Block`.
        lam : float, optional
            Slenderness ``H / B``, in [0.01, 100]. Give exactly one of ``lam`` and ``alpha``.
        alpha : float, optional
            Slenderness angle ``atan(B / H)``, rad, in [atan(0.01), atan(100)].
        M : float, optional
            Mass, kg, in [1e-6, 1e12]. Default 1.
        e_ratio : float, optional
            Eccentricity as a fraction of the base, ``e / B``, in ``(-0.5, 0.5)``.
            Default 0.
        g : float, optional
            Gravitational acceleration, m/s^2, in [0.1, 1e4]. Default 9.81.

        Returns
        -------
        Block
            Block with ``R = 3 g / (4 p^2)``, ``H = 2 R cos(alpha)``,
            ``B = 2 R sin(alpha)``, ``e = e_ratio B`` and homogeneous ``I_G``.

        Raises
        ------
        ParameterError
            If both or neither of ``lam`` and ``alpha`` are given, or any value is
            out of range.
        """
        _require_one("lam", lam, "alpha", alpha)
        p = check_in_range("p", p)
        g = check_in_range("g", g)
        if lam is not None:
            alpha = math.atan2(1.0, check_in_range("lam", lam))
        else:
            alpha = check_in_range("alpha", alpha, label="[atan(0.01), atan(100)]")
        e_ratio = check_in_range("e_ratio", e_ratio)
        R = 3 * g / (4 * p**2)
        B = 2 * R * math.sin(alpha)
        try:
            return cls(H=2 * R * math.cos(alpha), B=B, M=M, e=e_ratio * B, g=g)
        except ParameterError as exc:
            if str(exc).startswith(("H ", "B ")):  # the dimensions p and g give, not inputs: say so
                raise ParameterError(
                    f"p = {p!r} rad/s with g = {g!r} m/s^2 gives R = 3 g / (4 p^2) = {R:g} m: {exc}"
                ) from None
            raise

    @classmethod
    def reference(cls) -> Block:
        """Return the project's reference block (``docs/model.md`` section 9).

        ``H = 2.0 m``, ``B = 0.5 m`` (``lambda = 4``), ``e = 0.025 m``,
        ``M = 1000 kg``, homogeneous ``I_G``. The reference damper height
        ``h = 0.05 m`` belongs to :class:`Damper`.
        """
        return cls(H=2.0, B=0.5, M=1000.0, e=0.025)


#: The parameters of the paper's damper (model ``omd``) and of its end stops (model ``omd_stops``), by name.
DAMPER_PARAMETERS = ("m", "k_m", "c", "h")
STOP_PARAMETERS = ("L", "k_b", "c_b")
#: The parameters of Hunt-Crossley end stops (model ``omd_stops_hc``), by name: the model takes the pads' damping
#: factor ``chi_b``, :class:`Stops` their restitution ``e_b`` (:func:`hunt_crossley_damping`).
HC_STOP_PARAMETERS = ("L", "k_b", "n_b", "chi_b")
#: The contact laws of a bumper pad (docs/model.md section 11) and the model each runs on.
BUMPER_LAWS = {"kelvin-voigt": "omd_stops", "hunt-crossley": "omd_stops_hc"}

#: The default bumper pad at each of the block's edges (Stops.at_edges): a neoprene pad 20 mm thick (its depth,
#: m) of 50 x 50 mm (its area, m^2) in compression, of modulus 5 MPa (Pa): an estimate of the compression modulus
#: ``E0 (1 + 2 phi S^2)`` of a bonded block (Gent, Engineering with Rubber, 3rd ed. 2012; ``phi`` ~ 0.6) of a
#: Shore A 50-60 neoprene (``E0 = 3 G``, ``G`` ~ 0.9-1.3 MPa) of shape factor ``S = 2500 / (4 x 50 x 20) = 0.625``:
#: 4-6 MPa (docs/model.md section 11, "In the runtime").
BUMPER_DEPTH = 0.02
BUMPER_AREA = 2.5e-3
BUMPER_MODULUS = 5e6
#: Its stiffness, N/m: ``E A / t`` = 6.25e5 N/m, the same for every damper (a stiffness of the pad, not of the
#: damper's spring): a 50 kg mass hitting it at 1 m/s crushes it by ``v sqrt(m / k_b)`` = 9 mm of its 20 mm.
#: Rounded to the N/m: 625000, not the 625000.0000000001 of the floating-point product.
BUMPER_STIFFNESS = float(round(BUMPER_MODULUS * BUMPER_AREA / BUMPER_DEPTH))
#: The penetration at which a Hunt-Crossley pad's frequency is held to the range of a bumper's, m: 1 mm,
#: where its tangent stiffness is n k_b delta^(n-1) (Stops.check_on).
HC_REFERENCE_PENETRATION = 1e-3
#: Default bumper damping ratio: a restitution of 0.57 for a pad that only pushes (docs/model.md section 11;
#: exp(-0.2 pi / sqrt(0.96)) = 0.53 if it could pull), a rubber pad's.
BUMPER_DAMPING_RATIO = 0.2


def kelvin_voigt_restitution(zeta_b: float) -> float:
    """The restitution of one impact of a mass on a Kelvin-Voigt pad that only pushes, of damping ratio ``zeta_b``
    in ``[0, 1)`` (docs/model.md section 11): the pad lets go where ``k_b delta + c_b ddelta`` falls to 0, at
    ``omega_d t_r = pi - atan2(2 zeta_b sqrt(1 - zeta_b^2), 1 - 2 zeta_b^2)``, and the mass leaves at
    ``exp(-zeta_b omega_n t_r) (zeta_b / sqrt(1 - zeta_b^2) sin(omega_d t_r) - cos(omega_d t_r))`` of its
    approach speed (a pad that could pull would give ``exp(-zeta_b pi / sqrt(1 - zeta_b^2))``)."""
    root = math.sqrt(1.0 - zeta_b**2)
    phase = math.pi - math.atan2(2.0 * zeta_b * root, 1.0 - 2.0 * zeta_b**2)  # omega_d t_r
    return math.exp(-zeta_b * phase / root) * (zeta_b / root * math.sin(phase) - math.cos(phase))


#: Default restitution of a Hunt-Crossley pad (Stops.at_edges): that of the Kelvin-Voigt default pad, 0.5717, so
#: that the two laws' default pads restitute alike (bench/stops_laws.py).
BUMPER_RESTITUTION = kelvin_voigt_restitution(BUMPER_DAMPING_RATIO)


#: Terms of the series of :func:`_restitution_gap` below ``chi`` = 0.05: the 24th is below 1e-29 of the first.
_GAP_SERIES_TERMS = 24


def _alternating_gap(e: float, k: int) -> float:
    """``(-1)^k - e^k``; for even ``k`` as ``(1 - e) (1 + e + ... + e^(k-1))``, exact as ``e -> 1``."""
    return (1.0 - e) * math.fsum(e**j for j in range(k)) if k % 2 == 0 else -1.0 - e**k


def _restitution_gap(chi: float, e: float) -> float:
    """``(chi (1 + e) - ln((1 + chi) / (1 - chi e))) / chi^2``: > 0 where a Hunt-Crossley pad of damping factor
    ``chi`` restitutes more than ``e``, < 0 where less, 0 where exactly ``e`` (docs/model.md section 11).

    One impact of a mass on the pad, ``m ddelta = -k delta^n (1 + chi ddelta / v0)``, in ``w = ddelta / v0`` and
    ``s ~ delta^(n+1) / (n+1)`` is ``w dw/ds = -(1 + chi w)`` whatever ``n``, ``m``, ``k``, ``v0``; the
    restitution is the ``e`` at which the rebound (``w`` from 0 to ``-e``) spans the same ``s`` as the
    compression (``w`` from 1 to 0): the root of this gap. Divided by
    ``chi^2`` it keeps its sign as ``chi -> 0`` (the root ``chi = 0`` of the numerator is no pad's); below
    ``chi = 0.05`` it is summed as its series ``sum_k>=2 chi^(k-2) ((-1)^k - e^k) / k``, which the direct form
    would lose to cancellation (and so would ``1 - e^2`` computed as it reads, as ``e -> 1``).
    """
    if chi < 0.05:
        return math.fsum(chi ** (k - 2) * _alternating_gap(e, k) / k for k in range(2, 2 + _GAP_SERIES_TERMS))
    if chi * e >= 1.0:  # the pad would let go before the mass leaves at e: it restitutes less
        return -math.inf
    return (chi * (1.0 + e) - math.log1p(chi) + math.log1p(-chi * e)) / chi**2


def _bisect(gap, a: float, b: float) -> float:
    """The point between ``a`` (``gap > 0``) and ``b`` (``gap <= 0``) where ``gap`` changes sign, to the last bit."""
    while min(a, b) < (mid := 0.5 * (a + b)) < max(a, b):
        a, b = (mid, b) if gap(mid) > 0 else (a, mid)
    return b


def hunt_crossley_damping(e_b: float) -> float:
    """The damping factor ``chi_b`` of a Hunt-Crossley pad whose single-impact restitution is ``e_b``.

    The pad's force ``k_b delta^n (1 + chi_b ddelta / v_in)`` returns a mass that strikes it at ``v_in``
    with the speed ``e_b v_in``, where ``chi_b`` is the root in ``(0, 1 / e_b)`` of

        chi_b (1 + e_b) = ln((1 + chi_b) / (1 - chi_b e_b))

    (docs/model.md section 11; the same for every ``n``, ``k_b``, mass and ``v_in``). It has no closed
    form: found by bisection, to the last bit. ``e_b = 1`` gives 0; ``chi_b`` grows as ``1 / e_b`` as
    ``e_b -> 0``. (Lankarani & Nikravesh's ``3 (1 - e_b) / 2`` is its first order in ``1 - e_b``.)

    Parameters
    ----------
    e_b : float
        The pad's coefficient of restitution, in ``RANGES["e_b"]``.

    Returns
    -------
    float
        ``chi_b >= 0``.

    Raises
    ------
    ParameterError
        If ``e_b`` is not a real number in its range.
    """
    e_b = check_in_range("e_b", e_b)
    if e_b == 1.0:
        return 0.0
    return _bisect(lambda chi: _restitution_gap(chi, e_b), 0.0, 1.0 / e_b)


def hunt_crossley_restitution(chi_b: float) -> float:
    """The single-impact restitution of a Hunt-Crossley pad of damping factor ``chi_b``: the inverse of
    :func:`hunt_crossley_damping`, the root ``e`` in ``(0, min(1, 1 / chi_b))`` of the same equation.

    Parameters
    ----------
    chi_b : float
        The damping factor, in ``RANGES["chi_b"]``.

    Returns
    -------
    float
        The restitution, in ``(0, 1]`` (1 for ``chi_b = 0``).

    Raises
    ------
    ParameterError
        If ``chi_b`` is not a real number in its range.
    """
    chi_b = check_in_range("chi_b", chi_b)
    if chi_b == 0.0:
        return 1.0
    return _bisect(lambda e: _restitution_gap(chi_b, e), 0.0, min(1.0, 1.0 / chi_b))


@dataclass(frozen=True)
class Stops:
    """End stops of the damper's guide: a compliant bumper at ``x = +L`` and at ``x = -L`` (docs/model.md section 11).

    Beyond the gap each bumper is a linear spring ``k_b`` and dashpot ``c_b`` on the
    penetration ``delta = |x| - L`` that only pushes: its force is
    ``max(0, k_b delta + c_b ddelta)``, a compression-only Kelvin-Voigt contact (an unbonded
    pad cannot pull the mass back on rebound; it lets go where the bracket falls to 0). A
    damper with stops runs on the model ``omd_stops``. With ``law="hunt-crossley"`` the force
    is ``max(0, k_b delta^n (1 + chi_b ddelta / v_in))``, ``v_in`` the approach speed of the
    contact (Hunt & Crossley 1975), on the model ``omd_stops_hc``: ``e_b`` is the restitution of
    one impact on the pad, and ``chi_b = hunt_crossley_damping(e_b)`` the damping factor that
    gives it exactly, which :meth:`as_params` gives the model.

    Parameters
    ----------
    L : float
        Half-stroke, m, in (0, 1e3]; on a block, at most ``B/2`` unless ``beyond_edges``.
    k_b : float
        Bumper stiffness, N/m (Hunt-Crossley: N/m^n), in (0, 1e30].
    c_b : float, optional
        Bumper dashpot, N s/m, in [0, 1e30]. Default 0. Kelvin-Voigt only.
    beyond_edges : bool, optional
        Allow a guide longer than the block is wide (``L > B/2``). Default False.
    law : {"kelvin-voigt", "hunt-crossley"}, optional
        The pads' contact law. Default ``"kelvin-voigt"``.
    n : float, optional
        Hunt-Crossley exponent, in [1, 10]. Default 1.5 (Hertzian contact).
    e_b : float, optional
        Hunt-Crossley: the restitution of one impact of a mass on a pad (what a drop on the pad
        measures), in [1e-3, 1]; required with that law.

    Raises
    ------
    ParameterError
        If a parameter is non-numeric, non-finite or out of range.

    Notes
    -----
    On its damper and block (:meth:`check_on`) the bumper's frequency
    ``omega_b = sqrt(k_b / m)`` must lie in [1e-3 p, 1e4 p] (a stiffer bumper's
    contacts need more steps than a run's bound on work) and its damping ratio
    ``zeta_b = c_b / (2 sqrt(k_b m))`` in [0, 10].
    """

    L: float
    k_b: float
    c_b: float = 0.0
    beyond_edges: bool = False
    law: str = "kelvin-voigt"
    n: float = 1.5
    e_b: float | None = None

    __repr__ = rounded_repr

    def __post_init__(self) -> None:
        for field in ("L", "k_b", "c_b"):
            object.__setattr__(self, field, check_in_range(field, getattr(self, field)))
        if not isinstance(self.beyond_edges, (bool, np.bool_)):
            raise ParameterError(f"beyond_edges must be True or False (got {shown(self.beyond_edges)})")
        if not isinstance(self.law, str) or self.law not in BUMPER_LAWS:
            raise ParameterError(f"law must be one of {', '.join(BUMPER_LAWS)} (got {shown(self.law)})")
        if self.law == "kelvin-voigt":
            if self.e_b is not None:
                raise ParameterError("e_b is a parameter of law='hunt-crossley' (a Kelvin-Voigt pad has c_b)")
            return
        if self.c_b != 0.0:
            raise ParameterError("c_b must be 0 with law='hunt-crossley' (its damping comes from e_b)")
        if self.e_b is None:
            raise ParameterError("e_b must be given with law='hunt-crossley': the pad's restitution in (0, 1]")
        object.__setattr__(self, "n", check_in_range("n", self.n, "n_b"))
        object.__setattr__(self, "e_b", check_in_range("e_b", self.e_b))

    @property
    def model(self) -> str:
        """The generated model a damper with these stops runs on: ``omd_stops`` or ``omd_stops_hc``."""
        return BUMPER_LAWS[self.law]

    def check_on(self, block: Block, damper: Damper) -> Stops:
        """These stops if they suit ``damper`` on ``block``: the gap within the block, the bumper's ratios.

        Raises
        ------
        ParameterError
            Naming the parameter, its range relative to the block or damper, and the reason.
        """
        check_block(block)
        if not self.beyond_edges and self.L > block.B / 2:
            raise ParameterError(
                f"L must be in (0, B/2] = (0, {block.B / 2:g}] m (got {self.L!r}): the stops at the block's edges "
                "at most; Stops(..., beyond_edges=True) for a guide that overhangs the block"
            )
        if damper.m == 0.0:
            raise ParameterError("stops need a damper mass m > 0 kg (a bare block has no guide)")
        if self.law == "hunt-crossley":
            # The pad's frequency at 1 mm of penetration, where its stiffness is n k_b delta^(n-1).
            omega_b = math.sqrt(self.n * self.k_b * HC_REFERENCE_PENETRATION ** (self.n - 1) / damper.m)
            check_scaled("omega_b", omega_b, "omega_b_ratio", block.p, "[1e-3 p, 1e4 p] at 1 mm", "rad/s")
            return self
        omega_b = math.sqrt(self.k_b / damper.m)
        check_scaled("omega_b", omega_b, "omega_b_ratio", block.p, "[1e-3 p, 1e4 p]", "rad/s")
        check_in_range("zeta_b", self.c_b / (2 * math.sqrt(self.k_b * damper.m)), derived=True)
        return self

    def as_params(self) -> dict[str, float]:
        """The stops' parameters under the symbol names of the derivation: ``L``, ``k_b``, ``c_b``
        (Hunt-Crossley: ``L``, ``k_b``, ``n_b``, ``chi_b``, the damping factor of the restitution ``e_b``)."""
        if self.law == "hunt-crossley":
            e_b = cast(float, self.e_b)  # a float with this law (__post_init__)
            return dict(zip(HC_STOP_PARAMETERS, (self.L, self.k_b, self.n, hunt_crossley_damping(e_b))))
        return dict(zip(STOP_PARAMETERS, (self.L, self.k_b, self.c_b)))

    @classmethod
    def at_edges(
        cls,
        block: Block,
        damper: Damper,
        *,
        depth: float = BUMPER_DEPTH,
        k_b: float = BUMPER_STIFFNESS,
        zeta_b: float = BUMPER_DAMPING_RATIO,
        law: str = "kelvin-voigt",
        e_b: float = BUMPER_RESTITUTION,
        n: float = 1.5,
    ) -> Stops:
        """Bumper pads of ``depth`` at the block's edges: ``L = B/2 - depth``.

        Parameters
        ----------
        block, damper : Block, Damper
            The block and its damper (``m > 0``).
        depth : float, optional
            The pads' depth, m, in (0, B/2). Default :data:`BUMPER_DEPTH` (20 mm).
        k_b : float, optional
            The pads' stiffness, N/m. Default :data:`BUMPER_STIFFNESS`, 6.25e5 N/m: a neoprene pad 20 mm thick
            of 50 x 50 mm and modulus 5 MPa, ``E A / t``, the same whatever the damper.
        zeta_b : float, optional
            The bumpers' damping ratio. Default :data:`BUMPER_DAMPING_RATIO` (0.2). Kelvin-Voigt only.
        law : {"kelvin-voigt", "hunt-crossley"}, optional
            The pads' contact law. Default ``"kelvin-voigt"``.
        e_b, n : float, optional
            The Hunt-Crossley pads' restitution (default :data:`BUMPER_RESTITUTION`, 0.5717, that of
            the Kelvin-Voigt default pad) and exponent (default 1.5).

        Returns
        -------
        Stops
            With ``k_b`` and ``c_b = 2 zeta_b sqrt(k_b m)`` (the restitution of ``zeta_b``, 0.57 by default, whatever
            the mass); Hunt-Crossley: ``k_b depth^(1 - n)`` of that ``k_b``, the same elastic force where the pad is
            crushed to its full depth.
        """
        check_block(block)
        depth = check_interval("depth", depth, 0.0, block.B / 2, "m", label="(0, B/2)")
        k_b = check_in_range("k_b", k_b)
        zeta_b = check_in_range("zeta_b", zeta_b)
        L, k_b, c_b = edge_stops(block, damper.m, depth, k_b, zeta_b)
        if law == "hunt-crossley":
            n = check_in_range("n", n, "n_b")
            stops = cls(L=float(L), k_b=float(k_b) * depth ** (1.0 - n), law=law, n=n, e_b=e_b)
            return stops.check_on(block, damper)
        return cls(L=float(L), k_b=float(k_b), c_b=float(c_b), law=law).check_on(block, damper)


def edge_stops(block: Block, m, depth=BUMPER_DEPTH, k_b=BUMPER_STIFFNESS, zeta_b=BUMPER_DAMPING_RATIO) -> tuple:
    """``(L, k_b, c_b)`` of :meth:`Stops.at_edges` for dampers of mass ``m`` (broadcasting).

    ``L = B/2 - depth``, the pads' ``k_b`` (N/m) and ``c_b = 2 zeta_b sqrt(k_b m)``; unchecked.
    """
    m = np.asarray(m, dtype=float)
    k_b = np.full(np.shape(m), float(k_b))
    return np.full(np.shape(m), block.B / 2 - depth), k_b, 2 * zeta_b * np.sqrt(k_b * m)


@dataclass(frozen=True)
class Damper:
    """Oscillating mass damper on a horizontal guide on top of the block.

    Parameters
    ----------
    m : float
        Moving mass, kg: 0 (the bare block) or in [1e-16, 1e13].
    k_m : float
        Spring stiffness, N/m, in [0, 1e30], and > 0 when ``m > 0``.
    c : float, optional
        Dashpot coefficient, N s/m, in [0, 1e30]. Default 0.
    h : float, optional
        Height of the guide above the top side of the block, m, in [0, 1e3]. Default 0.
    stops : Stops, optional
        End stops of the guide (model ``omd_stops``; ``omd_stops_hc`` with Hunt-Crossley
        pads). Default None: the paper's unlimited guide (model ``omd``).

    Raises
    ------
    ParameterError
        If any parameter is non-numeric, non-finite or out of range.

    Notes
    -----
    These absolute bounds only keep ``k_m / m`` and ``c / m`` normal doubles. On its
    block (:meth:`check_on`, which :func:`rocking.simulate` calls) a damper must also
    have a mass ratio ``m / M`` of 0 or in [1e-10, 10], a frequency ratio
    ``omega_m / p`` in [1e-3, 1e4] (a stiffer damper needs more integrator steps
    than a run's bound on work) and a damping ratio ``zeta`` in [0, 10] (above, the
    dashpot is a stiff mode for the explicit integrator).
    """

    m: float
    k_m: float
    c: float = 0.0
    h: float = 0.0
    stops: Stops | None = None

    __repr__ = rounded_repr

    def __post_init__(self) -> None:
        if not (self.stops is None or isinstance(self.stops, Stops)):
            raise ParameterError(f"stops must be a rocking.Stops or None (got {type(self.stops).__name__})")
        m = check_in_range("m", self.m)
        k_m = check_in_range("k_m", self.k_m)
        c = check_in_range("c", self.c)
        h = check_in_range("h", self.h)
        if m > 0.0 and k_m == 0.0 and self.stops is None:
            # Without a spring the mass has no rest position and drifts off an unlimited guide.
            raise ParameterError(f"k_m must be > 0 N/m when m > 0 and no stops hold the mass (got k_m={k_m!r})")
        # Frozen dataclass: the normalised floats can only be stored this way.
        for field, value in (("m", m), ("k_m", k_m), ("c", c), ("h", h)):
            object.__setattr__(self, field, value)

    def _require_mass(self, quantity: str) -> None:
        if self.m == 0.0:
            raise ParameterError(f"{quantity} is undefined for m = 0 kg (no damper)")
        if self.k_m == 0.0 and quantity != "omega_m":
            raise ParameterError(f"{quantity} is undefined for k_m = 0 N/m (a free mass between stops)")

    # Cached (a frozen damper's fields never change): check_on reads omega_m twice per simulate call; a property
    # that raises (m = 0) caches nothing.
    @cached_property
    def omega_m(self) -> float:
        """Natural circular frequency ``omega_m = sqrt(k_m / m)``, rad/s.

        Raises
        ------
        ParameterError
            If ``m == 0``.
        """
        self._require_mass("omega_m")
        return math.sqrt(self.k_m / self.m)

    @property
    def T_m(self) -> float:
        """Natural period ``T_m = 2 pi / omega_m``, s.

        Raises
        ------
        ParameterError
            If ``m == 0``.
        """
        self._require_mass("T_m")
        return 2 * math.pi / self.omega_m

    @cached_property
    def zeta(self) -> float:
        """Damping ratio ``zeta = c / (2 m omega_m)``.

        Raises
        ------
        ParameterError
            If ``m == 0``.
        """
        self._require_mass("zeta")
        return self.c / (2 * self.m * self.omega_m)

    def gamma(self, block: Block) -> float:
        """Mass ratio ``gamma = m / M`` with respect to ``block``."""
        return self.m / check_block(block).M

    def check_on(self, block: Block) -> Damper:
        """This damper if it suits ``block``: the ranges of ``m / M``, ``omega_m / p`` and ``zeta``.

        Parameters
        ----------
        block : Block
            The block carrying the damper.

        Returns
        -------
        Damper
            ``self``.

        Raises
        ------
        ParameterError
            Naming the parameter, its range relative to the block and the reason.
        """
        check_block(block)
        check_scaled("m", self.m, "gamma", block.M, "[1e-10 M, 10 M]", "kg")
        if self.k_m > 0.0:  # k_m = 0 only for a free mass between stops: no frequency, no damping ratio
            check_scaled("omega_m", self.omega_m, "omega_ratio", block.p, "[1e-3 p, 1e4 p]", "rad/s")
            check_in_range("zeta", self.zeta, derived=True)
        if self.stops is not None:
            self.stops.check_on(block, self)
        return self

    @property
    def model(self) -> str:
        """The generated model this damper runs on: ``omd``, or that of its stops (``omd_stops``, ``omd_stops_hc``)."""
        return "omd" if self.stops is None else self.stops.model

    def as_params(self) -> dict[str, float]:
        """Return the damper parameters under the symbol names of the derivation.

        Returns
        -------
        dict
            Keys ``"m"``, ``"k_m"``, ``"c"``, ``"h"``, and with stops ``"L"``, ``"k_b"``, ``"c_b"``
            (Hunt-Crossley: ``"L"``, ``"k_b"``, ``"n_b"``, ``"chi_b"``: :meth:`Stops.as_params`).
        """
        own = dict(zip(DAMPER_PARAMETERS, (self.m, self.k_m, self.c, self.h)))
        return own if self.stops is None else {**own, **self.stops.as_params()}

    @classmethod
    def from_nondim(
        cls,
        block: Block,
        *,
        gamma: float,
        T_m: float | None = None,
        omega_ratio: float | None = None,
        zeta: float = 0.05,
        h: float = 0.0,
    ) -> Damper:
        """Build a damper tuned relative to ``block``.

        Parameters
        ----------
        block : Block
            Block carrying the damper; supplies ``M`` and ``p``.
        gamma : float
            Mass ratio ``m / M``: 0 (the bare block) or in [1e-10, 10].
        T_m : float, optional
            Natural period, s, in ``[2 pi / (1e4 p), 2 pi / (1e-3 p)]``. Give exactly
            one of ``T_m`` and ``omega_ratio``.
        omega_ratio : float, optional
            Frequency ratio ``omega_m / p``, in [1e-3, 1e4].
        zeta : float, optional
            Damping ratio, in [0, 10]. Default 0.05.
        h : float, optional
            Height of the guide above the top of the block, m, in [0, 1e3]. Default 0.

        Returns
        -------
        Damper
            Damper with ``m = gamma M``, ``k_m = m omega_m^2`` and
            ``c = 2 zeta m omega_m``.

        Raises
        ------
        ParameterError
            If both or neither of ``T_m`` and ``omega_ratio`` are given, or any value
            is out of range.
        """
        _require_one("T_m", T_m, "omega_ratio", omega_ratio)
        check_block(block)
        gamma = check_in_range("gamma", gamma)
        zeta = check_in_range("zeta", zeta)
        if T_m is not None:
            # omega_ratio = 2 pi / (T_m p): T_m's range is omega_ratio's, inverted.
            valid = RANGES["omega_ratio"]
            bounds = Range(TWO_PI / (valid.high * block.p), TWO_PI / (valid.low * block.p), "s", valid.why)
            omega_m = TWO_PI / _in_range("T_m", T_m, bounds, "[2 pi/(1e4 p), 2 pi/(1e-3 p)]")
        else:
            omega_m = check_in_range("omega_ratio", omega_ratio) * block.p
        m, k_m, c = tuned_damper(block.M, gamma, omega_m, zeta)
        return cls(m=m, k_m=k_m, c=c, h=h)


def tuned_damper(M, gamma, omega_m, zeta) -> tuple:
    """``(m, k_m, c)`` of a damper of mass ratio ``gamma`` on a block of mass ``M`` (kg), natural frequency
    ``omega_m`` (rad/s) and damping ratio ``zeta``: ``m = gamma M``, ``k_m = m omega_m^2``,
    ``c = 2 zeta m omega_m`` (kg, N/m, N s/m); arrays broadcast. The one place these are written."""
    m = gamma * M
    return m, m * omega_m**2, 2 * zeta * m * omega_m
