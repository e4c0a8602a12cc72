"""The Python examples of the README run as written, in order (each may use the names of those before it)."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parent.parent / "README.md"


def test_the_readme_examples_run(capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    assert len(blocks) >= 2
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, str(README), "exec"), namespace)  # noqa: S102 - the project's own documentation
        assert capsys.readouterr().out.strip(), block  # each example prints its results
    assert namespace["r"].stop_contacts >= 1  # the end-stop example meets the stops


def test_the_readme_commands_parse():
    """Every `rocking` command line of the README is accepted by the command's parser (not run: some take
    minutes or name the reader's own files)."""
    import shlex

    from rocking.cli.main import build_parser

    lines = re.findall(r"^    \.venv/bin/rocking (.*)$", README.read_text(encoding="utf-8"), re.M)
    assert len(lines) >= 10
    parser = build_parser()
    for line in lines:
        argv = shlex.split(line.split("  #")[0])
        if argv[0] == "derive":
            continue  # handed to rocking.derive's own parser
        args = parser.parse_args(argv)
        assert callable(args.func), line


def test_the_readme_counts_are_those_the_code_gives():
    """Numbers the README quotes are measured here, not typed: the functions `rocking verify` checks, the
    hostile specs of the security tests."""
    from rocking import load_model
    from rocking.reference.verify import verify
    from tests.test_spec_security import CORPUS, EXPENSIVE

    text = README.read_text(encoding="utf-8")
    checks = len(verify(load_model("omd"), n=2, seed=1))  # the README shows the report of omd
    assert f"    {checks} passed, 0 failed (tolerance 1e-12)" in text
    assert f"runs {len(CORPUS)} hostile specs and {len(EXPENSIVE)} short specs that are costly to derive" in text
