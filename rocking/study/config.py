"""What a parametric study is given: its configuration, and the hash that keys its tiles.

A study (the overturning map, the minimum overturning spectrum, the optimal
damper) is described by a :class:`Setting` (the block and the solver), a
damper :class:`Tuning` (the paper's ``omd``) or a :class:`Variant` (any
generated model with its parameters given explicitly) and :class:`Grid` s of the non-dimensional pulse
parameters of ``docs/model.md`` section 9 (``Omega = omega_g / p``,
``beta = a_g / (g tan(alpha))``). Its result is a :class:`rocking.study.result.Study`.

Units SI (m, kg, s, rad); the study parameters themselves are non-dimensional.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import platform
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..model.floor import PAPER_FLOOR, Floor, floor_of
from ..model.loading import GENERATED, ModelError, load_model
from ..model.motion import PULSE_TYPES, SHAPES, timing
from ..model.params import Block, ParameterError, check_in_range, check_real, shown
from ..model.vertical import Vertical
from ..sim import boundary
from ..sim.problem import OPTIONS
from ..version import __version__

#: Version of the layout of study data and tiles; part of every configuration hash.
#: 2: tiles carry a manifest (place, names, shapes, dtypes, checksum of their arrays).
#: 3: map tiles carry stop_contacts and bumper_force_max.
#: 4: tiles of maps, spectra and optimisations carry a last axis of pulse directions (signs).
FORMAT = 4

#: Largest number of values of a :class:`Grid`, and of cells (pulses) of a study's grid of
#: pulses (:func:`check_cells`): about 1 GB of results, and hours of work on a few cores.
MAX_N = 100_000
MAX_CELLS = 10_000_000

#: Back ends that :func:`rocking.sim.cases.run_cases` accepts.
BACKENDS = ("c", "numpy")
#: Pulse families of the studies (docs/model.md section 12).
PULSES = tuple(PULSE_TYPES)


def is_number(value) -> bool:
    """True for a finite real number (``bool`` is not one, nor NaN, nor infinity)."""
    real = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))
    return real and math.isfinite(value)


def is_count(value) -> bool:
    """True for an integer (``bool`` is not one)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def check_type(name: str, value, kind: type, text: str) -> None:
    """Refuse ``value`` unless it is a ``kind``; ``text`` says what is expected (``"a rocking.Grid"``)."""
    if not isinstance(value, kind):
        raise ParameterError(f"{name} must be {text} (got {type(value).__name__} {value!r})")


def name_text(name: str) -> str:
    """A name read from a file, as it is if short and printable, else as a message quotes a value (one line)."""
    return name if name.isprintable() and len(name) <= 40 else shown(name)


def check_signs(name: str, value) -> list:
    """Refuse pulse directions that are not a list of 1 and/or -1, each once; return them."""
    ok = isinstance(value, list) and 1 <= len(value) <= 2 and len(set(map(repr, value))) == len(value)
    if not (ok and all(is_count(s) and s in (1, -1) for s in value)):
        raise ParameterError(
            f"{name} must be the directions of the pulses: [1], [-1], [1, -1] or [-1, 1] (got {shown(value)})"
        )
    return list(value)


def check_cells(*grids: Grid) -> None:
    """Refuse a grid of pulses of more than :data:`MAX_CELLS` cells (the product of the grids' sizes)."""
    cells = math.prod(g.n for g in grids)
    if cells > MAX_CELLS:
        names = " x ".join(f"{g.name} ({g.n})" for g in grids)
        raise ParameterError(f"{names}: {cells} cells, at most {MAX_CELLS} in one study; split it or coarsen a grid")


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
        Number of values, in [1, :data:`MAX_N`].
    log : bool, optional
        Logarithmic spacing (then ``low > 0``).
    minimum : float, optional
        Values must exceed it (default 0: every study parameter is positive).

    Raises
    ------
    ParameterError
        Naming the grid and its valid range, for an empty, reversed or
        non-finite range, a grid size outside [1, MAX_N], or arguments of
        the wrong type.
    """

    name: str
    low: float
    high: float
    n: int | None = None
    log: bool = False
    minimum: float = 0.0
    #: Explicit values (:meth:`of`), or empty: evenly spaced.
    points: tuple = ()

    @classmethod
    def of(cls, name: str, values, minimum: float = 0.0) -> Grid:
        """A grid of the given ``values`` (array_like, increasing, each above ``minimum``).

        Raises
        ------
        ParameterError
            Naming the grid, unless the values are finite numbers in increasing order.
        """
        try:
            points = np.asarray(values, dtype=float).ravel()
        except (TypeError, ValueError):
            raise ParameterError(f"{name}: values must be numbers (got {values!r:.60})") from None
        if points.size == 0 or not np.isfinite(points).all():
            raise ParameterError(f"{name}: values must be finite numbers, at least one (got {values!r:.60})")
        if points.size > 1 and not (np.diff(points) > 0).all():
            raise ParameterError(f"{name}: values must increase (got {values!r:.60})")
        low, high = float(points[0]), float(points[-1])
        return cls(name, low, high, points.size, minimum=minimum, points=tuple(points.tolist()))

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise ParameterError(
                f"a grid's name must be a string (got {self.name!r}): Grid(name, low, high, n), e.g. "
                f"Grid('Omega', 0.5, 10, 20), or Grid.of('Omega', values) for given values"
            )
        if not (is_count(self.n) and 1 <= self.n <= MAX_N):
            raise ParameterError(
                f"{self.name}: the number of values N must be an integer in [1, {MAX_N}] (got {self.n!r})"
            )
        check_type(f"{self.name}: log", self.log, bool, "True or False")
        if not is_number(self.minimum):
            raise ParameterError(f"{self.name}: minimum must be a finite number (got {self.minimum!r})")
        for end in ("low", "high"):
            value = getattr(self, end)
            if not is_number(value):
                raise ParameterError(f"{self.name}: {end} end must be a finite number (got {value!r})")
            if not value > self.minimum:
                raise ParameterError(f"{self.name}: values must be > {self.minimum:g} (got {end} end {value!r})")
        if self.n > 1 and not self.low < self.high:
            raise ParameterError(
                f"{self.name}: the range MIN MAX must have MIN < MAX (got {self.low!r} .. {self.high!r})"
            )
        if self.n == 1 and self.low != self.high:
            raise ParameterError(f"{self.name}: with N = 1 give MIN = MAX (got {self.low!r} .. {self.high!r})")
        if self.log and not self.low > 0:
            raise ParameterError(f"{self.name}: a logarithmic grid needs values > 0 (got low end {self.low!r})")
        object.__setattr__(self, "low", float(self.low))
        object.__setattr__(self, "high", float(self.high))
        object.__setattr__(self, "n", int(self.n))

    def values(self) -> np.ndarray:
        """The grid as a float array of length ``n``."""
        if self.points:
            return np.array(self.points)
        if self.log:
            return np.geomspace(self.low, self.high, self.n)
        return np.linspace(self.low, self.high, self.n)

    @classmethod
    def from_record(cls, name: str, record) -> Grid:
        """The grid that :meth:`record` described as ``record`` (a saved configuration's), checked as any grid.

        Raises
        ------
        ParameterError
            Naming the grid, for a record that is not one (not an object, another scale, ``low``, ``high``
            and ``n`` other than its values'), or a grid out of range (:class:`Grid`).
        """
        if not isinstance(record, dict):
            raise ParameterError(
                f"{name} must be a grid {{low, high, n, scale}} or {{..., values}} (got {shown(record)})"
            )
        if "values" in record:
            grid = cls.of(name, record["values"])
            if [grid.low, grid.high, grid.n] != [record.get(k) for k in ("low", "high", "n")]:
                raise ParameterError(
                    f"{name}: low, high and n must be those of its values ({grid.low!r}, {grid.high!r}, {grid.n})"
                )
            return grid
        scale = record.get("scale")
        if not (isinstance(scale, str) and scale in ("linear", "log")):
            raise ParameterError(f"{name}: scale must be linear or log (got {shown(scale)})")
        return cls(name, record.get("low"), record.get("high"), record.get("n"), log=scale == "log")

    def record(self) -> dict:
        """JSON-ready description."""
        if self.points:
            return {"low": self.low, "high": self.high, "n": self.n, "values": list(self.points)}
        return {"low": self.low, "high": self.high, "n": self.n, "scale": "log" if self.log else "linear"}


def omega_grid(block: Block, T_g: Grid) -> Grid:
    """The grid of ``Omega = omega_g / p = 2 pi / (T_g p)`` of the pulse periods ``T_g`` (s) on ``block``.

    Its values are given explicitly (:meth:`Grid.of`), in increasing ``Omega`` (decreasing ``T_g``): a grid
    even in ``T_g`` is not even in ``Omega``, and a saved study's record (:meth:`Grid.record`) keeps them, so a
    rerun scans the same pulses.
    """
    return Grid.of("Omega", 2.0 * math.pi / (T_g.values()[::-1] * block.p))


def beta_grid(block: Block, a_g: Grid) -> Grid:
    """The grid of ``beta = a_g / (g tan alpha)`` (:meth:`rocking.Block.beta`) of the pulse amplitudes ``a_g``
    (m/s^2) on ``block``: spaced as ``a_g`` is (the scaling is linear)."""
    if a_g.points:
        return Grid.of("beta", block.beta(np.array(a_g.points)))
    return Grid("beta", block.beta(a_g.low), block.beta(a_g.high), a_g.n, log=a_g.log)


def pulse_grids(block: Block, Omega=None, beta=None, T_g=None, a_g=None, shown=str) -> dict:
    """The grids ``{"Omega": ..., "beta": ...}`` of a study of pulses, each given non-dimensionally or in SI units.

    Parameters
    ----------
    block : Block
        The block that sets the scales ``p`` and ``g tan(alpha)`` (docs/model.md section 9).
    Omega, beta : Grid, optional
        Frequency and amplitude ratios ``omega_g / p`` and ``a_g / (g tan alpha)``.
    T_g, a_g : Grid, optional
        In their place: pulse periods ``T_g = 2 pi / omega_g``, s (:func:`omega_grid`), and amplitudes, m/s^2
        (:func:`beta_grid`).
    shown : callable, optional
        How a message names a keyword (the command line gives its flag).

    Raises
    ------
    ParameterError
        Naming both, for a quantity given both ways or neither.
    """
    out = {}
    for name, ratio, si, convert in (("Omega", Omega, T_g, omega_grid), ("beta", beta, a_g, beta_grid)):
        other = "T_g" if name == "Omega" else "a_g"
        if (ratio is None) == (si is None):
            how = "not both" if ratio is not None else "one of them"
            raise ParameterError(f"give {shown(name)} or {shown(other)}, {how}")
        out[name] = ratio if si is None else convert(block, si)
    return out


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
        Time followed after the pulse ends, s, in (0, 1e4].
    backend : {"c", "numpy"}, optional
        Back end of :func:`rocking.sim.cases.run_cases`.
    pulse : {"sine", "cosine", "ricker", "ricker_anti", "mp"}, optional
        The family of every pulse (docs/model.md section 12): ``Omega`` and ``beta`` are its ``omega_g / p``
        and ``a_g / (g tan alpha)``. Default ``"sine"``, the paper's one-sine pulse.
    gamma_mp, nu : float, optional
        The oscillations (> 1) and phase (rad) of the Mavroeidis-Papageorgiou pulse (``pulse="mp"`` only).
    vertical_ratio, vertical_phase : float, optional
        The vertical component of every pulse, :class:`rocking.Vertical` ``(vertical_ratio, vertical_phase)``
        (docs/model.md section 14): ``ddy_g = vertical_ratio a_g f(t + vertical_phase / omega_g)``, > 0 up,
        unsigned by the pulse's direction; the ratio in [0, 10], the lead in [0, 2 pi) rad. Default 0, 0: none.
    floor : Floor, optional
        The floor of every response, its Coulomb friction (docs/model.md section 15) and its landings' normal
        restitution ``e_n`` (section 16); default ``None``, ``Floor()``: the paper's, on which the base never
        slides, with plastic landings. Only a back end that follows friction runs a finite one.
    """

    block: Block
    rtol: float = OPTIONS["rtol"]
    t_after: float = OPTIONS["t_after"]
    backend: str = "c"
    pulse: str = "sine"
    gamma_mp: float | None = None
    nu: float = 0.0
    vertical_ratio: float = 0.0
    vertical_phase: float = 0.0
    floor: Floor = PAPER_FLOOR

    def __post_init__(self) -> None:
        if not isinstance(self.block, Block):
            raise ParameterError(f"block must be a rocking.Block (got {type(self.block).__name__})")
        boundary.check("rtol", check_real("rtol", self.rtol))
        check_in_range("t_after", self.t_after)
        if not isinstance(self.backend, str) or self.backend not in BACKENDS:
            raise ParameterError(f"backend must be one of {', '.join(BACKENDS)} (got {self.backend!r})")
        if not isinstance(self.pulse, str) or self.pulse not in PULSES:
            raise ParameterError(f"pulse must be one of {', '.join(PULSES)} (got {self.pulse!r})")
        if (self.pulse == "mp") != (self.gamma_mp is not None) or (self.nu != 0.0 and self.pulse != "mp"):
            raise ParameterError(
                "gamma_mp (and nu) shape the Mavroeidis-Papageorgiou pulse: give gamma_mp with "
                "pulse='mp', and neither with another pulse"
            )
        # Plain floats: the configuration's JSON, hence its hash, is the same for 15, 15.0 and np.float32(15).
        object.__setattr__(self, "rtol", float(self.rtol))
        object.__setattr__(self, "t_after", float(self.t_after))
        object.__setattr__(self, "nu", float(check_real("nu", self.nu)))
        object.__setattr__(self, "vertical_ratio", check_in_range("vertical_ratio", self.vertical_ratio))
        phase = check_in_range("vertical_phase", self.vertical_phase, "psi", label="[0, 2 pi)")
        if phase != 0.0 and self.vertical_ratio == 0.0:
            raise ParameterError(
                "vertical_phase is the lead of the vertical component: give it with vertical_ratio > 0"
            )
        object.__setattr__(self, "vertical_phase", phase)
        object.__setattr__(self, "floor", floor_of(self.floor))

    @property
    def vertical(self) -> Vertical | None:
        """The pulses' vertical component, ``None`` for ``vertical_ratio = 0``."""
        return Vertical(self.vertical_ratio, self.vertical_phase) if self.vertical_ratio > 0.0 else None

    def floor_args(self) -> dict:
        """Keyword arguments of :func:`rocking.sim.cases.pulse_cases` and ``sampled_cases`` for the floor (none for
        the paper's: no friction, plastic landings)."""
        return {"floor": self.floor} if self.has_floor else {}

    @property
    def has_floor(self) -> bool:
        """The floor is not the paper's: a finite friction, or landings that bounce (``e_n > 0``)."""
        return self.floor.slides or self.floor.e_n > 0.0

    def pulse_args(self) -> dict:
        """Keyword arguments of :func:`rocking.sim.cases.pulse_cases` for the pulse family, its vertical
        component and the floor."""
        vertical = {"vertical": self.vertical} if self.vertical is not None else {}
        vertical.update(self.floor_args())
        if self.pulse == "sine":
            return vertical
        shape = {"gamma_mp": self.gamma_mp, "nu": self.nu} if self.pulse == "mp" else {}
        return {"motion": self.pulse, **shape, **vertical}

    def vertical_record(self) -> dict:
        """The vertical component, JSON-ready: ``{"ratio": ..., "phase": ...}``, empty for none."""
        return {"ratio": self.vertical_ratio, "phase": self.vertical_phase} if self.vertical is not None else {}

    def record(self) -> dict:
        """JSON-ready description: the pulse family only when it is not the paper's one-sine, the vertical component
        only when there is one, the floor only when it is not the paper's (:attr:`has_floor`: so the records, and
        the hashes of the tiles, of the studies without are unchanged)."""
        record = {"block": self.block.as_params(), "rtol": self.rtol, "t_after": self.t_after, "backend": self.backend}
        if self.pulse != "sine":
            shape = {"gamma_mp": self.gamma_mp, "nu": self.nu} if self.pulse == "mp" else {}
            record["pulse"] = {"motion": self.pulse, **shape}
        if self.vertical is not None:
            record["vertical"] = self.vertical_record()
        if self.has_floor:
            # A plastic landing, the default, is said by leaving e_n out (records and hashes saved before flight
            # stay), and a floor that never slides by leaving mu_s, mu_k out (JSON has no inf).
            record["floor"] = {k: v for k, v in self.floor.settings().items() if v if k == "e_n" or math.isfinite(v)}
        return record


def floor_attrs(config: dict) -> dict:
    """Attributes of a study's Dataset naming its floor (``config["floor"]``, :meth:`Setting.record`; the paper's
    when absent): ``mu_s``, ``mu_k``, ``e_n`` where landings bounce, and the convention, in words."""
    floor = config.get("floor", PAPER_FLOOR.settings())
    words = (
        "Coulomb friction of the floor, static mu_s and kinetic mu_k, dimensionless (docs/model.md section 15)"
        if math.isfinite(floor.get("mu_s", math.inf))
        else "mu_s = mu_k = inf: the base never slides (the paper's floor)"
    )
    e_n = floor.get("e_n", 0.0)  # left out of a record: plastic, and of the attributes (those saved before stay)
    if e_n:
        words += f"; landings after flight with normal restitution e_n = {e_n:g} (docs/model.md section 16)"
    mu_s, mu_k = (floor.get(k, math.inf) for k in ("mu_s", "mu_k"))
    return {"mu_s": mu_s, "mu_k": mu_k, **({"e_n": e_n} if e_n else {}), "floor": words}


def vertical_attrs(config: dict) -> dict:
    """Attributes of a map's or spectrum's Dataset naming its pulses' vertical component (``config["vertical"]``,
    :meth:`Setting.vertical_record`; none when absent): ratio, lead (rad) and the convention, in words."""
    vertical = config.get("vertical", {})
    if not vertical:
        return {"vertical_ratio": 0.0, "vertical_component": "none: ddy_g = 0 (horizontal pulses only)"}
    ratio, phase = vertical["ratio"], vertical["phase"]
    return {
        "vertical_ratio": ratio,
        "vertical_phase": phase,
        "vertical_component": (
            f"ddy_g(t) = {ratio:g} a_g f(t + {phase:g} rad / omega_g) on the pulse's [0, t_p], m/s^2, > 0 up (it adds "
            "to gravity), unsigned by the pulse's direction (docs/model.md section 14); a run where g + ddy_g "
            "reaches 0 ends with status flight, without a verdict"
        ),
    }


def flight_beta(block: Block, config: dict) -> float:
    """The amplitude ratio ``beta`` from which the pulses of a study's ``config`` lift the ground's pull past
    gravity: ``g + ddy_g(t) <= 0`` somewhere on the pulse, so the runs that do not overturn first end with the status
    ``flight`` (docs/model.md section 14); ``inf`` without a vertical component.

    The shape scales with ``omega_g``, so the bound is the same at every ``Omega``:
    ``beta_f = 1 / (ratio tan(alpha) max(-f_v))``, ``f_v`` the vertical shape over the pulse (scanned at 1e-4 of a
    radian of phase, the shapes being smooth there).
    """
    vertical = config.get("vertical", {})
    pulse = config.get("pulse", {"motion": "sine"})
    if not vertical:
        return math.inf
    family, gamma = pulse["motion"], pulse.get("gamma_mp", 0.0)
    phase = pulse.get("nu", 0.0)
    t_c, t_p = (float(v) for v in timing(family, 1.0, phase, gamma))
    t = np.linspace(0.0, t_p, int(t_p * 1e4) + 2)
    lowest = -float(np.min(SHAPES[family](t + vertical["phase"], 1.0, phase, t_c, gamma, np)))
    return 1.0 / (vertical["ratio"] * block.tan_alpha * lowest) if lowest > 0.0 else math.inf


def tm_omega_ratio(Tm_ratio, omega_ratio=1.0) -> float:
    """The ``omega_ratio = 1 / Tm_ratio`` of a damper given by its period ``T_m p / (2 pi)``; refused beside an
    ``omega_ratio`` other than the default 1 or that one."""
    if not (is_number(Tm_ratio) and Tm_ratio > 0):
        raise ParameterError(f"Tm_ratio must be > 0 (got {shown(Tm_ratio)})")
    converted = 1.0 / float(Tm_ratio)
    if omega_ratio not in (1.0, converted):
        raise ParameterError("give the damper's Tm_ratio or its omega_ratio = 1 / Tm_ratio, not both")
    return converted


@dataclass(frozen=True, init=False)
class Tuning:
    """A damper relative to its block (``docs/model.md`` section 9).

    Parameters
    ----------
    gamma : float, optional
        Mass ratio ``m / M``, in [1e-10, 10] (default 0.05, the damper of docs/model.md section 9).
    omega_ratio : float, optional
        ``omega_m / p``, in [1e-3, 1e4]; ``T_m p / (2 pi) = 1 / omega_ratio``. Default 1.
    Tm_ratio : float, optional
        Instead of ``omega_ratio``: the damper's period ``T_m p / (2 pi)`` (> 0), the mapping's ``Tm_ratio`` and
        the command line's ``--Tm-ratio``; it sets ``omega_ratio = 1 / Tm_ratio`` (refused beside another
        ``omega_ratio`` than the default or that one). Read back as the property :attr:`Tm_ratio`.
    zeta : float, optional
        Damping ratio, in [0, 10]. Default 0.05.
    h : float, optional
        Height of the guide above the top of the block, m, in [0, 1e3]. Default 0.05 m,
        the reference damper of docs/model.md section 9 (``Damper``'s own default is 0).
    stops : bool, optional
        The guide ends in the stops of :meth:`rocking.Stops.at_edges` (model ``omd_stops``).
        Default False: the paper's unlimited guide.
    stroke : float, optional
        With ``stops``: their half-stroke ``L``, m, in ``(0, B/2)`` of the study's block.
        Default None: ``B/2`` minus the pads' depth (:meth:`rocking.Stops.at_edges`).
    """

    gamma: float = 0.05
    omega_ratio: float = 1.0
    zeta: float = 0.05
    h: float = 0.05
    stops: bool = False
    stroke: float | None = None

    def __init__(
        self,
        gamma: float = 0.05,
        omega_ratio: float = 1.0,
        zeta: float = 0.05,
        h: float = 0.05,
        stops: bool = False,
        stroke: float | None = None,
        *,
        Tm_ratio: float | None = None,
    ) -> None:
        if Tm_ratio is not None:
            omega_ratio = tm_omega_ratio(Tm_ratio, omega_ratio)
        values = {"gamma": gamma, "omega_ratio": omega_ratio, "zeta": zeta, "h": h, "stops": stops, "stroke": stroke}
        for name, value in values.items():
            object.__setattr__(self, name, value)
        self.__post_init__()

    def __post_init__(self) -> None:
        # The ranges of Damper.from_nondim; JSON-ready floats, and one hash for 1 and 1.0.
        object.__setattr__(self, "gamma", check_in_range("gamma", self.gamma, nonzero=True))
        for name in ("omega_ratio", "zeta", "h"):
            object.__setattr__(self, name, check_in_range(name, getattr(self, name)))
        if not isinstance(self.stops, (bool, np.bool_)):
            raise ParameterError(f"stops must be True or False (got {self.stops!r})")
        object.__setattr__(self, "stops", bool(self.stops))
        if self.stroke is not None:
            if not self.stops:
                raise ParameterError("stroke is the half-stroke of the stops: give it with stops=True")
            object.__setattr__(self, "stroke", check_in_range("stroke", self.stroke, "L"))

    @property
    def Tm_ratio(self) -> float:
        """``T_m p / (2 pi)``: the damper period in units of ``2 pi / p``."""
        return 1.0 / self.omega_ratio

    def record(self) -> dict:
        """JSON-ready description (also the keyword arguments of :func:`rocking.sim.cases.pulse_cases`)."""
        record = {"gamma": self.gamma, "omega_ratio": self.omega_ratio, "zeta": self.zeta, "h": self.h}
        # Only when set: the record of the paper's unlimited damper stays as it was.
        stops = {"stops": True, **({} if self.stroke is None else {"stroke": self.stroke})} if self.stops else {}
        return {**record, **stops}

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


#: The packages whose versions a study records (:func:`versions`), installed or not.
RECORDED_PACKAGES = ("numpy", "scipy", "sympy", "matplotlib", "dask", "distributed", "tqdm")


def versions() -> dict:
    """Versions of Python, the numerical stack, ``rocking`` and the generated models.

    Read from the installed distributions' metadata (:func:`installed_version`): nothing is imported (SymPy and
    Dask are heavy and not needed to write a study).
    """
    out: dict = {"python": platform.python_version(), "rocking": __version__}
    out |= {package: installed_version(package) for package in RECORDED_PACKAGES}
    out["model_sha256"] = {name: model_hash(name) for name in ("block", "omd")}
    return out


def installed_version(package: str) -> str | None:
    """The version of the installed distribution ``package`` (None if it is not installed), as
    :func:`importlib.metadata.version` gives it, read from its metadata's header alone.

    The version is a field of the core metadata's header, which ends at the first blank line; the long description
    follows it (tens of kilobytes for NumPy and matplotlib, which ``version`` parses whole with the email package:
    2 ms each). importlib.metadata is imported here: the commands that record no study do without it (10 ms).
    """
    from importlib import metadata

    try:
        distribution = metadata.distribution(package)
    except metadata.PackageNotFoundError:
        return None
    header = (distribution.read_text("METADATA") or distribution.read_text("PKG-INFO") or "").partition("\n\n")[0]
    for line in header.splitlines():
        field_name, _, value = line.partition(":")
        if field_name.strip().lower() == "version":
            return value.strip()
    return distribution.version  # no header field: what the email parser makes of it


def part_config(kind: str, part: str, setting: Setting, **entries) -> dict:
    """Configuration of one part of a study (e.g. ``"bare"``, ``"damper"``): what its tiles depend on.

    ``entries`` holds the rest, JSON-ready: the damper (``None`` for the bare
    block), grids as :meth:`Grid.record`, tolerances. The bare part does not
    name the damper, so studies that differ only in the damper share its tiles.
    """
    return {
        "format": FORMAT,
        "rocking": __version__,
        "model_sha256": {name: model_hash(name) for name in ("block", "omd")},
        "solver_sha256": solver_hash(),
        "kind": kind,
        "part": part,
        **setting.record(),
        **entries,
    }
