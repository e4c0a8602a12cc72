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
    from rocking.reference.verify import report, verify
    from tests.test_spec_security import CORPUS, EXPENSIVE

    text = README.read_text(encoding="utf-8")
    omd = load_model("omd")
    printed = report(omd, verify(omd)).splitlines()  # the README shows the report of omd: its first lines, its last
    assert "\n".join("    " + line for line in printed[:2]) in text
    assert f"    {printed[-1]}" in text and printed[-1].endswith(" 0 failed (tolerance 1e-12)")
    assert f"runs {len(CORPUS)} hostile specs and {len(EXPENSIVE)} short specs that are costly to derive" in text


def test_the_readme_simulate_output_is_what_simulate_prints(capsys):
    """The README quotes rocking simulate's text of the reference block under Omega 7.5, beta 10: its words and
    numbers are those the command prints (the README joins its lines)."""
    from rocking.cli.main import main

    text = " ".join(README.read_text(encoding="utf-8").split())
    argv = ["simulate", "--gamma", "0.05", "--omega-ratio", "1", "--h", "0.05", "--beta", "10", "--Omega", "7.5"]
    assert main(argv) == 0
    unlimited = capsys.readouterr().out.splitlines()
    assert "x_max = 1.102 m" in unlimited[1] and unlimited[2].startswith("  with damper: WARNING: ")
    assert unlimited[2].removeprefix("  with damper: ") in text
    assert main([*argv, "--stops"]) == 0
    stops = capsys.readouterr().out
    for quoted in ("OVERTURNS at t = 2.3453 s;", "2 stop contact(s), bumper force max 6416 N"):
        assert quoted in stops and quoted in text, quoted
    assert main([*argv, "--stops", "--bumper-law", "hunt-crossley"]) == 0
    pads = capsys.readouterr().out
    for quoted in ("OVERTURNS at t = 2.3424 s;", "2 stop contact(s), bumper force max 7475 N"):
        assert quoted in pads and quoted in text, quoted


def test_the_readme_measured_figures_are_those_of_the_bench_files():
    """Each measured block of the README (the speed figures of the last `make bench`, the adaptive maps and
    spectra against full ones) is bench/readme.py's rendering of the file its command wrote: a figure typed
    by hand, or left from an older run, fails here."""
    import json
    import sys

    sys.path.insert(0, str(README.parent / "bench"))
    import readme

    text = README.read_text(encoding="utf-8")
    for name, (path, _) in readme.BLOCKS.items():
        results = json.loads((README.parent / path).read_text())
        assert readme.block(text, name) == readme.fresh(name), name
        assert results["machine"]["date"] in readme.fresh(name), name
