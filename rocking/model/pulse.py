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

from rocking.model.params import (
    Block,
    check_interval,
    check_nonnegative,
    check_positive,
)

__all__ = ["OneSinePulse"]


@dataclass(frozen=True)
class OneSinePulse:
    """Ground acceleration ``ddx_g(t) = a_g sin(omega_g t + psi)`` on ``[0, t_p]``.

    The pulse lasts ``t_p = (2 pi - psi) / omega_g``, i.e. it runs from the phase
    ``psi`` to the end of one sine cycle, and the ground acceleration is zero
    outside ``[0, t_p]``.

    Parameters
    ----------
    a_g : float
        Amplitude, m/s^2 (>= 0).
    omega_g : float
        Circular frequency, rad/s (> 0).
    psi : float, optional
        Phase at ``t = 0``, rad, in ``[0, 2 pi)``. Default 0.

    Raises
    ------
    ParameterError
        If any parameter is non-numeric, non-finite or out of range.
    """

    a_g: float
    omega_g: float
    psi: float = 0.0

    def __post_init__(self) -> None:
        a_g = check_nonnegative("a_g", self.a_g, "m/s^2")
        omega_g = check_positive("omega_g", self.omega_g, "rad/s")
        psi = check_interval("psi", self.psi, 0.0, 2 * math.pi, "rad", closed_low=True, label="[0, 2 pi)")
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
        acc = np.where(active, self.a_g * np.sin(self.omega_g * t + self.psi), 0.0)
        return float(acc) if acc.ndim == 0 else acc

    def beta(self, block: Block) -> float:
        """Amplitude ratio ``beta = a_g / (g tan(alpha))`` for ``block``."""
        return self.a_g / (block.g * block.tan_alpha)

    def Omega(self, block: Block) -> float:
        """Frequency ratio ``Omega = omega_g / p`` for ``block``."""
        return self.omega_g / block.p

    @classmethod
    def from_nondim(cls, block: Block, *, beta: float, Omega: float, psi: float = 0.0) -> OneSinePulse:
        """Build a pulse scaled to ``block``.

        Parameters
        ----------
        block : Block
            Block that sets the scales ``g tan(alpha)`` and ``p``.
        beta : float
            Amplitude ratio ``a_g / (g tan(alpha))`` (>= 0); ``beta = 1`` is the
            static uplift threshold of the bare symmetric block.
        Omega : float
            Frequency ratio ``omega_g / p`` (> 0).
        psi : float, optional
            Phase at ``t = 0``, rad, in ``[0, 2 pi)``. Default 0.

        Returns
        -------
        OneSinePulse
            Pulse with ``a_g = beta g tan(alpha)`` and ``omega_g = Omega p``.

        Raises
        ------
        ParameterError
            If any value is out of range.
        """
        beta = check_nonnegative("beta", beta)
        Omega = check_positive("Omega", Omega)
        return cls(a_g=beta * block.g * block.tan_alpha, omega_g=Omega * block.p, psi=psi)
