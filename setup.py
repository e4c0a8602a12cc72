"""Build hook of a platform wheel: the C simulator compiled for every built-in model ships in the package.

``pyproject.toml`` holds the project's metadata; this file only adds the compiled libraries to a wheel
(``rocking/sim/prebuilt``, found there by :mod:`rocking.sim.cbuild` before its cache), so that an installed
wheel runs the C back end on a machine without a compiler. An editable install builds nothing: a checkout
compiles at first use. Without a compiler, a wheel is still built, without the libraries, with a warning; a
compiler that rejects the code fails the build.
"""

from __future__ import annotations

import importlib.util
import json
import warnings
from pathlib import Path
from types import SimpleNamespace

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent


def _cbuild():
    """rocking/sim/cbuild.py, read by path: it needs only the standard library, unlike ``import rocking``."""
    spec = importlib.util.spec_from_file_location("_rocking_cbuild", ROOT / "rocking" / "sim" / "cbuild.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _builtin_models() -> list[SimpleNamespace]:
    """The built-in models as the build needs them: their folder, manifest and C files."""
    models = []
    for path in sorted((ROOT / "generated").glob("*/manifest.json")):
        manifest = json.loads(path.read_text(encoding="utf-8"))
        files = manifest["files"]
        models.append(
            SimpleNamespace(
                folder=path.parent,
                manifest=manifest,
                c_prefix=files["c_prefix"],
                c_source=path.parent / files["c_source"],
                c_header=path.parent / files["c_header"],
            )
        )
    return models


class BuildWithSimulator(build_py):
    """``build_py``, then the built-in models' libraries compiled into the build's ``rocking/sim/prebuilt``."""

    def run(self):
        super().run()
        if self.editable_mode:
            return
        cbuild = _cbuild()
        out = Path(self.build_lib) / "rocking" / "sim" / "prebuilt"
        try:
            for model in _builtin_models():
                cbuild.build(model, cache=out)
        except cbuild._CompilerUnavailable as exc:  # no compiler here: a wheel that compiles at first use
            warnings.warn(f"the wheel ships no compiled simulator: {exc}", stacklevel=1)
        finally:
            for lock in out.glob(".*.lock"):
                lock.unlink()


class BinaryDistribution(Distribution):
    """A distribution with compiled code: its wheel is tagged for this platform."""

    def has_ext_modules(self):
        return True


setup(cmdclass={"build_py": BuildWithSimulator}, distclass=BinaryDistribution)
