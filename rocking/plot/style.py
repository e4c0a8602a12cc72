"""The colours, hatches and markers of every figure, declared once.

Colours are the Okabe-Ito palette (Okabe and Ito 2008, "Color Universal Design"): its eight colours stay
distinct under the common colour-vision deficiencies, so no figure tells two categories apart by red against
green. Categories of a map also carry a hatch, and curves a marker, so that a grey print still separates them.
Continuous maps use colour maps that are ordered in lightness and safe for colour-blind readers (viridis for
a magnitude, ColorBrewer's PuOr for a gain about 1).
"""

from __future__ import annotations

import numpy as np

#: The Okabe-Ito palette by name (hex sRGB).
OKABE_ITO = {
    "black": "#000000",
    "orange": "#E69F00",
    "sky blue": "#56B4E9",
    "bluish green": "#009E73",
    "yellow": "#F0E442",
    "blue": "#0072B2",
    "vermillion": "#D55E00",
    "reddish purple": "#CC79A7",
}
#: Neutral tones beside the palette: the background of a safe cell, and cells or lines of no interest.
LIGHT = "#F7F7F7"
GREY = "#999999"

#: Colours of curves drawn in turn (the damper sizes of an optimisation, the blocks of a threshold figure).
CYCLE = tuple(
    OKABE_ITO[name]
    for name in ("blue", "orange", "bluish green", "reddish purple", "vermillion", "sky blue", "yellow", "black")
)
#: Markers that go with :data:`CYCLE`, so that curves differ in grey print too.
MARKERS = ("o", "s", "D", "v", "P", "X", "h", "*")

#: The block alone and the block with its damper, in every figure.
PART_STYLE = {
    "bare": {"color": OKABE_ITO["black"], "marker": "o", "label": "block alone"},
    "damper": {"color": OKABE_ITO["blue"], "marker": "s", "label": "with damper"},
}

#: A magnitude (Omega* over the geometries) and a gain ratio about 1 (the colour bar is logarithmic, centred on 1).
SEQUENTIAL = "viridis"
DIVERGING = "PuOr"


#: How a figure names each family of ground motion (rocking.model.motion.FAMILIES).
PULSE_NAMES = {
    "sine": "one-sine pulse",
    "cosine": "one-cosine pulse",
    "ricker": "symmetric Ricker wavelet",
    "ricker_anti": "antisymmetric Ricker wavelet",
    "mp": "Mavroeidis-Papageorgiou pulse",
    "sampled": "sampled motion",
}

#: How a figure names each measure of the levels of an IDA (rocking.study.ida.LEVELS).
MEASURE_NAMES = {
    "scale": "scale factor",
    "amplitude": "amplitude $a_g$",
    "pga": "PGA",
    "pgv": "PGV",
    "arias": "Arias intensity",
    "cav": "CAV",
}
#: How a figure writes each unit of those measures (mathtext).
UNIT_TEXT = {"": "", "m/s^2": "m/s$^2$", "m/s": "m/s"}


def cycle(i: int) -> dict:
    """Colour and marker of the ``i``-th curve of a set (they repeat after eight)."""
    return {"color": CYCLE[i % len(CYCLE)], "marker": MARKERS[i % len(MARKERS)]}


def extend(values, low: float, high: float) -> str:
    """The ``extend`` of a colour bar over ``[low, high]``: which ends the finite ``values`` pass."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    below, above = bool(v.size and v.min() < low), bool(v.size and v.max() > high)
    return {(False, False): "neither", (True, False): "min", (False, True): "max", (True, True): "both"}[below, above]
