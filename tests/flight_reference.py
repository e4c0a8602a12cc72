"""The bare block on a floor it can leave: Newton and Euler with contact forces and impulses, typed by hand.

The outside check of issue 39 (docs/model.md sections 6, 15 and 16): independent of ``derive/``, ``generated/``,
``rocking.sim`` and ``rocking.reference``. One rigid body, its centroid ``G`` at ``(X, Y)`` relative to the ground
(``(e, H / 2)`` at rest), turned by ``theta``; its base corners ``k = +1`` (``A``, left) and ``k = -1`` (``A'``,
right) at ``r_k = (-k B / 2 - e, -H / 2)`` from ``G`` in the block frame, at rest at ``(-k B / 2, 0)``. The ground
accelerates by ``(ddx_g, ddy_g)``: relative to it every body carries ``-M (ddx_g, g + ddy_g)``.

Each contact state writes Newton and Euler, ``M a_G = F + M (-ddx_g, -(g + ddy_g))`` and
``I_G ddtheta = sum (R r_k) x F_k``, with its constraints, and solves the linear system for the accelerations
and the floor's forces:

- ``contact``: both corners on the floor, ``theta = dtheta = ddtheta = 0``, ``a_Gy = 0`` and ``a_Gx = 0`` (stuck)
  or ``F = -mu_k sigma (N_A + N_A')`` (sliding in the direction ``sigma``); it uplifts where a corner's ``N`` falls
  to 0, takes off where both do;
- ``rocking`` about ``k``: the corner ``k`` does not move (stuck) or only along the floor with
  ``F = -mu_k sigma N``; it takes off where ``N`` falls to 0, impacts where ``theta`` reaches 0;
- ``flight``: no force, ``a_G = (-ddx_g, -(g + ddy_g))``, ``ddtheta = 0``; a corner lands where its height falls
  to 0.

Impacts and landings are Newton and Euler with impulses at the corners that touch: ``M dv_G = P``,
``I_G domega = sum (R r_k) x P_k``, the touching corner's normal velocity ``-e_n`` times the one before (0 at an
impact, as Housner's), its slip 0 (stick, if ``|P_t| <= mu_s P_n``) or ``P_t = -mu_k sigma P_n``. A flat landing
(``|sin theta| <= FLAT``) puts both corners down with ``omega+ = 0``; where one would pull, the other lands alone.
Each state is integrated by SciPy's DOP853 with its exits as events; the phases follow docs/simulation.md's
rules (rest snap below ``dtheta_rest``, rest in full contact after the motion, ``t_max``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

#: A landing is flat, on both corners, where ``|sin theta|`` is at most this (docs/model.md section 16).
FLAT = 1e-12


@dataclass(frozen=True)
class Body:
    """The bare block: mass [kg], centroidal inertia [kg m^2], base and height [m], eccentricity [m], gravity."""

    M: float
    I_G: float
    B: float
    H: float
    e: float
    g: float

    def r(self, k: int, theta: float) -> np.ndarray:
        """The corner ``k`` from ``G``, ``R(theta) r_k`` [m]."""
        x, y = -k * self.B / 2 - self.e, -self.H / 2
        c, s = math.cos(theta), math.sin(theta)
        return np.array([c * x - s * y, s * x + c * y])

    def corner(self, k: int, z) -> tuple[np.ndarray, np.ndarray]:
        """Position and velocity of the corner ``k`` relative to its place at rest, from ``z = (X, Y, theta, vX,
        vY, omega)``: ``(u, v)`` and ``(du, dv)``."""
        r = self.r(k, z[2])
        return np.array([z[0] + r[0] + k * self.B / 2, z[1] + r[1]]), np.array([z[3] - z[5] * r[1], z[4] + z[5] * r[0]])

    def centroid(self, k: int, theta: float, u: float, du: float, omega: float, v=0.0, dv=0.0) -> np.ndarray:
        """``z`` of the block whose corner ``k`` is at ``(u, v)`` from its rest moving at ``(du, dv)``."""
        r = self.r(k, theta)
        return np.array([u - k * self.B / 2 - r[0], v - r[1], theta, du + omega * r[1], dv - omega * r[0], omega])

    def energy(self, z) -> float:
        """Kinetic energy relative to the ground plus the weight's potential above the floor [J]."""
        return self.M * (z[3] ** 2 + z[4] ** 2) / 2 + self.I_G * z[5] ** 2 / 2 + self.M * self.g * z[1]


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
    jump_max: float = 0.0
    flight_time: float = 0.0
    flights: int = 0
    impacts: int = 0
    uplifts: int = 0
    slides: int = 0
    #: Every landing: ``(t, law, energy before, energy after, omega before, omega after, the corner's dv before)``.
    landings: list = field(default_factory=list)


def _solve(A, b):
    return np.linalg.solve(np.asarray(A, float), np.asarray(b, float))


def contact_forces(body: Body, ag: float, agy: float, sigma: int, mu_k: float) -> tuple[float, float, float, float]:
    """Full contact: ``(ddu, F, N_A, N_A')``; ``sigma = 0`` stuck, else sliding that way.

    Unknowns ``a_Gx, F, N_A, N_A'``: ``M a_Gx = F - M ddx_g``, ``0 = N_A + N_A' - M (g + ddy_g)``, the moment about
    ``G`` ``0 = (r_A)_x N_A + (r_A')_x N_A' + H/2 F`` and ``a_Gx = 0`` or ``F = -mu_k sigma (N_A + N_A')``.
    """
    M, h = body.M, body.H / 2
    ra, rb = body.r(1, 0.0)[0], body.r(-1, 0.0)[0]
    last = [1.0, 0.0, 0.0, 0.0] if sigma == 0 else [0.0, 1.0, mu_k * sigma, mu_k * sigma]
    a, F, NA, NB = _solve([[M, -1, 0, 0], [0, 0, 1, 1], [0, h, ra, rb], last], [-M * ag, M * (body.g + agy), 0.0, 0.0])
    return a, F, NA, NB


def rocking_forces(body: Body, k: int, theta, omega, ag, agy, sigma: int, mu_k: float):
    """Rocking about the corner ``k``: ``(ddtheta, ddu, F, N)``; ``sigma = 0`` stuck, else its slip's direction.

    Unknowns ``a_G, ddtheta, F, N``: Newton, Euler about ``G`` (``r x (F, N) = r_x N - r_y F``), the corner's
    acceleration ``a_G + ddtheta J r - omega^2 r`` with no normal part, and no tangential one (stuck) or
    ``F = -mu_k sigma N``.
    """
    M, r = body.M, body.r(k, theta)
    last = [1, 0, -r[1], 0, 0] if sigma == 0 else [0, 0, 0, 1, mu_k * sigma]
    A = [[M, 0, 0, -1, 0], [0, M, 0, 0, -1], [0, 0, body.I_G, r[1], -r[0]], [0, 1, r[0], 0, 0], last]
    b = [-M * ag, -M * (body.g + agy), 0.0, omega**2 * r[1], omega**2 * r[0] if sigma == 0 else 0.0]
    aX, _, dd, F, N = _solve(A, b)
    return dd, aX - dd * r[1] - omega**2 * r[0], F, N


def impulse(body: Body, k: int, z, dv_after: float, mu: float | None):
    """The floor's impulse on the corner ``k`` alone: ``(z+, P_t, P_n)``.

    ``M (v_G+ - v_G-) = P``, ``I_G (omega+ - omega-) = r x P``, the corner's normal velocity after ``dv_after``,
    its slip after 0 (``mu=None``: stick) or ``P_t = -mu P_n`` (``mu = mu_k sigma``).
    """
    M, r = body.M, body.r(k, z[2])
    last = [1, 0, -r[1], 0, 0] if mu is None else [0, 0, 0, 1, mu]
    A = [[M, 0, 0, -1, 0], [0, M, 0, 0, -1], [0, 0, body.I_G, r[1], -r[0]], [0, 1, r[0], 0, 0], last]
    b = [M * z[3], M * z[4], body.I_G * z[5], dv_after, 0.0]
    vX, vY, w, Pt, Pn = _solve(A, b)
    return np.array([z[0], z[1], z[2], vX, vY, w]), Pt, Pn


def flat_impulse(body: Body, z, dv_after: float, mu: float | None):
    """Both corners land at ``theta = 0``: ``(z+, P_t, P_A, P_A')`` with ``omega+ = 0``, ``v_Gy+ = dv_after``.

    ``M dv_G = (P_t, P_A + P_A')``, ``-I_G omega- = (r_A)_x P_A + (r_A')_x P_A' + H/2 P_t``; ``v_Gx+ = 0`` (stick)
    or ``P_t = -mu (P_A + P_A')``.
    """
    M, h = body.M, body.H / 2
    ra, rb = body.r(1, 0.0)[0], body.r(-1, 0.0)[0]
    last = [1, 0, 0, 0] if mu is None else [0, 1, mu, mu]
    vX, Pt, PA, PB = _solve(
        [[M, -1, 0, 0], [0, 0, 1, 1], [0, h, ra, rb], last],
        [M * z[3], M * (dv_after - z[4]), -body.I_G * z[5], 0.0],
    )
    return np.array([z[0], z[1], 0.0, vX, dv_after, 0.0]), Pt, PA, PB


def corner_law(body: Body, floor: Floor, k: int, z, dv_after: float):
    """The corner ``k``'s impulse by the landing law (``rocking.reference.flight.landing_law``'s rule, typed again):
    ``(z+, law)`` with ``law`` 0 (stuck), ``+-1`` (sliding that way) or ``None`` (neither: jammed)."""
    zs, Pt, Pn = impulse(body, k, z, dv_after, None)
    if Pn > 0 and floor.holds(Pt, Pn):
        return zs, 0
    du = body.corner(k, z)[1][0]
    for sigma in (1, -1):
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
    for sigma in (1, -1) if du == 0 else (int(np.sign(du)),):
        zp, Pt, PA, PB = flat_impulse(body, z, dv_after, sigma * floor.mu_k)
        if min(PA, PB) >= 0 and sigma * zp[3] >= 0:
            return zp, sigma, 0
    return z, None, 0


class _Sim:
    """One run: the phase, its state ``z`` and the counts, advanced segment by segment."""

    def __init__(self, body, ground, floor, t_max, dtheta_rest, rtol):
        self.body, self.ground, self.floor, self.t_max = body, ground, floor, t_max
        self.dtheta_rest, self.rtol = dtheta_rest, rtol
        self.run = Run()
        self.z = body.centroid(1, 0.0, 0.0, 0.0, 0.0)
        self.phase: tuple = ("contact", 0)  # ("contact", sigma), ("rocking", k, sigma), ("flight", armed)

    # --- the phases' right-hand sides and exits ---------------------------------------------------------------
    def _rocking(self, t, k, sigma, theta, omega):
        g = self.ground
        return rocking_forces(self.body, k, theta, omega, g.ax(t), g.ay(t), sigma, self.floor.mu_k)

    def _contact(self, t, sigma):
        g = self.ground
        return contact_forces(self.body, g.ax(t), g.ay(t), sigma, self.floor.mu_k)

    def _setup(self):
        """``(y0, rhs, events, names, to_z)`` of the current phase; an event named ``""`` only reports a peak."""
        b, fl, kind = self.body, self.floor, self.phase[0]
        finite = math.isfinite(fl.mu_s)
        if kind == "contact":
            sigma = self.phase[1]
            u, du = b.corner(1, self.z)[0][0], self.z[3]

            def rhs(t, y):
                return [y[1], self._contact(t, sigma)[0]]

            ev = {
                "uplift+1": lambda t, y: self._contact(t, sigma)[3],  # the corner A' leaves the floor
                "uplift-1": lambda t, y: self._contact(t, sigma)[2],
                "takeoff": lambda t, y: sum(self._contact(t, sigma)[2:]),
            }
            if sigma == 0 and finite:
                ev["slip"] = lambda t, y: fl.mu_s * sum(self._contact(t, 0)[2:]) - abs(self._contact(t, 0)[1])
            elif sigma:
                ev["stop"] = lambda t, y: sigma * y[1]
            return [u, du], rhs, ev, lambda y: b.centroid(1, 0.0, y[0], y[1], 0.0)
        if kind == "rocking":
            _, k, sigma = self.phase
            (u, _), (du, _) = b.corner(k, self.z)

            def rhs(t, y):
                dd, ddu, _, _ = self._rocking(t, k, sigma, y[0], y[1])
                return [y[1], dd, y[3], ddu]

            ev = {
                "impact": lambda t, y: k * y[0],
                "overturn": lambda t, y: math.pi / 2 - abs(y[0]),
                "takeoff": lambda t, y: self._rocking(t, k, sigma, y[0], y[1])[3],
                "": lambda t, y: y[1],
            }
            if sigma == 0 and finite:

                def slip(t, y):
                    _, _, F, N = self._rocking(t, k, 0, y[0], y[1])
                    return fl.mu_s * N - abs(F)

                ev["slip"] = slip
            elif sigma:
                ev["stop"] = lambda t, y: sigma * y[3]
            return [self.z[2], self.z[5], u, du], rhs, ev, lambda y: b.centroid(k, y[0], y[2], y[3], y[1])
        armed = self.phase[1]

        def rhs(t, y):
            return [y[3], y[4], y[5], -self.ground.ax(t), -self.ground.ay(t) - b.g, 0.0]

        def height(k):
            def f(t, y):
                v = b.corner(k, y)[0][1]
                if not armed[k] and v > 0:
                    armed[k] = True  # a corner that took off at height 0 lands only once it has risen
                return v if armed[k] else 1.0

            return f

        ev = {
            "land+1": height(1),
            "land-1": height(-1),
            "overturn": lambda t, y: math.pi / 2 - abs(y[2]),
            "": lambda t, y: b.corner(1, y)[1][1],
            " ": lambda t, y: b.corner(-1, y)[1][1],
        }
        return list(self.z), rhs, ev, np.array

    # --- one segment ------------------------------------------------------------------------------------------
    def segment(self, t):
        y0, rhs, ev, to_z = self._setup()
        fns = list(ev.values())
        for name, fn in zip(ev, fns, strict=True):
            fn.terminal, fn.direction = bool(name.strip()), -1 if name.strip() else 0
        later = [s for s in self.ground.kinks if s > t + 1e-15]
        end = min([self.t_max, *later])
        step = self.ground.t_p / 256 if t < self.ground.t_p else np.inf
        first = None
        if self.phase[0] == "rocking" and y0[0] == 0.0:
            # Rocking from theta = 0 swings back within ~2 |omega / ddtheta|: a first step past that would see the
            # impact at the start (docs/simulation.md's grazing lift-off).
            dd = abs(rhs(t, y0)[1])
            first = min(end - t, 0.05 * abs(y0[1]) / dd) if dd > 0 and y0[1] != 0 else None
        sol = solve_ivp(
            rhs, (t, end), y0, "DOP853", events=fns, rtol=self.rtol, atol=1e-14, max_step=step, first_step=first
        )
        zs = [to_z(y) for y in sol.y.T] + [to_z(y) for ye in sol.y_events for y in ye]
        self._maxima(zs)
        hits = [(te[0], name, ye[0]) for name, te, ye in zip(ev, sol.t_events, sol.y_events, strict=True) if te.size]
        hits = [h for h in hits if h[1].strip()]
        if self.phase[0] == "flight":
            self.run.flight_time += (min(hits)[0] if hits else sol.t[-1]) - t
        if not hits:
            self.z = to_z(sol.y[:, -1])
            return float(sol.t[-1]), None
        first = min(h[0] for h in hits)
        # Where both corners' N fall to 0 together (a vertical motion alone) the block takes off, not uplifts.
        t_hit, name, y = min((h for h in hits if h[0] <= first + 1e-12), key=lambda h: h[1] != "takeoff")
        self.z = to_z(y)
        return float(t_hit), name

    def _maxima(self, zs):
        r = self.run
        r.theta_max = max(r.theta_max, *(abs(z[2]) for z in zs))
        if self.phase[0] == "flight":
            r.jump_max = max(r.jump_max, *(self.body.corner(k, z)[0][1] for z in zs for k in (1, -1)))

    # --- transitions --------------------------------------------------------------------------------------------
    def start(self, t):
        """The checks where a phase on the floor starts: takeoff, uplift and slip at once (an event sees only a
        crossing)."""
        fl = self.floor
        for _ in range(4):
            kind = self.phase[0]
            if kind == "contact":
                sigma = self.phase[1]
                _, F, NA, NB = self._contact(t, sigma)
                if NA + NB < 0:
                    self.takeoff()
                elif min(NA, NB) < 0:
                    self.run.uplifts += 1
                    self.phase = ("rocking", 1 if NB < 0 else -1, sigma)
                elif sigma == 0 and not fl.holds(F, NA + NB):
                    self.run.slides += 1
                    self.phase = ("contact", -int(np.sign(F)))
                else:
                    return
            elif kind == "rocking":
                _, k, sigma = self.phase
                _, _, F, N = self._rocking(t, k, sigma, self.z[2], self.z[5])
                if N < 0:
                    self.takeoff()
                elif sigma == 0 and not fl.holds(F, N):
                    self.run.slides += 1
                    self.phase = ("rocking", k, -int(np.sign(F)))
                else:
                    return
            else:
                return

    def takeoff(self):
        """Into flight; a corner on the floor (the pivot, or both from full contact) lands only once it has risen."""
        self.run.flights += 1
        self.phase = ("flight", {j: self.body.corner(j, self.z)[0][1] > 1e-9 * self.body.B for j in (1, -1)})

    def on_floor(self, z, law, k):
        """The phase after an impact or a landing left the corner ``k`` (0: both) on the floor with ``law``."""
        self.z = z
        if k == 0:
            self.phase = ("contact", law)
        elif abs(z[5]) < self.dtheta_rest and z[2] == 0.0:  # the rest snap of an impact
            self.z = self.body.centroid(k, 0.0, self.body.corner(k, z)[0][0], self.body.corner(k, z)[1][0], 0.0)
            self.phase = ("contact", int(np.sign(self.z[3])))
        else:
            self.phase = ("rocking", k, law)

    def event(self, t, name):
        b, fl, r = self.body, self.floor, self.run
        kind = self.phase[0]
        if name == "overturn":
            r.status = "overturned"
        elif name == "takeoff":
            self.takeoff()
        elif name.startswith("uplift"):
            r.uplifts += 1
            self.phase = ("rocking", int(name[-2:]), self.phase[1])
        elif name == "slip":
            if kind == "contact":
                F = self._contact(t, 0)[1]
                self.phase = ("contact", -int(np.sign(F)))
            else:
                F = self._rocking(t, self.phase[1], 0, self.z[2], self.z[5])[2]
                self.phase = ("rocking", self.phase[1], -int(np.sign(F)))
            r.slides += 1
        elif name == "stop":
            k = 1 if kind == "contact" else self.phase[1]
            u = b.corner(k, self.z)[0][0]
            self.z = b.centroid(k, self.z[2], u, 0.0, self.z[5])
            F, N = (
                (self._contact(t, 0)[1], sum(self._contact(t, 0)[2:]))
                if kind == "contact"
                else self._rocking(t, k, 0, self.z[2], self.z[5])[2:]
            )
            sigma = 0 if fl.holds(F, N) else -int(np.sign(F))
            r.slides += sigma != 0
            self.phase = ("contact", sigma) if kind == "contact" else ("rocking", k, sigma)
        elif name == "impact":
            k = self.phase[1]
            z = self.z.copy()
            z[2] = 0.0
            zs, Pt, Pn = impulse(b, -k, z, 0.0, None)
            law = 0
            if Pn <= 0:
                raise RuntimeError(f"an impact at t = {t} whose corner leaves the floor")
            if not fl.holds(Pt, Pn):
                law = -int(np.sign(Pt))
                zs, Pt, Pn = impulse(b, -k, z, 0.0, law * fl.mu_k)
                r.slides += law != self.phase[2]
            r.impacts += 1
            if abs(zs[5]) < self.dtheta_rest:  # the rest snap: the base keeps its slip speed
                du = b.corner(-k, zs)[1][0]
                self.z = b.centroid(-k, 0.0, b.corner(-k, zs)[0][0], du, 0.0)
                self.phase = ("contact", int(np.sign(du)) if law else 0)
            else:
                self.z, self.phase = zs, ("rocking", -k, law)
        else:  # a landing
            self.land(t, int(name[-2:]))

    def land(self, t, k):
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
        if law and law != 0:
            r.slides += 1
        if -fl.e_n * dv > self.dtheta_rest * b.B / 2:  # bounces: flight goes on, the corner armed once it rises
            self.z = zp
            self.phase = ("flight", {j: j != k and k != 0 for j in (1, -1)})
            return
        if k:  # the corner is on the floor: exactly, and with no normal velocity
            (u, _), (du, _) = b.corner(k, zp)
            zp = b.centroid(k, zp[2], u, du, zp[5])
        else:
            zp[1], zp[4] = b.H / 2, 0.0
        self.on_floor(zp, law, k)


def simulate(body: Body, ground: Ground, floor: Floor, t_max: float, dtheta_rest: float, rtol: float = 1e-11) -> Run:
    """The bare block at rest on the floor at ``t = 0`` under ``ground``, followed to rest, overturning, a jam or
    ``t_max``: the counts and maxima of :class:`Run`."""
    sim = _Sim(body, ground, floor, t_max, dtheta_rest, rtol)
    t, last, stalled = 0.0, -1.0, 0
    sim.start(t)
    while sim.run.status == "t_max" and t < t_max:
        if sim.phase == ("contact", 0) and t >= ground.t_p:
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
    t0 = dt * k if k == 0 else dt * (k - 1) - dt * a[k - 1] / (a[k] - a[k - 1])  # the root on the ramp
    t, v, dv, i, peak = t0, 0.0, 0.0, k + (t0 == dt * k), 0.0
    while True:
        end, slope = (dt * i, (a[i] - a[i - 1]) / dt) if i < len(a) else (math.inf, 0.0)
        acc = a[-1] if i >= len(a) else a[i - 1] + slope * (t - dt * (i - 1))
        cubic = np.array([slope / 6, acc / 2, dv, v])  # v(t + s)
        landing = _roots_within(cubic, end - t)
        span = min(landing) if landing else end - t
        peak = max([peak, *(np.polyval(cubic, s) for s in _roots_within(np.polyder(cubic), span))])
        if landing:
            return t0, t + span, np.polyval(np.polyder(cubic), span), peak
        v, dv = np.polyval(cubic, span), np.polyval(np.polyder(cubic), span)
        t, i = end, i + 1


def _roots_within(coefficients, span: float) -> list[float]:
    """The real roots in ``(0, span]`` of a polynomial (numpy's order of ``coefficients``)."""
    return [r.real for r in np.roots(coefficients) if abs(r.imag) <= 1e-9 * abs(r) and 1e-12 < r.real <= span]
