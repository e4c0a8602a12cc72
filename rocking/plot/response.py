"""Figure of a time history: theta/alpha, the base's slip on a floor with friction, every coordinate of the damper
and the ground acceleration.

Each coordinate of the model's attached bodies has its own panel, named as the model names it and in its own
unit, the one its model's manifest records (rad for an angle, m for a displacement). Written with matplotlib's
Agg canvas.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..model.loading import load_model
from ..model.motion import describe, peak
from ..model.outputs import atomic_write
from ..model.params import RANGES, Block, Damper
from ..sim.history import FLIGHT_COLUMNS, FLOOR_COLUMNS
from .style import CYCLE, GREY, OKABE_ITO, PULSE_NAMES, quantity, symbol, wrap

#: The history's entries that are not a coordinate of the damper (rocking.sim.problem.Response.history): the base's
#: slip ``u`` (m), its speed and its sliding direction on a floor with friction have a panel of their own.
NOT_COORDINATES = ("t", "phase", "ag", "theta", *FLOOR_COLUMNS, *FLIGHT_COLUMNS)
#: The slip panel's unit: mm, m per unit.
SLIP_UNIT = ("mm", 1e-3)


def coordinate_unit(model, name: str) -> str:
    """The unit of the coordinate ``name`` of ``model``, as its manifest records it (derived: rad for an angle)."""
    return load_model(model).manifest["units"][name]


def _stroke(damper) -> float | None:
    """Half-stroke ``L`` of the damper's stops (m), or None for a guide without stops."""
    if isinstance(damper, Damper):
        return None if damper.stops is None else damper.stops.L
    return None if damper is None else damper.get("L")


def _damper_text(damper, model: str | None = None) -> str:
    """The damper's parameters for the title, each with its unit (:data:`rocking.model.params.RANGES`, or the
    manifest of a variant's ``model``)."""
    if damper is None:
        return "no damper"
    params = damper.as_params() if isinstance(damper, Damper) else damper
    units = {k: r.unit for k, r in RANGES.items()}
    if model:
        units.update({p["name"]: p["unit"] for p in load_model(model).manifest["parameters"]})
    return "damper " + wrap([f"{symbol(k)} = {quantity(v, units.get(k, ''))}" for k, v in params.items()])


def past_edge(histories: dict, name: str, half_width: float) -> list[str]:
    """The labels of the histories whose coordinate ``name`` (a stroke, m) passes the block's edge ``B/2``."""
    return [label for label, h in histories.items() if name in h and np.max(np.abs(h[name])) > half_width]


def _flag_past_edge(ax, labels: list[str]) -> None:
    """Say on a stroke's panel which responses ran the mass past the block's edge (held on paper only)."""
    if labels:
        ax.set_title(
            f"mass past the block's edge: {', '.join(labels)} (a guide on the block ends there)",
            loc="left",
            fontsize=8,
            color=OKABE_ITO["vermillion"],
        )


def motion_label(motion, block: Block, name: str = "") -> str:
    """A ground motion for a title: its family, amplitude in m/s^2 and g, and period in s (a pulse; with its
    ``beta`` and ``Omega`` for ``block``, docs/model.md section 9), or its peak and duration (a record, after its
    ``name``: the file it was read from).

    The amplitude is the pulse's peak where the two agree; a Mavroeidis-Papageorgiou pulse's amplitude
    parameter is not its peak, so both are given, each named for what it is, with its ``gamma_MP`` and ``nu``.
    """
    d = describe(motion)
    top = peak(motion)
    direction = "" if d.a_g >= 0 else ", sign -1"
    if d.family == "sampled":
        what = f"record {_escaped(name)}" if name else "sampled motion"
        return f"{what}: PGA = {top:.3g} m/s$^2$ ({top / block.g:.3g} g), {d.t_p:.3g} s{direction}"
    a = abs(d.a_g)
    scales = rf"$\beta$ = {block.beta(a):.3g}, $\Omega$ = {d.omega_g / block.p:.3g}"
    if d.family == "mp":
        return (
            rf"{PULSE_NAMES[d.family]} ($\gamma_{{MP}}$ = {d.shape:.3g}, $\nu$ = {d.phase:.3g} rad): amplitude "
            rf"$a_g$ = {a:.3g} m/s$^2$, peak {top:.3g} m/s$^2$ ({top / block.g:.3g} g), $T_g$ = {d.T_g:.3g} s "
            rf"({scales}){direction}"
        )
    return (
        rf"{PULSE_NAMES[d.family]}: peak $a_g$ = {a:.3g} m/s$^2$ ({a / block.g:.3g} g), $T_g$ = {d.T_g:.3g} s "
        rf"({scales}){direction}"
    )


def _escaped(text: str) -> str:
    """A text from outside (a file's name) as a title shows it: its ``$`` escaped, so that mathtext never parses it."""
    return text.replace("$", r"\$")


#: How far past the overturning line ``|theta| = alpha`` the rotation axis runs when a response overturns.
CLIP = 1.25


def _clip_overturned(ax, responses: dict, histories: dict, alpha: float, colours: dict) -> None:
    """Scale the ``theta / alpha`` axis to the responses that stay up, not to one that overturns.

    An overturned block's angle runs on to lying flat (``pi / (2 alpha)``, 6 for a slender block) and would
    squeeze a damped response of 0.2 into a line: the axis stops :data:`CLIP` past the overturning line, or
    just past the largest surviving rotation, and a marker where each overturning response leaves it says so.
    """
    standing = [np.max(np.abs(histories[k]["theta"])) / alpha for k, r in responses.items() if not r.overturned]
    if len(standing) == len(responses):
        return
    limit = max(CLIP, 1.05 * max(standing, default=0.0))
    ax.set_ylim(-limit, limit)
    overturned = [label for label, r in responses.items() if r.overturned]
    for k, label in enumerate(overturned):
        h = histories[label]
        ratio = h["theta"] / alpha
        out = np.flatnonzero(np.abs(ratio) > limit)
        at = out[0] if out.size else int(np.argmax(np.abs(ratio)))
        side = np.sign(ratio[at]) or 1.0
        marker = "^" if side > 0 else "v"
        ax.plot(h["t"][at], side * limit, marker, color=colours[label], ms=8, clip_on=False)
        ax.annotate(
            f"overturns ({label})",
            (h["t"][at], side * limit),
            xytext=(4, -10 * side * (1 + k)),  # one under the other: close times would overprint
            textcoords="offset points",
            fontsize=7,
            color=colours[label],
        )


def plot_responses(
    responses: dict,
    block: Block,
    path: str | Path,
    title: str = "",
    *,
    damper=None,
    model: str | None = None,
    motion=None,
    record: str = "",
) -> Path:
    """Draw recorded responses (:func:`response_figure`) and save the figure at ``path`` (its suffix picks the
    format: PNG, PDF, SVG); the path written. Written as every output is (:func:`rocking.study.files.atomic_write`:
    a temporary file renamed over ``path``, a symbolic link there replaced, not followed)."""
    fig = response_figure(responses, block, title, damper=damper, model=model, motion=motion, record=record)
    FigureCanvasAgg(fig)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write(path, lambda file: fig.savefig(file, format=path.suffix[1:].lower() or None, dpi=120))
    return path


def rotation_axes(ax, response, alpha: float, label: str = "") -> None:
    """Draw one recorded response's ``theta / alpha`` over ``t`` on the axes ``ax``, with the lines
    ``theta = +-alpha`` and, if it overturns, the time it does (:meth:`rocking.Response.plot`)."""
    h = response.history
    ax.plot(h["t"], h["theta"] / alpha, label=label or None)
    ax.axhline(1, color=GREY, lw=0.8, ls="--")
    ax.axhline(-1, color=GREY, lw=0.8, ls="--")
    if response.overturned:
        ax.axvline(response.t_overturn, color=GREY, ls=":", lw=1.2)
        ax.set_ylim(-np.pi / 2 / alpha * 1.05, np.pi / 2 / alpha * 1.05)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(r"$\theta / \alpha$")


def _slips(response, history: dict) -> bool:
    """The response's base may move on the floor: it has a floor with friction, or it flew (a model with flight
    records ``u`` on the paper's floor too, 0 unless it flies: docs/model.md section 16)."""
    if "u" not in history:
        return False
    inputs = response.inputs
    return bool((inputs is not None and np.isfinite(inputs.settings["mu_s"])) or np.any(history["u"]))


def _slip_panel(ax, responses: dict, histories: dict, colours: dict) -> None:
    """The base's slip ``u(t)`` of each response on a floor with friction, in mm, its peak and residual said."""
    unit, scale = SLIP_UNIT
    for label, h in histories.items():
        r = responses[label]
        if not _slips(r, h):
            continue
        ax.plot(
            h["t"],
            h["u"] / scale,
            color=colours[label],
            label=f"{label}: peak {r.u_max / scale:.3g} {unit}, residual {r.u_end / scale:.3g} {unit}",
        )
    ax.axhline(0.0, color=GREY, lw=0.8)
    ax.set_ylabel(f"base slip u ({unit})")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.1, 1), fontsize=7, frameon=False)


def response_figure(
    responses: dict,
    block: Block,
    title: str = "",
    *,
    damper=None,
    model: str | None = None,
    motion=None,
    record: str = "",
    fig: Figure | None = None,
) -> Figure:
    """Recorded responses on shared time axes: ``theta / alpha``, the base's slip ``u`` (mm, for responses on a
    floor with friction), each coordinate of the damper, the ground.

    Parameters
    ----------
    responses : dict of str to Response
        Label to a response run with ``record=True``.
    block : Block
        The rocking block: ``theta / alpha`` with the lines ``theta = +-alpha``, the block's edge ``B/2`` on a
        stroke in m (a stroke past it is named above its panel), the ground acceleration in g.
    title : str
        First line of the title; default the excitation ``motion`` (:func:`motion_label`). The block and the
        damper follow.
    damper : Damper or dict, optional
        The damper (a ``Damper`` or a variant's parameters in SI): its stops ``+-L`` are marked on its stroke.
    model : str, optional
        The model of the damped responses (default: the ``omd`` family, a stroke ``x`` in m).
    motion : optional
        The ground motion of the responses (a pulse or a :class:`~rocking.model.motion.SampledMotion`).
    record : str, optional
        The name of a record ``motion`` was read from (its file), for the title.
    fig : Figure, optional
        An empty figure to draw in (a ``matplotlib.pyplot`` figure in a notebook, a subfigure); default a
        new one.

    Returns
    -------
    Figure
        ``fig``, or a new figure not attached to a canvas (:func:`plot_responses` saves it).
    """
    histories = {}
    for label, r in responses.items():
        if r.history is None:
            raise ValueError(f"response {label!r} was not recorded (record=True)")
        histories[label] = r.history
    names = list(
        dict.fromkeys(
            k
            for h in histories.values()
            for k in h
            if k not in NOT_COORDINATES and not (k.startswith("d") and k[1:] in h)
        )
    )
    units = {name: coordinate_unit(model, name) if model else "m" for name in names}
    slip = any(_slips(responses[label], h) for label, h in histories.items())
    fig = Figure(figsize=(8, 3 + 2 * (len(names) + slip)), layout="constrained") if fig is None else fig
    axes = fig.subplots(2 + slip + len(names), 1, sharex=True)
    ax_th, ax_g = axes[0], axes[-1]
    colours = dict(zip(histories, CYCLE))
    if slip:  # under the rotation; the loops below draw the other panels
        _slip_panel(axes[1], responses, histories, colours)
        axes = np.delete(axes, 1)
    for label, r in responses.items():
        h, colour = histories[label], colours[label]
        ax_th.plot(h["t"], h["theta"] / block.alpha, color=colour, label=label)
        for ax, name in zip(axes[1:-1], names):
            if name in h:
                ax.plot(h["t"], h[name], color=colour, label=label)
        if r.overturned:
            ax_th.axvline(r.t_overturn, color=colour, ls=":", lw=1.2, label=f"overturns ({label})")
            for ax in axes[1:]:
                ax.axvline(r.t_overturn, color=colour, ls=":", lw=1.2)
    ax_th.axhline(1, color=GREY, lw=0.8, ls="--", label=r"$\theta = \pm\alpha$")
    ax_th.axhline(-1, color=GREY, lw=0.8, ls="--")
    ax_th.set_ylabel(r"$\theta / \alpha$")
    _clip_overturned(ax_th, responses, histories, block.alpha, colours)
    L = _stroke(damper)
    for ax, name in zip(axes[1:-1], names):
        ax.set_ylabel(f"{name} ({units[name]})")
        if units[name] != "m":
            continue
        marks = [(block.B / 2, OKABE_ITO["vermillion"], "--", r"block's edge, $\pm B/2$")]
        marks += [] if L is None else [(L, OKABE_ITO["black"], "-.", r"stops, $\pm L$")]
        for value, colour, ls, label in marks:
            ax.axhline(value, color=colour, lw=0.9, ls=ls, label=f"{label} = $\\pm${value:.3g} m")
            ax.axhline(-value, color=colour, lw=0.9, ls=ls)
        _flag_past_edge(ax, past_edge(histories, name, block.B / 2))
    # One ground motion for every response: drawn once, in no response's colour, over the longest history (a
    # response that overturns stops early; the ground goes on).
    longest = max(histories.values(), key=lambda h: h["t"][-1])
    ax_g.plot(longest["t"], longest["ag"], color=OKABE_ITO["black"], lw=1.0, label="ground motion")
    ax_g.set_ylabel(r"$\ddot{x}_g$ (m/s$^2$)")
    ax_g.secondary_yaxis("right", functions=(lambda a: a / block.g, lambda a: a * block.g)).set_ylabel(
        r"$\ddot{x}_g$ (g)"
    )
    ax_g.set_xlabel("t (s)")
    # One legend of the responses, beside the first panel; the others name only their own lines.
    for ax in axes:
        ax.grid(True, alpha=0.3)
        handles, labels = ax.get_legend_handles_labels()
        own = [(h, text) for h, text in zip(handles, labels) if ax is ax_th or text not in responses]
        if own:
            ax.legend(*zip(*own), loc="upper left", bbox_to_anchor=(1.1, 1), fontsize=7, frameon=False)
    title = title or ("" if motion is None else motion_label(motion, block, record))
    fig.suptitle(
        (f"{title}\n" if title else "")
        + f"block H = {quantity(block.H, 'm')}, B = {quantity(block.B, 'm')}, M = {quantity(block.M, 'kg')}, "
        + f"e = {quantity(block.e, 'm', 3)} "
        + rf"($\alpha$ = {block.alpha:.3g} rad, p = {block.p:.3g} rad/s)"
        + f"\n{_damper_text(damper, model)}",
        fontsize=9,
    )
    return fig
