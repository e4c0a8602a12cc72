"""What a study leaves on disk: ``<name>.npz`` (every array), ``<name>*.csv`` (tables), ``<name>.json``.

:func:`save` writes a :class:`~rocking.study.config.Study` with its
configuration, the configuration's hash, software versions, summary and
timing; :func:`load` reads it back without recomputing anything.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..model.params import ParameterError
from .config import Study, config_hash, versions


def _stem(path: str | Path) -> Path:
    path = Path(path)
    return path.with_suffix("") if path.suffix in (".npz", ".json", ".csv") else path


def write_csv(path: Path, columns: dict, chunk: int = 10_000) -> None:
    """Write equal-length columns as CSV with a header; floats as their shortest exact ``repr``.

    Rows are formatted ``chunk`` at a time, so that a big map needs no Python
    object per value of the whole table at once.
    """
    names = list(columns)
    data = [np.asarray(columns[k]).ravel() for k in names]
    row = ",".join("%r" if d.dtype.kind == "f" else "%s" for d in data) + "\n"
    with open(path, "w", encoding="utf-8") as f:
        f.write(",".join(names) + "\n")
        for start in range(0, len(data[0]) if data else 0, chunk):
            f.writelines(row % values for values in zip(*(d[start : start + chunk].tolist() for d in data)))


def save(study: Study, folder: str | Path, name: str | None = None) -> list[Path]:
    """Write ``study`` into ``folder`` as ``<name>.npz``, ``.json`` and its CSV tables.

    Returns
    -------
    list of Path
        The files written.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    stem = folder / (name or study.kind)
    np.savez(stem.with_suffix(".npz"), **study.arrays)
    written = [stem.with_suffix(".npz")]
    for table, columns in study.tables.items():
        path = folder / f"{table}.csv"
        write_csv(path, columns)
        written.append(path)
    record = {
        "kind": study.kind,
        "config": study.config,
        "config_sha256": config_hash(study.config),
        "versions": versions(),
        "summary": study.summary,
        "run": study.run,
        "files": [p.name for p in written],
    }
    stem.with_suffix(".json").write_text(json.dumps(record, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    return [*written, stem.with_suffix(".json")]


def load(path: str | Path) -> Study:
    """Read a saved study back from its ``.npz``/``.json`` pair (either path, or the common stem).

    Raises
    ------
    ParameterError
        If either file is missing.
    """
    stem = _stem(path)
    npz, meta = stem.with_suffix(".npz"), stem.with_suffix(".json")
    for p in (npz, meta):
        if not p.is_file():
            raise ParameterError(f"no saved study at {stem}: {p} is missing (a study writes both .npz and .json)")
    record = json.loads(meta.read_text(encoding="utf-8"))
    with np.load(npz) as z:
        arrays = {k: z[k] for k in z.files}
    return Study(record["kind"], record["config"], arrays, summary=record["summary"], run=record.get("run", {}))
