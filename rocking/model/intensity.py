"""Intensity measures of a ground acceleration sampled at a uniform step, linear between samples.

Every measure is exact for the piecewise-linear acceleration the simulator integrates
(docs/model.md section 12), not an approximation of it by rectangles:

- ``pga``: the peak ground acceleration ``max |a|``, m/s^2;
- ``pgv``: the peak ground velocity ``max |v|``, ``v = int_0^t a``, m/s;
- ``arias``: the Arias intensity ``I_a = pi / (2 g) int a^2 dt``, m/s;
- ``cav``: the cumulative absolute velocity ``int |a| dt``, m/s;
- ``significant_duration``: ``D_5-95``, s, between 5 % and 95 % of ``I_a``;
- ``response_spectrum``: the pseudo-acceleration ``omega^2 max |u|`` of damped linear oscillators,
  m/s^2, from their exact response to the piecewise-linear input (SciPy's first-order-hold
  discretisation of the oscillator, then a linear recursion).

``g`` of the Arias intensity is the standard gravity, 9.80665 m/s^2, unless given.
"""

from __future__ import annotations

import numpy as np

from .params import ParameterError
from .records import STANDARD_GRAVITY

#: The measures a study can scale a record to or plot against, with their units.
MEASURES = {"pga": "m/s^2", "pgv": "m/s", "arias": "m/s", "cav": "m/s"}


def _checked(a, dt) -> tuple[np.ndarray, float]:
    a = np.asarray(a, float)
    if a.ndim != 1 or a.size < 2:
        raise ParameterError(f"a record needs a 1-D array of at least 2 samples (got shape {a.shape})")
    if not np.isfinite(a).all():
        raise ParameterError(f"the sample {int(np.argmax(~np.isfinite(a)))} of the record is not finite")
    if not (np.isfinite(dt) and dt > 0):
        raise ParameterError(f"dt must be > 0 s (got {dt!r})")
    return a, float(dt)


def pga(a, dt) -> float:
    """Peak ground acceleration, m/s^2."""
    a, _ = _checked(a, dt)
    return float(np.max(np.abs(a)))


def velocity(a, dt) -> np.ndarray:
    """Ground velocity at the sample times, m/s, from rest: the exact integral of the linear acceleration."""
    a, dt = _checked(a, dt)
    return np.concatenate([[0.0], np.cumsum(0.5 * dt * (a[1:] + a[:-1]))])


def pgv(a, dt) -> float:
    """Peak ground velocity, m/s (the velocity is extreme where ``a`` changes sign, between samples too)."""
    a, dt = _checked(a, dt)
    v = velocity(a, dt)
    # Where a changes sign inside a step, v has an extremum there: v_k + a_k^2 dt / (2 (a_k - a_k+1)).
    cross = a[:-1] * a[1:] < 0
    inner = v[:-1][cross] + a[:-1][cross] ** 2 * dt / (2 * (a[:-1][cross] - a[1:][cross]))
    return float(max(np.max(np.abs(v)), np.max(np.abs(inner), initial=0.0)))


def arias_curve(a, dt, g: float = STANDARD_GRAVITY) -> np.ndarray:
    """The cumulative Arias intensity at the sample times, m/s: ``pi / (2 g) int_0^t a^2``."""
    a, dt = _checked(a, dt)
    steps = dt * (a[:-1] ** 2 + a[:-1] * a[1:] + a[1:] ** 2) / 3  # exact for a linear a
    return np.pi / (2 * g) * np.concatenate([[0.0], np.cumsum(steps)])


def arias(a, dt, g: float = STANDARD_GRAVITY) -> float:
    """Arias intensity, m/s."""
    return float(arias_curve(a, dt, g)[-1])


def cav(a, dt) -> float:
    """Cumulative absolute velocity ``int |a| dt``, m/s (exact where ``a`` changes sign inside a step)."""
    a, dt = _checked(a, dt)
    left, right = a[:-1], a[1:]
    same = left * right >= 0
    with np.errstate(divide="ignore", invalid="ignore"):
        crossing = dt * (left**2 + right**2) / (2 * (np.abs(left) + np.abs(right)))
    return float(np.sum(np.where(same, 0.5 * dt * (np.abs(left) + np.abs(right)), crossing)))


def significant_duration(a, dt, low: float = 0.05, high: float = 0.95) -> float:
    """``D_5-95`` (by default), s: the time between ``low`` and ``high`` of the Arias intensity."""
    curve = arias_curve(a, dt)
    if not curve[-1] > 0:
        raise ParameterError("a record of zero Arias intensity has no significant duration")
    t = np.arange(curve.size) * dt
    return float(np.interp(high * curve[-1], curve, t) - np.interp(low * curve[-1], curve, t))


def response_spectrum(a, dt, periods, zeta: float = 0.05) -> np.ndarray:
    """Pseudo-spectral acceleration ``omega^2 max |u|``, m/s^2, of oscillators of the ``periods`` (s) and damping
    ratio ``zeta``, at rest at ``t = 0``, under ``u'' + 2 zeta omega u' + omega^2 u = -a``.

    The response to the piecewise-linear ``a`` is exact at the samples (first-order hold); the peak between
    samples is not sought, so periods much shorter than ``10 dt`` are underestimated.
    """
    a, dt = _checked(a, dt)
    periods = np.atleast_1d(np.asarray(periods, float))
    if not (np.isfinite(periods).all() and (periods > 0).all()):
        raise ParameterError(f"periods must be > 0 s (got {periods!r})")
    if not 0 <= zeta < 1:
        raise ParameterError(f"zeta must be in [0, 1) (got {zeta!r})")
    # Imported here: scipy.signal takes about a second to import, paid only by those who use them.
    from scipy import signal

    out = np.empty(periods.size)
    for i, T in enumerate(periods):
        omega = 2 * np.pi / T
        system = (
            np.array([[0.0, 1.0], [-(omega**2), -2 * zeta * omega]]),
            np.array([[0.0], [-1.0]]),
            np.array([[1.0, 0.0]]),
            np.array([[0.0]]),
        )
        A, B, C, D, _ = signal.cont2discrete(system, dt, method="foh")
        _, u, _ = signal.dlsim((A, B, C, D, dt), a[:, None])
        out[i] = omega**2 * np.max(np.abs(u))
    return out


def measure(name: str, a, dt) -> float:
    """The intensity measure ``name`` (one of :data:`MEASURES`) of a record."""
    functions = {"pga": pga, "pgv": pgv, "arias": arias, "cav": cav}
    if name not in functions:
        raise ParameterError(f"measure must be one of {', '.join(MEASURES)} (got {name!r})")
    return functions[name](a, dt)
