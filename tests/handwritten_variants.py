"""Hand-written equations of the ``pendulum`` and ``omd2`` variants, and of a locked rigid block.

Like :mod:`rocking.reference.paper` for ``omd``, this module is a yardstick: it is derived
by hand (the steps are in the comments), uses plain NumPy, and never imports
SymPy or ``derive/``. Every function takes a mapping ``v`` of arrays keyed by
argument name (``s``, the state names, ``ag``, ``agy`` and the parameter names of the
variant's manifest) and returns the outputs in the order of the generated
function of the same name. The functions broadcast and keep the dtype of their
inputs, so a reference can be computed in ``np.longdouble``.

Conventions (docs/model.md sections 1-2): block frame with its origin at the centre of
the base, ``y`` up; pivot ``P_s = (-s B/2, 0)``; a point ``r`` of the block frame,
measured from the pivot, is at ``P_s + R(theta) r`` in the frame translating with
the ground. The ground acceleration enters as the inertial force ``-(mass) (ag, agy)``
on every body, i.e. as the potential ``(mass) (ag X + agy Y)``: ``agy`` beside every ``g``.
"""

from __future__ import annotations

import numpy as np


# ----------------------------------------------------------------------------- helpers
def _rot(theta, p):
    """``R(theta) p``."""
    c, s = np.cos(theta), np.sin(theta)
    return (p[0] * c - p[1] * s, p[0] * s + p[1] * c)


def _perp(p):
    """``k x p``: the velocity of ``p`` under a unit counter-clockwise rotation."""
    return (-p[1], p[0])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _add(*ps):
    return (sum(p[0] for p in ps), sum(p[1] for p in ps))


def _scale(k, p):
    return (k * p[0], k * p[1])


def _sq(p):
    return p[0] ** 2 + p[1] ** 2


def solve(A, b):
    """Solve the small linear systems ``A z = b`` case by case.

    ``A`` is a nested ``n x n`` list of arrays, ``b`` a list of ``n`` arrays;
    Gaussian elimination with partial pivoting, vectorised over the cases, in
    the dtype of the inputs (``np.linalg`` has no long double).
    """
    n = len(b)
    flat = np.broadcast_arrays(*[np.asarray(a) for row in A for a in row], *[np.asarray(x) for x in b])
    shape = flat[0].shape
    dtype = np.result_type(*flat, np.float64)
    aug = np.empty((int(np.prod(shape, dtype=int)), n, n + 1), dtype=dtype)
    for i in range(n):
        for j in range(n):
            aug[:, i, j] = flat[i * n + j].reshape(-1)
        aug[:, i, n] = flat[n * n + i].reshape(-1)
    cases = np.arange(aug.shape[0])
    for k in range(n):
        piv = k + np.argmax(np.abs(aug[:, k:, k]), axis=1)
        row = aug[cases, k].copy()
        aug[cases, k] = aug[cases, piv]
        aug[cases, piv] = row
        for i in range(k + 1, n):
            f = aug[:, i, k] / aug[:, k, k]
            aug[:, i] -= f[:, None] * aug[:, k]
    z = np.zeros((aug.shape[0], n), dtype=dtype)
    for i in reversed(range(n)):
        z[:, i] = (aug[:, i, n] - np.sum(aug[:, i, i + 1 : n] * z[:, i + 1 :], axis=1)) / aug[:, i, i]
    return tuple(z[:, i].reshape(shape) for i in range(n))


def _block(v):
    """``d_s``, ``I_s`` and the position of ``G`` from the pivot in the block frame."""
    s, B, H, e, M, I_G = (v[k] for k in ("s", "B", "H", "e", "M", "I_G"))
    d = s * B / 2 + e
    return d, I_G + M * (d**2 + H**2 / 4), (d, H / 2 + 0 * d)


def _block_velocity(v):
    """Position of ``G`` (from the pivot, rotated) and its velocity while rocking about ``s``."""
    _, _, rG = _block(v)
    XG = _rot(v["theta"], rG)
    return XG, _scale(v["dtheta"], _perp(XG))


def _upright(v, z):
    """``v`` with ``theta = 0``; ``z`` also zeroes ``dtheta`` (full contact)."""
    zero = 0 * v["theta"]
    return dict(v, theta=zero, dtheta=zero) if z else dict(v, theta=zero)


def _rigid_moments(v, masses):
    """Gravity and ground-inertia moments about the pivot of point masses ``[(m, r)]``
    (``r`` from the pivot in the block frame), and the sum ``sum m r`` of their arms.

    A weight ``(0, -m g)`` at ``X = R r`` has the moment ``X x F = -m g X_x``; the
    inertial force ``(-m ag, -m agy)`` has ``-X_y (-m ag) + X_x (-m agy) = m ag X_y - m agy X_x``.
    """
    th, g, ag, agy = v["theta"], v["g"], v["ag"], v["agy"]
    out = 0 * th
    for m, r in masses:
        X = _rot(th, r)
        out = out - m * g * X[0] + m * ag * X[1] - m * agy * X[0]
    return out


def _point_acceleration(v, r, dr, ddr, ddtheta):
    """Absolute acceleration of a point at the block-frame arm ``r`` from the pivot, moving on the block with the
    block-frame velocity ``dr`` and acceleration ``ddr``.

    ``X = P_s + R(theta) r + (x_g, y_g)``; differentiating twice, with ``R' = dtheta R k x``:
    ``X'' = R [ddr + 2 dtheta k x dr + ddtheta k x r - dtheta^2 r] + (ag, agy)``.
    """
    dth = v["dtheta"]
    inner = _add(ddr, _scale(2 * dth, _perp(dr)), _scale(ddtheta, _perp(r)), _scale(-(dth**2), r))
    a = _rot(v["theta"], inner)
    return a[0] + v["ag"], a[1] + v["agy"]


def _loads(v, bodies, ddtheta):
    """``(a_top, a_cm)`` and ``(V_b, N_b, M_b)`` of the block and ``bodies`` ``[(m, r, dr, ddr)]`` (point masses).

    Newton and Euler for each body, summed: the ground's reaction is ``sum m (a + g e_y)``, its moment about
    the centre of the base ``O`` is ``sum (X - O) x m (a + g e_y) + I_G ddtheta`` with ``X - O = P_s + R r``;
    ``M_b`` is minus that moment (docs/model.md section 13).
    """
    zero = (0 * v["theta"], 0 * v["theta"])
    s, B, H, g = v["s"], v["B"], v["H"], v["g"]
    _, _, rG = _block(v)
    top = _point_acceleration(v, (s * B / 2, H + 0 * s), zero, zero, ddtheta)
    everything = [(v["M"], rG, zero, zero)] + list(bodies)
    shear, normal, moment = 0 * s, 0 * s, v["I_G"] * ddtheta
    for m, r, dr, ddr in everything:
        a = _point_acceleration(v, r, dr, ddr, ddtheta)
        F = (m * a[0], m * (a[1] + g))
        moment = moment + _cross(_add((-s * B / 2, 0 * s), _rot(v["theta"], r)), F)
        shear, normal = shear + F[0], normal + F[1]
    centroid = _point_acceleration(v, rG, zero, zero, ddtheta)
    return (top[0], centroid[0]), (shear, normal, -moment)


def _affine(loads, v, accelerations):
    """The layout of the generated functions affine in the accelerations: per quantity of ``loads(dd)``
    (``dd`` the accelerations by name), its value at zero accelerations, then its coefficients (exact
    differences: ``loads`` is affine in them)."""
    zero = 0 * v["theta"]
    free = loads({a: zero for a in accelerations})
    units = [loads({b: zero + (a == b) for b in accelerations}) for a in accelerations]
    return tuple(c for j, f in enumerate(free) for c in (f, *(u[j] - f for u in units)))


class _Weights:
    """The static critical angle from a model's ``weights(v)``: lever arm and height of the weights."""

    @classmethod
    def critical_angle(cls, v):
        # The combined centre of mass straight above the pivot.
        return np.arctan2(*cls.weights(v))

    @classmethod
    def critical_tangent(cls, v):
        # Where the weights' centre is above the ground, NaN elsewhere.
        lever, height = cls.weights(v)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(height > 0, lever / height, np.nan)

    @staticmethod
    def stop_gaps(v):
        # These models' guides have no end stops: no penetration to report.
        return ()

    @staticmethod
    def stop_forces(v):
        return ()

    @staticmethod
    def stop_contact(v):
        return ()

    @staticmethod
    def stop_approach(v):
        return ()


# ----------------------------------------------------------------------------- pendulum
class Pendulum(_Weights):
    """Block with a pendulum mass damper: bob ``m`` on a massless rod ``l`` hinged at
    ``(x_p, y_p)``, relative angle ``phi`` (0: hanging down), spring ``k_phi``, dashpot ``c_phi``.

    Derivation. With ``a = x_p + s B/2`` and ``b = y_p`` (the hinge from the pivot),
    the bob is at ``r = (a + l sin phi, b - l cos phi)`` from the pivot in the block
    frame, so, absolutely, ``X = -s B/2 + a cos(th) - b sin(th) + l sin(th + phi)`` and
    ``Y = a sin(th) + b cos(th) - l cos(th + phi)``. Differentiating and expanding
    ``|V|^2`` the cross term collapses with ``sin(th + phi) cos(th) - cos(th + phi) sin(th)
    = sin(phi)``, which leaves, with ``kappa = a sin(phi) - b cos(phi)`` and
    ``w = dtheta + dphi`` (the rod's absolute angular velocity)::

        T_bob = m/2 [dtheta^2 (a^2 + b^2) + l^2 w^2 + 2 l dtheta w kappa]

    No ``theta`` in T: only ``phi`` makes the mass matrix vary.
    """

    @staticmethod
    def _arms(v):
        a = v["x_p"] + v["s"] * v["B"] / 2
        b = v["y_p"] + 0 * a
        phi = v["phi"]
        kappa = a * np.sin(phi) - b * np.cos(phi)
        # d kappa / d phi: every Christoffel term is proportional to it.
        dkappa = a * np.cos(phi) + b * np.sin(phi)
        return a, b, kappa, dkappa

    @staticmethod
    def mass_matrix(v):
        # T_bob with w = dtheta + dphi: collect dtheta^2, 2 dtheta dphi and dphi^2.
        _, I_s, _ = _block(v)
        a, b, kappa, _ = Pendulum._arms(v)
        m, ell = v["m"], v["l"]
        m11 = I_s + m * (a**2 + b**2 + ell**2 + 2 * ell * kappa)
        m12 = m * (ell**2 + ell * kappa)
        m22 = m * ell**2 + 0 * m11
        return m11, m12, m12, m22

    @staticmethod
    def forcing(v):
        """Lagrange: ``Mq'' = -C - dV/dq - dD/dq'`` with the effective potential
        ``V = (g + agy) (M Y_G + m Y_bob) + ag (M X_G + m X_bob) + k_phi phi^2 / 2``."""
        th, phi, dth, dphi = v["theta"], v["phi"], v["dtheta"], v["dphi"]
        M, ag, m, ell, k, c = (v[key] for key in ("M", "ag", "m", "l", "k_phi", "c_phi"))
        g = v["g"] + v["agy"]
        H = v["H"]
        d, _, _ = _block(v)
        a, b, _, dk = Pendulum._arms(v)
        # Only M11 (through 2 m ell kappa) and M12 (through m ell kappa) depend on phi, so
        # C_i = sum_jk (dM_ij/dq_k - dM_jk/dq_i / 2) dq_j dq_k gives
        # C_theta = m ell kappa' (2 dtheta dphi + dphi^2) and C_phi = -m ell kappa' dtheta^2.
        C_th = m * ell * dk * (2 * dth * dphi + dphi**2)
        C_phi = -m * ell * dk * dth**2
        sin, cos = np.sin(th), np.cos(th)
        sp_, cp_ = np.sin(th + phi), np.cos(th + phi)
        # dY/dtheta of G: d cos - H/2 sin; of the bob: a cos - b sin + ell sin(th + phi).
        # dX/dtheta of G: -(d sin + H/2 cos); of the bob: -(a sin + b cos) + ell cos(th + phi).
        dV_th = g * (M * (d * cos - H / 2 * sin) + m * (a * cos - b * sin + ell * sp_)) - ag * (
            M * (d * sin + H / 2 * cos) + m * (a * sin + b * cos - ell * cp_)
        )
        # dY/dphi = ell sin(th + phi), dX/dphi = ell cos(th + phi).
        dV_phi = m * g * ell * sp_ + ag * m * ell * cp_ + k * phi
        return -C_th - dV_th, -C_phi - dV_phi - c * dphi

    @staticmethod
    def rocking_accel(v):
        m11, m12, _, m22 = Pendulum.mass_matrix(v)
        f1, f2 = Pendulum.forcing(v)
        return solve([[m11, m12], [m12, m22]], [f1, f2])

    @staticmethod
    def contact_accel(v):
        # The ground holds theta: only the phi row of the rocking equations is left.
        u = _upright(v, True)
        _, f2 = Pendulum.forcing(u)
        _, _, _, m22 = Pendulum.mass_matrix(u)
        return 0 * f2, f2 / m22

    @staticmethod
    def uplift(v):
        # theta row with a constraint moment lam about the pivot: M11*0 + M12 phi'' = f1 + lam.
        # The ground can only push: lam >= 0 about A (s = 1), <= 0 about A' (s = -1),
        # so the block lifts when -s lam = s (f1 - M12 phi'') turns positive.
        u = _upright(v, True)
        _, m12, _, _ = Pendulum.mass_matrix(u)
        f1, _ = Pendulum.forcing(u)
        _, ddphi = Pendulum.contact_accel(u)
        return v["s"] * (f1 - m12 * ddphi)

    @staticmethod
    def _bob(v):
        """Bob from the pivot (block frame), its block-frame velocity, and the rod vector."""
        a, b, _, _ = Pendulum._arms(v)
        phi, ell = v["phi"], v["l"]
        rod = (ell * np.sin(phi), -ell * np.cos(phi))
        return (a + rod[0], b + rod[1]), _scale(v["dphi"], (ell * np.cos(phi), ell * np.sin(phi))), rod

    @staticmethod
    def impact(v):
        """Angular momentum about the new pivot (impulse there) and the bob's angular
        momentum about its hinge (the massless rod can only push along itself, and the
        spring and dashpot carry no impulse) are both conserved; written from absolute
        positions and velocities at theta = 0, where the block frame is the ground frame."""
        u = _upright(v, False)
        s, B, M, I_G, m = u["s"], u["B"], u["M"], u["I_G"], u["m"]
        dth = u["dtheta"]
        _, _, rG = _block(u)
        rb, drb, rod = Pendulum._bob(u)
        shift = s * B + 0 * dth  # new pivot P_-s minus old P_s, along x
        # Before: rotation about P_s. Positions from the new pivot: r - (s B, 0).
        VG = _scale(dth, _perp(rG))
        Vb = _add(_scale(dth, _perp(rb)), drb)
        G_new = (rG[0] - shift, rG[1])
        b_new = (rb[0] - shift, rb[1])
        L_before = I_G * dth + M * _cross(G_new, VG) + m * _cross(b_new, Vb)
        h_before = _cross(rod, Vb)
        # After: rotation dtheta+ about P_-s and rod rate dphi+; both momenta are linear in them.
        unit_rod_rate = (u["l"] * np.cos(u["phi"]), u["l"] * np.sin(u["phi"]))
        A = [
            [I_G + M * _sq(G_new) + m * _sq(b_new), m * _cross(b_new, unit_rod_rate)],
            [_cross(rod, _perp(b_new)), _cross(rod, unit_rod_rate)],
        ]
        return solve(A, [L_before, h_before])

    @staticmethod
    def _velocities(v):
        XG, VG = _block_velocity(v)
        rb, drb, _ = Pendulum._bob(v)
        Xb = _rot(v["theta"], rb)
        Vb = _add(_scale(v["dtheta"], _perp(Xb)), _rot(v["theta"], drb))
        return XG, VG, Xb, Vb

    @staticmethod
    def energy(v):
        # From absolute velocities, not from the mass matrix: an independent check of T.
        XG, VG, Xb, Vb = Pendulum._velocities(v)
        M, m, g = v["M"], v["m"], v["g"]
        T = v["I_G"] * v["dtheta"] ** 2 / 2 + M * _sq(VG) / 2 + m * _sq(Vb) / 2
        return T + g * (M * XG[1] + m * Xb[1]) + v["k_phi"] * v["phi"] ** 2 / 2

    @staticmethod
    def power(v):
        _, VG, _, Vb = Pendulum._velocities(v)
        inertial = v["ag"] * (v["M"] * VG[0] + v["m"] * Vb[0]) + v["agy"] * (v["M"] * VG[1] + v["m"] * Vb[1])
        return -v["c_phi"] * v["dphi"] ** 2 - inertial

    @staticmethod
    def _loads(v, dd):
        # The bob moves on the block along the rod's circle: dr = dphi l (cos, sin), and ddr adds the
        # centripetal dphi^2 l (-sin, cos).
        rb, drb, _ = Pendulum._bob(v)
        phi, ell, dphi = v["phi"], v["l"], v["dphi"]
        along, inward = (np.cos(phi), np.sin(phi)), (-np.sin(phi), np.cos(phi))
        ddr = _add(_scale(dd["ddphi"] * ell, along), _scale(dphi**2 * ell, inward))
        return _loads(v, [(v["m"], rb, drb, ddr)], dd["ddtheta"])

    @staticmethod
    def block_accelerations(v):
        return _affine(lambda dd: Pendulum._loads(v, dd)[0], v, ("ddtheta", "ddphi"))

    @staticmethod
    def base_reaction(v):
        return _affine(lambda dd: Pendulum._loads(v, dd)[1], v, ("ddtheta", "ddphi"))

    @staticmethod
    def element_forces(v):
        # The hinge's spring and dashpot: a moment about the hinge, on the block and against the rod.
        return (v["k_phi"] * v["phi"] + v["c_phi"] * v["dphi"],)

    @staticmethod
    def weights(v):
        """Lever arm and height of the weights about the pivot (over g), phi held relative to the block."""
        _, _, rG = _block(v)
        rb, _, _ = Pendulum._bob(v)
        M, m = v["M"], v["m"]
        return M * rG[0] + m * rb[0], M * rG[1] + m * rb[1]


# ----------------------------------------------------------------------------- omd2
class OMD2(_Weights):
    """Block with two masses on horizontal guides: ``m1`` at ``(x1, H + h)``, ``m2`` at
    ``(x2, H/2)``, springs ``k1``, ``k2``, dashpots ``c1``, ``c2``.

    Derivation. A mass at ``(x, eta)`` of the block frame is at ``r = (xi, eta)`` from the
    pivot with ``xi = s B/2 + x``; ``X = -s B/2 + xi cos - eta sin``, ``Y = xi sin + eta cos``
    and ``|V|^2 = dx^2 + dtheta^2 (xi^2 + eta^2) - 2 eta dx dtheta`` (the rotation terms
    of the cross product cancel). The two masses do not see each other: every term is
    a sum over the masses of docs/model.md (R1)-(R2)-like terms.
    """

    @staticmethod
    def _masses(v):
        s, B = v["s"], v["B"]
        return (
            (v["m1"], s * B / 2 + v["x1"], v["H"] + v["h"], v["k1"], v["c1"], v["x1"], v["dx1"]),
            (v["m2"], s * B / 2 + v["x2"], v["H"] / 2 + 0 * v["x2"], v["k2"], v["c2"], v["x2"], v["dx2"]),
        )

    @staticmethod
    def mass_matrix(v):
        _, I_s, _ = _block(v)
        (m1, xi1, eta1, *_), (m2, xi2, eta2, *_) = OMD2._masses(v)
        z = 0 * I_s
        m11 = I_s + m1 * (xi1**2 + eta1**2) + m2 * (xi2**2 + eta2**2)
        return (m11, -m1 * eta1 + z, -m2 * eta2 + z, -m1 * eta1 + z, m1 + z, z, -m2 * eta2 + z, z, m2 + z)

    @staticmethod
    def forcing(v):
        th, dth, ag, M, H = (v[k] for k in ("theta", "dtheta", "ag", "M", "H"))
        g = v["g"] + v["agy"]  # the weights and the vertical inertial forces
        d, _, _ = _block(v)
        sin, cos = np.sin(th), np.cos(th)
        # M11 depends on x_i through m_i xi_i^2: C_theta = sum 2 m xi dtheta dx,
        # C_x = -m xi dtheta^2 (the centrifugal pull along the guide).
        lever = M * d
        height = M * H / 2
        f_th = 0 * th
        f_x = []
        for m, xi, eta, k, c, x, dx in OMD2._masses(v):
            lever = lever + m * xi
            height = height + m * eta
            f_th = f_th - 2 * m * xi * dth * dx
            # dV/dx: weight along the tilted guide m g sin, ground inertia m ag cos, spring k x.
            f_x.append(m * xi * dth**2 - m * g * sin - m * ag * cos - k * x - c * dx)
        # dV/dtheta: g (sum m (xi cos - eta sin)) - ag (sum m (xi sin + eta cos)), G included.
        f_th = f_th - g * (lever * cos - height * sin) + ag * (lever * sin + height * cos)
        return (f_th, *f_x)

    @staticmethod
    def rocking_accel(v):
        mm = OMD2.mass_matrix(v)
        return solve([list(mm[0:3]), list(mm[3:6]), list(mm[6:9])], list(OMD2.forcing(v)))

    @staticmethod
    def contact_accel(v):
        u = _upright(v, True)
        _, f1, f2 = OMD2.forcing(u)
        return 0 * f1, f1 / u["m1"], f2 / u["m2"]

    @staticmethod
    def uplift(v):
        # As for the pendulum: lam = sum M1i x_i'' - f_theta, uplift = -s lam.
        u = _upright(v, True)
        mm = OMD2.mass_matrix(u)
        f_th, _, _ = OMD2.forcing(u)
        _, a1, a2 = OMD2.contact_accel(u)
        return u["s"] * (f_th - mm[1] * a1 - mm[2] * a2)

    @staticmethod
    def impact(v):
        """Angular momentum about the new pivot, and each mass's absolute horizontal
        velocity (its momentum over its mass: the frictionless guide and the spring
        and dashpot carry no horizontal impulse), conserved; a 3x3 linear system."""
        u = _upright(v, False)
        s, B, M, I_G, dth = u["s"], u["B"], u["M"], u["I_G"], u["dtheta"]
        _, _, rG = _block(u)
        shift = s * B + 0 * dth
        G_new = (rG[0] - shift, rG[1])
        L = I_G * dth + M * _cross(G_new, _scale(dth, _perp(rG)))
        row0 = [I_G + M * _sq(G_new)]
        rows, rhs = [], []
        for i, (m, xi, eta, _, _, _, dx) in enumerate(OMD2._masses(u)):
            r_new = (xi - shift, eta)
            V = _add(_scale(dth, _perp((xi, eta))), (dx, 0 * dx))  # before, about P_s
            L = L + m * _cross(r_new, V)
            # after: V+ = dtheta+ k x r_new + (dx+, 0)
            row0[0] = row0[0] + m * _sq(r_new)
            row0.append(m * _cross(r_new, (1.0 + 0 * dx, 0 * dx)))
            row = [-eta, 0 * eta, 0 * eta]
            row[1 + i] = 1.0 + 0 * eta
            rows.append(row)
            rhs.append(V[0])
        return solve([row0, *rows], [L, *rhs])

    @staticmethod
    def _velocities(v):
        XG, VG = _block_velocity(v)
        out = []
        for m, xi, eta, _, _, _, dx in OMD2._masses(v):
            X = _rot(v["theta"], (xi, eta))
            out.append((m, X, _add(_scale(v["dtheta"], _perp(X)), _rot(v["theta"], (dx, 0 * dx)))))
        return XG, VG, out

    @staticmethod
    def energy(v):
        XG, VG, masses = OMD2._velocities(v)
        M, g = v["M"], v["g"]
        E = v["I_G"] * v["dtheta"] ** 2 / 2 + M * _sq(VG) / 2 + M * g * XG[1]
        for m, X, V in masses:
            E = E + m * _sq(V) / 2 + m * g * X[1]
        return E + v["k1"] * v["x1"] ** 2 / 2 + v["k2"] * v["x2"] ** 2 / 2

    @staticmethod
    def power(v):
        _, VG, masses = OMD2._velocities(v)
        P = -v["c1"] * v["dx1"] ** 2 - v["c2"] * v["dx2"] ** 2 - v["M"] * (v["ag"] * VG[0] + v["agy"] * VG[1])
        for m, _, V in masses:
            P = P - m * (v["ag"] * V[0] + v["agy"] * V[1])
        return P

    @staticmethod
    def _loads(v, dd):
        # Each mass slides along its guide: dr = (dx, 0), ddr = (ddx, 0).
        zero = 0 * v["theta"]
        bodies = [
            (m, (xi, eta), (dx, zero), (dd[name], zero))
            for (m, xi, eta, *_, dx), name in zip(OMD2._masses(v), ("ddx1", "ddx2"))
        ]
        return _loads(v, bodies, dd["ddtheta"])

    @staticmethod
    def block_accelerations(v):
        return _affine(lambda dd: OMD2._loads(v, dd)[0], v, ("ddtheta", "ddx1", "ddx2"))

    @staticmethod
    def base_reaction(v):
        return _affine(lambda dd: OMD2._loads(v, dd)[1], v, ("ddtheta", "ddx1", "ddx2"))

    @staticmethod
    def element_forces(v):
        return tuple(k * x + c * dx for *_, k, c, x, dx in OMD2._masses(v))

    @staticmethod
    def weights(v):
        """Lever arm and height of the weights about the pivot (over g)."""
        _, _, rG = _block(v)
        lever, height = v["M"] * rG[0], v["M"] * rG[1]
        for m, xi, eta, *_ in OMD2._masses(v):
            lever, height = lever + m * xi, height + m * eta
        return lever, height

    @staticmethod
    def uplift_energy(v):
        """Least ``sum k x^2/2 + m dx^2/2`` on the uplift hyperplane without ground motion.

        ``u = u0 + sum_j a_j z_j`` is linear in ``z = (x1, x2, dx1, dx2)`` with
        ``u0 = -g [M (B/2 + s e) + (m1 + m2) B/2]``, ``a_x = -s (eta k + m g)``,
        ``a_v = -s eta c``; minimising ``sum K_j z_j^2 / 2`` on ``u = 0`` (Lagrange
        multiplier) gives ``u0^2 / (2 sum a_j^2 / K_j)``; 0 if the block lifts at rest.
        """
        s, g, M, B, e = (v[k] for k in ("s", "g", "M", "B", "e"))
        (m1, _, eta1, k1, c1, *_), (m2, _, eta2, k2, c2, *_) = OMD2._masses(v)
        u0 = -g * (M * (B / 2 + s * e) + (m1 + m2) * B / 2)
        denom = (eta1 * k1 + m1 * g) ** 2 / k1 + (eta2 * k2 + m2 * g) ** 2 / k2
        denom = denom + (eta1 * c1) ** 2 / m1 + (eta2 * c2) ** 2 / m2
        return np.maximum(-u0, 0) ** 2 / (2 * denom)

    @staticmethod
    def _potential(v, free):
        """Potential at rest velocities, each mass in ``free`` at its own least (the others where ``v`` puts them).

        A mass's terms ``m g xi sin + k x^2 / 2`` (``xi = s B/2 + x``) are least at
        ``x = -m g sin / k``, where they fall by ``(m g sin)^2 / (2 k)`` below their value at ``x = 0``.
        """
        th, g = v["theta"], v["g"]
        XG, _, masses = OMD2._velocities(dict(v, dtheta=0 * th, dx1=0 * th, dx2=0 * th))
        V = v["M"] * g * XG[1]
        for j, ((m, X, _), (*_, k, _, x, _)) in enumerate(zip(masses, OMD2._masses(v))):
            at_zero = m * g * (X[1] - x * np.sin(th))
            V = V + (at_zero - (m * g * np.sin(th)) ** 2 / (2 * k) if j in free else m * g * X[1] + k * x**2 / 2)
        return V

    @staticmethod
    def least_potential(v):
        return OMD2._potential(v, free=(0, 1))

    @staticmethod
    def least_stroke_potential(v):
        return OMD2._potential(v, free=(1,))


# ----------------------------------------------------------------------------- locked rigid block
class Rigid:
    """The block with a point mass ``m`` rigidly fixed at ``(x_m, y_m)`` of the block frame:
    the limit of any damper locked by an infinitely stiff spring. One coordinate.

    Arguments are plain values or arrays (not a mapping): ``s, theta, dtheta, ag`` and
    ``M, I_G, B, H, e, g, m, x_m, y_m``.
    """

    @staticmethod
    def _pts(s, M, B, H, e, m, x_m, y_m):
        return [(M, (s * B / 2 + e, H / 2)), (m, (s * B / 2 + x_m, y_m))]

    @staticmethod
    def inertia(s, M, I_G, B, H, e, m, x_m, y_m):
        # Parallel axes about the pivot for G, plus m |r|^2 for the point mass.
        return I_G + sum(mass * _sq(r) for mass, r in Rigid._pts(s, M, B, H, e, m, x_m, y_m))

    @staticmethod
    def rocking_accel(s, theta, dtheta, ag, M, I_G, B, H, e, g, m, x_m, y_m):
        # One rigid body about a fixed corner: I ddtheta = sum of moments about it.
        v = {"theta": theta, "g": g, "ag": ag, "agy": 0.0}
        moment = _rigid_moments(v, Rigid._pts(s, M, B, H, e, m, x_m, y_m))
        return moment / Rigid.inertia(s, M, I_G, B, H, e, m, x_m, y_m)

    @staticmethod
    def uplift(s, ag, M, B, H, e, g, m, x_m, y_m):
        # Moment about the pivot at theta = 0 that the ground would have to supply, times -s.
        return s * _rigid_moments({"theta": 0.0, "g": g, "ag": ag, "agy": 0.0}, Rigid._pts(s, M, B, H, e, m, x_m, y_m))

    @staticmethod
    def impact(s, dtheta, M, I_G, B, H, e, m, x_m, y_m):
        # Everything moves with the block: only the angular momentum about the new pivot.
        before = I_G * dtheta
        for mass, r in Rigid._pts(s, M, B, H, e, m, x_m, y_m):
            before = before + mass * _cross((r[0] - s * B, r[1]), _scale(dtheta, _perp(r)))
        return before / Rigid.inertia(-s, M, I_G, B, H, e, m, x_m, y_m)

    @staticmethod
    def critical_angle(s, M, B, H, e, m, x_m, y_m):
        pts = Rigid._pts(s, M, B, H, e, m, x_m, y_m)
        return np.arctan2(sum(mass * r[0] for mass, r in pts), sum(mass * r[1] for mass, r in pts))


#: The hand-written models by variant name.
HANDWRITTEN = {"pendulum": Pendulum, "omd2": OMD2}
