"""Generated models, loaded from their folder and manifest.

The runtime knows a model only through ``manifest.json`` and the generated
files next to it, so any folder written by ``rocking derive`` can be used.

Trust
-----
Loading a model runs its generated NumPy code, so what may name a model is decided here:

- a *built-in* model (:func:`available_models`) is named by its name, which always means the
  installed one (a folder of the same name in the working directory does not shadow it); its
  ``manifest.json`` must have the SHA-256 that ``rocking.generated.BUILTIN_MANIFESTS`` records in
  the installed package, and each of its files the SHA-256 its manifest records;
- a folder of the user's is trusted because the user named it, in Python (:func:`load_model`,
  ``rocking.Variant``) or on the command line (``--model DIR``); its manifest vouches only for
  edits by hand, not against a planted folder, which is why it must be named;
- a model named by a saved file (``--config``, :func:`rocking.load`) is resolved by
  :func:`saved_model`: a built-in, or a folder the user has named in this process; anything else is
  refused in one line, saying how to name the folder.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType

import numpy as np

import rocking.generated as generated_package

GENERATED = Path(generated_package.__file__).resolve().parent
#: The manifest layout this runtime reads; the derivation declares it.
MANIFEST_FORMAT = generated_package.MANIFEST_FORMAT


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

    @functools.cached_property
    def coordinates(self) -> tuple[str, ...]:
        return tuple(self.manifest["coordinates"])

    @functools.cached_property
    def state(self) -> tuple[str, ...]:
        return tuple(self.manifest["state"])

    @functools.cached_property
    def parameters(self) -> tuple[str, ...]:
        return tuple(p["name"] for p in self.manifest["parameters"])

    @functools.cached_property
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
        vector = [float(values[p]) for p in self.parameters]
        for (name, valid), value in zip(self.valid_ranges.items(), vector):
            bad = not math.isfinite(value) or (valid == "> 0" and value <= 0) or (valid == ">= 0" and value < 0)
            if bad:
                raise ModelError(f"model {self.name!r}: {name} must be finite and {valid} (got {value:g})")
        return np.array(vector)

    @functools.cached_property
    def own_parameters(self) -> tuple[str, ...]:
        """The parameters of the attached bodies (a damper's): :attr:`parameters` but :attr:`block_parameters`."""
        return tuple(k for k in self.parameters if k not in self.block_parameters)

    @functools.cached_property
    def valid_ranges(self) -> dict[str, str]:
        """Valid range of each parameter as the spec states it (``"> 0"``, ``">= 0"``, ``"any"``, ...)."""
        return {p["name"]: p["valid"] for p in self.manifest["parameters"]}

    def call(self, function: str, s, y, ag, p, agy=0.0):
        """Call a generated NumPy function with a state vector ``y`` and parameter vector ``p``.

        ``y`` has the state on its first axis, ``p`` the parameters on its first axis; ``ag`` and
        ``agy`` are the horizontal and vertical ground accelerations.
        """
        fn = getattr(self.functions, function)
        return fn(s, *y, ag, agy, *p)


def available_models() -> list[str]:
    """Names of the models installed in :mod:`rocking.generated`."""
    return sorted(generated_package.BUILTIN_MANIFESTS)


def load_model(model: str | Path | Model = "omd") -> Model:
    """Load a model by name (installed) or by the folder ``rocking derive`` wrote.

    A model is read and checked against its manifest once per process (its NumPy code runs from
    the bytes checked then; :mod:`rocking.sim.cbuild` checks its C files again before it compiles
    them): a folder derived again under the same path is seen by the next process.

    Examples
    --------
    >>> import rocking
    >>> rocking.available_models()
    ['block', 'omd', 'omd2', 'omd_stops', 'omd_stops_hc', 'pendulum']
    >>> omd = rocking.load_model("omd")
    >>> omd.coordinates, omd.parameters
    (('theta', 'x'), ('M', 'I_G', 'B', 'H', 'e', 'g', 'm', 'h', 'k_m', 'c'))
    """
    if isinstance(model, Model):
        return model
    if not isinstance(model, (str, os.PathLike)):
        raise ModelError(f"a model is a name or a folder, not a {type(model).__name__}")
    # A built-in's name and a folder never share a key: Path("omd") is a folder, "omd" the installed model.
    key = ("built-in", model) if _is_builtin(model) else ("folder", str(model), os.getcwd())
    loaded = _LOADED.get(key)
    if loaded is None:
        if _is_builtin(model):
            loaded = _load_folder(_builtin_folder(str(model)), generated_package.BUILTIN_MANIFESTS[model])
        else:
            loaded = _load_folder(_user_folder(model))
            _NAMED[loaded.folder] = loaded
        _LOADED[key] = loaded
    return loaded


def saved_model(name: object, source: str, remedy: str = "pass trust_model=DIR") -> Model:
    """The model a saved file names: a built-in model, or a folder the user has named in this process.

    Parameters
    ----------
    name : object
        What the file holds: a built-in model's name, a folder, or a model's manifest name.
    source : str
        The file and field, for the message (``"--config map.json: option model"``).
    remedy : str
        How the user names the folder to trust it, for the message.

    Raises
    ------
    ModelError
        In one line, for anything else: a saved file never selects code to run.
    """
    if not isinstance(name, (str, os.PathLike)) or not str(name):
        raise ModelError(f"{source}: a model is a name or a folder (got {type(name).__name__} {name!r:.60})")
    if _is_builtin(name):
        return load_model(str(name))
    for folder, model in _NAMED.items():
        if str(name) in (str(folder), model.name):
            return model
    raise ModelError(
        f"{source} names the model {str(name)!r:.200}, which is not built in ({', '.join(available_models())}): "
        f"a saved file never selects code to run; name its folder yourself to trust it ({remedy})"
    )


#: The models loaded in this process, by built-in name or by folder as given and the working directory (against
#: which a relative folder is read): each is read and checked against its manifest once per process.
_LOADED: dict[tuple, Model] = {}

#: The folders of their own that the user named in this process (:func:`load_model`), by resolved folder.
_NAMED: dict[Path, Model] = {}


def _is_builtin(model: str | os.PathLike) -> bool:
    """Whether ``model`` is a built-in model's name (a :class:`~pathlib.Path` is always a folder)."""
    return isinstance(model, str) and model in generated_package.BUILTIN_MANIFESTS


def _builtin_folder(name: str) -> Path:
    """The folder of the built-in model ``name`` (its manifest is checked as it is read, :func:`_load_folder`)."""
    return (GENERATED / name).resolve()


def _user_folder(model: str | os.PathLike) -> Path:
    """The folder of a model the user named by its folder, resolved."""
    folder = Path(model)
    if not (folder / "manifest.json").is_file():
        raise ModelError(
            f"unknown model {str(model)!r}: not an installed model ({', '.join(available_models())}) "
            "nor a folder with a manifest.json"
        )
    return folder.resolve()


#: The files of ``manifest["files"]`` the runtime executes or compiles; each must match its ``sha256``.
CHECKED_FILES = ("numpy", "c_source", "c_header")
#: A file name a manifest may give: no folder, no hidden file.
_FILE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]*")


def _rederive(folder: Path) -> str:
    """How to write ``folder`` again."""
    if folder.parent == GENERATED:
        return "re-derive it: make derive (or rocking derive --variant " + folder.name + ")"
    return "re-derive it: rocking derive --spec <spec.toml> --out " + str(folder)


def _checked_bytes(folder: Path, manifest: dict) -> dict[str, bytes]:
    """The content of every file of :data:`CHECKED_FILES`, each checked against the manifest's SHA-256.

    A generated file that was edited by hand is never imported or compiled: the
    manifest records the SHA-256 of every file the derivation wrote.

    Raises
    ------
    ModelError
        Naming the file that is missing, not listed or does not match, and how to derive it again.
    """
    files, hashes = manifest.get("files"), manifest.get("sha256")
    if not (isinstance(files, dict) and isinstance(hashes, dict)):
        raise ModelError(f"{folder / 'manifest.json'}: no files or sha256 table; {_rederive(folder)}")
    out = {}
    for key in CHECKED_FILES:
        name = files.get(key)
        if not (isinstance(name, str) and _FILE_NAME.fullmatch(name) and ".." not in name):
            raise ModelError(f"{folder / 'manifest.json'}: files.{key} is not a file name ({name!r})")
        path = folder / name
        try:
            data = path.read_bytes()
        except OSError:
            raise ModelError(f"{path}: generated file missing or unreadable; {_rederive(folder)}") from None
        if hashes.get(name) != hashlib.sha256(data).hexdigest():
            raise ModelError(
                f"{path}: does not match the SHA-256 its manifest.json records (edited by hand?); "
                f"generated files must not be edited, {_rederive(folder)}"
            )
        out[key] = data
    return out


@functools.lru_cache(maxsize=32)
def _load_folder(folder: Path, manifest_sha256: str | None = None) -> Model:
    """The model of ``folder``; with ``manifest_sha256`` (a built-in's), its manifest must have that SHA-256."""
    manifest_path = folder / "manifest.json"
    try:
        data = manifest_path.read_bytes()
        manifest = json.loads(data.decode("utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise ModelError(
            f"{manifest_path}: not a readable manifest ({type(exc).__name__}); {_rederive(folder)}"
        ) from None
    if manifest_sha256 is not None and hashlib.sha256(data).hexdigest() != manifest_sha256:
        raise ModelError(
            f"{manifest_path}: not the manifest the installed package records for the built-in model "
            f"{folder.name!r} (rocking.generated.BUILTIN_MANIFESTS); {_rederive(folder)}"
        )
    if not isinstance(manifest, dict) or manifest.get("format") != MANIFEST_FORMAT:
        found = manifest.get("format") if isinstance(manifest, dict) else None
        raise ModelError(
            f"{manifest_path}: manifest format {found} is not {MANIFEST_FORMAT}; "
            "derive the model again (rocking derive --spec ... --out ...)"
        )
    source = _checked_bytes(folder, manifest)["numpy"]
    # Run the bytes that were checked, not the file again: no window to swap it, no stale bytecode cache.
    module = ModuleType(f"rocking_model_{manifest['model']}")
    module.__file__ = str(folder / manifest["files"]["numpy"])
    exec(compile(source, module.__file__, "exec"), module.__dict__)
    return Model(manifest["model"], folder, manifest, module)
