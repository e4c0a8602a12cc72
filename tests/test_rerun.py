"""Reproducibility: a saved study reruns from its JSON (--config); --json outputs carry model, versions, units."""

from __future__ import annotations

import json

import numpy as np
import pytest

import rocking
from rocking.cli.main import main

MAP = ["map", "--Omega", "1", "6", "4", "--beta", "1", "6", "5", "--gamma", "0.04", "--no-progress", "--workers", "1"]


def test_a_saved_study_reruns_exactly_from_its_json(tmp_path, capsys):
    assert main([*MAP, "--out", str(tmp_path / "a")]) == 0
    saved = json.loads((tmp_path / "a" / "map.json").read_text())
    assert saved["command"]["name"] == "map" and saved["command"]["options"]["gamma"] == 0.04
    assert "out" not in saved["command"]["options"] and "workers" not in saved["command"]["options"]
    capsys.readouterr()
    assert main(["map", "--config", str(tmp_path / "a" / "map.json"), "--out", str(tmp_path / "b"),
                 "--no-progress"]) == 0  # fmt: skip
    assert "rerun exactly" in capsys.readouterr().out
    again = json.loads((tmp_path / "b" / "map.json").read_text())
    assert again["config_sha256"] == saved["config_sha256"]
    a, b = rocking.load(tmp_path / "a" / "map.json"), rocking.load(tmp_path / "b" / "map.json")
    for k, v in a.arrays.items():
        np.testing.assert_array_equal(b.arrays[k], v, err_msg=k)
    # An option given on the command line wins, and the changed configuration is said.
    assert main(["map", "--config", str(tmp_path / "a" / "map.json"), "--out", str(tmp_path / "c"), "--gamma", "0.05",
                 "--no-progress"]) == 0  # fmt: skip
    assert "rerun of" in capsys.readouterr().out
    assert rocking.load(tmp_path / "c" / "map.json").config["damper"]["gamma"] == 0.05


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    return err


def test_bad_configs_and_foreign_files_are_refused_in_one_line(tmp_path, capsys):
    assert main([*MAP, "--out", str(tmp_path)]) == 0
    record = json.loads((tmp_path / "map.json").read_text())
    capsys.readouterr()
    assert main(["spectrum", "--config", str(tmp_path / "map.json")]) == 2
    assert "a study of 'rocking map', not of 'rocking spectrum'" in _one_line(capsys)
    record["command"]["options"]["warp_speed"] = 9
    (tmp_path / "unknown.json").write_text(json.dumps(record))
    assert main(["map", "--config", str(tmp_path / "unknown.json")]) == 2
    assert "unknown option(s) warp_speed" in _one_line(capsys)
    (tmp_path / "text.json").write_text("not json")
    assert main(["map", "--config", str(tmp_path / "text.json")]) == 2
    assert "not a saved study's JSON" in _one_line(capsys)
    del record["command"]
    (tmp_path / "python.json").write_text(json.dumps(record))
    assert main(["map", "--config", str(tmp_path / "python.json")]) == 2
    assert "saved without its command line" in _one_line(capsys)


def test_a_study_of_another_format_is_refused(tmp_path):
    assert main([*MAP, "--out", str(tmp_path)]) == 0
    record = json.loads((tmp_path / "map.json").read_text())
    record["format"] = 1
    (tmp_path / "map.json").write_text(json.dumps(record))
    with pytest.raises(rocking.ParameterError, match="format 1 .* this version reads format"):
        rocking.load(tmp_path / "map.json")


def test_simulate_json_names_the_model_versions_and_units(capsys):
    argv = ["simulate", "--beta", "3", "--Omega", "4", "--gamma", "0.05", "--omega-ratio", "1", "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "omd"
    assert out["versions"]["rocking"] == rocking.__version__ and out["versions"]["numpy"]
    assert out["units"]["theta_max"] == "rad" and out["units"]["k_m"] == "N/m" and out["units"]["a_g"] == "m/s^2"
    assert set(out["responses"]["with damper"]) <= set(out["units"])
    assert main(["simulate", "--beta", "3", "--Omega", "4", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["model"] == "block"
