"""The paper's equations, typed by hand from ``docs/model.md`` sections 3-7.

This module is deliberately independent of SymPy and of ``derive/``: it is the
yardstick the generated code is held against (``rocking verify``). Every
function broadcasts over NumPy arrays. Units SI; ``s = +1`` is the pivot ``A``
(left corner), ``s = -1`` the pivot ``A'``.

Short-hands (docs/model.md section 1)::

    d_s  = s B/2 + e        xi_s = s B/2 + x        eta = H + h
    I_s  = I_G + M (d_s^2 + H^2/4)
"""

from __future__ import annotations

import numpy as np

IMPACT_LAWS = ("momentum", "velocity")


def arms(s, x, B, e):
    """Horizontal arms of ``G`` and of the mass from the pivot ``s``: ``(d_s, xi_s)``."""
    return s * B / 2 + e, s * B / 2 + x


def pivot_inertia(s, M, I_G, B, H, e):
    """Block inertia about the pivot ``s``: ``I_s = I_G + M (d_s^2 + H^2/4)``."""
    d = s * B / 2 + e
    return I_G + M * (d**2 + H**2 / 4)


def mass_matrix(s, theta, x, M, I_G, B, H, e, m, h):
    """Mass matrix of (R1), (R2): ``((m11, m12), (m21, m22))``."""
    _, xi = arms(s, x, B, e)
    eta = H + h
    m11 = pivot_inertia(s, M, I_G, B, H, e) + m * (xi**2 + eta**2)
    m12 = -m * eta + 0 * theta
    return (m11, m12), (m12, m + 0 * theta)


def forcing(s, theta, x, dtheta, dx, ag, M, B, H, e, g, m, h, k_m, c):
    """Right-hand sides of (R1) and (R2) once the acceleration terms are moved left."""
    d, xi = arms(s, x, B, e)
    eta = H + h
    cos, sin = np.cos(theta), np.sin(theta)
    lever = M * d + m * xi
    height = M * H / 2 + m * eta
    f1 = ag * (height * cos + lever * sin) - g * (lever * cos - height * sin) - 2 * m * xi * dtheta * dx
    f2 = -m * ag * cos - c * dx - k_m * x + m * xi * dtheta**2 - m * g * sin
    return f1, f2


def rocking_accel(s, theta, x, dtheta, dx, ag, M, I_G, B, H, e, g, m, h, k_m, c):
    """``(ddtheta, ddx)`` from (R1), (R2) by solving the 2x2 system numerically."""
    (a, b), (_, d) = mass_matrix(s, theta, x, M, I_G, B, H, e, m, h)
    f1, f2 = forcing(s, theta, x, dtheta, dx, ag, M, B, H, e, g, m, h, k_m, c)
    det = a * d - b * b
    return (d * f1 - b * f2) / det, (a * f2 - b * f1) / det


def contact_accel(x, dx, ag, m, k_m, c):
    """``ddx`` in full contact, (C1): ``m ddx + c dx + k_m x = -m ddx_g``."""
    return (-m * ag - c * dx - k_m * x) / m


def overturning_moment(x, dx, ag, M, H, h, k_m, c):
    """``Mo = M (H/2) ddx_g - eta (k_m x + c dx)`` of section 5."""
    return M * H / 2 * ag - (H + h) * (k_m * x + c * dx)


def uplift_margin(s, x, dx, ag, M, B, H, e, g, m, h, k_m, c):
    """How far (U1) (``s = +1``) or (U2) (``s = -1``) is from holding; positive: uplift.

    ``s = +1``: ``Mo - g [M (B/2 + e) + m (B/2 + x)]``;
    ``s = -1``: ``-Mo - g [M (B/2 - e) + m (B/2 - x)]``.
    """
    Mo = overturning_moment(x, dx, ag, M, H, h, k_m, c)
    return s * Mo - g * (M * (B / 2 + s * e) + m * (B / 2 + s * x))


def impact(s, x, dtheta, dx, M, I_G, B, H, e, m, h, law="momentum"):
    """Velocities after an impact ending rocking about ``s``, (I1) and (I2).

    ``law="momentum"``: the mass keeps its absolute horizontal momentum (I2).
    ``law="velocity"``: ``dx`` is continuous and only the total angular
    momentum about the new pivot is conserved, which gives
    ``dtheta+ = dtheta- [I_G + M (H^2/4 + d_s d_-s) + m (xi_s xi_-s + eta^2)]
    / [I_-s + m (xi_-s^2 + eta^2)]``.
    """
    if law not in IMPACT_LAWS:
        raise ValueError(f"law must be one of {IMPACT_LAWS}, got {law!r}")
    d_s, xi_s = arms(s, x, B, e)
    d_o, xi_o = arms(-s, x, B, e)
    eta = H + h
    I_o = pivot_inertia(-s, M, I_G, B, H, e)
    common = I_G + M * (H**2 / 4 + d_s * d_o) + m * xi_s * xi_o
    if law == "momentum":
        dtheta_plus = dtheta * common / (I_o + m * xi_o**2)
        return dtheta_plus, dx + eta * (dtheta_plus - dtheta)
    dtheta_plus = dtheta * (common + m * eta**2) / (I_o + m * (xi_o**2 + eta**2))
    return dtheta_plus, dx + 0 * dtheta_plus


def uplift_energy(s, M, B, H, e, g, m, h, k_m, c):
    """Least damper energy ``k_m x^2/2 + m dx^2/2`` at which the mass alone lifts the block about ``s``.

    Without ground motion (U1)/(U2) read ``u = u_0 + a_x x + a_v dx = 0`` with
    ``u_0 = -g [M (B/2 + s e) + m B/2]``, ``a_x = -s (eta k_m + m g)`` and
    ``a_v = -s eta c``; a Lagrange multiplier gives the least energy on that line,
    ``u_0^2 / (2 (a_x^2 / k_m + a_v^2 / m))``.
    """
    eta = H + h
    u0 = -g * (M * (B / 2 + s * e) + m * B / 2)
    a_x = -s * (eta * k_m + m * g)
    a_v = -s * eta * c
    return u0**2 / (2 * (a_x**2 / k_m + a_v**2 / m))


def energy(s, theta, x, dtheta, dx, M, I_G, B, H, e, g, m, h, k_m):
    """Mechanical energy ``T + V`` in the ground frame while rocking about ``s``."""
    d, xi = arms(s, x, B, e)
    eta = H + h
    sin, cos = np.sin(theta), np.cos(theta)
    T = pivot_inertia(s, M, I_G, B, H, e) * dtheta**2 / 2
    T = T + m * (dtheta**2 * (xi**2 + eta**2) + dx**2 - 2 * eta * dtheta * dx) / 2
    V = M * g * (d * sin + H / 2 * cos) + m * g * (xi * sin + eta * cos) + k_m * x**2 / 2
    return T + V


def power(s, theta, x, dtheta, dx, ag, M, B, H, e, m, h, c):
    """``dE/dt`` between impacts: ``-c dx^2`` plus the power of ``-(mass) ddx_g``."""
    d, xi = arms(s, x, B, e)
    eta = H + h
    sin, cos = np.sin(theta), np.cos(theta)
    vx_G = -dtheta * (d * sin + H / 2 * cos)
    vx_m = -dtheta * (xi * sin + eta * cos) + dx * cos
    return -c * dx**2 - ag * (M * vx_G + m * vx_m)


def _weights(s, x, M, B, H, e, m, h):
    """Lever arm ``M d_s + m xi_s`` and height ``M H/2 + m eta`` of the weights about ``s`` (over ``g``)."""
    d, xi = arms(s, x, B, e)
    return M * d + m * xi, M * H / 2 + m * (H + h)


def critical_angle(s, x, M, B, H, e, m, h):
    """Static critical angle about ``s``: ``tan = (M d_s + m xi_s) / (M H/2 + m eta)``."""
    return np.arctan2(*_weights(s, x, M, B, H, e, m, h))


def critical_tangent(s, x, M, B, H, e, m, h):
    """``tan`` of :func:`critical_angle` where the weights' centre is above the ground, NaN elsewhere."""
    lever, height = _weights(s, x, M, B, H, e, m, h)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(height > 0, lever / height, np.nan)
