"""The documentation site documents every command, every option and every public name.

The command-line reference is written from the parser at each build (docs/cli_reference.py); the API
reference lists names by task (docs/api.rst). These tests hold both to what the code offers, so a new
command, option or public name cannot be left off the site.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import importlib.util
import json
import re
from pathlib import Path

import pytest

import rocking
from rocking.cli.main import build_parser

DOCS = Path(__file__).resolve().parent.parent / "docs"
EXAMPLES = DOCS.parent / "examples"


def _module(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


cli_reference = _module("cli_reference", DOCS / "cli_reference.py")


@pytest.fixture(scope="module")
def page() -> str:
    return cli_reference.page()


def _documented_parsers() -> dict[str, argparse.ArgumentParser]:
    """Each command's parser as the page documents it (derive: the derivation's own, which holds its options)."""
    found = {name: sub for name, (_, sub) in cli_reference.commands(build_parser()).items()}
    derive = cli_reference.derive_parser()
    if derive is not None:
        found["derive"] = derive
    return found


def _options(parser: argparse.ArgumentParser) -> list[argparse.Action]:
    return [a for a in parser._actions if a.help != argparse.SUPPRESS and not isinstance(a, argparse._HelpAction)]


def test_every_command_has_a_section_in_the_command_line_reference(page):
    commands = cli_reference.commands(build_parser())
    assert {"simulate", "map", "spectrum", "design", "ida", "fragility", "verify", "derive"} <= set(commands)
    for name in commands:
        assert f"\n## rocking {name}\n" in page, name
        assert f"[`rocking {name}`](#rocking-{name})" in page, name


def test_every_option_is_a_row_with_its_meaning(page):
    rows = {line.split(" | ")[0].removeprefix("| ") for line in page.splitlines() if line.startswith("| `")}
    for name, parser in _documented_parsers().items():
        for action in _options(parser):
            shown = cli_reference.invocation(parser, action)
            assert f"`{shown}`" in rows, f"rocking {name} {shown}"
            assert cli_reference.meaning(parser, action), f"rocking {name} {shown} has no help text"


def test_the_reference_is_the_same_text_at_each_build(page):
    assert cli_reference.page() == page


def test_table_cells_hold_no_markup(page):
    # A bare | would split a row, a bare $ would start math: every row keeps its three cells.
    for line in page.splitlines():
        if line.startswith("| `"):
            assert len(re.findall(r"(?<!\\)\|", line)) == 4, line


@pytest.mark.parametrize(
    ("text", "default"),
    [
        ("height, m (default 0.05 m with --gamma, as rocking.Tuning; ...)", "0.05 m with --gamma"),
        ("bumper stiffness, N/m (default m (60 omega_m)^2: a bumper frequency)", "m (60 omega_m)^2"),
        ("dashpot (default: a damping ratio of 0.2)", "a damping ratio of 0.2"),
        ("a block by name; the default when no block option is given", ""),
        ("half-stroke, m", ""),
    ],
)
def test_stated_default(text, default):
    assert cli_reference.stated_default(text) == default


def _api_entries() -> set[str]:
    """The names listed in docs/api.rst's autosummary tables, relative to ``rocking``."""
    text = (DOCS / "api.rst").read_text(encoding="utf-8")
    entries = set()
    for block in re.findall(r"\.\. autosummary::\n((?:   .*\n|\n)+)", text):
        entries |= {line.strip() for line in block.splitlines() if line.strip() and not line.strip().startswith(":")}
    return entries


def test_every_public_name_is_in_the_api_reference():
    entries = _api_entries()
    missing = sorted(set(rocking.__all__) - entries)
    assert not missing, f"not in docs/api.rst: {missing}"


def test_every_api_entry_exists():
    for entry in _api_entries():
        module, _, name = f"rocking.{entry}".rpartition(".")
        assert hasattr(importlib.import_module(module), name), entry


def _tutorial_names() -> set[str]:
    """``rocking`` functions, classes and methods the tutorial calls: ``rocking.X``, ``rocking.a.b.f``,
    ``from rocking.a import f`` (constants in capitals left out: data, documented where they are used)."""
    notebook = json.loads((EXAMPLES / "tutorial.ipynb").read_text(encoding="utf-8"))
    code = "\n".join("".join(c["source"]) for c in notebook["cells"] if c["cell_type"] == "code")
    names = set()
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("rocking."):
            names |= {f"{node.module}.{a.name}".removeprefix("rocking.") for a in node.names}
        elif isinstance(node, ast.Attribute) and not isinstance(node.ctx, ast.Store):
            chain = []
            part = node
            while isinstance(part, ast.Attribute):
                chain.append(part.attr)
                part = part.value
            if isinstance(part, ast.Name) and part.id == "rocking":
                names.add(".".join(reversed(chain)))
    return {n for n in names if not _is_module(n) and not n.rpartition(".")[2].isupper() and n != "__version__"}


def _is_module(name: str) -> bool:
    try:
        importlib.import_module(f"rocking.{name}")
    except ModuleNotFoundError:
        return False
    return True


def test_every_name_the_tutorial_uses_is_in_the_api_reference():
    used = _tutorial_names()
    assert {"simulate", "plot.response.response_figure"} <= used
    entries = _api_entries()
    # a method (Damper.from_nondim) is documented on its class's page
    missing = sorted(n for n in used if n not in entries and n.rpartition(".")[0] not in entries)
    assert not missing, f"the tutorial uses names not in docs/api.rst: {missing}"


def _resolves(dotted: str) -> bool:
    """Whether ``dotted`` (``rocking.Stops.at_edges``, ``rocking.model.records.read_record``) names an object."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ModuleNotFoundError:
            continue
        for attr in parts[cut:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


def test_every_python_name_the_command_line_reference_cites_exists(page):
    # the help texts say which Python call each option sets: a renamed one must not leave a stale name there
    cited = set(re.findall(r"\{py:obj\}`([\w.]+)`", page))
    assert {"rocking.Block", "rocking.Stops.at_edges"} <= cited
    assert not sorted(n for n in cited if not _resolves(n))
