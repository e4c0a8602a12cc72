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
from contextvars import ContextVar
from pathlib import Path

from ..model.loading import ModelError, saved_model
from ..model.params import ParameterError
from ..study.config import Study, config_hash
from ..study.storage import describe

#: Options that say where and how a study runs, not what it computes: never saved, never read back.
EXECUTION = frozenset(
    {"command", "func", "config", "rerun", "out", "workers", "scheduler", "dask_workers", "no_progress"}
)

#: The command being run and its options, for the record its study saves.
CURRENT: ContextVar[dict | None] = ContextVar("rocking_command", default=None)


def command_record(args: argparse.Namespace) -> dict:
    """The command and the options of ``args`` that decide its results, JSON-ready."""
    options = {k: v for k, v in sorted(vars(args).items()) if k not in EXECUTION}
    return {"name": args.command, "options": json.loads(json.dumps(options, default=str))}


def _read(path: Path) -> dict:
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise ParameterError(f"--config {path}: not a saved study's JSON ({describe(exc)})") from None
    if not isinstance(record, dict) or not isinstance(record.get("config"), dict):
        raise ParameterError(f"--config {path}: not a saved study's JSON (no configuration)")
    return record


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
        raise ParameterError(f"--config {path}: a study of 'rocking {command.get('name')}', not of "
                             f"'rocking {args.command}'")  # fmt: skip
    unknown = sorted(set(command["options"]) - (set(vars(args)) - EXECUTION))
    if unknown:
        raise ParameterError(f"--config {path}: unknown option(s) {', '.join(unknown)} for 'rocking {args.command}' "
                             f"(saved by another version?)")  # fmt: skip
    _check_model(command["options"].get("model"), args, path)
    subcommands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    subcommands.choices[args.command].set_defaults(**command["options"])
    again = parser.parse_args(argv)
    again.rerun = (record, str(path))
    return again


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
    changed = sorted(k for k in set(study.config) | set(record["config"])
                     if study.config.get(k) != record["config"].get(k))  # fmt: skip
    return f"{study.kind}: rerun of {path} with other {', '.join(changed)} (given on the command line)"
