"""rocking: a rigid block rocking on the ground with an oscillating mass damper on its top.

The equations come from SymPy (:mod:`rocking.derive`) as generated NumPy and C
code (:mod:`rocking.generated`); this package is the runtime around them,
one subpackage per layer:

- :mod:`rocking.model`: the generated models, the block and its damper, the ground motions;
- :mod:`rocking.sim`: one response, on the C or the NumPy/SciPy back end;
- :mod:`rocking.study`: overturning maps, spectra, the optimal damper, the design answer, the threshold
  frequency across geometries and IDA/fragility over suites of motions, in tiles, over both directions of
  the motion; with plain arguments, returning an :class:`xarray.Dataset`, at the top level;
- :mod:`rocking.plot`, :mod:`rocking.cli`: figures and the ``rocking`` command;
- :mod:`rocking.reference`: the paper's equations typed by hand, and ``rocking verify``.

The names below are the public interface. Units are SI throughout: m, kg, s,
rad, N/m, N s/m; study parameters are non-dimensional (docs/model.md section 9).

Examples
--------
>>> import rocking
>>> block = rocking.Block.reference()
>>> damper = rocking.Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
>>> pulse = rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=4.0)
>>> rocking.simulate(block, None, pulse).overturned, rocking.simulate(block, damper, pulse).overturned
(True, True)
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

from .version import __version__ as __version__

#: The public names, each with the module that defines it, imported at the name's first use (PEP 562): ``import
#: rocking`` loads no NumPy, so that the ``rocking`` command chooses how many threads NumPy's BLAS starts before
#: NumPy loads (:mod:`rocking.cli`). Type checkers read the same names from the imports below.
PUBLIC = {
    "Floor": ".model.floor",
    "Model": ".model.loading",
    "ModelError": ".model.loading",
    "available_models": ".model.loading",
    "load_model": ".model.loading",
    "MavroeidisPapageorgiou": ".model.motion",
    "OneCosinePulse": ".model.motion",
    "RickerWavelet": ".model.motion",
    "SampledMotion": ".model.motion",
    "Block": ".model.params",
    "Damper": ".model.params",
    "ParameterError": ".model.params",
    "Stops": ".model.params",
    "PlausibilityWarning": ".model.plausibility",
    "OneSinePulse": ".model.pulse",
    "Vertical": ".model.vertical",
    "CBuildError": ".sim.cbuild",
    "Response": ".sim.problem",
    "SimulationError": ".sim.problem",
    "BackendWarning": ".sim.run",
    "simulate": ".sim.run",
    "design": ".study.api",
    "fragility": ".study.api",
    "friction_map": ".study.api",
    "incremental_dynamic_analysis": ".study.api",
    "minimum_overturning_spectrum": ".study.api",
    "optimal_damper": ".study.api",
    "overturning_map": ".study.api",
    "threshold_map": ".study.api",
    "Grid": ".study.config",
    "Setting": ".study.config",
    "Tuning": ".study.config",
    "Variant": ".study.config",
    "DesignWarning": ".study.design",
    "designed_damper": ".study.design",
    "DiskFull": ".study.files",
    "FitWarning": ".study.fragility",
    "Study": ".study.result",
    "load": ".study.storage",
    "save": ".study.storage",
    "Suite": ".study.suite",
    "Execution": ".study.tiles",
    "Interrupted": ".study.tiles",
    "TileWarning": ".study.tiles",
}

__all__ = sorted(PUBLIC)


def __getattr__(name: str) -> Any:
    """The public ``name``, imported from its module at its first use and kept here."""
    if name not in PUBLIC:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(PUBLIC[name], __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The module's names with the public ones not imported yet."""
    return sorted(set(globals()) | set(__all__))


# The names of PUBLIC for type checkers and readers (tests/test_import.py holds the two the same); F401: ruff does
# not read __all__ from PUBLIC.
if TYPE_CHECKING:
    from .model.floor import Floor  # noqa: F401
    from .model.loading import Model, ModelError, available_models, load_model  # noqa: F401
    from .model.motion import MavroeidisPapageorgiou, OneCosinePulse, RickerWavelet, SampledMotion  # noqa: F401
    from .model.params import Block, Damper, ParameterError, Stops  # noqa: F401
    from .model.plausibility import PlausibilityWarning  # noqa: F401
    from .model.pulse import OneSinePulse  # noqa: F401
    from .model.vertical import Vertical  # noqa: F401
    from .sim.cbuild import CBuildError  # noqa: F401
    from .sim.problem import Response, SimulationError  # noqa: F401
    from .sim.run import BackendWarning, simulate  # noqa: F401
    from .study.api import (  # noqa: F401
        design,
        fragility,
        friction_map,
        incremental_dynamic_analysis,
        minimum_overturning_spectrum,
        optimal_damper,
        overturning_map,
        threshold_map,
    )
    from .study.config import Grid, Setting, Tuning, Variant  # noqa: F401
    from .study.design import DesignWarning, designed_damper  # noqa: F401
    from .study.files import DiskFull  # noqa: F401
    from .study.fragility import FitWarning  # noqa: F401
    from .study.result import Study  # noqa: F401
    from .study.storage import load, save  # noqa: F401
    from .study.suite import Suite  # noqa: F401
    from .study.tiles import Execution, Interrupted, TileWarning  # noqa: F401
