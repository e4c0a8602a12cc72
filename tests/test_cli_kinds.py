"""The study commands are built from the registry of kinds: one subcommand per entry, a new kind gets its own."""

import argparse

import pytest

import rocking
import rocking.cli.study
from rocking.cli.main import build_parser, main
from rocking.cli.study import GROUPS
from rocking.study import api
from rocking.study.config import Grid, Setting
from rocking.study.kinds import KINDS, Command, Kind
from rocking.study.result import Study
from rocking.study.tiles import Execution
from tests.test_python_cli import FUNCTIONS


def _commands(parser: argparse.ArgumentParser) -> dict:
    (commands,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return commands.choices


def _helps(parser: argparse.ArgumentParser) -> dict:
    (commands,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {action.dest: action.help for action in commands._choices_actions}


@pytest.mark.parametrize("name", sorted(KINDS))
def test_every_kind_has_its_command_built_from_its_entry(name):
    command = KINDS[name].command
    parser = build_parser()
    assert _helps(parser)[name] == command.help
    assert {group for group, _ in command.options} <= set(GROUPS)
    # Its Python function is the one whose keywords are its options (tests/test_python_cli.py).
    assert getattr(api, command.function) is FUNCTIONS[name] and callable(getattr(rocking.cli.study, command.describe))
    args = _commands(parser)[name].parse_args([])
    for group, params in command.options:
        if group == "grid" and "si" in params:  # left None, its default applied unless its SI alternative is given
            assert getattr(args, params["name"]) is None and getattr(args, params["si"]) is None
            grid = rocking.cli.study._grid_values(args, params)[params["name"]]
            assert grid == rocking.cli.study.grid_from(params["name"], params["default"]), (name, params["name"])
        elif group in ("grid", "levels"):
            assert tuple(getattr(args, params["name"])) == params["default"], (name, params["name"])


def toy_driver(setting, Omega, execution, *, runs, directions="auto"):
    """A study of a toy kind: records how it was called."""
    return Study(
        "toy",
        {"directions": directions},
        None,
        summary={"setting": setting, "Omega": Omega, "execution": execution, "runs": runs},
    )


def test_a_kind_registered_at_run_time_gets_its_command(monkeypatch, tmp_path, capsys):
    command = Command(
        "a toy study over Omega",
        (
            ("block", {}),
            ("grid", {"name": "Omega", "default": (1.0, 3.0, 3), "help": "pulse frequency ratios"}),
            ("directions", {}),
            ("solver", {}),
        ),
        ("setting", "Omega", "execution"),
        "overturning_map",
        "toy_lines",
    )
    kind = Kind(toy_driver, {"Omega": "Omega"}, lambda data, config: {}, "toy_figure", {}.__getitem__, command)
    monkeypatch.setitem(KINDS, "toy", kind)
    monkeypatch.setattr(rocking.cli.study, "toy_lines", lambda study: ["toy: done", "toy: twice"], raising=False)
    reported = []
    monkeypatch.setattr(rocking.cli.study, "_report", lambda study, out, formats: reported.append((study, out)))

    parser = _commands(build_parser())["toy"]
    assert _helps(build_parser())["toy"] == "a toy study over Omega"
    assert "--Omega MIN MAX N" in parser.format_help() and "--H H" in parser.format_help()

    out = tmp_path / "out"
    assert main(["toy", "--Omega", "2", "4", "5", "--rtol", "1e-6", "--no-progress", "--out", str(out)]) == 0
    ((study, folder),) = reported
    assert folder == out and study.summary["runs"] == out / "runs"
    assert study.summary["Omega"] == Grid("Omega", 2.0, 4.0, 5)
    assert study.summary["setting"] == Setting(rocking.Block.reference(), rtol=1e-6)
    assert study.summary["execution"] == Execution(progress=False)
    assert study.config == {"directions": "auto"}  # the driver's default: an option not given is not passed
    assert capsys.readouterr().out == "toy: done\ntoy: twice\n"

    assert main(["toy", "--Omega", "2", "x", "5", "--out", str(tmp_path / "bad")]) == 2
    assert (
        capsys.readouterr().err
        == "rocking toy: error: --Omega takes MIN MAX N: two numbers and an integer (got 2 x 5)\n"
    )
    assert not (tmp_path / "bad").exists()  # refused before the output folder is made
