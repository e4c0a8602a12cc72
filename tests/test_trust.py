"""Trust: a saved file never selects code to run; a cache someone else can write is never loaded from.

The attacks of issue 23, each reproduced: a model folder planted beside a saved study with its manifest
updated to vouch for its payload, named by the study's ``--config`` or its configuration; a folder named like
a built-in model; a foreign shared library with an updated sidecar in the C library cache. Each payload
creates a sentinel file; none may exist afterwards.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import rocking
from rocking.cli.main import main
from rocking.model import loading
from rocking.model.loading import GENERATED, ModelError, load_model
from rocking.plot.figures import _damper_label
from rocking.sim import cbuild
from rocking.sim.cbuild import CBuildError
from rocking.study.config import config_hash
from tests.planted import plant_library, plant_model

MAP = ["map", "--Omega", "1", "6", "4", "--beta", "1", "6", "5", "--gamma", "0.04", "--no-progress", "--workers", "1"]


@pytest.fixture(scope="module")
def saved_map(tmp_path_factory):
    out = tmp_path_factory.mktemp("map")
    assert main([*MAP, "--out", str(out)]) == 0
    return out / "map.json"


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    return err


def test_a_saved_study_naming_a_planted_model_folder_runs_nothing(saved_map, tmp_path, capsys):
    evil = plant_model(GENERATED / "omd", tmp_path / "evil", tmp_path / "PWNED")
    record = json.loads(saved_map.read_text())
    record["command"]["options"]["model"] = str(evil)
    config = tmp_path / "map.json"
    config.write_text(json.dumps(record))
    capsys.readouterr()
    assert main(["map", "--config", str(config), "--out", str(tmp_path / "out")]) == 2
    said = _one_line(capsys)
    assert f"names the model '{evil}', which is not built in" in said and "rerun with --model DIR" in said
    for name in ({}, [1], 7, "", "../" * 40 + "etc"):
        record["command"]["options"]["model"] = name
        config.write_text(json.dumps(record))
        assert main(["map", "--config", str(config), "--out", str(tmp_path / "out")]) == 2
        assert "model" in _one_line(capsys)
    assert not (tmp_path / "PWNED").exists()


def test_a_saved_study_names_a_built_in_model_whatever_the_working_directory(saved_map, tmp_path, monkeypatch, capsys):
    plant_model(GENERATED / "omd", tmp_path / "omd", tmp_path / "PWNED")
    record = json.loads(saved_map.read_text())
    record["command"]["options"].update(model="omd")
    (tmp_path / "map.json").write_text(json.dumps(record))
    monkeypatch.chdir(tmp_path)
    assert main(["map", "--config", "map.json", "--out", "out"]) == 0
    assert not (tmp_path / "PWNED").exists()
    assert rocking.load("out/map.json").config["damper"]["gamma"] == 0.04


def test_a_loaded_study_naming_a_planted_model_runs_nothing(saved_map, tmp_path):
    evil = plant_model(GENERATED / "pendulum", tmp_path / "evil", tmp_path / "PWNED")
    shutil.copy(saved_map.with_suffix(".nc"), tmp_path / "map.nc")
    record = json.loads(saved_map.read_text())
    record["config"]["damper"] = {"model": str(evil), "params": {"m": 1.0}, "model_sha256": "0" * 64}
    (tmp_path / "map.json").write_text(json.dumps(record))
    with pytest.raises(rocking.ParameterError, match=r"map\.json: config: not the configuration its results were"):
        rocking.load(tmp_path / "map.json")  # an edit by hand is told by the configuration's checksum
    record["config_sha256"] = config_hash(record["config"])  # one who also forges it still runs nothing
    (tmp_path / "map.json").write_text(json.dumps(record))
    study = rocking.load(tmp_path / "map.json")
    assert study.to_dataset()["x_max"].attrs["units"] == "m"  # the unit is not taken from its manifest
    assert "model" in _damper_label(study.config)
    with pytest.raises(rocking.ParameterError, match="trust_model .* not the model folder"):
        rocking.load(tmp_path / "map.json", trust_model=evil)
    assert not (tmp_path / "PWNED").exists()


def test_a_folder_the_user_names_is_trusted_and_a_saved_file_may_then_name_it(tmp_path):
    mine = shutil.copytree(GENERATED / "pendulum", tmp_path / "mine")
    with pytest.raises(ModelError, match="not built in"):
        loading.saved_model(str(mine), "a saved file")
    assert load_model(mine).folder == mine.resolve()
    assert loading.saved_model(str(mine.resolve()), "a saved file") is load_model(mine)


def test_a_built_in_model_is_checked_against_the_package_not_its_folder(monkeypatch):
    monkeypatch.setitem(rocking.generated.BUILTIN_MANIFESTS, "pendulum", "0" * 64)
    monkeypatch.setattr(loading, "_LOADED", {})
    loading._load_folder.cache_clear()
    with pytest.raises(ModelError, match="not the manifest the installed package records for the built-in model"):
        load_model("pendulum")
    loading._load_folder.cache_clear()


# --- the C library cache --------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def built_cache(tmp_path_factory):
    """A private cache holding the block model's library, built once for the module."""
    cache = tmp_path_factory.mktemp("built") / "cache"
    return cache, cbuild.build(load_model("block"), cache=cache).name


@pytest.fixture
def planted_cache(built_cache, tmp_path):
    """A copy of the built cache whose library is replaced by a planted one with an updated sidecar."""
    cache = shutil.copytree(built_cache[0], tmp_path / "cache")
    library = cache / built_cache[1]
    source_key = json.loads(library.with_name(library.name + ".json").read_text())["source_key"]
    plant_library(library, tmp_path / "PWNED", source_key)
    return cache, library


def _load_in_a_subprocess(cache) -> subprocess.CompletedProcess:
    code = "import rocking; rocking.simulate(rocking.Block.reference(), None, rocking.OneSinePulse(1, 1), backend='c')"
    env = {**os.environ, "ROCKING_CACHE_DIR": str(cache)}
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)


def test_a_cache_others_can_write_is_refused_before_any_library_is_read(planted_cache, tmp_path):
    cache, _ = planted_cache
    cache.chmod(0o777)
    with pytest.raises(CBuildError, match=r"writable by group or others \(mode 0777\).* chmod go-w"):
        cbuild.build(load_model("block"), cache=cache)
    proc = _load_in_a_subprocess(cache)
    assert proc.returncode != 0 and "writable by group or others" in proc.stderr
    assert not (tmp_path / "PWNED").exists()


@pytest.mark.parametrize("attack", ["group-writable", "symlink", "foreign owner"])
def test_a_planted_library_not_private_to_the_user_is_rebuilt_never_loaded(planted_cache, tmp_path, attack):
    cache, library = planted_cache
    if attack == "group-writable":
        library.chmod(0o664)
    elif attack == "symlink":
        shutil.move(library, tmp_path / "elsewhere.so")
        library.symlink_to(tmp_path / "elsewhere.so")
    elif os.geteuid() != 0:
        pytest.skip("changing a file's owner needs root")
    else:
        os.chown(library, 65534, 65534)
    planted = (tmp_path / "elsewhere.so" if attack == "symlink" else library).read_bytes()
    assert cbuild.build(load_model("block"), cache=cache) == library
    assert not library.is_symlink() and library.read_bytes() != planted
    assert _load_in_a_subprocess(cache).returncode == 0
    assert not (tmp_path / "PWNED").exists()


def test_a_new_cache_folder_is_private(tmp_path):
    cache = tmp_path / "new" / "cache"
    cbuild.build(load_model("block"), cache=cache)
    assert cache.stat().st_mode & 0o777 == 0o700


def test_a_header_planted_beside_a_models_sources_is_never_compiled(tmp_path):
    """The compiler reads copies of the checked sources only: a ``math.h`` in the model's folder, which ``-I``
    on that folder would have put before the system's, does not reach the library."""
    mine = shutil.copytree(GENERATED / "block", tmp_path / "mine")
    (mine / "math.h").write_text('#error "a planted header was compiled"\n')
    library = cbuild.build(load_model(mine), cache=tmp_path / "cache")
    assert library.is_file() and not list((tmp_path / "cache").glob(".sources-*"))


def test_a_folder_loaded_by_path_never_takes_a_built_in_models_name(tmp_path, monkeypatch):
    installed = load_model("omd")
    shutil.copytree(GENERATED / "omd", tmp_path / "omd")
    monkeypatch.chdir(tmp_path)
    mine = load_model(Path("omd"))
    assert mine.folder == (tmp_path / "omd").resolve() != installed.folder
    assert load_model("omd") is installed and loading.saved_model("omd", "a saved file") is installed
