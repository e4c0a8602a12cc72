"""Flight and landing of the block, typed by hand with Newton and Euler (docs/model.md section 16).

Independent of ``derive/``: the yardstick the derived flight accelerations and landing map are held to. The state
of a flying block is its rocking state about a reference corner ``s`` (``theta``, the damper's ``x`` and their
rates) and the displacement ``(u, v)`` of that corner relative to its place at rest on the ground, ``(-s B / 2, 0)``:
``v`` is the corner's height above the floor. Everything is relative to the ground, whose acceleration
``(ddx_g, ddy_g)`` acts as the inertial force ``-(mass) (ddx_g, ddy_g)`` on every body, beside its weight.

The block's centroid ``G`` is at ``r_G = (d_s, H/2)`` from the corner ``s`` in the block frame (``d_s = s B/2 + e``)
and the damper's mass at ``(xi_s, eta)`` (``xi_s = s B/2 + x``, ``eta = H + h``). ``R`` is the rotation by
``theta`` and ``J = [[0, -1], [1, 0]]`` the quarter turn: ``d/dt (R r) = dtheta R J r`` for a point fixed to the
block.
"""

from __future__ import annotations

import numpy as np

_J = np.array([[0.0, -1.0], [1.0, 0.0]])


def _rotate(theta, r):
    """``R(theta) r`` for arrays of angles and of block-frame vectors ``r`` (last axis 2)."""
    c, s_ = np.cos(theta), np.sin(theta)
    return np.stack([c * r[..., 0] - s_ * r[..., 1], s_ * r[..., 0] + c * r[..., 1]], axis=-1)


def _float(*values):
    """The floating type of ``values``: at least double, extended if one of them is (``rocking verify`` runs the
    references in extended precision)."""
    return np.result_type(*(np.asarray(a) for a in values), np.float64)


def _arrays(*values):
    """``values`` as float arrays of their common shape."""
    kind = _float(*values)
    return np.broadcast_arrays(*(np.asarray(a, dtype=kind) for a in values))


def _vec(a, b):
    """Stack two broadcast arrays on a last axis of 2."""
    kind = _float(a, b)
    a, b = np.broadcast_arrays(np.asarray(a, dtype=kind), np.asarray(b, dtype=kind))
    return np.stack([a, b], axis=-1)


def block_flight_accel(s, theta, dtheta, ag, agy, M, I_G, B, H, e, g):
    """The bare block in flight: ``(ddtheta, ddu, ddv)`` of the corner ``s``.

    No force but the weight and the inertial ground force: ``G`` falls on the parabola
    ``a_G = (-ddx_g, -(g + ddy_g))``, no moment about it (``ddtheta = 0``), and the corner, at ``-R r_G`` from ``G``,
    has ``a_c = a_G + dtheta^2 R r_G``.
    """
    shape = np.broadcast(s, theta, dtheta, ag, agy, M, I_G, B, H, e, g).shape
    r_G = _vec(s * B / 2 + e, H / 2)
    a = _vec(-ag, -(g + agy)) + np.asarray(dtheta**2)[..., None] * _rotate(theta, r_G)
    return np.zeros(shape, a.dtype), np.broadcast_to(a[..., 0], shape), np.broadcast_to(a[..., 1], shape)


def omd_flight_accel(s, theta, x, dtheta, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c, guide=None):
    """The block with its damper in flight: ``(ddtheta, ddx, ddu, ddv)``.

    Unknowns: ``a_G`` (in the block frame, ``R^T a_G``), ``ddtheta``, ``ddx`` and the guide's normal force ``N_g`` on
    the mass (along ``R (0, 1)``). The spring and dashpot pull the mass back along the guide, ``-G t`` with
    ``G = k_m x + c dx``, ``t = R (1, 0)``, and push the block by ``+G t``; the guide pushes the mass by ``N_g n``,
    the block by ``-N_g n``. With ``rho = (x - e, eta - H/2)`` the mass from ``G`` in the block frame:

    - block:  ``M a_G = -M (ddx_g, g + ddy_g) + G t - N_g n``,
      ``I_G ddtheta = rho x (G, -N_g) = -rho_x N_g - rho_y G`` (both forces act on the guide's line at the mass);
    - mass:   ``m a_m = -m (ddx_g, g + ddy_g) - G t + N_g n``, with
      ``a_m = a_G + ddtheta R J rho - dtheta^2 R rho + 2 dtheta dx R J (1, 0) + ddx t``.

    Written in the block frame (multiplied by ``R^T``), five linear equations. ``guide``, if given, is ``G`` itself:
    with end stops, their force added (:func:`rocking.reference.paper.guide_force`).
    """
    s, theta, x, dtheta, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c = _arrays(
        s, theta, x, dtheta, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c
    )
    shape = s.shape
    G = k_m * x + c * dx if guide is None else np.broadcast_to(np.asarray(guide, dtype=s.dtype), shape)
    rho = _vec(x - e, H + h - H / 2)
    gravity = _rotate(-theta, _vec(-ag, -(g + agy)))  # per unit mass, in the block frame
    Jrho = rho @ _J.T
    A = np.zeros(shape + (5, 5), s.dtype)
    b = np.zeros(shape + (5,), s.dtype)
    # Unknowns: a_G (2, block frame), ddtheta, ddx, N_g.
    A[..., 0, 0], A[..., 1, 1] = M, M
    A[..., 1, 4] = 1.0
    b[..., 0] = M * gravity[..., 0] + G
    b[..., 1] = M * gravity[..., 1]
    A[..., 2, 2], A[..., 2, 4] = I_G, rho[..., 0]
    b[..., 2] = -rho[..., 1] * G
    A[..., 3, 0], A[..., 3, 2], A[..., 3, 3] = m, m * Jrho[..., 0], m
    A[..., 4, 1], A[..., 4, 2], A[..., 4, 4] = m, m * Jrho[..., 1], -1.0
    b[..., 3] = m * gravity[..., 0] - G + m * dtheta**2 * rho[..., 0]
    b[..., 4] = m * gravity[..., 1] + m * dtheta**2 * rho[..., 1] - 2 * m * dtheta * dx
    a_G, ddtheta, ddx = _solve(A, b)
    r_G = _vec(s * B / 2 + e, H / 2)
    # The corner is at -R r_G from G: a_c = a_G + ddtheta (-R J r_G) + dtheta^2 R r_G.
    a_c = (
        _rotate(theta, a_G)
        - ddtheta[..., None] * _rotate(theta, r_G @ _J.T)
        + (dtheta**2)[..., None] * _rotate(theta, r_G)
    )
    return ddtheta, ddx, a_c[..., 0], a_c[..., 1]


def _linear(A, b):
    """The solution of the linear systems ``A z = b`` (batched on the leading axes): numpy.linalg's in double
    precision, Gauss's elimination with partial pivoting in extended precision (numpy.linalg has none)."""
    if A.dtype == np.float64:
        return np.linalg.solve(A, b[..., None])[..., 0]
    shape, n = b.shape, b.shape[-1]
    A, b = A.reshape(-1, n, n).copy(), b.reshape(-1, n).copy()
    rows = np.arange(len(b))
    for k in range(n):
        p = k + np.argmax(np.abs(A[:, k:, k]), axis=1)
        A[rows, k], A[rows, p] = A[rows, p], A[rows, k].copy()
        b[rows, k], b[rows, p] = b[rows, p], b[rows, k].copy()
        f = A[:, k + 1 :, k] / A[:, k, k][:, None]
        A[:, k + 1 :] -= f[..., None] * A[:, k, None, :]
        b[:, k + 1 :] -= f * b[:, k, None]
    z = np.zeros_like(b)
    for k in reversed(range(n)):
        z[:, k] = (b[:, k] - np.sum(A[:, k, k + 1 :] * z[:, k + 1 :], axis=1)) / A[:, k, k]
    return z.reshape(shape)


def _solve(A, b):
    """``(a_G, ddtheta, ddx)`` of :func:`omd_flight_accel`'s linear system."""
    z = _linear(A, b)
    return z[..., :2], z[..., 2], z[..., 3]


def block_landing(s, theta, dtheta, du, dv, M, I_G, B, H, e, e_n=0.0, mu_slip=0.0, stick=True):
    """The bare block's landing on the corner ``s``: ``(dtheta+, du+, dv+, P_t, P_n)``.

    Newton and Euler with the floor's impulse ``P = (P_t, P_n)`` at the corner, ``-R r_G`` from ``G``:
    ``M (v_G+ - v_G-) = P``, ``I_G (omega+ - omega-) = (-R r_G) x P``; the corner's velocity is
    ``v_G + omega J (-R r_G)``. After the landing its normal velocity is ``-e_n dv`` and either its slip is 0
    (``stick``) or ``P_t = -mu_slip P_n``.
    """
    s, theta, dtheta, du, dv, M, I_G, B, H, e, e_n, mu_slip = _arrays(
        s, theta, dtheta, du, dv, M, I_G, B, H, e, e_n, mu_slip
    )
    rc = -_rotate(theta, _vec(s * B / 2 + e, H / 2))  # the corner from G
    # v_c = v_G + omega (-rc_y, rc_x): the velocity of G before, from the corner's.
    vG = _vec(du + dtheta * rc[..., 1], dv - dtheta * rc[..., 0])
    # Unknowns: v_G+ (2), omega+ and the impulse per unit mass P / M (rows scaled alike: a well-conditioned system).
    k = M / I_G
    A = np.zeros(s.shape + (5, 5), s.dtype)
    b = np.zeros(s.shape + (5,), s.dtype)
    A[..., 0, 0], A[..., 0, 3] = 1.0, -1.0
    A[..., 1, 1], A[..., 1, 4] = 1.0, -1.0
    A[..., 2, 2], A[..., 2, 3], A[..., 2, 4] = 1.0, k * rc[..., 1], -k * rc[..., 0]
    b[..., 0], b[..., 1], b[..., 2] = vG[..., 0], vG[..., 1], dtheta
    A[..., 3, 1], A[..., 3, 2] = 1.0, rc[..., 0]
    b[..., 3] = -e_n * dv
    if stick:
        A[..., 4, 0], A[..., 4, 2] = 1.0, -rc[..., 1]
    else:
        A[..., 4, 3], A[..., 4, 4] = 1.0, mu_slip
    z = _linear(A, b)
    w = z[..., 2]
    return w, z[..., 0] - w * rc[..., 1], z[..., 1] + w * rc[..., 0], M * z[..., 3], M * z[..., 4]


def omd_landing(s, theta, x, dtheta, dx, du, dv, M, I_G, B, H, e, m, h, e_n=0.0, mu_slip=0.0, stick=True):
    """The block with its damper landing on the corner ``s``: ``(dtheta+, dx+, du+, dv+, P_t, P_n)``.

    Newton and Euler with impulses: the floor's ``P = (P_t, P_n)`` at the corner, ``rc = -R r_G`` from ``G``, and the
    guide's ``Lambda n`` on the mass (``n = R (0, 1)``; the spring and dashpot carry none, so the mass keeps its
    momentum along the guide, the momentum law of section 6), ``-Lambda n`` on the block at the mass:
    ``M (v_G+ - v_G-) = P - Lambda n``, ``I_G (omega+ - omega-) = rc x P - Lambda rho_x``,
    ``m (v_m+ - v_m-) = Lambda n`` with ``v_m = v_G + omega J R rho + dx R (1, 0)``; the corner's normal velocity
    after is ``-e_n dv`` and either its slip is 0 (``stick``) or ``P_t = -mu_slip P_n``.
    """
    s, theta, x, dtheta, dx, du, dv, M, I_G, B, H, e, m, h, e_n, mu_slip = _arrays(
        s, theta, x, dtheta, dx, du, dv, M, I_G, B, H, e, m, h, e_n, mu_slip
    )
    rc = -_rotate(theta, _vec(s * B / 2 + e, H / 2))
    rho = _vec(x - e, H + h - H / 2)
    Jr = _rotate(theta, rho @ _J.T)  # J R rho = R J rho
    t, n = _rotate(theta, _vec(np.ones_like(x), 0.0)), _rotate(theta, _vec(0.0, np.ones_like(x)))
    vG = _vec(du + dtheta * rc[..., 1], dv - dtheta * rc[..., 0])
    vm = vG + dtheta[..., None] * Jr + dx[..., None] * t
    # Unknowns: v_G+ (2), omega+, dx+, and the impulses per unit block mass Lambda / M, P_t / M, P_n / M.
    A = np.zeros(s.shape + (7, 7), s.dtype)
    b = np.zeros(s.shape + (7,), s.dtype)
    k, r = M / I_G, m / M
    for i in (0, 1):
        A[..., i, i], A[..., i, 4], A[..., i, 5 + i] = 1.0, n[..., i], -1.0
        b[..., i] = vG[..., i]
        A[..., 3 + i, i], A[..., 3 + i, 2], A[..., 3 + i, 3] = r, r * Jr[..., i], r * t[..., i]
        A[..., 3 + i, 4] = -n[..., i]
        b[..., 3 + i] = r * vm[..., i]
    A[..., 2, 2], A[..., 2, 4], A[..., 2, 5], A[..., 2, 6] = 1.0, k * rho[..., 0], k * rc[..., 1], -k * rc[..., 0]
    b[..., 2] = dtheta
    A[..., 5, 1], A[..., 5, 2] = 1.0, rc[..., 0]
    b[..., 5] = -e_n * dv
    if stick:
        A[..., 6, 0], A[..., 6, 2] = 1.0, -rc[..., 1]
    else:
        A[..., 6, 5], A[..., 6, 6] = 1.0, mu_slip
    z = _linear(A, b)
    w = z[..., 2]
    return w, z[..., 3], z[..., 0] - w * rc[..., 1], z[..., 1] + w * rc[..., 0], M * z[..., 5], M * z[..., 6]


def block_flat_landing(s, dtheta, du, dv, M, I_G, B, H, e, e_n=0.0, mu_slip=0.0, stick=True):
    """The bare block landing flat on both corners at ``theta = 0``: ``(du+, dv+, P_t, P_s, P_o)``; ``dtheta+ = 0``.

    Newton and Euler with the floor's impulses, ``P_t`` and ``P_s`` at the corner ``s``, ``-(d_s, H/2)`` from ``G``,
    and ``P_o`` at the other, ``(s B/2 - e, -H/2)`` from ``G``: ``G`` moves at ``v_G = (du - H/2 dtheta,
    dv + d_s dtheta)`` before; after, no spin and the base's normal velocity ``-e_n dv``, so
    ``P_n = P_s + P_o = -M ((1 + e_n) dv + d_s dtheta)``, and ``P_t = -M v_Gx`` (``stick``) or ``-mu_slip P_n``;
    the moment about ``G``, ``-I_G dtheta = -d_s P_s + H/2 P_t + (s B/2 - e) P_o``, gives
    ``P_o = (d_s P_n - H/2 P_t - I_G dtheta) / (s B)``.
    """
    d = s * B / 2 + e
    P_n = -M * ((1 + e_n) * dv + d * dtheta)
    vGx = du - H / 2 * dtheta
    P_t = -M * vGx if stick else -mu_slip * P_n
    P_o = (d * P_n - H / 2 * P_t - I_G * dtheta) / (s * B)
    return vGx + P_t / M, -e_n * dv, P_t, P_n - P_o, P_o


def omd_flat_landing(s, x, dtheta, dx, du, dv, M, I_G, B, H, e, m, h, e_n=0.0, mu_slip=0.0, stick=True):
    """The block with its damper landing flat at ``theta = 0``: ``(dx+, du+, dv+, P_t, P_s, P_o)``; ``dtheta+ = 0``.

    :func:`block_flat_landing` with the guide's impulse ``Lambda`` on the mass, vertical at ``theta = 0``, and
    ``-Lambda`` on the block at the mass, ``rho = (x - e, eta - H/2)`` from ``G`` (``eta = H + h``); the spring and
    dashpot carry none (the attached coordinates take no impulse). The mass moves at ``(du - eta dtheta + dx,
    dv + xi_s dtheta)`` before (``xi_s = s B/2 + x``) and at ``(du+ + dx+, dv+)`` after: it keeps its horizontal
    velocity, and ``Lambda = m (dv+ - dv - xi_s dtheta)``. The block's vertical momentum gives
    ``P_n = P_s + P_o = M (dv+ - dv - d_s dtheta) + Lambda``, its horizontal ``P_t = M (du+ - du + H/2 dtheta)``,
    and its moment about ``G``, ``-I_G dtheta = -d_s P_s + H/2 P_t + (s B - d_s) P_o - (x - e) Lambda``, gives
    ``P_o = (d_s P_n - H/2 P_t - I_G dtheta + (x - e) Lambda) / (s B)``.
    """
    d, xi = s * B / 2 + e, s * B / 2 + x
    dv_plus = -e_n * dv
    Lam = m * (dv_plus - dv - xi * dtheta)
    P_n = M * (dv_plus - dv - d * dtheta) + Lam
    vGx = du - H / 2 * dtheta
    P_t = -M * vGx if stick else -mu_slip * P_n
    du_plus = vGx + P_t / M
    P_o = (d * P_n - H / 2 * P_t - I_G * dtheta + (x - e) * Lam) / (s * B)
    return du - (H + h) * dtheta + dx - du_plus, du_plus, dv_plus + 0 * du_plus, P_t, P_n - P_o, P_o


def block_energy(s, theta, dtheta, v, du, dv, M, I_G, B, H, e, g):
    """The bare block's energy in flight, relative to the ground: ``M |v_G|^2 / 2 + I_G dtheta^2 / 2 + M g y_G``."""
    r_G = _rotate(theta, _vec(s * B / 2 + e, H / 2))
    vG = _vec(du, dv) + dtheta[..., None] * (r_G @ _J.T)
    return M * (vG[..., 0] ** 2 + vG[..., 1] ** 2) / 2 + I_G * dtheta**2 / 2 + M * g * (v + r_G[..., 1])


def omd_energy(s, theta, x, dtheta, dx, v, du, dv, M, I_G, B, H, e, g, m, h, k_m, stored=None):
    """The block and its damper's energy in flight, relative to the ground: the kinetic energies of the block
    (``M |v_G|^2 / 2 + I_G dtheta^2 / 2``) and of the mass (``m |v_m|^2 / 2``), their weights' potential, and the
    energy ``stored`` in the guide's elements (default the spring's ``k_m x^2 / 2``; with end stops, the pads' added).

    The corner ``s`` is at height ``v`` moving at ``(du, dv)``; ``G`` at ``R r_G`` from it, the mass at
    ``R (xi_s, eta)``, moving along the guide ``R (1, 0)`` at ``dx`` besides.
    """
    r_G = _rotate(theta, _vec(s * B / 2 + e, H / 2))
    r_m = _rotate(theta, _vec(s * B / 2 + x, H + h))
    corner = _vec(du, dv)
    vG = corner + np.asarray(dtheta)[..., None] * (r_G @ _J.T)
    vm = (
        corner
        + np.asarray(dtheta)[..., None] * (r_m @ _J.T)
        + np.asarray(dx)[..., None] * _rotate(theta, _vec(1.0, 0.0))
    )
    kinetic = M * np.sum(vG**2, axis=-1) / 2 + I_G * dtheta**2 / 2 + m * np.sum(vm**2, axis=-1) / 2
    weights = M * g * (v + r_G[..., 1]) + m * g * (v + r_m[..., 1])
    return kinetic + weights + (k_m * x**2 / 2 if stored is None else stored)


def other_corner(s, theta, dtheta, u, v, du, dv, B):
    """The corner ``-s``'s ``(u, v, du, dv)`` from the corner ``s``'s: it is at ``R (s B, 0)`` from the corner ``s``,
    and its ``u`` is counted from its own place at rest, ``s B`` to the right of the corner ``s``'s."""
    arm = _rotate(theta, _vec(s * B, 0.0))
    rate = np.asarray(dtheta)[..., None] * (arm @ _J.T)
    return u + arm[..., 0] - s * B, v + arm[..., 1], du + rate[..., 0], dv + rate[..., 1]


def centroid(theta, u, v, s, B, H, e):
    """The position ``(X_G, Y_G)`` of the block's centroid relative to the ground, the corner ``s`` being at
    ``(-s B / 2 + u, v)`` (the origin at the centre of the base at rest)."""
    r_G = _rotate(theta, _vec(s * B / 2 + e, H / 2))
    return -s * B / 2 + u + r_G[..., 0], v + r_G[..., 1]


def parabola(X0, Y0, VX0, VY0, ag, agy, g, t):
    """The position at ``t`` of a point that starts at ``(X0, Y0)`` with ``(VX0, VY0)`` and accelerates by
    ``(-ddx_g, -(g + ddy_g))`` relative to a ground of constant acceleration: the centroid of a flying system."""
    return X0 + VX0 * t - ag * t**2 / 2, Y0 + VY0 * t - (g + agy) * t**2 / 2


def landing_law(stick, slide, du, mu_s, mu_k):
    """The law of a landing (docs/model.md section 16) and its outputs, from the two maps of one landing.

    ``stick()`` and ``slide(mu_slip)`` return a landing map's outputs, the slip speed after at index -4 and the
    impulses ``(P_t, P_n)`` last. The corner sticks if the floor holds it (``P_n > 0``, ``|P_t| <= mu_s P_n``);
    else it slides in the direction ``sigma`` in which the slip keeps its sign through the landing
    (``sigma du >= 0`` before and after) with ``P_n > 0``. Returns ``(outputs, law)``, ``law`` ``"stick"``,
    ``"slide"`` or ``""``: neither is consistent (the slip would reverse within the landing, or the sliding impulse
    would pull: the model does not follow the impulse through the landing).
    """
    out = stick()
    if out[-1] > 0.0 and abs(out[-2]) <= mu_s * out[-1]:
        return out, "stick"
    for sigma in (1.0, -1.0):
        out = slide(sigma * mu_k)
        if out[-1] > 0.0 and sigma * du >= 0.0 and sigma * out[-4] >= 0.0:
            return out, "slide"
    return out, ""
