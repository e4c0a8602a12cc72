"""An outside check of a floor with friction (issue 37): a general rigid-body engine beside the project.

MuJoCo (``pip install mujoco``: a bench tool only, never a dependency of ``rocking``) simulates the block
``H = 2 m, B = 0.5 m, M = 1000 kg`` as a box on a plane with Coulomb friction (elliptic cone, stiff contact:
time constant ``TC`` = 2 ms, critically damped, so plastic; step ``DT`` = 1e-4 s; the no-slip solver on). The
ground motion is the inertial force ``-M ddx_g`` at the centre of mass (the ground frame). It prints and
writes (``--json``):

1. the engine's restitution of a rocking impact against Housner's ``1 - 3/2 sin^2 alpha`` (docs/model.md 10.5);
2. the table of issue 37: under the one-sine pulse ``a_g = 0.4 g``, ``T = 0.5 s``, for each ``mu``, the
   engine's peak and residual slip of the contact point and its ``theta_max / alpha``, beside the project's
   no-slip response (``rocking.simulate``), the closed form of pure sliding and the hand-typed slide-rock
   reference of docs/model.md section 15 (``rocking.reference.sliding``: ``one_sine_sliding``, ``slide_rock``);
3. the engine's own convergence: the same at half the step and half the contact time constant.

Run: ``.venv/bin/python bench/outside_floor.py --json bench/outside-floor.json`` (about a minute).
"""

from __future__ import annotations

import argparse
import datetime
import json
import time

import numpy as np

import rocking
from rocking.reference.sliding import one_sine_sliding, slide_rock

G = 9.81
H, B, M = 2.0, 0.5, 1000.0
A_G, OMEGA_G = 0.4 * G, 2 * np.pi / 0.5
DT, TC = 1e-4, 0.002
MUS = (0.2, 0.24, 0.26, 0.28, 0.3, 0.4, 0.5, 0.7)


def engine(mu: float, dt: float = DT, tc: float = TC):
    """The MuJoCo model and data of the block on the floor, settled under its weight."""
    import mujoco

    xml = f"""<mujoco><option timestep="{dt}" gravity="0 0 -{G}" cone="elliptic" noslip_iterations="30"/>
    <default><geom solref="{tc} 1" solimp="0.99 0.999 0.0001" friction="{mu} 0 0" condim="3"/></default>
    <worldbody><geom type="plane" size="20 20 0.1"/>
    <body name="block" pos="0 0 {H / 2}"><freejoint/><geom type="box" size="{B / 2} 0.25 {H / 2}" mass="{M}"/></body>
    </worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    for _ in range(int(0.3 / dt)):
        mujoco.mj_step(model, data)
    return model, data


#: Tilt below which the block counts as in full contact, rad: the soft contact's own tilt under the pulse
#: stays below it (a corner lifted by less than 0.1 mm).
FLAT = 1e-4 / B


def pose(data):
    """Tilt about the out-of-plane axis (positive: rocking about the right corner) and the contact point's x:
    the base's centre in full contact, the lower corner once the block tilts past :data:`FLAT`."""
    R = data.xmat[1].reshape(3, 3)
    theta = np.arctan2(R[0, 2], R[2, 2])
    corners = [data.xpos[1] + R @ np.array([side * B / 2, 0.0, -H / 2]) for side in (-1, 1)]
    low = min(corners, key=lambda c: c[2]) if abs(theta) > FLAT else (corners[0] + corners[1]) / 2
    return theta, low[0]


def engine_response(mu: float, dt: float = DT, tc: float = TC, t_after: float = 2.0) -> dict:
    """The engine's response to the pulse: peak and residual slip of the contact point, m; ``theta_max / alpha``."""
    import mujoco

    model, data = engine(mu, dt, tc)
    T = 2 * np.pi / OMEGA_G
    _, x0 = pose(data)
    theta_max, u_max, t = 0.0, 0.0, 0.0
    pivot, u = 0.0, 0.0
    while t < T + t_after:
        data.xfrc_applied[1, 0] = -M * A_G * np.sin(OMEGA_G * t) if t < T else 0.0
        mujoco.mj_step(model, data)
        t += dt
        theta, x = pose(data)
        theta_max = max(theta_max, abs(theta))
        # Slip of the contact point: of the base's centre in full contact, of the pivot while rocking (a pivot
        # change moves the contact point by B: counted from the corner's own position at the change).
        side = np.sign(theta) if abs(theta) > FLAT else 0.0
        if side != pivot:
            x0 = x - u
            pivot = side
        u = x - x0
        u_max = max(u_max, abs(u))
        if abs(theta) > np.pi / 2:
            break
    return {"u_max": u_max, "u_end": u, "theta_max_over_alpha": theta_max / np.arctan(B / H)}


def engine_restitution(mu: float = 0.7) -> float:
    """The engine's restitution of a rocking impact, from the heights before and after it.

    Free rocking from rest at ``theta_0 = 0.5 alpha``: the rise after the first impact to ``theta_1`` gives
    ``r = sqrt((cos(alpha - theta_1) - cos alpha) / (cos(alpha - theta_0) - cos alpha))`` (energy between
    impacts, exact for a rigid block): no reading of a velocity through the contact's few milliseconds.
    """
    import mujoco

    model, data = engine(mu)
    alpha = np.arctan(B / H)
    theta0 = 0.5 * alpha
    corner = np.array([B / 2, 0.0, 0.0])
    turn = np.array([[np.cos(theta0), 0, np.sin(theta0)], [0, 1, 0], [-np.sin(theta0), 0, np.cos(theta0)]])
    data.qpos[:3] = corner + turn @ (np.array([0.0, 0.0, H / 2]) - corner)
    data.qpos[3:7] = [np.cos(theta0 / 2), 0.0, np.sin(theta0 / 2), 0.0]
    data.qvel[:] = 0.0
    mujoco.mj_forward(model, data)
    start, _ = pose(data)
    theta1, t = 0.0, 0.0
    while t < 3.0:
        mujoco.mj_step(model, data)
        t += DT
        theta, _ = pose(data)
        if np.sign(theta) == -np.sign(start) and abs(theta) > FLAT:
            theta1 = max(theta1, abs(theta))
        elif theta1 > 0:
            break
    return float(np.sqrt((np.cos(alpha - theta1) - np.cos(alpha)) / (np.cos(alpha - abs(start)) - np.cos(alpha))))


def project_no_slip() -> float:
    """The project's ``theta_max / alpha`` (no slip: mu = inf)."""
    block = rocking.Block(H=H, B=B, M=M)
    r = rocking.simulate(block, None, rocking.OneSinePulse(a_g=A_G, omega_g=OMEGA_G), rtol=1e-10)
    return r.theta_max / block.alpha


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json", help="write the figures to this file")
    args = parser.parse_args()
    start = time.process_time()
    alpha = np.arctan(B / H)
    housner = 1 - 1.5 * np.sin(alpha) ** 2
    measured = engine_restitution()
    print(
        f"restitution of a rocking impact: engine {measured:.5f}, Housner {housner:.5f} ({measured / housner - 1:+.2%})"
    )
    no_slip = project_no_slip()
    rows = []
    heads = (
        "engine u_max mm",
        "u_end mm",
        "theta_max/alpha",
        "reference u_max mm",
        "u_end mm",
        "theta_max/alpha",
        "project (no slip)",
        "pure sliding u_max mm",
    )
    print(f"{'mu':>5} " + " ".join(f"{h:>{len(h) + 1}}" for h in heads))
    for mu in MUS:
        e = engine_response(mu)
        slide = one_sine_sliding(A_G, OMEGA_G, mu)
        ref = slide_rock(M, M * (B**2 + H**2) / 12, B, H, 0.0, G, A_G, OMEGA_G, mu, t_after=2.0)
        rows.append(
            {
                "mu": mu,
                "engine": e,
                "project_no_slip_theta_max_over_alpha": no_slip,
                "pure_sliding_u_max": slide.u_max,
                "pure_sliding_u_end": slide.u_end,
                "reference": {"u_max": ref.u_max, "u_end": ref.u_end, "theta_max_over_alpha": ref.theta_max / alpha},
            }
        )
        values = (
            e["u_max"] * 1e3,
            e["u_end"] * 1e3,
            e["theta_max_over_alpha"],
            ref.u_max * 1e3,
            ref.u_end * 1e3,
            ref.theta_max / alpha,
            no_slip,
            slide.u_max * 1e3,
        )
        print(f"{mu:5.2f} " + " ".join(f"{v:>{len(h) + 1}.4f}" for h, v in zip(heads, values)))
    converged = {str(mu): engine_response(mu, DT / 2, TC / 2) for mu in (0.2, 0.3)}
    for mu, e in converged.items():
        print(
            f"engine at dt {DT / 2:g} s, time constant {TC / 2:g} s, mu {mu}: "
            f"u_max {e['u_max'] * 1e3:.2f} mm, theta_max/alpha {e['theta_max_over_alpha']:.4f}"
        )
    out = {
        "date": datetime.date.today().isoformat(),
        "engine": "MuJoCo " + __import__("mujoco").__version__,
        "settings": {
            "dt": DT,
            "time_constant": TC,
            "cone": "elliptic",
            "a_g": A_G,
            "T": 2 * np.pi / OMEGA_G,
            "H": H,
            "B": B,
            "M": M,
        },
        "restitution": {"engine": measured, "housner": housner},
        "table": rows,
        "converged": converged,
        "cpu_s": time.process_time() - start,
    }
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
