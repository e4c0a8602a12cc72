"""``rocking <study> --config saved.json``: rerun a saved study with the options it was run with.

A study run from the command line saves, in its JSON record, the command and the options that decide its
results (:func:`command_record`): not where it ran (``--out``, ``--workers``, a Dask cluster, the progress
bar). ``--config`` reads them back (:func:`apply_config`): an option given on the command line wins over
the file's, so ``--out`` or ``--workers`` can change, and the study then checks that its configuration is
the saved one (:func:`check_same`).
"""

from __future__ import annotations

import argparse
import json
import math
from contextvars import ContextVar
from pathlib import Path

from ..model.loading import ModelError, saved_model
from ..model.params import ParameterError, shown
from ..study.config import config_hash, name_text
from ..study.result import Study
from ..study.storage import read_record

#: Options that say where and how a study runs, not what it computes: never saved, never read back.
EXECUTION = frozenset(
    {"command", "func", "config", "rerun", "out", "workers", "scheduler", "dask_workers", "no_progress"}
    | {"formats", "pdf"}  # the figure's files
)

#: Options of earlier versions that are gone, by command, and why. A saved study that did not give one (its saved
#: value null, or 1, the step that computes every amplitude) reruns as before; one that did is refused in one line.
REMOVED = {
    ("spectrum", "coarse"): "adaptive beta scans, which could miss bands of overturning amplitudes and report a "
    "beta_min too high (issue 35); spectra now scan every amplitude: run rocking spectrum again without it",
}

#: The command being run and its options, for the record its study saves.
CURRENT: ContextVar[dict | None] = ContextVar("rocking_command", default=None)


def command_record(args: argparse.Namespace) -> dict:
    """The command and the options of ``args`` that decide its results, JSON-ready.

    An infinite number (``--mu inf``, the paper's floor) is kept as its text, which JSON holds and the option reads
    back (:func:`_value`).
    """
    options = {k: _finite_or_text(v) for k, v in sorted(vars(args).items()) if k not in EXECUTION}
    return {"name": args.command, "options": json.loads(json.dumps(options, default=str))}


def _finite_or_text(value):
    return repr(value) if isinstance(value, float) and not math.isfinite(value) else value


def _read(path: Path) -> dict:
    """The saved study's record at ``path`` (:func:`rocking.study.storage.read_record`: bounded in size and
    depth, of this format), its configuration plain JSON (:func:`check_same` hashes it)."""
    try:
        record = read_record(path)
    except ParameterError as exc:
        raise ParameterError(f"--config {exc}") from None
    try:
        config_hash(record["config"])
    except ValueError:
        raise ParameterError(f"--config {path}: its config holds NaN or infinity (not saved by rocking)") from None
    return record


def _expected(action: argparse.Action) -> str:
    """What an option's saved value must be, in words."""
    if isinstance(action, argparse._StoreConstAction):
        return f"{json.dumps(action.const)} or {json.dumps(action.default)}"
    # The grids' MIN MAX N are texts on the command line, numbers in their defaults: either is read.
    text = "a number" if isinstance(action.nargs, int) else "a string"
    one = {float: "a number", int: "an integer"}.get(action.type, text)
    if action.choices is not None:
        one = f"one of {', '.join(map(str, action.choices))}"
    if isinstance(action, argparse._AppendAction):
        return f"a list of values, each {one}"
    if action.nargs is None:
        return one if action.default is not None else f"{one}, or null"
    count = "one or more" if action.nargs == "+" else action.nargs
    return f"a list of {count} values ({' '.join(action.metavar or ())}), each {one}".replace(" ()", "")


def _value(action: argparse.Action, value):
    """One saved value as the command line gives it: the option's type applied to its text, in its choices."""
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        raise ValueError(value)
    text = value if isinstance(value, str) else repr(value)  # repr: the shortest text of the same float
    converted = action.type(text) if action.type is not None else text
    if action.choices is not None and converted not in action.choices:
        raise ValueError(value)
    return converted


def _option(action: argparse.Action, value):
    """A saved option's value checked and typed as ``action`` parses it (ValueError or TypeError if not)."""
    if isinstance(action, argparse._StoreConstAction):
        if not any(value is v for v in (action.const, action.default)):
            raise ValueError(value)
        return value
    if value is None and action.default is None:  # not given
        return None
    if action.nargs is None and not isinstance(action, argparse._AppendAction):
        return _value(action, value)
    if not isinstance(value, list):
        raise ValueError(value)
    if (isinstance(action.nargs, int) and len(value) != action.nargs) or (action.nargs == "+" and not value):
        raise ValueError(value)
    return [_value(action, v) for v in value]


def checked_options(parser: argparse.ArgumentParser, options: dict, path: Path) -> dict:
    """The saved ``options`` of a command, each checked and typed as ``parser`` parses it from the command line.

    Raises
    ------
    ParameterError
        In one line naming the file, the option and what it must be.
    """
    actions = {action.dest: action for action in parser._actions}
    checked = {}
    for name, value in options.items():
        action = actions[name]
        try:
            checked[name] = _option(action, value)
        except (TypeError, ValueError, ArithmeticError):
            flag = action.option_strings[-1] if action.option_strings else name
            raise ParameterError(
                f"--config {path}: option {name} ({flag}) must be {_expected(action)} (got {shown(value)})"
            ) from None
    return checked


def apply_config(parser: argparse.ArgumentParser, args: argparse.Namespace, argv: list[str]):
    """``argv`` parsed again with the options of the study saved at ``args.config`` as the command's defaults:
    an option given in ``argv`` wins. The namespace's ``rerun`` holds the saved record and its path.

    Raises
    ------
    ParameterError
        In one line naming the file: not a saved study, saved without its command (from Python), by another
        command, or with options this version does not know.
    """
    path = Path(args.config)
    record = _read(path)
    command = record.get("command")
    if not isinstance(command, dict) or not isinstance(command.get("options"), dict):
        raise ParameterError(
            f"--config {path}: the study was saved without its command line (from Python, or by an older "
            "version); rerun it from Python with its configuration"
        )
    if command.get("name") != args.command:
        name = command.get("name")
        name = name_text(name) if isinstance(name, str) else shown(name)
        raise ParameterError(f"--config {path}: a study of 'rocking {name}', not of 'rocking {args.command}'")
    saved = _without_removed(args.command, command["options"], path)
    unknown = sorted(set(saved) - (set(vars(args)) - EXECUTION))
    if unknown:
        names = ", ".join(map(name_text, unknown[:5])) + (", ..." if len(unknown) > 5 else "")
        raise ParameterError(
            f"--config {path}: unknown option(s) {names} for 'rocking {args.command}' (saved by another version?)"
        )
    subcommands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    command_parser = subcommands.choices[args.command]
    options = checked_options(command_parser, saved, path)
    _check_model(options.get("model"), args, path)
    command_parser.set_defaults(**options)
    again = parser.parse_args(argv)
    again.rerun = (record, str(path))
    return again


def _without_removed(name: str, options: dict, path: Path) -> dict:
    """The saved ``options`` of command ``name`` without those of :data:`REMOVED` that were not given.

    Raises
    ------
    ParameterError
        In one line naming the file, if one of them was given.
    """
    kept = dict(options)
    for (command, option), why in REMOVED.items():
        value = kept.pop(option, None) if command == name else None
        if value is not None and value != 1:
            raise ParameterError(f"--config {path}: option {option} = {shown(value)} was removed: {why}")
    return kept


def _check_model(saved: object, args: argparse.Namespace, path: Path) -> None:
    """Refuse a saved ``model`` option that is not built in, unless ``--model`` is given again on the command line.

    A saved file never selects code to run (:func:`rocking.model.loading.saved_model`).
    """
    if saved is None or getattr(args, "model", None) is not None:
        return
    try:
        saved_model(saved, f"--config {path}: option model", "rerun with --model DIR")
    except ModelError as exc:
        raise ParameterError(str(exc)) from None


def check_same(study: Study, record: dict, path: str) -> str:
    """A line saying whether ``study`` has the configuration of the saved ``record``."""
    if config_hash(study.config) == record.get("config_sha256", config_hash(record["config"])):
        return f"{study.kind}: the configuration of {path}, rerun exactly"
    changed = sorted(
        k for k in set(study.config) | set(record["config"]) if study.config.get(k) != record["config"].get(k)
    )
    return f"{study.kind}: rerun of {path} with other {', '.join(changed)} (given on the command line)"
