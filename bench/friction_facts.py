"""The outside facts of a floor with friction (issue 37 item 5; docs/model.md section 15), measured and drawn.

Each fact is a function here that runs the simulator and returns what the fact compares;
``tests/test_friction_facts.py`` loads this file and asserts each on a small grid, and this script measures
each on a finer one, prints the numbers, writes them (``--json``) and draws one figure per fact (``--figures``):

(a) ``mu = inf`` is the run without a floor, bit for bit; a floor that always holds (``mu = 1e3``) is the
    ``mu = inf`` run to 1e-12;
(b) pure sliding under the one-sine pulse against its closed form
    (:func:`rocking.reference.sliding.one_sine_sliding`): slip starts at ``asin(mu_s g / a_g) / omega_g``,
    peak and residual slip;
(c) Shenton (1996)'s initiation from rest under a slowly growing ramp: a symmetric bare block slides first if
    ``mu_s < B/H``, rocks first if ``mu_s > B/H``;
(d) Housner (1963)'s restitution of a sticking impact, ``dtheta+ / dtheta- = 1 - 3/2 sin^2 alpha``
    (docs/model.md section 6);
(e) the energy in the ground frame never rises after the pulse (friction, impacts and the damper only
    dissipate);
(f) issue 37's table: the block ``H = 2, B = 0.5, M = 1000`` under ``a_g = 0.4 g``, ``T = 0.5 s``; peak slip
    31.45 mm at ``mu = 0.2`` (an independent sliding-only model), slide-rock at 0.26, the no-slip response from
    0.3; and the hand-typed reference :func:`rocking.reference.sliding.slide_rock`.

Run: ``.venv/bin/python bench/friction_facts.py`` (about a minute on one core; ``--backend c`` once the C back
end follows friction).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

import rocking
from rocking.reference.sliding import one_sine_sliding, slide_rock
from rocking.sim.backends import BACKENDS

G = 9.81
#: Issue 37's block and pulse: H = 2 m, B = 0.5 m, M = 1000 kg under a_g = 0.4 g, T = 0.5 s.
H, B, M = 2.0, 0.5, 1000.0
A_G, OMEGA_G = 0.4 * G, 2 * math.pi / 0.5
#: Time followed after the pulse, s, and the tolerance of every run here: tight, so that the facts test the
#: model, not the integrator.
T_AFTER, RTOL = 3.0, 1e-10
#: The back ends whose phase machine follows a floor with friction (rocking.sim.backends' flags).
FRICTION_BACKENDS = tuple(name for name, backend in BACKENDS.items() if backend.friction)
#: The regimes of the table: slides alone, slides and rocks, rocks (issue 37).
TABLE_MUS = (0.2, 0.26, 0.3, 0.4, 0.5)
#: The ramp of fact (c): its peak reached over RAMP_TIME, sampled every RAMP_DT; slow against the block's
#: frequency p (about 2 rad/s here) so that the block starts from a quasi-static state.
RAMP_PEAK, RAMP_TIME, RAMP_DT = 1.0 * G, 4.0, 0.01


def table_block(b_over_h: float = B / H) -> rocking.Block:
    """Issue 37's block (``H = 2 m``, ``M = 1000 kg``), of base ``B = b_over_h H``."""
    return rocking.Block(H=H, B=b_over_h * H, M=M)


def table_damper(block: rocking.Block) -> rocking.Damper:
    """The damper of docs/model.md section 9's examples: 5 % of the block's mass, tuned, 5 % damping."""
    return rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)


def one_sine(a_g: float = A_G, omega_g: float = OMEGA_G, sign: int = 1) -> rocking.OneSinePulse:
    """The one-sine pulse ``sign a_g sin(omega_g t)``."""
    return rocking.OneSinePulse(a_g=a_g, omega_g=omega_g, sign=sign)


def run(backend: str, block, damper, motion, record: bool = False, **options) -> rocking.Response:
    """One run at :data:`RTOL`, followed :data:`T_AFTER` s after the motion unless ``options`` say otherwise."""
    options.setdefault("t_after", T_AFTER)
    options.setdefault("rtol", RTOL)
    return rocking.simulate(block, damper, motion, backend=backend, record=record, **options)


# --------------------------------------------------------------------------- (a)


def paper_floor(backend: str, damper: bool) -> tuple[rocking.Response, rocking.Response]:
    """The table's pulse without a floor argument and with ``mu = inf``, recorded."""
    block = table_block()
    args = (backend, block, table_damper(block) if damper else None, one_sine())
    return run(*args, record=True), run(*args, record=True, mu=math.inf)


def identical(one: rocking.Response, other: rocking.Response) -> bool:
    """Every result and every column of the history equal, bit for bit."""
    h, k = one.history, other.history
    assert h is not None and k is not None, "recorded runs"
    return (
        one.summary() == other.summary() and h.keys() == k.keys() and all(h[c].tobytes() == k[c].tobytes() for c in h)
    )


def holding_floor(backend: str, damper: bool, mu: float = 1e3) -> tuple[rocking.Response, rocking.Response]:
    """The table's pulse on the paper's floor (``mu = inf``) and on a floor that holds (``mu``), recorded.

    Both without the early verdict and the early rest (docs/simulation.md rule 4): on a finite floor the back end
    gives neither (the slip is not bounded by the energy), so the two runs end by the same rule only without.
    """
    block = table_block()
    args = (backend, block, table_damper(block) if damper else None, one_sine(), True)
    return run(*args, early_verdict=False, early_rest=False), run(*args, mu=mu, early_verdict=False, early_rest=False)


# --------------------------------------------------------------------------- (b)


def pure_sliding(backend: str, a_g: float, omega_g: float, mu_s: float, mu_k: float, sign: int):
    """The table's block (``B/H = 0.25 > mu_s``: it never lifts) under the one-sine pulse: the recorded run and
    the closed form of :func:`rocking.reference.sliding.one_sine_sliding`."""
    r = run(backend, table_block(), None, one_sine(a_g, omega_g, sign), record=True, mu=mu_s, mu_k=mu_k, t_after=1.0)
    return r, one_sine_sliding(a_g, omega_g, mu_s, mu_k, sign=sign)


def first_slip_time(history: dict) -> float:
    """The time of the first recorded row that slides (``nan`` if none)."""
    rows = np.flatnonzero(history["slide"] != 0)
    return float(history["t"][rows[0]]) if rows.size else math.nan


def start_time(a_g: float, omega_g: float, mu_s: float) -> float:
    """Section 15's start of slip under the one-sine pulse: ``asin(mu_s g / a_g) / omega_g``."""
    return math.asin(mu_s * G / a_g) / omega_g


# --------------------------------------------------------------------------- (c)


def ramp() -> rocking.SampledMotion:
    """A linear ramp of ground acceleration from 0 to :data:`RAMP_PEAK` over :data:`RAMP_TIME`."""
    t = np.arange(0.0, RAMP_TIME + RAMP_DT / 2, RAMP_DT)
    return rocking.SampledMotion(RAMP_PEAK * t / RAMP_TIME, dt=RAMP_DT)


def first_event(history: dict | None) -> str:
    """How a history first leaves rest: ``"slides"`` (a sliding row first), ``"rocks"`` (a rocking row first),
    ``"both"`` (the same row) or ``"none"``."""
    assert history is not None, "a recorded run"
    slides, rocks = np.flatnonzero(history["slide"] != 0), np.flatnonzero(history["phase"] != 0)
    first_slide = slides[0] if slides.size else math.inf
    first_rock = rocks[0] if rocks.size else math.inf
    if first_slide == first_rock:
        return "none" if math.isinf(first_slide) else "both"
    return "slides" if first_slide < first_rock else "rocks"


def initiation(backend: str, b_over_h: float, ratio: float) -> rocking.Response:
    """The symmetric bare block of ``B/H = b_over_h`` on a floor of ``mu_s = ratio B/H`` under :func:`ramp`,
    recorded until the ramp passes both thresholds (``mu_s g`` and ``g B/H``) by 10 %."""
    mu = ratio * b_over_h
    t_max = 1.1 * max(mu, b_over_h) * G * RAMP_TIME / RAMP_PEAK
    return rocking.simulate(
        table_block(b_over_h), None, ramp(), backend=backend, mu=mu, record=True, check="none", t_max=t_max
    )


# --------------------------------------------------------------------------- (d)


def housner(alpha: float) -> float:
    """Housner's restitution of the rectangular block, ``1 - 3/2 sin^2 alpha`` (docs/model.md section 6)."""
    return 1.0 - 1.5 * math.sin(alpha) ** 2


def free_rocking(backend: str, b_over_h: float, mu: float = 0.7) -> rocking.Response:
    """The bare block of ``B/H = b_over_h`` released at rest from ``theta = 0.2 alpha`` about ``A``, recorded
    (the motion, which the model needs, is a negligible pulse: 1 mm/s^2 over 6 ms)."""
    block = table_block(b_over_h)
    pulse = one_sine(1e-3, 1e3)
    return run(backend, block, None, pulse, True, mu=mu, y0=[0.2 * block.alpha, 0.0], phase0=1, t_max=3.0)


def restitutions(history: dict | None) -> np.ndarray:
    """``dtheta+ / dtheta-`` of each impact of a history: the pairs of rows at one instant whose pivot changes
    from ``s`` to ``-s`` (an impact that brings the block to rest ends in full contact: not counted)."""
    assert history is not None, "a recorded run"
    phase, t, dtheta = history["phase"], history["t"], history["dtheta"]
    k = np.flatnonzero((t[1:] == t[:-1]) & (phase[:-1] != 0) & (phase[1:] == -phase[:-1]))
    return dtheta[k + 1] / dtheta[k]


# --------------------------------------------------------------------------- (e)


def ground_frame_energy(response: rocking.Response, slip: bool = True) -> tuple[np.ndarray, np.ndarray, float]:
    """``(t, E, E_rest)`` of a recorded run on a floor with friction: ``E`` the generated ``energy`` plus
    ``slip_energy(du)`` at each row (docs/model.md section 15; without it if not ``slip``: the balance's check),
    ``E_rest`` the energy at rest."""
    h, inputs = response.history, response.inputs
    assert h is not None and inputs is not None, "a recorded run"
    model, p = inputs.model, list(inputs.p)
    state = [h[name] for name in model.state]
    s = np.where(h["phase"] == 0, 1.0, h["phase"]).astype(float)  # in full contact theta = 0: either pivot
    energy = np.asarray(model.functions.energy(s, *state, 0.0, 0.0, *p), dtype=np.float64)
    if slip:
        energy = energy + np.asarray(model.functions.slip_energy(s, *state, 0.0, 0.0, *p, h["du"]), dtype=np.float64)
    rest = float(model.functions.energy(1.0, *np.zeros(len(state)), 0.0, 0.0, *p))
    return h["t"], energy, rest


def t_p(response: rocking.Response) -> float:
    """The end of a run's ground motion, s."""
    assert response.inputs is not None, "a response with its inputs"
    return float(response.inputs.settings["t_p"])


def energy_rise(response: rocking.Response, slip: bool = True) -> tuple[float, float]:
    """The largest rise of the ground-frame energy from one recorded row to the next after the pulse, J, and the
    largest ``|E|`` of the run, J: the energy measured from the floor, whose size (``M g H / 2`` and more) sets
    the integrator's error on it (a relative error ``rtol`` of the state is one of about ``rtol |E|`` on ``E``)."""
    t, energy, _ = ground_frame_energy(response, slip)
    after = energy[t >= t_p(response)]
    return float(np.max(np.diff(after))), float(np.max(np.abs(energy)))


def slide_rock_runs(backend: str, damper: bool) -> dict[str, rocking.Response]:
    """The slide-rock runs of fact (e), recorded: the table's ``mu = 0.26`` (it slides while rocking during the
    pulse) and a longer pulse (``T = 1 s``) under which the block slides while it falls after the pulse."""
    block = table_block()
    d = table_damper(block) if damper else None
    return {
        "table mu 0.26": run(backend, block, d, one_sine(), True, mu=0.26),
        "T = 1 s, mu 0.3": run(backend, block, d, one_sine(A_G, 2 * math.pi), True, mu=0.3),
    }


# --------------------------------------------------------------------------- (f)


def table_run(backend: str, mu: float | None, record: bool = False) -> rocking.Response:
    """Issue 37's table: the bare block under the pulse on a floor ``mu`` (``None``: the paper's)."""
    return run(backend, table_block(), None, one_sine(), record, **({} if mu is None else {"mu": mu}))


def table_reference(mu: float):
    """The hand-typed slide-rock reference (:func:`rocking.reference.sliding.slide_rock`) of the table's run."""
    I_G = M * (B**2 + H**2) / 12
    return slide_rock(M, I_G, B, H, 0.0, G, A_G, OMEGA_G, mu, t_after=T_AFTER, rtol=RTOL)


# --------------------------------------------------------------------------- measurements

#: The finer grids of the figures.
SLIDING_CASES = (
    (A_G, OMEGA_G, 0.2, 0.2, 1),
    (A_G, OMEGA_G, 0.2, 0.15, -1),
    (0.8 * G, 6.0, 0.2, 0.15, 1),
    (0.3 * G, 20.0, 0.1, 0.1, -1),
)
MAP_SLENDERNESS = tuple(np.round(np.linspace(0.15, 0.5, 8), 4))
MAP_RATIOS = (0.7, 0.75, 0.8, 0.85, 0.9, 0.95, 0.99, 1.01, 1.05, 1.1, 1.15, 1.2, 1.25, 1.3)
RESTITUTION_SLENDERNESS = tuple(np.round(np.linspace(0.05, 0.6, 12), 4))
#: The classes of the initiation map: what comes first, and whether the other follows before the run ends.
INITIATION_CLASSES = ("slides", "slides, then rocks", "rocks", "rocks, then slides")


def initiation_class(response: rocking.Response) -> str:
    """The class of an initiation run (:data:`INITIATION_CLASSES`)."""
    first = first_event(response.history)
    other = response.uplifts if first == "slides" else response.slides
    return first + (", then " + ("rocks" if first == "slides" else "slides") if other else "")


def relative(a: float, b: float) -> float:
    """``|a - b| / |b|`` (0 where both are 0)."""
    return abs(a - b) / abs(b) if b else abs(a)


def measure_a(backend: str) -> dict:
    out: dict[str, object] = {}
    for damper in (False, True):
        key = "omd" if damper else "block"
        plain, infinite = paper_floor(backend, damper)
        out[f"mu_inf_bit_identical_{key}"] = identical(plain, infinite)
        paper, holding = holding_floor(backend, damper)
        out[f"mu_1e3_{key}"] = {
            f"{name}_rel_diff": relative(getattr(holding, name), getattr(paper, name))
            for name in ("theta_max", "x_max", "t_end")
        } | {"impacts": [paper.impacts, holding.impacts], "slides": holding.slides}
    return out


def measure_b(backend: str) -> tuple[dict, list]:
    rows, runs = [], []
    for a_g, omega_g, mu_s, mu_k, sign in SLIDING_CASES:
        r, closed = pure_sliding(backend, a_g, omega_g, mu_s, mu_k, sign)
        t0 = start_time(a_g, omega_g, mu_s)
        rows.append(
            {
                "a_g/g": a_g / G,
                "omega_g": omega_g,
                "mu_s": mu_s,
                "mu_k": mu_k,
                "sign": sign,
                "u_max_mm": r.u_max * 1e3,
                "u_max_closed_mm": closed.u_max * 1e3,
                "u_max_rel_err": r.u_max / closed.u_max - 1,
                "u_end_mm": r.u_end * 1e3,
                "u_end_closed_mm": closed.u_end * 1e3,
                "u_end_rel_err": r.u_end / closed.u_end - 1,
                "t_first_slip": first_slip_time(r.history),
                "t_start_closed": t0,
                "t_first_slip_rel_err": first_slip_time(r.history) / t0 - 1,
                "uplifts": r.uplifts,
            }
        )
        runs.append((r, closed))
    return {"cases": rows}, runs


def measure_c(backend: str) -> dict:
    classes = [[initiation_class(initiation(backend, bh, ratio)) for ratio in MAP_RATIOS] for bh in MAP_SLENDERNESS]
    wrong = sum((c.split(",")[0] == "slides") != (ratio < 1) for row in classes for c, ratio in zip(row, MAP_RATIOS))
    return {"B_over_H": list(MAP_SLENDERNESS), "mu_over_B_over_H": list(MAP_RATIOS), "classes": classes, "wrong": wrong}


def measure_d(backend: str) -> dict:
    rows = []
    for bh in RESTITUTION_SLENDERNESS:
        r = free_rocking(backend, bh)
        ratios = restitutions(r.history)
        expected = housner(table_block(bh).alpha)
        rows.append(
            {
                "B_over_H": bh,
                "housner": expected,
                "ratios": ratios.tolist(),
                "max_rel_err": float(np.max(np.abs(ratios / expected - 1))) if ratios.size else None,
                "slides": r.slides,
            }
        )
    return {"mu": 0.7, "rows": rows}


def measure_e(backend: str) -> tuple[dict, dict]:
    out, runs = {}, {}
    for damper in (False, True):
        for name, r in slide_rock_runs(backend, damper).items():
            key = f"{'omd' if damper else 'block'}, {name}"
            rise, scale = energy_rise(r)
            out[key] = {
                "status": r.status,
                "slides": r.slides,
                "uplifts": r.uplifts,
                "max_rise_J": rise,
                "max_abs_E_J": scale,
                "tolerance_J": 10 * RTOL * scale,
                "max_rise_without_slip_energy_J": energy_rise(r, slip=False)[0],
            }
            runs[key] = r
    return out, runs


def measure_f(backend: str) -> tuple[dict, dict]:
    # Without the early verdict, so that the drawn no-slip response runs to the end as the others (its theta_max
    # is the same: the verdict only ends a run whose maxima are final).
    no_slip = run(backend, table_block(), None, one_sine(), True, early_verdict=False)
    alpha = table_block().alpha
    rows, runs = [], {"no slip": no_slip} | {mu: table_run(backend, mu, record=True) for mu in TABLE_MUS}
    for mu in TABLE_MUS:
        r, ref = runs[mu], table_reference(mu)
        rows.append(
            {
                "mu": mu,
                "u_max_mm": r.u_max * 1e3,
                "u_end_mm": r.u_end * 1e3,
                "theta_max_over_alpha": r.theta_max / alpha,
                "slides": r.slides,
                "uplifts": r.uplifts,
                "theta_max_vs_no_slip": r.theta_max / no_slip.theta_max - 1,
                "reference": {
                    "u_max_mm": ref.u_max * 1e3,
                    "u_end_mm": ref.u_end * 1e3,
                    "theta_max_over_alpha": ref.theta_max / alpha,
                    "slides": ref.slides,
                    "uplifts": ref.uplifts,
                },
            }
        )
    return {"no_slip_theta_max_over_alpha": no_slip.theta_max / alpha, "rows": rows}, runs


# --------------------------------------------------------------------------- figures


def figure_b(runs: list, path: Path) -> None:
    """u(t) of each pure-sliding run against the closed form's start, peak and residual slip (the long slip of
    the third case on a panel of its own)."""
    import matplotlib.pyplot as plt

    from rocking.plot.style import cycle

    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.8), layout="constrained", width_ratios=(3, 2))
    for i, ((a_g, omega_g, mu_s, mu_k, sign), (r, closed)) in enumerate(zip(SLIDING_CASES, runs)):
        ax, style, h = axes[1 if closed.u_max > 0.2 else 0], cycle(i), r.history
        label = (
            f"$a_g$ = {a_g / G:.1f} g, $\\omega_g$ = {omega_g:.3g} rad/s, $\\mu_s$ = {mu_s}, $\\mu_k$ = {mu_k}, "
            f"sign {sign:+d}"
        )
        ax.plot(h["t"], h["u"] * 1e3, color=style["color"], lw=1.6, label=label)
        ax.plot([closed.t_start], [0.0], ls="none", marker="|", ms=14, mew=2, color=style["color"])
        k = np.argmax(np.abs(h["u"]))
        u_peak = math.copysign(closed.u_max, h["u"][k]) * 1e3
        ax.plot([h["t"][k]], [u_peak], ls="none", marker="o", mfc="none", ms=10, mew=1.5, color=style["color"])
        ax.plot([closed.t_end], [closed.u_end * 1e3], ls="none", marker="*", ms=12, color=style["color"])
    for ax in axes:
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_xlabel("time t [s]")
    axes[0].plot(
        [],
        [],
        ls="none",
        marker="|",
        ms=12,
        mew=2,
        color="0.3",
        label=r"closed form: start, $\arcsin(\mu_s g/a_g)/\omega_g$",
    )
    axes[0].plot([], [], ls="none", marker="o", mfc="none", ms=10, color="0.3", label="closed form: peak slip")
    axes[0].plot(
        [], [], ls="none", marker="*", ms=12, color="0.3", label="closed form: residual slip at the slip's end"
    )
    axes[0].set_ylabel("slip u [mm]")
    axes[0].set_ylim(-45.0, 95.0)
    for ax in axes:
        ax.legend(fontsize=7.5, loc="upper left")
    fig.suptitle("(b) Pure sliding under the one-sine pulse: the simulator (lines) against the closed form (markers)")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def figure_c(data: dict, path: Path) -> None:
    """The initiation map over (B/H, mu_s / (B/H)), each run marked by what comes first."""
    import matplotlib.pyplot as plt

    from rocking.plot.style import OKABE_ITO

    looks = {
        "slides": (OKABE_ITO["blue"], "s", "full", "slides first, never lifts"),
        "slides, then rocks": (OKABE_ITO["blue"], "s", "none", "slides first, then rocks"),
        "rocks": (OKABE_ITO["vermillion"], "^", "full", "rocks first, never slides"),
        "rocks, then slides": (OKABE_ITO["vermillion"], "^", "none", "rocks first, then slides (slide-rock)"),
    }
    fig, ax = plt.subplots(figsize=(7.0, 5.0), layout="constrained")
    for name, (color, marker, fill, label) in looks.items():
        points = [
            (bh, ratio)
            for bh, row in zip(data["B_over_H"], data["classes"])
            for ratio, c in zip(data["mu_over_B_over_H"], row)
            if c == name
        ]
        if points:
            x, y = zip(*points)
            ax.plot(
                x,
                y,
                ls="none",
                marker=marker,
                ms=8,
                color=color,
                fillstyle=fill,
                label=label,
            )
    ax.axhline(1.0, color="0.3", ls="--", lw=1.0, label=r"Shenton (1996): $\mu_s = B/H$")
    ax.set_xlabel("slenderness B/H")
    ax.set_ylabel(r"static friction $\mu_s$ / (B/H)")
    ax.set_title("(c) Initiation from rest under a ramp (0 to 1 g in 4 s)")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.savefig(path, dpi=120)
    plt.close(fig)


def figure_d(data: dict, path: Path) -> None:
    """dtheta+/dtheta- of the sticking impacts against Housner's over the slenderness, and the deviation."""
    import matplotlib.pyplot as plt

    from rocking.plot.style import OKABE_ITO

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.0, 6.0), sharex=True, layout="constrained", height_ratios=(3, 2))
    bh = np.linspace(0.02, 0.62, 200)
    top.plot(
        bh, [housner(math.atan(x)) for x in bh], color="0.3", lw=1.2, label=r"Housner: $1 - \frac{3}{2}\sin^2\alpha$"
    )
    for row in data["rows"]:
        x = np.full(len(row["ratios"]), row["B_over_H"])
        top.plot(x, row["ratios"], ls="none", marker="o", mfc="none", color=OKABE_ITO["blue"])
        errors = np.maximum(np.abs(np.asarray(row["ratios"]) / row["housner"] - 1), 1e-17)
        bottom.semilogy(x, errors, ls="none", marker="o", mfc="none", color=OKABE_ITO["blue"])
    top.plot(
        [],
        [],
        ls="none",
        marker="o",
        mfc="none",
        color=OKABE_ITO["blue"],
        label=rf"each impact of a free rocking run, $\mu$ = {data['mu']}",
    )
    top.set_ylabel(r"$\dot\theta^+ / \dot\theta^-$")
    top.set_title(r"(d) Restitution of sticking impacts ($\mu$ = 0.7) against Housner (1963)")
    top.legend(fontsize=8)
    bottom.axhline(1e-9, color=OKABE_ITO["vermillion"], ls="--", lw=1.0, label="the test's tolerance 1e-9")
    bottom.set_ylabel("relative deviation\n(1e-17: exact)")
    bottom.set_xlabel("slenderness B/H")
    bottom.legend(fontsize=8)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def figure_e(runs: dict, path: Path) -> None:
    """E(t) - E_rest of the slide-rock runs, slip marked, the pulse's end drawn."""
    import matplotlib.pyplot as plt

    from rocking.plot.style import cycle

    fig, axes = plt.subplots(2, 1, figsize=(8.0, 6.4), sharex=True, layout="constrained")
    for ax, part in zip(axes, ("block", "omd")):
        for i, (key, r) in enumerate((k, r) for k, r in runs.items() if k.startswith(part)):
            t, energy, rest = ground_frame_energy(r)
            style = cycle(i)
            label = key.split(", ", 1)[1] + f" ({r.status})"
            ax.plot(t, (energy - rest) / 1e3, color=style["color"], lw=1.4, label=label)
            sliding = r.history["slide"] != 0
            ax.plot(t[sliding], (energy[sliding] - rest) / 1e3, ls="none", marker=".", ms=4, color=style["color"])
            ax.axvline(t_p(r), color=style["color"], ls=":", lw=1.0)
        ax.plot([], [], ls="none", marker=".", color="0.3", label="rows where the base slides")
        ax.plot([], [], ls=":", color="0.3", label="end of the pulse $t_p$")
        ax.set_ylabel(r"$E - E_{rest}$ [kJ]")
        ax.set_title(
            ("block alone" if part == "block" else "with damper") + ": energy in the ground frame, the slip's included"
        )
        ax.legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time t [s]")
    axes[-1].set_xlim(0.0, 2.5)
    fig.suptitle("(e) After the pulse the energy never rises (friction, impacts and the damper dissipate)")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def figure_f(runs: dict, path: Path) -> None:
    """Issue 37's three regimes: theta/alpha and u against t, the no-slip response beside."""
    import matplotlib.pyplot as plt

    from rocking.plot.style import cycle

    alpha = table_block().alpha
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8.0, 6.4), sharex=True, layout="constrained")
    h = runs["no slip"].history
    top.plot(h["t"], h["theta"] / alpha, color="0.5", lw=2.5, ls="--", label=r"no slip ($\mu = \infty$)")
    for i, mu in enumerate((0.2, 0.26, 0.4)):
        h, style = runs[mu].history, cycle(i)
        word = {0.2: "slides", 0.26: "slides and rocks", 0.4: "rocks"}[mu]
        top.plot(h["t"], h["theta"] / alpha, color=style["color"], lw=1.4, label=rf"$\mu$ = {mu}: {word}")
        bottom.plot(h["t"], h["u"] * 1e3, color=style["color"], lw=1.4, label=rf"$\mu$ = {mu}")
    bottom.axhline(-31.45, color="0.3", ls=":", lw=1.0, label="31.45 mm: peak of an independent sliding-only model")
    top.set_ylabel(r"$\theta / \alpha$")
    bottom.set_ylabel("slip u [mm]")
    bottom.set_xlabel("time t [s]")
    bottom.set_xlim(0.0, 2.0)
    top.legend(fontsize=8, loc="lower left")
    bottom.legend(fontsize=8, loc="center right")
    fig.suptitle("(f) Issue 37's block (H = 2 m, B = 0.5 m) under $a_g$ = 0.4 g, T = 0.5 s on three floors")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--backend", default=FRICTION_BACKENDS[0], choices=FRICTION_BACKENDS)
    parser.add_argument("--json", default="bench/results/friction_facts.json", help="write the numbers here")
    parser.add_argument("--figures", default="bench/results", help="write the PNGs in this folder")
    args = parser.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    folder = Path(args.figures)
    folder.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    out: dict = {"backend": args.backend, "rtol": RTOL}
    out["a"] = measure_a(args.backend)
    out["b"], runs_b = measure_b(args.backend)
    figure_b(runs_b, folder / "friction_b_sliding.png")
    out["c"] = measure_c(args.backend)
    figure_c(out["c"], folder / "friction_c_initiation.png")
    out["d"] = measure_d(args.backend)
    figure_d(out["d"], folder / "friction_d_restitution.png")
    out["e"], runs_e = measure_e(args.backend)
    figure_e(runs_e, folder / "friction_e_energy.png")
    out["f"], runs_f = measure_f(args.backend)
    figure_f(runs_f, folder / "friction_f_table.png")
    out["seconds"] = round(time.perf_counter() - start, 1)
    report(out)
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    with open(args.json, "w") as f:
        json.dump(out, f, indent=1)


def report(out: dict) -> None:
    """The numbers a closing note quotes."""
    print(f"back end {out['backend']}, rtol {out['rtol']:g}, {out['seconds']} s")
    a = out["a"]
    for key in ("block", "omd"):
        diffs = ", ".join(f"{k} {v:.1e}" for k, v in a[f"mu_1e3_{key}"].items() if k.endswith("rel_diff"))
        print(f"(a) {key}: mu = inf bit-identical {a[f'mu_inf_bit_identical_{key}']}; mu = 1e3 against inf: {diffs}")
    for c in out["b"]["cases"]:
        print(
            f"(b) a_g {c['a_g/g']:.1f} g, omega {c['omega_g']:.3g}, mu_s {c['mu_s']}, mu_k {c['mu_k']}, "
            f"sign {c['sign']:+d}: "
            f"u_max {c['u_max_mm']:.4f} mm ({c['u_max_rel_err']:+.1e}), u_end {c['u_end_mm']:.4f} mm "
            f"({c['u_end_rel_err']:+.1e}), first slip {c['t_first_slip']:.6f} s ({c['t_first_slip_rel_err']:+.1e})"
        )
    c = out["c"]
    print(
        f"(c) {len(c['B_over_H'])} x {len(c['mu_over_B_over_H'])} runs, "
        f"first event against Shenton's rule wrong: {c['wrong']}"
    )
    worst = max(r["max_rel_err"] for r in out["d"]["rows"] if r["max_rel_err"] is not None)
    impacts = sum(len(r["ratios"]) for r in out["d"]["rows"])
    slid = sum(r["slides"] for r in out["d"]["rows"])
    print(
        f"(d) {impacts} sticking impacts over B/H 0.05..0.6, slides {slid}: largest deviation from Housner {worst:.1e}"
    )
    for key, e in out["e"].items():
        print(
            f"(e) {key}: {e['status']}, largest rise after t_p {e['max_rise_J']:.1e} J "
            f"(tolerance {e['tolerance_J']:.1e} J; "
            f"without the slip's energy {e['max_rise_without_slip_energy_J']:.2f} J)"
        )
    f = out["f"]
    print(f"(f) no slip: theta_max/alpha {f['no_slip_theta_max_over_alpha']:.4f}")
    for r in f["rows"]:
        ref = r["reference"]
        print(
            f"(f) mu {r['mu']}: u_max {r['u_max_mm']:.2f} mm, u_end {r['u_end_mm']:.2f} mm, theta_max/alpha "
            f"{r['theta_max_over_alpha']:.4f} ({r['theta_max_vs_no_slip']:+.1e} from no slip), slides {r['slides']}, "
            f"uplifts {r['uplifts']}; reference {ref['u_max_mm']:.2f} mm, {ref['u_end_mm']:.2f} mm, "
            f"{ref['theta_max_over_alpha']:.4f}"
        )


if __name__ == "__main__":
    main()
