"""The colours, hatches and markers of every figure, declared once.

Colours are the Okabe-Ito palette (Okabe and Ito 2008, "Color Universal Design"): its eight colours stay
distinct under the common colour-vision deficiencies, so no figure tells two categories apart by red against
green. Categories of a map also carry a hatch, and curves a marker, so that a grey print still separates them.
Continuous maps use colour maps that are ordered in lightness and safe for colour-blind readers (viridis for
a magnitude, ColorBrewer's PuOr for a gain about 1).
"""

from __future__ import annotations

import re

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


#: SI prefixes of engineering notation by power of a thousand (the exponent is a multiple of 3).
PREFIXES = {-4: "p", -3: "n", -2: "µ", -1: "m", 0: "", 1: "k", 2: "M", 3: "G", 4: "T"}
#: Units a prefix may go before (never a unit that has one, kg, nor rad: a rad/s is not a krad/s).
PREFIXED = frozenset({"N/m", "N s/m", "N", "m", "s", "Pa", "J", "W"})
#: A value of a prefixed unit outside this range takes a prefix: 0.02 m and 356.9 N/m read as they are.
PLAIN = (1e-2, 1e3)


def quantity(value: float, unit: str = "", digits: int = 4) -> str:
    """A quantity as every title writes it: ``digits`` significant digits, engineering notation with an SI prefix
    for a large or small value of a unit that takes one (``11.29 kN/m``, ``406.5 kN/m``, ``5 mm``), and never a
    power of ten like ``1.129e+04`` (a value without such a unit that needs one is written ``1.13 x 10^4``).

    Parameters
    ----------
    value : float
        The value, in ``unit``.
    unit : str, optional
        Its SI unit as :data:`rocking.model.params.RANGES` writes it (``N/m``); empty for a pure number.
    digits : int, optional
        Significant digits.
    """
    v = float(value)
    space = " " if unit else ""
    if not np.isfinite(v) or v == 0:
        return f"{abs(v) if v == 0 else v:g}{space}{UNIT_TEXT.get(unit, unit)}"
    rounded = float(f"{v:.{digits}g}")
    if unit in PREFIXED and not PLAIN[0] <= abs(rounded) < PLAIN[1]:
        power = int(np.clip(np.floor(np.log10(abs(rounded)) / 3), min(PREFIXES), max(PREFIXES)))
        mantissa = float(f"{rounded / 1000.0**power:.{digits}g}")
        return f"{mantissa:g} {PREFIXES[power]}{UNIT_TEXT.get(unit, unit)}"
    text = f"{rounded:.{digits}g}"
    if "e" in text:
        digits_part, exponent = text.split("e")
        text = rf"{float(digits_part):g}$\times 10^{{{int(exponent)}}}$"
    return f"{text}{space}{UNIT_TEXT.get(unit, unit)}"


def visible(text: str) -> int:
    """About how many characters ``text`` shows: mathtext's commands count one (``\\beta``), its ``$ { } ^ _`` none."""
    return len(re.sub(r"[${}^_]", "", re.sub(r"\\[A-Za-z]+", "x", text)))


def wrap(parts: list[str], width: int = 95, sep: str = ", ") -> str:
    """``parts`` joined by ``sep`` into lines of at most ``width`` characters (a part is never cut: mathtext
    stays whole), so that a title's line fits its figure."""
    lines = [""]
    for part in parts:
        joined = f"{lines[-1]}{sep}{part}" if lines[-1] else part
        if lines[-1] and visible(joined) > width:
            lines[-1] += sep.rstrip()
            lines.append(part)
        else:
            lines[-1] = joined
    return "\n".join(lines)


#: Width of an average character of a title (DejaVu Sans), in ems: how many characters a line of a figure holds.
CHAR_EM = 0.55


def fit(text: str, inches: float, fontsize: float) -> str:
    """``text`` with each line longer than a figure ``inches`` wide holds at ``fontsize`` (points) broken at its
    commas (:func:`wrap`; a comma inside mathtext, between ``$``, never), so that a title stays on its canvas."""
    return broken(text, max(int(inches * 72 / (CHAR_EM * fontsize)), 20))


def broken(text: str, width: int, sep: str = ", ") -> str:
    """``text`` with each line longer than ``width`` characters broken at ``sep`` (:func:`wrap`), never inside
    mathtext (between ``$``)."""
    lines = []
    for line in text.split("\n"):
        parts: list[str] = []
        for piece in line.split(sep):
            if parts and parts[-1].count("$") % 2:  # inside mathtext: keep going
                parts[-1] += sep + piece
            else:
                parts.append(piece)
        lines.append(wrap(parts, width, sep))
    return "\n".join(lines)


def symbol(name: str) -> str:
    """A parameter's name as mathtext (``k_m`` as $k_m$, as every title writes it); a name that is not letters with
    one subscript (a variant's own) is kept as plain text, its ``$`` escaped."""
    head, _, tail = name.partition("_")
    if head.isalpha() and tail.isalnum():
        return rf"${head}_{{{tail}}}$"
    return name.replace("$", r"\$")
