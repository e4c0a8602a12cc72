"""Physical parameters of the rocking block and of the oscillating mass damper.

Notation follows ``docs/model.md`` (sections 1 and 9). All quantities are in SI units:
lengths in m, masses in kg, moments of inertia in kg m^2, times in s, angles in rad,
accelerations in m/s^2, stiffnesses in N/m and damping coefficients in N s/m.

Both parameter sets are frozen dataclasses that validate and convert their inputs to
``float`` on construction, so an invalid model can never reach the simulator. Every
validation failure raises :class:`ParameterError`, whose message names the parameter,
the valid range and the offending value.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

__all__ = [
    "Block",
    "Damper",
    "ParameterError",
    "check_interval",
    "check_nonnegative",
    "check_positive",
    "check_real",
]


class ParameterError(ValueError):
    """A model parameter is missing, non-numeric, non-finite or out of range."""


def _with_unit(text: str, unit: str) -> str:
    return f"{text} {unit}" if unit else text


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
        If ``value`` is not a real number (booleans included) or is nan or infinite.
    """
    # bool is an Integral, but True as a length is almost surely a caller's mistake.
    if not isinstance(value, numbers.Real) or isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} must be a real number (got {value!r})")
    x = float(value)
    if not math.isfinite(x):
        raise ParameterError(f"{name} must be finite (got {x!r})")
    return x


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
    x = check_real(name, value)
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
    x = check_real(name, value)
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
    x = check_real(name, value)
    above_low = x >= low if closed_low else x > low
    if not (above_low and x < high):
        numeric = f"{'[' if closed_low else '('}{low:g}, {high:g})"
        interval = f"{label} = {numeric}" if label else numeric
        raise ParameterError(f"{name} must be in {_with_unit(interval, unit)} (got {x!r})")
    return x


def _require_one(name_a: str, a: object, name_b: str, b: object) -> None:
    if (a is None) == (b is None):
        raise ParameterError(f"give exactly one of {name_a} or {name_b} (got {name_a}={a!r}, {name_b}={b!r})")


@dataclass(frozen=True)
class Block:
    """Rigid rectangular block rocking on its base corners (``docs/model.md`` section 1).

    Parameters
    ----------
    H : float
        Height of the block, m (> 0).
    B : float
        Width of the base, m (> 0).
    M : float
        Mass of the block, kg (> 0).
    e : float, optional
        Horizontal eccentricity of the centroid ``G`` from the geometric centre, m;
        ``e > 0`` moves ``G`` towards the right corner ``A'``. Requires
        ``|e| < B/2``. Default 0.
    I_G : float or None, optional
        Centroidal moment of inertia, kg m^2 (> 0). ``None`` (default) stores the
        homogeneous value ``M (B^2 + H^2) / 12``.
    g : float, optional
        Gravitational acceleration, m/s^2 (> 0). Default 9.81.

    Raises
    ------
    ParameterError
        If any parameter is non-numeric, non-finite or out of range.
    """

    H: float
    B: float
    M: float
    e: float = 0.0
    I_G: float | None = None
    g: float = 9.81

    def __post_init__(self) -> None:
        H = check_positive("H", self.H, "m")
        B = check_positive("B", self.B, "m")
        M = check_positive("M", self.M, "kg")
        e = check_interval("e", self.e, -B / 2, B / 2, "m", label="(-B/2, B/2)")
        I_G = M * (B**2 + H**2) / 12 if self.I_G is None else self.I_G
        I_G = check_positive("I_G", I_G, "kg m^2")
        g = check_positive("g", self.g, "m/s^2")
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

    @property
    def alpha(self) -> float:
        """Slenderness angle ``alpha = atan(B / H)``, rad."""
        return math.atan2(self.B, self.H)

    @property
    def tan_alpha(self) -> float:
        """``tan(alpha) = B / H``, the static uplift acceleration of the bare symmetric
        block in units of ``g``."""
        return self.B / self.H

    @property
    def R(self) -> float:
        """Half-diagonal ``R = sqrt(B^2 + H^2) / 2``, m."""
        return math.hypot(self.B, self.H) / 2

    @property
    def I_O(self) -> float:
        """``I_O = I_G + M R^2``, kg m^2.

        This is the inertia about a base corner of the symmetric block; for ``e != 0``
        it is kept as the reference inertia of the non-dimensional presentation, not
        the pivot inertia ``I_s`` of the equations of motion.
        """
        return self.I_G + self.M * self.R**2

    @property
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
            Frequency parameter, rad/s (> 0).
        lam : float, optional
            Slenderness ``H / B`` (> 0). Give exactly one of ``lam`` and ``alpha``.
        alpha : float, optional
            Slenderness angle ``atan(B / H)``, rad, in ``(0, pi/2)``.
        M : float, optional
            Mass, kg (> 0). Default 1.
        e_ratio : float, optional
            Eccentricity as a fraction of the base, ``e / B``, in ``(-0.5, 0.5)``.
            Default 0.
        g : float, optional
            Gravitational acceleration, m/s^2 (> 0). Default 9.81.

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
        p = check_positive("p", p, "rad/s")
        g = check_positive("g", g, "m/s^2")
        if lam is not None:
            alpha = math.atan2(1.0, check_positive("lam", lam))
        else:
            alpha = check_interval("alpha", alpha, 0.0, math.pi / 2, "rad", label="(0, pi/2)")
        e_ratio = check_interval("e_ratio", e_ratio, -0.5, 0.5)
        R = 3 * g / (4 * p**2)
        B = 2 * R * math.sin(alpha)
        return cls(H=2 * R * math.cos(alpha), B=B, M=M, e=e_ratio * B, g=g)

    @classmethod
    def reference(cls) -> Block:
        """Return the project's reference block (``docs/model.md`` section 9).

        ``H = 2.0 m``, ``B = 0.5 m`` (``lambda = 4``), ``e = 0.025 m``,
        ``M = 1000 kg``, homogeneous ``I_G``. The reference damper height
        ``h = 0.05 m`` belongs to :class:`Damper`.
        """
        return cls(H=2.0, B=0.5, M=1000.0, e=0.025)


@dataclass(frozen=True)
class Damper:
    """Oscillating mass damper on a horizontal guide on top of the block.

    Parameters
    ----------
    m : float
        Moving mass, kg (>= 0); ``m = 0`` is the bare block.
    k_m : float
        Spring stiffness, N/m (>= 0, and > 0 when ``m > 0``).
    c : float, optional
        Dashpot coefficient, N s/m (>= 0). Default 0.
    h : float, optional
        Height of the guide above the top side of the block, m (>= 0). Default 0.

    Raises
    ------
    ParameterError
        If any parameter is non-numeric, non-finite or out of range.
    """

    m: float
    k_m: float
    c: float = 0.0
    h: float = 0.0

    def __post_init__(self) -> None:
        m = check_nonnegative("m", self.m, "kg")
        k_m = check_nonnegative("k_m", self.k_m, "N/m")
        c = check_nonnegative("c", self.c, "N s/m")
        h = check_nonnegative("h", self.h, "m")
        if m > 0.0 and k_m == 0.0:
            # Without a spring the mass has no rest position and drifts off the guide.
            raise ParameterError(f"k_m must be > 0 N/m when m > 0 (got k_m={k_m!r}, m={m!r})")
        # Frozen dataclass: the normalised floats can only be stored this way.
        for field, value in (("m", m), ("k_m", k_m), ("c", c), ("h", h)):
            object.__setattr__(self, field, value)

    def _require_mass(self, quantity: str) -> None:
        if self.m == 0.0:
            raise ParameterError(f"{quantity} is undefined for m = 0 kg (no damper)")

    @property
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

    @property
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
        return self.m / block.M

    def as_params(self) -> dict[str, float]:
        """Return the damper parameters under the symbol names of the derivation.

        Returns
        -------
        dict
            Keys ``"m"``, ``"k_m"``, ``"c"``, ``"h"``.
        """
        return {"m": self.m, "k_m": self.k_m, "c": self.c, "h": self.h}

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
            Mass ratio ``m / M`` (>= 0).
        T_m : float, optional
            Natural period, s (> 0). Give exactly one of ``T_m`` and ``omega_ratio``.
        omega_ratio : float, optional
            Frequency ratio ``omega_m / p`` (> 0).
        zeta : float, optional
            Damping ratio (>= 0). Default 0.05.
        h : float, optional
            Height of the guide above the top of the block, m (>= 0). Default 0.

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
        gamma = check_nonnegative("gamma", gamma)
        zeta = check_nonnegative("zeta", zeta)
        if T_m is not None:
            omega_m = 2 * math.pi / check_positive("T_m", T_m, "s")
        else:
            omega_m = check_positive("omega_ratio", omega_ratio) * block.p
        m = gamma * block.M
        return cls(m=m, k_m=m * omega_m**2, c=2 * zeta * m * omega_m, h=h)
