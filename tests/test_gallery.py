"""The documentation's figures are those ``make figures`` drew with the code as it is (rocking.plot.gallery)."""

from __future__ import annotations

import json
from pathlib import Path

from rocking.plot.gallery import GALLERY, RECORD, file_sha256, source_sha256

FIGURES = Path(__file__).resolve().parent.parent / "docs" / "figures"


def test_the_documentations_figures_are_drawn_by_the_code_as_it_is():
    record = json.loads((FIGURES / RECORD).read_text(encoding="utf-8"))
    assert record["source_sha256"] == source_sha256(), "docs/figures are stale: run `make figures` and commit them"
    assert sorted(record["figures"]) == sorted(f"{stem}.png" for stem in GALLERY)
    for name, digest in record["figures"].items():
        assert file_sha256(FIGURES / name) == digest, f"docs/figures/{name} is not the one make figures drew"
