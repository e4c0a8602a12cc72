"""One-sine ground acceleration pulse (``docs/model.md`` section 8).

All quantities are in SI units: accelerations in m/s^2, circular frequencies in
rad/s, times in s and phases in rad. Invalid parameters raise
:class:`rocking.model.params.ParameterError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from rocking.model.params import Block, ParameterError, check_block, check_in_range, check_positive, shown
from rocking.model.vertical import Vertical, check_vertical

__all__ = ["OneSinePulse"]


def check_sign(sign: object) -> int:
    """``sign`` if it is the integer +1 or -1 (a direction; bool and float refused)."""
    if not (isinstance(sign, (int, np.integer)) and not isinstance(sign, (bool, np.bool_)) and sign in (1, -1)):
        raise ParameterError(f"sign must be +1 or -1 (got {shown(sign)}): the direction of the pulse")
    return int(sign)


def check_signs(sign: object) -> np.ndarray:
    """``sign`` as an integer array of +1 and -1 (a scalar or an array of directions; bool and float refused)."""
    a = np.asarray(sign)
    if a.dtype.kind not in "iu" or not np.isin(a, (1, -1)).all():
        raise ParameterError(
            f"sign must be +1 or -1, or an array of them (got {shown(sign)}): the direction of the pulse"
        )
    return a.astype(np.int64)


def from_period(cls, a_g: float, T_g: float, **shape):
    """The pulse ``cls`` of period ``T_g = 2 pi / omega_g`` (s); the other arguments as the constructor's.

    The ``from_period`` classmethod of every analytic pulse.
    """
    T_g = check_positive("T_g", T_g, "s")
    return cls(a_g=a_g, omega_g=2 * math.pi / T_g, **shape)


@dataclass(frozen=True)
class OneSinePulse:
    """Ground acceleration ``ddx_g(t) = sign a_g sin(omega_g t + psi)`` on ``[0, t_p]``.

    The pulse lasts ``t_p = (2 pi - psi) / omega_g``, i.e. it runs from the phase
    ``psi`` to the end of one sine cycle, and the ground acceleration is zero
    outside ``[0, t_p]``.

    Parameters
    ----------
    a_g : float
        Amplitude, m/s^2, in [0, 1e5] (10,000 g: beyond any ground motion).
    omega_g : float
        Circular frequency, rad/s, in ``[2 pi / 1000, 2 pi / 0.001]``: sine periods
        from 1 ms to 1000 s (ground-motion pulses last 0.1 - 10 s), which bounds the
        pulse's share of a run.
    psi : float, optional
        Phase at ``t = 0``, rad, in ``[0, 2 pi)``. Default 0.
    sign : {+1, -1}, optional
        Direction: +1 (default) first pushes the ground to the right, ``ddx_g > 0``,
        towards an uplift about ``A``; -1 is the mirrored pulse (docs/model.md 10.6).
    vertical : Vertical, optional
        Vertical component, ``ddy_g = ratio a_g f(t + phase / omega_g)`` on ``[0, t_p]``, > 0 up,
        unsigned by ``sign`` (docs/model.md section 14). Default None: none.

    Raises
    ------
    ParameterError
        If any parameter is non-numeric, non-finite or out of range.

    Notes
    -----
    The ranges are entries of :data:`rocking.model.params.RANGES`; bool and str are
    not numbers.
    """

    a_g: float
    omega_g: float
    psi: float = 0.0
    sign: int = 1
    vertical: Vertical | None = None

    def __post_init__(self) -> None:
        check_sign(self.sign)
        check_vertical(self.vertical)
        a_g = check_in_range("a_g", self.a_g)
        omega_g = check_in_range("omega_g", self.omega_g, label="[2 pi/1000, 2 pi/0.001]")
        psi = check_in_range("psi", self.psi, label="[0, 2 pi)")
        # Frozen dataclass: the normalised floats can only be stored this way.
        for field, value in (("a_g", a_g), ("omega_g", omega_g), ("psi", psi)):
            object.__setattr__(self, field, value)

    @property
    def T_g(self) -> float:
        """Period of the sine, ``T_g = 2 pi / omega_g``, s."""
        return 2 * math.pi / self.omega_g

    @property
    def t_p(self) -> float:
        """Pulse duration ``t_p = (2 pi - psi) / omega_g``, s."""
        return (2 * math.pi - self.psi) / self.omega_g

    def acceleration(self, t: ArrayLike) -> float | np.ndarray:
        """Ground acceleration at time(s) ``t``.

        Parameters
        ----------
        t : float or array_like
            Time(s), s.

        Returns
        -------
        float or numpy.ndarray
            ``ddx_g(t)``, m/s^2; a float for scalar ``t``, otherwise an array of the
            shape of ``t``.
        """
        t = np.asarray(t, dtype=float)
        active = (t >= 0.0) & (t <= self.t_p)
        acc = np.where(active, self.sign * self.a_g * np.sin(self.omega_g * t + self.psi), 0.0)
        return float(acc) if acc.ndim == 0 else acc

    from_period = classmethod(from_period)

    def beta(self, block: Block) -> float:
        """Amplitude ratio ``beta = a_g / (g tan(alpha))`` for ``block``."""
        return block.beta(self.a_g)

    def Omega(self, block: Block) -> float:
        """Frequency ratio ``Omega = omega_g / p`` for ``block``."""
        return self.omega_g / block.p

    @classmethod
    def from_nondim(
        cls,
        block: Block,
        *,
        beta: float,
        Omega: float,
        psi: float = 0.0,
        sign: int = 1,
        vertical: Vertical | None = None,
    ) -> OneSinePulse:
        """Build a pulse scaled to ``block``.

        Parameters
        ----------
        block : Block
            Block that sets the scales ``g tan(alpha)`` and ``p``.
        beta : float
            Amplitude ratio ``a_g / (g tan(alpha))``, in [0, 1e4]; ``beta = 1`` is the
            static uplift threshold of the bare symmetric block. ``a_g`` must also lie
            in the range of :class:`OneSinePulse`.
        Omega : float
            Frequency ratio ``omega_g / p``, in [0.01, 1000] (the studies use 0.5 - 15);
            ``omega_g`` must also lie in the range of :class:`OneSinePulse` (periods of
            1 ms to 1000 s).
        psi : float, optional
            Phase at ``t = 0``, rad, in ``[0, 2 pi)``. Default 0.
        sign : {+1, -1}, optional
            Direction of the pulse (see :class:`OneSinePulse`). Default +1.
        vertical : Vertical, optional
            Vertical component (see :class:`OneSinePulse`). Default None.

        Returns
        -------
        OneSinePulse
            Pulse with ``a_g = beta g tan(alpha)`` and ``omega_g = Omega p``.

        Raises
        ------
        ParameterError
            If any value is out of range.
        """
        check_block(block)
        check_sign(sign)
        beta = check_in_range("beta", beta)
        Omega = check_in_range("Omega", Omega)
        try:
            return cls(a_g=block.a_g(beta), omega_g=Omega * block.p, psi=psi, sign=sign, vertical=vertical)
        except ParameterError as exc:
            if str(exc).startswith(("a_g ", "omega_g ")):  # derived from beta and Omega: say so
                raise ParameterError(
                    f"beta = {beta!r}, Omega = {Omega!r} on this block (g tan(alpha) = "
                    f"{block.a_g(1.0):g} m/s^2, p = {block.p:g} rad/s) give {exc}"
                ) from None
            raise
