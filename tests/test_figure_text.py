"""Figures that never mislead (issue 38 item 6), read from the drawn artists: every text inside the canvas, no power
of ten in a title, legend entries that a reader tells apart, the ground motion drawn once, a record named."""

from __future__ import annotations

import re

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.text import Text

import rocking
from rocking import Block, Damper, Stops
from rocking.plot.figures import EFFECT_CLASSES, OUTCOME_CLASSES, map_figure
from rocking.plot.response import response_figure
from rocking.plot.style import LIGHT, quantity, symbol
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import overturning_map
from rocking.study.tiles import Execution

SERIAL = Execution(workers=1, progress=False)

#: A power of ten as Python's ``g`` format writes it (1.129e+04, 2e-05).
POWER_OF_TEN = re.compile(r"\de[+-]\d")


def drawn_texts(fig) -> list[Text]:
    """The visible, non-empty texts of ``fig`` once drawn (titles, labels, tick labels, legend entries): of the tick
    labels, those of the ticks in view (matplotlib keeps the others, undrawn)."""
    FigureCanvasAgg(fig).draw()
    axes = [ax for ax in fig.findobj(lambda a: hasattr(a, "_update_ticks"))]
    every_tick = {id(t) for axis in axes for t in axis.get_ticklabels(which="both")}
    drawn_ticks = {id(label) for axis in axes for tick in axis._update_ticks() for label in (tick.label1, tick.label2)}
    return [
        t
        for t in fig.findobj(Text)
        if t.get_visible() and t.get_text().strip() and (id(t) not in every_tick or id(t) in drawn_ticks)
    ]


def assert_inside_canvas(fig) -> None:
    """Every drawn text lies within the figure (one pixel of slack for antialiasing)."""
    texts = drawn_texts(fig)
    canvas, renderer = fig.bbox, fig.canvas.get_renderer()
    outside = [
        t.get_text()
        for t in texts
        if (box := t.get_window_extent(renderer)).x0 < canvas.x0 - 1
        or box.x1 > canvas.x1 + 1
        or box.y0 < canvas.y0 - 1
        or box.y1 > canvas.y1 + 1
    ]
    assert not outside, outside


def titles(fig) -> list[str]:
    """The figure's title and every axes' titles."""
    found = [fig._suptitle.get_text()] if fig._suptitle else []
    for ax in fig.axes:
        found += [ax.get_title(loc) for loc in ("left", "center", "right")]
    return [t for t in found if t]


def assert_no_power_of_ten(fig) -> None:
    bad = [t for t in titles(fig) if POWER_OF_TEN.search(t)]
    assert not bad, bad


def legends(fig) -> list:
    """Every legend of ``fig``: its axes' and its own."""
    return [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends)


def legend_entries(legend) -> list[tuple[str, tuple]]:
    """Each entry of ``legend`` (a Legend, or axes): its label and what a reader sees of its handle (colour, line
    style, marker and its face, fill, hatch)."""
    legend = legend.get_legend() if hasattr(legend, "get_legend") else legend
    if legend is None:
        return []
    entries = []
    for handle, text in zip(legend.legend_handles, legend.get_texts()):
        look = tuple(
            str(getter())
            for name in (
                "get_color",
                "get_linestyle",
                "get_marker",
                "get_markerfacecolor",
                "get_facecolor",
                "get_hatch",
            )
            if (getter := getattr(handle, name, None)) is not None
        )
        entries.append((text.get_text(), look))
    return entries


def assert_legends_distinct(fig) -> None:
    """No two entries of a legend share a label, nor (with different labels) a look."""
    for legend in legends(fig):
        entries = legend_entries(legend)
        entries = [(label, look) for label, look in entries if label.strip()]  # blanks pad a legend's columns
        labels = [label for label, _ in entries]
        looks = [look for _, look in entries]
        assert len(set(labels)) == len(labels), labels
        assert len(set(looks)) == len(looks), entries


def test_quantities_take_an_si_prefix_never_a_power_of_ten():
    """The issue's stiffnesses in engineering notation; values that read well as they are stay so."""
    assert quantity(11290.0, "N/m") == "11.29 kN/m"
    assert quantity(406500.0, "N/m") == "406.5 kN/m"
    assert quantity(1.285e6, "N/m") == "1.285 MN/m"
    assert quantity(3206.0, "N s/m") == "3.206 kN s/m"
    assert quantity(356.9, "N/m") == "356.9 N/m"
    assert quantity(0.005, "m") == "5 mm" and quantity(0.02, "m") == "0.02 m" and quantity(2.2, "m") == "2.2 m"
    assert quantity(350.0, "kg") == "350 kg" and quantity(-0.0, "N") == "0 N"
    assert quantity(999.96, "N/m") == "1 kN/m"  # rounded first, then prefixed
    assert not POWER_OF_TEN.search(quantity(1.2e5)) and "10^{5}" in quantity(1.2e5)
    assert symbol("k_m") == "$k_{m}$" and symbol("L") == "L" and symbol("a$b") == r"a\$b"


#: The issue's showcase (a 2.2 m x 0.6 m, 350 kg cabinet, e = 2 cm): its damper's line was clipped at both edges.
SHOWCASE = Block(H=2.2, B=0.6, M=350.0, e=0.02)


def _stops_responses():
    block = SHOWCASE
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    damper = Damper(damper.m, damper.k_m, damper.c, damper.h, stops=Stops.at_edges(block, damper))
    pulse = rocking.OneSinePulse.from_nondim(block, beta=2.0, Omega=3.0)
    responses = {
        "with damper": rocking.simulate(block, damper, pulse, record=True, early_verdict=False),
        "block alone": rocking.simulate(block, None, pulse, record=True, early_verdict=False),
    }
    return block, damper, pulse, responses


@pytest.fixture(scope="module")
def stops_run():
    return _stops_responses()


def test_a_response_with_stops_keeps_its_title_on_the_canvas_in_si_prefixes(stops_run):
    """``simulate --plot`` with stops: the damper's line (m, k_m, c, h, L, k_b, c_b) fits the figure, its names
    in mathtext ($k_m$, never a raw k_m) and its stiffnesses with a prefix (no 1.285e+06)."""
    block, damper, pulse, responses = stops_run
    fig = response_figure(responses, block, damper=damper, motion=pulse)
    assert_inside_canvas(fig)
    assert_no_power_of_ten(fig)
    title = fig._suptitle.get_text()
    assert f"$k_{{b}}$ = {quantity(damper.stops.k_b, 'N/m')}" in title and "kN/m" in title or "MN/m" in title
    assert "k_m =" not in title.replace("$k_{m}$ =", "") and "$k_{m}$ = " in title
    assert_legends_distinct(fig)


def test_the_ground_motion_is_drawn_once_in_no_responses_colour(stops_run):
    """The block alone overturns first: the ground goes on to the end of the longest run, one line, labelled (it
    was drawn per response, in the block alone's colour until it overturned, then in the damper's)."""
    block, damper, pulse, responses = stops_run
    ends = {label: r.history["t"][-1] for label, r in responses.items()}
    assert responses["block alone"].overturned and ends["block alone"] < ends["with damper"]
    fig = response_figure(responses, block, damper=damper, motion=pulse)
    ax_th, ax_g = fig.axes[0], fig.axes[2]
    colours = {line.get_label(): line.get_color() for line in ax_th.get_lines()}
    ground = [line for line in ax_g.get_lines() if len(line.get_xdata()) > 2]
    assert len(ground) == 1 and ground[0].get_label() == "ground motion"
    assert ground[0].get_color() not in (colours["with damper"], colours["block alone"])
    assert ground[0].get_xdata()[-1] == ends["with damper"]
    assert "ground motion" in [label for label, _ in legend_entries(ax_g)]


def test_a_records_response_names_the_record():
    block = Block.reference()
    record = rocking.SampledMotion(np.sin(np.linspace(0.0, 6.0, 200)), dt=0.01)
    responses = {"block alone": rocking.simulate(block, None, record, record=True)}
    fig = response_figure(responses, block, motion=record, record="RSN1063_NORTHR_RRS228.AT2")
    assert fig._suptitle.get_text().startswith("record RSN1063_NORTHR_RRS228.AT2: PGA = 1 m/s$^2$")
    assert_inside_canvas(fig)


def test_map_classes_never_share_a_look_across_the_panels():
    """A reader matches the effect panel's classes against the outcome panels' legend: no effect class looks like an
    outcome class (the stroke not computed was yellow with dots, as "after 2 impacts"), and the saved cells of
    unknown stroke are a kind of saved (its blue), told apart by their hatch."""
    looks = [(colour.lower(), hatch) for _, colour, hatch in (*OUTCOME_CLASSES, *EFFECT_CLASSES)]
    shared = {look for look in looks if looks.count(look) > 1}
    assert shared == {(LIGHT.lower(), "")}  # the safe background, "safe" and "safe either way"
    saved, unknown = EFFECT_CLASSES[1], EFFECT_CLASSES[5]
    assert unknown[0].startswith(saved[0]) and unknown[1] == saved[1] and unknown[2]


@pytest.fixture(scope="module")
def adaptive_map(tmp_path_factory):
    return overturning_map(
        Setting(Block.reference()),
        Tuning(0.05),
        Grid("Omega", 0.5, 15.0, 32),
        Grid("beta", 1.0, 15.0, 32),
        SERIAL,
        runs=tmp_path_factory.mktemp("map"),
        coarse=8,
    )


def test_an_adaptive_map_names_its_saved_cells_of_unknown_stroke_distinctly(adaptive_map):
    fig = map_figure(adaptive_map)
    labels = [label for legend in legends(fig) for label, _ in legend_entries(legend)]
    assert EFFECT_CLASSES[5][0] in labels
    assert_legends_distinct(fig)
    assert_inside_canvas(fig)
    assert_no_power_of_ten(fig)


def test_the_threshold_legends_list_what_is_drawn_each_entry_its_own_look(small_threshold):
    """The right panel's unlimited and stops entries differ (as in the left panel: open markers for the stops); the
    middle legend has an Omega* star only where one is drawn; every dotted line's meaning has a dotted entry."""
    from rocking.plot.figures import threshold_figure

    fig = threshold_figure(small_threshold)
    assert_legends_distinct(fig)
    assert_inside_canvas(fig)
    assert_no_power_of_ten(fig)
    ax_gain, ax_omega, ax_curve = fig.axes[:3]
    stars = [line for line in ax_omega.get_lines() if line.get_marker() == "*" and np.isfinite(line.get_ydata()).any()]
    starred = any(look[2] == "*" for _, look in legend_entries(ax_omega))
    assert starred == bool(stars)
    for ax in (ax_omega, ax_curve):
        dotted = [line for line in ax.get_lines() if line.get_linestyle() == ":"]
        entries = [look for _, look in legend_entries(ax) if ":" in look]
        assert not dotted or entries, ax.get_title()
    right = dict(legend_entries(ax_curve))
    lam = small_threshold.data["lam"].values[0]
    # Dashes do not show in a legend's short line: the marker's face tells them apart (index 3 of the look).
    assert right[rf"$\lambda$ = {lam:.3g}, unlimited"][3] != right[rf"$\lambda$ = {lam:.3g}, stops"][3]


@pytest.mark.parametrize("layout", [None, "constrained"])
def test_a_map_drawn_in_the_users_axes_keeps_its_title_and_legends_clear(adaptive_map, layout):
    """Into a figure of the user's own axes (pyplot's default layout, or a constrained one): the title overlaps no
    panel, and no text leaves the canvas."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(15, 6.5), layout=layout)
    axes = fig.subplots(1, 3)
    map_figure(adaptive_map, ax=axes)
    assert_inside_canvas(fig)
    renderer = fig.canvas.get_renderer()
    title = fig._suptitle.get_window_extent(renderer)
    for ax in axes:
        assert not title.overlaps(ax.get_tightbbox(renderer)), ax.get_title()


def test_long_title_lines_break_at_commas_never_inside_mathtext():
    from rocking.plot.style import broken, fit

    assert broken(r"a $\beta$ the scan, only $a, b$ bounds", 12) == "a $\\beta$ the scan,\nonly $a, b$ bounds"
    assert broken("the worse direction with the damper", 15, " ") == "the worse\ndirection with\nthe damper"
    assert fit("short, line", 8.0, 10) == "short, line"


@pytest.fixture(scope="module")
def vertical_spectra(tmp_path_factory):
    import warnings

    runs = tmp_path_factory.mktemp("vertical")
    studies = []
    for ratio in (0.0, 1.0):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the flights past beta_f, which the figure draws
            studies.append(
                rocking.minimum_overturning_spectrum(
                    Block.reference(),
                    Tuning(0.05),
                    Omega=[10.0, 12.0],
                    beta=Grid("beta", 0.5, 8.0, 16),
                    vertical_ratio=ratio,
                    runs=runs / f"{ratio:g}",
                    workers=1,
                    progress=False,
                    study=True,
                )
            )
    return studies


def test_the_vertical_spectra_legend_has_a_column_per_ratio_and_bounds_side_by_side(vertical_spectra):
    """Each ratio's entries in one column of the legend (they were split across columns), and the lower bounds of
    the block alone and with the damper, at the same scan's end, side by side (they were drawn one over the
    other), the block alone's open, the damper's filled."""
    from matplotlib.container import ErrorbarContainer

    from rocking.plot.figures import vertical_spectra_figure

    fig = vertical_spectra_figure(vertical_spectra)
    assert_inside_canvas(fig)
    assert_legends_distinct(fig)
    (legend,) = fig.legends
    columns = legend._legend_handle_box.get_children()
    ratios = [
        {t.get_text().split(",")[0].split(":")[0] for t in column.findobj(Text) if t.get_text().startswith("r =")}
        for column in columns
    ]
    assert [r for r in ratios if r] == [{"r = 0"}, {"r = 1"}]
    for ax in fig.axes[:2]:
        bounds = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
        points = [(x, y) for c in bounds for x, y in zip(c.lines[0].get_xdata(), c.lines[0].get_ydata())]
        assert bounds and len(set(points)) == len(points)
        faces = {c.lines[0].get_markerfacecolor() for c in bounds}
        assert "white" in faces and len(faces) > 1


def test_a_fragility_grid_shows_the_block_alone_beside_the_damper(tmp_path):
    """Each motion's cell at each level tells both blocks apart (safe either way, saved, lost, overturned either way),
    as a map's effect panel: it showed only "with the damper"."""
    from rocking.plot.figures import ida_figure
    from rocking.study.ida import envelope

    pulses = [rocking.RickerWavelet.from_period(3.0, T) for T in (0.6, 1.3, 1.6)]
    study = rocking.fragility(
        Block.reference(),
        Tuning(0.1),
        motions=pulses,
        levels=[2.0, 4.0, 8.0, 16.0],
        im="pga",
        t_after=3.0,
        runs=tmp_path,
        workers=1,
        progress=False,
        study=True,
    )
    fig = ida_figure(study)
    ax_m = fig.axes[1]
    over = envelope(study.data)["overturned"]
    expected = (over.sel(part="bare").values == 1) + 2 * (over.sel(part="damper").values == 1)
    (cells,) = [a for a in (*ax_m.images, *ax_m.collections) if getattr(a, "get_array", lambda: None)() is not None]
    np.testing.assert_array_equal(np.asarray(cells.get_array()).reshape(expected.shape), expected)
    assert (expected == 1).any()  # the damper saves some: the old grid drew these as plain "safe"
    labels = [label for label, _ in legend_entries(ax_m)]
    assert EFFECT_CLASSES[1][0] in labels and "block alone" in ax_m.get_title()
    assert_inside_canvas(fig)
    assert_legends_distinct(fig)
