"""The paper's equations, typed by hand from ``docs/model.md`` sections 3-7 and 11.

This module is deliberately independent of SymPy and of ``derive/``: it is the
yardstick the generated code is held against (``rocking verify``). Every
function broadcasts over NumPy arrays. Units SI; ``s = +1`` is the pivot ``A``
(left corner), ``s = -1`` the pivot ``A'``.

The ground acceleration is ``(ag, agy)``: ``ddx_g`` (> 0 right) and ``ddy_g`` (> 0 up,
docs/model.md section 14). In the frame that moves with the ground, ``ddy_g`` is the
inertial force ``-(mass) ddy_g`` on every body, written here beside each weight.

Short-hands (docs/model.md section 1)::

    d_s  = s B/2 + e        xi_s = s B/2 + x        eta = H + h
    I_s  = I_G + M (d_s^2 + H^2/4)

End stops (section 11): a bumper of stiffness ``k_b`` and damping ``c_b`` at
``|x| = L`` on either side. Every function that sees the guide force takes
``L, k_b, c_b`` as keywords, default ``L = inf`` (the paper's unlimited guide);
Hunt-Crossley pads take ``n_b, chi_b`` and the least approach speed ``floor`` instead of
``c_b``, and a contact's approach speed ``v_in`` is that of a contact starting at the
state, ``max(ddelta, floor)`` (:func:`pad`).
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


def penetration(x, L):
    """``delta = |x| - L``: the bumper acts while it is > 0."""
    return np.abs(x) - L


def pad(x, dx, L=np.inf, k_b=0.0, c_b=0.0, n_b=None, chi_b=None, floor=None, v_in=None, side=None):
    """The pad on the side of the mass: ``(delta, bracket, force, potential, damping)`` of section 11.

    Kelvin-Voigt (``n_b`` None): the bracket and force ``k_b delta + c_b ddelta``, the potential
    ``k_b delta^2 / 2``, the damping ``c_b``. Hunt-Crossley: with the approach speed of a contact
    starting at this state, ``v_in = max(ddelta, floor)``, the bracket ``v_in + chi ddelta``, the force
    ``k_b delta^n (1 + chi ddelta / v_in)``, the potential ``k_b delta^(n+1) / (n+1)``, the damping
    ``k_b delta^n chi / v_in``, ``chi = chi_b`` (the damping factor). ``ddelta = sign(x) dx``; the pad pushes where
    ``delta > 0`` and the bracket is ``> 0``. ``side`` (+1 upper, -1 lower): that side's pad, wherever the
    mass is (default: the side of the mass). ``v_in``: the approach speeds ``(upper, lower)`` of contacts that
    started earlier, instead of this state's.
    """
    sigma = np.sign(x) if side is None else side
    delta = np.maximum(sigma * x - L, 0.0)  # 0, not -inf, where the guide is unlimited
    rate = sigma * dx
    if n_b is None:
        push = k_b * delta + c_b * rate
        return delta, push, push, k_b * delta**2 / 2, c_b + 0 * delta
    chi = chi_b
    if v_in is None:
        v_in = np.maximum(rate, floor)
    else:
        v_in = np.where(sigma > 0, v_in[0], v_in[1])
    stiff = k_b * delta**n_b
    return delta, v_in + chi * rate, stiff * (1 + chi * rate / v_in), stiff * delta / (n_b + 1), stiff * chi / v_in


def pushes(x, dx, **stops):
    """Whether the pad pushes: ``delta > 0`` and its bracket ``> 0`` (an unbonded pad cannot pull)."""
    delta, bracket, *_ = pad(x, dx, **stops)
    return (delta > 0) & (bracket > 0)


def bumper_force(x, dx, **stops):
    """The bumper's part of the guide force: ``sign(x) F_b`` where the pad pushes, else 0."""
    return np.where(pushes(x, dx, **stops), np.sign(x) * pad(x, dx, **stops)[2], 0.0)


def guide_force(x, dx, k_m, c, **stops):
    """``G(x, dx) = k_m x + c dx`` plus :func:`bumper_force`: what the guide exerts on the mass, reversed."""
    return k_m * x + c * dx + bumper_force(x, dx, **stops)


def mass_matrix(s, theta, x, M, I_G, B, H, e, m, h):
    """Mass matrix of (R1), (R2): ``((m11, m12), (m21, m22))``."""
    _, xi = arms(s, x, B, e)
    eta = H + h
    m11 = pivot_inertia(s, M, I_G, B, H, e) + m * (xi**2 + eta**2)
    m12 = -m * eta + 0 * theta
    return (m11, m12), (m12, m + 0 * theta)


def forcing(s, theta, x, dtheta, dx, ag, agy, M, B, H, e, g, m, h, k_m, c, **stops):
    """Right-hand sides of (R1) and (R2) once the acceleration terms are moved left (section 14: the weights
    with the vertical inertial forces)."""
    d, xi = arms(s, x, B, e)
    eta = H + h
    cos, sin = np.cos(theta), np.sin(theta)
    lever = M * d + m * xi
    height = M * H / 2 + m * eta
    weights = -g * (lever * cos - height * sin)
    vertical = -agy * (lever * cos - height * sin)
    f1 = ag * (height * cos + lever * sin) + weights + vertical - 2 * m * xi * dtheta * dx
    f2 = -m * ag * cos - guide_force(x, dx, k_m, c, **stops) + m * xi * dtheta**2 - m * g * sin - m * agy * sin
    return f1, f2


def rocking_accel(s, theta, x, dtheta, dx, ag, agy, M, I_G, B, H, e, g, m, h, k_m, c, **stops):
    """``(ddtheta, ddx)`` from (R1), (R2), the 2x2 system solved by hand.

    ``ddtheta`` by the Schur complement of ``m22 = m``: with ``m12 / m22 = -eta``,
    ``ddtheta = (f1 + eta f2) / (m11 - m eta^2)``, finite as ``m -> 0`` (the bare block: Housner's
    equation, where ``m11 m22 - m12^2`` would give 0 / 0); then ``ddx = (f2 - m12 ddtheta) / m``.
    """
    (a, b), (_, d) = mass_matrix(s, theta, x, M, I_G, B, H, e, m, h)
    f1, f2 = forcing(s, theta, x, dtheta, dx, ag, agy, M, B, H, e, g, m, h, k_m, c, **stops)
    eta = H + h
    ddtheta = (f1 + eta * f2) / (a - m * eta**2)
    return ddtheta, (f2 - b * ddtheta) / d


def contact_accel(x, dx, ag, m, k_m, c, **stops):
    """``ddx`` in full contact, (C1): ``m ddx + G(x, dx) = -m ddx_g``."""
    return (-m * ag - guide_force(x, dx, k_m, c, **stops)) / m


def overturning_moment(x, dx, ag, M, H, h, k_m, c, **stops):
    """``Mo = M (H/2) ddx_g - eta G(x, dx)`` of sections 5 and 11."""
    return M * H / 2 * ag - (H + h) * guide_force(x, dx, k_m, c, **stops)


def uplift_margin(s, x, dx, ag, agy, M, B, H, e, g, m, h, k_m, c, **stops):
    """How far (U1) (``s = +1``) or (U2) (``s = -1``) is from holding; positive: uplift.

    ``s = +1``: ``Mo - (g + ddy_g) [M (B/2 + e) + m (B/2 + x)]``;
    ``s = -1``: ``-Mo - (g + ddy_g) [M (B/2 - e) + m (B/2 - x)]`` (section 14).
    """
    Mo = overturning_moment(x, dx, ag, M, H, h, k_m, c, **stops)
    return s * Mo - (g + agy) * (M * (B / 2 + s * e) + m * (B / 2 + s * x))


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


def potential(s, theta, x, M, B, H, e, g, m, h, k_m):
    """Potential energy ``V`` of section 2 while rocking about ``s``, bumpers' ``V_b`` left out."""
    d, xi = arms(s, x, B, e)
    eta = H + h
    sin, cos = np.sin(theta), np.cos(theta)
    return M * g * (d * sin + H / 2 * cos) + m * g * (xi * sin + eta * cos) + k_m * x**2 / 2


def least_potential(s, theta, M, B, H, e, g, m, h, k_m):
    """Least :func:`potential` over the stroke ``x`` at the tilt ``theta``: ``-inf`` unless ``k_m > 0``.

    ``dV/dx = m g sin(theta) + k_m x`` vanishes at ``x* = -m g sin(theta) / k_m``, where
    ``V = V(theta, 0) - (m g sin(theta))^2 / (2 k_m)``.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        least = potential(s, theta, 0.0, M, B, H, e, g, m, h, k_m) - (m * g * np.sin(theta)) ** 2 / (2 * k_m)
    return np.where(k_m > 0, least, -np.inf)


def stop_regions(s, M, B, H, e, g, m, h, k_m, c, L, k_b, c_b):
    """The least damper energy to lift the block about ``s`` with the mass pressing a bumper (side ``sigma``).

    For ``sigma x > L`` the guide force is ``(k_m + k_b) x - sigma k_b L + (c + c_b) dx`` and the
    energy ``(k_m + k_b) x^2/2 - sigma k_b L x + k_b L^2/2 + m dx^2/2``, least
    ``E* = k_m k_b L^2 / (2 (k_m + k_b))`` at ``x* = sigma k_b L / (k_m + k_b)``. The uplift margin
    ``u = u_0 + a_x x + a_v dx`` has ``u_0 = -g [M (B/2 + s e) + m B/2] + s eta sigma k_b L``,
    ``a_x = -s (eta (k_m + k_b) + m g)``, ``a_v = -s eta (c + c_b)``; its value at ``x*`` is ``u*``, and
    the least energy on ``u >= 0`` is ``E* + max(0, -u*)^2 / (2 (a_x^2 / (k_m + k_b) + a_v^2 / m))``,
    taken over every state (a bound for the region's). Returns the two sides' values.
    """
    eta = H + h
    k = k_m + k_b
    least = k_m * k_b * L**2 / (2 * k)
    a_x = -s * (eta * k + m * g)
    a_v = -s * eta * (c + c_b)
    out = []
    for sigma in (1, -1):
        u0 = -g * (M * (B / 2 + s * e) + m * B / 2) + s * eta * sigma * k_b * L
        u_least = u0 + a_x * sigma * k_b * L / k
        out.append(least + np.maximum(0, -u_least) ** 2 / (2 * (a_x**2 / k + a_v**2 / m)))
    return tuple(out)


def uplift_energy_with_stops(s, M, B, H, e, g, m, h, k_m, c, L=np.inf, k_b=0.0, c_b=0.0, n_b=None, **hunt_crossley):
    """:func:`uplift_energy` with bumpers: the least over the free guide and each bumper (:func:`stop_regions`).

    Hunt-Crossley pads (``n_b`` given): 0, no bound. Their energy is not quadratic in ``x`` nor their
    force affine, so the least energy on ``u >= 0`` has no closed form; 0 is the answer that is never
    wrong (the runtime then makes no early rest).
    """
    free = uplift_energy(s, M, B, H, e, g, m, h, k_m, c)
    if n_b is not None:
        return 0 * free
    if not np.all(np.isfinite(L)):
        return free
    return np.minimum(free, np.minimum(*stop_regions(s, M, B, H, e, g, m, h, k_m, c, L, k_b, c_b)))


def stop_gaps(x, L):
    """Penetrations of the upper and lower bumpers: ``(x - L, -x - L)``."""
    return x - L, -x - L


def stop_forces(x, dx, **stops):
    """Each bumper's force against its penetration, its law's where it pushes (it only pushes), else 0."""
    forces = []
    for side, gap in zip((1, -1), stop_gaps(x, stops["L"])):
        _, bracket, force, *_ = pad(x, dx, side=side, **stops)
        forces.append(np.where((gap > 0) & (bracket > 0), force, 0.0))
    return tuple(forces)


def stop_contact(x, dx, L, k_b, c_b=0.0, n_b=None, chi_b=None, floor=None, v_in=None):
    """Each bumper's ``min(delta, bracket)``: > 0 exactly while it pushes (the bracket of :func:`pad`, with
    the penetration itself where it is < 0)."""
    out = []
    for i, (side, gap) in enumerate(zip((1, -1), stop_gaps(x, L))):
        rate = side * dx
        if n_b is None:
            out.append(np.minimum(gap, k_b * gap + c_b * rate))
        else:
            approach = np.maximum(rate, floor) if v_in is None else v_in[i]
            out.append(np.minimum(gap, approach + chi_b * rate))
    return tuple(out)


def stop_approach(x, dx, L):
    """Each bumper's rate of penetration ``ddelta``: ``(dx, -dx)``."""
    return dx + 0 * L, -dx + 0 * L


def energy(s, theta, x, dtheta, dx, M, I_G, B, H, e, g, m, h, k_m, **stops):
    """Mechanical energy ``T + V`` in the ground frame while rocking about ``s``, with ``V_b`` of a pad that pushes
    (a released pad's potential has left the mass)."""
    d, xi = arms(s, x, B, e)
    eta = H + h
    sin, cos = np.sin(theta), np.cos(theta)
    T = pivot_inertia(s, M, I_G, B, H, e) * dtheta**2 / 2
    T = T + m * (dtheta**2 * (xi**2 + eta**2) + dx**2 - 2 * eta * dtheta * dx) / 2
    V = M * g * (d * sin + H / 2 * cos) + m * g * (xi * sin + eta * cos) + k_m * x**2 / 2
    return T + V + np.where(pushes(x, dx, **stops), pad(x, dx, **stops)[3], 0.0)


def power(s, theta, x, dtheta, dx, ag, agy, M, B, H, e, m, h, c, **stops):
    """``dE/dt`` between impacts: ``-(c + [pad pushes] c_pad) dx^2`` plus the power of ``-(mass) (ddx_g, ddy_g)``
    on the velocities relative to the ground, ``c_pad`` the pad's damping (:func:`pad`)."""
    d, xi = arms(s, x, B, e)
    eta = H + h
    sin, cos = np.sin(theta), np.cos(theta)
    vx_G = -dtheta * (d * sin + H / 2 * cos)
    vx_m = -dtheta * (xi * sin + eta * cos) + dx * cos
    vy_G = dtheta * (d * cos - H / 2 * sin)
    vy_m = dtheta * (xi * cos - eta * sin) + dx * sin
    damping = c + np.where(pushes(x, dx, **stops), pad(x, dx, **stops)[4], 0.0)
    return -damping * dx**2 - ag * (M * vx_G + m * vx_m) - agy * (M * vy_G + m * vy_m)


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


def block_point_acceleration(s, theta, dtheta, ddtheta, ag, agy, a, b):
    """Absolute acceleration ``(horizontal, vertical)`` of the block's point at the arm ``(a, b)`` from the pivot.

    The point is at ``X = -s B/2 + a cos(theta) - b sin(theta)``, ``Y = a sin(theta) + b cos(theta)``
    from the centre of the base (docs/model.md section 13), and the ground adds ``ag`` to ``X''``
    and ``agy`` to ``Y''``.
    """
    sin, cos = np.sin(theta), np.cos(theta)
    along, across = a * sin + b * cos, a * cos - b * sin
    return ag - along * ddtheta - across * dtheta**2, agy + across * ddtheta - along * dtheta**2


def block_accelerations(s, theta, dtheta, ddtheta, ag, B, H, e):
    """Absolute horizontal accelerations of the centre of the top side ``(0, H)`` and of ``G``: ``(a_top, a_cm)``."""
    d, _ = arms(s, 0.0, B, e)
    top = block_point_acceleration(s, theta, dtheta, ddtheta, ag, 0.0, s * B / 2, H)
    centroid = block_point_acceleration(s, theta, dtheta, ddtheta, ag, 0.0, d, H / 2)
    return top[0], centroid[0]


def mass_acceleration(s, theta, x, dtheta, dx, ddtheta, ddx, ag, agy, B, H, h):
    """Absolute acceleration ``(horizontal, vertical)`` of the damper's mass, at the arm ``(xi_s, eta)``.

    Differentiating ``X = -s B/2 + xi cos(theta) - eta sin(theta)``, ``Y = xi sin(theta) + eta cos(theta)``
    twice with ``xi' = dx``: the terms of a fixed point plus ``ddx (cos, sin)`` and the Coriolis
    term ``2 dx dtheta (-sin, cos)``.
    """
    _, xi = arms(s, x, B, 0.0)
    sin, cos = np.sin(theta), np.cos(theta)
    fixed = block_point_acceleration(s, theta, dtheta, ddtheta, ag, agy, xi, H + h)
    return fixed[0] + ddx * cos - 2 * dx * dtheta * sin, fixed[1] + ddx * sin + 2 * dx * dtheta * cos


def base_reaction(s, theta, x, dtheta, dx, ddtheta, ddx, ag, agy, M, I_G, B, H, e, g, m, h):
    """Base shear, vertical reaction and overturning moment ``(V_b, N_b, M_b)`` (docs/model.md section 13).

    Newton for the block and the mass: ``V_b = M a_G,x + m a_m,x``, ``N_b = M (a_G,y + g) + m (a_m,y + g)``;
    the moment of the reaction about the centre of the base ``O`` balances the rate of angular
    momentum and the weights' moment there, ``sum r x m (a + g e_y) + I_G ddtheta``; ``M_b`` is minus it.
    """
    d, xi = arms(s, x, B, e)
    sin, cos = np.sin(theta), np.cos(theta)
    aG = block_point_acceleration(s, theta, dtheta, ddtheta, ag, agy, d, H / 2)
    am = mass_acceleration(s, theta, x, dtheta, dx, ddtheta, ddx, ag, agy, B, H, h)
    rG = (-s * B / 2 + d * cos - H / 2 * sin, d * sin + H / 2 * cos)
    rm = (-s * B / 2 + xi * cos - (H + h) * sin, xi * sin + (H + h) * cos)
    FG = (M * aG[0], M * (aG[1] + g))
    Fm = (m * am[0], m * (am[1] + g))
    moment = rG[0] * FG[1] - rG[1] * FG[0] + rm[0] * Fm[1] - rm[1] * Fm[0] + I_G * ddtheta
    return FG[0] + Fm[0], FG[1] + Fm[1], -moment
