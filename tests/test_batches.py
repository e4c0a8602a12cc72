"""The batches of a tile of several motions (rocking/study/batches.py): the cases of each motion as if built alone,
and the tolerance check's results as if every run were made on every response."""

from __future__ import annotations

import re

import numpy as np
import pytest

import rocking
from rocking.model.motion import SampledMotion
from rocking.model.params import ParameterError
from rocking.model.stochastic import SiteModel
from rocking.sim.accuracy import PERTURBATION, checked_fields
from rocking.sim.batch import Packed
from rocking.sim.boundary import CASE, SERIES
from rocking.study.batches import checked_rows, motion_cases, tile_cases
from rocking.study.config import Setting, Tuning
from rocking.study.ida import ida_tile
from rocking.study.suite import Suite

BLOCK = rocking.Block.reference()
SETTING = Setting(BLOCK, t_after=2.0)
SIGNS = (1, -1)
#: The count of each series of a case.
COUNTS = {f.name: f.count for f in CASE if f.kind == SERIES}


def _records(vertical: bool = False) -> list[SampledMotion]:
    """Records of other lengths, spacings, scales and directions (with vertical samples if ``vertical``)."""
    rng = np.random.default_rng(3)
    shapes = [(400, 0.01, 1.0, 1), (250, 0.02, 1.5, -1), (300, 0.005, 0.7, 1)]
    return [
        SampledMotion(
            rng.normal(0.0, 1.0, n), dt=dt, scale=scale, sign=sign, a_v=rng.normal(0, 1, n) if vertical else None
        )
        for n, dt, scale, sign in shapes
    ]


def _same_cases(got, expected) -> None:
    """Two batches hold the same runs: the model, the parameters and every setting, a series by the values each
    case reads."""
    assert got.model is expected.model and len(got) == len(expected)
    np.testing.assert_array_equal(got.p, expected.p)
    assert set(got.settings) == set(expected.settings)
    for name, column in got.settings.items():
        if isinstance(column, Packed):
            counts = got.settings[COUNTS[name]].astype(int)
            for i, count in enumerate(counts):
                np.testing.assert_array_equal(column.row(i, count), expected.settings[name].row(i, count), err_msg=name)
        else:
            np.testing.assert_array_equal(column, expected.settings[name], err_msg=name)


@pytest.mark.parametrize("vertical", [False, True])
@pytest.mark.parametrize("tuning", [None, Tuning(0.05), Tuning(0.05, stops=True)])
def test_a_tiles_cases_are_each_motions_built_alone(tuning, vertical):
    """Sampled motions' cases are the first's rows with what each motion gives them; a vertical component's are
    built a motion at a time: either way, every setting of every case is what sampled_cases gives the motion."""
    motions = _records(vertical)
    scales = np.array([[0.5, 1.0, 2.0], [0.3, 0.6, 0.9], [1.0, 1.5, 2.5]])
    damper = {} if tuning is None else tuning.case_args()
    rows = tile_cases(SETTING, motions, scales, SIGNS, damper)
    alone = [motion_cases(SETTING, m, s, SIGNS, damper) for m, s in zip(motions, scales)]
    every = np.ones(len(rows.p), bool)
    from_alone = tile_cases(SETTING, motions[:1], scales[:1], SIGNS, damper).take(every[: len(alone[0])])
    _same_cases(from_alone, alone[0])
    for i, motion_alone in enumerate(alone):
        mine = np.zeros(len(rows.p), bool)
        mine[i * len(motion_alone) : (i + 1) * len(motion_alone)] = True
        _same_cases(rows.take(mine), motion_alone)
    some = every.copy()
    some[::3] = False  # a batch of some responses: those rows, as they are
    assert len(rows.take(some)) == some.sum()


def test_a_tile_refuses_a_motion_scaled_out_of_range_as_the_motion_alone_is():
    small, big = _records()[0], SampledMotion(np.array([0.0, 5e4, -1.0]), dt=0.01)
    scales = np.array([[1.0, 2.0], [1.0, 3.0]])  # 3 x 5e4 m/s^2: past a_g's range
    with pytest.raises(ParameterError) as alone:
        motion_cases(SETTING, big, scales[1], SIGNS, {})
    with pytest.raises(ParameterError, match=f"^{re.escape(str(alone.value))}$"):
        tile_cases(SETTING, [small, big], scales, SIGNS, {})


def _runs(n: int):
    """Runs of ``n`` responses made up to walk every path of the ladder: a third follow one trajectory at every
    tolerance, a third move from the first tolerance to the second and stay there, a third are chaotic (their
    maximum moves with the motion's perturbation at every tolerance)."""
    kind = np.arange(n) % 3

    def run(rtol: float, factor: float) -> dict:
        tight = rtol < 1e-9
        step = np.rint((factor - 1.0) / PERTURBATION)
        theta = np.where(kind == 1, np.where(tight, 0.2, 0.1), 0.1) * (1 + np.where(kind == 2, 0.3 * step, 0.0))
        theta = theta * (1 + 0.01 * np.arange(n) / n)
        return {
            "overturned": np.where(kind == 2, step % 2, 0).astype(np.int64),
            "status": np.zeros(n, np.int64),
            "impacts": np.where(kind == 1, np.where(tight, 7, 5), 5).astype(np.int64),
            "theta_max": theta,
            "x_max": np.full(n, 0.01),
            "t_end": 9.0 + np.arange(n),
        }

    return run


def test_the_check_on_the_rows_it_counts_gives_the_check_on_every_row():
    """checked_rows makes each run below the first on the responses the ladder counts there only, and gives what
    checked_fields gives from every run made on every response: the run reported, its sensitivity and spread."""
    n, rtol = 12, 1e-8
    run, made = _runs(n), []

    def on_rows(r: float, factor: float, rows: np.ndarray) -> dict:
        made.append(rows.copy())
        return {k: v[rows] for k, v in run(r, factor).items()}

    expected, got = checked_fields(run, rtol), checked_rows(on_rows, rtol, n)
    assert set(got) == set(expected)
    for k in expected:
        np.testing.assert_array_equal(got[k], expected[k], err_msg=k)
    kind = np.arange(n) % 3
    runs = np.sum(made, axis=0)
    assert (runs[kind == 0] == 3).all()  # one trajectory: its run and the first rung's two, none more
    assert (runs[kind == 1] == 5).all() and (runs[kind == 2] > 5).all()  # down the ladder; chaotic: its spread
    assert got["sensitive"][kind > 0].all() and not got["sensitive"][kind == 0].any()  # moved: 0.1 to 0.2 rad


def test_a_tile_of_several_motions_holds_what_each_motion_alone_gives():
    """The responses of a motion do not depend on the motions it shares its tile and its batches with."""
    site = SiteModel(arias=0.3, d595=2.0, t_mid=1.5, f_mid=4.0, f_slope=-0.1, zeta_f=0.25, dt=0.01, duration=4.0)
    suite = Suite.stochastic(site, 3, seed=2)
    levels = np.array([1.0, 3.0, 6.0])
    damper = Tuning(0.05).case_args()
    tile = ida_tile((SETTING, damper, suite, 0, 3, levels, "pga", SIGNS, None))
    for i in range(3):
        alone = ida_tile((SETTING, damper, suite, i, i + 1, levels, "pga", SIGNS, None))
        for k, v in alone.items():
            np.testing.assert_array_equal(tile[k][i], v[0], err_msg=k)
    assert tile["sensitive"].shape == (3, levels.size, len(SIGNS))
