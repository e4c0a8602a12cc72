"""The baseline: what a user without this toolkit would write.

The paper's equations (R1), (R2), (C1), (U1), (U2), (I1), (I2) typed into SymPy,
solved for the accelerations and turned into NumPy functions with ``lambdify``,
then integrated phase by phase with ``scipy.integrate.solve_ivp`` (RK45) and
its events. It shares no code with ``rocking``: it is the yardstick for speed.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp


def build_functions():
    """Lambdified accelerations, uplift margins and impact map of the paper's model."""
    th, x, dth, dx, ag, s = sp.symbols("theta x dtheta dx ag s")
    M, I_G, B, H, e, g, m, h, k, c = sp.symbols("M I_G B H e g m h k_m c")
    ddth, ddx = sp.symbols("ddtheta ddx")
    d = s * B / 2 + e
    xi = s * B / 2 + x
    eta = H + h
    I_s = I_G + M * (d**2 + H**2 / 4)
    r1 = (
        (I_s + m * (xi**2 + eta**2)) * ddth
        - m * eta * ddx
        + 2 * m * xi * dth * dx
        + g * ((M * d + m * xi) * sp.cos(th) - (M * H / 2 + m * eta) * sp.sin(th))
        - ag * ((M * H / 2 + m * eta) * sp.cos(th) + (M * d + m * xi) * sp.sin(th))
    )
    r2 = m * ddx - m * eta * ddth + c * dx + k * x - m * xi * dth**2 + m * g * sp.sin(th) + m * ag * sp.cos(th)
    # Linear in the accelerations: mass matrix and the rest, solved without
    # simplification (sympy.solve takes minutes on this system).
    residual = sp.Matrix([r1, r2])
    mass = residual.jacobian([ddth, ddx])
    acc = mass.LUsolve(-residual.subs({ddth: 0, ddx: 0}))
    params = (M, I_G, B, H, e, g, m, h, k, c)
    rocking = sp.lambdify((s, th, x, dth, dx, ag, *params), list(acc), "numpy")
    Mo = M * H / 2 * ag - eta * (k * x + c * dx)
    up_A = Mo - g * (M * (B / 2 + e) + m * (B / 2 + x))
    up_Ap = -Mo - g * (M * (B / 2 - e) + m * (B / 2 - x))
    uplift = sp.lambdify((x, dx, ag, *params), [up_A, up_Ap], "numpy")
    d_o, xi_o = -s * B / 2 + e, -s * B / 2 + x
    ratio = (I_G + M * (H**2 / 4 + d * d_o) + m * xi * xi_o) / (I_G + M * (d_o**2 + H**2 / 4) + m * xi_o**2)
    impact = sp.lambdify((s, x, *params), ratio, "numpy")
    return rocking, uplift, impact


def simulate(funcs, params, a_g, omega_g, t_after=15.0, rtol=1e-8, atol=1e-10, rest=1e-4):
    """Overturned or not, and the number of impacts, for one one-sine pulse."""
    t_p = 2 * np.pi / omega_g

    def ag(t):
        return a_g * np.sin(omega_g * t) if t <= t_p else 0.0

    return simulate_motion(funcs, params, ag, t_p, t_p / 64, t_after, rtol, atol, rest)


def simulate_record(funcs, params, a, dt, scale, t_after=15.0, rtol=1e-8, atol=1e-10, rest=1e-4):
    """The same for a sampled record ``scale a`` (spacing ``dt``), interpolated with ``np.interp``."""
    t_rec = np.arange(len(a)) * dt

    def ag(t):
        return scale * np.interp(t, t_rec, a, right=0.0)

    return simulate_motion(funcs, params, ag, t_rec[-1], dt, t_after, rtol, atol, rest)


def simulate_motion(funcs, params, ag, t_p, max_step, t_after=15.0, rtol=1e-8, atol=1e-10, rest=1e-4):
    """Overturned or not, and the number of impacts, under the ground acceleration ``ag(t)`` that ends at ``t_p``
    (full contact steps at most ``max_step`` while it acts)."""
    rocking, uplift, impact = funcs
    M, I_G, B, H, e, g, m, h, k, c = params
    t_end = t_p + t_after
    t, y, pivot, impacts = 0.0, np.zeros(4), 0, 0
    while t < t_end - 1e-12:
        if pivot == 0:

            def contact(t, y):
                return [0.0, y[3], 0.0, (-m * ag(t) - c * y[3] - k * y[1]) / m]

            def up_a(t, y):
                return uplift(y[1], y[3], ag(t), *params)[0]

            def up_ap(t, y):
                return uplift(y[1], y[3], ag(t), *params)[1]

            up_a.terminal = up_ap.terminal = True
            up_a.direction = up_ap.direction = 1
            t1 = t_p if t < t_p else t_end
            sol = solve_ivp(contact, (t, t1), y, events=[up_a, up_ap], rtol=rtol, atol=atol, max_step=max_step)
            t, y = sol.t[-1], sol.y[:, -1]
            if sol.status == 1:
                pivot = 1 if sol.t_events[0].size else -1
            elif t >= t_p and abs(y[1]) < 1e-9 and abs(y[3]) < 1e-9:
                break
        else:
            s = pivot

            def rhs(t, y, s=s):
                a1, a2 = rocking(s, y[0], y[1], y[2], y[3], ag(t), *params)
                return [y[2], y[3], a1, a2]

            def hit(t, y, s=s, t_start=t):
                return s * y[0] if t > t_start + 1e-9 else 1.0

            def over(t, y):
                return abs(y[0]) - np.pi / 2

            hit.terminal = over.terminal = True
            hit.direction = -1
            t1 = t_p if t < t_p else t_end
            sol = solve_ivp(rhs, (t, t1), y, events=[hit, over], rtol=rtol, atol=atol)
            t, y = sol.t[-1], sol.y[:, -1].copy()
            if sol.status == 1 and sol.t_events[1].size:
                return True, impacts
            if sol.status == 1:
                impacts += 1
                r = impact(s, y[1], *params)
                y[3] = y[3] + eta_of(H, h) * (r - 1) * y[2]
                y[2] *= r
                y[0] = 0.0
                pivot = -s
                if abs(y[2]) < rest:
                    y[2], pivot = 0.0, 0
    return False, impacts


def eta_of(H, h):
    """Height of the damper mass above the base."""
    return H + h
