"""The floor the block stands on: Coulomb friction, static and kinetic (docs/model.md section 15).

``mu_s = mu_k = inf`` is the paper's floor, on which the base never slides: the default of every
run and study. Both coefficients are dimensionless.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .checks import RANGES, ParameterError, as_real, check_in_range, shown

__all__ = ["PAPER_FLOOR", "Floor", "check_pair", "floor_of"]

#: Why a finite kinetic coefficient needs a finite static one.
_NO_KINETIC = "a floor that never lets the base start sliding (mu_s = inf) has no kinetic friction to follow"


def _coefficient(name: str, value: object, high: str = "inf") -> float:
    """``value`` as a float in ``RANGES["mu"]`` (``(0, inf]``), else a one-line :class:`ParameterError`."""
    valid = RANGES["mu"]
    x = as_real(name, value, f"in (0, {high}]")
    if not valid.holds(x):
        raise ParameterError(f"{name} must be in (0, {high}] (got {shown(value)}): {valid.why}")
    return x


def check_pair(mu_s, mu_k) -> None:
    """Refuse a kinetic coefficient above the static one, or finite beside ``mu_s = inf`` (elementwise).

    ``mu_s`` and ``mu_k`` (numbers or arrays, each already in ``(0, inf]``) must satisfy
    ``mu_k <= mu_s``, with ``mu_k = inf`` when ``mu_s = inf``.

    Raises
    ------
    ParameterError
        Naming ``mu_k``, its range and the first offending pair.
    """
    s, k = np.broadcast_arrays(np.asarray(mu_s, dtype=float), np.asarray(mu_k, dtype=float))
    above = ~(k <= s)
    if np.any(above):
        i = np.flatnonzero(above.ravel())[0]
        low, high = float(s.ravel()[i]), float(k.ravel()[i])
        raise ParameterError(
            f"mu_k must be in (0, mu_s] = (0, {low!r}] (got {high!r}): Coulomb's kinetic friction does not exceed "
            "the static"
        )
    lone = np.isinf(s) & np.isfinite(k)
    if np.any(lone):
        raise ParameterError(f"mu_k must be inf when mu_s is inf (got {float(k[lone].ravel()[0])!r}): {_NO_KINETIC}")


@dataclass(frozen=True)
class Floor:
    """A floor with Coulomb friction (docs/model.md section 15); dimensionless coefficients.

    Parameters
    ----------
    mu_s : float, optional
        Static coefficient, in ``(0, inf]``; default ``inf``: the base never slides (the paper's floor).
    mu_k : float, optional
        Kinetic coefficient, in ``(0, mu_s]``; default ``mu_s``. Finite only with a finite ``mu_s``.
    e_n : float, optional
        Normal restitution of a landing after flight, in ``[0, 1]`` (docs/model.md section 16); default 0: plastic.

    Raises
    ------
    ParameterError
        A coefficient out of its range, NaN or no real number (one line naming it and the range).

    Examples
    --------
    >>> import rocking
    >>> rocking.Floor(0.3)
    Floor(mu_s=0.3, mu_k=0.3, e_n=0.0)
    >>> rocking.Floor().slides
    False
    """

    mu_s: float = math.inf
    mu_k: float | None = None
    e_n: float = 0.0

    def __post_init__(self) -> None:
        mu_s = _coefficient("mu_s", self.mu_s)
        mu_k = mu_s if self.mu_k is None else _coefficient("mu_k", self.mu_k, "mu_s")
        check_pair(mu_s, mu_k)
        object.__setattr__(self, "mu_s", mu_s)
        object.__setattr__(self, "mu_k", mu_k)
        object.__setattr__(self, "e_n", check_in_range("e_n", self.e_n))

    @property
    def slides(self) -> bool:
        """The base may slide: ``mu_s`` is finite."""
        return math.isfinite(self.mu_s)

    def settings(self) -> dict[str, float]:
        """The fields ``mu_s``, ``mu_k`` and ``e_n`` of a run (:data:`rocking.sim.boundary.CASE`)."""
        mu_k = self.mu_s if self.mu_k is None else self.mu_k  # never None once built
        return {"mu_s": self.mu_s, "mu_k": mu_k, "e_n": self.e_n}


def check_model_floor(mu_s, model) -> None:
    """Refuse a finite ``mu_s`` (any element of a batch's column) on a model without the phases of a floor with
    friction: its spec does not say ``[ground] friction = true`` (manifest ``"friction"``).

    Raises
    ------
    ParameterError
        Naming the model and the floor it takes.
    """
    mu_s = np.asarray(mu_s, dtype=float)
    if np.all(np.isinf(mu_s)) or model.manifest.get("friction", False):
        return
    shown_mu = float(mu_s[np.isfinite(mu_s)].ravel()[0])
    raise ParameterError(
        f"mu_s = {shown_mu:g}: model {model.name!r} has no phases of a floor with friction (its spec does not say "
        "[ground] friction = true); mu = inf is the only floor it takes"
    )


def floor_of(floor: object = None, mu: float | None = None, mu_k: float | None = None) -> Floor:
    """The :class:`Floor` of a call given ``floor=``, or its shorthand ``mu=`` (with ``mu_k=``), or neither.

    Raises
    ------
    ParameterError
        Both given, ``mu_k`` without ``mu``, or ``floor`` no :class:`Floor`.
    """
    if floor is not None:
        if mu is not None or mu_k is not None:
            raise ParameterError("give floor= or its shorthand mu= (with mu_k=), not both")
        if not isinstance(floor, Floor):
            raise ParameterError(f"floor must be a rocking.Floor or None (got {shown(floor)})")
        return floor
    if mu is None:
        if mu_k is not None:
            raise ParameterError("mu_k is the kinetic friction beside mu=: give mu (the static) too")
        return PAPER_FLOOR
    return Floor(mu, mu_k)


#: The paper's floor: the base never slides.
PAPER_FLOOR = Floor()
