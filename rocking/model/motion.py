"""Ground motions: the families of ``docs/model.md`` section 12, and one interface to all of them.

Every motion is ``ddx_g(t) = sign a_g f(t)`` on ``[0, t_p]`` and 0 outside: the
one-sine pulse (:class:`~rocking.model.pulse.OneSinePulse`), the one-cosine pulse
(:class:`OneCosinePulse`), the Ricker wavelets (:class:`RickerWavelet`), the
Mavroeidis-Papageorgiou near-fault pulse (:class:`MavroeidisPapageorgiou`) and a
sampled record (:class:`SampledMotion`). Each has ``acceleration(t)``, ``t_p`` and
``sign``; :func:`describe` turns one of them (its exact type, nothing else) into the
numbers both back ends run on.

The shapes are written once, for scalars (``math``) and arrays (``numpy``) alike
(:data:`SHAPES`): the NumPy back end, ``acceleration(t)`` and the recorded history use
these functions; ``rocking/sim/csrc/sim.c`` repeats them operation for operation.

Units SI: m/s^2, rad/s, s, rad. Invalid parameters raise
:class:`~rocking.model.params.ParameterError` naming the parameter.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TypedDict

import numpy as np
from numpy.typing import ArrayLike

from .params import RANGES, Block, ParameterError, as_real, check_block, check_in_range, check_nonnegative, shown
from .pulse import OneSinePulse, check_sign, from_period
from .vertical import Vertical, check_vertical

__all__ = [
    "FAMILIES",
    "MavroeidisPapageorgiou",
    "Motion",
    "OneCosinePulse",
    "OneSinePulse",
    "RickerWavelet",
    "SampledMotion",
    "Vertical",
    "describe",
]

#: The families, in the order of their codes (``rocking.sim.boundary.MOTIONS``).
FAMILIES = ("sine", "cosine", "ricker", "ricker_anti", "mp", "sampled")

#: The Ricker wavelets are cut at ``|u| = 4`` (``exp(-16)``, 1e-7 of the peak): ``t_c = 4 RICKER_PHASE / omega_g``.
RICKER_CUT = 4.0
#: Phase ``omega_g (t - t_c)`` per unit of ``u`` of each wavelet: 2 for the symmetric one, sqrt 6 for the
#: antisymmetric one, so that both spectra peak at ``omega_g`` (|F| ~ w^2 exp(-w^2 / (4 c^2)) and w^3 of it,
#: c = omega_g / RICKER_PHASE): Vassiliou and Makris (2011)'s period ``T_p`` of both wavelets.
RICKER_PHASE = {"ricker": 2.0, "ricker_anti": math.sqrt(6.0)}
#: ``u*^2`` of the antisymmetric wavelet's peak, ``(3 - sqrt 6) / 2``.
_U_STAR2 = (3.0 - math.sqrt(6.0)) / 2.0
#: The antisymmetric wavelet's peak before normalisation, ``u* (3 - 2 u*^2) exp(-u*^2)``.
RICKER_ANTI_PEAK = math.sqrt(_U_STAR2) * (3.0 - 2.0 * _U_STAR2) * math.exp(-_U_STAR2)


# --------------------------------------------------------------------------- #
# The shapes f, written once for math (scalars) and numpy (arrays)             #
# --------------------------------------------------------------------------- #


def _sine(t, omega_g, phase, t_c, gamma, m):
    return m.sin(omega_g * t + phase)


def _cosine(t, omega_g, phase, t_c, gamma, m):
    return m.cos(omega_g * t)


def _ricker(t, omega_g, phase, t_c, gamma, m):
    u = 0.5 * omega_g * (t - t_c)
    u2 = u * u
    return (1.0 - 2.0 * u2) * m.exp(-u2)


def _ricker_anti(t, omega_g, phase, t_c, gamma, m):
    u = omega_g * (t - t_c) / RICKER_PHASE["ricker_anti"]
    u2 = u * u
    return -(u * (3.0 - 2.0 * u2) * m.exp(-u2)) / RICKER_ANTI_PEAK


def _mp(t, omega_g, phase, t_c, gamma, m):
    phi = omega_g * (t - t_c)
    return -0.5 * (m.sin(phi / gamma) / gamma * m.cos(phi + phase) + (1.0 + m.cos(phi / gamma)) * m.sin(phi + phase))


#: ``f(t, omega_g, phase, t_c, gamma, m)`` of each analytic family, ``m`` being ``math`` or ``numpy``.
SHAPES: dict[str, Callable] = {
    "sine": _sine,
    "cosine": _cosine,
    "ricker": _ricker,
    "ricker_anti": _ricker_anti,
    "mp": _mp,
}


def sample_piece(t, dt: float, n: int):
    """Index ``k`` of the sample interval ``[k dt, (k + 1) dt)`` holding ``t``, within ``[0, n - 2]``.

    ``floor(t / dt)`` corrected for the rounding of the ratio (sim.c's ``pulse_piece``); a float, or an
    array of floats for an array ``t``.
    """
    k = np.floor(np.asarray(t, dtype=float) / dt)
    k = np.where((k + 1.0) * dt <= t, k + 1.0, k)
    k = np.where(k * dt > t, k - 1.0, k)
    k = np.clip(k, 0.0, n - 2.0)
    return float(k) if k.ndim == 0 else k


def interpolate(samples: np.ndarray, dt: float, k, t):
    """``a(t)`` on the piece ``k``: ``a_k + (a_{k+1} - a_k) (t - k dt) / dt`` (scalars or arrays)."""
    i = np.asarray(k).astype(np.int64)
    return samples[i] + (samples[i + 1] - samples[i]) * ((t - k * dt) / dt)


def timing(family: str, omega_g, phase=0.0, gamma=0.0):
    """``(t_c, t_p)`` of an analytic family: its centre and its end, s (docs/model.md section 12).

    Vectorised over its arguments: one formula for a motion and for a batch of them.
    """
    omega_g = np.asarray(omega_g, dtype=float)
    if family == "sine":
        t_c, t_p = 0.0 * omega_g, (2 * math.pi - phase) / omega_g
    elif family == "cosine":
        t_c, t_p = 0.0 * omega_g, 2 * math.pi / omega_g
    elif family in RICKER_PHASE:
        t_c = RICKER_PHASE[family] * RICKER_CUT / omega_g
        t_p = 2.0 * t_c
    else:
        t_c, t_p = gamma * math.pi / omega_g, 2.0 * gamma * math.pi / omega_g
    return (float(t_c), float(t_p)) if omega_g.ndim == 0 else (t_c, t_p)


# --------------------------------------------------------------------------- #
# Extrema of the analytic shapes, in phase units phi = omega_g (t - t_c)       #
# --------------------------------------------------------------------------- #


def _mp_slope(phi, gamma: float, nu: float, m=math):
    """``df / dphi`` of the Mavroeidis-Papageorgiou shape (``m``: ``math`` or ``numpy``)."""
    c, s = m.cos(phi / gamma), m.sin(phi / gamma)
    return -0.5 * ((c / gamma**2 + 1.0 + c) * m.cos(phi + nu) - (2.0 / gamma) * s * m.sin(phi + nu))


#: Points per unit of phase where the slope of the MP shape is scanned for sign changes (the shape's
#: fastest oscillation has period 2 pi: 64 points per radian leave every root in its own bracket).
MP_SCAN = 64


def mp_extrema(gamma: float, nu: float) -> np.ndarray:
    """The extrema of the Mavroeidis-Papageorgiou shape on ``|phi| < gamma pi``, sorted, in phase units.

    The roots of ``df/dphi``, bracketed on a scan of :data:`MP_SCAN` points per radian and each
    solved by Brent's method to a few ulps: located once, before any run.
    """
    from scipy.optimize import brentq  # here: SciPy is imported by the runs, not by ``import rocking``

    half = gamma * math.pi
    grid = np.linspace(-half, half, int(math.ceil(2 * half * MP_SCAN)) + 1)
    slope = _mp_slope(grid, gamma, nu, np)
    roots = [grid[i] for i in np.flatnonzero(slope[1:-1] == 0.0) + 1]
    for i in np.flatnonzero(slope[:-1] * slope[1:] < 0.0):
        root = brentq(_mp_slope, grid[i], grid[i + 1], args=(gamma, nu), xtol=1e-15, rtol=4 * np.finfo(float).eps)
        roots.append(root)
    return np.array(sorted(roots), dtype=float)


def listed_extrema(family: str, gamma: float = 0.0, nu: float = 0.0) -> np.ndarray | None:
    """The extrema of a family's shape in phase units (Ricker, MP); ``None`` for the others."""
    if family in RICKER_PHASE:
        return ricker_extrema(family == "ricker_anti")
    return mp_extrema(gamma, nu) if family == "mp" else None


def ricker_extrema(antisymmetric: bool) -> np.ndarray:
    """The extrema of a Ricker wavelet in phase units ``phi = RICKER_PHASE u``: ``u = 0, +-sqrt(3/2)``, or
    ``u^2 = (3 -+ sqrt 6) / 2`` for the antisymmetric one (docs/model.md section 12)."""
    if antisymmetric:
        inner, outer = math.sqrt((3.0 - math.sqrt(6.0)) / 2.0), math.sqrt((3.0 + math.sqrt(6.0)) / 2.0)
        return RICKER_PHASE["ricker_anti"] * np.array([-outer, -inner, inner, outer])
    return RICKER_PHASE["ricker"] * np.array([-math.sqrt(1.5), 0.0, math.sqrt(1.5)])


def _slope(family: str, phi, gamma: float, nu: float, m=np):
    """``df / dphi`` of an aperiodic family's shape in phase units ``phi = omega_g (t - t_c)`` (``m``: ``math``
    or ``numpy``)."""
    if family == "mp":
        return _mp_slope(phi, gamma, nu, m)
    x = phi / RICKER_PHASE[family]
    if family == "ricker":
        return (4.0 * x**3 - 6.0 * x) * m.exp(-x * x) / RICKER_PHASE[family]
    return -(3.0 - 12.0 * x**2 + 4.0 * x**4) * m.exp(-x * x) / (RICKER_ANTI_PEAK * RICKER_PHASE[family])


def margin_extrema(family: str, gamma: float, nu: float, ratio: float, lead: float, tans) -> np.ndarray | None:
    """The extrema of the uplift margins of a pulse with a vertical lead, with those of its shape (docs/model.md
    section 14); ``None`` where they are the shape's own (no lead, or no vertical component).

    Every direction ``d`` and sign ``s`` has the margin ``d s a_g f(phi) - (g + ratio a_g f(phi + lead)) tan_d``
    (``tans``: the ``tan(alpha_d)`` of both pivots): its extrema, the roots of ``f'(phi) = c f'(phi + lead)`` with
    ``c = d s ratio tan_d``, depend neither on ``a_g`` nor on ``omega_g``, so one list serves a whole batch and
    both directions. The one-sine and the one-cosine (``f = sin v``, ``v`` the sine's argument) have them in
    closed form, one offset in ``[0, pi)`` per ``c`` (``v = offset + k pi``), listed instead of phase units; the
    others are bracketed on a scan of :data:`MP_SCAN` points per radian over the pulse and solved by Brent's
    method, those that may lift the block kept (below), merged with the shape's extrema, sorted, without
    duplicates.
    """
    if ratio == 0.0 or lead == 0.0:
        return None
    c = np.unique([d * ratio * tan for tan in tans for d in (1.0, -1.0)])
    if family in ("sine", "cosine"):
        # cos v - c cos(v + lead) = (1 - c cos lead) cos v + c sin lead sin v: zero at one v mod pi.
        a, b = 1.0 - c * math.cos(lead), c * math.sin(lead)
        offsets = np.mod(np.arctan2(-a, b)[(a != 0.0) | (b != 0.0)], math.pi)
        return _distinct(np.append(offsets, math.pi / 2))
    from scipy.optimize import brentq  # here: SciPy is imported by the runs, not by ``import rocking``

    own = ricker_extrema(family == "ricker_anti") if family in RICKER_PHASE else mp_extrema(gamma, nu)
    half = gamma * math.pi if family == "mp" else RICKER_PHASE[family] * RICKER_CUT
    grid = np.linspace(-half, half, int(math.ceil(2 * half * MP_SCAN)) + 1)
    slope = _slope(family, grid, gamma, nu)[None, :] - c[:, None] * _slope(family, grid + lead, gamma, nu)[None, :]
    roots = list(own) + [grid[j + 1] for _, j in zip(*np.nonzero(slope[:, 1:-1] == 0.0))]
    shape = SHAPES[family]
    # The margin of c is a_g F - g tan, F = sign(c) f(phi) - |c| f(phi + lead), and its slope a_g sign(c) times
    # that of c: only its maxima where F > 0 can be above 0 at some amplitude, and only they are listed (a
    # margin below 0 at both ends of a monotone stretch, or at a maximum, is below 0 between).
    rising = np.sign(c)[:, None] * slope[:, :-1] > 0.0
    for k, j in zip(*np.nonzero(rising & (slope[:, :-1] * slope[:, 1:] < 0.0))):

        def h(phi, ck=float(c[k])):
            return _slope(family, phi, gamma, nu, math) - ck * _slope(family, phi + lead, gamma, nu, math)

        root = brentq(h, grid[j], grid[j + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps)
        if math.copysign(1.0, c[k]) * shape(root, 1.0, nu, 0.0, gamma, math) > abs(c[k]) * shape(
            root + lead, 1.0, nu, 0.0, gamma, math
        ):
            roots.append(root)
    return _distinct(np.array(roots, dtype=float))


def _distinct(phi: np.ndarray) -> np.ndarray:
    """``phi`` sorted, without the values within ``MERGED`` of the one before (one extremum found twice)."""
    phi = np.sort(phi)
    return phi[np.concatenate(([True], np.diff(phi) > MERGED))]


#: Phase units within which two listed extrema are one (found twice, by two roots differing in rounding only):
#: a segment between them would last a few ulps.
MERGED = 1e-12


# --------------------------------------------------------------------------- #
# The analytic families                                                        #
# --------------------------------------------------------------------------- #


class _Analytic:
    """What the analytic families share: amplitude, frequency and sign, checked, and ``f`` on ``[0, t_p]``.

    A subclass declares ``family`` and the dataclass fields ``a_g``, ``omega_g``, ``sign``; its centre and end
    follow from them (:func:`timing`).
    """

    a_g: float
    omega_g: float
    sign: int
    vertical: Vertical | None

    @property
    def family(self) -> str:
        """The family's name, a key of :data:`SHAPES` (each subclass gives its own)."""
        raise NotImplementedError

    def _check(self) -> None:
        check_sign(self.sign)
        check_vertical(self.vertical)
        a_g = check_in_range("a_g", self.a_g)
        omega_g = check_in_range("omega_g", self.omega_g, label="[2 pi/1000, 2 pi/0.001]")
        # Frozen dataclass: the normalised floats can only be stored this way.
        object.__setattr__(self, "a_g", a_g)
        object.__setattr__(self, "omega_g", omega_g)

    @property
    def T_g(self) -> float:
        """Period ``2 pi / omega_g``, s."""
        return 2 * math.pi / self.omega_g

    @property
    def phase(self) -> float:
        """The phase of the shape (``nu`` of the MP pulse, 0 otherwise), rad."""
        return 0.0

    @property
    def shape_parameter(self) -> float:
        """The shape parameter (``gamma_mp`` of the MP pulse, 0 otherwise)."""
        return 0.0

    @property
    def t_c(self) -> float:
        """Centre of the motion, s (0 for the one-cosine)."""
        return timing(self.family, self.omega_g, self.phase, self.shape_parameter)[0]

    @property
    def t_p(self) -> float:
        """End of the motion, s."""
        return timing(self.family, self.omega_g, self.phase, self.shape_parameter)[1]

    def acceleration(self, t: ArrayLike) -> float | np.ndarray:
        """Ground acceleration ``sign a_g f(t)`` on ``[0, t_p]``, 0 outside, m/s^2 (float for a scalar ``t``)."""
        t = np.asarray(t, dtype=float)
        f = SHAPES[self.family](t, self.omega_g, self.phase, self.t_c, self.shape_parameter, np)
        acc = np.where((t >= 0.0) & (t <= self.t_p), self.sign * self.a_g * f, 0.0)
        return float(acc) if acc.ndim == 0 else acc

    def beta(self, block: Block) -> float:
        """Amplitude ratio ``beta = a_g / (g tan(alpha))`` for ``block``."""
        return block.beta(self.a_g)

    def Omega(self, block: Block) -> float:
        """Frequency ratio ``Omega = omega_g / p`` for ``block``."""
        return self.omega_g / block.p

    @classmethod
    def from_nondim(cls: Callable[..., _Analytic], block: Block, *, beta: float, Omega: float, **shape):
        """The motion scaled to ``block``: ``a_g = beta g tan(alpha)``, ``omega_g = Omega p``.

        Parameters
        ----------
        block : Block
            Block that sets the scales ``g tan(alpha)`` and ``p``.
        beta : float
            Amplitude ratio, in [0, 1e4].
        Omega : float
            Frequency ratio, in [0.01, 1000].
        **shape
            The family's other parameters (``sign``, ``antisymmetric``, ``gamma_mp``, ``nu``).

        Raises
        ------
        ParameterError
            If any value is out of range (naming it).
        """
        check_block(block)
        beta, Omega = check_in_range("beta", beta), check_in_range("Omega", Omega)
        try:
            return cls(a_g=block.a_g(beta), omega_g=Omega * block.p, **shape)
        except ParameterError as exc:
            if str(exc).startswith(("a_g ", "omega_g ")):  # derived from beta and Omega: say so
                raise ParameterError(f"beta = {beta!r}, Omega = {Omega!r} on this block give {exc}") from None
            raise

    from_period = classmethod(from_period)


@dataclass(frozen=True)
class OneCosinePulse(_Analytic):
    """``ddx_g = sign a_g cos(omega_g t)`` on ``[0, 2 pi / omega_g]``: one full cosine cycle, a step at ``t = 0``.

    Parameters
    ----------
    a_g : float
        Amplitude, m/s^2, in [0, 1e5].
    omega_g : float
        Circular frequency, rad/s, in ``[2 pi / 1000, 2 pi / 0.001]``.
    sign : {+1, -1}, optional
        Direction (+1: the ground first accelerates to the right).
    vertical : Vertical, optional
        Vertical component (docs/model.md section 14), unsigned by ``sign``; default None.
    """

    a_g: float
    omega_g: float
    sign: int = 1
    vertical: Vertical | None = None
    family = "cosine"

    def __post_init__(self) -> None:
        self._check()


@dataclass(frozen=True)
class RickerWavelet(_Analytic):
    """A Ricker wavelet ``sign a_g f(t)``, cut at ``|u| = 4`` (docs/model.md 12).

    Symmetric ``f = (1 - 2 u^2) exp(-u^2)``, ``u = omega_g (t - t_c) / 2``; antisymmetric, its derivative
    normalised to a peak of 1 (first lobe positive), ``u = omega_g (t - t_c) / sqrt 6``. For both,
    ``omega_g = 2 pi f_p``, ``f_p`` the peak of its Fourier spectrum (Vassiliou and Makris 2011).

    Parameters
    ----------
    a_g : float
        Peak, m/s^2, in [0, 1e5].
    omega_g : float
        ``2 pi f_p``, rad/s, in ``[2 pi / 1000, 2 pi / 0.001]``.
    antisymmetric : bool, optional
        The antisymmetric wavelet. Default False.
    sign : {+1, -1}, optional
        Direction.
    vertical : Vertical, optional
        Vertical component (docs/model.md section 14), unsigned by ``sign``; default None.
    """

    a_g: float
    omega_g: float
    antisymmetric: bool = False
    sign: int = 1
    vertical: Vertical | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.antisymmetric, (bool, np.bool_)):
            raise ParameterError(f"antisymmetric must be True or False (got {shown(self.antisymmetric)})")
        self._check()

    @property
    def family(self) -> str:
        return "ricker_anti" if self.antisymmetric else "ricker"


@dataclass(frozen=True)
class MavroeidisPapageorgiou(_Analytic):
    """The near-fault pulse of Mavroeidis and Papageorgiou (2003), ``omega_g = 2 pi f_p`` (docs/model.md 12).

    Ground velocity ``v = A/2 [1 + cos(phi / gamma_mp)] cos(phi + nu)``, ``phi = omega_g (t - t_c)``,
    ``|phi| <= gamma_mp pi``; the acceleration is its derivative, ``a_g = A omega_g``. Its peak is
    below ``a_g`` in general.

    Parameters
    ----------
    a_g : float
        ``A omega_g``, m/s^2, in [0, 1e5].
    omega_g : float
        ``2 pi f_p``, rad/s, in ``[2 pi / 1000, 2 pi / 0.001]``.
    gamma_mp : float
        Oscillations (Mavroeidis and Papageorgiou's gamma, named apart from the damper's mass ratio), in
        (1, 20].
    nu : float, optional
        Phase, rad, in ``[0, 2 pi)``. Default 0.
    sign : {+1, -1}, optional
        Direction.
    vertical : Vertical, optional
        Vertical component (docs/model.md section 14), unsigned by ``sign``; default None.
    """

    a_g: float
    omega_g: float
    gamma_mp: float
    nu: float = 0.0
    sign: int = 1
    vertical: Vertical | None = None
    family = "mp"

    def __post_init__(self) -> None:
        self._check()
        object.__setattr__(self, "gamma_mp", check_in_range("gamma_mp", self.gamma_mp))
        object.__setattr__(self, "nu", check_in_range("nu", self.nu, "psi", label="[0, 2 pi)"))

    @property
    def phase(self) -> float:
        return self.nu

    @property
    def shape_parameter(self) -> float:
        return self.gamma_mp


# --------------------------------------------------------------------------- #
# A sampled record                                                             #
# --------------------------------------------------------------------------- #

#: Relative spread of the spacing of a ``t`` array that still counts as uniform.
UNIFORM = 1e-6

#: The rounding of a time written in single precision, relative to the time: a record's times saved as float32
#: (``0.00499999989``, ``10.0050001``) are off their uniform grid by up to this much of themselves.
SINGLE = float(np.finfo(np.float32).eps)


def irregular_step(t: np.ndarray) -> tuple[float, int | None]:
    """The mean step ``(t[-1] - t[0]) / (n - 1)`` of the times ``t`` (n >= 2), and the first ``k`` whose step
    ``t[k + 1] - t[k]`` is off the median step by more than :data:`UNIFORM` of it plus the single-precision
    rounding of a step and of the median (:data:`SINGLE` of the largest time each; None: the times are uniform).

    The median, not the mean, is the reference so that one bad step is named, not every step. A missing or
    doubled sample is off by a whole step, far beyond either.
    """
    t = np.asarray(t, float)
    steps = np.diff(t)
    typical = float(np.median(steps))
    off = np.abs(steps - typical) > UNIFORM * abs(typical) + 2 * SINGLE * float(np.max(np.abs(t)))
    return float((t[-1] - t[0]) / (t.size - 1)), (int(np.argmax(off)) if off.any() else None)


def real_array(name: str, values: object) -> np.ndarray:
    """``values`` as a float array if every element is a real number (nan and inf kept for the caller's check).

    A NumPy cast would take strings (``"1"``), booleans and complex numbers (dropping the imaginary
    part), and overflow on an integer beyond the doubles: each element is checked as a scalar is
    (:func:`~rocking.model.params.as_real`), an integer beyond the doubles becoming ``+-inf``.

    Raises
    ------
    ParameterError
        Naming ``name`` and the first element that is no real number.
    """
    try:
        raw = np.asarray(values)
    except (TypeError, ValueError):  # ragged nested sequences
        raise ParameterError(f"{name} must be an array of real numbers (got {type(values).__name__})") from None
    if raw.dtype.kind in "iuf":
        return raw.astype(float, copy=False)
    if raw.dtype.kind != "O":  # bool, complex, str, bytes, dates
        raise ParameterError(f"{name} must be an array of real numbers (got dtype {raw.dtype})")
    flat = [as_real(f"{name}[{i}]", v) for i, v in enumerate(raw.ravel().tolist())]
    return np.array(flat, dtype=float).reshape(raw.shape)


def _samples(a: object, name: str = "a") -> np.ndarray:
    """``a`` as a 1-D float array of at least 2 finite samples; the error names ``name`` and the first bad index."""
    arr = real_array(name, a)
    if arr.ndim != 1:
        raise ParameterError(f"{name} must be one-dimensional (got shape {arr.shape})")
    if arr.size < 2:
        raise ParameterError(f"{name} must hold at least 2 samples (got {arr.size})")
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise ParameterError(f"{name} must be finite: {name}[{bad[0]}] = {float(arr[bad[0]])!r}")
    if arr.flags.writeable:  # the caller's array, or a new one: a frozen copy; a frozen one is shared as it is
        arr = arr.copy()
        arr.setflags(write=False)  # shared by every scaled copy and by the back ends: never changed
    return arr


def _spacing(t: object, n: int) -> float:
    """The uniform spacing of the times ``t`` of ``n`` samples, from 0; else the error naming the index."""
    t = real_array("t", t).reshape(-1)
    if t.size != n:
        raise ParameterError(f"t must hold one time per sample ({n}, got {t.size})")
    if not np.all(np.isfinite(t)):
        raise ParameterError(f"t must be finite: t[{np.flatnonzero(~np.isfinite(t))[0]}] is not")
    dt, k = irregular_step(t)
    if not dt > 0.0:
        raise ParameterError(f"t must increase (got t[0] = {float(t[0])!r}, t[-1] = {float(t[-1])!r})")
    if abs(t[0]) > UNIFORM * dt:
        raise ParameterError(f"t must start at 0 (got t[0] = {float(t[0])!r})")
    if k is not None:
        raise ParameterError(
            f"t must be uniformly spaced (to {UNIFORM:g} dt): t[{k + 1}] - t[{k}] = "
            f"{float(t[k + 1] - t[k])!r}, dt = {float(dt)!r}"
        )
    return dt


@dataclass(frozen=True, eq=False)
class SampledMotion:
    """A recorded (or synthetic) ground acceleration: ``ddx_g = sign scale a(t)``, ``a`` linear between samples.

    Samples ``a_k`` at ``t_k = k dt``, ``k = 0 ... n - 1``; ``t_p = (n - 1) dt``, 0 after.

    Parameters
    ----------
    a : array_like
        The samples, m/s^2: at least 2, all finite.
    dt : float, optional
        Sample spacing, s, in [1e-6, 10]. Give ``dt`` or ``t``.
    t : array_like, optional
        Sample times from 0, uniformly spaced (to :data:`UNIFORM` of the spacing).
    scale : float, optional
        Factor on the samples (``>= 0``; it plays ``a_g``). Default 1.
    sign : {+1, -1}, optional
        Direction. Default +1.
    a_v : array_like, optional
        Vertical samples at the same times, m/s^2, > 0 up (docs/model.md section 14): one per
        sample of ``a``, all finite, scaled by ``scale`` and unsigned by ``sign``. Default None: none.

    Raises
    ------
    ParameterError
        One line naming the parameter: non-finite sample (its index), non-uniform ``t``, a bad
        ``dt``, fewer than 2 samples, a peak ``scale max|a|`` beyond the range of ``a_g``, vertical
        samples of another count.
    """

    a: np.ndarray = field(repr=False)
    dt: float | None = None
    t: np.ndarray | None = field(default=None, repr=False)
    scale: float = 1.0
    sign: int = 1
    a_v: np.ndarray | None = field(default=None, repr=False)
    family = "sampled"

    def __post_init__(self) -> None:
        a = _samples(self.a)
        if (self.dt is None) == (self.t is None):
            raise ParameterError("give exactly one of dt (the sample spacing) or t (the sample times)")
        dt = _spacing(self.t, a.size) if self.dt is None else check_in_range("dt", self.dt, "pulse_dt")
        check_in_range("dt", dt, "pulse_dt")
        scale = check_nonnegative("scale", self.scale)
        check_sign(self.sign)
        peak = scale * float(np.max(np.abs(a)))
        if peak not in RANGES["a_g"]:
            raise ParameterError(f"scale max|a| = {peak!r} m/s^2 must be {RANGES['a_g'].text()}: {RANGES['a_g'].why}")
        if (a.size - 1) * dt > RANGES["record_length"].high:
            raise ParameterError(
                f"the record lasts {(a.size - 1) * dt:g} s: at most {RANGES['record_length'].high:g} s"
            )
        a_v = None if self.a_v is None else _samples(self.a_v, "a_v")
        if a_v is not None and a_v.size != a.size:
            raise ParameterError(
                f"a_v must hold one vertical sample per sample of a, at the same dt ({a.size}, got {a_v.size})"
            )
        for name, value in (("a", a), ("dt", dt), ("t", None), ("scale", scale), ("a_v", a_v)):
            object.__setattr__(self, name, value)

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.a.size)

    @property
    def _dt(self) -> float:
        """The sample spacing ``dt``, s, typed as what it is once built."""
        assert self.dt is not None  # __post_init__ stores it, from t when dt was not given
        return self.dt

    @property
    def t_p(self) -> float:
        """End of the record, ``(n - 1) dt``, s."""
        return (self.n - 1) * self._dt

    @property
    def pga(self) -> float:
        """Peak ground acceleration ``scale max|a|``, m/s^2."""
        return self.scale * float(np.max(np.abs(self.a)))

    def scaled(self, factor: float) -> SampledMotion:
        """The same record with its scale multiplied by ``factor`` (``>= 0``); the samples are shared, not copied."""
        factor = check_nonnegative("factor", factor)
        return replace(self, scale=self.scale * factor)

    def scaled_to_pga(self, target: float) -> SampledMotion:
        """The same record scaled so that its peak ground acceleration is ``target`` (m/s^2, ``>= 0``)."""
        target = check_nonnegative("target", target, "m/s^2")
        peak = float(np.max(np.abs(self.a)))
        if peak == 0.0:
            raise ParameterError("scaled_to_pga: every sample is 0, no scale reaches a peak")
        return replace(self, scale=target / peak)

    def acceleration(self, t: ArrayLike) -> float | np.ndarray:
        """Ground acceleration ``sign scale a(t)`` on ``[0, t_p]``, 0 outside, m/s^2 (float for a scalar ``t``)."""
        t = np.asarray(t, dtype=float)
        k = sample_piece(t, self._dt, self.n)
        acc = np.where((t >= 0.0) & (t <= self.t_p), self.sign * self.scale * interpolate(self.a, self._dt, k, t), 0.0)
        return float(acc) if acc.ndim == 0 else acc


# --------------------------------------------------------------------------- #
# One interface: the numbers a run needs                                       #
# --------------------------------------------------------------------------- #

#: The motions the back ends evaluate, by exact type (a subclass may override ``acceleration``: refused).
REGISTRY: dict[type, str] = {
    OneSinePulse: "sine",
    OneCosinePulse: "cosine",
    RickerWavelet: "ricker",
    MavroeidisPapageorgiou: "mp",
    SampledMotion: "sampled",
}

#: Each analytic family's class and the fixed arguments that select it (docs/model.md section 12).
PULSE_TYPES: dict[str, tuple[type, dict]] = {
    "sine": (OneSinePulse, {}),
    "cosine": (OneCosinePulse, {}),
    "ricker": (RickerWavelet, {}),
    "ricker_anti": (RickerWavelet, {"antisymmetric": True}),
    "mp": (MavroeidisPapageorgiou, {}),
}

#: Any motion of :data:`REGISTRY`.
Motion = OneSinePulse | OneCosinePulse | RickerWavelet | MavroeidisPapageorgiou | SampledMotion


@dataclass(frozen=True)
class Description:
    """A motion as numbers: ``ddx_g = a_g f(t)`` on ``[0, t_p]`` (``a_g`` signed), what both back ends run on.

    Attributes
    ----------
    family : str
        One of :data:`FAMILIES`.
    a_g : float
        Signed amplitude (``sign scale`` of a sampled motion), m/s^2.
    omega_g, phase, t_c, shape : float
        The shape's frequency (rad/s), phase (rad), centre (s) and parameter (0 where unused).
    t_p : float
        End of the motion, s.
    T_g : float
        Period ``2 pi / omega_g`` (inf for a sampled motion), for the default steps.
    extrema : ndarray or None
        Extrema of ``f`` in phase units ``omega_g (t - t_c)`` (Ricker, MP), sorted.
    samples : ndarray or None
        The samples (unscaled) of a sampled motion.
    dt : float
        Their spacing, s (0 otherwise).
    a_v : float
        Vertical amplitude, m/s^2, > 0 up: ``ddy_g = a_v f_v(t)`` on ``[0, t_p]`` (0: none;
        docs/model.md section 14).
    phase_v : float
        Lead of the vertical shape: ``f_v(t) = f(t + phase_v / omega_g)`` (analytic motions).
    v_samples : ndarray or None
        A sampled motion's vertical samples (unscaled): ``f_v`` their interpolation.
    """

    family: str
    a_g: float
    omega_g: float = 0.0
    phase: float = 0.0
    t_c: float = 0.0
    shape: float = 0.0
    t_p: float = 0.0
    T_g: float = math.inf
    extrema: np.ndarray | None = None
    samples: np.ndarray | None = None
    dt: float = 0.0
    a_v: float = 0.0
    phase_v: float = 0.0
    v_samples: np.ndarray | None = None


class _Shared(TypedDict, total=False):
    """The fields of a :class:`Description` that a one-sine pulse and the other analytic pulses share."""

    omega_g: float
    t_p: float
    T_g: float
    a_v: float
    phase_v: float


def family_of(motion: object) -> str:
    """The family of ``motion`` if its exact type is registered, else a one-line :class:`ParameterError`."""
    family = REGISTRY.get(type(motion))
    if family is None:
        names = ", ".join(f"rocking.{cls.__name__}" for cls in REGISTRY)
        parents = [cls.__name__ for cls in REGISTRY if isinstance(motion, cls)]
        why = f", a subclass of rocking.{parents[0]}: the back ends run the registered types only" if parents else ""
        raise ParameterError(f"pulse must be one of {names} (got {type(motion).__name__}{why})")
    return family


def describe(motion: object) -> Description:
    """The numbers of ``motion`` that both back ends run on (:class:`Description`).

    Raises
    ------
    ParameterError
        ``motion`` is not exactly one of the registered types (:data:`REGISTRY`).
    """
    family_of(motion)
    if isinstance(motion, SampledMotion):
        return Description(
            "sampled",
            motion.sign * motion.scale,
            t_p=motion.t_p,
            samples=motion.a,
            dt=motion._dt,
            a_v=0.0 if motion.a_v is None else motion.scale,
            v_samples=motion.a_v,
        )
    assert isinstance(motion, (OneSinePulse, _Analytic))  # family_of admits the registered types only
    common: _Shared = {"omega_g": motion.omega_g, "t_p": motion.t_p, "T_g": 2 * math.pi / motion.omega_g}
    if motion.vertical is not None:  # unsigned by the direction (docs/model.md section 14)
        common["a_v"], common["phase_v"] = motion.vertical.ratio * motion.a_g, motion.vertical.phase
    if isinstance(motion, OneSinePulse):
        return Description("sine", motion.sign * motion.a_g, phase=motion.psi, **common)
    extrema = listed_extrema(motion.family, motion.shape_parameter, motion.phase)
    return Description(
        motion.family,
        motion.sign * motion.a_g,
        phase=motion.phase,
        t_c=motion.t_c,
        shape=motion.shape_parameter,
        extrema=extrema,
        **common,
    )


def peak(motion: Motion) -> float:
    """The peak ground acceleration ``max |ddx_g(t)|`` of ``motion``, m/s^2.

    A pulse's amplitude parameter is its peak for the sine, cosine and Ricker families, not for the
    Mavroeidis-Papageorgiou pulse, whose peak depends on ``gamma`` and ``nu``: the peak is the largest
    ``|ddx_g|`` over the ends of the motion and the extrema of its shape (the listed ones, and for the
    trigonometric families every quarter period of the phase), so it is exact, not a sampled estimate.
    """
    d = describe(motion)
    if d.samples is not None:
        return abs(d.a_g) * float(np.max(np.abs(d.samples)))
    quarters = (np.arange(-8, 9) * math.pi / 2 - d.phase) / d.omega_g
    listed = () if d.extrema is None else d.t_c + d.extrema / d.omega_g
    times = np.concatenate(([0.0, d.t_p], quarters, listed))
    return float(np.max(np.abs(motion.acceleration(times[(times >= 0.0) & (times <= d.t_p)]))))
