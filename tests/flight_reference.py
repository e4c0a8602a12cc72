"""The block on a floor it can leave: Newton and Euler with contact forces and impulses, typed by hand.

The outside check of issue 39 (docs/model.md sections 6, 11, 15 and 16): independent of ``derive/``, ``generated/``,
``rocking.sim`` and ``rocking.reference``. The block is one rigid body, its centroid ``G`` at ``(X, Y)`` relative to
the ground (``(e, H / 2)`` at rest), turned by ``theta``; its base corners ``k = +1`` (``A``, left) and ``k = -1``
(``A'``, right) at ``r_k = (-k B / 2 - e, -H / 2)`` from ``G`` in the block frame, at rest at ``(-k B / 2, 0)``. The
damper, if any, is a point mass ``m`` on a guide along the block's ``x`` at ``rho = (x - e, H + h - H / 2)`` from
``G``, held by a spring ``k_m`` and a dashpot ``c`` (the force ``G_x = k_m x + c dx`` on the mass, ``-G_x`` along
the guide, and its reaction on the block) and by the guide's normal force ``N_g``. The ground accelerates by
``(ddx_g, ddy_g)``: relative to it every body carries ``-(mass) (ddx_g, g + ddy_g)``.

Every contact state is the same linear system (:func:`dynamics`): Newton for the block and the mass, Euler for the
block about ``G``, and the contact's constraints, with the unknowns ``a_G``, ``ddtheta``, ``ddx``, ``N_g`` and the
floor's forces: in ``flight`` none; ``rocking`` about ``k``: the corner ``k``'s normal acceleration is 0 and its
tangential one too (stuck) or ``F = -mu_k sigma N`` (sliding in the direction ``sigma``); full ``contact``: both
corners' normal accelerations are 0 (so ``ddtheta = 0``) and the base's tangential one too or Coulomb's. It uplifts
where a corner's ``N`` falls to 0, takes off where every ``N`` does, slips where ``|F|`` reaches ``mu_s N``.

Impacts and landings are the same equations with impulses (:func:`impulses`): the floor's on the corners that touch,
the guide's normal to it on the mass (none along it: the mass keeps its momentum along the guide, the momentum law
of section 6), the touching corners' normal velocity ``-e_n`` times the one before (0 at an impact, Housner's), the
slip after 0 (stick, if the floor holds ``|P_t| <= mu_s P_n``) or ``P_t = -mu_k sigma P_n``. A flat landing
(``|sin theta| <= FLAT``) puts both corners down; where one would pull, the other lands alone.

Each state is integrated by SciPy's DOP853 with its exits as events; the phases follow docs/simulation.md's rules:
the rest snap below ``dtheta_rest`` (the mass keeps its absolute velocity), rest in full contact after the motion
once the damper's energy is below ``energy_rest``, and ``t_max``; no early rest or verdict. Where the spec of issue
39 and the back ends part (a stuck corner of the paper's floor whose ``N`` reaches 0 while its free flight would
drive it into the floor), :func:`simulate` follows either (``lifts``).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg.lapack import dgesv

#: A landing is flat, on both corners, where ``|sin theta|`` is at most this (docs/model.md section 16).
FLAT = 1e-12
#: How far along the free flight a stuck corner's takeoff looks whether the corner rises [s] (:meth:`_Sim.sinks`).
PROBE = 1e-6


def _rot(theta: float, x: float, y: float) -> np.ndarray:
    c, s = math.cos(theta), math.sin(theta)
    return np.array([c * x - s * y, s * x + c * y])


def _solve(A, b) -> np.ndarray:
    """``A^-1 b`` by LAPACK's dgesv (numpy.linalg.solve's, without its checks: a fifth of its cost here)."""
    _, _, z, info = dgesv(A, b)
    if info:
        raise np.linalg.LinAlgError(f"a singular system (dgesv info {info})")
    return z


def _perp(a) -> np.ndarray:
    """``J a``, the quarter turn: ``d/dt (R r) = omega J R r``."""
    return np.array([-a[1], a[0]])


@dataclass(frozen=True)
class Body:
    """The block [kg, kg m^2, m, m, m, m/s^2] and its damper (``m = 0``: none) [kg, m, N/m, N s/m].

    A state ``z`` is ``(X, Y, theta, vX, vY, omega, x, dx)``: the centroid relative to the ground, the tilt, their
    rates, the mass's place on the guide and its rate.
    """

    M: float
    I_G: float
    B: float
    H: float
    e: float
    g: float
    m: float = 0.0
    h: float = 0.0
    k_m: float = 0.0
    c: float = 0.0

    def r(self, k: int, theta: float) -> np.ndarray:
        """The corner ``k`` from ``G``, ``R(theta) r_k`` [m]."""
        return _rot(theta, -k * self.B / 2 - self.e, -self.H / 2)

    def rho(self, theta: float, x: float) -> np.ndarray:
        """The mass from ``G`` [m]."""
        return _rot(theta, x - self.e, self.h + self.H / 2)

    def corner(self, k: int, z) -> tuple[np.ndarray, np.ndarray]:
        """The corner ``k``'s ``(u, v)`` from its place at rest and ``(du, dv)``."""
        r = self.r(k, z[2])
        return np.array([z[0] + r[0] + k * self.B / 2, z[1] + r[1]]), np.array([z[3], z[4]]) + z[5] * _perp(r)

    def centroid(self, k, theta, u, du, omega, v=0.0, dv=0.0, *, x=0.0, dx=0.0) -> np.ndarray:
        """``z`` of the block whose corner ``k`` is at ``(u, v)`` from its rest moving at ``(du, dv)``."""
        r = self.r(k, theta)
        vG = np.array([du, dv]) - omega * _perp(r)
        return np.array([u - k * self.B / 2 - r[0], v - r[1], theta, vG[0], vG[1], omega, x, dx])

    def mass_velocity(self, z) -> np.ndarray:
        rho = self.rho(z[2], z[6])
        return np.array([z[3], z[4]]) + z[5] * _perp(rho) + z[7] * _rot(z[2], 1.0, 0.0)

    def damper_energy(self, z) -> float:
        return self.k_m * z[6] ** 2 / 2 + self.m * float(np.sum(self.mass_velocity(z) ** 2)) / 2

    def energy(self, z) -> float:
        """Kinetic energy relative to the ground, the weights' potential above the floor and the spring's [J]."""
        kinetic = self.M * (z[3] ** 2 + z[4] ** 2) / 2 + self.I_G * z[5] ** 2 / 2
        weights = self.M * self.g * z[1] + self.m * self.g * (z[1] + self.rho(z[2], z[6])[1])
        return kinetic + weights + self.damper_energy(z)


def _system(body: Body, z, contacts, law: int, mu_k: float):
    """The matrix shared by the forces and the impulses, and the vectors its right-hand sides are made of.

    Unknowns: ``(a_G or v_G+) (2), ddtheta or omega+, [ddx or dx+, N_g or Lambda], F or P_t, N_k or P_k per
    contact``. Rows: the block's Newton (2) and Euler about ``G``, the mass's Newton (2, with a damper), each
    contact's normal constraint, then the tangential one (stick: the first contact's, else Coulomb's). Vectors as
    tuples of floats: ``t``, ``n`` the guide's directions, ``rho`` the mass from ``G``, ``rs`` the contacts from
    ``G`` (a run evaluates this some ten thousand times: no small arrays).
    """
    c, s = math.cos(z[2]), math.sin(z[2])
    t, n = (c, s), (-s, c)
    px, py = z[6] - body.e, body.h + body.H / 2
    rho = (c * px - s * py, s * px + c * py)
    rs = [(c * qx - s * qy, s * qx + c * qy) for qx, qy in ((-k * body.B / 2 - body.e, -body.H / 2) for k in contacts)]
    d = body.m > 0
    nu = 3 + 2 * d + (len(contacts) + 1 if contacts else 0)
    A = np.zeros((nu, nu))
    A[0, 0] = A[1, 1] = body.M
    A[2, 2] = body.I_G
    f = 3 + 2 * d  # the first floor unknown
    if d:
        m = body.m
        A[0, 4], A[1, 4] = n  # -N_g n on the block, moved to the left
        A[2, 4] = rho[0] * n[1] - rho[1] * n[0]
        A[3, 0] = A[4, 1] = m
        A[3, 2], A[4, 2] = -m * rho[1], m * rho[0]  # m J rho
        A[3, 3], A[4, 3] = m * t[0], m * t[1]
        A[3, 4], A[4, 4] = -n[0], -n[1]
    if contacts:
        A[0, f] = -1.0  # the tangential force, at the first contact
        A[2, f] = rs[0][1]  # -(r x (F, 0)) = r_y F
        for j, r in enumerate(rs):
            A[1, f + 1 + j] = -1.0
            A[2, f + 1 + j] = -r[0]
            row = 3 + 2 * d + j
            A[row, 1], A[row, 2] = 1.0, r[0]  # the corner's normal rate: (v_G + omega J r)_y
        last = nu - 1
        if law == 0:
            A[last, 0], A[last, 2] = 1.0, -rs[0][1]
        else:
            A[last, f] = 1.0
            A[last, f + 1 :] = mu_k * law
    return A, t, rho, rs


def dynamics(body: Body, z, ag: float, agy: float, contacts=(), law: int = 0, mu_k: float = 0.0):
    """The accelerations and the floor's forces in a contact state: ``(ddtheta, ddx, a_G, F, N)``, ``N`` one per
    contact (``contacts``: the corners on the floor; ``law`` 0 stuck, else the slip's direction)."""
    A, t, rho, rs = _system(body, z, contacts, law, mu_k)
    omega, dx, d = z[5], z[7], body.m > 0
    gx, gy = -ag, -(body.g + agy)
    G = body.k_m * z[6] + body.c * dx
    b = np.zeros(len(A))
    b[0], b[1] = body.M * gx + G * t[0], body.M * gy + G * t[1]
    b[2] = G * (rho[0] * t[1] - rho[1] * t[0])
    if d:
        m, w2, cor = body.m, omega**2, 2 * body.m * omega * dx
        b[3] = m * gx - G * t[0] + m * w2 * rho[0] + cor * t[1]  # -2 m omega dx J t
        b[4] = m * gy - G * t[1] + m * w2 * rho[1] - cor * t[0]
    for j, r in enumerate(rs):
        b[3 + 2 * d + j] = omega**2 * r[1]
    if contacts and law == 0:
        b[-1] = omega**2 * rs[0][0]
    sol = _solve(A, b)
    f = 3 + 2 * d
    return sol[2], sol[3] if d else 0.0, sol[0:2], (sol[f] if contacts else 0.0), sol[f + 1 :]


def corner_rate(body: Body, k: int, z, ddtheta: float, a_G) -> np.ndarray:
    """The corner ``k``'s acceleration ``(ddu, ddv)``: ``a_G + ddtheta J r - omega^2 r``."""
    r = body.r(k, z[2])
    return a_G + ddtheta * _perp(r) - z[5] ** 2 * r


def impulses(body: Body, z, contacts, dv_after: float, mu: float | None, normal: bool = True):
    """The floor's impulses on the corners ``contacts``: ``(z+, P_t, P)``, ``P`` one per contact.

    Momentum and angular momentum of the block about ``G`` and the mass's momentum change by the impulses; the
    touching corners' normal velocity after is ``dv_after`` (``normal=False``: no normal impulse instead, the
    tangential impulse alone); their slip after 0 (``mu=None``) or ``P_t = -mu P_n``.
    """
    d = body.m > 0
    A, *_ = _system(body, z, contacts, 0 if mu is None else 1, 0.0 if mu is None else mu)
    b = np.zeros(len(A))
    b[0:2] = body.M * np.array([z[3], z[4]])
    b[2] = body.I_G * z[5]
    if d:
        b[3:5] = body.m * body.mass_velocity(z)
    b[3 + 2 * d : 3 + 2 * d + len(contacts)] = dv_after
    if not normal:
        for j in range(len(contacts)):
            A[3 + 2 * d + j] = 0.0
            A[3 + 2 * d + j, 3 + 2 * d + 1 + j] = 1.0
            b[3 + 2 * d + j] = 0.0
    sol = _solve(A, b)
    f = 3 + 2 * d
    after = np.array([z[0], z[1], z[2], sol[0], sol[1], sol[2], z[6], sol[3] if d else 0.0])
    return after, sol[f], sol[f + 1 :]


def impulse(body: Body, k: int, z, dv_after: float, mu: float | None, normal: bool = True):
    """The corner ``k`` alone: ``(z+, P_t, P_n)``."""
    after, Pt, P = impulses(body, z, (k,), dv_after, mu, normal)
    return after, Pt, P[0]


def flat_impulse(body: Body, z, dv_after: float, mu: float | None):
    """Both corners at ``theta = 0``: ``(z+, P_t, P_A, P_A')``; ``omega+ = 0`` follows."""
    after, Pt, (PA, PB) = impulses(body, z, (1, -1), dv_after, mu)
    return after, Pt, PA, PB


@dataclass(frozen=True)
class Ground:
    """The ground's acceleration ``(ddx_g, ddy_g)`` [m/s^2] and its kinks [s], where a segment must end."""

    ax: Callable[[float], float]
    ay: Callable[[float], float]
    t_p: float
    kinks: tuple[float, ...] = ()

    @classmethod
    def one_sine(cls, a_g: float, omega: float, sign: int = 1, ratio: float = 0.0, phase: float = 0.0) -> Ground:
        """``ddx_g = sign a_g sin(omega t)``, ``ddy_g = ratio a_g sin(omega t + phase)`` on ``[0, 2 pi / omega]``."""
        t_p = 2 * math.pi / omega

        def ax(t):
            return sign * a_g * math.sin(omega * t) if t <= t_p else 0.0

        def ay(t):
            return ratio * a_g * math.sin(omega * t + phase) if t <= t_p else 0.0

        return cls(ax, ay, t_p, (t_p,))

    @classmethod
    def sampled(cls, dt: float, x, y) -> Ground:
        """Samples ``dt`` apart from ``t = 0``, linear between them, 0 after the last."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        t = dt * np.arange(len(x))

        def at(a):
            return lambda s: float(np.interp(s, t, a, right=0.0))

        return cls(at(x), at(y), float(t[-1]), tuple(float(s) for s in t[1:]))


@dataclass(frozen=True)
class Floor:
    """Static and kinetic Coulomb friction (``inf``: never slides) and the landings' normal restitution."""

    mu_s: float = math.inf
    mu_k: float = math.inf
    e_n: float = 0.0

    def holds(self, F: float, N: float) -> bool:
        """Whether the floor holds a contact that needs the tangential force ``F`` under the normal ``N``."""
        return math.isinf(self.mu_s) or abs(F) <= self.mu_s * N


@dataclass
class Run:
    """What a run of :func:`simulate` gives (the project's names and meanings, docs/model.md section 16)."""

    status: str = "t_max"
    t_end: float = 0.0
    theta_max: float = 0.0
    x_max: float = 0.0
    jump_max: float = 0.0
    #: The lowest a corner went in flight [m]: below 0, it went through the floor (a takeoff the free flight does not
    #: lift, the spec's rule: ``simulate(..., lifts=False)``).
    lowest: float = 0.0
    #: The least normal force on a rocking corner [N]: below 0 the floor pulls (a stuck corner of the paper's floor
    #: waiting for the free flight to lift it: ``lifts=True``).
    least_N: float = math.inf
    flight_time: float = 0.0
    flights: int = 0
    impacts: int = 0
    uplifts: int = 0
    #: Slip episodes on the floor (a stuck contact that slips, a slip that reverses, an impact that slides from a
    #: stuck or the other way): a sliding landing counts none, as the back ends count (the spec is silent).
    slides: int = 0
    #: Every landing: ``(t, law, energy before, energy after, omega before, omega after, the corner's dv before)``.
    landings: list = field(default_factory=list)


def corner_law(body: Body, floor: Floor, k: int, z, dv_after: float):
    """The corner ``k``'s impulse by the landing law (``rocking.reference.flight.landing_law``'s rule, typed again):
    ``(z+, law)`` with ``law`` 0 (stuck), ``+-1`` (sliding that way) or ``None`` (neither: jammed)."""
    zs, Pt, Pn = impulse(body, k, z, dv_after, None)
    if Pn > 0 and floor.holds(Pt, Pn):
        return zs, 0
    if math.isinf(floor.mu_s):
        # The floor's impulses fill the half-plane P_n >= 0: where sticking would pull, the tangential impulse
        # alone stops the slip and the corner leaves the floor (the back ends' decision, docs/model.md section 16).
        zt, _, _ = impulse(body, k, z, dv_after, None, normal=False)
        return (zt, 0) if body.corner(k, zt)[1][1] >= 0 else (z, None)
    du = body.corner(k, z)[1][0]
    for sigma in (1, -1) if math.isfinite(floor.mu_k) else ():
        zp, Pt, Pn = impulse(body, k, z, dv_after, sigma * floor.mu_k)
        if Pn > 0 and sigma * du >= 0 and sigma * body.corner(k, zp)[1][0] >= 0:
            return zp, sigma
    return z, None


def flat_law(body: Body, floor: Floor, z, dv_after: float):
    """A flat landing: ``(z+, law, k)``; ``k = 0`` both corners down, else the corner ``k`` landed alone."""
    zs, Pt, PA, PB = flat_impulse(body, z, dv_after, None)
    if min(PA, PB) < 0:
        k = 1 if PA > PB else -1  # the corner that pulls leaves the floor: the other lands alone
        zk, law = corner_law(body, floor, k, z, dv_after)
        return zk, law, k
    if floor.holds(Pt, PA + PB):
        return zs, 0, 0
    du = z[3]
    for sigma in ((1, -1) if du == 0 else (int(np.sign(du)),)) if math.isfinite(floor.mu_k) else ():
        zp, Pt, PA, PB = flat_impulse(body, z, dv_after, sigma * floor.mu_k)
        if min(PA, PB) >= 0 and sigma * zp[3] >= 0:
            return zp, sigma, 0
    return z, None, 0


class _Sim:
    """One run: the phase, the state ``z`` and the counts, advanced segment by segment.

    The phases: ``("contact", sigma)``, ``("rocking", k, sigma)`` (``sigma`` 0 stuck, else the slip's direction) and
    ``("flight",)``. Each integrates its own coordinates: ``(x, dx, u, du)`` in contact, ``(theta, omega, x, dx, u,
    du)`` rocking (the corner ``k`` at ``(u, 0)``), ``z`` in flight.
    """

    def __init__(self, body, ground, floor, t_max, dtheta_rest, energy_rest, rtol, lifts):
        self.body, self.ground, self.floor, self.t_max = body, ground, floor, t_max
        self.dtheta_rest, self.energy_rest, self.rtol, self.lifts = dtheta_rest, energy_rest, rtol, lifts
        self.run = Run()
        self.z = body.centroid(1, 0.0, 0.0, 0.0, 0.0)
        self.phase: tuple = ("contact", 0)
        self._t = 0.0  # the start of the current segment
        self.armed: list = [True]  # the rocking phase's takeoff: emptied by a graze until its margin is positive

    def forces(self, t, z, phase=None):
        """``(ddtheta, ddx, a_G, F, N)`` of ``phase`` (default the current one) at ``(t, z)``."""
        kind, *rest = phase or self.phase
        contacts = {"contact": (1, -1), "rocking": (rest[0],) if rest else (), "flight": ()}[kind]
        law = rest[-1] if kind != "flight" else 0
        return dynamics(self.body, z, self.ground.ax(t), self.ground.ay(t), contacts, law, self.floor.mu_k)

    def _setup(self):
        """``(y0, rhs, events, to_z)`` of the current phase; an event whose name is blank only reports a peak."""
        return {"contact": self._contact, "rocking": self._rocking, "flight": self._flight}[self.phase[0]]()

    def _contact(self):
        b, fl, z = self.body, self.floor, self.z
        finite = math.isfinite(self.floor.mu_s)
        sigma = self.phase[1]
        (u, _), (du, _) = b.corner(1, z)

        def to_z(y):
            return b.centroid(1, 0.0, y[2], y[3], 0.0, x=y[0], dx=y[1])

        def rhs(t, y):
            _, ddx, a_G, _, _ = self.forces(t, to_z(y))
            return [y[1], ddx, y[3], a_G[0]]

        def N(t, y, j):
            return self.forces(t, to_z(y))[4][j]

        ev = {
            "uplift+1": lambda t, y: N(t, y, 1),  # the corner A' leaves the floor: rocking about A
            "uplift-1": lambda t, y: N(t, y, 0),
            "takeoff": lambda t, y: N(t, y, 0) + N(t, y, 1),
            "  ": lambda t, y: y[1],
        }
        if sigma == 0 and finite:

            def slip(t, y):
                *_, F, Ns = self.forces(t, to_z(y))
                return fl.mu_s * sum(Ns) - abs(F)

            ev["slip"] = slip
        elif sigma:
            ev["stop"] = lambda t, y: sigma * y[3]
        if sigma == 0 and b.m > 0 and self.ground.t_p <= self._t:
            ev["rest"] = lambda t, y: b.damper_energy(to_z(y)) - self.energy_rest
        return [z[6], z[7], u, du], rhs, ev, to_z

    def _rocking(self):
        b, fl, z = self.body, self.floor, self.z
        finite = math.isfinite(self.floor.mu_s)
        _, k, sigma = self.phase
        (u, _), (du, _) = b.corner(k, z)

        def to_z(y):
            return b.centroid(k, y[0], y[4], y[5], y[1], x=y[2], dx=y[3])

        def rhs(t, y):
            zz = to_z(y)
            dd, ddx, a_G, _, _ = self.forces(t, zz)
            return [y[1], dd, y[3], ddx, y[5], corner_rate(b, k, zz, dd, a_G)[0]]

        armed, t0 = self.armed, self._t

        def takeoff(t, y):
            margin = self.takeoff_margin(t, to_z(y))
            armed.extend([True] if margin > 0 and t > t0 and not armed else [])
            return margin if armed else -1.0  # after a graze: armed once the margin is positive past the start

        ev = {
            "impact": lambda t, y: k * y[0],
            "overturn": lambda t, y: math.pi / 2 - abs(y[0]),
            "takeoff": takeoff,
            " ": lambda t, y: y[1],
            "  ": lambda t, y: y[3],
        }
        if sigma == 0 and finite:

            def slip(t, y):
                *_, F, (N,) = self.forces(t, to_z(y))
                return fl.mu_s * N - abs(F)

            ev["slip"] = slip
        elif sigma:
            ev["stop"] = lambda t, y: sigma * y[5]
        return [z[2], z[5], z[6], z[7], u, du], rhs, ev, to_z

    def _flight(self):
        b, z, t0 = self.body, self.z, self._t

        def rhs(t, y):
            dd, ddx, a_G, _, _ = self.forces(t, y)
            return [y[3], y[4], y[5], a_G[0], a_G[1], dd, y[7], ddx]

        def height(k):
            (_, v0), (_, dv0) = b.corner(k, z)
            if v0 > 1e-9 * b.B:
                return lambda t, y: b.corner(k, y)[0][1]
            if dv0 > 0:
                # A bounce: the root of v / (t - t0), whose value at t0 is the limit dv0 > 0, is the next landing.
                return lambda t, y: b.corner(k, y)[0][1] / (t - t0) if t > t0 else dv0
            armed = []

            def f(t, y):
                # A takeoff at rest rises as (t - t0)^3, under the rounding of v at first: armed once it has risen.
                v = b.corner(k, y)[0][1]
                armed.extend([True] if v > 0 and not armed else [])
                return v if armed else 1.0

            return f

        ev = {
            "land+1": height(1),
            "land-1": height(-1),
            "overturn": lambda t, y: math.pi / 2 - abs(y[2]),
            " ": lambda t, y: b.corner(1, y)[1][1],
            "  ": lambda t, y: b.corner(-1, y)[1][1],
            "   ": lambda t, y: y[5],
            "    ": lambda t, y: y[7],
        }
        return list(z), rhs, ev, np.array

    def segment(self, t):
        """Integrate the phase from ``t`` to its first exit, a kink of the motion or ``t_max``: ``(t, exit)``."""
        self._t = t
        y0, rhs, ev, to_z = self._setup()
        fns = list(ev.values())
        for name, fn in zip(ev, fns, strict=True):
            fn.terminal, fn.direction = bool(name.strip()), -1 if name.strip() else 0
        end = min([self.t_max, *(s for s in self.ground.kinks if s > t + 1e-15)])
        step = self.ground.t_p / 256 if t < self.ground.t_p else np.inf
        first = None
        if self.phase[0] == "rocking" and y0[0] == 0.0 and y0[1] != 0.0:
            # Rocking from theta = 0 swings back within ~2 |omega / ddtheta|: a first step past that would see the
            # impact at the start (docs/simulation.md's grazing lift-off).
            dd = abs(rhs(t, y0)[1])
            first = min(end - t, 0.05 * abs(y0[1]) / dd) if dd > 0 else None
        sol = solve_ivp(
            rhs, (t, end), y0, "DOP853", events=fns, rtol=self.rtol, atol=1e-14, max_step=step, first_step=first
        )
        if not sol.success:  # e.g. the sliding corner's effective mass through 0 (Painleve): out of this model
            raise RuntimeError(f"{sol.message} at t = {sol.t[-1]} in the phase {self.phase}")
        ts = [*sol.t, *(t for te in sol.t_events for t in te)]
        self._maxima(ts, [to_z(y) for y in sol.y.T] + [to_z(y) for ye in sol.y_events for y in ye])
        hits = [
            (te[0], name, ye[0])
            for name, te, ye in zip(ev, sol.t_events, sol.y_events, strict=True)
            if te.size and name.strip()
        ]
        t_end = min(h[0] for h in hits) if hits else float(sol.t[-1])
        if self.phase[0] == "flight":
            self.run.flight_time += t_end - t
        if not hits:
            self.z = to_z(sol.y[:, -1])
            return t_end, None
        # Where both corners' N fall to 0 together (a vertical motion alone) the block takes off, not uplifts.
        t_hit, name, y = min((h for h in hits if h[0] <= t_end + 1e-12), key=lambda h: h[1] != "takeoff")
        self.z = to_z(y)
        return float(t_hit), name

    def _maxima(self, ts, zs):
        """The maxima over the points ``(ts, zs)`` of a segment (its steps' ends and its events)."""
        r = self.run
        r.theta_max = max(r.theta_max, *(abs(z[2]) for z in zs))
        r.x_max = max(r.x_max, *(abs(z[6]) for z in zs))
        if self.phase[0] == "rocking":
            r.least_N = min(r.least_N, *(self.forces(t, z)[4][0] for t, z in zip(ts, zs, strict=True)))
        if self.phase[0] == "flight":
            heights = [self.body.corner(k, z)[0][1] for z in zs for k in (1, -1)]
            r.jump_max, r.lowest = max(r.jump_max, *heights), min(r.lowest, *heights)

    def start(self, t):
        """The checks where a phase on the floor starts: takeoff, uplift and slip at once (an event sees only a
        crossing)."""
        for _ in range(4):
            kind = self.phase[0]
            if kind == "flight":
                return
            *_, F, N = self.forces(t, self.z)
            sigma = self.phase[-1]
            if (
                kind == "contact"
                and sum(N) < 0
                or kind == "rocking"
                and self.armed
                and self.takeoff_margin(t, self.z) < 0
            ):
                if not self.takeoff(t):
                    return
            elif kind == "contact" and min(N) < 0:
                self.run.uplifts += 1
                self.phase = ("rocking", 1 if N[1] < 0 else -1, sigma)
            elif sigma == 0 and not self.floor.holds(F, sum(N)):
                self.run.slides += 1
                self.phase = (*self.phase[:-1], -int(np.sign(F)))
            else:
                return

    def takeoff_margin(self, t, z) -> float:
        """What a rocking phase's takeoff watches, falling to 0: ``N``; with ``lifts``, on a stuck corner of a floor
        without friction, the larger of ``N`` and minus the corner's vertical acceleration in free flight (the NumPy
        back end's decision, docs/simulation.md "Flight": it takes off only where the free flight lifts it)."""
        N = self.forces(t, z)[4][0]
        if not self.lifts or N > 0 or math.isfinite(self.floor.mu_s) or self.phase[-1] != 0:
            return N
        dd, _, a_G, _, _ = self.forces(t, z, ("flight",))
        return max(N, -corner_rate(self.body, self.phase[1], z, dd, a_G)[1])

    def sinks(self, t: float) -> bool:
        """With ``lifts``, at the takeoff of a stuck corner of a floor without friction: whether the free flight
        fails to lift it. Its vertical acceleration is 0 there (up to rounding) when the takeoff is the free flight's
        margin's, so it is read ``PROBE`` seconds along the flight itself (integrated, rtol 1e-12): not positive, the
        corner would go into the floor, and the takeoff grazes (the back ends' decision, docs/simulation.md
        "Flight")."""
        if not self.lifts or self.phase[0] != "rocking" or self.phase[-1] != 0 or math.isfinite(self.floor.mu_s):
            return False

        def rhs(t, y):
            dd, ddx, a_G, _, _ = self.forces(t, y, ("flight",))
            return [y[3], y[4], y[5], a_G[0], a_G[1], dd, y[7], ddx]

        z = solve_ivp(rhs, (t, t + PROBE), self.z, "DOP853", rtol=1e-12, atol=1e-15).y[:, -1]
        dd, _, a_G, _, _ = self.forces(t + PROBE, z, ("flight",))
        return not corner_rate(self.body, self.phase[1], z, dd, a_G)[1] > 0

    def takeoff(self, t: float) -> bool:
        """Into flight (the corners on the floor land only once they have risen: :meth:`_flight`), unless the
        takeoff grazes (:meth:`sinks`): then the pivot is held and its takeoff disarmed until its margin is
        positive. Whether the block took off."""
        if self.sinks(t):
            self.armed = []
            return False
        self.run.flights += 1
        self.phase = ("flight",)
        return True

    def rest_snap(self, k: int, z, law: int):
        """Full contact on the corner ``k``'s side at ``omega = 0`` after an impact of ``law``: the base keeps its
        slip speed (0 if the corner stuck) and the mass its absolute velocity (docs/simulation.md, rule 2)."""
        b = self.body
        (u, _), (du, _) = b.corner(k, z)
        du = du if law else 0.0
        eta = b.H + b.h
        self.z = b.centroid(k, 0.0, u, du, 0.0, x=z[6], dx=z[7] - eta * z[5] if b.m > 0 else 0.0)
        self.phase = ("contact", int(np.sign(du)))

    def event(self, t, name):
        b, fl, r = self.body, self.floor, self.run
        kind = self.phase[0]
        if name in ("slip", "uplift+1", "uplift-1") and sum(self.forces(t, self.z)[4]) <= 1e-9 * (b.M + b.m) * b.g:
            name = "takeoff"  # every N reaches 0 at once (a vertical motion alone): nothing holds the block
        self.armed = [True]
        if name == "overturn":
            r.status = "overturned"
        elif name == "rest":
            r.status = "rest"
        elif name == "takeoff":
            self.takeoff(t)
        elif name.startswith("uplift"):
            r.uplifts += 1
            self.phase = ("rocking", int(name[-2:]), self.phase[1])
        elif name == "slip":
            F = self.forces(t, self.z)[3]
            self.phase = (*self.phase[:-1], -int(np.sign(F)))
            r.slides += 1
        elif name == "stop":
            k = 1 if kind == "contact" else self.phase[1]
            z = self.z
            self.z = b.centroid(k, z[2], b.corner(k, z)[0][0], 0.0, z[5], x=z[6], dx=z[7])
            stuck = (*self.phase[:-1], 0)
            *_, F, N = self.forces(t, self.z, stuck)
            sigma = 0 if fl.holds(F, sum(N)) else -int(np.sign(F))
            r.slides += sigma != 0
            self.phase = (*self.phase[:-1], sigma)
        elif name == "impact":
            self.impact(t, self.phase[1])
        else:
            self.land(t, int(name[-2:]))

    def impact(self, t, k):
        """``theta`` reached 0 rocking about ``k``: the corner ``-k`` strikes (Housner's, with friction)."""
        b, fl, r = self.body, self.floor, self.run
        z = self.z.copy()
        z[2] = 0.0
        zs, Pt, Pn = impulse(b, -k, z, 0.0, None)
        if Pn <= 0:
            raise RuntimeError(f"an impact at t = {t} whose corner leaves the floor")
        law = 0
        if not fl.holds(Pt, Pn):
            law = -int(np.sign(Pt))
            zs, Pt, Pn = impulse(b, -k, z, 0.0, law * fl.mu_k)
            r.slides += law != self.phase[2]
        r.impacts += 1
        if abs(zs[5]) < self.dtheta_rest:
            self.rest_snap(-k, zs, law)
        else:
            self.z, self.phase = zs, ("rocking", -k, law)

    def land(self, t, k):
        """The corner ``k`` reached the floor moving down."""
        b, fl, r = self.body, self.floor, self.run
        z = self.z.copy()
        dv = b.corner(k, z)[1][1]
        before = b.energy(z)
        if abs(math.sin(z[2])) <= FLAT:
            z[2] = 0.0
            zp, law, k = flat_law(b, fl, z, -fl.e_n * dv)
        else:
            zp, law = corner_law(b, fl, k, z, -fl.e_n * dv)
        r.landings.append((t, law, before, b.energy(zp), z[5], zp[5], dv))
        if law is None:
            r.status = "jammed"
            return
        if b.corner(k or 1, zp)[1][1] > self.dtheta_rest * b.B / 2:  # bounces (or leaves tangentially): flight goes on
            self.z = zp
            self.phase = ("flight",)
            return
        if k == 0:
            zp[1], zp[4] = b.H / 2, 0.0  # the base on the floor, exactly
            self.z, self.phase = zp, ("contact", law)
            return
        (u, _), (du, _) = b.corner(k, zp)
        self.z = b.centroid(k, zp[2], u, du, zp[5], x=zp[6], dx=zp[7])
        self.phase = ("rocking", k, law)


def simulate(
    body: Body,
    ground: Ground,
    floor: Floor,
    t_max: float,
    dtheta_rest: float,
    energy_rest: float = 0.0,
    rtol: float = 1e-11,
    lifts: bool = False,
) -> Run:
    """The block at rest on the floor at ``t = 0`` under ``ground``, followed to rest, overturning, a jam or
    ``t_max``: the counts and maxima of :class:`Run`. Rest: full contact, stuck, after the motion, the damper's
    energy below ``energy_rest`` (the bare block at once). ``lifts``: a stuck corner of a floor without friction
    takes off only where the free flight lifts it too (:meth:`_Sim.takeoff_margin`); default: where its ``N``
    reaches 0 (the spec of issue 39)."""
    sim = _Sim(body, ground, floor, t_max, dtheta_rest, energy_rest, rtol, lifts)
    t, last, stalled = 0.0, -1.0, 0
    sim.start(t)
    while sim.run.status == "t_max" and t < t_max:
        if sim.phase == ("contact", 0) and t >= ground.t_p and body.damper_energy(sim.z) <= energy_rest:
            sim.run.status = "rest"
            break
        t, name = sim.segment(t)
        stalled = stalled + 1 if t == last else 0
        if stalled > 8:
            raise RuntimeError(f"the phases switch without end at t = {t}")
        last = t
        if name is not None:
            sim.event(t, name)
        if sim.run.status == "t_max":
            sim.start(t)
    sim.run.t_end = t
    return sim.run


def free_flight(g: float, dt: float, a_v) -> tuple[float, float, float, float]:
    """A body at rest on a floor whose vertical acceleration is the samples ``a_v`` [m/s^2], ``dt`` apart and linear
    between them, the last one held after: ``(t_takeoff, t_landing, dv_landing, v_max)`` in closed form.

    It leaves the floor where ``g + ddy_g`` first reaches 0 and then, relative to the floor, ``ddv = -(g + ddy_g)``:
    on each piece between two samples ``v`` is a cubic in time, whose first root past the takeoff is the landing
    and the roots of whose derivative are its peaks (``numpy.roots``). During a plateau at ``ddy_g = -c g``,
    ``v = (c - 1) g t^2 / 2`` from its start.
    """
    a = -(g + np.asarray(a_v, float))  # the free body's acceleration relative to the floor
    k = int(np.flatnonzero(a >= 0)[0])
    t0 = dt * k if k == 0 else float(dt * (k - 1) - dt * a[k - 1] / (a[k] - a[k - 1]))  # the root on the ramp
    t, v, dv, i, peak = t0, 0.0, 0.0, k + (t0 == dt * k), 0.0
    while True:
        end, slope = (dt * i, (a[i] - a[i - 1]) / dt) if i < len(a) else (math.inf, 0.0)
        acc = a[-1] if i >= len(a) else a[i - 1] + slope * (t - dt * (i - 1))
        cubic = np.array([slope / 6, acc / 2, dv, v])  # v(t + s)
        landing = _roots_within(cubic, end - t)
        span = min(landing) if landing else end - t
        peak = max([peak, *(float(np.polyval(cubic, s)) for s in _roots_within(np.polyder(cubic), span))])
        if landing:
            return float(t0), t + span, float(np.polyval(np.polyder(cubic), span)), peak
        v, dv = float(np.polyval(cubic, span)), float(np.polyval(np.polyder(cubic), span))
        t, i = end, i + 1


def bounce_series(g: float, dt: float, a_v, e_n: float, threshold: float) -> tuple[int, float]:
    """The floor's drop of :func:`free_flight` landing with Newton's restitution ``e_n`` on a still floor: the base
    leaves again at ``e_n^k |dv|`` for each ``k`` while that is above ``threshold`` (docs/model.md section 16,
    step 4), each flight ``2 e_n^k |dv| / g`` long. ``(bounces, total flight time [s])``."""
    t0, t1, dv, _ = free_flight(g, dt, a_v)
    speeds = list(itertools.takewhile(lambda w: w > threshold, (e_n**k * abs(dv) for k in itertools.count(1))))
    return len(speeds), t1 - t0 + sum(2 * w / g for w in speeds)


def _roots_within(coefficients, span: float) -> list[float]:
    """The real roots in ``(0, span]`` of a polynomial (numpy's order of ``coefficients``)."""
    return [float(r.real) for r in np.roots(coefficients) if abs(r.imag) <= 1e-9 * abs(r) and 1e-12 < r.real <= span]
