"""Studies as labelled data: xarray Datasets with units and keys, NetCDF beside the other files, DataFrames."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import rocking
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.dataset import read_netcdf, to_dataset
from rocking.study.overturning_map import envelope
from rocking.study.spectrum import envelope as spectrum_envelope
from rocking.study.threshold import thresholds
from rocking.study.tiles import Execution
from rocking.study.vocabulary import ABOVE, BELOW, BRACKETED

SERIAL = Execution(workers=1, progress=False)
BLOCK = rocking.Block.reference()


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    runs = tmp_path_factory.mktemp("runs")
    Omega = np.linspace(1.0, 6.0, 4)
    plain = {"damper": {"gamma": 0.05}, "Omega": Omega, "runs": runs, "workers": 1, "progress": False, "study": True}
    pulses = [rocking.RickerWavelet.from_period(3.0, T) for T in (0.5, 1.0, 2.0)]
    few = {k: plain[k] for k in ("runs", "workers", "progress", "study")}
    return {
        "map": rocking.overturning_map(BLOCK, beta=np.linspace(1.0, 6.0, 5), **plain),
        "spectrum": rocking.minimum_overturning_spectrum(BLOCK, beta=np.linspace(0.5, 8.0, 8), **plain),
        "optimize": rocking.optimal_damper(
            BLOCK, [0.05], Omega=[4.0], beta=[0.5, 2, 4, 8, 15], Tm_ratio=[0.5, 2.0], **few
        ),
        "design": rocking.design(
            BLOCK,
            Omega=[4.0, 6.0],
            beta=np.linspace(0.5, 20.0, 27),
            Tm_ratio=[0.5, 1.5, 4.0],
            zeta_grid=[0.02, 0.2],
            refine=0,
            **few,
        ),
        "threshold": rocking.threshold_map(lam=[4.0], p=[2.0], Omega=[4.0, 14.0], Tm_ratio=[0.5, 2.0], refine=0, **few),
        "ida": rocking.incremental_dynamic_analysis(BLOCK, motions=pulses, scales=[0.5, 1.0, 2.0], t_after=5.0, **few),
        "friction": rocking.friction_map(
            rocking.Block(2.0, 0.5, 1000.0), T_g=0.5, mu=[0.15, 0.5], a_g=[3.0, 4.0], directions="both", **few
        ),
        "fragility": rocking.fragility(
            BLOCK,
            {"gamma": 0.05, "stops": True},
            motions=pulses,
            levels=[1.0, 3.0, 9.0],
            im="pga",
            t_after=5.0,
            **few,
        ),
    }


def test_the_plain_interface_gives_the_studys_arrays(studies, tmp_path):
    """Arrays of values give the arrays of the same study with Grids, and the Dataset by default."""
    from rocking.study.overturning_map import overturning_map

    grids = Grid("Omega", 1.0, 6.0, 4), Grid("beta", 1.0, 6.0, 5)
    study = overturning_map(Setting(BLOCK), Tuning(0.05), *grids, SERIAL, runs=tmp_path)
    xr.testing.assert_identical(studies["map"].data, study.data)
    ds = rocking.overturning_map(BLOCK, Omega=[1.0, 6.0], beta=[2.0], runs=tmp_path, workers=1, progress=False)
    assert isinstance(ds, xr.Dataset) and dict(ds.sizes) == {"part": 2, "Omega": 2, "beta": 1, "sign": 2}
    with pytest.raises(rocking.ParameterError, match="Omega: values must increase"):
        rocking.overturning_map(BLOCK, Omega=[3.0, 1.0], beta=[2.0], runs=tmp_path)
    with pytest.raises(rocking.ParameterError, match="keywords of rocking.Tuning"):
        rocking.overturning_map(BLOCK, {"mass": 1.0}, Omega=[1.0], beta=[2.0], runs=tmp_path)


def test_map_dataset_is_labelled_in_both_terms(studies):
    study = studies["map"]
    ds = study.to_dataset()
    assert dict(ds.sizes) == {"part": 2, "Omega": 4, "beta": 5, "sign": 2}
    assert ds["overturned"].dims == ("part", "Omega", "beta", "sign")
    assert list(ds["part"].values) == ["bare", "damper"] and list(ds["sign"].values) == [1, -1]
    both = envelope(ds)  # the envelope over the directions: a reduction over sign
    assert both["overturned"].dims == ("part", "Omega", "beta") and both["effect"].dims == ("Omega", "beta")
    # SI coordinates from the block (docs/model.md section 9): T_g = 2 pi / (Omega p), a_g = beta g tan(alpha).
    np.testing.assert_allclose(ds["T_g"], 2 * np.pi / (ds["Omega"] * BLOCK.p))
    np.testing.assert_allclose(ds["a_g"], ds["beta"] * 9.81 * BLOCK.B / BLOCK.H)
    assert ds["T_g"].attrs["units"] == "s" and ds["a_g"].attrs["units"] == "m/s^2"
    assert ds["x_max"].attrs["units"] == "m" and ds["theta_max"].attrs["units"] == "rad"
    assert ds["bumper_force_max"].attrs["units"] == "N" and both["x_max"].attrs["units"] == "m"
    for name, var in ds.data_vars.items():
        assert {"units", "long_name"} <= set(var.attrs), name
    # Categorical values carry their key.
    status = ds["status"].attrs
    meanings = dict(zip(status["flag_values"].tolist(), status["flag_meanings"].split(), strict=True))
    assert meanings[0] == "overturned" and meanings[5] == "bounded" and meanings[-1] == "not_computed"
    effect = both["effect"].attrs
    assert dict(zip(effect["flag_values"].tolist(), effect["flag_meanings"].split(), strict=True)) == {
        -1: "lost",
        0: "unchanged",
        1: "saved",
    }
    assert json.loads(ds.attrs["config"]) == study.config
    assert json.loads(ds.attrs["versions"])["rocking"] == rocking.__version__
    assert ds.attrs["Conventions"].startswith("CF-")


def test_spectrum_dataset_and_flags_in_words(studies):
    study = studies["spectrum"]
    ds = study.to_dataset()
    assert ds["scan_outcome"].dims == ("part", "Omega", "sign", "beta_scan")
    both = spectrum_envelope(ds)  # the envelope over the directions: a reduction over sign
    assert both["beta_min"].dims == ("part", "Omega") and both["scan_outcome"].dims == ("part", "Omega", "beta_scan")
    flag = both["flag"].attrs
    words = dict(zip(flag["flag_values"].tolist(), flag["flag_meanings"].split(), strict=True))
    assert words == {BELOW: "upper_bound", BRACKETED: "bracketed", ABOVE: "lower_bound"}
    table = study.to_dataframes()["spectrum"]
    expected = np.array([words[f] for f in both["flag"].sel(part="bare").values])
    np.testing.assert_array_equal(table["bare_beta_min_is"].to_numpy(), expected)


def test_saved_study_reads_back_as_the_same_dataset(studies, tmp_path):
    for kind, study in studies.items():
        files = rocking.save(study, tmp_path / kind)
        nc = tmp_path / kind / f"{kind}.nc"
        assert nc in files
        saved = read_netcdf(nc)
        xr.testing.assert_identical(saved, rocking.load(nc).to_dataset().assign_attrs(versions=saved.attrs["versions"]))
        xr.testing.assert_equal(saved, study.to_dataset())
        assert all(saved[k].dtype == v.dtype for k, v in study.data.variables.items()), kind
        # Its tables, made again from what was saved, are the finished study's.
        loaded, made = rocking.load(nc).to_dataframes(), study.to_dataframes()
        assert loaded.keys() == made.keys() == study.tables.keys() and loaded, kind
        for name, frame in made.items():
            pd.testing.assert_frame_equal(loaded[name], frame, obj=f"{kind}: {name}")


def test_every_kind_is_in_the_plain_interface(studies):
    """The top-level functions give every kind of study; an array of values is a Grid of those values."""
    from rocking.study.kinds import KINDS

    assert set(studies) == set(KINDS)
    assert studies["design"].config["Tm_ratio"]["values"] == [0.5, 1.5, 4.0]
    assert studies["fragility"].kind == "fragility" and studies["ida"].kind == "ida"
    ds = studies["threshold"].to_dataset()
    found = thresholds(ds)
    assert dict(ds.sizes)["lam"] == 1 and found["Omega_star"].dims == ("part", "lam", "p")
    # A threshold's status is where Omega* lies, not why a run ended.
    from rocking.study.vocabulary import THRESHOLD_STATUSES as STATUSES

    assert found["status"].attrs["flag_meanings"].split() == list(STATUSES)
    assert ds["flag"].attrs["flag_meanings"] == "upper_bound bracketed lower_bound"


def test_plain_interface_refuses_bad_motions_in_one_line(tmp_path):
    pulse = rocking.RickerWavelet.from_period(3.0, 1.0)
    with pytest.raises(rocking.ParameterError, match="motions must be a rocking.Suite, record files or pulses"):
        rocking.incremental_dynamic_analysis(BLOCK, motions=3, scales=[1.0], runs=tmp_path)
    with pytest.raises(rocking.ParameterError, match="unit is the unit of record files"):
        rocking.incremental_dynamic_analysis(BLOCK, motions=[pulse], scales=[1.0], unit="g", runs=tmp_path)
    with pytest.raises(rocking.ParameterError, match="levels: values must increase"):
        rocking.incremental_dynamic_analysis(BLOCK, motions=[pulse], scales=[2.0, 1.0], runs=tmp_path)
    with pytest.raises(rocking.ParameterError, match="zeta: values must be > 0"):
        rocking.design(BLOCK, Omega=[4.0], beta=[1.0, 2.0], zeta_grid=[0.0, 0.1], runs=tmp_path)


def test_dataframes_carry_units_and_labels(studies):
    frame = studies["map"].to_dataframes()["map"]
    assert len(frame) == 4 * 5
    assert frame.attrs["units"]["damper_x_max"] == "m"
    assert set(frame["effect"].cat.categories) == {"lost", "unchanged", "saved"}
    assert set(frame["damper_status"]) <= {
        "overturned",
        "rest",
        "t_max",
        "max_events",
        "max_steps",
        "bounded",
        "not_computed",
    }


def test_every_kind_describes_the_dimensions_of_its_data(studies):
    """The registry of kinds gives the dimensions of every variable of a study's data, which a load checks."""
    from rocking.study.kinds import KINDS

    assert set(studies) == set(KINDS)
    for kind, study in studies.items():
        for name, variable in study.data.variables.items():
            assert variable.dims == KINDS[kind].dims(name), (kind, name)


@pytest.mark.parametrize(
    ("kind", "old", "message"),
    [
        ("optimize", {"bare_beta_min": ["Omega"]}, r"bare_beta_min: not a variable of a optimize study"),
        ("design", {"bare_beta_min_by_sign": ["Omega", "sign"]}, r"bare_beta_min_by_sign: not a variable"),
        ("design", {"stroke_use": ["Omega"]}, r"stroke_use has dimensions \(Omega\), not \(Omega, sign\)"),
    ],
)
def test_an_optimum_or_a_design_of_the_earlier_layout_is_refused_not_misread(studies, kind, old, message):
    """Their variables named their dimensions (``bare_beta_min_by_sign``) or had fewer (``stroke_use`` per Omega):
    a file of that layout, still format 3, is refused by the schema of its kind before it is read."""
    from rocking.study.storage import check_config, check_variables, data_layout

    study = studies[kind]
    listed = data_layout(study.data)
    for name, dims in old.items():
        sizes = [dict(study.data.sizes)[d] for d in dims]
        listed[name] = {"dims": dims, "dtype": "<f8", "shape": sizes}
    with pytest.raises(rocking.ParameterError, match=message):
        check_variables(kind, listed, check_config(kind, study.config)[1])
    check_variables(kind, data_layout(study.data), check_config(kind, study.config)[1])  # its own layout passes


def test_not_a_study_netcdf_is_refused_in_one_line(tmp_path):
    other = tmp_path / "other.nc"
    xr.Dataset({"a": ("x", np.arange(3))}).to_netcdf(other, engine="netcdf4")
    with pytest.raises(rocking.ParameterError, match="not a rocking study"):
        read_netcdf(other)
    text = tmp_path / "text.nc"
    text.write_text("hello")
    with pytest.raises(rocking.ParameterError, match="not a readable NetCDF file"):
        read_netcdf(text)


def test_study_html_for_notebooks(studies):
    html = studies["map"]._repr_html_()
    assert "rocking map study" in html and "xr-wrap" in html  # xarray's own rich view inside
    assert to_dataset(studies["map"]).attrs["kind"] == "map"
    assert "<th>summary</th>" in html
    # An IDA's fit is in its variables, its summary empty: no empty summary table above them.
    ida = studies["ida"]._repr_html_()
    assert "rocking ida study" in ida and "<th>summary</th>" not in ida and "dispersion" in ida
