"""Pure sliding of a rigid block on a floor with Coulomb friction, in closed form (docs/model.md section 15).

A block that never lifts, standing on a floor with friction coefficients ``mu_s >= mu_k``, under the
one-sine pulse ``ddx_g(t) = sign a_g sin(omega_g t)`` on ``[0, 2 pi / omega_g]`` (0 after). Its slip
``u`` (the base's displacement relative to the ground, m) sticks while the friction needed,
``|ddx_g|`` per unit mass, is within ``mu_s g``, and slides with

    ddu = -ddx_g - mu_k g sign(du)

otherwise (model.md section 15, fact (b)). Within an episode that starts at ``t0`` with ``du = 0``
in the direction ``d``, both the slip speed and the slip are closed forms:

    du(t) = -(a/omega) (cos(omega t0) - cos(omega t)) - mu_k g d (t - t0)
    u(t)  = u(t0) - (a/omega) cos(omega t0) (t - t0) + (a/omega^2) (sin(omega t) - sin(omega t0))
            - mu_k g d (t - t0)^2 / 2

(``a = sign a_g``), and after the pulse the slip speed falls linearly to 0. The only numerical step
is the instant an episode ends, a root of ``du`` (Brent's method, to 1e-15 s). This module is
independent of SymPy and of the simulator: the yardstick a sliding model is held against, and an
outside fact of its own (an independent sliding-only model gives 31.45 mm peak and 1.57 mm residual
slip for ``a_g = 0.4 g``, ``T = 0.5 s``, ``mu = 0.2``: issue 37).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..model.checks import ParameterError
from . import paper

#: Points per pulse of the scan that brackets the end of an episode before Brent's method refines it.
SCAN_POINTS = 4096


@dataclass(frozen=True)
class Sliding:
    """A pure-sliding response.

    Attributes
    ----------
    t_start : float
        First instant of slip, s (``nan`` if the block never slides).
    u_max : float
        Peak slip ``max |u|``, m.
    u_end : float
        Residual slip once the block sticks for good, m.
    slides : int
        Slip episodes (a reversal of the slip starts a new one).
    t_end : float
        Instant the block sticks for good, s.
    """

    t_start: float
    u_max: float
    u_end: float
    slides: int
    t_end: float


def _check(name: str, value: float, low: float, high: float) -> float:
    """``value`` as a float if it is finite and in ``[low, high]``, else a one-line ParameterError."""
    v = float(value)
    if not (np.isfinite(v) and low <= v <= high):
        raise ParameterError(f"{name} must be in [{low:g}, {high:g}] (got {value!r})")
    return v


def first_slip(a_g: float, omega_g: float, mu_s: float, g: float, t: float) -> float | None:
    """The first instant ``>= t`` within the pulse at which ``|a_g sin(omega_g t)|`` exceeds ``mu_s g``.

    ``None`` when it never does before the pulse ends.
    """
    ratio = mu_s * g / abs(a_g)
    if ratio >= 1.0:
        return None
    if abs(a_g * np.sin(omega_g * t)) > mu_s * g:
        return t
    # |sin| = ratio on its way up at k pi + asin(ratio): the start time asin(mu_s g / a_g) / omega_g first.
    rising = (k * np.pi + np.arcsin(ratio) for k in range(2))
    later = [phase / omega_g for phase in rising if t <= phase / omega_g <= 2.0 * np.pi / omega_g]
    return min(later) if later else None


def one_sine_sliding(
    a_g: float, omega_g: float, mu_s: float, mu_k: float | None = None, g: float = 9.81, sign: int = 1
) -> Sliding:
    """Pure sliding of a block at rest under the one-sine pulse, in closed form.

    Parameters
    ----------
    a_g : float
        Pulse amplitude, m/s^2, in (0, 1e3].
    omega_g : float
        Pulse circular frequency, rad/s, in (0, 1e4].
    mu_s, mu_k : float
        Static and kinetic friction coefficients, ``0 < mu_k <= mu_s <= 10``; ``mu_k`` defaults to ``mu_s``.
    g : float
        Gravity, m/s^2.
    sign : {1, -1}
        Direction of the pulse's first half.

    Returns
    -------
    Sliding
    """
    a_g = _check("a_g", a_g, 1e-12, 1e3)
    omega_g = _check("omega_g", omega_g, 1e-6, 1e4)
    mu_s = _check("mu_s", mu_s, 1e-9, 10.0)
    mu_k = mu_s if mu_k is None else _check("mu_k", mu_k, 1e-9, mu_s)
    if sign not in (1, -1):
        raise ParameterError(f"sign must be 1 or -1 (got {sign!r})")
    a, w, T = sign * a_g, omega_g, 2.0 * np.pi / omega_g
    t, u, u_max, slides, t_start = 0.0, 0.0, 0.0, 0, np.nan
    while (t0 := first_slip(a, w, mu_s, g, t)) is not None:
        d = -np.sign(a * np.sin(w * t0))  # the block lags the ground
        slides += 1
        t_start = t0 if slides == 1 else t_start
        t, u = _episode(a, w, mu_k * g, d, t0, u, T)
        u_max = max(u_max, abs(u))
        if t >= T:
            break
    return Sliding(t_start=t_start, u_max=u_max, u_end=u, slides=slides, t_end=t)


def _episode(a: float, w: float, friction: float, d: float, t0: float, u0: float, T: float) -> tuple[float, float]:
    """The end of a slip episode that starts at ``t0`` in the direction ``d``: its instant and the slip then.

    ``friction`` is ``mu_k g``. The slip speed is a closed form (module docstring); its root is bracketed on
    a scan of :data:`SCAN_POINTS` points per pulse and refined by Brent's method.
    """

    def speed(t: float) -> float:
        return -(a / w) * (np.cos(w * t0) - np.cos(w * t)) - friction * d * (t - t0)

    def slip(t: float) -> float:
        return (
            u0
            - (a / w) * np.cos(w * t0) * (t - t0)
            + (a / w**2) * (np.sin(w * t) - np.sin(w * t0))
            - friction * d * (t - t0) ** 2 / 2
        )

    grid = np.linspace(t0, T, max(2, int(SCAN_POINTS * (T - t0) / T) + 1))[1:]
    ahead = d * np.array([speed(t) for t in grid])
    stopped = np.flatnonzero(ahead <= 0.0)
    if stopped.size:
        from scipy.optimize import brentq  # here: the command's parser imports this module, and SciPy costs 0.3 s

        i = stopped[0]
        t1 = brentq(lambda t: d * speed(t), grid[i - 1] if i else t0 + 1e-15, grid[i], xtol=1e-15, rtol=1e-15)
        return t1, slip(t1)
    v = speed(T)  # still sliding at the pulse's end: the friction alone stops it
    t1 = T + abs(v) / friction
    return t1, slip(T) + v * (t1 - T) - friction * d * (t1 - T) ** 2 / 2


def slide_rock_frame_accel(s, theta, dtheta, ag, mu_slip, M, I_G, B, H, e, g):
    """The bare block rocking about ``s`` while its pivot slides: ``ddx_g + ddu``, typed by hand.

    docs/model.md section 15: with ``P = H/2 cos(theta) + d_s sin(theta)``, ``Q = d_s cos(theta) - H/2 sin(theta)``
    and ``a = ddx_g + ddu`` (the pivot's absolute acceleration), Housner's equation
    ``I_s ddtheta = M a P - M g Q``, the shear ``V_b = M (a - P ddtheta - Q dtheta^2)``, the normal force
    ``N_b = M (g + Q ddtheta - P dtheta^2)`` and Coulomb's ``V_b = -mu_slip N_b`` give

        a = [(Q + mu_slip P) dtheta^2 - mu_slip g + (mu_slip Q - P) M g Q / I_s] / [1 + (mu_slip Q - P) M P / I_s].
    """
    d = s * B / 2 + e
    I_s = I_G + M * (d**2 + H**2 / 4)
    P = H / 2 * np.cos(theta) + d * np.sin(theta)
    Q = d * np.cos(theta) - H / 2 * np.sin(theta)
    top = (Q + mu_slip * P) * dtheta**2 - mu_slip * g + (mu_slip * Q - P) * M * g * Q / I_s
    return top / (1 + (mu_slip * Q - P) * M * P / I_s)


def contact_slide_frame_accel(x, dx, mu_slip, M, g, m, k_m, c, **stops):
    """The block with its damper in full contact while its base slides: ``ddx_g + ddu``, typed by hand.

    docs/model.md section 15: the mass follows (C1) in the sliding frame, ``m (a + ddx) = -G(x, dx)``, so
    the shear is ``V_b = M a - G(x, dx)``; with ``N_b = (M + m) g`` Coulomb's ``V_b = -mu_slip N_b`` gives
    ``a = (G(x, dx) - mu_slip (M + m) g) / M``. ``G`` is :func:`paper.guide_force`, the bumpers' with ``stops``.
    """
    return (paper.guide_force(x, dx, k_m, c, **stops) - mu_slip * (M + m) * g) / M


def _loaded(m, ddx):
    """``ddx`` where the mass has one; 0 where it is 0 (the bare block), whose ``ddx`` is 0 / 0 and carries no load."""
    return np.where(m == 0, 0.0, ddx)


def stick_force(s, theta, x, dtheta, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c, **stops):
    """``(F, N)`` the floor holds while rocking about a sticking pivot ``s``: section 13's ``(V_b, N_b)`` at the
    accelerations of (R1)-(R2) (:func:`paper.rocking_accel`, :func:`paper.base_reaction`, typed by hand)."""
    ddtheta, ddx = paper.rocking_accel(s, theta, x, dtheta, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c, **stops)
    V, N, _ = paper.base_reaction(s, theta, x, dtheta, dx, ddtheta, _loaded(m, ddx), ag, agy, M, I_G, B, H, e, g, m, h)
    return V, N


def contact_stick_force(x, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c, **stops):
    """``(F, N)`` the floor holds in full contact with the base stuck: section 13's ``(V_b, N_b)`` at
    ``theta = dtheta = ddtheta = 0`` and the mass's (C1), ``F = M ddx_g - G(x, dx)``, ``N = (M + m)(g + ddy_g)``."""
    zero = 0 * x
    ddx = paper.contact_accel(x, dx, ag, m, k_m, c, **stops)
    V, N, _ = paper.base_reaction(1, zero, x, zero, dx, zero, _loaded(m, ddx), ag, agy, M, I_G, B, H, e, g, m, h)
    return V, N


def slide_rock_accel(s, theta, x, dtheta, dx, ag, agy, mu_slip, M, I_G, B, H, e, g, m, h, k_m, c, **stops):
    """Rocking about ``s`` while the pivot slides, with the damper: ``(ddtheta, ddx, ddu, N)``, typed by hand.

    docs/model.md section 15: (R1)-(R2) with the frame accelerated by ``a = ddx_g + ddu``
    (:func:`paper.rocking_accel`), section 13's shear and normal force at those accelerations
    (:func:`paper.base_reaction`), and Coulomb's ``V_b + mu_slip N_b = 0``. The balance is affine in ``ddu``
    (the accelerations are affine in ``a``, the reactions in ``a`` and the accelerations): its values at
    ``ddu = 0`` and ``ddu = 1`` give its root. For the bare block (``m = 0``) this is
    :func:`slide_rock_frame_accel`.
    """

    def at(ddu):
        a = ag + ddu
        ddtheta, ddx = paper.rocking_accel(s, theta, x, dtheta, dx, a, agy, M, I_G, B, H, e, g, m, h, k_m, c, **stops)
        V, N, _ = paper.base_reaction(
            s, theta, x, dtheta, dx, ddtheta, _loaded(m, ddx), a, agy, M, I_G, B, H, e, g, m, h
        )
        return V + mu_slip * N, ddtheta, ddx, N

    r0, r1 = at(0.0)[0], at(1.0)[0]
    ddu = -r0 / (r1 - r0)
    _, ddtheta, ddx, N = at(ddu)
    return ddtheta, ddx, ddu, N


def contact_slide_accel(x, dx, ag, agy, mu_slip, M, g, m, k_m, c, **stops):
    """Full contact while the base slides: ``(0, ddx, ddu, N)``, typed by hand.

    docs/model.md section 15: ``a`` of :func:`contact_slide_frame_accel` (gravity ``g + ddy_g``, section 14), the
    mass's (C1) at ``a`` (:func:`paper.contact_accel`), ``ddu = a - ddx_g`` and ``N = (M + m)(g + ddy_g)``.
    """
    a = contact_slide_frame_accel(x, dx, mu_slip, M, g + agy, m, k_m, c, **stops)
    return 0 * x, paper.contact_accel(x, dx, a, m, k_m, c, **stops), a - ag, (M + m) * (g + agy)


def horizontal_momentum(s, theta, x, dtheta, dx, M, B, H, e, m, h):
    """``P_x``: the horizontal momentum of the block and the mass relative to the contact, from their positions.

    docs/model.md sections 1 and 15: from the pivot ``s``, ``X_G = -s B/2 + d_s cos(theta) - H/2 sin(theta)`` and
    ``X_m = -s B/2 + xi_s cos(theta) - eta sin(theta)`` (``xi_s' = dx``), so
    ``P_x = -M dtheta (d_s sin + H/2 cos) + m (dx cos - dtheta (xi_s sin + eta cos))``.
    """
    d, xi = paper.arms(s, x, B, e)
    sin, cos = np.sin(theta), np.cos(theta)
    return -M * dtheta * (d * sin + H / 2 * cos) + m * (dx * cos - dtheta * (xi * sin + (H + h) * cos))


def slip_energy(s, theta, x, dtheta, dx, du, M, B, H, e, m, h):
    """The kinetic energy the slip speed ``du`` adds: ``du P_x + (M + m) du^2 / 2`` (docs/model.md section 15).

    Every body's horizontal velocity gains ``du``, so ``sum m (v + du)^2 / 2 - sum m v^2 / 2`` is this, with
    :func:`horizontal_momentum`; the rotation's energy does not change.
    """
    return du * horizontal_momentum(s, theta, x, dtheta, dx, M, B, H, e, m, h) + (M + m) * du**2 / 2


def friction_impact(s, x, dtheta, dx, du, mu_slip, M, I_G, B, H, e, m, h, stick=True):
    """The impact of the corner ``-s`` at ``theta = 0`` with the damper, on a floor with friction, typed by hand.

    docs/model.md section 15, Newton and Euler with impulses. Before it the old pivot moves at ``(du, 0)``:
    ``G`` at ``(d_s, H/2)`` from it moves at ``(du - H/2 dtheta, d_s dtheta)``, the mass at ``(xi_s, eta)``
    at ``(du - eta dtheta + dx, xi_s dtheta)``. The floor's impulse ``(P_t, P_n)`` acts on the new corner alone,
    at ``r = (s B - d_s, -H/2)`` from ``G``; the guide's on the mass is normal to it (vertical), so the mass keeps
    its absolute horizontal momentum (the momentum law, (I2)). Then the system's momentum
    ``M dvG + m dvm = (P_t, P_n)``, its angular momentum about the new corner (the floor's impulse has no
    moment there) is kept, the corner's normal velocity after is 0, and it sticks (``du+ = 0``) or slides
    (``P_t = -mu_slip P_n``). Every balance is affine in ``omega+``: two evaluations give it.

    Returns
    -------
    tuple
        ``(dtheta+, dx+, du+, P_t, P_n)``; ``du+`` is the base's slip speed after (every point of the base moves
        alike at ``theta = 0``).
    """
    d, xi = paper.arms(s, x, B, e)
    eta = H + h
    rx, ry = s * B - d, -H / 2
    vGx, vGy = du - dtheta * H / 2, dtheta * d
    vmx, vmy = vGx - dtheta * (eta - H / 2) + dx, vGy + dtheta * (x - e)

    def after(w):
        """Velocities and impulses after the impact at ``omega+ = w``, and the angular momentum balance's residue."""
        gy = -w * rx  # the new corner's normal velocity is 0
        my = gy + w * (x - e)  # the mass is carried vertically by the block
        P_n = M * (gy - vGy) + m * (my - vmy)
        gx = -w * H / 2 if stick else vGx - mu_slip * P_n / M  # the mass keeps its own horizontal momentum
        # Angular momentum about the new corner: G at (-rx, -ry) from it, the mass at (x - s B/2, eta), whose
        # horizontal velocity does not change.
        residue = I_G * (w - dtheta) + M * (-rx * (gy - vGy) + ry * (gx - vGx)) + m * (x - s * B / 2) * (my - vmy)
        return residue, gx, P_n

    r0, r1 = after(0.0)[0], after(1.0)[0]
    w = -r0 / (r1 - r0)
    _, gx, P_n = after(w)
    dx_plus = vmx - (gx - w * (eta - H / 2))
    return w, dx_plus, gx - w * ry, M * (gx - vGx), P_n


def corner_impact(s, dtheta, du, mu_slip, M, I_G, B, H, e, stick=True):
    """The bare block's impact of the corner ``-s`` at ``theta = 0`` on a floor with friction, typed by hand.

    docs/model.md section 15, Newton and Euler with impulses: ``G`` is at ``(d_s, H/2)`` from the old pivot, which
    moves at ``(du, 0)``; the new corner is at ``(s B - d_s, -H/2)`` from ``G``. Unknowns ``vG+``, ``omega+`` and
    the floor's impulse ``(P_t, P_n)`` on the corner: ``M (vG+ - vG-) = P``,
    ``I_G (omega+ - omega-) = (s B - d_s) P_n + H/2 P_t``, the corner's normal velocity after is 0 and either its
    slip is 0 (``stick``) or ``P_t = -mu_slip P_n``. Returns ``(omega+, du+, P_t, P_n)``, ``du+`` the corner's
    slip speed after.
    """
    d = s * B / 2 + e
    rx, ry = s * B - d, -H / 2
    vGx, vGy = du - dtheta * H / 2, dtheta * d
    # Rows: momentum x, y, angular momentum about G, normal velocity, closure. Unknowns: vGx+, vGy+, w+, P_t, P_n.
    A = np.array(
        [
            [M, 0, 0, -1, 0],
            [0, M, 0, 0, -1],
            [0, 0, I_G, ry, -rx],
            [0, 1, rx, 0, 0],
            [1, 0, -ry, 0, 0] if stick else [0, 0, 0, 1, mu_slip],
        ],
        dtype=float,
    )
    b = np.array([M * vGx, M * vGy, I_G * dtheta, 0.0, 0.0])
    vx, _, w, P_t, P_n = np.linalg.solve(A, b)
    return w, vx - w * ry, P_t, P_n


@dataclass(frozen=True)
class SlideRock:
    """A response of the bare block on a floor with friction (:func:`slide_rock`).

    Attributes
    ----------
    theta_max : float
        Peak ``|theta|``, rad.
    u_max, u_end : float
        Peak and final ``|u|`` and ``u`` of the contact's slip, m.
    slides, uplifts, impacts : int
        Slip episodes, uplifts from full contact, impacts.
    status : str
        ``"rest"`` (full contact, sticking, after the motion), ``"overturned"``, ``"flight"`` (the normal force
        reached 0: out of this model) or ``"t_max"``.
    t_end : float
        Instant the run ended, s.
    first : str
        How the block first left rest: ``"slides"``, ``"rocks"`` or ``"none"``.
    """

    theta_max: float
    u_max: float
    u_end: float
    slides: int
    uplifts: int
    impacts: int
    status: str
    t_end: float
    first: str = "none"


@dataclass(frozen=True)
class _Block:
    """The bare block's numbers and the motion: ``ddx_g = a sin(w t)`` on ``[0, T]``, followed to ``T + t_after``."""

    M: float
    I_G: float
    B: float
    H: float
    e: float
    g: float
    a: float
    w: float
    mu_s: float
    mu_k: float
    t_after: float

    @property
    def T(self) -> float:
        return 2 * np.pi / self.w

    @property
    def t_max(self) -> float:
        return self.T + self.t_after

    def ag(self, t: float) -> float:
        return self.a * np.sin(self.w * t) if t < self.T else 0.0

    def arms(self, s: int, theta: float) -> tuple[float, float, float]:
        """``(P, Q, I_s)`` of the rocking phase about ``s`` (docs/model.md section 15)."""
        d = s * self.B / 2 + self.e
        P = self.H / 2 * np.cos(theta) + d * np.sin(theta)
        Q = d * np.cos(theta) - self.H / 2 * np.sin(theta)
        return P, Q, self.I_G + self.M * (d**2 + self.H**2 / 4)

    def rocking(self, s: int, theta: float, dtheta: float, a: float) -> tuple[float, float, float]:
        """``ddtheta`` about ``s`` with the pivot accelerated by ``a``, and the floor's ``(V_b, N_b)``."""
        P, Q, I_s = self.arms(s, theta)
        ddtheta = self.M * (a * P - self.g * Q) / I_s
        return ddtheta, self.M * (a - P * ddtheta - Q * dtheta**2), self.M * (self.g + Q * ddtheta - P * dtheta**2)

    def pivot_accel(self, s: int, sigma: int, t: float, theta: float, dtheta: float) -> float:
        """The pivot's absolute acceleration: the ground's while it sticks (``sigma = 0``), else Coulomb's."""
        if sigma == 0:
            return self.ag(t)
        if s == 0:
            return -sigma * self.mu_k * self.g
        return slide_rock_frame_accel(
            s, theta, dtheta, self.ag(t), sigma * self.mu_k, self.M, self.I_G, self.B, self.H, self.e, self.g
        )

    def uplift(self, s: int, a: float) -> float:
        """Section 5's margin about ``s`` of the bare block in full contact, the base accelerated by ``a``."""
        return s * self.M * self.H / 2 * a - self.M * self.g * (self.B / 2 + s * self.e)


def _rhs(blk: _Block, s: int, sigma: int):
    """``y' `` of ``y = (theta, dtheta, u, du)`` in the phase ``(s, sigma)``: pivot ``s`` (0: full contact),
    slip ``sigma`` (0: stick, else the slip's direction)."""

    def f(t, y):
        a = blk.pivot_accel(s, sigma, t, y[0], y[1])
        ddtheta = blk.rocking(s, y[0], y[1], a)[0] if s else 0.0
        return [y[1], ddtheta, y[3], a - blk.ag(t)]

    return f


def _events(blk: _Block, s: int, sigma: int) -> dict:
    """The phase's exits, each a function of ``(t, y)`` that turns positive (or reaches 0) where the phase ends."""
    out: dict[str, Callable[..., float]] = {}
    if s == 0:
        for side in (1, -1):
            out[f"uplift{side:+d}"] = lambda t, y, side=side: blk.uplift(side, blk.pivot_accel(0, sigma, t, 0.0, 0.0))
    else:
        out["impact"] = lambda t, y: -s * y[0]
        out["overturn"] = lambda t, y: abs(y[0]) - np.pi / 2
        out["flight"] = lambda t, y: -blk.rocking(s, y[0], y[1], blk.pivot_accel(s, sigma, t, y[0], y[1]))[2]
    if sigma == 0:

        def slip(t, y):
            _, V, N = blk.rocking(s, y[0], y[1], blk.ag(t)) if s else (0.0, blk.M * blk.ag(t), blk.M * blk.g)
            return abs(V) - blk.mu_s * N

        out["slip"] = slip
    else:
        out["stop"] = lambda t, y: -sigma * y[3]  # rises to 0 where the slip stops
    return out


def _peak(t, y):
    """``dtheta``: its zeros are the tilt's extrema (recorded, the phase goes on)."""
    return y[1]


def _stick_or_reverse(blk: _Block, s: int, t: float, y) -> int:
    """The slip's state where the slip speed is 0: 0 if the floor can hold the contact, else the new direction."""
    _, V, N = blk.rocking(s, y[0], y[1], blk.ag(t)) if s else (0.0, blk.M * blk.ag(t), blk.M * blk.g)
    return 0 if abs(V) <= blk.mu_s * N else int(-np.sign(V))


def _after_impact(blk: _Block, s: int, y) -> tuple[float, float]:
    """``(dtheta, du)`` after the impact of the corner ``-s``: sticking if the floor holds it, else sliding."""
    w, du, P_t, P_n = corner_impact(s, y[1], y[3], 0.0, blk.M, blk.I_G, blk.B, blk.H, blk.e, stick=True)
    if abs(P_t) <= blk.mu_s * P_n:
        return w, 0.0
    for sigma in (1, -1):
        w, du, P_t, P_n = corner_impact(s, y[1], y[3], sigma * blk.mu_k, blk.M, blk.I_G, blk.B, blk.H, blk.e, False)
        if sigma * du >= 0:
            return w, du
    raise RuntimeError("no consistent sliding impact")


def _segment(blk: _Block, s: int, sigma: int, t: float, y, rtol: float):
    """One phase from ``t`` to its first exit (or to the motion's end, or ``t_max``): ``(sol, names)``."""
    from scipy.integrate import solve_ivp

    events = _events(blk, s, sigma)
    for fn in events.values():
        fn.terminal, fn.direction = True, 1
    end = blk.T if t < blk.T else blk.t_max
    # The exits move with the motion even where the state does not (a block at rest): steps of 1/256 of it.
    sol = solve_ivp(
        _rhs(blk, s, sigma),
        (t, end),
        y,
        "DOP853",
        events=[*events.values(), _peak],
        rtol=rtol,
        atol=1e-13,
        max_step=blk.T / 256,
    )
    return sol, list(events)


def _transition(blk: _Block, name: str, s: int, sigma: int, t: float, y) -> tuple[int, int, str]:
    """The phase ``(s, sigma)`` after the exit ``name`` at ``(t, y)`` (``y`` set to the state after it), and what
    it counts: ``"uplift"``, ``"slide"``, ``"impact"``, ``"impact slide"`` or ``""``."""
    if name.startswith("uplift"):
        return int(name[-2:]), sigma, "uplift"
    if name == "slip":
        return s, -int(np.sign(blk.rocking(s, y[0], y[1], blk.ag(t))[1] if s else blk.ag(t))), "slide"
    if name == "stop":
        y[3] = 0.0
        new = _stick_or_reverse(blk, s, t, y)
        return s, new, "slide" if new else ""
    y[0] = 0.0
    y[1], y[3] = _after_impact(blk, s, y)
    slip = int(np.sign(y[3]))
    if abs(y[1]) < 1e-6 * np.sqrt(blk.g / blk.H):  # at rest on its base
        y[1], s = 0.0, 0
    return -s, slip, "impact slide" if slip not in (0, sigma) else "impact"


def slide_rock(M, I_G, B, H, e, g, a_g, omega_g, mu_s, mu_k=None, sign=1, t_after=3.0, rtol=1e-10) -> SlideRock:
    """The bare block under the one-sine pulse on a floor with Coulomb friction: an independent reference.

    The phases of docs/model.md section 15, each integrated by SciPy's DOP853 with its exits as events: full
    contact sticking or sliding, rocking about either corner sticking or sliding; an impact sticks when the floor
    holds the corner (:func:`corner_impact`) and slides through otherwise; the rest snap below
    ``1e-6 sqrt(g / H)`` rad/s. The equations are typed by hand in this module, independent of ``derive/``.
    """
    blk = _Block(M, I_G, B, H, e, g, sign * a_g, omega_g, mu_s, mu_s if mu_k is None else mu_k, t_after)
    t, y, s, sigma = 0.0, np.zeros(4), 0, 0
    theta_max = u_max = 0.0
    counts = {"uplift": 0, "slide": 0, "impact": 0}
    status, first, stalled = "t_max", "none", 0
    while t < blk.t_max - 1e-12 and status == "t_max":
        sol, names = _segment(blk, s, sigma, t, y, rtol)
        peaks = np.concatenate([sol.y, *(ye.T for ye in sol.y_events if ye.size)], axis=1)
        theta_max = max(theta_max, float(np.max(np.abs(peaks[0]))))
        u_max = max(u_max, float(np.max(np.abs(peaks[2]))))
        hit = [(te[0], k) for k, te in enumerate(sol.t_events[:-1]) if te.size]
        if hit:
            t_hit, k = min(hit)
            stalled = stalled + 1 if t_hit == t else 0
            if stalled > 8:
                raise RuntimeError(f"the phases switch without end at t = {t}")
            t, y, name = float(t_hit), sol.y_events[k][0].copy(), names[k]
            if name in ("overturn", "flight"):
                status = "overturned" if name == "overturn" else "flight"
                break
            first = ("rocks" if name.startswith("uplift") else "slides") if first == "none" else first
            s, sigma, counted = _transition(blk, name, s, sigma, t, y)
            if sigma == 0 and _stick_or_reverse(blk, s, t, y):
                # The phase starts stuck with more force than the floor holds (after an impact, say): a slip event
                # sees only a crossing, so the slip starts here.
                sigma, counted = _stick_or_reverse(blk, s, t, y), counted + " slide"
            for word in counted.split():
                counts[word] += 1
        else:
            t, y = float(sol.t[-1]), sol.y[:, -1].copy()
        if s == 0 and sigma == 0 and t >= blk.T:
            status = "rest"
    return SlideRock(
        theta_max, u_max, float(y[2]), counts["slide"], counts["uplift"], counts["impact"], status, t, first
    )
