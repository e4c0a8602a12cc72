"""rocking: a rigid block rocking on the ground with an oscillating mass damper on its top.

The equations come from SymPy (``derive/``) as generated NumPy and C code
(``generated/``, installed as :mod:`rocking.generated`); this package is the
runtime around them. Units are SI throughout: m, kg, s, rad, N/m, N s/m.
"""

from .model.loading import Model, available_models, load_model
from .model.params import Block, Damper, ParameterError
from .sim.problem import Response
from .model.pulse import OneSinePulse
from .sim.run import simulate

__all__ = [
    "Block",
    "Damper",
    "Model",
    "OneSinePulse",
    "ParameterError",
    "Response",
    "available_models",
    "load_model",
    "simulate",
]
__version__ = "0.1.0"
