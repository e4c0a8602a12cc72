"""Figures of the studies, drawn from saved data only.

Every figure is drawn from a :class:`rocking.study.config.Study` as
:func:`rocking.study.storage.load` reads it back, so :func:`redraw` re-renders a
figure from its ``.npz``/``.json`` without recomputing anything. Figures are
written as PNG and PDF with matplotlib's Agg canvas (no pyplot, no display).

- map: outcome of the bare block and of the damped block over ``(Omega,
  beta)`` (safe / overturned without impact / after n impacts), and the
  damper's effect (cells saved, cells lost);
- spectrum: ``beta_min(Omega)`` with and without damper, the safe windows
  above it as bars, and the gain ``beta_min`` ratio;
- optimize: optimal ``T_m / T_g`` and ``T_m p / (2 pi)``, best gain with
  ``Omega*`` marked, and the gain landscape ``G(Omega, T_m)`` of the coarse scan.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from ..model.params import ParameterError
from ..study.config import Study
from ..study.overturning_map import saved_past_edges
from ..study.spectrum import ABOVE, BELOW, BRACKETED
from ..study.storage import load

#: Outcome classes of a map cell: label and colour; the class is min(outcome + 1, 4).
OUTCOME_CLASSES = (
    ("safe", "#f7f7f7"),
    ("overturned, no impact", "#b2182b"),
    ("overturned after 1 impact", "#ef8a62"),
    ("after 2 impacts", "#fddbc7"),
    ("after 3 or more impacts", "#9970ab"),
)
#: Effect classes: bare overturned + 2 x damped overturned, 4 for cells saved only with the
#: damper's mass past the block's edge (rocking.study.overturning_map.saved_past_edges), and 5 for saved
#: cells whose damped response an adaptive map did not compute (its stroke is not known).
EFFECT_CLASSES = (
    ("safe either way", "#f7f7f7"),
    ("saved by the damper", "#1a9850"),
    ("lost with the damper", "#d73027"),
    ("overturned either way", "#bdbdbd"),
    ("saved only with the mass past the edge (x_max > B/2)", "#a6d96a"),
    ("saved, stroke not computed (cell of an adaptive map filled in)", "#d9f0d3"),
)
PART_STYLE = {
    "bare": {"color": "black", "label": "block alone"},
    "damper": {"color": "tab:blue", "label": "with damper"},
}


def _edges(centres: np.ndarray) -> np.ndarray:
    """Cell edges around grid points (mid-points; half a step beyond the ends)."""
    c = np.asarray(centres, float)
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[2 * c[0] - mid[0]], mid, [2 * c[-1] - mid[-1]]])


def _classes(ax, Omega, beta, classes: np.ndarray, palette) -> None:
    """Draw integer classes on the (Omega, beta) plane with a categorical palette and legend."""
    cmap = ListedColormap([c for _, c in palette])
    norm = BoundaryNorm(np.arange(len(palette) + 1) - 0.5, cmap.N)
    ax.pcolormesh(_edges(Omega), _edges(beta), classes.T, cmap=cmap, norm=norm, shading="flat", rasterized=True)
    present = np.unique(classes)
    handles = [Patch(facecolor=c, edgecolor="0.5", label=label) for i, (label, c) in enumerate(palette) if i in present]
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.9)
    ax.set_xlabel(r"$\Omega = \omega_g / p$")
    ax.set_ylabel(r"$\beta = a_g / (g \tan\alpha)$")


def _damper_label(config: dict) -> str:
    """The damper of a study for a title: the omd tuning, or a variant's model name and parameters."""
    d = config["damper"]
    if "model" in d:
        params = ", ".join(f"{k} = {v:g}" for k, v in d["params"].items())
        return f"model {d['model']}" + (f" ({params})" if params else "")
    period = rf"$T_m p / 2\pi$ = {1 / d['omega_ratio']:.3g}"
    stops = ", stops at the edges" if d.get("stops") else ""
    return rf"damper $\gamma$ = {d['gamma']:g}, {period}, $\zeta$ = {d['zeta']:g}, h = {d['h']:g} m{stops}"


#: How a figure names each pulse family (rocking.study.config.PULSES).
PULSE_NAMES = {"sine": "one-sine pulse", "cosine": "one-cosine pulse", "ricker": "symmetric Ricker wavelet",
               "ricker_anti": "antisymmetric Ricker wavelet", "mp": "Mavroeidis-Papageorgiou pulse"}  # fmt: skip


def _pulse_label(config: dict) -> str:
    """The pulse family of a study for a title (the one-sine when the configuration names none)."""
    pulse = config.get("pulse", {"motion": "sine"})
    shape = f" (gamma = {pulse['gamma_mp']:g}, nu = {pulse['nu']:g})" if pulse["motion"] == "mp" else ""
    return PULSE_NAMES[pulse["motion"]] + shape


def _suite_label(suite: dict) -> str:
    """The motions of an IDA or fragility study (:meth:`rocking.study.suite.Suite.record`) for a title."""
    if "files" in suite:
        return f"{len(suite['files'])} records"
    if "pulses" in suite:
        pulses = suite["pulses"]
        families = sorted({PULSE_NAMES[p["family"]] for p in pulses})
        periods = [p["T_g"] for p in pulses]
        return f"{len(pulses)} pulses ({', '.join(families)}), T_g {min(periods):.3g} to {max(periods):.3g} s"
    return f"{suite['n']} stochastic motions (seed {suite['seed']})"


def _directions_label(config: dict) -> str:
    """The directions of a study's pulses for a title: both (the envelope shown) or one sign."""
    chosen = config.get("directions", {"directions": "positive", "signs": [1]})  # studies before format 4
    if len(chosen["signs"]) > 1:
        return "pulses of both signs, the worse shown"
    mirrored = " (symmetric: the other sign mirrors them)" if chosen["directions"] == "auto" else ""
    return f"{'positive' if chosen['signs'][0] > 0 else 'negative'} pulses{mirrored}"


#: Legend of the open triangles of :func:`_gain_curve`.
LOWER_BOUND = r"lower bound (no overturning up to the last $\beta$ scanned)"


def _gain_curve(ax, Omega, gain, flag, color, label) -> bool:
    """A gain curve, open triangles where the damped block did not overturn in the scan; True if any."""
    ax.plot(Omega, gain, "-", color=color, label=label)
    exact = flag != ABOVE
    ax.plot(Omega[exact], gain[exact], "o", ms=3, color=color)
    ax.plot(Omega[~exact], gain[~exact], "^", ms=5, mfc="none", color=color)
    return not exact.all()


def _lower_bound_legend(ax) -> None:
    ax.plot([], [], "^", ms=5, mfc="none", color="0.3", label=LOWER_BOUND)


def map_figure(study: Study) -> Figure:
    """Outcome maps of the bare and the damped block, and the damper's effect."""
    a = study.arrays
    fig = Figure(figsize=(15, 4.8), layout="constrained")
    axes = fig.subplots(1, 3, sharex=True, sharey=True)
    for ax, part, title in zip(axes, ("bare", "damper"), ("block alone", "with damper")):
        cls = np.where(a[f"{part}_overturned"], np.minimum(a[f"{part}_impacts"] + 1, 4), 0)
        _classes(ax, a["Omega"], a["beta"], cls, OUTCOME_CLASSES)
        ax.set_title(title)
    effect = a["bare_overturned"].astype(int) + 2 * a["damper_overturned"].astype(int)
    past = saved_past_edges(a, study.config["block"]["B"] / 2)
    computed = a.get("damper_computed", np.ones_like(effect, bool))  # studies saved before adaptive maps
    unknown = (effect == 1) & ~computed
    _classes(axes[2], a["Omega"], a["beta"], np.select([past, unknown], [4, 5], effect), EFFECT_CLASSES)
    s = study.summary
    axes[2].set_title(
        f"effect of the damper: {s.get('saved', 0)} cells saved\n({int(past.sum())} only past the edge"
        + (f", {int(unknown.sum())} of unknown stroke" if unknown.any() else "")
        + f"), {s.get('lost', 0)} lost",
        fontsize=9,
    )
    fig.suptitle(
        f"Overturning map, {_pulse_label(study.config)}; {_damper_label(study.config)}\n"
        f"{_directions_label(study.config)}{_refinement_label(study)}"
    )
    return fig


def _refinement_label(study: Study) -> str:
    """How many cells an adaptive map computed, for a title; nothing for a full map."""
    refinement = study.config.get("refinement", {"adaptive": False})
    if not refinement["adaptive"]:
        return ""
    a = study.arrays
    cells = a["bare_computed"].size
    computed = ", ".join(f"{int(a[f'{part}_computed'].sum())}" for part in ("bare", "damper"))
    return (
        f"; adaptive, coarse step {refinement['coarse']}: {computed} of {cells} cells computed (alone, damped), "
        "the others take the outcome around them"
    )


def spectrum_figure(study: Study) -> Figure:
    """``beta_min(Omega)`` with and without damper, windows as bars; gain of the damper."""
    a = study.arrays
    Om = a["Omega"]
    step = np.diff(Om).min() if Om.size > 1 else 1.0
    fig = Figure(figsize=(12, 4.8), layout="constrained")
    ax, ax_gain = fig.subplots(1, 2, width_ratios=(2, 1))
    for shift, part in zip((-0.12, 0.12), ("bare", "damper")):
        style = PART_STYLE[part]
        flag, bm = a[f"{part}_flag"], a[f"{part}_beta_min"]
        ax.plot(
            Om,
            np.where(flag == BRACKETED, bm, np.nan),
            "-o",
            ms=3,
            color=style["color"],
            label=rf"$\beta_{{min}}$, {style['label']}",
        )
        for code, marker, text in ((BELOW, "v", "at or below"), (ABOVE, "^", "above")):
            sel = flag == code
            if sel.any():
                ax.plot(
                    Om[sel],
                    bm[sel],
                    marker,
                    color=style["color"],
                    mfc="none",
                    label=f"{style['label']}: {text} the scan range",
                )
        w = a[f"{part}_windows"]
        if len(w):
            ax.vlines(
                w[:, 0] + shift * step,
                w[:, 1],
                w[:, 2],
                color=style["color"],
                alpha=0.45,
                lw=3,
                label=f"safe windows, {style['label']}",
            )
    ax.set_xlabel(r"$\Omega = \omega_g / p$")
    ax.set_ylabel(r"$\beta = a_g / (g \tan\alpha)$")
    ax.set_title("minimum overturning amplitude (bars: safe windows above it)")
    ax.legend(fontsize=7)
    both = (a["bare_flag"] == BRACKETED) & (a["damper_flag"] != BELOW)
    gain = np.where(both, a["damper_beta_min"] / a["bare_beta_min"], np.nan)
    if _gain_curve(ax_gain, Om, gain, a["damper_flag"], PART_STYLE["damper"]["color"], None):
        _lower_bound_legend(ax_gain)
        ax_gain.legend(fontsize=7)
    ax_gain.axhline(1.0, color="0.4", lw=0.8)
    ax_gain.set_xlabel(r"$\Omega$")
    ax_gain.set_ylabel(r"$G = \beta_{min}$(damper) / $\beta_{min}$(block)")
    ax_gain.set_title("gain of the damper")
    fig.suptitle(
        f"Minimum overturning spectrum, {_pulse_label(study.config)}; {_damper_label(study.config)}\n"
        f"{_directions_label(study.config)}"
    )
    return fig


def _threshold_text(t: dict) -> str:
    """``Omega*`` as :func:`rocking.study.optimize.threshold_frequency` found it, for a figure."""
    if t["status"] == "bracketed":
        return rf"$\Omega^*$ = {t['Omega_star']:.3g} (scanned {t['low']:.3g} .. {t['high']:.3g})"
    if t["status"] == "above_range":
        return rf"$\Omega^*$ > {t['low']:.3g} (still useful there)"
    if t["status"] == "below_range":
        return rf"$\Omega^*$ $\leq$ {t['high']:.3g} (never useful)"
    return r"$\Omega^*$ unknown (no gain defined)"


def optimize_figure(study: Study) -> Figure:
    """Optimal period (two normalisations), best gain with ``Omega*``, gain landscape of one ``gamma``."""
    a = study.arrays
    Om, gammas = a["Omega"], a["gamma"]
    fig = Figure(figsize=(12, 8.5), layout="constrained")
    (ax_tg, ax_tp), (ax_g, ax_map) = fig.subplots(2, 2)
    colors = [f"C{i}" for i in range(len(gammas))]
    useless = study.summary.get("useless_gain", 1.01)
    bounded = False
    for g, (gamma, c) in enumerate(zip(gammas, colors)):
        label = rf"$\gamma$ = {gamma:g}"
        ax_tg.plot(Om, a["Tm_over_Tg_opt"][g], "-o", ms=3, color=c, label=label)
        ax_tp.plot(Om, a["r_opt"][g], "-o", ms=3, color=c, label=label)
        bounded = _gain_curve(ax_g, Om, a["gain_opt"][g], a["flag_opt"][g], c, label) or bounded
        threshold = study.summary["Omega_star"][f"{gamma:g}"]
        if threshold["status"] == "bracketed":
            ax_g.axvspan(threshold["low"], threshold["high"], color=c, alpha=0.12)
            ax_g.axvline(threshold["Omega_star"], color=c, ls="--", lw=1)
    if len(gammas) > 1:
        ax_g.plot(Om, a["best_gain"], "k:", lw=1.5, label=r"best over $\gamma$")
    if bounded:
        _lower_bound_legend(ax_g)
    who = {key: "best" if key == "best" else rf"$\gamma$ = {key}" for key in study.summary["Omega_star"]}
    text = "\n".join(f"{who[key]}: {_threshold_text(t)}" for key, t in study.summary["Omega_star"].items())
    ax_g.text(
        0.98,
        0.97,
        text,
        transform=ax_g.transAxes,
        ha="right",
        va="top",
        fontsize=7,
        bbox={"facecolor": "white", "edgecolor": "0.7", "alpha": 0.9},
    )
    ax_g.axhline(useless, color="0.3", lw=0.8, ls=":")
    ax_g.axhline(1.0, color="0.3", lw=0.8)
    ax_g.set_ylabel(r"best gain $G = \beta_{min}$(damper) / $\beta_{min}$(block)")
    ax_g.set_title(rf"best gain; $\Omega^*$: above it $G$ < {useless:g}")
    ax_tg.set_ylabel(r"optimal $T_m / T_g$")
    ax_tp.set_ylabel(r"optimal $T_m p / 2\pi$")
    for ax in (ax_tg, ax_tp):
        ax.set_yscale("log")
    for ax in (ax_tg, ax_tp, ax_g):
        ax.set_xlabel(r"$\Omega = \omega_g / p$")
        ax.legend(fontsize=7)
    g = len(gammas) // 2
    r = a["r_coarse"]
    image = ax_map.pcolormesh(
        _edges(Om), np.exp(_edges(np.log(r))), a["gain_coarse"][g].T, cmap="RdBu", vmin=0.5, vmax=1.5
    )
    ax_map.plot(Om, a["r_opt"][g], "k.", ms=4, label="optimum (after refinement)")
    ax_map.set_yscale("log")
    ax_map.set_xlabel(r"$\Omega$")
    ax_map.set_ylabel(r"$T_m p / 2\pi$")
    ax_map.set_title(rf"gain over the coarse scan, $\gamma$ = {gammas[g]:g}")
    ax_map.legend(fontsize=7, loc="upper right")
    fig.colorbar(image, ax=ax_map, label="G")
    cfg = study.config
    fig.suptitle(rf"Optimal damper ($\zeta$ = {cfg['zeta']:g}, h = {cfg['h']:g} m); {_directions_label(cfg)}")
    return fig


def design_figure(study: Study) -> Figure:
    """The design: its gain over the band (per direction and the envelope), the worst gain of every damper of
    the coarse search, and the stroke the design uses at the pulses that overturn the block alone."""
    a, s = study.arrays, study.summary
    fig = Figure(figsize=(15, 4.6), layout="constrained")
    ax_g, ax_map, ax_x = fig.subplots(1, 3)
    Om = a["Omega"]
    for i, sign in enumerate(a["signs"]):
        ratio = a["damper_beta_min_by_sign"][:, i] / a["bare_beta_min_by_sign"][:, i]
        ax_g.plot(Om, ratio, ":", color="0.5" if sign > 0 else "tab:orange", label=f"pulses of sign {sign:+d} alone")
    if _gain_curve(ax_g, Om, a["gain_opt"], a["flag_opt"], PART_STYLE["damper"]["color"], "gain (envelopes)"):
        _lower_bound_legend(ax_g)
    ax_g.axhline(1.0, color="0.3", lw=0.8)
    ax_g.set_xlabel(r"$\Omega = \omega_g / p$")
    ax_g.set_ylabel(r"$G = \beta_{min}$(damper) / $\beta_{min}$(block)")
    ax_g.set_title(f"worst gain over the band: {s['worst_gain']:.3g} at Omega = {s['worst_at_Omega']:.3g}")
    ax_g.legend(fontsize=7)
    r, z = a["r_coarse"], a["zeta_coarse"]
    worst = a["candidate_worst_gain"][: r.size * z.size].reshape(z.size, r.size)
    image = ax_map.pcolormesh(np.exp(_edges(np.log(r))), np.exp(_edges(np.log(z))), worst, cmap="RdBu", vmin=0.5,
                              vmax=1.5)  # fmt: skip
    off = ~a["candidate_on_block"]
    ax_map.plot(a["candidate_r"][off], a["candidate_zeta"][off], "kx", ms=5, label="mass past the block's edge")
    d = s["damper"]
    ax_map.plot([d["Tm_ratio"]], [d["zeta"]], "*", color="gold", mec="k", ms=14, label="design")
    ax_map.set_xscale("log")
    ax_map.set_yscale("log")
    ax_map.set_xlabel(r"$T_m p / 2\pi$")
    ax_map.set_ylabel(r"$\zeta$")
    ax_map.set_title("worst gain over the band, coarse search", fontsize=9)
    ax_map.legend(fontsize=7, loc="upper right")
    fig.colorbar(image, ax=ax_map, label="worst G")
    ax_x.bar(Om, a["stroke_use"], width=0.6 * np.min(np.diff(Om)) if Om.size > 1 else 0.5, color="tab:green")
    ax_x.axhline(1.0, color="0.3", lw=0.8, label="the stops (|x| = L)")
    ax_x.axhline(study.config["block"]["B"] / 2 / d["L_m"], color="tab:red", lw=0.8, ls="--", label="block's edge")
    ax_x.set_xlabel(r"$\Omega$")
    ax_x.set_ylabel(r"$x_{max} / L$ at $\beta_{min}$ of the block alone")
    ax_x.set_title("stroke used at the pulses that overturn the block alone", fontsize=9)
    ax_x.legend(fontsize=7)
    fig.suptitle(
        f"Damper design: m = {d['m_kg']:.4g} kg, k_m = {d['k_m_N_per_m']:.4g} N/m, c = {d['c_N_s_per_m']:.4g} N s/m "
        f"(T_m = {d['T_m_s']:.3g} s, zeta = {d['zeta']:.3g}), stops at L = {d['L_m']:.3g} m; "
        f"{_directions_label(study.config)}"
    )
    return fig


def _omega_star_panel(fig, ax, study: Study, kind: str) -> None:
    """``Omega*`` of one kind of damper over ``(lambda, p)``: the value where bracketed, else the highest ``Omega``
    at which it still helps (a lower bound, hatched); each cell also says from which ``Omega`` the block alone
    no longer overturns within the bound."""
    a = study.arrays
    lam, p = a["lam"], a["p"]
    status = a[f"{kind}_status"]
    value = np.where(np.isfinite(a[f"{kind}_Omega_star"]), a[f"{kind}_Omega_star"], a[f"{kind}_Omega_star_low"])
    image = ax.pcolormesh(_edges(p), _edges(lam), value, cmap="viridis", vmin=0, vmax=float(a["Omega"][-1]))
    for i in range(lam.size):
        for j in range(p.size):
            v, st = value[i, j], STATUS_TEXT[status[i, j]]
            text = "?" if not np.isfinite(v) else f"{st}{v:.3g}"
            safe = a["safe_from"][i, j]
            text += f"\nsafe from {safe:.3g}" if np.isfinite(safe) else ""
            ax.text(p[j], lam[i], text, ha="center", va="center", fontsize=7, color="w")
    ax.set_xlabel("p (rad/s)")
    ax.set_ylabel(r"$\lambda = H / B$")
    ax.set_title(f"{kind} guide: " + r"$\Omega^*$ ('>': still useful at the last $\Omega$ that overturns)",
                 fontsize=9)  # fmt: skip
    fig.colorbar(image, ax=ax, label=r"$\Omega^*$ or its lower bound")


#: How a cell of the threshold figure writes each status of Omega* (rocking.study.threshold.STATUSES).
STATUS_TEXT = ("", "<=", ">", "")


def threshold_figure(study: Study) -> Figure:
    """``Omega*(lambda, p)`` for the unlimited guide and the stops, and the best gain against ``Omega``."""
    a = study.arrays
    fig = Figure(figsize=(16, 4.8), layout="constrained")
    axes = fig.subplots(1, 3)
    for ax, kind in zip(axes[:2], ("unlimited", "stops")):
        _omega_star_panel(fig, ax, study, kind)
    j = a["p"].size // 2
    colors = [f"C{i}" for i in range(a["lam"].size)]
    for i, lam in enumerate(a["lam"]):
        for kind, style in (("unlimited", "-"), ("stops", "--")):
            label = rf"$\lambda$ = {lam:.3g}, {kind}"
            axes[2].plot(a["Omega"], a[f"{kind}_gain"][i, j], style, color=colors[i], marker=".", label=label)
    axes[2].axhline(study.summary["useless_gain"], color="0.3", lw=0.8, ls=":")
    axes[2].set_xlabel(r"$\Omega = \omega_g / p$")
    axes[2].set_ylabel("best gain (envelopes over the directions)")
    axes[2].set_title(f"best gain at p = {a['p'][j]:.3g} rad/s; ends where the block alone survives "
                      f"{study.summary['a_max_g']:g} g", fontsize=9)  # fmt: skip
    axes[2].legend(fontsize=6, ncol=2)
    fig.suptitle(f"Threshold frequency across geometries (pulses up to {study.summary['a_max_g']:g} g); "
                 f"{_directions_label(study.config)}")  # fmt: skip
    return fig


def ida_figure(study: Study) -> Figure:
    """The fraction of motions that overturn the block at each level, with the fitted lognormal fragility and its
    band, block alone and with the damper; and the outcome of every motion at every level (with the damper),
    resurrections marked."""
    a, s = study.arrays, study.summary
    fig = Figure(figsize=(13, 4.8), layout="constrained")
    ax_f, ax_m = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.2, 1]})
    unit = f" ({s['unit']})" if s["unit"] else ""
    for part in ("bare", "damper"):
        style, fit = PART_STYLE[part], s[part]
        ax_f.plot(a["levels"], a[f"{part}_fraction"], "o", color=style["color"], ms=4,
                  label=f"{style['label']}: fraction overturned")  # fmt: skip
        if fit["status"] in ("fitted", "separated"):
            label = rf"lognormal fit, $\theta$ = {fit['theta']:.3g}, $\beta$ = {fit['beta']:.2f}"
            ax_f.plot(a["curve_x"], a[f"{part}_curve"], "-", color=style["color"], label=label)
            ax_f.fill_between(a["curve_x"], a[f"{part}_band_low"], a[f"{part}_band_high"], color=style["color"],
                              alpha=0.15, lw=0)  # fmt: skip
    ax_f.set_xlabel(f"{s['measure']}{unit}")
    ax_f.set_ylabel("probability of overturning")
    ax_f.set_ylim(-0.02, 1.02)
    ax_f.set_title(f"{_suite_label(study.config['suite'])}; bands: 90 % bootstrap over the motions", fontsize=9)
    ax_f.legend(fontsize=7, loc="upper left")
    over = a["damper_overturned"].astype(int)
    image = np.where(over == 1, 1, 0)
    ax_m.pcolormesh(_edges(a["levels"]), np.arange(over.shape[0] + 1) - 0.5, image,
                    cmap=ListedColormap(["#f7f7f7", "#b2182b"]), vmin=0, vmax=1, rasterized=True)  # fmt: skip
    rows = np.flatnonzero(a["damper_reversals"] > 0)
    ax_m.plot(np.full(rows.size, a["levels"][-1]), rows, "<", color="tab:blue", ms=5,
              label="non-monotone: overturns, then survives a higher level")  # fmt: skip
    ax_m.set_xlabel(f"{s['measure']}{unit}")
    ax_m.set_ylabel("motion")
    ax_m.set_title("with the damper: overturned (red) at each level", fontsize=9)
    if rows.size:
        ax_m.legend(fontsize=7, loc="lower right")
    title = "Incremental dynamic analysis" if study.kind == "ida" else "Fragility"
    fig.suptitle(f"{title}; {_damper_label(study.config)}\n{_directions_label(study.config)}")
    return fig


FIGURES = {
    "ida": ida_figure,
    "fragility": ida_figure,
    "map": map_figure,
    "spectrum": spectrum_figure,
    "optimize": optimize_figure,
    "design": design_figure,
    "threshold": threshold_figure,
}


def draw(study: Study, folder: str | Path, name: str | None = None) -> list[Path]:
    """Draw the figure of ``study`` as ``<folder>/<name>.png`` and ``.pdf`` (name: the study's kind)."""
    if study.kind not in FIGURES:
        raise ParameterError(f"no figure for a study of kind {study.kind!r} (known: {', '.join(FIGURES)})")
    fig = FIGURES[study.kind](study)
    FigureCanvasAgg(fig)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / f"{name or study.kind}.{ext}" for ext in ("png", "pdf")]
    for path in paths:
        try:
            fig.savefig(path, dpi=150)
        except OSError as exc:
            raise ParameterError(f"cannot write the figure {path} ({exc.strerror or exc})") from None
    return paths


#: What drawing a saved study whose data do not fit its figure raises: a missing array or
#: summary entry, an array of another shape or type.
UNFIT = (KeyError, IndexError, TypeError, ValueError, AttributeError)


def _redraw_one(stem: Path) -> list[Path]:
    """Draw the study saved at ``stem`` next to it; a ParameterError naming it if its data do not fit."""
    study = load(stem)
    try:
        return draw(study, stem.parent, stem.name)
    except ParameterError:
        raise
    except UNFIT as exc:  # the file passed load()'s checks but is not what this version of rocking writes
        text = str(exc).splitlines()[0] if str(exc) else ""
        raise ParameterError(
            f"{stem}.npz/.json: the saved {study.kind} cannot be drawn ({type(exc).__name__}: {text}); "
            "it lacks data its figure needs (saved by another version of rocking?)"
        ) from exc


def redraw(path: str | Path) -> list[Path]:
    """Redraw figures from saved data: one study (its ``.npz``, ``.json`` or stem) or every study in a folder.

    The figures are written next to the data, under the same stem.

    Raises
    ------
    ParameterError
        Naming the file: nothing saved at ``path``, a study that cannot be read
        (:func:`rocking.study.storage.load`) or drawn (data missing), or a
        figure that cannot be written.
    """
    path = Path(path)
    stems = (
        sorted(p.with_suffix("") for p in path.glob("*.json") if p.with_suffix(".npz").is_file())
        if path.is_dir()
        else [path]
    )
    if not stems:
        raise ParameterError(f"no saved study (<name>.npz with <name>.json) in {path}")
    written = []
    for stem in stems:
        written += _redraw_one(stem.with_suffix("") if stem.suffix in (".npz", ".json") else stem)
    return written
