"""Shared fixtures: compiled generated C, loaded models."""

from __future__ import annotations

import ctypes
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # derive/ is a development tool, not installed
# A shell without job control starts background commands with SIGINT ignored, and children inherit that:
# the interruption tests need Ctrl-C to reach this process and the commands it starts.
signal.signal(signal.SIGINT, signal.default_int_handler)

CFLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2", "-fPIC", "-shared"]


class CModel:
    """The generated C functions of a model, compiled and called through ctypes."""

    def __init__(self, model, lib_path: Path):
        self.model = model
        self.lib = ctypes.CDLL(str(lib_path))
        dbl, ptr = ctypes.c_double, ctypes.POINTER(ctypes.c_double)
        self.ny = len(model.state)
        self.np = len(model.parameters)
        # The functions without a prepared form (a floor with friction's) take the stops' regime `on` after `p`,
        # then their own inputs (model.h).
        self.direct = {
            n for n in model.manifest["functions"] if not hasattr(self.lib, f"{model.c_prefix}_{n}_prepared")
        }
        for name, info in model.manifest["functions"].items():
            fn = getattr(self.lib, f"{model.c_prefix}_{name}")
            fn.restype = dbl if info["scalar"] else None
            own = [ptr] + [dbl] * len(info["inputs"]) if name in self.direct else []
            fn.argtypes = [dbl, ptr, dbl, dbl, ptr] + own + ([] if info["scalar"] else [ptr])

    def regime(self, values: dict) -> np.ndarray:
        """The stops' regime of each state, cases along the first axis: a side acts where its contact is > 0,
        then a Hunt-Crossley pad's memory v_in, the approach speed of a contact starting there (model.h)."""
        stops = self.model.manifest["stops"]
        if not stops:
            return np.zeros(np.shape(values["s"]) + (0,))
        acting = [c > 0 for c in self("stop_contact", values)]
        floors = [side["approach_floor"] for side in stops]
        memory = [np.maximum(a, f) for a, f in zip(self("stop_approach", values), floors)]
        return np.stack([*acting, *memory][: len(self.model.manifest["regime"])], axis=-1).astype(float)

    def __call__(self, name: str, values: dict):
        """Evaluate ``name`` case by case on arrays of values keyed by argument name."""
        info = self.model.manifest["functions"][name]
        y = np.stack(np.broadcast_arrays(*(np.asarray(values[k], float) for k in self.model.state)), axis=-1)
        p = np.stack(np.broadcast_arrays(*(np.asarray(values[k], float) for k in self.model.parameters)), axis=-1)
        s = np.broadcast_to(np.asarray(values["s"], float), y.shape[:-1])
        ag = np.broadcast_to(np.asarray(values["ag"], float), y.shape[:-1])
        agy = np.broadcast_to(np.asarray(values.get("agy", 0.0), float), y.shape[:-1])
        own: list = []
        if name in self.direct:
            on = np.broadcast_to(self.regime(dict(values, s=s)), y.shape[:-1] + (len(self.model.manifest["regime"]),))
            inputs = [np.broadcast_to(np.asarray(values[k], float), y.shape[:-1]) for k in info["inputs"]]
        fn = getattr(self.lib, f"{self.model.c_prefix}_{name}")
        out = np.zeros(y.shape[:-1] + (info["outputs"],))
        as_ptr = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))
        for i in np.ndindex(y.shape[:-1]):
            yi, pi = np.ascontiguousarray(y[i]), np.ascontiguousarray(p[i])
            if name in self.direct:
                oni = np.ascontiguousarray(on[i])
                own = [as_ptr(oni) if oni.size else None, *(float(a[i]) for a in inputs)]
            if info["scalar"]:
                out[i][0] = fn(s[i], as_ptr(yi), ag[i], agy[i], as_ptr(pi), *own)
            else:
                oi = np.zeros(info["outputs"])
                fn(s[i], as_ptr(yi), ag[i], agy[i], as_ptr(pi), *own, as_ptr(oi))
                out[i][:] = oi
        return out[..., 0] if info["scalar"] else tuple(np.moveaxis(out, -1, 0))


def compile_model(model, folder: Path) -> Path:
    """Compile a model's generated C with strict warnings into a shared library."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.fail("no C compiler found (cc or gcc); the generated C cannot be checked")
    lib = folder / f"lib{model.c_prefix}.so"
    subprocess.run([cc, *CFLAGS, "-I", str(model.folder), str(model.c_source), "-o", str(lib), "-lm"], check=True)
    return lib


@pytest.fixture(scope="session")
def c_model(tmp_path_factory):
    """``c_model(name)``: the compiled generated C of an installed model."""
    from rocking import load_model

    cache = {}

    def get(name):
        if name not in cache:
            model = load_model(name)
            cache[name] = CModel(model, compile_model(model, tmp_path_factory.mktemp(name)))
        return cache[name]

    return get


@pytest.fixture(scope="session")
def small_threshold(tmp_path_factory):
    """A threshold map of 2 x 2 geometries and 4 frequencies, computed once for the figures' tests."""
    from rocking.study.config import Grid
    from rocking.study.threshold import threshold_map
    from rocking.study.tiles import Execution

    return threshold_map(
        Grid("lam", 3.0, 4.0, 2),
        Grid("p", 1.5, 4.0, 2),
        Grid("Omega", 2.0, 14.0, 4),
        Execution(workers=1, progress=False),
        Tm=Grid("Tm", 0.3, 3.0, 3, log=True),
        runs=tmp_path_factory.mktemp("threshold"),
    )
