"""The command-line reference of the documentation site, written from the ``rocking`` parser at each build.

``docs/conf.py`` calls :func:`write` before Sphinx reads the sources: every command of
:func:`rocking.cli.main.build_parser` (and the derivation's own parser, :func:`rocking.derive.cli.make_parser`)
becomes a section with one table per option group: the option as typed, its meaning as ``--help`` prints it
(units there), and its default. The page is text made from the parser alone, so the same code gives the same
page, and ``tests/test_docs_reference.py`` checks that every command and option is on it.
"""

from __future__ import annotations

import argparse
import copy
import re
from pathlib import Path

from rocking.cli.main import build_parser

#: Width of the option column's formatter (no terminal is asked: the page must not depend on it).
WIDTH = 100

#: Where a help text states a default: "(default 0.05 m)", "(default: a damping ratio of 0.1)", "; default 1".
STATED_DEFAULT = re.compile(r"(?:^|[(;,] ?)default:? ")

#: Characters Markdown would read as markup; CommonMark lets a backslash escape any ASCII punctuation.
MARKUP = re.compile(r"([\\`*_{}\[\]<>|$~#+!])")


#: A flag in a help text (``--k-m``), shown as code: as typed, and never joined into a dash by the typesetter;
#: a Python name (``rocking.Stops.at_edges``), shown as a link to its page in the API reference.
TOKEN = re.compile(r"(?<![\w-])(--[A-Za-z][\w-]*)|\b(rocking(?:\.[A-Za-z_]\w*)+)")


def escape(text: str) -> str:
    """``text`` as literal Markdown (no emphasis, table cell, math or link), its flags as code and its Python
    names as cross-references (a name the API reference does not document stays code, without a warning)."""
    text = " ".join(text.split())
    out, end = [], 0
    for found in TOKEN.finditer(text):
        out.append(MARKUP.sub(r"\\\1", text[end : found.start()]))
        flag, name = found.groups()
        out.append(f"`{flag}`" if flag else f"{{py:obj}}`{name}`")
        end = found.end()
    out.append(MARKUP.sub(r"\\\1", text[end:]))
    return "".join(out)


def commands(parser: argparse.ArgumentParser) -> dict[str, tuple[str, argparse.ArgumentParser]]:
    """``{name: (one-line help, parser)}`` of the subcommands of ``parser``, in its order."""
    (sub,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    helps = {choice.dest: choice.help or "" for choice in sub._choices_actions}
    return {name: (helps.get(name, ""), p) for name, p in sub.choices.items()}


def derive_parser() -> argparse.ArgumentParser | None:
    """The parser of ``rocking derive`` (the derivation's own), or None without its extra (SymPy)."""
    try:
        from rocking.derive.cli import make_parser
    except ModuleNotFoundError:
        return None
    return make_parser(prog="rocking derive")


def default_of(action: argparse.Action) -> str:
    """The default of an option: argparse's own, else the one its help states, else empty."""
    if isinstance(action, argparse._StoreTrueAction):
        return "off"
    value = action.default
    if value not in (None, argparse.SUPPRESS) and value != []:
        return " ".join(map(number, value)) if isinstance(value, (list, tuple)) else number(value)
    if action.required:
        return "required"
    return stated_default(action.help or "")


def stated_default(text: str) -> str:
    """The default a help text states, up to the end of its clause: ``(default m (60 omega_m)^2: ...)`` gives
    ``m (60 omega_m)^2``; empty when it states none."""
    found = STATED_DEFAULT.search(text)
    if not found:
        return ""
    depth, end = 0, len(text)
    for i, char in enumerate(text[found.end() :], found.end()):
        if char == "(":
            depth += 1
        elif char == ")" and depth == 0:
            end = i
            break
        elif char == ")":
            depth -= 1
        elif char in ";:," and depth == 0:
            end = i
            break
    return text[found.end() : end].strip()


def number(value) -> str:
    """A default as the help texts write it: ``2`` for ``2.0``, ``1e-08``; other values as they are."""
    return f"{value:g}" if isinstance(value, float) else str(value)


def meaning(parser: argparse.ArgumentParser, action: argparse.Action) -> str:
    """The help text of ``action`` as ``--help`` prints it (``%(default)s`` expanded), with its choices."""
    formatter = parser.formatter_class(prog=parser.prog, width=WIDTH)
    text = formatter._expand_help(action) if action.help else ""
    if action.choices is not None and not isinstance(action, argparse._SubParsersAction):
        text += f" (one of: {', '.join(map(str, action.choices))})"
    return text.strip()


def invocation(parser: argparse.ArgumentParser, action: argparse.Action) -> str:
    """How the option is typed, as ``--help`` shows it: ``--Omega MIN MAX N``, ``--stops``, ``FILE``."""
    formatter = parser.formatter_class(prog=parser.prog, width=WIDTH)
    if action.option_strings:
        if action.choices is not None and action.metavar is None:
            # the choices are listed in the meaning: --pulse PULSE, not --pulse {sine,cosine,...}
            action = copy.copy(action)
            action.metavar = action.dest.upper()
        # a | would end the table's cell, even in code: NAME|FOLDER is written NAME/FOLDER
        return formatter._format_action_invocation(action).replace("|", "/")
    return formatter._metavar_formatter(action, action.dest)(1)[0].replace("|", "/")


def options_table(parser: argparse.ArgumentParser, actions: list[argparse.Action]) -> list[str]:
    """A Markdown table of ``actions``: option, meaning, default."""
    rows = ["| option | meaning | default |", "| --- | --- | --- |"]
    for action in actions:
        if action.help == argparse.SUPPRESS or isinstance(action, argparse._HelpAction):
            continue
        rows.append(
            f"| `{invocation(parser, action)}` | {escape(meaning(parser, action))} | {escape(default_of(action))} |"
        )
    return rows if len(rows) > 2 else []


def command_section(name: str, summary: str, parser: argparse.ArgumentParser) -> list[str]:
    """The section of one command: its description, then a table per option group."""
    lines = [f"## rocking {name}", "", escape(parser.description or summary), ""]
    for group in parser._action_groups:
        table = options_table(parser, group._group_actions)
        if not table:
            continue
        lines += [f"### {escape(group.title or '')}", ""]
        if group.description:
            lines += [escape(group.description), ""]
        lines += [*table, ""]
    if parser.epilog:
        lines += [escape(parser.epilog), ""]
    return lines


def page() -> str:
    """The Markdown of the command-line reference."""
    parser = build_parser()
    found = commands(parser)
    derive = derive_parser()
    lines = [
        "# Command-line reference",
        "",
        "Every command of `rocking` and every option, written from the command's own parser when this site was "
        "built (`rocking COMMAND --help` prints the same). Units are SI and stated in each option's meaning; an "
        "option not given takes the default of the Python function it calls (the default column; empty: not "
        "used unless given). Run a command as `rocking COMMAND ...` after an install, or "
        "`.venv/bin/rocking COMMAND ...` in a clone after `make setup`.",
        "",
        escape(parser.description or ""),
        "",
        "| command | what it does |",
        "| --- | --- |",
        *(f"| [`rocking {name}`](#rocking-{name}) | {escape(summary)} |" for name, (summary, _) in found.items()),
        "",
    ]
    for name, (summary, sub) in found.items():
        lines += command_section(name, summary, derive if name == "derive" and derive is not None else sub)
    return "\n".join(lines).rstrip() + "\n"


def write(path: Path) -> Path:
    """Write :func:`page` to ``path`` (only when it changed, so that Sphinx rebuilds it only then)."""
    text = page()
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return path
