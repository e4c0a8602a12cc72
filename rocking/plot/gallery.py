"""The figures of the documentation (``docs/figures``): made by ``make figures``, with a record of the code.

``make figures`` runs ``rocking demo`` and publishes its figures here with ``figures.json``: the SHA-256 of
the code that made them (every file of the ``rocking`` package and of the generated models) and of each
picture. A figure is stale when that code has changed since: ``tests/test_gallery.py`` fails then, and
``make figures`` (about 90 s on 2 cores) draws them again. The record is of sources, not of pixels, so it
holds on any machine (a PNG's bytes depend on the fonts and libraries that drew it).

Usage: ``python -m rocking.plot.gallery DEMO_OUT DOCS_FIGURES``.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import sys
from pathlib import Path

import rocking
import rocking.generated

from ..study.config import tree_hash

#: The demo's figures the documentation shows (README, docs/gallery.md).
GALLERY = ("map", "map-unlimited", "spectrum", "spectrum-vertical", "design", "threshold")

#: The record beside the figures.
RECORD = "figures.json"


def source_sha256() -> str:
    """SHA-256 of the code that draws the figures: the ``rocking`` package and the generated models."""
    package = Path(rocking.__file__).resolve().parent
    return tree_hash(package, Path(rocking.generated.__file__).resolve().parent)


def file_sha256(path: Path) -> str:
    """SHA-256 of a file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def publish(demo: Path, docs: Path) -> dict:
    """Copy the :data:`GALLERY` figures of a demo run from ``demo`` into ``docs`` and write their record.

    Returns
    -------
    dict
        The record written to ``docs / RECORD``.
    """
    docs.mkdir(parents=True, exist_ok=True)
    for stem in GALLERY:
        shutil.copyfile(demo / f"{stem}.png", docs / f"{stem}.png")
    record = {
        "source_sha256": source_sha256(),
        "figures": {f"{stem}.png": file_sha256(docs / f"{stem}.png") for stem in GALLERY},
    }
    (docs / RECORD).write_text(json.dumps(record, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    return record


if __name__ == "__main__":
    publish(Path(sys.argv[1]), Path(sys.argv[2]))
    print(f"figures: {', '.join(GALLERY)} published in {sys.argv[2]} with {RECORD}")
