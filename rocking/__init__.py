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

from .model.floor import Floor
from .model.loading import Model, ModelError, available_models, load_model
from .model.motion import MavroeidisPapageorgiou, OneCosinePulse, RickerWavelet, SampledMotion
from .model.params import Block, Damper, ParameterError, Stops
from .model.plausibility import PlausibilityWarning
from .model.pulse import OneSinePulse
from .model.vertical import Vertical
from .sim.cbuild import CBuildError
from .sim.problem import Response, SimulationError
from .sim.run import BackendWarning, simulate
from .study.api import (
    design,
    fragility,
    friction_map,
    incremental_dynamic_analysis,
    minimum_overturning_spectrum,
    optimal_damper,
    overturning_map,
    threshold_map,
)
from .study.config import Grid, Setting, Tuning, Variant
from .study.design import DesignWarning, designed_damper
from .study.files import DiskFull
from .study.fragility import FitWarning
from .study.result import Study
from .study.storage import load, save
from .study.suite import Suite
from .study.tiles import Execution, Interrupted, TileWarning
from .version import __version__ as __version__

__all__ = [
    "BackendWarning",
    "Block",
    "CBuildError",
    "Damper",
    "DesignWarning",
    "DiskFull",
    "Execution",
    "FitWarning",
    "Floor",
    "Grid",
    "Interrupted",
    "MavroeidisPapageorgiou",
    "Model",
    "ModelError",
    "OneCosinePulse",
    "OneSinePulse",
    "ParameterError",
    "PlausibilityWarning",
    "Response",
    "RickerWavelet",
    "SampledMotion",
    "Setting",
    "SimulationError",
    "Stops",
    "Study",
    "Suite",
    "TileWarning",
    "Tuning",
    "Variant",
    "Vertical",
    "available_models",
    "design",
    "designed_damper",
    "fragility",
    "friction_map",
    "incremental_dynamic_analysis",
    "load",
    "load_model",
    "minimum_overturning_spectrum",
    "optimal_damper",
    "overturning_map",
    "save",
    "simulate",
    "threshold_map",
]
