"""Reproducibility: a saved study reruns from its JSON (--config); --json outputs carry model, versions, units.
Hostile saved studies (issue 23): --config and rocking.load refuse them in one line, before any work."""

from __future__ import annotations

import copy
import functools
import json
import os
import re
import signal
import tempfile
from contextlib import contextmanager
from pathlib import Path

import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rocking
import rocking.cli.study
from rocking.cli.main import main
from rocking.study.config import config_hash

MAP = ["map", "--Omega", "1", "6", "4", "--beta", "1", "6", "5", "--gamma", "0.04", "--no-progress", "--workers", "1"]


def test_a_saved_study_reruns_exactly_from_its_json(tmp_path, capsys):
    assert main([*MAP, "--out", str(tmp_path / "a")]) == 0
    saved = json.loads((tmp_path / "a" / "map.json").read_text())
    assert saved["command"]["name"] == "map" and saved["command"]["options"]["gamma"] == 0.04
    assert "out" not in saved["command"]["options"] and "workers" not in saved["command"]["options"]
    capsys.readouterr()
    assert (
        main(["map", "--config", str(tmp_path / "a" / "map.json"), "--out", str(tmp_path / "b"), "--no-progress"]) == 0
    )
    assert "rerun exactly" in capsys.readouterr().out
    again = json.loads((tmp_path / "b" / "map.json").read_text())
    assert again["config_sha256"] == saved["config_sha256"]
    a, b = rocking.load(tmp_path / "a" / "map.json"), rocking.load(tmp_path / "b" / "map.json")
    xr.testing.assert_identical(b.data, a.data)
    # An option given on the command line wins, and the changed configuration is said.
    assert (
        main(
            [
                "map",
                "--config",
                str(tmp_path / "a" / "map.json"),
                "--out",
                str(tmp_path / "c"),
                "--gamma",
                "0.05",
                "--no-progress",
            ]
        )
        == 0
    )
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


# --- hostile saved studies (issue 23) --------------------------------------------------------------


@pytest.fixture(scope="module")
def saved(studies):
    """A map saved from the command line: its folder and its JSON record."""
    return studies["map"]


#: Studies the fuzz tests mutate, each as saved by its command (small grids, a suite of two pulses).
FUZZED = {
    "map": MAP[1:],
    "spectrum": ["--Omega", "2", "6", "2", "--beta", "0.5", "8", "6", "--no-progress", "--workers", "1"],
    "fragility": ["--pulses", "ricker", "--periods", "0.5", "1", "--amplitude", "2", "--im", "amplitude",
                  "--levels", "2", "12", "2", "--t-after", "5", "--no-progress", "--workers", "1"],
}  # fmt: skip


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    """Each study of :data:`FUZZED`, saved from the command line: kind -> (folder, JSON record)."""
    found = {}
    for kind, argv in FUZZED.items():
        folder = tmp_path_factory.mktemp(kind)
        assert main([kind, *argv, "--out", str(folder)]) == 0
        found[kind] = folder, json.loads((folder / f"{kind}.json").read_text())
    return found


class Reached(Exception):
    """The study's work would start: every check passed."""


#: The study functions the commands call, where their work starts.
STUDIES = ("overturning_map", "minimum_overturning_spectrum", "incremental_dynamic_analysis")


@pytest.fixture
def no_work(monkeypatch):
    """Studies of the command line stop where their work would start."""
    for name in STUDIES:
        real = getattr(rocking.cli.study, name)

        @functools.wraps(real)  # its signature gives the command line's defaults
        def stop(*args, **kwargs):
            raise Reached

        monkeypatch.setattr(rocking.cli.study, name, stop)


def _rerun(path: Path, out: Path, command: str = "map") -> int:
    return main([command, "--config", str(path), "--out", str(out), "--no-progress", "--workers", "1"])


def _with(record: dict, where: tuple, value) -> dict:
    changed = copy.deepcopy(record)
    node = changed
    for key in where[:-1]:
        node = node[key]
    node[where[-1]] = value
    return changed


HOSTILE_CONFIGS = {
    "Omega an object": (("command", "options", "Omega"), {"a": 1}, "option Omega (--Omega) must be a list of 3"),
    "block a path": (("command", "options", "block"), "/etc/passwd", "option block (--block) must be one of"),
    "model an object": (("command", "options", "model"), {}, "option model (--model) must be a string, or null"),
    "format 99": (("format",), 99, "a study saved in format 99"),
    "gamma a text": (("command", "options", "gamma"), "abc", "option gamma (--gamma) must be a number"),
    "tile huge": (("command", "options", "tile"), [1e300, 5], "option tile (--tile) must be a list of 2 values"),
    "grid of two": (("command", "options", "beta"), ["1", "6"], "option beta (--beta) must be a list of 3 values"),
    "config NaN": (("config", "rtol"), float("nan"), "its config holds NaN or infinity"),
}


@pytest.mark.parametrize("case", HOSTILE_CONFIGS)
def test_hostile_configs_are_refused_in_one_line_before_any_work(case, saved, tmp_path, capsys, no_work):
    where, value, message = HOSTILE_CONFIGS[case]
    path = tmp_path / "hostile.json"
    path.write_text(json.dumps(_with(saved[1], where, value)))
    assert _rerun(path, tmp_path / "out") == 2
    err = _one_line(capsys)
    assert err.startswith(f"rocking map: error: --config {path}: ") and message in err, err
    assert not (tmp_path / "out").exists()


def test_deep_and_huge_json_is_refused_before_it_is_parsed(tmp_path, capsys):
    deep = tmp_path / "deep.json"
    deep.write_text('{"config": ' + "[" * 100_000 + "]" * 100_000 + "}")
    assert main(["map", "--config", str(deep)]) == 2
    assert "nested 100001 deep, at most 32" in _one_line(capsys)
    assert main(["map", "--config", "/dev/zero"]) == 2  # a device: never opened
    assert "under /dev: not an input file" in _one_line(capsys)
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    assert main(["map", "--config", str(fifo)]) == 2  # not a regular file: never read (a FIFO would block)
    assert "not a regular file" in _one_line(capsys)
    with pytest.raises(rocking.ParameterError, match="nested 100001 deep"):
        rocking.load(_copy_nc_beside(deep))


def _copy_nc_beside(meta: Path) -> Path:
    meta.with_suffix(".nc").write_bytes(b"\x89HDF\r\n\x1a\n")
    return meta


CONTRADICTIONS = {
    "Omega.n 1e9": (("Omega", "n"), 1e9, "config: Omega: the number of values N must be an integer in [1, 100000]"),
    "Omega.n negative": (("Omega", "n"), -3, "config: Omega: the number of values N must be an integer"),
    "Omega.n another": (("Omega", "n"), 5, "variables: Omega has 4 values along Omega, not 5"),
    "Omega.high": (("Omega", "high"), 7.0, "config: Omega gives other values than the coordinate Omega holds"),
    "signs 7": (("signs",), [1, -1, 7], "config: signs must be the directions of the pulses"),
    "one sign": (("signs",), [1], "config: directions.signs must be the study's signs [1] (got [1, -1])"),
    "block a path": (("block",), "/etc/passwd", "config: setting: block must be the record of a rocking.Block"),
}


@pytest.mark.parametrize("case", CONTRADICTIONS)
def test_a_loaded_configuration_must_agree_with_its_arrays(case, saved, tmp_path):
    where, value, message = CONTRADICTIONS[case]
    record = _with(saved[1], ("config", *where), value)
    record["config_sha256"] = config_hash(record["config"])  # a consistent forgery
    (tmp_path / "map.json").write_text(json.dumps(record))
    (tmp_path / "map.nc").write_bytes((saved[0] / "map.nc").read_bytes())
    with pytest.raises(rocking.ParameterError, match=re.escape(f"{tmp_path / 'map.json'}: {message}")):
        rocking.load(tmp_path / "map")


def test_a_data_file_larger_than_its_record_allows_is_refused_unread(saved, tmp_path):
    """The NetCDF file's size is checked against the variables its JSON lists before the file is read: a file of
    gigabytes (here sparse) is refused at once."""
    (tmp_path / "map.json").write_text((saved[0] / "map.json").read_text())
    with open(tmp_path / "map.nc", "wb") as f:
        f.truncate(1 << 32)
    with pytest.raises(rocking.ParameterError, match=r"map.nc: 4294967296 bytes, more than the \d+ its JSON allows"):
        rocking.load(tmp_path / "map")


# --- fuzz: --config and rocking.load on mutated saved studies ---------------------------------------

#: Examples per fuzz test and kind of study (ROCKING_FUZZ_EXAMPLES for a longer run).
FUZZ_EXAMPLES = int(os.environ.get("ROCKING_FUZZ_EXAMPLES", "30"))

#: Seconds an example may take before it counts as a hang.
HANG = 20

DEEP = "\x00deep\x00"

scalars = st.one_of(
    st.none(), st.booleans(), st.integers(-(2**70), 2**70), st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, -1, 1e9, 1e308, -1e308, 2**63, "", "/etc/passwd", "1e999", "nan", "-1", "omd", "map",
                     "reference", "sine", "c", "../..", DEEP]),
    st.text(max_size=20),
)  # fmt: skip
values = st.recursive(
    scalars,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=8,
)


def _paths(node, prefix=()) -> list[tuple]:
    """Every place in a JSON value: the keys and indices to it."""
    found = [prefix] if prefix else []
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for key, child in items:
        found += _paths(child, (*prefix, key))
    return found


def _mutate(record: dict, data, places: list) -> str:
    """The JSON text of ``record`` with a few places replaced by hostile values or new keys."""
    changed = copy.deepcopy(record)
    for _ in range(data.draw(st.integers(1, 3))):
        where = data.draw(st.sampled_from(places))
        new_key = data.draw(st.text(min_size=1, max_size=8)) if data.draw(st.booleans()) else None
        value = data.draw(values)
        try:
            parent = _node(changed, where[:-1])
            parent[new_key if new_key is not None and isinstance(parent, dict) else where[-1]] = value
        except (KeyError, IndexError, TypeError):  # the place went with an earlier change
            continue
    if data.draw(st.booleans()):  # its hash made again: a consistent forgery
        try:
            changed["config_sha256"] = config_hash(changed["config"])
        except (ValueError, TypeError, KeyError):
            pass
    text = json.dumps(changed)
    depth = data.draw(st.sampled_from([30, 33, 1000, 100_000]))
    return text.replace(json.dumps(DEEP), "[" * depth + "]" * depth)


def _node(record, where):
    for key in where:
        record = record[key]
    return record


class Hang(Exception):
    """An example ran longer than :data:`HANG` seconds."""


@contextmanager
def _deadline(seconds: int):
    def expired(signum, frame):
        raise Hang(f"more than {seconds} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


#: What each fuzz test saw: refused in one line, accepted (the work would start, or a study loaded).
OUTCOMES: dict = {}

FUZZ = settings(
    max_examples=FUZZ_EXAMPLES,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


def _count(test: str, outcome: str) -> None:
    OUTCOMES.setdefault(test, {}).setdefault(outcome, 0)
    OUTCOMES[test][outcome] += 1


@pytest.mark.parametrize("kind", FUZZED)
@FUZZ
@given(data=st.data())
def test_fuzz_config_refuses_in_one_line_or_reaches_the_work(kind, studies, tmp_path, capsys, no_work, data):
    record = studies[kind][1]
    places = [p for p in _paths(record) if p[0] in ("command", "config", "format", "kind", "config_sha256")]
    path = tmp_path / "fuzz.json"
    path.write_text(_mutate(record, data, places))
    capsys.readouterr()
    try:
        with _deadline(HANG):
            code = _rerun(path, tmp_path / "out", kind)
    except Reached:
        _count(f"--config, {kind}", "reached the work")
        return
    except SystemExit as exc:  # argparse, in one line
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and err.startswith(f"rocking {kind}: error: "), (code, err)
    _count(f"--config, {kind}", "refused")


@pytest.mark.parametrize("kind", FUZZED)
@FUZZ
@given(data=st.data())
def test_fuzz_load_refuses_with_a_parameter_error_or_loads(kind, studies, tmp_path, data):
    source, record = studies[kind]
    folder = Path(tempfile.mkdtemp(dir=tmp_path))
    (folder / f"{kind}.nc").write_bytes((source / f"{kind}.nc").read_bytes())
    (folder / f"{kind}.json").write_text(_mutate(record, data, _paths(record)))
    outcome = "loaded"
    try:
        with _deadline(HANG):
            rocking.load(folder / kind)
    except rocking.ParameterError as exc:
        assert "\n" not in str(exc) and str(folder / kind) in str(exc), str(exc)
        outcome = "refused"
    _count(f"load, {kind}", outcome)


def test_fuzz_counts(capsys):
    """Print what the fuzz tests saw (pytest -s): their examples all ended in one of these."""
    with capsys.disabled():
        print(f"\nfuzz ({FUZZ_EXAMPLES} examples each): {OUTCOMES}")
