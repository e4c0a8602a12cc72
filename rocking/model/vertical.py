"""The vertical component of a ground motion (docs/model.md section 14), and where the model ends.

The vertical ground acceleration ``ddy_g`` is positive **up**; it adds to gravity, and the
block feels the effective gravity ``g + ddy_g``. An analytic pulse carries it as a
:class:`Vertical`: ``ddy_g(t) = ratio a_g f(t + phase / omega_g)`` on the pulse's own
``[0, t_p]``, the horizontal family's shape ``f`` at the same period, ``phase`` ahead, and
**unsigned** by the pulse's direction: a pulse of sign -1 has the same vertical component as
that of sign +1 (the direction mirrors the horizontal motion, docs/model.md 10.6, and the
mirror leaves the vertical unchanged). A sampled motion carries vertical samples
(``SampledMotion(a_v=...)``).

Where ``g + ddy_g(t) <= 0`` the base may leave the ground: free flight is out of scope, and a
run ends at :func:`flight_time` with the status ``flight``.

Units SI: m/s^2, s, rad.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .checks import ParameterError, check_in_range

#: Points per unit of phase where ``g + ddy_g`` is scanned for its first zero (as the MP extrema's scan).
FLIGHT_SCAN = 64


@dataclass(frozen=True)
class Vertical:
    """The vertical component of an analytic pulse: ``ddy_g = ratio a_g f(t + phase / omega_g)`` on ``[0, t_p]``.

    Parameters
    ----------
    ratio : float
        Vertical amplitude over the horizontal ``a_g``, in [0, 10].
    phase : float, optional
        Lead of the vertical shape over the horizontal one, rad, in [0, 2 pi); default 0, in phase.

    Raises
    ------
    ParameterError
        If either is out of range (naming it).
    """

    ratio: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        # Frozen dataclass: the normalised floats can only be stored this way.
        object.__setattr__(self, "ratio", check_in_range("ratio", self.ratio, "vertical_ratio"))
        object.__setattr__(self, "phase", check_in_range("phase", self.phase, "psi"))


def flight_time(vertical: Callable[[np.ndarray], np.ndarray], g: float, t_p: float, omega: float, dt: float) -> float:
    """The first time in ``[0, t_p]`` where ``g + vertical(t) <= 0``, s; ``inf`` if none.

    Parameters
    ----------
    vertical : callable
        ``ddy_g(t)`` on arrays of times inside ``[0, t_p]``, m/s^2.
    g : float
        Gravity, m/s^2.
    t_p : float
        End of the motion, s.
    omega : float
        The shape's circular frequency (rad/s), for the scan of an analytic shape; 0 for samples.
    dt : float
        The spacing of a sampled motion (its pieces are linear: each zero is exact), 0 otherwise.
    """
    from scipy.optimize import brentq  # here: SciPy is imported by the runs, not by ``import rocking``

    step = dt if dt > 0.0 else 1.0 / (FLIGHT_SCAN * omega)
    t = np.linspace(0.0, t_p, int(math.ceil(t_p / step)) + 1)
    lift = g + np.asarray(vertical(t), dtype=float)
    below = np.flatnonzero(lift <= 0.0)
    if below.size == 0:
        return math.inf
    i = int(below[0])
    if i == 0:
        return 0.0
    if dt > 0.0:  # linear between samples: the zero itself
        return float(t[i - 1] + (t[i] - t[i - 1]) * lift[i - 1] / (lift[i - 1] - lift[i]))
    return float(brentq(lambda x: g + float(vertical(np.asarray(x))), t[i - 1], t[i], xtol=1e-15))


def check_vertical(vertical: object) -> Vertical | None:
    """``vertical`` if it is a :class:`Vertical` or ``None``, else a one-line :class:`ParameterError`."""
    if vertical is not None and type(vertical) is not Vertical:
        raise ParameterError(f"vertical must be a rocking.Vertical or None (got {type(vertical).__name__})")
    return vertical
