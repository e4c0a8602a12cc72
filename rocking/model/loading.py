"""Generated models, loaded from their folder and manifest.

The runtime knows a model only through ``manifest.json`` and the generated
files next to it, so any folder written by ``rocking derive`` can be used.
"""

from __future__ import annotations

import functools
import importlib.util
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType

import numpy as np

import rocking.generated

GENERATED = Path(rocking.generated.__file__).resolve().parent
#: The manifest layout this runtime reads; the derivation declares it.
MANIFEST_FORMAT = rocking.generated.MANIFEST_FORMAT


class ModelError(ValueError):
    """A model cannot be found, loaded, or given the parameters it needs."""


@dataclass(frozen=True)
class Model:
    """A generated model.

    Attributes
    ----------
    name : str
        Model name (``manifest["model"]``).
    folder : Path
        Folder holding the generated files.
    manifest : dict
        The parsed ``manifest.json``.
    functions : ModuleType
        The generated NumPy module.
    """

    name: str
    folder: Path
    manifest: dict = field(repr=False)
    functions: ModuleType = field(repr=False)

    @property
    def coordinates(self) -> tuple[str, ...]:
        return tuple(self.manifest["coordinates"])

    @property
    def state(self) -> tuple[str, ...]:
        return tuple(self.manifest["state"])

    @property
    def parameters(self) -> tuple[str, ...]:
        return tuple(p["name"] for p in self.manifest["parameters"])

    @property
    def block_parameters(self) -> tuple[str, ...]:
        """The parameters the block sets (``Block.as_params``); the rest are the attached bodies'."""
        return tuple(self.manifest["block_parameters"])

    @property
    def nq(self) -> int:
        return len(self.coordinates)

    @property
    def c_source(self) -> Path:
        return self.folder / self.manifest["files"]["c_source"]

    @property
    def c_header(self) -> Path:
        return self.folder / self.manifest["files"]["c_header"]

    @property
    def c_prefix(self) -> str:
        return self.manifest["files"]["c_prefix"]

    def param_vector(self, values: Mapping[str, float]) -> np.ndarray:
        """Parameters in the model's argument order, from a mapping by name.

        Raises
        ------
        ModelError
            Naming the parameters the mapping lacks.
        """
        missing = [p for p in self.parameters if p not in values]
        if missing:
            raise ModelError(f"model {self.name!r} needs parameter(s) {', '.join(missing)}")
        vector = np.array([float(values[p]) for p in self.parameters])
        for (name, valid), value in zip(self.valid_ranges.items(), vector):
            bad = not np.isfinite(value) or (valid == "> 0" and value <= 0) or (valid == ">= 0" and value < 0)
            if bad:
                raise ModelError(f"model {self.name!r}: {name} must be finite and {valid} (got {value:g})")
        return vector

    @property
    def valid_ranges(self) -> dict[str, str]:
        """Valid range of each parameter as the spec states it (``"> 0"``, ``">= 0"``, ``"any"``, ...)."""
        return {p["name"]: p["valid"] for p in self.manifest["parameters"]}

    def call(self, function: str, s, y, ag, p):
        """Call a generated NumPy function with a state vector ``y`` and parameter vector ``p``.

        ``y`` has the state on its first axis, ``p`` the parameters on its first axis.
        """
        fn = getattr(self.functions, function)
        return fn(s, *y, ag, *p)


def available_models() -> list[str]:
    """Names of the models installed in :mod:`rocking.generated`."""
    return sorted(p.parent.name for p in GENERATED.glob("*/manifest.json"))


def load_model(model: str | Path | Model = "omd") -> Model:
    """Load a model by name (installed) or by the folder ``rocking derive`` wrote.

    Examples
    --------
    >>> import rocking
    >>> rocking.available_models()
    ['block', 'omd', 'omd2', 'pendulum']
    >>> omd = rocking.load_model("omd")
    >>> omd.coordinates, omd.parameters
    (('theta', 'x'), ('M', 'I_G', 'B', 'H', 'e', 'g', 'm', 'h', 'k_m', 'c'))
    """
    if isinstance(model, Model):
        return model
    folder = Path(model)
    if not (folder / "manifest.json").is_file():
        folder = GENERATED / str(model)
    manifest_path = folder / "manifest.json"
    if not manifest_path.is_file():
        raise ModelError(
            f"unknown model {str(model)!r}: not an installed model ({', '.join(available_models())}) "
            "nor a folder with a manifest.json"
        )
    # Studies load the model once per tile: import each generated module once,
    # again only when the folder is regenerated.
    return _load_folder(folder.resolve(), manifest_path.stat().st_mtime_ns)


@functools.lru_cache(maxsize=32)
def _load_folder(folder: Path, manifest_mtime_ns: int) -> Model:
    manifest_path = folder / "manifest.json"
    manifest = json.loads(manifest_path.read_text(encoding="utf-8"))
    if manifest.get("format") != MANIFEST_FORMAT:
        raise ModelError(
            f"{manifest_path}: manifest format {manifest.get('format')} is not {MANIFEST_FORMAT}; "
            "derive the model again (rocking derive --spec ... --out ...)"
        )
    spec = importlib.util.spec_from_file_location(
        f"rocking_model_{manifest['model']}", folder / manifest["files"]["numpy"]
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return Model(manifest["model"], folder.resolve(), manifest, module)
