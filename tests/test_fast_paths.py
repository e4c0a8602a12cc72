"""The faster paths of a command's fixed cost (issue 40) give what the plain ones gave: the CSV writer's texts,
byte for byte."""

from __future__ import annotations

import numpy as np

from rocking.study.files import write_csv


def plain_csv(columns: dict) -> str:
    """The CSV of ``columns`` as a row-by-row formatter writes it: ``repr`` of a float, ``str`` of anything else."""
    names = list(columns)
    data = [np.asarray(columns[k]).ravel() for k in names]
    kinds = [d.dtype.kind for d in data]
    lines = [",".join(names)]
    for values in zip(*(d.tolist() for d in data)):
        lines.append(",".join(repr(v) if k == "f" else str(v) for v, k in zip(values, kinds)))
    return "\n".join(lines) + "\n"


def awkward_columns(n: int, seed: int = 0) -> dict:
    """Columns of every kind a study's table holds, with the values a formatter can get wrong: signed zeros, NaN,
    infinities, tiny and huge magnitudes, few distinct values (a grid's coordinates) and many."""
    rng = np.random.default_rng(seed)
    specials = np.array([0.0, -0.0, np.nan, np.inf, -np.inf, 1e-300, 5e-324, 1e16, 1e-5, 0.1, 123456789012345.0])
    spread = rng.standard_normal(n) * 10.0 ** rng.integers(-30, 30, n)
    special = rng.random(n) < 0.2
    spread[special] = rng.choice(specials, special.sum())
    return {
        "grid": np.repeat(np.linspace(1.0, 10.0, 7), -(-n // 7))[:n],
        "signed_zeros": rng.choice([0.0, -0.0, np.nan], n),
        "spread": spread,
        "float32": rng.standard_normal(n).astype(np.float32),
        "longdouble": np.repeat(np.arange(3, dtype=np.longdouble) / 3, -(-n // 3))[:n],
        "codes": rng.integers(-1, 5, n),
        "counts": rng.integers(0, 10**9, n),
        "flags": rng.random(n) < 0.5,
        "int8": rng.integers(-1, 2, n).astype(np.int8),
        "words": np.array(["safe", "overturned", "not_computed"], object)[rng.integers(0, 3, n)],
    }


def test_csv_as_the_plain_formatter(tmp_path):
    # Several chunks, the last one short; few distinct values and many in each chunk.
    columns = awkward_columns(2_503)
    write_csv(tmp_path / "t.csv", columns, chunk=1_000)
    assert (tmp_path / "t.csv").read_text() == plain_csv(columns)


def test_csv_of_a_map(tmp_path):
    # The columns of a map's table, as its CSV writer gets them (a 17 x 17 map, adaptive: NaN where not computed).
    from rocking import Block, Setting, Tuning
    from rocking.study.config import Grid
    from rocking.study.overturning_map import overturning_map
    from rocking.study.storage import headed
    from rocking.study.tiles import Execution

    study = overturning_map(
        Setting(Block.reference()),
        Tuning(0.05),
        Grid("Omega", 2.0, 6.0, 17),
        Grid("beta", 1.0, 9.0, 17),
        Execution(workers=1, progress=False),
        runs=tmp_path / "runs",
        coarse=16,
    )
    columns = headed(study.tables["map"], study.data)
    assert np.isnan(columns["damper_theta_max [rad]"]).any()  # cells not computed
    write_csv(tmp_path / "map.csv", columns)
    assert (tmp_path / "map.csv").read_text() == plain_csv(columns)


def test_progress_bar_only_when_asked(tmp_path, capsys):
    # tqdm is imported for a bar shown only (tests/test_import.py: a map without one does not load it).
    from rocking import Block, Setting, Tuning
    from rocking.study.config import Grid
    from rocking.study.overturning_map import overturning_map
    from rocking.study.tiles import Execution

    grids = Grid("Omega", 2.0, 6.0, 2), Grid("beta", 1.0, 9.0, 2)
    for shown in (False, True):
        execution = Execution(workers=1, progress=shown)
        overturning_map(Setting(Block.reference()), Tuning(0.05), *grids, execution, runs=tmp_path / str(shown))
        assert ("tile" in capsys.readouterr().err) is shown


def test_a_figure_laid_out_once_is_the_one_savefig_lays_out(tmp_path):
    # write_figure lays a figure out once, without savefig's draw that renders nothing: the same pixels.
    import matplotlib.image as mimg
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from rocking import Block, Setting, Tuning
    from rocking.plot.figures import DPI, map_figure, write_figure
    from rocking.study.config import Grid
    from rocking.study.overturning_map import overturning_map
    from rocking.study.tiles import Execution

    grids = Grid("Omega", 1.0, 10.0, 9), Grid("beta", 1.0, 10.0, 9)
    execution = Execution(workers=1, progress=False)
    study = overturning_map(Setting(Block.reference()), Tuning(0.05), *grids, execution, runs=tmp_path / "runs")
    write_figure(map_figure(study), tmp_path, "once", ("png",))
    fig = map_figure(study)
    FigureCanvasAgg(fig)
    assert fig.get_layout_engine() is not None
    fig.savefig(tmp_path / "savefig.png", dpi=DPI)
    once, plain = (mimg.imread(tmp_path / f"{name}.png") for name in ("once", "savefig"))
    assert once.shape == plain.shape and np.array_equal(once, plain)


def test_a_figure_laid_out_once_keeps_no_engine_whatever_the_rc_params(tmp_path):
    # None as a layout engine stands for the rcParams' engine: a tight one would be refused beside a colour bar.
    from matplotlib import rc_context
    from matplotlib.figure import Figure

    from rocking.plot.figures import write_figure

    fig = Figure(layout="constrained")
    ax = fig.subplots()
    fig.colorbar(ax.imshow(np.arange(6.0).reshape(2, 3)), ax=ax)
    with rc_context({"figure.autolayout": True, "figure.constrained_layout.use": True}):
        written = write_figure(fig, tmp_path, "bar", ("png", "pdf"))
    assert [p.name for p in written] == ["bar.png", "bar.pdf"] and fig.get_layout_engine() is None
