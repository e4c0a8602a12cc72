"""Derive a spec and write, or check, its generated folder."""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from .codegen import MANIFEST_FORMAT, generate
from .equations import derive
from .spec import Spec, SpecError, registered_variants

#: The folder of the package ``rocking.generated``, the default home of the models. It is
#: derive's sibling both in a checkout (``derive/``, ``generated/``) and once installed
#: (``rocking/derive/``, ``rocking/generated/``): pyproject.toml maps the two side by side.
GENERATED = Path(__file__).resolve().parent.parent / "generated"


@dataclass(frozen=True)
class Built:
    """Files of one model and the wall time their derivation took."""

    name: str
    files: dict
    seconds: float


def build(spec: Spec, options: dict | None = None, stage=lambda name: None) -> Built:
    """Derive ``spec`` and render every file, without writing anything.

    ``stage`` is called with the name of each stage as it begins (:func:`rocking.derive.equations.derive`).
    """
    start = time.perf_counter()
    files = generate(derive(spec, options, stage), spec, stage)
    return Built(spec.name, files, time.perf_counter() - start)


#: A file name a manifest may list: no folder, no hidden file, no ``..``.
_FILE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")


def previous_files(folder: Path) -> set[str] | None:
    """The files a previous derivation wrote into ``folder``, as its manifest.json lists them.

    Returns
    -------
    set of str or None
        ``manifest.json`` and every file its ``sha256`` and ``files`` name (plain
        file names only); None when ``folder`` holds no readable manifest of a
        derivation.
    """
    try:
        manifest = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    if not (isinstance(manifest, dict) and isinstance(manifest.get("sha256"), dict) and "model" in manifest):
        return None
    files = isinstance(manifest.get("files"), dict) and manifest["files"] or {}
    named = set(manifest["sha256"]) | {v for k, v in files.items() if k != "c_prefix" and isinstance(v, str)}
    return {"manifest.json"} | {n for n in named if isinstance(n, str) and _FILE_NAME.fullmatch(n) and ".." not in n}


def check_output_folder(built: Built, folder: Path) -> set[str]:
    """The files of ``folder`` a derivation may replace or remove: those of the previous derivation.

    ``--out`` writes only into a new or empty folder, or one holding the
    manifest of a previous derivation; it never touches a file that manifest
    does not list (the user's own notes, scripts, spec).

    Raises
    ------
    SpecError
        When ``folder`` is not a folder, holds files but no previous manifest, or
        holds a file of the user's under the name of a file to write.
    """
    if not folder.exists():
        return set()
    if not folder.is_dir():
        raise SpecError(f"output {folder} exists and is not a folder")
    entries = {p.name for p in folder.iterdir()}
    if not entries:
        return set()
    previous = previous_files(folder)
    if previous is None:
        raise SpecError(
            f"output {folder} is not empty and holds no manifest.json of a previous derivation; "
            "choose a new or empty folder"
        )
    theirs = sorted(n for n in built.files if n in entries and n not in previous)
    if theirs:
        raise SpecError(f"output {folder}: {', '.join(theirs)} is not listed in its manifest.json; not overwriting it")
    return previous & entries


def _stage(staging: Path, built: Built) -> None:
    """Write every file of ``built`` into the folder ``staging`` (mode 0644: generated code is meant to be read)."""
    for name, text in built.files.items():
        (staging / name).write_text(text, encoding="utf-8")
        os.chmod(staging / name, 0o644)


def write(built: Built, folder: Path) -> None:
    """Write the files into ``folder``, removing only files of the previous derivation the model no longer has.

    Every file is written first into a temporary folder beside ``folder``, then renamed into place: a derivation
    stopped before its last stage writes nothing (the files are written only once all are derived), and a write
    that fails (a full disk) leaves the previous files as they were. A renamed file replaces a symbolic link at
    its name, never follows it.

    Raises
    ------
    SpecError
        When ``folder`` may not be written (:func:`check_output_folder`), or writing fails.
    """
    previous = check_output_folder(built, folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.derive-"))
        try:
            _stage(staging, built)
            # Every file written: renames alone from here, which need no space.
            for name in sorted(previous - set(built.files)):
                path = folder / name
                if path.is_file() or path.is_symlink():
                    path.unlink()
            for name, text in built.files.items():
                path = folder / name
                if path.is_symlink() or not path.is_file() or path.read_text(encoding="utf-8") != text:
                    os.replace(staging / name, path)
        finally:
            shutil.rmtree(staging, ignore_errors=True)
    except OSError as exc:
        raise SpecError(f"cannot write {folder}: {exc.strerror or exc}") from None


def stale_files(built: Built, folder: Path) -> list[str]:
    """Names of the files in ``folder`` that differ from a fresh derivation."""
    stale = [
        n
        for n, text in built.files.items()
        if not (folder / n).is_file() or (folder / n).read_text(encoding="utf-8") != text
    ]
    extra = [p.name for p in folder.glob("*") if p.is_file() and p.name not in built.files] if folder.is_dir() else []
    return sorted(stale + extra)


def builtin_hashes(root: Path = GENERATED) -> dict[str, str]:
    """SHA-256 of the ``manifest.json`` of every registered variant under ``root``, by name.

    A manifest lists the SHA-256 of each file it vouches for, so this table vouches
    for every file of every built-in model (a missing manifest is left out: the
    freshness check reports it).
    """
    hashes = {}
    for name in registered_variants():
        manifest = root / name / "manifest.json"
        if manifest.is_file():
            hashes[name] = hashlib.sha256(manifest.read_bytes()).hexdigest()
    return hashes


def package_init(root: Path = GENERATED) -> str:
    """Text of the ``__init__.py`` of ``rocking.generated``.

    It declares the manifest format its models follow, so that a runtime
    learns it from the generated files alone, and the SHA-256 of each built-in
    model's manifest: the runtime checks a built-in model against this table,
    held in the installed package, not against a file of the model's own folder.
    """
    table = "".join(f'    "{name}": "{digest}",\n' for name, digest in builtin_hashes(root).items())
    return (
        '"""Models generated by ``make derive``: one folder each, described by its manifest.json."""\n'
        "\n"
        "#: Version of the layout of every manifest.json that rocking.derive writes (its key ``format``).\n"
        f"MANIFEST_FORMAT = {MANIFEST_FORMAT}\n"
        "\n"
        "#: SHA-256 of the manifest.json of each built-in model (the manifest holds those of its files).\n"
        f"BUILTIN_MANIFESTS = {{\n{table}}}\n"
    )


def package_init_is_stale(root: Path = GENERATED) -> bool:
    """Whether ``root/__init__.py`` differs from :func:`package_init`."""
    init = root / "__init__.py"
    return not init.is_file() or init.read_text(encoding="utf-8") != package_init(root)


def write_package_init(root: Path = GENERATED) -> None:
    """Write ``root/__init__.py``: ``generated/`` is installed as the package ``rocking.generated``."""
    root.mkdir(parents=True, exist_ok=True)
    if package_init_is_stale(root):
        (root / "__init__.py").write_text(package_init(root), encoding="utf-8")
