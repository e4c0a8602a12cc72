"""What a parametric study is given: its configuration, and the hash that keys its tiles.

A study (the overturning map, the minimum overturning spectrum, the optimal
damper) is described by a :class:`Setting` (the block and the solver), a
damper :class:`Tuning` (the paper's ``omd``) or a :class:`Variant` (any
generated model with its parameters given explicitly) and :class:`Grid` s of the non-dimensional pulse
parameters of ``docs/model.md`` section 9 (``Omega = omega_g / p``,
``beta = a_g / (g tan(alpha))``). Its result is a :class:`Study`: arrays,
CSV tables, a JSON-ready configuration and a summary
(:mod:`rocking.study.storage` writes and reads it).

Units SI (m, kg, s, rad); the study parameters themselves are non-dimensional.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import platform
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import numpy as np

from ..model.loading import GENERATED, ModelError, load_model
from ..model.params import Block, ParameterError
from ..sim import boundary

#: Version of the layout of study data and tiles; part of every configuration hash.
FORMAT = 1

#: Back ends that :func:`rocking.sim.cases.run_cases` accepts.
BACKENDS = ("c", "numpy")


@dataclass(frozen=True)
class Grid:
    """``n`` values from ``low`` to ``high``, evenly spaced (``log``: in logarithm).

    Parameters
    ----------
    name : str
        Parameter name shown in error messages (e.g. ``"Omega"``).
    low, high : float
        End points, both included; ``low < high`` when ``n > 1``, ``low == high``
        when ``n == 1``.
    n : int
        Number of values, >= 1.
    log : bool, optional
        Logarithmic spacing (then ``low > 0``).
    minimum : float, optional
        Values must exceed it (default 0: every study parameter is positive).

    Raises
    ------
    ParameterError
        Naming the grid and its valid range, for an empty, reversed or
        non-finite range or a grid size below 1.
    """

    name: str
    low: float
    high: float
    n: int
    log: bool = False
    minimum: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.n, (int, np.integer)) or isinstance(self.n, bool) or self.n < 1:
            raise ParameterError(f"{self.name}: the number of values N must be an integer >= 1 (got {self.n!r})")
        for end in ("low", "high"):
            value = getattr(self, end)
            if not (isinstance(value, (int, float, np.floating, np.integer)) and math.isfinite(value)):
                raise ParameterError(f"{self.name}: {end} end must be a finite number (got {value!r})")
            if not value > self.minimum:
                raise ParameterError(f"{self.name}: values must be > {self.minimum:g} (got {end} end {value!r})")
        if self.n > 1 and not self.low < self.high:
            raise ParameterError(
                f"{self.name}: the range MIN MAX must have MIN < MAX (got {self.low!r} .. {self.high!r})"
            )
        if self.n == 1 and self.low != self.high:
            raise ParameterError(f"{self.name}: with N = 1 give MIN = MAX (got {self.low!r} .. {self.high!r})")
        object.__setattr__(self, "low", float(self.low))
        object.__setattr__(self, "high", float(self.high))
        object.__setattr__(self, "n", int(self.n))

    def values(self) -> np.ndarray:
        """The grid as a float array of length ``n``."""
        if self.log:
            return np.geomspace(self.low, self.high, self.n)
        return np.linspace(self.low, self.high, self.n)

    def record(self) -> dict:
        """JSON-ready description."""
        return {"low": self.low, "high": self.high, "n": self.n, "scale": "log" if self.log else "linear"}


@dataclass(frozen=True)
class Setting:
    """The block and the solver, shared by every response of a study.

    Parameters
    ----------
    block : Block
        The rocking block.
    rtol : float, optional
        Relative tolerance of the integrator, in [1e-12, 0.01].
    t_after : float, optional
        Time followed after the pulse ends, s (> 0).
    backend : {"c", "numpy"}, optional
        Back end of :func:`rocking.sim.cases.run_cases`.
    """

    block: Block
    rtol: float = 1e-8
    t_after: float = 15.0
    backend: str = "c"

    def __post_init__(self) -> None:
        if not isinstance(self.block, Block):
            raise ParameterError(f"block must be a rocking.Block (got {type(self.block).__name__})")
        if not isinstance(self.rtol, (int, float)):
            raise ParameterError(f"rtol must be a number in [1e-12, 0.01] (got {self.rtol!r})")
        boundary.check("rtol", self.rtol)
        if not (isinstance(self.t_after, (int, float)) and math.isfinite(self.t_after) and self.t_after > 0):
            raise ParameterError(f"t_after must be a finite number of seconds > 0 (got {self.t_after!r})")
        if self.backend not in BACKENDS:
            raise ParameterError(f"backend must be one of {', '.join(BACKENDS)} (got {self.backend!r})")

    def record(self) -> dict:
        """JSON-ready description."""
        return {"block": self.block.as_params(), "rtol": self.rtol, "t_after": self.t_after, "backend": self.backend}


@dataclass(frozen=True)
class Tuning:
    """A damper relative to its block (``docs/model.md`` section 9).

    Parameters
    ----------
    gamma : float, optional
        Mass ratio ``m / M``, > 0 (default 0.05, the damper of docs/model.md section 9).
    omega_ratio : float, optional
        ``omega_m / p`` (> 0); ``T_m p / (2 pi) = 1 / omega_ratio``. Default 1.
    zeta : float, optional
        Damping ratio, >= 0. Default 0.05.
    h : float, optional
        Height of the guide above the top of the block, m (>= 0). Default 0.05 m,
        the reference damper of docs/model.md section 9 (``Damper``'s own default is 0).
    """

    gamma: float = 0.05
    omega_ratio: float = 1.0
    zeta: float = 0.05
    h: float = 0.05

    def __post_init__(self) -> None:
        for name, low, strict in (
            ("gamma", 0.0, True),
            ("omega_ratio", 0.0, True),
            ("zeta", 0.0, False),
            ("h", 0.0, False),
        ):
            value = getattr(self, name)
            ok = isinstance(value, (int, float)) and math.isfinite(value) and (value > low if strict else value >= low)
            if not ok:
                raise ParameterError(
                    f"{name} must be a finite number {'>' if strict else '>='} {low:g} (got {value!r})"
                )

    @property
    def Tm_ratio(self) -> float:
        """``T_m p / (2 pi)``: the damper period in units of ``2 pi / p``."""
        return 1.0 / self.omega_ratio

    def record(self) -> dict:
        """JSON-ready description (also the keyword arguments of :func:`rocking.sim.cases.pulse_cases`)."""
        return {"gamma": self.gamma, "omega_ratio": self.omega_ratio, "zeta": self.zeta, "h": self.h}

    def case_args(self) -> dict:
        """Keyword arguments of :func:`rocking.sim.cases.pulse_cases` for this damper."""
        return self.record()


@dataclass(frozen=True)
class Variant:
    """Any generated model with its own parameters given explicitly, in place of a :class:`Tuning`.

    Parameters
    ----------
    model : str
        Installed model name (``"pendulum"``, ``"omd2"``, ...) or a folder
        written by ``rocking derive`` (kept as its absolute path).
    params : dict
        Value of each of the model's own parameters (those not set by the
        block), SI units; their ranges are checked against the block when the
        study runs (:func:`rocking.sim.cases.pulse_cases`).

    Raises
    ------
    ParameterError
        For an unknown model, or parameters missing, unknown, set by the
        block or not numeric.
    """

    model: str
    params: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        try:
            model = load_model(self.model)
        except (ModelError, TypeError) as exc:
            raise ParameterError(str(exc)) from None
        if model.folder != (GENERATED / model.name).resolve():
            object.__setattr__(self, "model", str(model.folder))  # a folder: absolute, for every worker
        if not isinstance(self.params, dict):
            raise ParameterError(f"params must be a dict of values by name (got {type(self.params).__name__})")
        own = [k for k in model.parameters if k not in model.block_parameters]
        unknown = sorted(str(k) for k in self.params if k not in own)
        if unknown:
            raise ParameterError(
                f"model {model.name!r} has no parameter(s) {', '.join(unknown)} of its own; "
                f"give {', '.join(own) or 'none'} (the block sets {', '.join(model.block_parameters)})"
            )
        missing = [k for k in own if k not in self.params]
        if missing:
            raise ParameterError(f"model {model.name!r} needs parameter(s) {', '.join(missing)}")
        values = {}
        for k in own:
            v = self.params[k]
            ok = isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)
            if not (ok and math.isfinite(v)):
                raise ParameterError(f"model {model.name!r}: {k} must be a finite number (got {v!r})")
            values[k] = float(v)
        object.__setattr__(self, "params", values)
        object.__setattr__(self, "_name", model.name)

    @property
    def name(self) -> str:
        """The model's name (``manifest["model"]``)."""
        return self._name

    def record(self) -> dict:
        """JSON-ready description, with the hash of the model's manifest (stale tiles are never reused)."""
        return {"model": self.name, "params": dict(self.params), "model_sha256": model_hash(self.model)}

    def case_args(self) -> dict:
        """Keyword arguments of :func:`rocking.sim.cases.pulse_cases` for this damper."""
        return {"model": self.model, "params": dict(self.params)}


@dataclass
class Study:
    """A finished study.

    Attributes
    ----------
    kind : str
        ``"map"``, ``"spectrum"`` or ``"optimize"``.
    config : dict
        Full JSON-ready configuration.
    arrays : dict of ndarray
        Every result array (what the figures are drawn from).
    tables : dict of dict of ndarray
        CSV tables by file stem, each a dict of equal-length columns.
    summary : dict
        JSON-ready key results.
    run : dict
        How it ran (tiles computed and reused, wall time); not part of the configuration.
    """

    kind: str
    config: dict
    arrays: dict
    tables: dict = field(default_factory=dict)
    summary: dict = field(default_factory=dict)
    run: dict = field(default_factory=dict)


def config_hash(config: dict) -> str:
    """SHA-256 of the canonical JSON of ``config`` (sorted keys, exact float repr)."""
    text = json.dumps(config, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


def tree_hash(*folders: Path) -> str:
    """SHA-256 of every file under ``folders`` (relative path and bytes, in sorted order; caches skipped)."""
    digest = hashlib.sha256()
    for folder in folders:
        for path in sorted(folder.rglob("*")):
            if path.is_file() and "__pycache__" not in path.parts:
                digest.update(path.relative_to(folder.parent).as_posix().encode() + b"\0")
                digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def model_hash(name: str) -> str:
    """SHA-256 of every file of a generated model's folder (manifest, NumPy, C, equations)."""
    return tree_hash(load_model(name).folder)


#: The runtime's packages that decide a response, besides the generated models:
#: the parameters and pulses (``rocking.model``) and the simulator (``rocking.sim``, C sources included).
SOLVER_PACKAGES = ("model", "sim")


@functools.cache
def solver_hash() -> str:
    """SHA-256 of :data:`SOLVER_PACKAGES`: a change of the simulator never reuses finished tiles."""
    root = Path(__file__).resolve().parent.parent
    return tree_hash(*(root / name for name in SOLVER_PACKAGES))


def versions() -> dict:
    """Versions of Python, the numerical stack, ``rocking`` and the generated models.

    Read from the installed distributions' metadata: nothing is imported (SymPy and
    Dask are heavy and not needed to write a study).
    """
    import rocking

    out = {"python": platform.python_version(), "rocking": rocking.__version__}
    for package in ("numpy", "scipy", "sympy", "matplotlib", "dask", "distributed", "tqdm"):
        try:
            out[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            out[package] = None
    out["model_sha256"] = {name: model_hash(name) for name in ("block", "omd")}
    return out


def part_config(kind: str, part: str, setting: Setting, **entries) -> dict:
    """Configuration of one part of a study (e.g. ``"bare"``, ``"damper"``): what its tiles depend on.

    ``entries`` holds the rest, JSON-ready: the damper (``None`` for the bare
    block), grids as :meth:`Grid.record`, tolerances. The bare part does not
    name the damper, so studies that differ only in the damper share its tiles.
    """
    import rocking

    return {
        "format": FORMAT,
        "rocking": rocking.__version__,
        "model_sha256": {name: model_hash(name) for name in ("block", "omd")},
        "solver_sha256": solver_hash(),
        "kind": kind,
        "part": part,
        **setting.record(),
        **entries,
    }
