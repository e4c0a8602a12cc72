"""Planted models and libraries: the attacks of a stranger who can write a folder the user may be led to."""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
from pathlib import Path

#: A C constructor: it runs when the library is loaded, before any of its functions is called.
CONSTRUCTOR = """
#include <stdio.h>
__attribute__((constructor)) static void planted(void) {{
    FILE *f = fopen("{sentinel}", "w");
    if (f) fclose(f);
}}
"""


def plant_model(source: Path, folder: Path, sentinel: Path) -> Path:
    """A copy of the model folder ``source`` whose NumPy code creates ``sentinel`` when run, its manifest
    updated to vouch for it: a manifest beside the code proves nothing."""
    shutil.copytree(source, folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    code = folder / manifest["files"]["numpy"]
    code.write_text(code.read_text() + f"\nopen({str(sentinel)!r}, 'w').close()\n")
    manifest["sha256"][code.name] = hashlib.sha256(code.read_bytes()).hexdigest()
    (folder / "manifest.json").write_text(json.dumps(manifest, indent=1))
    return folder


def plant_library(library: Path, sentinel: Path, source_key: str) -> None:
    """A foreign shared library at ``library`` whose constructor creates ``sentinel``, with a sidecar that
    matches it (hash, size and the source key it is looked up by)."""
    c_file = library.with_name("planted.c")
    c_file.write_text(CONSTRUCTOR.format(sentinel=sentinel))
    subprocess.run(["cc", "-shared", "-fPIC", str(c_file), "-o", str(library)], check=True)
    c_file.unlink()
    data = library.read_bytes()
    sidecar = {
        "format": 1,
        "library": library.name,
        "sha256": hashlib.sha256(data).hexdigest(),
        "size": len(data),
        "source_key": source_key,
    }
    library.with_name(library.name + ".json").write_text(json.dumps(sidecar))
