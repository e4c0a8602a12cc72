"""The threshold frequency across geometries (rocking threshold): the rising amplitude scan, the bound of the
ground acceleration, Omega* per geometry, and the similarity of the bare block."""

from __future__ import annotations

import argparse

import numpy as np
import pytest
import xarray as xr

from rocking import Block
from rocking.cli.study import add_study_commands, safe_from_words
from rocking.model.params import ParameterError
from rocking.study.config import Grid, Setting
from rocking.study.overturning_map import TMaxWarning
from rocking.study.spectrum import beta_min
from rocking.study.threshold import (
    BETA_TOP,
    STATUSES,
    beta_bound,
    rising_beta_min,
    safe_from,
    threshold_map,
    thresholds,
)
from rocking.study.tiles import Execution
from rocking.study.vocabulary import ABOVE, BRACKETED

SERIAL = Execution(workers=1, progress=False)
REFERENCE = Setting(Block.reference())


def test_rising_scan_extends_past_its_first_top_and_stops_at_the_bound():
    """At Omega = 10 the reference block's beta_min (about 8.7, positive pulse) lies above the first segment's top;
    the scan rises to it. With a bound of 1 g (beta <= 4) it stops at the bound: no verdict of overturning."""
    bound = beta_bound(REFERENCE.block, 4.0)
    assert bound == pytest.approx(16.0)
    res = rising_beta_min(REFERENCE, [10.0], None, sign=1, beta_max=bound, tol=1e-3)
    assert res["flag"][0] == BRACKETED and res["beta_min"][0] > BETA_TOP and res["top"][0] == 2 * BETA_TOP
    wide = beta_min(REFERENCE, [10.0], np.linspace(0.5, 16.0, 200), None, tol=1e-3)
    step = 15.5 / 199
    assert abs(res["beta_min"][0] - wide["beta_min"][0]) <= step  # the same first overturning amplitude
    low = rising_beta_min(REFERENCE, [10.0], None, sign=1, beta_max=beta_bound(REFERENCE.block, 1.0), tol=1e-3)
    assert low["flag"][0] == ABOVE and low["beta_min"][0] == pytest.approx(4.0) and low["top"][0] == 4.0


def test_safe_from_is_the_start_of_the_safe_tail():
    flags = np.array([[0, 1, 0, 1, 1], [0, 0, 0, 0, 0], [1, 1, 1, 1, 1]])
    np.testing.assert_array_equal(safe_from([1.0, 2.0, 3.0, 4.0, 5.0], flags), [4.0, np.nan, 1.0])


def test_safe_from_in_words_says_when_no_safe_tail_was_found():
    """Where the block alone still overturns at the highest Omega (safe_from nan) the line says so, not "-"."""
    assert safe_from_words(14.0, 14.0) == "from Omega = 14"
    assert safe_from_words(np.nan, 14.0) == "from no Omega on: it still overturns at the highest scanned, Omega = 14"


def one_geometry(runs, **keywords):
    """A threshold map of one geometry (lambda = 3, p = 2 rad/s), two frequencies and one damper period."""
    grids = Grid("lam", 3.0, 3.0, 1), Grid("p", 2.0, 2.0, 1), Grid("Omega", 4.0, 6.0, 2)
    return threshold_map(*grids, SERIAL, Tm=Grid("Tm", 1.0, 1.0, 1, log=True), refine=0, runs=runs, **keywords)


def test_threshold_warns_of_responses_cut_at_t_max(tmp_path):
    """A t_after of 0.01 s cuts the runs at t_max: the threshold map warns with their count."""
    with pytest.warns(TMaxWarning, match=r"^threshold: \d+ response\(s\) reached t_max \(t_after = 0.01 s"):
        one_geometry(tmp_path, t_after=0.01)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    return threshold_map(
        Grid("lam", 4.0, 4.0, 1),
        Grid("p", 1.5, 4.0, 2),
        Grid("Omega", 2.0, 14.0, 4),
        SERIAL,
        Tm=Grid("Tm", 0.3, 3.0, 3, log=True),
        runs=tmp_path_factory.mktemp("runs"),
    )


def test_bare_block_is_similar_across_sizes(small):
    """The bare block's beta_min(Omega) depends on the slenderness alone, not on the size p (dimensional
    analysis of docs/model.md (R1)-(I): in the time p t, with beta and Omega, p drops out; Dimitrakopoulos and
    DeJong 2012, Proc. R. Soc. A 468, similarity laws of the rocking block). Only the absolute 15 s followed
    after the pulse could tell the sizes apart."""
    a = small.data
    np.testing.assert_allclose(a["beta_min"].values[0, 0], a["beta_min"].values[0, 1], rtol=2e-3)
    np.testing.assert_array_equal(a["flag"].values[0, 0], a["flag"].values[0, 1])


def test_threshold_reports_omega_star_or_where_the_block_is_safe(small):
    a, found = small.data, thresholds(small.data)
    Omega = a["Omega"].values
    assert small.summary["directions"]["signs"] == [1, -1]
    assert a["beta_max"].values[0] == pytest.approx(16.0)  # 4 g on a block of lambda = 4
    # At Omega = 14 the block alone survives every pulse up to 4 g: no gain there, and safe from 14 on.
    assert (a["flag"].values[0, :, -1] == ABOVE).all()
    assert np.isnan(a["gain"].sel(part="unlimited").values[0, :, -1]).all()
    np.testing.assert_array_equal(found["safe_from"].values[0], [14.0, 14.0])
    for kind in ("unlimited", "stops"):
        gains, t = a["gain"].sel(part=kind).values[0], found.sel(part=kind)
        assert np.isfinite(gains[:, :3]).all() and (gains[:, :3] > 0).all()
        for j in range(2):
            status = STATUSES[t["status"].values[0, j]]
            useful = np.flatnonzero(gains[j] >= 1.01)
            if status == "above_range":  # useful at the last Omega where the block alone overturns
                assert t["Omega_star_low"].values[0, j] == Omega[useful[-1]] == 10.0
            elif status == "bracketed":
                assert t["Omega_star_low"].values[0, j] <= t["Omega_star"].values[0, j]
    table = small.tables["threshold"]
    assert len(table["lam"]) == 4 and set(table["damper"]) == {"unlimited", "stops"}


def test_threshold_resumes_from_its_tiles(small, tmp_path_factory):
    runs = tmp_path_factory.getbasetemp() / "again"
    first, again = one_geometry(runs), one_geometry(runs)
    assert again.run["tiles_computed"] == 0 and again.run["tiles_reused"] == first.run["tiles_computed"] == 2
    xr.testing.assert_identical(again.data, first.data)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"a_max": 0.0}, r"a_max must be > 0"), ({"refine": -1}, r"refine must be an integer"),
     ({"e_ratio": 0.6}, r"^e_ratio must be in \(-0.5, 0.5\)")],
)  # fmt: skip
def test_bad_threshold_input_is_refused_naming_it(kwargs, message, tmp_path):
    with pytest.raises(ParameterError, match=message):
        threshold_map(
            Grid("lam", 4.0, 4.0, 1),
            Grid("p", 2.0, 2.0, 1),
            Grid("Omega", 2.0, 4.0, 2),
            SERIAL,
            runs=tmp_path,
            **kwargs,
        )


def test_cli_threshold_prints_omega_star_and_the_safe_frequencies(tmp_path, capsys):
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(
        [
            "threshold",
            "--lam",
            "4",
            "4",
            "1",
            "--p",
            "2",
            "2",
            "1",
            "--Omega",
            "2",
            "14",
            "4",
            "--Tm-ratio",
            "0.5",
            "2",
            "2",
            "--refine",
            "0",
            "--workers",
            "1",
            "--no-progress",
            "--out",
            str(tmp_path),
        ]
    )
    assert args.func(args) == 0
    out = capsys.readouterr().out
    assert "threshold, unlimited guide: Omega* bracketed at" in out
    assert "the block alone survives every pulse up to 4 g from Omega = 14" in out
    assert (tmp_path / "threshold.png").is_file() and (tmp_path / "threshold.csv").is_file()
