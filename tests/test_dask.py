"""The studies on a Dask cluster give the same arrays as on local processes."""

from __future__ import annotations

import argparse

import pytest
import xarray as xr

from rocking import Block
from rocking.cli.study import add_study_commands
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import overturning_map
from rocking.study.spectrum import minimum_overturning_spectrum
from rocking.study.storage import load
from rocking.study.tiles import Execution

distributed = pytest.importorskip("distributed")

SETTING = Setting(Block.reference(), backend="c")
OMEGA = Grid("Omega", 1.0, 8.0, 5)
BETA = Grid("beta", 0.5, 8.0, 16)
TUNING = Tuning(0.05, omega_ratio=0.8)


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=":0"
    ) as local_cluster:
        yield local_cluster


def assert_same(a, b) -> None:
    """Two studies' data are the same, labels and values."""
    xr.testing.assert_identical(a.data, b.data)


def test_map_on_dask_equals_local(cluster, tmp_path):
    local = overturning_map(
        SETTING, TUNING, OMEGA, BETA, Execution(workers=2, progress=False), runs=tmp_path / "local", tile=(2, 4)
    )
    on_dask = overturning_map(
        SETTING,
        TUNING,
        OMEGA,
        BETA,
        Execution(scheduler=cluster.scheduler_address, progress=False),
        runs=tmp_path / "dask",
        tile=(2, 4),
    )
    # The adaptive map: its rounds run on Dask as on local workers, and ask for the same cells (on a grid this
    # small, the verification's rounds end up computing every cell).
    assert on_dask.run["tiles_computed"] == local.run["tiles_computed"] > 0
    assert on_dask.run["rounds"] == local.run["rounds"] > 1
    assert on_dask.run["responses"] == local.run["responses"] <= local.run["responses_full_grid"]
    assert_same(on_dask, local)


def test_spectrum_on_local_dask_cluster_equals_serial(tmp_path):
    serial = minimum_overturning_spectrum(
        SETTING, TUNING, OMEGA, BETA, Execution(workers=1, progress=False), runs=tmp_path / "serial"
    )
    on_dask = minimum_overturning_spectrum(
        SETTING, TUNING, OMEGA, BETA, Execution(dask_workers=2, progress=False), runs=tmp_path / "dask"
    )
    assert_same(on_dask, serial)


def test_cli_runs_on_a_scheduler_and_resumes_from_its_tiles(cluster, tmp_path, capsys):
    parser = argparse.ArgumentParser(prog="rocking")
    add_study_commands(parser.add_subparsers(dest="command", required=True))
    argv = [
        "map",
        "--Omega",
        "1",
        "8",
        "5",
        "--beta",
        "0.5",
        "8",
        "16",
        "--omega-ratio",
        "0.8",
        "--tile",
        "2",
        "4",
        "--no-progress",
        "--out",
        str(tmp_path),
    ]
    args = parser.parse_args([*argv, "--scheduler", cluster.scheduler_address])
    assert args.func(args) == 0
    on_dask = load(tmp_path / "map")
    computed = on_dask.run["tiles_computed"]
    args = parser.parse_args([*argv, "--workers", "2"])  # same configuration: every tile is reused
    assert args.func(args) == 0
    assert f"0 tiles computed, {computed} reused" in capsys.readouterr().out
    assert_same(load(tmp_path / "map"), on_dask)
