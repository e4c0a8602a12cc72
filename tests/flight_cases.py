"""The runs that hold flight to outside facts (issue 39, item 5): one case, run by the reference and by a back end.

A case is the reference block (docs/model.md section 9), bare or with a damper, under a one-sine pulse with a
vertical component past the flight threshold (``g + ddy_g`` reaches 0), on the paper's floor or one with friction.
:func:`reference` runs it with :mod:`tests.flight_reference` (Newton and Euler typed by hand), :func:`project` with
``rocking.simulate``; both at rest on the floor at ``t = 0``, followed to rest or ``t_max`` (no early verdict or
rest), the same ``dtheta_rest``, ``energy_rest`` and ``t_max``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

import rocking
from rocking.reference import flight as hand
from tests import flight_reference as ref

#: The tolerance of the project's runs; the reference runs at 1e-11 (its events to the integrator's tolerance).
RTOL = 1e-10
#: Time followed after the pulse [s]: the block comes to rest within it (at most ~11 s in the random cases).
T_AFTER = 15.0
#: The drop of the floor (item 5): ``ddy_g = -DROP g`` for ``PLATEAU`` seconds, sampled every ``DROP_DT``.
DROP, PLATEAU, DROP_DT = 1.5, 0.1, 0.01


@dataclass(frozen=True)
class Case:
    """A one-sine pulse of ``beta`` and ``Omega`` (docs/model.md section 9) in the direction ``sign``, its vertical
    component ``ratio`` times it with the lead ``phase`` [rad], on a floor of ``mu_s``, ``mu_k`` (``inf``: no slip);
    ``damper`` the keywords of ``rocking.Damper.from_nondim`` (``None``: the bare block)."""

    beta: float
    Omega: float
    sign: int
    ratio: float
    phase: float
    mu_s: float
    mu_k: float
    damper: tuple[tuple[str, float], ...] | None = None

    @property
    def block(self) -> rocking.Block:
        return rocking.Block.reference()

    @property
    def the_damper(self) -> rocking.Damper | None:
        return None if self.damper is None else rocking.Damper.from_nondim(self.block, **dict(self.damper))

    @property
    def pulse(self) -> rocking.OneSinePulse:
        return rocking.OneSinePulse.from_nondim(
            self.block,
            beta=self.beta,
            Omega=self.Omega,
            sign=self.sign,
            vertical=rocking.Vertical(self.ratio, self.phase) if self.ratio else None,
        )

    @property
    def dtheta_rest(self) -> float:
        return 1e-3 * self.block.alpha * self.block.p

    @property
    def energy_rest(self) -> float:
        """The project's default (docs/simulation.md rule 4): ``1e-8 M g B / 2``."""
        return 1e-8 * self.block.M * self.block.g * self.block.B / 2

    @property
    def t_after(self) -> float:
        """Followed after the pulse: to rest for the bare block; a damper's decay would take minutes, so 4 s."""
        return T_AFTER if self.damper is None else 4.0


def random_cases(n: int = 20, seed: int = 39, damper: bool = False) -> list[Case]:
    """``n`` cases past the flight threshold, ``r beta tan(alpha) > 1`` by 5 to 60 %: both directions, the vertical in
    phase (odd cases) or with a random lead, and every other pair on a floor with friction; ``damper``: each with a
    random damper (mass ratio 0.02 to 0.2, tuned 0.5 to 2 times ``p``, damping ratio 0.02 to 0.2, ``h = 0.05`` m)."""
    rng = np.random.default_rng(seed)
    tan_alpha = rocking.Block.reference().tan_alpha
    cases = []
    for i in range(n):
        ratio = rng.uniform(0.5, 1.5)
        beta = rng.uniform(1.05, 1.6) / (ratio * tan_alpha)
        Omega, sign = rng.uniform(2.0, 12.0), int(rng.choice([-1, 1]))
        phase = 0.0 if i % 2 else rng.uniform(0.0, 2 * math.pi)
        mu_s = math.inf if i % 4 < 2 else rng.uniform(0.3, 1.0)
        tuned = (
            (("gamma", rng.uniform(0.02, 0.2)), ("omega_ratio", rng.uniform(0.5, 2)), ("zeta", rng.uniform(0.02, 0.2)))
            if damper
            else None
        )
        cases.append(
            Case(
                beta,
                Omega,
                sign,
                ratio,
                phase,
                mu_s,
                mu_s if math.isinf(mu_s) else 0.8 * mu_s,
                None if tuned is None else (*tuned, ("h", 0.05)),
            )
        )
    return cases


def body(block: rocking.Block, damper: rocking.Damper | None = None) -> ref.Body:
    """The reference's body of ``block`` and ``damper``."""
    d = {} if damper is None else {k: damper.as_params()[k] for k in ("m", "h", "k_m", "c")}
    I_G = block.as_params()["I_G"]  # Block stores None for the homogeneous default
    return ref.Body(block.M, I_G, block.B, block.H, block.e, block.g, **d)


@functools.cache  # a test module and the next share their runs (a Case is frozen, so hashable)
def reference(case: Case, lifts: bool = True) -> ref.Run:
    """The case run by the reference (rtol 1e-11); ``lifts``: a stuck corner on the paper's floor takes off only where
    the free flight lifts it, as the back ends decided (docs/simulation.md, "Flight"); else where its ``N`` reaches 0.
    """
    p = case.pulse
    ground = ref.Ground.one_sine(p.a_g, p.omega_g, case.sign, case.ratio, case.phase)
    return ref.simulate(
        body(case.block, case.the_damper),
        ground,
        ref.Floor(case.mu_s, case.mu_k),
        p.t_p + case.t_after,
        case.dtheta_rest,
        case.energy_rest,
        lifts=lifts,
    )


def project(case: Case, backend: str, record: bool = False) -> rocking.Response:
    """The case run by a back end of the project at :data:`RTOL`: no early verdict, no early rest (rule 4)."""
    floor = None if math.isinf(case.mu_s) else rocking.Floor(case.mu_s, case.mu_k)
    return rocking.simulate(
        case.block,
        case.the_damper,
        case.pulse,
        backend=backend,
        rtol=RTOL,
        t_after=case.t_after,
        early_verdict=False,
        early_rest=False,
        dtheta_rest=case.dtheta_rest,
        energy_rest=case.energy_rest,
        floor=floor,
        record=record,
    )


#: The project's statuses the reference calls ``t_max``: at ``t_max`` after the pulse, below the overturning barrier.
SAME_STATUS = {"below_barrier": "t_max"}


def differences(run: ref.Run, response) -> dict:
    """The relative differences of ``theta_max``, ``x_max``, ``jump_max``, ``flight_time`` (to the reference's value)
    and whether the status and the counts of flights, impacts, uplifts and slides agree."""

    def rel(a: float, b: float) -> float:
        return abs(a - b) / max(abs(b), 1e-300) if (a, b) != (0.0, 0.0) else 0.0

    status = SAME_STATUS.get(response.status, response.status)
    counts = ("flights", "impacts", "uplifts", "slides")
    return {
        "same": (status, *(getattr(response, k) for k in counts)) == (run.status, *(getattr(run, k) for k in counts)),
        "theta_max": rel(response.theta_max, run.theta_max),
        "x_max": rel(response.x_max, run.x_max),
        "jump_max": rel(response.jump_max, run.jump_max),
        "flight_time": rel(response.flight_time, run.flight_time),
    }


def drop_samples(g: float) -> np.ndarray:
    """The floor's drop as vertical samples ``DROP_DT`` apart: 0, then ``-DROP g`` for ``PLATEAU`` s, then 0 (ramps
    of one sample between), long enough for the landing and the rest after it."""
    n = round(PLATEAU / DROP_DT)
    return np.r_[0.0, np.full(n + 1, -DROP * g), np.zeros(60)]


def landings(history: dict) -> list[tuple[int, int]]:
    """The rows of a landing in a recorded history: ``(i, i + 1)``, flying at ``i``, on the floor at ``i + 1``."""
    fly = np.asarray(history["fly"])
    return [(int(i), int(i) + 1) for i in np.flatnonzero((fly[:-1] == 1.0) & (fly[1:] == 0.0))]


def history_energy(block: rocking.Block, damper, history: dict, i: int) -> float:
    """The energy at the row ``i`` of a history, from its own columns (the reference corner ``phase`` in flight, the
    pivot rocking, the corner A in full contact): kinetic relative to the ground, the weights' and the spring's."""
    k = int(history["phase"][i]) or 1
    get = {
        name: float(history[name][i]) if name in history else 0.0
        for name in ("theta", "dtheta", "u", "du", "v", "dv", "x", "dx")
    }
    b = body(block, damper)
    z = b.centroid(k, get["theta"], get["u"], get["du"], get["dtheta"], get["v"], get["dv"], x=get["x"], dx=get["dx"])
    return b.energy(z)


def typed_twice(n: int, seed: int, s: int, damper: bool = False) -> float:
    """The largest difference between the reference and ``rocking.reference.flight`` (typed apart) on ``n`` random
    flying states about the corner ``s``: the impulses at the corner (stick and slide, any ``e_n``) and on both
    corners at ``theta = 0``, and with ``damper`` (random ones) the accelerations in flight too. In m/s, rad/s, m/s^2,
    rad/s^2, impulses per unit mass."""
    rng = np.random.default_rng(seed)
    blk, worst = rocking.Block.reference(), 0.0
    for _ in range(n):
        tuned = rocking.Damper.from_nondim(
            blk, gamma=rng.uniform(0.02, 0.3), omega_ratio=rng.uniform(0.5, 2), zeta=rng.uniform(0, 0.3), h=0.1
        )
        b = body(blk, tuned if damper else None)
        theta, x, dx = s * rng.uniform(1e-3, 0.6), rng.uniform(-0.5, 0.5) * damper, rng.uniform(-2, 2) * damper
        u, du, omega, dv = rng.uniform(-1, 1), rng.uniform(-2, 2), rng.uniform(-3, 3), rng.uniform(-2, -0.1)
        z = b.centroid(s, theta, u, du, omega, 0.0, dv, x=x, dx=dx)
        e_n, mu, M = rng.uniform(0, 1), rng.uniform(-1, 1), blk.M
        body_args = (blk.M, b.I_G, blk.B, blk.H, blk.e)
        d = (b.m, b.h)
        if damper:
            ag, agy = rng.uniform(-10, 10), rng.uniform(-20, 5)
            dd, ddx, a_G, _, _ = ref.dynamics(b, z, ag, agy)
            accel = hand.omd_flight_accel(s, theta, x, omega, dx, ag, agy, *body_args, blk.g, *d, b.k_m, b.c)
            worst = max(worst, np.max(np.abs(np.subtract((dd, ddx, *ref.corner_rate(b, s, z, dd, a_G)), accel))))
        flat = z.copy()
        flat[2] = 0.0
        du_c, dv_c = b.corner(s, flat)[1]
        for stick in (True, False):
            law = None if stick else mu
            zp, Pt, Pn = ref.impulse(b, s, z, -e_n * dv, law)
            zf, Pf, PA, PB = ref.flat_impulse(b, flat, -e_n * dv_c, law)
            Ps, Po = (PA, PB) if s == 1 else (PB, PA)
            got: tuple
            want: tuple
            got_flat: tuple
            if damper:
                got = (zp[5], zp[7], *b.corner(s, zp)[1], Pt / M, Pn / M)
                want = hand.omd_landing(s, theta, x, omega, dx, du, dv, *body_args, *d, e_n, mu, stick)
                got_flat = (zf[7], zf[3], zf[4], Pf / M, Ps / M, Po / M)
                want_flat = hand.omd_flat_landing(s, x, omega, dx, du_c, dv_c, *body_args, *d, e_n, mu, stick)
            else:
                got = (zp[5], *b.corner(s, zp)[1], Pt / M, Pn / M)
                want = hand.block_landing(s, theta, omega, du, dv, *body_args, e_n, mu, stick)
                got_flat = (zf[3], zf[4], Pf / M, Ps / M, Po / M)
                want_flat = hand.block_flat_landing(s, omega, du_c, dv_c, *body_args, e_n, mu, stick)
            scale = np.ones(len(got))
            scale[-2:] = M
            worst = max(worst, np.max(np.abs(np.subtract(got, np.divide(want, scale)))))
            scale = np.ones(len(got_flat))
            scale[-3:] = M
            worst = max(worst, np.max(np.abs(np.subtract(got_flat, np.divide(want_flat, scale)))))
    return float(worst)
