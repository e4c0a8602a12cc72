"""The labels of the studies' data: units and meanings of every field and coordinate, SI coordinates, NetCDF.

A study builds its :class:`xarray.Dataset` where it allocates its arrays (:attr:`rocking.study.result.Study.data`),
with

- dimensions named after the swept quantities and the study's own (``part``, ``sign``, ``Omega``, ``beta``,
  ``motion``, ``level``, ...);
- coordinates in non-dimensional and SI terms (``T_g`` in s and ``a_g`` in m/s^2 beside ``Omega`` and
  ``beta``, from the study's block, :func:`si_coordinates`: docs/model.md section 9);
- CF-style ``units`` and ``long_name`` on every variable (:func:`field_attrs`, :func:`coordinate_attrs`), the
  response fields' taken from the simulator's own table (:data:`rocking.sim.boundary.RESULT`); categorical
  values (statuses, flags, outcomes, the damper's effect) with their key as ``flag_values`` and
  ``flag_meanings``.

:func:`to_dataset` adds the configuration, the software versions and the summary as JSON attributes; saved as
NetCDF (``<name>.nc``, :func:`rocking.study.storage.save`), it reads back as the same ``Dataset``
(:func:`read_netcdf`).
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np

from ..model.intensity import MEASURES
from ..model.loading import ModelError, saved_model
from ..model.params import Block, ParameterError
from ..sim.boundary import RESULT, STATUSES
from .config import config_hash
from .config import versions as current_versions
from .files import describe
from .vocabulary import FLAG_WORDS, FLIGHT, NOT_COMPUTED, PART_NAMES, REGIMES, SAFE, THRESHOLD_STATUSES

#: NetCDF attribute conventions followed.
CONVENTIONS = "CF-1.10"

_PART = "(?:" + "|".join(PART_NAMES) + ")"

#: Keys of categorical arrays: the meaning of each value (CF ``flag_values`` / ``flag_meanings``).
STATUS_KEY = {-1: "not_computed", **{s.value: s.name for s in STATUSES}}
FLAG_KEY = FLAG_WORDS
EFFECT_KEY = {-1: "lost", 0: "unchanged", 1: "saved"}
SIGN_KEY = {-1: "negative", 0: "not_known", 1: "positive"}
THRESHOLD_STATUS_KEY = dict(enumerate(THRESHOLD_STATUSES))
REGIME_KEY = {NOT_COMPUTED: "not_computed", **REGIMES}
FLEW_KEY = {NOT_COMPUTED: "not_computed", 0: "on_the_floor", 1: "flew"}

#: What a field means, by name: ``(units, long name[, key])``.
_RESULTS = {f.name: (f.unit or "1", f.doc) for f in RESULT}
FIELDS: dict[str, tuple] = {
    **_RESULTS,
    "overturned": ("1", "overturned: |theta| reached pi/2"),
    "status": ("1", "why the run ended", STATUS_KEY),
    "computed": ("1", "computed (not filled in by the adaptive map from its neighbours)"),
    "worst_sign": ("1", "direction of the pulse that governs the envelope", SIGN_KEY),
    "effect": ("1", "effect of the damper on overturning", EFFECT_KEY),
    "outcome": ("1", "outcome: -1 safe, n >= 0 overturned after n impacts"),
    "regime": (
        "1",
        "what the block did on the floor with friction: rest, rocks (the base lifted), slides (the base slipped, "
        "never lifted), slides and rocks (both), overturns",
        REGIME_KEY,
    ),
    "flew": (
        "1",
        "the base left the floor (flights > 0, docs/model.md section 16): with a verdict, the response flew and "
        "landed, or flew and overturned",
        FLEW_KEY,
    ),
    "flown": ("1", "responses of the scan and the bisection whose base left the floor and came to a verdict"),
    "beta_min_flew": (
        "1",
        "the response that overturns at beta_min flew first (flights > 0: flies and overturns); 0 where it did not "
        "or beta_min is not reached",
    ),
    "stroke_over_half_width": ("1", "largest damper stroke over the block's half-width B/2"),
    "stroke_over_L": ("1", "largest damper stroke over the stops' half-stroke L"),
    "beta_min": ("1", "smallest overturning amplitude ratio a_g / (g tan alpha); NaN where not reached in the scan"),
    "a_g_min": ("m/s^2", "smallest overturning pulse amplitude a_g = beta_min g tan(alpha); NaN where not reached"),
    "a_g_min_lower_bound": ("m/s^2", "lower bound of an a_g_min not reached in the scan (a_g_min NaN)"),
    "beta_min_lower_bound": (
        "1",
        "lower bound of a beta_min not reached in the scan (beta_min NaN): the last amplitude ratio scanned, none "
        "overturning",
    ),
    "beta_safe": ("1", "largest safe amplitude ratio below beta_min"),
    "flag": ("1", "how beta_min was found", FLAG_KEY),
    "undetermined": ("1", "responses without a verdict (max_events, max_steps, flight or jammed)"),
    "scan_outcome": (
        "1",
        f"outcome at each scan amplitude: {SAFE} not overturned (safe, or no verdict: counted in "
        f"undetermined), {FLIGHT} flight (g + ddy_g reached 0 on a model without flight functions: no verdict here "
        "nor above), n >= 0 overturned after n impacts",
    ),
    "windows": ("1", "safe windows above beta_min: Omega, first and last safe scan amplitude"),
    "gain": ("1", "gain: beta_min with the damper over beta_min of the block alone"),
    "worst_gain": ("1", "worst gain over the band: the smallest gain over its Omega"),
    "r": ("1", "damper period ratio T_m p / (2 pi)"),
    "zeta": ("1", "damping ratio of the damper"),
    "k_m": ("N/m", "spring stiffness of the damper"),
    "c": ("N s/m", "dashpot coefficient of the damper"),
    "Tm_over_Tg": ("1", "damper period over the pulse period T_m / T_g"),
    "edge": ("1", "the optimum lies on an edge of the searched period range (1) or inside it (0)"),
    "Omega_star": ("1", "threshold frequency ratio Omega*: above it the damper helps"),
    "Omega_star_low": ("1", "lower end of the bracket of Omega*"),
    "Omega_star_high": ("1", "upper end of the bracket of Omega*"),
    "best_gamma": ("1", "mass ratio m/M of the best damper"),
    "stroke_use": ("1", "largest damper stroke over the half-stroke L"),
    "on_block": ("1", "the damper's stroke stays on the block"),
    "beta_max": ("1", "largest amplitude ratio searched (the acceleration bound a_max)"),
    "gain_flag": ("1", "how the damped block's beta_min was found: the gain is a bound unless bracketed", FLAG_KEY),
    "safe_from": ("1", "Omega above which the block alone never overturns within beta_max"),
    "r_at_edge": ("1", "the optimum period lies on an edge of the searched range"),
    "first": ("level units", "first level at which the motion overturns the block"),
    "last_safe": ("level units", "last safe level of the motion"),
    "reversals": ("1", "levels at which the motion overturns the block and not at the next one"),
    "fraction": ("1", "fraction of the motions that overturn the block"),
    "sensitive": ("1", "sensitive to the tolerance: the tolerance check's runs disagree (in either direction)"),
    "sensitive_fraction": (
        "1",
        "fraction of the responses (motions and directions) sensitive to the tolerance; NaN: not checked",
    ),
    "curve": ("1", "fitted lognormal probability of overturning"),
    "band_low": ("1", "lower end of the bootstrap 90 % band of the fitted probability"),
    "band_high": ("1", "upper end of the bootstrap 90 % band of the fitted probability"),
    "im": ("level units", "intensity measure of each motion, unscaled"),
    "median": ("level units", "median of the fitted lognormal fragility (theta of Baker 2015)"),
    "dispersion": (
        "1",
        "dispersion of the fitted lognormal fragility: standard deviation of ln IM (beta of Baker 2015)",
    ),
    "median_low": ("level units", "lower end of the bootstrap 90 % interval of the median"),
    "median_high": ("level units", "upper end of the bootstrap 90 % interval of the median"),
    "dispersion_low": ("1", "lower end of the bootstrap 90 % interval of the dispersion"),
    "dispersion_high": ("1", "upper end of the bootstrap 90 % interval of the dispersion"),
}
#: What a field means in one kind of study, where it differs from :data:`FIELDS`.
KIND_FIELDS = {
    "threshold": {"status": ("1", "where Omega* lies against the scanned Omega", THRESHOLD_STATUS_KEY)},
}

#: Coordinates: ``(units, long name)``.
COORDINATES = {
    "Omega": ("1", "pulse frequency ratio omega_g / p"),
    "beta": ("1", "pulse amplitude ratio a_g / (g tan alpha)"),
    "beta_scan": ("1", "scanned pulse amplitude ratio a_g / (g tan alpha)"),
    # The SI coordinates beside Omega and beta (si_coordinates), and the CSV columns of the same names.
    "T_g": ("s", "pulse period T_g = 2 pi / omega_g"),
    "a_g": ("m/s^2", "pulse amplitude a_g = beta g tan(alpha)"),
    "sign": ("1", "direction of the pulse (+1: the paper's, -1: mirrored)"),
    "mu": ("1", "Coulomb friction of the floor, static = kinetic (mu_s = mu_k = mu)"),
    "gamma": ("1", "damper mass ratio m / M"),
    "r_coarse": ("1", "damper period ratio T_m p / (2 pi) of the coarse search"),
    "zeta_coarse": ("1", "damping ratio of the coarse search"),
    "lam": ("1", "slenderness H / B"),
    "p": ("rad/s", "frequency parameter p = sqrt(3 g / (4 R))"),
    "level": ("level units", "level of the intensity measure"),
    "curve_x": ("level units", "level of the fitted fragility curve"),
}


def _strip(name: str) -> str:
    """A table's column's field: its name without its part's prefix, its direction's suffix, the ``best_`` of the
    best over a search and the ``_opt`` of an optimum."""
    name = re.sub(rf"^{_PART}_", "", name)
    name = re.sub(r"_(pos|neg)$", "", name)
    name = re.sub(r"^(best|worst)_", "", name) if name not in FIELDS else name
    return re.sub(r"_opt$", "", name) if name not in FIELDS else name


def _part(name: str) -> str | None:
    match = re.match(rf"^({_PART})_", name)
    return match.group(1) if match else None


def _level_units(config: dict) -> str:
    measure = config.get("measure", "scale")
    return {"scale": "1", "amplitude": "m/s^2", **MEASURES}.get(measure, "1")


def _stroke_units(config: dict) -> str:
    """The unit of ``x_max``, the largest ``|q[1]|``: the unit of the damper's first coordinate in its model's
    manifest (rad for the pendulum's angle), m for the paper's damper."""
    damper = config.get("damper")
    name = damper.get("model") if isinstance(damper, dict) else None
    if not name:
        return "m"
    try:
        model = saved_model(name, "the study's configuration: damper.model")
        return model.manifest["units"][model.coordinates[1]]
    except (ModelError, KeyError, IndexError):
        return "m"


def field_attrs(field: str, config: dict) -> dict:
    """CF-style attributes of the result ``field`` (a name of :data:`FIELDS`) of a study of ``config``: units,
    long name, the key of a categorical one."""
    return _entry_attrs({**FIELDS, **KIND_FIELDS.get(config.get("kind"), {})}.get(field), field, config)


def coordinate_attrs(dim: str, config: dict) -> dict:
    """CF-style attributes of the coordinate ``dim`` (a name of :data:`COORDINATES`)."""
    return _entry_attrs(COORDINATES.get(dim), dim, config)


def _entry_attrs(entry: tuple | None, field: str, config: dict) -> dict:
    if entry is None:
        return {}
    units, long_name, *key = entry
    if units == "level units":
        units = _level_units(config)
    if field == "x_max":
        units = _stroke_units(config)
    attrs = {"units": units, "long_name": long_name}
    if key:
        attrs["flag_values"] = np.array(list(key[0]), np.int64)
        attrs["flag_meanings"] = " ".join(key[0].values())
    return attrs


def _attrs(name: str, config: dict, coordinate: bool = False) -> dict:
    """CF-style attributes of a table's column ``name``, which may name its part and direction (:func:`_strip`)."""
    attrs = coordinate_attrs(name, config) if coordinate else field_attrs(_strip(name), config)
    part = _part(name)
    if attrs and part:
        attrs["long_name"] += f" ({PART_NAMES[part]})"
    return attrs


def si_coordinates(config: dict, coords: dict) -> dict:
    """Dimensional coordinates beside the non-dimensional ones, for a study of one block."""
    if "block" not in config:
        return {}
    block = Block(**config["block"])
    out = {}
    if "Omega" in coords:
        out["T_g"] = ("Omega", 2 * math.pi / (np.asarray(coords["Omega"][1]) * block.p), coordinate_attrs("T_g", {}))
    for beta in ("beta", "beta_scan"):
        if beta in coords:
            a_g = block.a_g(np.asarray(coords[beta][1]))
            out[f"a_g_{beta}" if beta != "beta" else "a_g"] = (beta, a_g, coordinate_attrs("a_g", {}))
    if "r_coarse" in coords:
        out["T_m_coarse"] = (
            "r_coarse",
            np.asarray(coords["r_coarse"][1]) * 2 * math.pi / block.p,
            {"units": "s", "long_name": "damper period T_m of the coarse search"},
        )
    return out


#: The amplitudes in SI units of a study's results (:func:`si_amplitudes`), each of its amplitude ratio.
SI_AMPLITUDES = {"a_g_min": "beta_min", "a_g_min_lower_bound": "beta_min_lower_bound"}


def si_amplitudes(config: dict, fields: dict) -> dict:
    """The amplitudes ``a_g = beta g tan(alpha)`` (m/s^2, :meth:`rocking.Block.a_g`) of the amplitude ratios among
    ``fields`` (:data:`SI_AMPLITUDES`), for a study of one block (none for another)."""
    if "block" not in config:
        return {}
    block = Block(**config["block"])
    return {si: block.a_g(np.asarray(fields[ratio], float)) for si, ratio in SI_AMPLITUDES.items() if ratio in fields}


def to_dataset(study, versions: dict | None = None):
    """The study's data (:attr:`rocking.study.result.Study.data`) with its configuration, summary and the
    software's versions as attributes (see the module's text).

    Parameters
    ----------
    study : Study
    versions : dict, optional
        The software versions to record (default: those of this process, :func:`rocking.study.config.versions`).

    Returns
    -------
    xarray.Dataset
    """
    attrs = {
        "Conventions": CONVENTIONS,
        "title": f"rocking {study.kind} study",
        "kind": study.kind,
        "config": json.dumps(study.config, sort_keys=True),
        "config_sha256": config_hash(study.config),
        "summary": json.dumps(study.summary, sort_keys=True, default=_json_default),
        "versions": json.dumps(versions if versions is not None else current_versions(), sort_keys=True),
        "units": "SI (m, kg, s, rad, N); ratios are non-dimensional (units 1)",
    }
    if isinstance(study.summary.get("verdict"), dict):  # a design's verdict: its code and its sentence
        attrs["verdict"], attrs["verdict_text"] = study.summary["verdict"]["code"], study.summary["verdict"]["text"]
    if isinstance(study.summary.get("gain"), dict):  # a spectrum's gain of the damper, as its command says it
        attrs["gain_text"] = study.summary["gain"]["text"]
    if "guarantee" in study.summary:  # what an adaptive map can miss, in plain words beside the JSON
        attrs["guarantee"] = study.summary["guarantee"]
    return study.data.copy().assign_attrs(attrs)


def _json_default(value):
    """JSON of the NumPy scalars a summary may hold."""
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON: {type(value).__name__}")


def read_netcdf(path: str | Path):
    """The :class:`xarray.Dataset` of a study saved by :func:`rocking.study.storage.save`, read into memory.

    Raises
    ------
    ParameterError
        In one line naming the file, if it is not a NetCDF file of a rocking study.
    """
    import xarray as xr

    path = Path(path)
    try:
        dataset = xr.load_dataset(path, engine="netcdf4")
    except (OSError, ValueError) as exc:
        raise ParameterError(f"{path}: not a readable NetCDF file ({describe(exc)})") from None
    if not isinstance(dataset.attrs.get("kind"), str) or "config" not in dataset.attrs:
        raise ParameterError(f"{path}: not a rocking study (no kind and configuration in its attributes)")
    return dataset


def to_dataframes(study) -> dict:
    """The study's tables (:attr:`Study.tables`) as :class:`pandas.DataFrame`, by name.

    Each frame's ``attrs["units"]`` and ``attrs["long_names"]`` give every column's units and meaning where
    the column is a field of :data:`FIELDS` (a column whose name states its units, ``k_m_opt_N_per_m``, says
    so itself); coded columns (the damper's effect, a direction) hold their meanings as categories.
    """
    import pandas as pd

    frames = {}
    for name, columns in study.tables.items():
        frame = pd.DataFrame({k: np.asarray(v) for k, v in columns.items()})
        units, long_names = {}, {}
        for column in frame.columns:
            attrs = _attrs(column, study.config) or _attrs(column, study.config, coordinate=True)
            if not attrs:
                continue
            units[column], long_names[column] = attrs["units"], attrs["long_name"]
            if "flag_values" in attrs and frame[column].dtype.kind in "iu":
                key = dict(zip(attrs["flag_values"].tolist(), attrs["flag_meanings"].split(), strict=True))
                frame[column] = pd.Categorical(frame[column].map(key), categories=list(key.values()))
        frame.attrs.update(kind=study.kind, units=units, long_names=long_names)
        frames[name] = frame
    return frames


def html(study) -> str:
    """An HTML view of a study for Jupyter: its kind, its summary and its :class:`xarray.Dataset`."""
    from html import escape

    rows = "".join(
        f"<tr><td>{escape(str(k))}</td><td>{escape(json.dumps(v, default=_json_default))}</td></tr>"
        for k, v in study.summary.items()
        if not isinstance(v, dict | list)
    )
    # An IDA's summary is in its Dataset's variables: no empty table above them.
    table = f"<table><tr><th>summary</th><th></th></tr>{rows}</table>" if rows else ""
    return f"<div><strong>rocking {escape(study.kind)} study</strong>{table}{to_dataset(study)._repr_html_()}</div>"
