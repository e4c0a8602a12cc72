"""Figures of the studies, drawn from saved data only.

Every figure is drawn from a :class:`rocking.study.config.Study` as
:func:`rocking.study.storage.load` reads it back, so :func:`redraw` re-renders a
figure from its ``.nc``/``.json`` without recomputing anything. Figures are
written as PNG (PDF or SVG on request: :data:`rocking.plot.FORMATS`) with matplotlib's Agg canvas (no pyplot,
no display); each figure function also draws in a figure (``fig=``) or axes (``ax=``) it is given, and returns
the figure, as pandas and xarray do.
A map's cells are an image (on a log axis, a rasterized mesh) and its hatches one region path per class,
rasterized: drawing a million cells costs about what 2,500 do, and a PDF is vector only in its axes and text.

Every title names the block (``H``, ``B``, ``M``, ``e`` in m and kg; ``alpha``, ``p``), the damper and the
pulses from the study's saved configuration, and the non-dimensional axes carry their dimensional
counterparts for that block (docs/model.md section 9): ``T_g = 2 pi / (Omega p)`` in s on top of an
``Omega`` axis, ``a_g / g = beta tan(alpha)`` beside a ``beta`` axis. Colours, hatches and markers are
those of :mod:`rocking.plot.style`; values the scan only bounds are open markers with an arrow, never
joined to measured values.

- map: outcome of the bare block and of the damped block over ``(Omega,
  beta)`` (safe / overturned without impact / after n impacts), and the
  damper's effect (cells saved, cells lost);
- spectrum: ``beta_min(Omega)`` with and without damper, the safe windows
  above it as bars, and the gain ``beta_min`` ratio;
- optimize: optimal ``T_m / T_g`` and ``T_m p / (2 pi)``, best gain with
  ``Omega*`` marked, and the gain landscape ``G(Omega, T_m)`` of the coarse scan;
- design: the design's gain over the band, the worst gain of the coarse search, the stroke it uses;
- threshold: per geometry ``(lambda, p)``, the best gain of each guide, from which ``Omega`` the block alone
  survives and ``Omega*`` (or its bound); and the best gain against ``Omega``;
- ida, fragility: the fraction of motions that overturn the block at each level with the fitted
  lognormal fragility, and the outcome of every motion with the damper.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import matplotlib.path as mpath
import numpy as np
from matplotlib import rc_context
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, PathPatch
from matplotlib.ticker import FuncFormatter, MaxNLocator

from ..model.loading import ModelError, saved_model
from ..model.motion import MavroeidisPapageorgiou, peak
from ..model.params import Block, ParameterError
from ..sim.problem import STATUS
from ..study.config import flight_beta
from ..study.design import VERDICTS, stroke_use, verdict
from ..study.files import DiskFull, atomic_write, name_lock
from ..study.fragility import FITTED, MEDIAN_PLACES
from ..study.friction_map import envelope as friction_envelope
from ..study.ida import LEVELS
from ..study.ida import envelope as ida_envelope
from ..study.kinds import KINDS
from ..study.overturning_map import PARTS, envelope, half_stroke, saved_past_edges
from ..study.result import Study
from ..study.spectrum import beta_min_or_bound, safe_windows
from ..study.spectrum import envelope as spectrum_envelope
from ..study.storage import load, study_stem
from ..study.suite import motion_names
from ..study.threshold import thresholds
from ..study.vocabulary import ABOVE, BELOW, BRACKETED, FIT_STATUSES, REGIMES, SLIDES, SLIDES_AND_ROCKS, regime_label
from ..study.vocabulary import THRESHOLD_STATUSES as STATUSES
from . import DEFAULT_FORMATS, check_formats
from .style import (
    CHAR_EM,
    DIVERGING,
    GREY,
    LIGHT,
    MEASURE_NAMES,
    OKABE_ITO,
    PART_STYLE,
    PULSE_NAMES,
    UNIT_TEXT,
    broken,
    cycle,
    extend,
    fit,
    quantity,
    symbol,
    visible,
)

#: Colour and hatch of each regime of a response on a floor with friction (rocking.study.vocabulary.REGIMES), in
#: the order of their codes: the regime map's classes, and the map's where the base slid.
REGIME_STYLE = (
    (LIGHT, ""),
    (OKABE_ITO["yellow"], ""),
    (OKABE_ITO["bluish green"], ""),
    (OKABE_ITO["sky blue"], "++"),
    (OKABE_ITO["vermillion"], ""),
)
#: The regime map's classes: label, colour and hatch by regime code.
REGIME_CLASSES = tuple((regime_label(code), *REGIME_STYLE[code]) for code in REGIMES)
#: Outcome classes of a map cell: label, colour and hatch; the class is min(outcome + 1, 4), or 5 where the cell
#: did not overturn and a run ended in flight (a model without flight functions) or jammed at a landing, or on a
#: floor with friction 6 or 7 where it did not overturn and the base slid (:data:`MAP_SLID_CLASSES`), or with a
#: vertical component 8 or 9 where the governing response flew and landed, or flew and overturned
#: (:data:`MAP_FLEW_CLASSES`, docs/model.md section 16).
OUTCOME_CLASSES = (
    ("safe", LIGHT, ""),
    ("overturned, no impact", OKABE_ITO["vermillion"], ""),
    ("overturned after 1 impact", OKABE_ITO["orange"], "//"),
    ("after 2 impacts", OKABE_ITO["yellow"], ".."),
    ("after 3 or more impacts", OKABE_ITO["reddish purple"], "xx"),
    ("no verdict: a run ended in flight or jammed at a landing", GREY, "\\\\"),
    *(("not overturned, " + regime_label(code), *REGIME_STYLE[code]) for code in (SLIDES, SLIDES_AND_ROCKS)),
    ("flies and lands, not overturned", OKABE_ITO["blue"], "oo"),
    ("flies and overturns", OKABE_ITO["black"], "oo"),
)
#: The outcome class of a map's cell whose governing response flew: landed without overturning, overturned.
MAP_FLEW_CLASSES = {False: 8, True: 9}
#: The outcome class of a map's cell that did not overturn, by the regime in which its base slid.
MAP_SLID_CLASSES = {SLIDES: 6, SLIDES_AND_ROCKS: 7}
#: Effect classes: bare overturned + 2 x damped overturned, 4 for cells saved only with the
#: damper's mass past the block's edge (rocking.study.overturning_map.saved_past_edges), 5 for saved
#: cells whose damped response an adaptive map did not compute (its stroke is not known), and 6 for cells
#: where a part that did not overturn ended in flight or jammed at a landing (no verdict, docs/model.md sections
#: 14, 16).
EFFECT_CLASSES = (
    ("safe either way", LIGHT, ""),
    ("saved by the damper", OKABE_ITO["blue"], ""),
    ("lost with the damper", OKABE_ITO["vermillion"], "xx"),
    ("overturned either way", GREY, ""),
    ("saved only with the mass past the edge (x_max > B/2)", OKABE_ITO["sky blue"], "//"),
    # Saved as the class above (its blue), told apart by a hatch no outcome class has: yellow dots read as the
    # outcome "after 2 impacts" of the panels beside it.
    ("saved by the damper, stroke not computed (an adaptive map's cell filled in)", OKABE_ITO["blue"], "--"),
    ("no verdict: a run ended in flight or jammed at a landing", OKABE_ITO["reddish purple"], "\\\\"),
)
#: Colour of the hatches over the classes' colours.
HATCH_COLOUR = "#333333"
#: Legends go below their axes (never over the data), in this font size.
LEGEND = {"fontsize": 7, "frameon": False}
#: Colour bars of a gain centre on 1 and span its data, up to this factor either way (beyond: an extension).
GAIN_SPAN = 10.0


def _edges(centres: np.ndarray, log: bool = False) -> np.ndarray:
    """Cell edges around grid points (mid-points; half a step beyond the ends), in log scale if ``log``."""
    c = np.asarray(centres, float)
    if log:
        return np.exp(_edges(np.log(c)))
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    # A grid of positive values (Omega, beta: a pulse's frequency and amplitude) ends at 0, not half a step past.
    first = max(2 * c[0] - mid[0], 0.0) if c[0] > 0 else 2 * c[0] - mid[0]
    return np.concatenate([[first], mid, [2 * c[-1] - mid[-1]]])


def _legend_below(ax, handles=None, ncols: int = 2) -> None:
    """A legend under ``ax`` (below its axis label), so that it covers no data: no wider than its panel (fewer
    columns, long entries broken between words), so that a narrow figure does not cut it."""
    handles = ax.get_legend_handles_labels()[0] if handles is None else handles
    labels = [h.get_label() for h in handles]
    # The panel's share of the figure's width (its position before the layout is narrower than it will be).
    spec = ax.get_subplotspec()
    share = len(spec.colspan) / spec.get_gridspec().ncols if spec is not None else ax.get_position().width
    inches = share * ax.get_figure(root=True).get_figwidth()
    # Each entry's handle and padding take about 4 characters.
    room = max(int(inches * 72 / (CHAR_EM * LEGEND["fontsize"])), 24)
    longest = max((max(map(visible, label.split("\n"))) + 4 for label in labels), default=1)
    ncols = max(1, min(ncols, room // longest))
    width = max(room // ncols - 4, 20)
    labels = [broken(label, width, " ") for label in labels]
    ax.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=ncols, **LEGEND)


def _runs(mask: np.ndarray) -> np.ndarray:
    """The cells of a boolean ``(x, y)`` grid as few rectangles of cell indices ``(i0, i1, j0, j1)`` (ends
    exclusive): runs along ``x`` in each row, joined along ``y`` where consecutive rows hold the same run."""
    padded = np.pad(mask.T.astype(np.int8), ((0, 0), (1, 1)))
    step = np.diff(padded, axis=1)
    j, i0 = np.nonzero(step == 1)
    i1 = np.nonzero(step == -1)[1]  # row by row, each end follows its start
    order = np.lexsort((j, i1, i0))
    j, i0, i1 = j[order], i0[order], i1[order]
    # A new rectangle wherever the run changes or its row does not follow the one before.
    new = np.ones(j.size, bool)
    new[1:] = (i0[1:] != i0[:-1]) | (i1[1:] != i1[:-1]) | (j[1:] != j[:-1] + 1)
    first = np.flatnonzero(new)
    last = np.append(first[1:], j.size) - 1
    return np.c_[i0[first], i1[first], j[first], j[last] + 1]


def _region(x: np.ndarray, y: np.ndarray, mask: np.ndarray) -> mpath.Path:
    """One compound path of the cells of ``mask`` on the cell edges ``x``, ``y``: a class's region, drawn (and
    hatched) as one artist however many cells it holds."""
    i0, i1, j0, j1 = _runs(mask).T
    corners = np.stack([np.c_[x[i0], y[j0]], np.c_[x[i1], y[j0]], np.c_[x[i1], y[j1]], np.c_[x[i0], y[j1]]], 1)
    vertices = np.concatenate([corners, corners[:, :1]], axis=1).reshape(-1, 2)
    codes = np.tile([mpath.Path.MOVETO] + 3 * [mpath.Path.LINETO] + [mpath.Path.CLOSEPOLY], i0.size)
    return mpath.Path(vertices, codes)


def _classes(ax, Omega, beta, classes: np.ndarray, palette, xlog: bool = False) -> list[Patch]:
    """Draw integer classes on the (Omega, beta) plane in colour and hatch (cells centred in log scale along
    ``Omega`` if ``xlog``); the legend's handles of the classes present, in the palette's order.

    The colours are one raster mesh and each hatch one region path, both rasterized: the cost of drawing, and the
    size of a PDF, do not grow with the number of cells (the axes and the text stay vector).
    """
    x, y = _edges(Omega, xlog), _edges(beta)
    cmap = ListedColormap([c for _, c, _ in palette])
    norm = BoundaryNorm(np.arange(len(palette) + 1) - 0.5, cmap.N)
    if xlog:  # an image is resampled evenly in data terms: on a log axis, a mesh (IDA's levels, a few)
        ax.pcolormesh(x, y, classes.T, cmap=cmap, norm=norm, shading="flat", rasterized=True)
    else:
        ax.pcolorfast(x, y, classes.T, cmap=cmap, norm=norm)
    present = np.unique(classes)
    for k, (_, _, hatch) in enumerate(palette):
        if hatch and k in present:
            region = PathPatch(_region(x, y, classes == k), facecolor="none", edgecolor=HATCH_COLOUR, hatch=hatch, lw=0)
            region.set_rasterized(True)
            # As an artist, not a patch: the image already sets the limits, and a patch's would be found
            # by walking every one of its segments.
            ax.add_artist(region)
    return [
        Patch(facecolor=c, edgecolor=HATCH_COLOUR, hatch=h, lw=0.5, label=label)
        for k, (label, c, h) in enumerate(palette)
        if k in present
    ]


def _block(config: dict) -> Block:
    """The block of a study's configuration (:meth:`rocking.study.config.Setting.record`)."""
    return Block(**config["block"])


def _block_label(block: Block) -> str:
    """The block for a title: its dimensions and mass, and the ``alpha`` and ``p`` of the non-dimensional axes."""
    e = f", e = {quantity(block.e, 'm', 3)}" if block.e else ""
    return (
        f"block H = {quantity(block.H, 'm')}, B = {quantity(block.B, 'm')}, M = {quantity(block.M, 'kg')}{e} "
        rf"($\alpha$ = {block.alpha:.3g} rad, p = {block.p:.3g} rad/s)"
    )


def _parameter_units(model: str) -> dict:
    """Unit of each parameter of a generated model by name (none if the model cannot be loaded here)."""
    try:
        found = saved_model(model, "the study's configuration: damper.model")
        return {p["name"]: p["unit"] for p in found.manifest["parameters"]}
    except ModelError:
        return {}


def _stops_label(block: Block, record: dict) -> str:
    L = half_stroke(block, record)
    return "unlimited guide" if L is None else f"stops at L = {L:.3g} m"


#: Most characters of a text read from a saved study (a model's name or folder) that a title shows.
SAVED_TEXT_CHARS = 60


def _saved_text(text: str) -> str:
    """A text read from a saved study as a title shows it: at most :data:`SAVED_TEXT_CHARS` characters (a longer one
    keeps its end: a folder's name), every ``$`` escaped, so that mathtext never parses it."""
    if len(text) > SAVED_TEXT_CHARS:
        text = "..." + text[3 - SAVED_TEXT_CHARS :]
    return text.replace("$", r"\$")


def _damper_label(config: dict) -> str:
    """The damper of a study for a title: the omd tuning, or a variant's model name and parameters with units."""
    d, block = config["damper"], _block(config)
    if "model" in d:
        units = _parameter_units(d["model"])
        params = ", ".join(
            f"{symbol(_saved_text(k))} = {quantity(v, units.get(k, ''))}" for k, v in d["params"].items()
        )
        return f"damper: model {_saved_text(d['model'])}" + (f" ({params})" if params else "")
    T_m = 2 * np.pi / (d["omega_ratio"] * block.p)
    return (
        rf"damper $\gamma$ = {d['gamma']:g}, $\omega_m / p$ = {d['omega_ratio']:.3g} ($T_m$ = {T_m:.3g} s), "
        rf"$\zeta$ = {d['zeta']:g}, h = {d['h']:g} m, {_stops_label(block, d)}"
    )


def _pulse_label(config: dict) -> str:
    """The pulse family of a study for a title (the one-sine when the configuration names none)."""
    pulse = config.get("pulse", {"motion": "sine"})
    shape = (
        rf" ($\gamma_{{MP}}$ = {pulse['gamma_mp']:g}, $\nu$ = {pulse['nu']:g} rad)" if pulse["motion"] == "mp" else ""
    )
    return PULSE_NAMES[pulse["motion"]] + shape + _vertical_label(config)


def _vertical_label(config: dict) -> str:
    """The pulses' vertical component for a title (docs/model.md section 14); nothing without one."""
    vertical = config.get("vertical", {})
    if not vertical:
        return ""
    lead = rf" + {vertical['phase']:.3g}/\omega_g" if vertical["phase"] else ""
    return rf", vertical $\ddot y_g$ = {vertical['ratio']:g} $a_g f(t{lead})$ (> 0 up, either direction)"


def _flight_line(ax, config: dict, beta_high: float) -> list[Line2D]:
    """The amplitude above which ``g + ddy_g`` reaches 0 (the base may fly: a flight model follows it, a model
    without flight functions ends with the status flight, no verdict), as a dashed line when it lies below
    ``beta_high``; its legend handle, or none."""
    beta_f = flight_beta(_block(config), config)
    if not beta_f < beta_high:
        return []
    label = rf"$\beta$ = {beta_f:.3g}: above, g + $\ddot y_g$ reaches 0 (the base may fly)"
    return [ax.axhline(beta_f, color=GREY, ls="--", lw=1.2, zorder=5, label=label)]


def _excitation_label(config: dict) -> str:
    """The pulses of a study in dimensional terms for its block: amplitude in g, period in s."""
    block = _block(config)
    ratio = _peak_ratio(config)
    amplitude = (
        rf"$a_g = A \omega_g$ = {block.tan_alpha:.3g} $\beta$ g (peak {ratio:.3g} $a_g$)"
        if ratio != 1.0
        else (rf"$a_g$ = {block.tan_alpha:.3g} $\beta$ g")
    )
    return (
        rf"{_pulse_label(config)}: {amplitude}, "
        rf"$T_g = 2\pi / \omega_g$ = {2 * np.pi / block.p:.3g} s / $\Omega$; "
        f"{_directions_label(config)}"
    )


def _title(fig, what: str, config: dict, extra: str = "", damper: str | None = None) -> None:
    """The figure's title: what it shows, the pulses, the block and the damper of ``config`` (or ``damper``)."""
    damper = _damper_label(config) if damper is None else damper
    block = _block_label(_block(config)) + _floor_label(config)
    _suptitle(fig, f"{what}: {_excitation_label(config)}{extra}\n{block}\n{damper}")


def _floor_label(config: dict) -> str:
    """A study's floor with friction (docs/model.md section 15) and its landings' restitution where they bounce
    (section 16) for a title; nothing for the paper's."""
    floor = config.get("floor", {})
    friction = rf"; floor $\mu_s$ = {floor['mu_s']:g}, $\mu_k$ = {floor['mu_k']:g}" if "mu_s" in floor else ""
    return friction + (f"; landings e_n = {floor['e_n']:g}" if floor.get("e_n") else "")


def _suptitle(fig, text: str, fontsize: float = 10) -> None:
    """The figure's title, its long lines broken to fit the figure's width (:func:`~rocking.plot.style.fit`)."""
    fig.suptitle(fit(text, fig.bbox.width / fig.dpi, fontsize), fontsize=fontsize)


def _suite_label(suite: dict) -> str:
    """The motions of an IDA or fragility study (:meth:`rocking.study.suite.Suite.record`) for a title."""
    if "files" in suite:
        n = len(suite["files"])
        if "vertical" in suite:
            return "1 record with its vertical record" if n == 1 else f"{n} records with their vertical records"
        return "1 record" if n == 1 else f"{n} records"
    if "pulses" in suite:
        pulses = suite["pulses"]
        families = sorted({PULSE_NAMES[p["family"]] for p in pulses})
        periods = [p["T_g"] for p in pulses]
        return f"{len(pulses)} pulses ({', '.join(families)}), $T_g$ {min(periods):.3g} to {max(periods):.3g} s"
    return f"{suite['n']} stochastic motions (seed {suite['seed']})"


def _directions_label(config: dict, what: str = "pulses") -> str:
    """The directions of a study's ``what`` (pulses, motions) for a title: both (the envelope shown) or one sign."""
    chosen = config.get("directions", {"directions": "positive", "signs": [1]})  # studies before format 4
    if len(chosen["signs"]) > 1:
        return f"{what} of both signs, the worse shown"
    mirrored = " (symmetric: the other sign mirrors them)" if chosen["directions"] == "auto" else ""
    return f"{'positive' if chosen['signs'][0] > 0 else 'negative'} {what}{mirrored}"


#: Tick values of a period axis (s): these mantissas in every decade, the roundest first (a tick is kept only
#: where it does not crowd those before it).
PERIOD_TICKS = np.array([m * 10.0**k for m in (1, 2, 5, 3, 1.5, 7) for k in range(-3, 4)])
#: Least distance between two period ticks, and from the axis' left end: inches, and a share of the axis.
TICK_GAP = (0.45, 0.08)


def _period_axis(ax, p: float) -> None:
    """A top axis of the pulse period ``T_g = 2 pi / (Omega p)``, s, over an ``Omega`` axis (call it once the
    axis has its limits: its ticks are round periods :data:`TICK_GAP` apart and from its left end)."""

    def period(x):  # its own inverse; Omega <= 0 lies off every axis drawn
        return 2 * np.pi / (p * np.maximum(np.asarray(x, float), 1e-9))

    low, high = sorted(ax.get_xlim())
    # The panel's share of the figure's width (its position before the layout is narrower than it will be).
    spec = ax.get_subplotspec()
    share = len(spec.colspan) / spec.get_gridspec().ncols if spec is not None else ax.get_position().width
    inches = share * ax.get_figure(root=True).get_figwidth()
    gap = (high - low) * max(TICK_GAP[0] / inches, TICK_GAP[1])
    # The periods crowd where Omega is small, and grow without bound towards an axis that starts at Omega = 0:
    # the left end counts as a tick.
    kept = {low: None}
    for T in PERIOD_TICKS:
        where = float(period(T))
        if low <= where <= high and all(abs(where - w) >= gap for w in kept):
            kept[where] = float(T)
    ticks = sorted(T for T in kept.values() if T is not None)
    axis = ax.secondary_xaxis("top", functions=(period, period))
    axis.set_xticks(ticks, [f"{T:g}" for T in ticks])
    axis.set_xlabel(r"$T_g = 2\pi / \omega_g$ (s)")


def _peak_ratio(config: dict) -> float:
    """The peak ground acceleration of a study's pulses over their amplitude ``a_g`` (``beta g tan(alpha)``): 1, but
    for a Mavroeidis-Papageorgiou pulse, whose ``a_g = A omega_g`` is not its peak (0.906 of it at ``gamma_MP`` = 2,
    ``nu`` = 0; :func:`rocking.model.motion.peak`, independent of ``omega_g``)."""
    pulse = config.get("pulse", {"motion": "sine"})
    if pulse["motion"] != "mp":
        return 1.0
    return peak(MavroeidisPapageorgiou(1.0, 1.0, pulse["gamma_mp"], pulse["nu"]))


def _acceleration_axis(ax, config: dict) -> None:
    """A right axis of the pulses' peak ground acceleration in g over a ``beta`` axis: ``a_g / g = beta tan(alpha)``
    times :func:`_peak_ratio` (the amplitude itself but for a Mavroeidis-Papageorgiou pulse)."""
    scale = _block(config).tan_alpha * _peak_ratio(config)
    axis = ax.secondary_yaxis("right", functions=(lambda b: b * scale, lambda a: a / scale))
    axis.set_ylabel(r"peak ground acceleration (g)" if _peak_ratio(config) != 1.0 else r"$a_g$ (g)")


def _omega_axis(ax, label: str = r"$\Omega = \omega_g / p$") -> None:
    ax.set_xlabel(label)


def _beta_axis(ax) -> None:
    ax.set_ylabel(r"$\beta = a_g / (g \tan\alpha)$")


#: Legend of the bounds of :func:`_bounds`.
LOWER_BOUND = r"lower bound (no overturning up to the last $\beta$ scanned)"
UPPER_BOUND = r"upper bound (overturns at the first $\beta$ scanned)"


def _bounds(ax, x, y, arrow: float, color, up: bool, label=None, face: str = "white") -> None:
    """Values the scan only bounds: open triangles (or of the colour ``face``) with an arrow of length ``arrow``
    towards the unknown value, not joined to the measured values."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    keep = np.isfinite(y)
    if keep.any():
        ax.errorbar(
            x[keep],
            y[keep],
            yerr=arrow,
            lolims=up,
            uplims=not up,
            fmt="^" if up else "v",
            ms=6,
            mfc=face,
            color=color,
            ls="none",
            capsize=3,
            elinewidth=1,
            zorder=5,
            label=label,
        )


def _gain_curve(ax, Omega, gain, flag, style: dict, label, dodge: float = 0.0) -> bool:
    """A gain curve: measured values joined, lower bounds (the damped block did not overturn in the scan) as open
    triangles with arrows, moved ``dodge`` along ``Omega`` (curves of a set bound at the same pulses); True if any
    bound is drawn."""
    bound = flag == ABOVE
    ax.plot(Omega, np.where(bound, np.nan, gain), ms=4, label=label, zorder=4, **{"ls": "-", **style})
    arrow = 0.06 * max(np.nanmax(gain, initial=1.0), 1.0)
    _bounds(ax, Omega[bound] + dodge, gain[bound], arrow, style["color"], up=True)
    return bool(np.isfinite(gain[bound]).any())


def _bound_handle(up: bool = True) -> Line2D:
    """Legend entry of :func:`_bounds` (in grey: it stands for every colour)."""
    return Line2D(
        [], [], ls="none", marker="^" if up else "v", mfc="white", color="0.3", label=LOWER_BOUND if up else UPPER_BOUND
    )


def _gain_norm(values) -> tuple[LogNorm, str]:
    """A logarithmic colour scale of a gain centred on 1 that spans the finite ``values`` (at most
    :data:`GAIN_SPAN` either way), and the colour bar's ``extend`` for values beyond it."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v) & (v > 0)]
    # The bounds are the data's own extremes where they set the span, not exp(log(.)) round trips, which may
    # land a last bit inside them (by CPU) and mark the bar as extended past a value it holds.
    top = float(np.clip(max(v.max(), 1 / v.min()), 1.1, GAIN_SPAN)) if v.size else GAIN_SPAN
    low = min(1 / top, v.min()) if v.size and v.min() * top >= 1 - 1e-12 else 1 / top
    norm = LogNorm(low, top)
    return norm, extend(v, norm.vmin, norm.vmax)


def _gain_colorbar(fig, image, ax, label: str, extension: str) -> None:
    """The colour bar of a gain map: ticks at round ratios, extended where values pass its range."""
    bar = fig.colorbar(image, ax=ax, label=label, extend=extension)
    low, high = image.norm.vmin, image.norm.vmax
    ticks = []
    # Coarse ratios first: a finer one only where it does not crowd them (at least 12 % of the bar apart).
    for t in (1.0, 0.5, 2.0, 0.2, 5.0, 0.1, 10.0, 0.8, 1.25, 0.9, 1.1, 0.95, 1.05):
        if low <= t <= high and all(abs(np.log(t / u)) >= 0.12 * np.log(high / low) for u in ticks):
            ticks.append(t)
    bar.set_ticks(ticks, labels=[f"{t:g}" for t in ticks])
    bar.minorticks_off()


def _plain_ticks(axis) -> None:
    """Tick labels of a logarithmic axis as plain numbers (0.5, 2, 10), not powers of ten."""

    def minor(v, _):  # every one within a decade, 2, 3 and 5 within two, else none
        low, high = sorted(axis.get_view_interval())
        mantissa = round(v / 10 ** np.floor(np.log10(v)), 6)
        return f"{v:g}" if high < 10 * low or (high < 100 * low and mantissa in (2, 3, 5)) else ""

    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(FuncFormatter(minor))


def _panels(size: tuple, shape: tuple, fig=None, ax=None, **grid) -> tuple:
    """The figure and the ``shape`` panels a figure function draws in: the axes ``ax`` given (as many as its
    panels, in reading order), or new ones in the figure ``fig`` given, or in a new figure of ``size`` (inches).

    Raises
    ------
    ParameterError
        ``ax`` and ``fig`` both given, or ``ax`` not one axes per panel.
    """
    if ax is not None:
        if fig is not None:
            raise ParameterError("give ax= or fig=, not both (ax= draws in the figure of its axes)")
        axes = np.asarray(ax, dtype=object).ravel()
        if axes.size != np.prod(shape):
            raise ParameterError(f"ax= needs {np.prod(shape)} axes for this figure's panels, got {axes.size}")
        root = axes[0].get_figure(root=True)
        if root.get_layout_engine() is None:
            # Axes laid out by hand or by default leave no room for the title above them and the legends below:
            # a constrained layout makes it (a layout the user chose is kept).
            root.set_layout_engine("constrained")
        return axes[0].get_figure(), axes.reshape(shape)
    fig = Figure(figsize=size, layout="constrained") if fig is None else fig
    return fig, np.asarray(fig.subplots(*shape, squeeze=False, **grid), dtype=object).reshape(shape)


#: The parameters and the result of every figure function, in its docstring (:func:`_figure_function`).
PARAMETERS = """

    Parameters
    ----------
    study : Study
        The study, as it ran or as :func:`rocking.study.storage.load` reads it back.
    fig : Figure, optional
        A figure to draw in (a ``matplotlib.pyplot`` figure in a notebook, a subfigure); default a new one.
    ax : sequence of Axes, optional
        Axes to draw in instead, one per panel in reading order (their figure takes the title and legends; a
        figure without a layout engine is given a constrained layout, which makes room for them).

    Returns
    -------
    Figure
        The figure drawn in (a new one is not attached to a canvas: :func:`draw` saves it).
"""


def _figure_function(function):
    """A figure function with its parameters (:data:`PARAMETERS`) in its docstring."""
    function.__doc__ = function.__doc__.rstrip() + PARAMETERS
    return function


@_figure_function
def map_figure(study: Study, *, fig: Figure | None = None, ax=None) -> Figure:
    """Outcome maps of the bare and the damped block, and the damper's effect."""
    data, block = study.data, _block(study.config)
    env = envelope(data)
    Om, beta = data["Omega"].values, data["beta"].values
    over, impacts = ({part: env[k].sel(part=part).values for part in PARTS} for k in ("overturned", "impacts"))
    # Cells that did not overturn in either direction but ended in flight in one, on a model without flight
    # functions, or jammed at a landing: no verdict (docs/model.md sections 14, 16).
    ended = [STATUS.index("flight"), STATUS.index("jammed")]
    flew = {part: data["status"].sel(part=part).isin(ended).any("sign").values & ~over[part] for part in PARTS}
    fig, (axes,) = _panels((15, 6.2), (1, 3), fig, ax, sharex=True, sharey=True)
    cls = {part: _outcome_classes(env, part, over[part], impacts[part], flew[part]) for part in PARTS}
    for ax, part in zip(axes, PARTS):
        handles = _classes(ax, Om, beta, cls[part], OUTCOME_CLASSES)
        ax.set_title(PART_STYLE[part]["label"])
    # One legend of the outcomes, as wide as both outcome panels: the same classes, the same colours.
    present = {h.get_label(): h for h in handles}
    for label, c, h in (OUTCOME_CLASSES[k] for k in np.unique(cls["bare"])):
        present.setdefault(label, Patch(facecolor=c, edgecolor=HATCH_COLOUR, hatch=h, lw=0.5, label=label))
    order = [label for label, _, _ in OUTCOME_CLASSES if label in present]
    flight = [line for ax in axes for line in _flight_line(ax, study.config, float(beta[-1]))][:1]
    fig.legend(handles=[present[label] for label in order] + flight, loc="outside lower left", ncols=3, **LEGEND)
    effect = over["bare"].astype(int) + 2 * over["damper"].astype(int)
    past = saved_past_edges(env, block.B / 2)
    unknown = (effect == 1) & ~data["computed"].sel(part="damper").values
    no_verdict = flew["bare"] | flew["damper"]
    handles = _classes(axes[2], Om, beta, np.select([past, unknown, no_verdict], [4, 5, 6], effect), EFFECT_CLASSES)
    fig.legend(handles=handles, loc="outside lower right", ncols=2, **LEGEND)
    s = study.summary
    axes[2].set_title(
        f"effect of the damper: {_cells(s.get('saved', 0))} saved\n({int(past.sum())} only past the edge"
        + (f", {int(unknown.sum())} of unknown stroke" if unknown.any() else "")
        + f"), {s.get('lost', 0)} lost",
        fontsize=9,
    )
    for ax in axes:
        _omega_axis(ax)
        _period_axis(ax, block.p)
    _beta_axis(axes[0])
    _acceleration_axis(axes[2], study.config)
    _title(fig, "Overturning map", study.config, _refinement_label(study))
    return fig


def _outcome_classes(env, part: str, over, impacts, flew) -> np.ndarray:
    """The :data:`OUTCOME_CLASSES` of a part's cells (``env``: the map's envelope): overturned after so many
    impacts, ended in flight without a verdict, or on a floor with friction slid without overturning
    (:data:`MAP_SLID_CLASSES`), else safe; with a vertical component a cell whose governing response flew is
    :data:`MAP_FLEW_CLASSES`."""
    safe = np.zeros(over.shape, int)
    if "regime" in env:
        regime = env["regime"].sel(part=part).values
        for code, k in MAP_SLID_CLASSES.items():
            safe[regime == code] = k
    classes = np.where(over, np.minimum(impacts + 1, 4), np.where(flew, 5, safe))
    if "flew" in env:  # a vertical component: the governing response flew, and landed or overturned
        landed = (env["flew"].sel(part=part).values == 1) & ~flew
        classes = np.where(landed, np.where(over, MAP_FLEW_CLASSES[True], MAP_FLEW_CLASSES[False]), classes)
    return classes


@_figure_function
def friction_figure(study: Study, *, fig: Figure | None = None, ax=None) -> Figure:
    """The regime map over floors and amplitudes at one pulse frequency: rest, rocks, slides, slides and rocks,
    overturns (both directions of each pulse together), with Shenton's boundary ``mu = B/H`` between sliding and
    rocking first and the floor's static hold ``a_g = mu g``."""
    data, config = study.data, study.config
    block = _block(config)
    env = friction_envelope(data)
    mu, beta = data["mu"].values, data["beta"].values
    fig, ((axis,),) = _panels((7.5, 6.4), (1, 1), fig, ax)
    handles = _classes(axis, mu, beta, env["regime"].values, REGIME_CLASSES)
    ratio = block.B / block.H
    line = axis.axvline(
        ratio, color=OKABE_ITO["black"], lw=1.4, zorder=5, label=f"$\\mu = B/H$ = {ratio:.3g} (Shenton)"
    )
    axis.annotate(
        "slides first | rocks first",
        (ratio, 0.98),
        xycoords=("data", "axes fraction"),
        ha="center",
        va="top",
        fontsize=8,
        bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 1.5},
    )
    low, high = axis.get_xlim()
    x = np.linspace(low, high, 50)
    hold = axis.plot(
        x,
        x / block.tan_alpha,
        color=OKABE_ITO["black"],
        ls=":",
        lw=1.2,
        label=r"$a_g = \mu g$ (the floor's static hold)",
    )
    axis.set_ylim(*_edges(beta)[[0, -1]])
    axis.set_xlabel(r"$\mu = \mu_s = \mu_k$ (floor's Coulomb friction)")
    _beta_axis(axis)
    _acceleration_axis(axis, config)
    _legend_below(axis, [*handles, line, *hold], ncols=2)
    frequency = f"$\\Omega$ = {data.attrs['Omega']:.3g} ($T_g$ = {data.attrs['T_g']:.3g} s)"
    damper = _damper_label(config) if "damper" in config else "block alone"
    _suptitle(
        fig,
        f"Regime map: {_pulse_label(config)}, {frequency}\n{_directions_label(config)}\n"
        f"{_block_label(block)}\n{damper}",
    )
    return fig


def _cells(n: int) -> str:
    """A count of map cells in words: "1 cell", "12 cells"."""
    return f"{n} cell" if n == 1 else f"{n} cells"


def _refinement_label(study: Study) -> str:
    """How many cells an adaptive map computed, for a title; nothing for a full map."""
    refinement = study.config.get("refinement", {"adaptive": False})
    if not refinement["adaptive"]:
        return ""
    computed = study.data["computed"]
    cells = computed.sel(part="bare").size
    counts = ", ".join(f"{int(computed.sel(part=part).sum())}" for part in PARTS)
    note = study.summary.get("guarantee", "")
    return (
        f"\nadaptive, coarse step {refinement['coarse']}: {counts} of {cells} cells computed (alone, damped), "
        f"the others take the outcome around them\n{note}"
    )


#: Hatches of the safe windows of a spectrum, by part.
WINDOW_HATCH = {"bare": "\\\\\\", "damper": "///"}


@_figure_function
def spectrum_figure(study: Study, *, fig: Figure | None = None, ax=None) -> Figure:
    """``beta_min(Omega)`` with and without damper, windows as bars; gain of the damper."""
    env, block = spectrum_envelope(study.data), _block(study.config)
    a = {k: {part: env[k].sel(part=part).values for part in PARTS} for k in ("flag", "beta_min")}
    # A beta_min not reached in the scan is censored (NaN): its lower bound is drawn as one, never on the curve.
    a["beta_min"] = {part: beta_min_or_bound(env.sel(part=part)) for part in PARTS}
    Om = env["Omega"].values
    step = np.diff(Om).min() if Om.size > 1 else 1.0
    scan = study.config["beta"]
    arrow = 0.05 * (scan["high"] - scan["low"]) if scan["n"] > 1 else 0.05 * scan["high"]
    fig, ((ax, ax_gain),) = _panels((13, 6.4), (1, 2), fig, ax, width_ratios=(2, 1))
    # The damped block's markers are larger, drawn under the bare block's: both stay visible where the two
    # coincide (below the damper's frequency range they often do).
    for shift, part, z in zip((-0.15, 0.15), ("bare", "damper"), (4, 3)):
        style = PART_STYLE[part]
        flag, bm = a["flag"][part], a["beta_min"][part]
        ax.plot(
            Om,
            np.where(flag == BRACKETED, bm, np.nan),
            "-",
            color=style["color"],
            marker=style["marker"],
            ms=4 if part == "bare" else 6.5,
            zorder=z,
            label=rf"$\beta_{{min}}$, {style['label']}",
        )
        for code, up in ((ABOVE, True), (BELOW, False)):
            sel = flag == code
            # Both parts are bounded by the same scan's ends: side by side, neither hides the other.
            _bounds(ax, Om[sel] + 1.5 * shift * step, bm[sel], arrow, style["color"], up)
        w = safe_windows(env, part)
        if len(w):
            ax.bar(
                w[:, 0] + shift * step,
                w[:, 2] - w[:, 1],
                bottom=w[:, 1],
                width=0.25 * step,
                color=style["color"],
                alpha=0.35,
                edgecolor=style["color"],
                hatch=WINDOW_HATCH[part],
                lw=1,
                zorder=2,
                label="safe window above " + rf"$\beta_{{min}}$, {style['label']}",
            )
    _omega_axis(ax)
    _beta_axis(ax)
    _period_axis(ax, block.p)
    _acceleration_axis(ax, study.config)
    ax.set_title("minimum overturning amplitude", fontsize=9)
    handles = ax.get_legend_handles_labels()[0] + _flight_line(ax, study.config, scan["high"])
    for code, up in ((ABOVE, True), (BELOW, False)):
        if any((a["flag"][part] == code).any() for part in PARTS):
            handles.append(_bound_handle(up))
    both = (a["flag"]["bare"] == BRACKETED) & (a["flag"]["damper"] != BELOW)
    gain = np.where(both, a["beta_min"]["damper"] / a["beta_min"]["bare"], np.nan)
    style = PART_STYLE["damper"]
    _gain_curve(ax_gain, Om, gain, a["flag"]["damper"], {"color": style["color"], "marker": style["marker"]}, None)
    ax_gain.axhline(1.0, color=GREY, lw=0.8)
    _omega_axis(ax_gain)
    _period_axis(ax_gain, block.p)
    ax_gain.set_ylabel(r"$G = \beta_{min}$(damper) / $\beta_{min}$(block)")
    ax_gain.set_title("gain of the damper", fontsize=9)
    fig.legend(handles=handles, loc="outside lower center", ncols=3, **LEGEND)
    _title(fig, "Minimum overturning spectrum", study.config)
    return fig


def vertical_spectra_figure(studies, *, fig: Figure | None = None, ax=None) -> Figure:
    """``beta_min(Omega)`` of spectra that differ only in their pulses' vertical ratio (docs/model.md section 14),
    one panel per direction: the block alone dashed, with its damper solid, a colour per ratio; each ratio's
    ``beta_f`` (above it the ground pulls past gravity: the base may fly) dotted in its colour.

    The bracketed ``beta_min`` are joined, ringed where the response that overturns there flew first (flies and
    overturns, docs/model.md section 16); where the scan found no overturning up to its last amplitude, or, on a
    model without flight functions, up to the one before its first flight (past ``beta_f`` such a run ends in
    flight, no verdict), that amplitude is an open triangle pointing up (a lower bound), and where it overturned
    at its first amplitude, one pointing down.
    """
    studies = sorted(studies, key=lambda st: st.config.get("vertical", {}).get("ratio", 0.0))
    config = studies[0].config
    signs = studies[0].data["sign"].values.tolist()
    fig, (axes,) = _panels((13, 6.4), (1, len(signs)), fig, ax, sharex=True, sharey=True)
    scan = config["beta"]
    arrow = 0.03 * (scan["high"] - scan["low"]) if scan["n"] > 1 else 0.03 * scan["high"]
    groups: list[list] = []
    bounded = set()
    ringed = False
    Om = studies[0].data["Omega"].values
    # The parts' bounds lie at the same amplitudes (the scan's end, for every ratio whose runs fly and land): side
    # by side, a slot per ratio and part within 0.6 of a step, not one over the other, the block alone's open, the
    # damper's filled.
    slots = 2 * len(studies)

    def dodge(i: int, part: str) -> float:
        return (2 * i + (part == "damper") - (slots - 1) / 2) * 0.6 / slots

    step = float(np.min(np.diff(Om))) if Om.size > 1 else 1.0
    for i, study in enumerate(studies):
        ratio = study.config.get("vertical", {}).get("ratio", 0.0)
        colour = cycle(i)["color"]
        data = study.data
        handles: list = []
        for panel, sign in zip(axes, signs):
            for part, line in (("bare", "--"), ("damper", "-")):
                cell = data.sel(part=part, sign=sign)
                bracketed = np.where(cell["flag"].values == BRACKETED, cell["beta_min"].values, np.nan)
                label = f"r = {ratio:g}, {PART_STYLE[part]['label']}"
                marker = PART_STYLE[part]["marker"]
                drawn = panel.plot(
                    data["Omega"].values, bracketed, line, color=colour, marker=marker, ms=3.5, label=label
                )
                if panel is axes[0]:
                    handles += drawn
                if "beta_min_flew" in cell:  # a vertical component: the overturning response at beta_min flew
                    flew = cell["beta_min_flew"].values == 1
                    panel.plot(data["Omega"].values[flew], bracketed[flew], "o", mfc="none", mec=colour, ms=9)
                    ringed |= bool(flew.any())
                for code, up in ((ABOVE, True), (BELOW, False)):
                    sel = cell["flag"].values == code
                    if sel.any():
                        bound = beta_min_or_bound(cell)[sel]
                        x = data["Omega"].values[sel] + dodge(i, part) * step
                        _bounds(panel, x, bound, arrow, colour, up, face=colour if part == "damper" else "white")
                        bounded.add(up)
            beta_f = flight_beta(_block(study.config), study.config)
            if beta_f < study.config["beta"]["high"]:
                flight = panel.axhline(beta_f, color=colour, ls=":", lw=1.5)
                if panel is axes[0]:
                    flight.set_label(
                        rf"r = {ratio:g}: $\beta_f$ = {beta_f:.3g}, g + $\ddot y_g$ reaches 0 above (flight)"
                    )
                    handles.append(flight)
        groups.append(handles)
    block = _block(config)
    for panel, sign in zip(axes, signs):
        panel.set_title(f"pulses of sign {sign:+d}", fontsize=9)
        _omega_axis(panel)
        _period_axis(panel, block.p)
    _beta_axis(axes[0])
    _acceleration_axis(axes[-1], config)
    bounds = []
    for up in sorted(bounded, reverse=True):
        handle = _bound_handle(up)
        if up:
            handle.set_label(
                r"lower bound (no overturning up to the last $\beta$ scanned, or below $\beta_f$ on a model without "
                "flight functions)"
            )
        handle.set_label(f"{handle.get_label()};\nopen: block alone, filled: with damper")
        bounds.append(handle)
    if ringed:
        ring = Line2D([], [], ls="none", marker="o", mfc="none", mec=HATCH_COLOUR, ms=9)
        bounds.append(ring)
        ring.set_label(r"ringed: the response overturning at $\beta_{min}$ flew first (flies and overturns)")
    groups += [bounds] if bounds else []
    # A column per ratio (a legend fills its columns in turn): each group padded with blank entries to the longest.
    rows = max(map(len, groups))
    handles = [h for group in groups for h in group + [Line2D([], [], ls="none", label=" ")] * (rows - len(group))]
    fig.legend(handles=handles, loc="outside lower center", ncols=len(groups), **LEGEND)
    pulse = PULSE_NAMES[config.get("pulse", {"motion": "sine"})["motion"]]
    _suptitle(
        fig,
        f"Minimum overturning spectrum under a vertical component: {pulse} with "
        rf"$\ddot y_g$ = r $a_g f(t)$ (> 0 up, in phase, the same for both signs)"
        f"\n{_block_label(block)}\n{_damper_label(config)}",
        fontsize=10,
    )
    return fig


def draw_vertical_spectra(
    studies, folder: str | Path, name: str = "spectrum-vertical", formats: tuple[str, ...] = DEFAULT_FORMATS
) -> list[Path]:
    """Draw :func:`vertical_spectra_figure` of ``studies`` as ``<folder>/<name>.<format>`` for each of ``formats``."""
    return write_figure(vertical_spectra_figure(studies), Path(folder), name, formats)


def _threshold_text(t: dict) -> str:
    """``Omega*`` as :func:`rocking.study.optimize.threshold_frequency` found it, for a figure."""
    if t["status"] == "bracketed":
        return rf"$\Omega^*$ = {t['Omega_star']:.3g} (scanned {t['low']:.3g} .. {t['high']:.3g})"
    if t["status"] == "above_range":
        return rf"$\Omega^*$ > {t['low']:.3g} (still useful there)"
    if t["status"] == "below_range":
        return rf"$\Omega^*$ $\leq$ {t['high']:.3g} (never useful)"
    return r"$\Omega^*$ unknown (no gain defined)"


@_figure_function
def optimize_figure(study: Study, *, fig: Figure | None = None, ax=None) -> Figure:
    """Optimal period (two normalisations), best gain with ``Omega*``, gain landscape of one ``gamma``."""
    data, cfg = study.data, study.config
    block = _block(cfg)
    Om, gammas = data["Omega"].values, data["gamma"].values
    gain, flag = data["gain_opt"].values, data["flag_opt"].values
    fig, ((ax_tg, ax_tp), (ax_g, ax_map)) = _panels((12, 10), (2, 2), fig, ax)
    useless = study.summary.get("useless_gain", 1.01)
    bounded = False
    step = np.ptp(Om) / 100
    for g, gamma in enumerate(gammas):
        label, style = rf"$\gamma$ = {gamma:g}", cycle(g)
        ax_tg.plot(Om, data["Tm_over_Tg_opt"].values[g], "-", ms=4, label=label, **style)
        ax_tp.plot(Om, data["r_opt"].values[g], "-", ms=4, label=label, **style)
        dodge = (g - (len(gammas) - 1) / 2) * step
        bounded = _gain_curve(ax_g, Om, gain[g], flag[g], style, label, dodge) or bounded
        threshold = study.summary["Omega_star"][f"{gamma:g}"]
        if threshold["status"] == "bracketed":
            ax_g.axvspan(threshold["low"], threshold["high"], color=style["color"], alpha=0.12)
            ax_g.axvline(threshold["Omega_star"], color=style["color"], ls="--", lw=1)
    if len(gammas) > 1:
        # The best is one of the curves: where that one is only bounded, so is the best (its triangle is drawn).
        pick = np.argmax(np.nan_to_num(gain, nan=-np.inf), axis=0)
        bound = flag[pick, np.arange(Om.size)] == ABOVE
        ax_g.plot(
            Om,
            np.where(bound, np.nan, data["best_gain"].values),
            ":",
            color=OKABE_ITO["black"],
            lw=1.5,
            label=r"best over $\gamma$ (measured)",
        )
    who = {key: "best" if key == "best" else rf"$\gamma$ = {key}" for key in study.summary["Omega_star"]}
    text = "\n".join(f"{who[key]}: {_threshold_text(t)}" for key, t in study.summary["Omega_star"].items())
    ax_g.axhline(useless, color=GREY, lw=0.8, ls=":")
    ax_g.axhline(1.0, color=GREY, lw=0.8)
    ax_g.set_ylabel(r"best gain $G = \beta_{min}$(damper) / $\beta_{min}$(block)")
    ax_g.set_title(rf"best gain; $\Omega^*$: above it $G$ < {useless:g}" + f"\n{text}", fontsize=8)
    ax_tg.set_ylabel(r"optimal $T_m / T_g$")
    ax_tp.set_ylabel(r"optimal $T_m p / 2\pi$")
    for ax in (ax_tg, ax_tp):
        ax.set_yscale("log")
    # Made on the logarithmic axis: a secondary axis made before would reset its ticks when it is drawn.
    period = ax_tp.secondary_yaxis(
        "right", functions=(lambda r: r * 2 * np.pi / block.p, lambda t: t * block.p / (2 * np.pi))
    )
    period.set_ylabel(r"$T_m$ (s)")
    for axis in (ax_tg.yaxis, ax_tp.yaxis, period.yaxis):
        _plain_ticks(axis)
    for ax in (ax_tg, ax_tp, ax_g):
        _omega_axis(ax)
        _period_axis(ax, block.p)
    _legend_below(ax_tg, ncols=3)
    _legend_below(ax_tp, ncols=3)
    handles = ax_g.get_legend_handles_labels()[0] + ([_bound_handle()] if bounded else [])
    _legend_below(ax_g, handles, ncols=2)
    g = len(gammas) // 2
    r, coarse = data["r_coarse"].values, data["gain_coarse"].values[g]
    norm, extension = _gain_norm(coarse)
    image = ax_map.pcolormesh(_edges(Om), np.exp(_edges(np.log(r))), coarse.T, cmap=DIVERGING, norm=norm)
    ax_map.plot(
        Om,
        data["r_opt"].values[g],
        "o",
        color=OKABE_ITO["black"],
        mfc="white",
        ms=5,
        label="optimum (after refinement)",
    )
    ax_map.set_yscale("log")
    _plain_ticks(ax_map.yaxis)
    _omega_axis(ax_map)
    _period_axis(ax_map, block.p)
    ax_map.set_ylabel(r"$T_m p / 2\pi$")
    ax_map.set_title(rf"gain over the coarse scan, $\gamma$ = {gammas[g]:g} (blank: no gain defined)", fontsize=9)
    _legend_below(ax_map)
    _gain_colorbar(fig, image, ax_map, "G", extension)
    stops = _stops_label(block, {"stops": True} if cfg.get("stops") else {})
    damper = (
        rf"dampers $\gamma$ = {', '.join(f'{x:g}' for x in gammas)} (period optimised at each $\Omega$), "
        rf"$\zeta$ = {cfg['zeta']:g}, h = {cfg['h']:g} m, {stops}"
    )
    _title(fig, "Optimal damper", cfg, damper=damper)
    return fig


#: The legend of a design's gain of the envelopes, against the gains of each direction.
ENVELOPE_GAIN = (
    "gain of the envelopes: the worse direction with the damper over the worse alone\n"
    "(the gain of one direction where it governs both; between the two where they differ)"
)


def _stroke_text(Omega, use, contacts, L: float, half_width: float) -> str:
    """What the stroke panel of a design shows, in words: the largest stroke (``use`` in units of the stops'
    ``L``, m), where it is, and whether the mass reaches the stops (``contacts`` per ``Omega``) or the block's edge."""
    use = np.asarray(use, float)
    if not np.isfinite(use).any():
        return "stroke: no pulse of the band overturns the block alone"
    i = int(np.nanargmax(use))
    on_stops = int((np.asarray(contacts) > 0).sum())
    text = f"stroke up to {use[i]:.2f} L = {use[i] * L:.3g} m (at $\\Omega$ = {Omega[i]:.3g});\n"
    text += f"on the stops at {on_stops} of {use.size} $\\Omega$" if on_stops else "never on the stops"
    return text + (", past the block's edge" if use[i] * L > half_width else ", on the block")


#: Legend of a gain the scan only bounds (its beta_min with the damper, or alone, is a bound), by ``up``.
GAIN_BOUND = {
    True: r"gain at least this: a $\beta_{min}$ the scan only bounds",
    False: r"gain at most this: a $\beta_{min}$ the scan only bounds",
}


def _direction_gain(cell) -> tuple[np.ndarray, np.ndarray]:
    """One direction's gain ``beta_min`` with the damper over ``beta_min`` alone at each ``Omega`` of a design's data
    (``cell``: one ``sign``), and what each value is: ``measured``, a ``lower`` or ``upper`` bound (a ``beta_min``
    the scan only bounds), or ``undefined`` (bounds either way: both blocks survive the scan, say)."""
    ratios, flags = {}, {}
    for part in PARTS:
        ratios[part] = beta_min_or_bound(cell.sel(part=part))
        flags[part] = cell["flag"].sel(part=part).values
    up = (flags["damper"] == ABOVE) | (flags["bare"] == BELOW)
    down = (flags["damper"] == BELOW) | (flags["bare"] == ABOVE)
    kind = np.select([up & down, up, down], ["undefined", "lower", "upper"], "measured")
    return ratios["damper"] / ratios["bare"], kind


@_figure_function
def design_figure(study: Study, *, fig: Figure | None = None, ax=None) -> Figure:
    """The design: its gain over the band (per direction and the envelope), the worst gain of every damper of
    the coarse search, and the stroke the design uses at the pulses that overturn the block alone."""
    data, s, block = study.data, study.summary, _block(study.config)
    fig, ((ax_g, ax_map, ax_x),) = _panels((15, 6), (1, 3), fig, ax)
    Om = data["Omega"].values
    undefined_at, bounds = [], set()
    for i, sign in enumerate(data["sign"].values):
        ratio, kind = _direction_gain(data.sel(sign=sign))
        style = cycle(i + 1)
        # On top of the envelope: where one direction governs both blocks its gain is the envelope's.
        ax_g.plot(
            Om,
            np.where(kind == "measured", ratio, np.nan),
            ("--", ":")[i % 2],
            ms=4,
            zorder=5,
            label=f"pulses of sign {sign:+d} alone",
            **style,
        )
        arrow = 0.06 * max(np.nanmax(ratio, initial=1.0), 1.0)
        dodge = 0.01 * (np.ptp(Om) or 1.0) * (1 if i % 2 else -1)
        for bound, up in (("lower", True), ("upper", False)):
            _bounds(ax_g, Om[kind == bound] + dodge, ratio[kind == bound], arrow, style["color"], up)
            bounds |= {up} if (kind == bound).any() else set()
        undefined_at += [f"{sign:+d}"] if (kind == "undefined").any() else []
    envelope_style = {"color": PART_STYLE["damper"]["color"], "lw": 6, "alpha": 0.3, "solid_capstyle": "round"}
    if _gain_curve(ax_g, Om, data["gain_opt"].values, data["flag_opt"].values, envelope_style, ENVELOPE_GAIN):
        bounds.add(True)
    ax_g.axhline(1.0, color=GREY, lw=0.8)
    _omega_axis(ax_g)
    _period_axis(ax_g, block.p)
    ax_g.set_ylabel(r"$G = \beta_{min}$(damper) / $\beta_{min}$(block)")
    found = s.get("verdict") or verdict(s)  # a design saved before the verdict was stored: from its summary
    helps = found["code"] == "helps"
    heading = (
        rf"worst gain over the band: {s['worst_gain']:.3g} at $\Omega$ = {s['worst_at_Omega']:.3g}"
        if s["worst_gain"] is not None
        else "worst gain undefined over the band"
    )
    # A design that does not help says so where its gain is read, in the verdict's words.
    ax_g.set_title(heading if helps else f"{heading}:\n{VERDICTS[found['code']]}", fontsize=9)
    handles = ax_g.get_legend_handles_labels()[0]
    for up in sorted(bounds, reverse=True):  # of a gain: the words of _bound_handle are those of a beta_min
        handle = _bound_handle(up)
        handle.set_label(GAIN_BOUND[up])
        handles.append(handle)
    if undefined_at:  # no mark to show: the gap in the curve, said in words
        words = f"pulses of sign {', '.join(undefined_at)}: no gain where the scan only bounds both blocks (gap)"
        handles.append(Line2D([], [], ls="none", label=words))
    _legend_below(ax_g, handles, ncols=1)
    r, z = data["r_coarse"].values, data["zeta_coarse"].values
    worst = data["candidate_worst_gain"].values[: r.size * z.size].reshape(z.size, r.size)
    norm, extension = _gain_norm(worst)
    image = ax_map.pcolormesh(np.exp(_edges(np.log(r))), np.exp(_edges(np.log(z))), worst, cmap=DIVERGING, norm=norm)
    off = ~data["candidate_on_block"].values
    ax_map.plot(
        data["candidate_r"].values[off],
        data["candidate_zeta"].values[off],
        "x",
        color=OKABE_ITO["black"],
        ms=5,
        label="mass past the block's edge",
    )
    d = s["damper"]
    if helps:
        ax_map.plot([d["Tm_ratio"]], [d["zeta"]], "*", color=OKABE_ITO["yellow"], mec="k", ms=14, label="design")
    else:  # no star for a damper that does not help: the best tried, named by the verdict
        ax_map.plot(
            [d["Tm_ratio"]],
            [d["zeta"]],
            "o",
            mfc="none",
            mec=OKABE_ITO["black"],
            mew=1.5,
            ms=12,
            label=f"best tried: {VERDICTS[found['code']]}",
        )
    ax_map.set_xscale("log")
    ax_map.set_yscale("log")
    ax_map.set_xlabel(r"$T_m p / 2\pi$")
    period = ax_map.secondary_xaxis(
        "top", functions=(lambda r: r * 2 * np.pi / block.p, lambda t: t * block.p / (2 * np.pi))
    )
    period.set_xlabel(r"$T_m$ (s)")
    for axis in (ax_map.xaxis, ax_map.yaxis, period.xaxis):
        _plain_ticks(axis)
    ax_map.set_ylabel(r"$\zeta$")
    ax_map.set_title("worst gain over the band, coarse search", fontsize=9)
    _legend_below(ax_map)
    _gain_colorbar(fig, image, ax_map, "worst G", extension)
    step = np.min(np.diff(Om)) if Om.size > 1 else 1.0
    use = stroke_use(data)
    ax_x.bar(
        Om,
        use,
        width=0.6 * step,
        color=OKABE_ITO["sky blue"],
        edgecolor=OKABE_ITO["blue"],
        label=r"$x_{max}$",
    )
    ax_x.axhline(1.0, color=OKABE_ITO["black"], lw=0.8, label="the stops (|x| = L)")
    ax_x.axhline(block.B / 2 / d["L_m"], color=OKABE_ITO["vermillion"], lw=1, ls="--", label="block's edge (B/2)")
    _omega_axis(ax_x)
    _period_axis(ax_x, block.p)
    ax_x.set_ylabel(r"$x_{max} / L$ at $\beta_{min}$ of the block alone")
    ax_x.secondary_yaxis("right", functions=(lambda u: u * d["L_m"], lambda x: x / d["L_m"])).set_ylabel(
        r"$x_{max}$ (m)"
    )
    ax_x.set_title(_stroke_text(Om, use, data["stop_contacts"].max("sign").values, d["L_m"], block.B / 2), fontsize=9)
    _legend_below(ax_x, ncols=3)
    damper = (
        f"design: m = {quantity(d['m_kg'], 'kg')}, $k_m$ = {quantity(d['k_m_N_per_m'], 'N/m')}, "
        f"c = {quantity(d['c_N_s_per_m'], 'N s/m')} "
        rf"($\gamma$ = {d['gamma']:g}, $T_m$ = {d['T_m_s']:.3g} s, $\zeta$ = {d['zeta']:.3g}), "
        f"h = {quantity(d['h_m'], 'm')}, stops at L = {quantity(d['L_m'], 'm', 3)}"
    )
    _title(fig, "Damper design" if helps else f"Damper design: {VERDICTS[found['code']]}", study.config, damper=damper)
    return fig


#: The two dampers of a threshold map: line style and marker face (filled: unlimited guide, open: stops).
GUIDES = {"unlimited": ("-", None), "stops": ("--", "white")}


def _size_axis(ax, p) -> None:
    """A top axis of the homogeneous block's half-diagonal ``R = 3 g / (4 p^2)``, m, over a ``p`` axis
    (docs/model.md section 9), its ticks at the grid's ``p`` (rad/s), which the bottom axis also marks."""
    g = Block.__dataclass_fields__["g"].default

    def size(x):
        return 3 * g / (4 * np.maximum(np.asarray(x, float), 1e-9) ** 2)

    def frequency(R):
        return np.sqrt(3 * g / (4 * np.maximum(np.asarray(R, float), 1e-9)))

    axis = ax.secondary_xaxis("top", functions=(size, frequency))
    axis.set_xticks(size(p), [f"{R:.3g}" for R in size(p)])
    axis.set_xlabel("R (m), half-diagonal")
    ax.set_xticks(p, [f"{v:.3g}" for v in p])


def _best_gain_panel(ax, found) -> None:
    """The best gain over ``Omega`` of each damper against ``p``, one colour per slenderness."""
    p = found["p"].values
    for i, lam in enumerate(found["lam"].values):
        for kind, (ls, face) in GUIDES.items():
            style = cycle(i)
            gain = found["best_gain"].sel(part=kind).values[i]
            ax.plot(p, gain, ls, ms=6, mfc=face or style["color"], label=rf"$\lambda$ = {lam:.3g}, {kind}", **style)
    ax.axhline(1.0, color=GREY, lw=0.8)
    ax.set_xlabel("p (rad/s)")
    ax.set_ylabel(r"best gain over $\Omega$ ($\beta_{min}$ damped / alone)")
    ax.set_title("the most the damper gives, per geometry (filled: unlimited guide; open: stops)", fontsize=9)
    _size_axis(ax, found["p"].values)
    _legend_below(ax, ncols=2)


def _frequency_panel(ax, found) -> None:
    """Per geometry, against ``p``: from which ``Omega`` the block alone survives (``safe_from``) and ``Omega*``
    of each damper, measured where bracketed, else a bound (an arrow towards the unknown value)."""
    p, lams = found["p"].values, found["lam"].values
    dodge = 0.02 * (np.ptp(p) or 1.0)
    handles: list = []
    for i, lam in enumerate(lams):
        style = cycle(i)
        safe = found["safe_from"].values[i]
        label = rf"$\lambda$ = {lam:.3g}"
        ax.plot(p, safe, ":", color=style["color"], marker="_", ms=14, mew=2, label=label)
        handles.append(Patch(color=style["color"], label=label))
        for k, (kind, (_, face)) in enumerate(GUIDES.items()):
            a = found.sel(part=kind).isel(lam=i)
            x = p + (k - 0.5) * dodge
            status = a["status"].values
            star = np.where(status == STATUSES.index("bracketed"), a["Omega_star"].values, np.nan)
            ax.plot(x, star, "*", ms=10, color=style["color"], mfc=face or style["color"], ls="none")
            for name, up, bound in (("above_range", True, "Omega_star_low"), ("below_range", False, "Omega_star_high")):
                where = status == STATUSES.index(name)
                _bounds(ax, x[where], a[bound].values[where], 0.04 * float(found["Omega"][-1]), style["color"], up)
    ax.set_xlabel("p (rad/s)")
    ax.set_ylabel(r"$\Omega = \omega_g / p$")
    ax.set_ylim(0, float(found["Omega"][-1]) * 1.08)
    _size_axis(ax, found["p"].values)
    status = found["status"].values
    # The slendernesses by colour alone, and the dotted line by its style alone: the short line of a legend entry
    # under a wide marker would read as solid.
    handles.append(Line2D([], [], ls=":", lw=1.5, color="0.3", label="block alone safe from this $\\Omega$ on"))
    # An entry for each mark drawn, none for a mark that appears nowhere.
    marks = (
        ("bracketed", "*", r"$\Omega^*$ (filled: unlimited; open: stops)"),
        ("above_range", "^", r"$\Omega^*$ above the scan: still useful here"),
        ("below_range", "v", r"$\Omega^*$ below the scan: useless here"),
    )
    for name, marker, label in marks:
        if (status == STATUSES.index(name)).any():
            face = "0.3" if marker == "*" else "white"
            handles.append(
                Line2D(
                    [], [], ls="none", marker=marker, ms=10 if marker == "*" else 6, mfc=face, color="0.3", label=label
                )
            )
    _legend_below(ax, handles, ncols=2)
    counts = {name: int((found["status"].values == n).sum()) for n, name in enumerate(STATUSES)}
    ax.set_title(
        rf"$\Omega^*$ (the damper's gain falls below useful): bracketed in {counts['bracketed']} of "
        f"{found['status'].size} cases;\nabove the scan (useful wherever the block alone overturns) in "
        f"{counts['above_range']}",
        fontsize=9,
    )


@_figure_function
def threshold_figure(study: Study, *, fig: Figure | None = None, ax=None) -> Figure:
    """What a threshold map found per geometry ``(lambda, p)``: the best gain of each damper, from which ``Omega``
    the block alone survives and ``Omega*`` (or its bound); and the best gain against ``Omega`` at one ``p``."""
    data, cfg = study.data, study.config
    p, Om = data["p"].values, data["Omega"].values
    fig, (axes,) = _panels((16, 6.5), (1, 3), fig, ax)
    found = thresholds(data)
    _best_gain_panel(axes[0], found)
    _frequency_panel(axes[1], found)
    j = p.size // 2
    for i, lam in enumerate(data["lam"].values):
        for kind, (ls, face) in GUIDES.items():  # as in the left panel: open markers and dashes for the stops
            style = cycle(i)
            label = rf"$\lambda$ = {lam:.3g}, {kind}"
            gain = data["gain"].sel(part=kind).values[i, j]
            axes[2].plot(Om, gain, ls, ms=5, mfc=face or style["color"], label=label, **style)
    useless = study.summary["useless_gain"]
    axes[2].axhline(
        useless, color=GREY, lw=0.8, ls=":", label=rf"G = {useless:g}: $\Omega^*$ where the gain falls below it"
    )
    _omega_axis(axes[2])
    _period_axis(axes[2], float(p[j]))
    axes[2].set_ylabel("best gain (envelopes over the directions)")
    axes[2].set_title(
        f"best gain at p = {p[j]:.3g} rad/s; ends where the block alone survives {study.summary['a_max_g']:g} g",
        fontsize=9,
    )
    _legend_below(axes[2], ncols=2)
    dampers = "; ".join(
        rf"$\gamma$ = {d['gamma']:g}, $\zeta$ = {d['zeta']:g}, h = {d['h']:g} m, "
        + ("stops at B/2 minus the pads" if d.get("stops") else "unlimited guide")
        for d in cfg["dampers"]
    )
    grid = ", ".join(
        f"{name} {cfg[key]['low']:g} to {cfg[key]['high']:g}{unit} ({cfg[key]['n']})"
        for key, name, unit in (("lam", r"$\lambda$ = H/B", ""), ("p", "p", " rad/s"))
    )
    _suptitle(
        fig,
        f"Threshold frequency across geometries: one-sine pulses up to {study.summary['a_max_g']:g} g; "
        f"{_directions_label(cfg)}\nhomogeneous blocks of M = {cfg['M']:g} kg, e = {cfg['e_ratio']:g} B, {grid}\n"
        f"dampers (period optimised at each $\\Omega$): {dampers}",
        fontsize=10,
    )
    return fig


#: A motion axis names its motions up to this many; beyond, its ticks are motion numbers.
NAMED_MOTIONS = 30


def _motion_axis(ax, names: list[str]) -> None:
    """The motions of an IDA along ``ax``'s y axis: a tick at each, with its name (when they are few)."""
    ax.set_ylim(-0.5, len(names) - 0.5)
    if len(names) <= NAMED_MOTIONS:
        ax.set_yticks(np.arange(len(names)), names, fontsize=7 if len(names) > 10 else None)
        ax.set_ylabel("motion")
    else:
        ax.yaxis.set_major_locator(MaxNLocator(integer=True))
        ax.set_ylabel("motion (number in the suite)")


def _readable(value: float) -> str:
    """A number for a title or a legend: three significant digits, without a power of ten (407000, 0.00213)."""
    return np.format_float_positional(value, precision=3, unique=False, fractional=False, trim="-")


#: Step between the arrowheads of the parts' extrapolated medians outside the axes, in axes widths: side by side.
MEDIAN_ARROW_STEP = 0.035


def _median_outside(ax, place: str, style: dict, index: int) -> None:
    """An open arrowhead at half probability on the edge of the axes beyond which a part's median lies
    (:data:`~rocking.study.fragility.MEDIAN_PLACES`), pointing out of the levels tested, the ``index``-th part's
    :data:`MEDIAN_ARROW_STEP` further out; nothing for a median within them."""
    if place not in ("above_levels", "below_levels"):
        return
    above = place == "above_levels"
    side = "above the highest" if above else "below the lowest"
    ax.plot(
        1.0 + MEDIAN_ARROW_STEP * index if above else -MEDIAN_ARROW_STEP * index,
        0.5,
        ">" if above else "<",
        transform=ax.get_yaxis_transform(),  # x across the axes, y the probability
        ms=9,
        mfc="none",
        mew=1.5,
        color=style["color"],
        ls="none",
        clip_on=False,
        zorder=6,
        label=f"{style['label']}: median {side} level tested: extrapolated",
    )


@_figure_function
def ida_figure(study: Study, *, fig: Figure | None = None, ax=None) -> Figure:
    """The fraction of motions that overturn the block at each level, with the fitted lognormal fragility and its
    band, block alone and with the damper; and the outcome of every motion at every level, both blocks in one grid,
    resurrections marked."""
    data, measure_name = study.data, study.config["measure"]
    levels, curve_x = data["level"].values, data["curve_x"].values
    fig, ((ax_f, ax_m),) = _panels((13, 6), (1, 2), fig, ax, width_ratios=(1.2, 1))
    unit = UNIT_TEXT[LEVELS[measure_name]]
    measure = MEASURE_NAMES[measure_name] + (f" ({unit})" if unit else "")
    for index, part in enumerate(("bare", "damper")):
        style, a = PART_STYLE[part], data.sel(part=part)
        ax_f.plot(
            levels,
            a["fraction"].values,
            ls="none",
            color=style["color"],
            marker=style["marker"],
            ms=4 if part == "bare" else 6.5,
            zorder=5 if part == "bare" else 4,
            label=f"{style['label']}: fraction overturned",
        )
        if FIT_STATUSES[int(a["fit_status"])] in FITTED:
            median = f"{_readable(float(a['median']))} {unit}".rstrip()
            place = MEDIAN_PLACES[int(a["median_extrapolated"])] if "median_extrapolated" in a else "within_levels"
            outside = " (extrapolated)" if place in ("above_levels", "below_levels") else ""
            label = f"lognormal fit: median {median}{outside}, dispersion {float(a['dispersion']):.2f}"
            ax_f.plot(curve_x, a["curve"].values, "-" if part == "bare" else "--", color=style["color"], label=label)
            ax_f.fill_between(
                curve_x, a["band_low"].values, a["band_high"].values, color=style["color"], alpha=0.15, lw=0
            )
            _median_outside(ax_f, place, style, index)
    # Levels over a decade or more (scale factors, say) read best in log scale, as IDA curves are drawn.
    xlog = bool(levels.min() > 0 and levels.max() >= 10 * levels.min())
    ax_f.set_xlabel(measure)
    if xlog:
        ax_f.set_xscale("log")
        _plain_ticks(ax_f.xaxis)
    if LEVELS[measure_name] == "m/s^2":  # an acceleration: in g too, the block's gravity
        g = _block(study.config).g
        in_g = ax_f.secondary_xaxis("top", functions=(lambda x: x / g, lambda x: x * g))
        in_g.set_xlabel(f"{MEASURE_NAMES[measure_name]} (g)")
        if xlog:
            _plain_ticks(in_g.xaxis)
    ax_f.set_ylabel("probability of overturning")
    ax_f.set_ylim(-0.02, 1.02)
    ax_f.set_title(
        "fraction of the motions that overturn the block; bands: 90 % bootstrap over the motions", fontsize=9
    )
    _legend_below(ax_f)
    # Both blocks in one grid, as a map's effect panel: safe either way, saved, lost, overturned either way.
    over = ida_envelope(data)["overturned"]
    bare, damped = (over.sel(part=part).values.astype(int) == 1 for part in PARTS)
    effect = (bare + 2 * damped).T
    handles = _classes(ax_m, levels, np.arange(effect.shape[1]), effect, EFFECT_CLASSES[:4], xlog)
    if xlog:
        ax_m.set_xscale("log")
        _plain_ticks(ax_m.xaxis)
    rows = np.flatnonzero(data["reversals"].sel(part="damper").values > 0)
    if rows.size:
        ax_m.plot(
            np.full(rows.size, levels[-1]),
            rows,
            "<",
            color=OKABE_ITO["blue"],
            ms=6,
            ls="none",
            label="with the damper, non-monotone: overturns, then survives a higher level",
        )
        handles += ax_m.get_legend_handles_labels()[0]
    ax_m.set_xlabel(measure)
    _motion_axis(ax_m, motion_names(study.config["suite"]))
    ax_m.set_title("outcome of each motion at each level, block alone and with the damper", fontsize=9)
    _legend_below(ax_m, handles)
    title = "Incremental dynamic analysis" if study.kind == "ida" else "Fragility"
    config = study.config
    _suptitle(
        fig,
        f"{title}: {_suite_label(config['suite'])}; {_directions_label(config, 'motions')}\n"
        f"{_block_label(_block(config))}\n{_damper_label(config)}",
        fontsize=10,
    )
    return fig


#: The figure of each kind of study, by the name its entry of :data:`rocking.study.kinds.KINDS` gives.
FIGURES = {name: globals()[kind.figure] for name, kind in KINDS.items()}


def draw(
    study: Study, folder: str | Path, name: str | None = None, formats: tuple[str, ...] = DEFAULT_FORMATS
) -> list[Path]:
    """Draw the figure of ``study`` as ``<folder>/<name>.<format>`` for each of ``formats`` (:data:`FORMATS
    <rocking.plot.FORMATS>`; default the PNG alone), name: the study's kind."""
    if study.kind not in FIGURES:
        raise ParameterError(f"no figure for a study of kind {study.kind!r} (known: {', '.join(FIGURES)})")
    formats = check_formats(formats)  # before the figure is drawn
    return write_figure(FIGURES[study.kind](study), Path(folder), name or study.kind, formats)


#: Dots per inch of every figure file (the PNG's pixels; a PDF's rasterized cells).
DPI = 150


def write_figure(fig: Figure, folder: Path, name: str, formats: tuple[str, ...] = DEFAULT_FORMATS) -> list[Path]:
    """Write ``fig`` as ``<folder>/<name>.<format>`` for each of ``formats``: laid out once (:func:`laid_out`), each
    file with that layout.

    Each file is written as a study's data are (:func:`rocking.study.files.atomic_write`: a temporary file renamed
    over it, a symbolic link in its place replaced, not followed), under the lock on ``name`` in ``folder``
    (:func:`rocking.study.files.name_lock`): a reader sees the old figure or the new one, never a part, and
    two saves of one name do not leave one's picture beside the other's data.
    """
    FigureCanvasAgg(fig)
    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / f"{name}.{ext}" for ext in check_formats(formats)]
    with name_lock(folder, name), laid_out(fig, DPI):
        for path in paths:
            save_figure(fig, path, dpi=DPI)
    return paths


#: rcParams under which a figure without a layout engine keeps none: matplotlib reads ``None`` as these ask.
NO_LAYOUT_ENGINE: dict[Any, Any] = {"figure.autolayout": False, "figure.constrained_layout.use": False}


@contextmanager
def laid_out(fig: Figure, dpi: float) -> Iterator[Figure]:
    """``fig`` (on an Agg canvas) laid out once by its layout engine at ``dpi``, as matplotlib's ``savefig`` lays it
    out, then without an engine while the context lasts: ``savefig`` of a figure with an engine draws it twice, once
    without rendering to lay it out and once to render it (the layout is most of a figure's cost), and would lay
    it out again for a second format. The files are those ``savefig`` writes with the engine
    (tests/test_fast_paths.py)."""
    with rc_context(NO_LAYOUT_ENGINE):
        engine = fig.get_layout_engine()
        if engine is not None:
            fig.set_dpi(dpi)  # the text's extents at the files' dpi, as savefig measures them
            engine.execute(fig)
            fig.set_layout_engine(None)
        yield fig


def save_figure(fig: Figure, path: Path, dpi: float) -> None:
    """Write ``fig`` at ``path`` in the format of its suffix (:func:`rocking.study.files.atomic_write`).

    Raises
    ------
    DiskFull
        If the disk is full.
    ParameterError
        If it cannot be written otherwise, naming it.
    """
    try:
        # A file object of atomic_write's, closed however the writer fails (a full disk fails the PDF writer with its
        # rasterized parts in a state that keeps its file open until garbage collection).
        atomic_write(path, lambda file: fig.savefig(file, format=path.suffix[1:].lower() or None, dpi=dpi))
    except DiskFull:
        raise
    except OSError as exc:
        raise ParameterError(f"cannot write the figure {path} ({exc.strerror or exc})") from None


#: What drawing a saved study whose data do not fit its figure raises: a missing array or
#: summary entry, an array of another shape or type.
UNFIT = (KeyError, IndexError, TypeError, ValueError, AttributeError)


def _redraw_one(stem: Path, formats: tuple[str, ...]) -> list[Path]:
    """Draw the study saved at ``stem`` next to it, under the lock on its name (a save of it waits: the figures are
    those of the data read); a ParameterError naming it if its data do not fit."""
    with name_lock(stem.parent, stem.name):
        study = load(stem)
        try:
            return draw(study, stem.parent, stem.name, formats)
        except ParameterError:
            raise
        except UNFIT as exc:  # the file passed load()'s checks but is not what this version of rocking writes
            text = str(exc).splitlines()[0] if str(exc) else ""
            raise ParameterError(
                f"{stem}.nc/.json: the saved {study.kind} cannot be drawn ({type(exc).__name__}: {text}); "
                "it lacks data its figure needs (saved by another version of rocking?)"
            ) from exc


def redraw(path: str | Path, formats: tuple[str, ...] = DEFAULT_FORMATS) -> list[Path]:
    """Redraw figures from saved data: one study (its ``.nc``, ``.json`` or stem) or every study in a folder.

    The figures are written next to the data, under the same stem, in each of ``formats`` (default the PNG).

    Raises
    ------
    ParameterError
        Naming the file: nothing saved at ``path``, a study that cannot be read
        (:func:`rocking.study.storage.load`) or drawn (data missing), or a
        figure that cannot be written.
    """
    path = Path(path)
    stems = (
        sorted(p.with_suffix("") for p in path.glob("*.json") if p.with_suffix(".nc").is_file())
        if path.is_dir()
        else [path]
    )
    if not stems:
        raise ParameterError(f"no saved study (<name>.nc with <name>.json) in {path}")
    written = []
    for stem in stems:
        written += _redraw_one(study_stem(stem), formats)
    return written
