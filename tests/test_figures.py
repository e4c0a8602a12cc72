"""The figures say what they show: the block, the damper and the pulses by their values, dimensional axes,
a palette that colour-blind readers and grey prints tell apart, bounds apart from measured values."""

from __future__ import annotations

import colorsys
import dataclasses

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import to_hex, to_rgb
from matplotlib.container import ErrorbarContainer
from matplotlib.figure import Figure

import rocking
from rocking import Block, Damper, Stops
from rocking.plot import figures
from rocking.plot.figures import EFFECT_CLASSES, OUTCOME_CLASSES, map_figure, spectrum_figure
from rocking.plot.response import coordinate_unit, response_figure
from rocking.plot.style import GREY, LIGHT, OKABE_ITO, extend
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import overturning_map
from rocking.study.spectrum import envelope as spectrum_envelope
from rocking.study.spectrum import minimum_overturning_spectrum, safe_windows, spectrum_data, spectrum_tables
from rocking.study.storage import load, save
from rocking.study.tiles import Execution
from rocking.study.vocabulary import BRACKETED

SERIAL = Execution(workers=1, progress=False)
CABINET = Block(H=1.2, B=0.4, M=300.0)
PALETTE = {c.lower() for c in (*OKABE_ITO.values(), LIGHT, GREY)}


def _hue(colour) -> tuple[float, float]:
    h, _, s = colorsys.rgb_to_hls(*to_rgb(colour))
    return 360 * h, s


def _red_green_pair(colours) -> bool:
    """True if the colours hold a saturated red and a saturated green (the pair deuteranopes confuse)."""
    hues = [_hue(c) for c in colours]
    red = any((h < 15 or h > 345) and s > 0.3 for h, s in hues)
    green = any(75 < h < 160 and s > 0.3 for h, s in hues)
    return red and green


@pytest.fixture(scope="module")
def cabinet_map(tmp_path_factory):
    runs = tmp_path_factory.mktemp("map")
    tuning = Tuning(0.1, omega_ratio=2.0, stops=True)
    return overturning_map(
        Setting(CABINET), tuning, Grid("Omega", 1.0, 10.0, 8), Grid("beta", 1.0, 10.0, 8), SERIAL, runs=runs, full=True
    )


def test_the_map_title_names_the_block_the_damper_and_the_pulses_and_a_redrawn_one_the_same(cabinet_map, tmp_path):
    title = map_figure(cabinet_map)._suptitle.get_text()
    for text in (
        "H = 1.2 m",
        "B = 0.4 m",
        "M = 300 kg",
        r"$\alpha$ = 0.322 rad",
        "p = 3.41 rad/s",
        r"$\gamma$ = 0.1",
        r"$\omega_m / p$ = 2",
        r"$\zeta$ = 0.05",
        "h = 0.05 m",
        "stops at L = 0.18 m",
        "one-sine pulse",
        r"$a_g$ = 0.333 $\beta$ g",
    ):
        assert text in title, text
    save(cabinet_map, tmp_path, "map")
    assert map_figure(load(tmp_path / "map"))._suptitle.get_text() == title


def test_the_map_has_dimensional_axes_for_its_block(cabinet_map):
    fig = map_figure(cabinet_map)
    FigureCanvasAgg(fig).draw()
    top = fig.axes[0].child_axes[0]
    assert "T_g" in top.get_xlabel()
    # Omega = 2 of this block: T_g = 2 pi / (2 p).
    tick = min(top.get_xticks(), key=lambda T: abs(2 * np.pi / (CABINET.p * T) - 2))
    right = fig.axes[2].child_axes[-1]
    assert "a_g" in right.get_ylabel() and "(g)" in right.get_ylabel()
    assert right._functions[0](np.array([3.0])) == pytest.approx(3.0 * CABINET.tan_alpha)
    assert tick > 0


def test_the_map_colours_come_from_the_palette_without_a_red_green_pair_and_classes_are_hatched(cabinet_map):
    fig = map_figure(cabinet_map)
    used = set()
    for ax in fig.axes[:3]:
        (image,) = ax.images
        used |= {to_hex(c) for c in image.cmap(np.arange(image.cmap.N))}
    assert used <= PALETTE
    assert not _red_green_pair(used)
    for classes in (OUTCOME_CLASSES, EFFECT_CLASSES):
        # Each class its own look (colour and hatch: saved cells of unknown stroke share the saved blue).
        looks = [(c, h) for _, c, h in classes]
        assert len(set(looks)) == len(looks) and not _red_green_pair([c for c, _ in looks])
    # Saved and lost differ in grey print: by hatch.
    hatches = {label: hatch for label, _, hatch in EFFECT_CLASSES}
    assert hatches["lost with the damper"] != hatches["saved by the damper"]
    legends = [patch for legend in fig.legends for patch in legend.get_patches()]
    assert {p.get_label() for p in legends if p.get_hatch()} and all(ax.get_legend() is None for ax in fig.axes[:3])


def test_the_reference_block_and_the_cabinet_get_different_titles(cabinet_map):
    a = dict(cabinet_map.config)
    reference = dataclasses.replace(cabinet_map, config={**a, "block": Block.reference().as_params()})
    assert map_figure(reference)._suptitle.get_text() != map_figure(cabinet_map)._suptitle.get_text()


@pytest.fixture(scope="module")
def spectrum(tmp_path_factory):
    runs = tmp_path_factory.mktemp("spectrum")
    return minimum_overturning_spectrum(
        Setting(Block.reference()),
        Tuning(0.05),
        Grid("Omega", 2.0, 12.0, 6),
        Grid("beta", 0.5, 12.0, 24),
        SERIAL,
        runs=runs,
    )


def test_the_spectrum_draws_bounds_apart_from_measured_values_and_its_windows(spectrum):
    both = spectrum_envelope(spectrum.data)
    flag = both["flag"].sel(part="damper").values
    fig = spectrum_figure(spectrum)
    ax, ax_gain = fig.axes[:2]
    assert (flag != BRACKETED).any(), "a spectrum with bounds"
    damper = next(line for line in ax.get_lines() if line.get_label().endswith("with damper"))
    measured = np.isfinite(damper.get_ydata())
    assert np.array_equal(measured, flag == BRACKETED)
    # The bounds: open triangles with arrows (error bars with limits), in the legend once, in grey.
    bounds = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
    assert bounds and all(c.has_yerr and c.lines[0].get_markerfacecolor() == "white" for c in bounds)
    labels = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert figures.LOWER_BOUND in labels
    gain_line = ax_gain.get_lines()[0]
    assert not np.isfinite(gain_line.get_ydata()[flag != BRACKETED]).any()
    windows = [p for p in ax.patches if p.get_height() > 0]
    assert len(windows) == sum(len(safe_windows(both, part)) for part in ("bare", "damper"))
    assert all(p.get_alpha() >= 0.3 and p.get_hatch() for p in windows)
    assert ax.get_legend() is None and ax_gain.get_legend() is None


def test_a_gain_colour_bar_spans_its_data_and_extends_past_its_cap():
    norm, ext = figures._gain_norm([0.6, 1.0, 3.8, np.nan])
    assert norm.vmin <= 0.6 and norm.vmax >= 3.8 and ext == "neither"
    for low in (0.2, 0.3, 1 / 3.8, 0.7 / 3):  # the least gain sets the span: the bar still holds it
        norm, ext = figures._gain_norm([low, 1.0, 1.5])
        assert norm.vmin <= low and norm.vmax * low == pytest.approx(1.0) and ext == "neither"
    norm, ext = figures._gain_norm([0.01, 1.0, 50.0])
    assert norm.vmax == pytest.approx(figures.GAIN_SPAN) and ext == "both"
    assert extend([1, 2], 0, 1.5) == "max" and extend([np.nan, 1.0], 0, 2) == "neither"


def test_a_gain_colour_bar_beyond_its_cap_is_extended(monkeypatch):
    """Gains reach 3.8 on a scale capped at 2: the bar's top is an extension, not a silent clip."""
    from matplotlib.figure import Figure

    monkeypatch.setattr(figures, "GAIN_SPAN", 2.0)
    gains = np.array([[0.7, 1.0], [1.5, 3.8]])
    fig = Figure()
    ax = fig.subplots()
    norm, extension = figures._gain_norm(gains)
    image = ax.pcolormesh(gains, norm=norm)
    figures._gain_colorbar(fig, image, ax, "G", extension)
    bar = fig.axes[-1]._colorbar
    assert bar.extend == "max" and norm.vmax == pytest.approx(2.0)
    assert 1.0 in bar.get_ticks()


def _responses(damper, model=None, **params):
    block = Block.reference()
    pulse = rocking.OneSinePulse.from_nondim(block, beta=4.0, Omega=3.0)
    kwargs = {"model": model} if model else {}
    return block, {
        "with damper": rocking.simulate(block, damper, pulse, record=True, early_verdict=False, **kwargs),
        "block alone": rocking.simulate(block, None, pulse, record=True, early_verdict=False),
    }


def test_the_response_figure_labels_alpha_the_edge_and_the_stops():
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    damper = Damper(damper.m, damper.k_m, damper.c, damper.h, stops=Stops.at_edges(block, damper))
    block, responses = _responses(damper)
    fig = response_figure(responses, block, "pulse", damper=damper)
    ax_th, ax_x = fig.axes[:2]
    assert any(line.get_label() == r"$\theta = \pm\alpha$" for line in ax_th.get_lines())
    labels = [line.get_label() for line in ax_x.get_lines()]
    L = damper.stops.L
    assert any(label.startswith(r"stops, $\pm L$") and f"{L:.3g} m" in label for label in labels)
    assert any(label.startswith("block's edge") for label in labels)
    assert sorted(line.get_ydata()[0] for line in ax_x.get_lines() if line.get_linestyle() == "-.") == [-L, L]
    assert ax_x.get_ylabel() == "x (m)" and "H = 2 m" in fig._suptitle.get_text()


def test_the_response_title_names_the_excitation_and_the_damper_with_units():
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    block, responses = _responses(damper)
    pulse = rocking.OneSinePulse.from_nondim(block, beta=4.0, Omega=3.0)
    title = response_figure(responses, block, damper=damper, motion=pulse)._suptitle.get_text()
    a_g, T_g = 4.0 * block.g * block.tan_alpha, 2 * np.pi / (3.0 * block.p)  # docs/model.md section 9
    for text in (
        "one-sine pulse",
        f"{a_g:.3g} m/s$^2$",
        f"({a_g / block.g:.3g} g)",
        f"$T_g$ = {T_g:.3g} s",
        r"$\beta$ = 4",
        r"$\Omega$ = 3",
        "m = 50 kg",
        f"$k_{{m}}$ = {damper.k_m:.4g} N/m",
        "c = ",
        " N s/m",
    ):
        assert text in title, text
    record = rocking.SampledMotion([0.0, 2.0, -3.0, 0.0], dt=0.1, sign=-1)
    assert (
        response_figure(responses, block, motion=record)
        ._suptitle.get_text()
        .startswith("sampled motion: PGA = 3 m/s$^2$ (0.306 g), 0.3 s, sign -1")
    )


def test_the_pendulum_gets_its_own_panel_in_radians():
    params = {"m": 50.0, "l": 0.5, "x_p": 0.0, "y_p": 2.0, "k_phi": 100.0, "c_phi": 10.0}
    block, responses = _responses(params, model="pendulum")
    fig = response_figure(responses, block, damper=params, model="pendulum")
    ax_phi = fig.axes[1]
    assert ax_phi.get_ylabel() == "phi (rad)"
    assert "l = 0.5 m" in fig._suptitle.get_text() and "$c_{phi}$ = 10 N m s/rad" in fig._suptitle.get_text()
    data = ax_phi.get_lines()[0].get_ydata()
    assert data.size > 10 and np.abs(data).max() > 0
    assert coordinate_unit("pendulum", "phi") == "rad" and coordinate_unit("omd", "x") == "m"
    assert [coordinate_unit("omd2", name) for name in ("x1", "x2")] == ["m", "m"]


def test_period_ticks_stay_away_from_an_axis_that_starts_at_omega_zero(cabinet_map):
    """Towards Omega = 0 the period grows without bound: no tick of thousands of seconds at the axis' end."""
    fig = spectrum_figure_of(cabinet_map.config, [0.05, 5.0, 10.0])
    FigureCanvasAgg(fig).draw()
    ax = fig.axes[0]
    low, high = ax.get_xlim()
    ticks = ax.child_axes[0].get_xticks()
    first = min(2 * np.pi / (CABINET.p * T) for T in ticks)
    assert first >= low + 0.08 * (high - low)


def spectrum_figure_of(config: dict, Omega, above=()):
    """A spectrum figure of made-up values over ``Omega``, one direction, no window; at the indices ``above``
    neither part overturns in the scan (0.5 to 15): its ``beta_min`` is 15, a lower bound."""
    from rocking.study.vocabulary import ABOVE

    Om = np.asarray(Omega, float)
    shape = (2, Om.size, 1)  # part, Omega, sign
    fields = {
        "beta_min": np.broadcast_to(1 + Om[None, :, None], shape).copy(),
        "beta_safe": np.full(shape, np.nan),
        **{k: np.full(shape, BRACKETED if k == "flag" else 0) for k in ("flag", "impacts", "undetermined")},
        "scan_outcome": np.full((*shape, 5), -1),
    }
    fields["flag"][:, list(above)] = ABOVE
    fields["beta_min"][:, list(above)] = 15.0
    config = {**config, "directions": {"directions": "positive", "signs": [1]}}
    data = spectrum_data(config, Om, np.linspace(0.5, 15, 5), [1], fields)
    return spectrum_figure(rocking.Study("spectrum", config, data, tabulate=spectrum_tables))


def test_ida_levels_over_decades_in_log_scale_and_the_title_says_motions(tmp_path):
    from rocking.plot.figures import ida_figure

    pulses = [rocking.RickerWavelet.from_period(3.0, T) for T in (0.5, 1.0, 2.0)]
    study = rocking.incremental_dynamic_analysis(
        Block.reference(),
        motions=pulses,
        scales=[0.5, 2.0, 8.0],
        t_after=3.0,
        runs=tmp_path,
        workers=1,
        progress=False,
        study=True,
    )
    fig = ida_figure(study)
    assert [ax.get_xscale() for ax in fig.axes[:2]] == ["log", "log"]
    assert fig.axes[0].get_xlabel() == "scale factor"
    assert "motions of both signs" in fig._suptitle.get_text()


def test_the_response_figure_names_a_stroke_past_the_edge():
    """Unlimited guide on the reference block at beta 4, Omega 3: the mass leaves the block, and its panel says so."""
    damper = Damper.from_nondim(Block.reference(), gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    block, responses = _responses(damper)
    assert responses["with damper"].x_max > block.B / 2  # the premise
    ax_x = response_figure(responses, block, damper=damper).axes[1]
    assert ax_x.get_title(loc="left").startswith("mass past the block's edge: with damper")
    stops = Damper(damper.m, damper.k_m, damper.c, damper.h, stops=Stops.at_edges(block, damper))
    block, held = _responses(stops)
    assert held["with damper"].x_max <= block.B / 2  # the premise: the pads hold it
    assert response_figure(held, block, damper=stops).axes[1].get_title(loc="left") == ""


def test_an_overturning_block_does_not_squeeze_the_response_that_stays_up():
    """Omega = 6, beta = 3: the block alone overturns, the damped block stays up at 0.53 alpha; the axis ends
    1.25 alpha out (the overturned angle runs to pi / (2 alpha) = 6.1), with a marker where it leaves."""
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    pulse = rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=6.0)
    responses = {
        "with damper": rocking.simulate(block, damper, pulse, record=True),
        "block alone": rocking.simulate(block, None, pulse, record=True),
    }
    assert responses["block alone"].overturned and not responses["with damper"].overturned
    ax = response_figure(responses, block, damper=damper, motion=pulse).axes[0]
    assert ax.get_ylim() == (-1.25, 1.25)
    assert 0.3 < responses["with damper"].theta_max / block.alpha < 1.25
    assert [t.get_text() for t in ax.texts] == ["overturns (block alone)"]


def test_an_mp_title_names_its_amplitude_parameter_and_gives_its_peak():
    """The MP pulse's amplitude parameter is not its peak (docs/model.md section 12): the title gives both,
    the peak equal to the largest |ddx_g| of a 200,001-point scan within 1 %, and gamma_MP by that name."""
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    pulse = rocking.MavroeidisPapageorgiou(5.0, 4.0, gamma_mp=2.0, nu=0.5)
    responses = {"with damper": rocking.simulate(block, damper, pulse, record=True)}
    title = response_figure(responses, block, damper=damper, motion=pulse)._suptitle.get_text()
    scanned = np.max(np.abs(pulse.acceleration(np.linspace(0.0, pulse.t_p, 200_001))))
    shown = float(title.split("peak ")[1].split(" m/s")[0])
    assert shown == pytest.approx(scanned, rel=0.01) and abs(shown - 5.0) > 0.1
    assert r"amplitude $a_g$ = 5 m/s$^2$" in title and r"$\gamma_{MP}$ = 2" in title


def test_a_response_plots_itself_on_given_axes_or_a_new_figure():
    """Response.plot draws theta/alpha over t (the recorded samples, divided by atan(B/H) of the block that
    ran), returns the figure; response_figure draws in a figure it is given."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    pulse = rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=6.0)
    response = rocking.simulate(block, damper, pulse, record=True)
    fig, ax = plt.subplots()
    assert response.plot(ax=ax) is fig
    (line,) = [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2]
    np.testing.assert_array_equal(line.get_ydata(), response.history["theta"] / np.arctan(0.5 / 2.0))
    new = response.plot()
    assert new is not fig and new.axes[0].get_ylabel() == r"$\theta / \alpha$"
    plt.close("all")
    with pytest.raises(rocking.ParameterError, match=r"record=True"):
        rocking.simulate(block, damper, pulse).plot()
    given = Figure()
    assert response_figure({"with damper": response}, block, fig=given) is given and len(given.axes) == 3


def test_a_response_shows_rounded_values_in_the_words_of_the_docs():
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    response = rocking.simulate(block, damper, rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=4.0))
    html = response._repr_html_()
    assert "STATUSES" not in html and "q[1]" not in html and "largest |x|" in html
    assert f"<td>{response.theta_max:.4g}</td>" in html and f"{response.theta_max!r}" not in html
    assert "why the run ended: |theta| reached pi/2" in html


def test_a_records_history_and_plot_show_its_peak():
    """A record at 0.01 s is recorded and drawn at its own samples (the block's 2 pi / p / 100 is 0.0235 s):
    the ground panel's peak is the record's PGA within 1 % (the issue's 5.58 against 6.87 m/s^2)."""
    block = Block.reference()
    record = rocking.SampledMotion(np.random.default_rng(5).normal(0.0, 2.0, 1000), dt=0.01)
    response = rocking.simulate(block, None, record, record=True)
    assert np.diff(response.history["t"]).max() <= 0.01 * (1 + 1e-9)
    ax_g = response_figure({"block alone": response}, block, motion=record).axes[-1]
    drawn = max(np.max(np.abs(line.get_ydata())) for line in ax_g.get_lines() if len(line.get_xdata()) > 2)
    assert drawn == pytest.approx(record.pga, rel=0.01)


def test_a_class_region_is_few_rectangles_that_tile_exactly_its_cells():
    """The rectangles of figures._runs cover every cell of the mask once and no other; a band of 1,000 cells a
    row wide and 40 rows deep is one rectangle, a checkerboard one per cell."""
    rng = np.random.default_rng(3)
    for mask in (rng.random((37, 23)) < 0.4, np.ones((1000, 40), bool), np.indices((6, 5)).sum(0) % 2 == 0):
        covered = np.zeros(mask.shape, int)
        for i0, i1, j0, j1 in figures._runs(mask):
            covered[i0:i1, j0:j1] += 1
        np.testing.assert_array_equal(covered, mask.astype(int))
    assert len(figures._runs(np.ones((1000, 40), bool))) == 1
    assert len(figures._runs(np.indices((6, 5)).sum(0) % 2 == 0)) == 15


@pytest.mark.parametrize("n", [8, 300])
def test_a_map_draws_one_image_and_one_region_per_hatch_whatever_its_size(cabinet_map, n):
    """Issue 28 target 0: the artists of a class map do not grow with its cells (a 300 x 300 map of noisy
    classes, 90,000 cells, has the 8 x 8 map's artists), and the hatched regions are rasterized."""
    study = _resampled_map(cabinet_map, n)
    fig = map_figure(study)
    for ax in fig.axes[:3]:
        assert len(ax.images) == 1 and not ax.collections
        regions = [p for p in ax.artists + ax.patches if p.get_hatch()]
        assert len(regions) <= 3 and all(r.get_rasterized() for r in regions)


def _resampled_map(study, n: int):
    """``study`` with random outcomes on an ``n x n`` grid over the same ranges (the registry's schema)."""
    from rocking.study.overturning_map import map_data, map_summary

    rng = np.random.default_rng(n)
    Om, beta = np.linspace(1.0, 10.0, n), np.linspace(1.0, 10.0, n)
    shape = (2, n, n, 1)
    over = rng.random(shape) < 0.6
    fields = {
        "overturned": over,
        "impacts": np.where(over, rng.integers(0, 5, shape), 0),
        "theta_max": np.where(over, np.pi / 2, 0.1),
        "x_max": np.full(shape, 0.1),
        **{k: np.zeros(shape, int) for k in ("status", "stop_contacts")},
        "bumper_force_max": np.zeros(shape),
    }
    config = {**study.config, **{k: {**study.config[k], "n": n} for k in ("Omega", "beta")}}
    data = map_data(config, Om, beta, [1], fields, np.ones((2, n, n), bool))
    return dataclasses.replace(study, config=config, data=data, summary=map_summary(data, CABINET.B / 2))


def test_every_figure_function_draws_in_a_figure_or_axes_it_is_given(cabinet_map, spectrum):
    """As pandas and xarray do: ``fig=`` draws in that figure, ``ax=`` in those axes (one per panel), and the
    figure drawn in is returned; each function's docstring says so."""
    for name in ("map_figure", "spectrum_figure", "optimize_figure", "design_figure", "threshold_figure", "ida_figure"):
        doc = getattr(figures, name).__doc__
        assert "fig : Figure, optional" in doc and "ax : sequence of Axes, optional" in doc, name
    given = Figure()
    assert map_figure(cabinet_map, fig=given) is given and len(given.axes) >= 3
    outer = Figure()
    left, right = outer.subfigures(1, 2)
    assert spectrum_figure(spectrum, fig=right) is right and not left.axes and len(right.axes) >= 2
    host = Figure()
    axes = host.subplots(1, 3)
    assert map_figure(cabinet_map, ax=axes) is host and all(ax.images for ax in axes)
    with pytest.raises(rocking.ParameterError, match="needs 2 axes"):
        spectrum_figure(spectrum, ax=axes)


def test_ida_names_its_motions_and_writes_its_measure_with_its_unit(tmp_path):
    """Two pulses scaled to a PGA: one tick per motion at 0 and 1 with the suite's names (not -0.5 ... 1.5),
    "PGA (m/s$^2$)" on the level axes, the fit's median without a power of ten."""
    from rocking.plot.figures import ida_figure
    from rocking.study.suite import motion_names

    pulses = [rocking.RickerWavelet.from_period(3.0, T) for T in (0.5, 1.0)]
    study = rocking.fragility(
        Block.reference(),
        motions=pulses,
        levels=[1.0, 3.0, 9.0, 27.0],
        im="pga",
        t_after=3.0,
        runs=tmp_path,
        workers=1,
        progress=False,
        study=True,
    )
    fig = ida_figure(study)
    FigureCanvasAgg(fig).draw()
    ax_f, ax_m = fig.axes[:2]
    names = motion_names(study.config["suite"])
    assert names[0].startswith("ricker") and len(names) == 2
    assert list(ax_m.get_yticks()) == [0, 1] and [t.get_text() for t in ax_m.get_yticklabels()] == names
    assert ax_m.get_ylim() == (-0.5, 1.5)
    assert ax_f.get_xlabel() == ax_m.get_xlabel() == "PGA (m/s$^2$)"
    texts = [t.get_text() for t in ax_f.get_legend().get_texts()] + [fig._suptitle.get_text()]
    assert not any("e+" in t or "e-0" in t for t in texts)
    fitted = study.data["median"].dropna("part")  # a curve, and its legend, only where the fit gives one
    assert fitted.size > 0
    for part in fitted["part"].values:
        dispersion = float(study.data["dispersion"].sel(part=part))
        assert sum("lognormal fit: median" in t and f"dispersion {dispersion:.2f}" in t for t in texts) >= 1


def test_readable_numbers_have_no_power_of_ten():
    assert [figures._readable(v) for v in (407123.0, 0.0021345, 2.5, 1.0)] == ["407000", "0.00213", "2.5", "1"]


def test_map_axes_start_at_zero_and_say_one_cell_in_the_singular(cabinet_map):
    """A 4 x 4 map from Omega = 0.5, beta = 0.5 in steps of 1 would reach -0.0 and 0 half a step out: its axes
    stop at 0; the effect's title counts "1 cell saved", not "1 cells"."""
    study = _resampled_map(cabinet_map, 4)
    data = study.data.assign_coords(Omega=[0.3, 1.3, 2.3, 3.3], beta=[0.2, 1.2, 2.2, 3.2])
    one = dataclasses.replace(study, data=data, summary={**study.summary, "saved": 1})
    fig = map_figure(one)
    for ax in fig.axes[:3]:
        assert ax.get_xlim()[0] == 0.0 and ax.get_ylim()[0] == 0.0
    assert "1 cell saved" in fig.axes[2].get_title()
    assert figures._cells(2) == "2 cells"


def test_the_map_legend_lists_the_classes_that_occur_and_its_secondary_axes_read_as_its_own(cabinet_map):
    """Classes 'after 2 impacts' and 'after 3 or more impacts' absent from both panels: not in the legend; the
    a_g (g) and T_g (s) labels as large as the beta and Omega labels."""
    study = _resampled_map(cabinet_map, 6)
    impacts = np.minimum(study.data["impacts"].values, 1)
    study = dataclasses.replace(study, data=study.data.assign(impacts=study.data["impacts"].copy(data=impacts)))
    fig = map_figure(study)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "after 2 impacts" not in labels and "after 3 or more impacts" not in labels
    assert "overturned after 1 impact" in labels and "safe" in labels
    ax = fig.axes[0]
    right, top = fig.axes[2].child_axes[-1], ax.child_axes[0]
    assert right.yaxis.label.get_size() == ax.yaxis.label.get_size()
    assert top.xaxis.label.get_size() == ax.xaxis.label.get_size()


def test_the_block_alones_bounds_show_beside_the_dampers_and_period_ticks_do_not_crowd(cabinet_map):
    """Where neither block overturns within the scan (beta_min = the last beta scanned, flag ABOVE), both get a
    lower-bound marker at that beta, side by side; the period ticks are at least 0.4 inch apart on a drawn figure
    (0.05 to 30 in Omega: periods from 37 s to 0.06 s)."""
    from rocking.plot.style import PART_STYLE

    Om = np.linspace(0.05, 30.0, 25)
    fig = spectrum_figure_of(cabinet_map.config, Om, above=[20, 21, 22])
    FigureCanvasAgg(fig).draw()
    ax = fig.axes[0]
    bounds = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
    colours = {to_hex(c.lines[0].get_color()): c.lines[0] for c in bounds}
    bare, damper = (colours[to_hex(PART_STYLE[part]["color"])] for part in ("bare", "damper"))
    for line in (bare, damper):
        np.testing.assert_allclose(line.get_xdata(), Om[20:23], atol=0.5 * (Om[1] - Om[0]))
        np.testing.assert_allclose(line.get_ydata(), 15.0)
    assert (bare.get_xdata() < damper.get_xdata()).all()
    top = ax.child_axes[0]
    ticks = np.sort(2 * np.pi / (CABINET.p * np.asarray(top.get_xticks())))
    inches = np.diff(ax.transData.transform(np.c_[ticks, np.zeros_like(ticks)])[:, 0]) / fig.dpi
    assert ticks.size >= 3 and inches.min() >= 0.4


@pytest.fixture(scope="module")
def small_design(tmp_path_factory):
    from rocking.study.design import design

    return design(
        Setting(Block.reference()),
        Grid("Omega", 4.0, 6.0, 2),
        Grid("beta", 0.5, 20.0, 27),
        SERIAL,
        runs=tmp_path_factory.mktemp("design"),
        Tm=Grid("Tm", 0.5, 4.0, 3, log=True),
        zeta=Grid("zeta", 0.02, 0.2, 2, log=True),
        refine=1,
    )


def test_the_design_figure_keeps_each_direction_visible_and_says_what_the_stroke_does(small_design):
    """The reference block is eccentric: both directions. Each direction's gain (beta_min with the damper over
    beta_min alone, of that sign) is drawn over the envelope's, which the legend explains; the stroke panel's
    title gives the largest x_max / L and the stops' contacts."""
    from rocking.plot.figures import ENVELOPE_GAIN, design_figure

    data = small_design.data
    fig = design_figure(small_design)
    ax_g, ax_x = fig.axes[0], fig.axes[2]
    lines = {line.get_label(): line for line in ax_g.get_lines()}
    envelope = lines[ENVELOPE_GAIN]
    for sign in data["sign"].values:
        line = lines[f"pulses of sign {sign:+d} alone"]
        beta_min = data["beta_min"].sel(sign=sign)
        measured = (data["flag"].sel(sign=sign) == BRACKETED).all("part").values
        ratio = (beta_min.sel(part="damper") / beta_min.sel(part="bare")).values
        np.testing.assert_allclose(line.get_ydata(), np.where(measured, ratio, np.nan))
        assert line.get_zorder() > envelope.get_zorder() and line.get_linewidth() < envelope.get_linewidth()
    title = ax_x.get_title()
    assert f"stroke up to {np.nanmax(data['stroke_use']):.2f} L" in title
    assert ("on the stops at" in title) == bool((data["stop_contacts"] > 0).any())


def test_an_mp_study_title_writes_gamma_mp_and_the_dampers_gamma():
    config = {
        "block": Block.reference().as_params(),
        "pulse": {"motion": "mp", "gamma_mp": 2.0, "nu": 0.5},
        "damper": {"gamma": 0.05, "omega_ratio": 1.0, "zeta": 0.05, "h": 0.05},
    }
    fig = Figure()
    figures._title(fig, "Map", config)
    title = fig._suptitle.get_text()
    assert r"$\gamma_{MP}$ = 2" in title and r"damper $\gamma$ = 0.05" in title


def test_the_threshold_figure_shows_what_the_study_found_per_geometry(small_threshold):
    """No heat map: per (lambda, p) the best gain of each damper (filled: unlimited, open: stops), the Omega from
    which the block alone survives, and Omega* as a star where bracketed, else an open triangle at its bound;
    the values drawn are those of rocking.study.threshold.thresholds."""
    from rocking.study.threshold import thresholds
    from rocking.study.vocabulary import THRESHOLD_STATUSES

    found = thresholds(small_threshold.data)
    fig = figures.threshold_figure(small_threshold)
    ax_gain, ax_omega = fig.axes[:2]
    assert not ax_gain.images + ax_omega.images and not ax_gain.collections
    lines = {line.get_label(): line for line in ax_gain.get_lines()}
    for i, lam in enumerate(found["lam"].values):
        for kind in ("unlimited", "stops"):
            line = lines[rf"$\lambda$ = {lam:.3g}, {kind}"]
            np.testing.assert_allclose(line.get_ydata(), found["best_gain"].sel(part=kind).values[i])
            assert (line.get_markerfacecolor() == "white") == (kind == "stops")
        safe = next(ln for ln in ax_omega.get_lines() if ln.get_label() == rf"$\lambda$ = {lam:.3g}")
        np.testing.assert_allclose(safe.get_ydata(), found["safe_from"].values[i])
    status = found["status"].values
    stars = [ln for ln in ax_omega.get_lines() if ln.get_marker() == "*"]
    drawn = np.concatenate([ln.get_ydata() for ln in stars])
    assert np.isfinite(drawn).sum() == (status == THRESHOLD_STATUSES.index("bracketed")).sum()
    bounds = [c for c in ax_omega.containers if isinstance(c, ErrorbarContainer)]
    above = found["Omega_star_low"].values[status == THRESHOLD_STATUSES.index("above_range")]
    below = found["Omega_star_high"].values[status == THRESHOLD_STATUSES.index("below_range")]
    drawn = np.concatenate([c.lines[0].get_ydata() for c in bounds]) if bounds else []
    np.testing.assert_allclose(np.sort(drawn), np.sort(np.concatenate([above, below])))
    bracketed = (status == THRESHOLD_STATUSES.index("bracketed")).sum()
    assert f"in {bracketed} of {status.size} cases" in ax_omega.get_title()


def test_a_maps_pdf_holds_its_cells_as_images_not_paths(cabinet_map, tmp_path):
    """90,000 noisy cells (each a hatched vector path before) make a PDF under 2 MB: the cells and their hatches
    are images, the axes and text stay vector."""
    from rocking.plot.figures import draw

    (png, pdf) = draw(_resampled_map(cabinet_map, 300), tmp_path, "map", ("png", "pdf"))
    assert png.stat().st_size > 0 and pdf.stat().st_size < 2_000_000
    assert pdf.read_bytes().count(b"/Subtype /Image") >= 3


def test_an_mp_spectrums_right_axis_is_the_peak_not_the_amplitude_parameter():
    """A Mavroeidis-Papageorgiou pulse's ``a_g = A omega_g`` is not its peak (0.906 of it at gamma_MP = 2, nu = 0,
    the issue's value): the right axis reads the peak ground acceleration, and the title says how the two relate."""
    from rocking.model.motion import MavroeidisPapageorgiou, peak

    block = Block.reference()
    config = {
        "block": block.as_params(),
        "pulse": {"motion": "mp", "gamma_mp": 2.0, "nu": 0.0},
        "damper": {"gamma": 0.05, "omega_ratio": 1.0, "zeta": 0.05, "h": 0.05},
        "beta": {"low": 0.5, "high": 15.0, "n": 5},
    }
    fig = spectrum_figure_of(config, [1.0, 2.0, 4.0])
    assert peak(MavroeidisPapageorgiou(1.0, 3.0, 2.0, 0.0)) == pytest.approx(0.906, abs=5e-4)
    (right,) = [child for ax in fig.axes for child in ax.child_axes if child.get_ylabel()]
    assert right.get_ylabel() == "peak ground acceleration (g)"
    beta = 4.0
    pulse = MavroeidisPapageorgiou.from_nondim(block, beta=beta, Omega=2.0, gamma_mp=2.0, nu=0.0)
    assert right._functions[0](beta) == pytest.approx(peak(pulse) / block.g)
    assert "(peak 0.906 $a_g$)" in fig._suptitle.get_text()
    sine = spectrum_figure_of({**config, "pulse": {"motion": "sine"}}, [1.0, 2.0, 4.0])
    (right,) = [child for ax in sine.axes for child in ax.child_axes if child.get_ylabel()]
    assert right.get_ylabel() == "$a_g$ (g)" and right._functions[0](beta) == pytest.approx(beta * block.tan_alpha)


def test_the_design_draws_a_directions_bounded_gain_as_a_bound_and_an_undefined_one_not_at_all(small_design):
    """Where the scan bounds both blocks' beta_min (both survive it) a direction's gain is undefined: no point (it
    was drawn as a measured 1.00, joined to its neighbours); where it bounds one, an open triangle, not on the line."""
    import xarray as xr

    from rocking.plot.figures import GAIN_BOUND, design_figure
    from rocking.study.vocabulary import ABOVE

    data = small_design.data.copy(deep=True)
    sign = data["sign"].values[0]
    flag = data["flag"].sel(sign=sign).transpose("part", "Omega").values.copy()
    flag[:, 0] = ABOVE  # both survive the scan at the first Omega
    flag[:, 1] = [0, ABOVE]  # (bare, damper): only the damped block does at the second
    assert list(data["part"].values) == ["bare", "damper"]
    data["flag"].loc[{"sign": sign}] = xr.DataArray(flag, dims=("part", "Omega"))
    fig = design_figure(dataclasses.replace(small_design, data=data))
    ax_g = fig.axes[0]
    line = next(ln for ln in ax_g.get_lines() if ln.get_label() == f"pulses of sign {sign:+d} alone")
    assert np.isnan(line.get_ydata()[:2]).all()
    triangles = [c for c in ax_g.containers if isinstance(c, ErrorbarContainer)]
    drawn_at = np.concatenate([c.lines[0].get_xdata() for c in triangles])
    Om = data["Omega"].values
    assert np.any(np.isclose(drawn_at, Om[1], atol=0.05 * np.ptp(Om))) and not np.any(np.isclose(drawn_at, Om[0]))
    labels = [t.get_text() for t in ax_g.get_legend().get_texts()]
    assert GAIN_BOUND[True] in labels and any("no gain where the scan only bounds both" in t for t in labels)


@pytest.mark.parametrize(("kind", "size"), [("spectrum", (8, 6)), ("design", (9, 6))])
def test_a_figure_drawn_in_a_narrow_constrained_figure_keeps_its_title_and_legends_on_it(
    spectrum, small_design, kind, size
):
    """The user's own axes in a constrained layout narrower than the figure's own: the title's long lines break
    at commas and the legends take fewer columns and break, so that nothing drawn leaves the canvas (the title
    and the design's gain legend did)."""
    study, function = {"spectrum": (spectrum, spectrum_figure), "design": (small_design, figures.design_figure)}[kind]
    fig = Figure(figsize=size, layout="constrained")
    function(study, ax=fig.subplots(1, 2 if kind == "spectrum" else 3))
    FigureCanvasAgg(fig).draw()
    drawn = fig.get_tightbbox(fig.canvas.get_renderer())  # inches, every artist drawn
    assert drawn.x0 >= -0.02 and drawn.y0 >= -0.02 and drawn.x1 <= size[0] + 0.02 and drawn.y1 <= size[1] + 0.02
