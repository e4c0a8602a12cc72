"""The type check: mypy's errors per file may only shrink.

The package ships ``py.typed``, so a user's type checker reads its annotations. The errors that remain are
counted per file in ``tests/mypy_baseline.json``; a file with more errors than its count fails this test, and so
does a count higher than the file's errors, so that a fix is recorded and cannot be undone unnoticed. After a
fix, ``python -m tests.test_types`` writes the smaller counts.
"""

import json
import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BASELINE = ROOT / "tests" / "mypy_baseline.json"
ERROR = re.compile(r"^(?P<file>[^:\s]+\.py):\d+: error: ")


def error_counts() -> dict[str, int]:
    """mypy's errors per file over the files of ``[tool.mypy]`` in pyproject.toml."""
    done = subprocess.run(
        [sys.executable, "-m", "mypy", "--no-error-summary", "--no-pretty"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode not in (0, 1):
        raise RuntimeError(f"mypy failed to run (exit {done.returncode}): {done.stderr.strip()}")
    found = (ERROR.match(line) for line in done.stdout.splitlines())
    return dict(sorted(Counter(m["file"] for m in found if m).items()))


def test_type_errors_only_shrink():
    baseline = json.loads(BASELINE.read_text())
    counts = error_counts()
    grown = {f: (baseline.get(f, 0), n) for f, n in counts.items() if n > baseline.get(f, 0)}
    shrunk = {f: (n, counts.get(f, 0)) for f, n in baseline.items() if counts.get(f, 0) < n}
    assert not grown, f"new type errors (baseline, now) by file: {grown}; run mypy to see them"
    assert not shrunk, (
        f"fewer type errors than recorded (baseline, now): {shrunk}; record them: python -m tests.test_types"
    )


if __name__ == "__main__":
    BASELINE.write_text(json.dumps(error_counts(), indent=1) + "\n")
    print(f"{BASELINE.relative_to(ROOT)}: {sum(json.loads(BASELINE.read_text()).values())} errors recorded")
