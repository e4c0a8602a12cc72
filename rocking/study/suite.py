"""A suite of ground motions for incremental dynamic analysis and fragility: record files, the stochastic
model, or analytic pulses.

A suite is a recipe, not the motions: :meth:`Suite.motion` builds motion ``i`` where it is
used (in a tile, on any worker), so a study of thousands of motions holds one at a time.
Files are read once when the suite is made, to refuse a bad file at once and to record its
SHA-256; a file changed afterwards is refused when a tile reads it. A record file may carry a vertical record
(:meth:`Suite.from_files`, ``vertical_motions``), hashed, checked and read the same way. A stochastic motion
is drawn from the ``i``-th child of its seed (:func:`rocking.model.stochastic.record_rng`).
A suite of pulses holds the pulses themselves (a few numbers each): near-fault motions
of uncertain period, say, for a fragility against the pulse's amplitude.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..model.motion import PULSE_TYPES, SampledMotion, describe, family_of
from ..model.params import ParameterError, check_in_range
from ..model.records import UNITS, Record, file_sha256, paired_vertical, read_record
from ..model.stochastic import DEFAULT_SITE, SiteModel, check_vertical_site, record_rng, synthesize, vertical_rng

#: Largest number of motions in a suite.
MAX_MOTIONS = 100_000

#: The sources of a suite (:func:`suite_of`), as their messages name them.
SOURCES = {"motions": "motions FILES", "stochastic": "stochastic N", "pulses": "pulses FAMILY"}
#: The options of each source of a suite.
OPTIONS_OF = {
    "motions": ("unit", "vertical_motions"),
    "stochastic": ("seed", "site", "vertical_ratio", "vertical_site"),
    "pulses": ("periods", "amplitude", "gamma_mp", "nu"),
}


class DuplicateMotionWarning(UserWarning):
    """Two record files of a suite hold the same motion (the same dt and samples, in m/s^2): the suite counts it
    twice, weighing it double in a fragility."""


def _warn_if_seen(seen: dict, record: Record, path: Path) -> None:
    """Warn (:class:`DuplicateMotionWarning`) if a file of ``seen`` (by dt and samples) held ``record`` already,
    naming both; else add it."""
    key = (record.dt, hashlib.sha256(record.acceleration.tobytes()).hexdigest())
    if key in seen:
        warnings.warn(
            f"motions {seen[key]} and {path} hold the same samples ({len(record.acceleration)} at dt = "
            f"{record.dt:g} s): the suite counts them as two motions",
            DuplicateMotionWarning,
            stacklevel=3,
        )
    else:
        seen[key] = path


@dataclass(frozen=True)
class Suite:
    """Ground motions for a study, made one at a time by :meth:`motion`.

    Use :meth:`from_files` or :meth:`stochastic`.

    Attributes
    ----------
    files : tuple of (str, str, str or None)
        Absolute path, SHA-256 and unit of the accelerations of each record file (empty for a stochastic suite);
        a unit of None: the one its header states (``.AT2`` files are in g).
    site : SiteModel or None
        The stochastic model (None for files).
    seed, n : int
        The seed and the number of motions of a stochastic suite.
    pulses : tuple
        The analytic pulses of a suite of pulses (:meth:`from_pulses`).
    vertical_ratio : float
        A stochastic suite's vertical component: ``ddy_g = vertical_ratio a_v(t)``, ``a_v`` a record of
        ``vertical_site`` (:mod:`rocking.model.stochastic`); 0: none.
    vertical_site : SiteModel or None
        The vertical component's site model; None: the horizontal ``site``.
    vertical_files : tuple of (str, str, str or None)
        Absolute path, SHA-256 and unit of the vertical record paired with each of ``files``, > 0 up (docs/model.md
        section 14), or empty: none; its samples at the horizontal record's times
        (:func:`~rocking.model.records.paired_vertical`).
    """

    files: tuple = ()
    site: SiteModel | None = None
    seed: int = 0
    n: int = 0
    pulses: tuple = ()
    vertical_ratio: float = 0.0
    vertical_site: SiteModel | None = None
    vertical_files: tuple = ()

    @classmethod
    def from_files(cls, paths, unit: str | None = None, vertical_motions=None) -> Suite:
        """The records of ``paths``, each read now: ``.AT2``, or columns of time and acceleration.

        Parameters
        ----------
        paths : iterable of path or (path, unit)
            Record files; a pair gives its file's own unit of acceleration (``"g"``, ``"m/s2"``, ``"cm/s2"``, ...).
        unit : str, optional
            The unit of the files given without one (the vertical ones too); default: the one each header states.
        vertical_motions : iterable of path or (path, unit), optional
            The vertical record of each of ``paths``, in the same order, > 0 up: of the same dt, taken as 0 after
            its end and cut at the horizontal record's, as ``rocking simulate --motion H --vertical V``
            (:func:`~rocking.model.records.paired_vertical`). A level of a study scales both components by the same
            factor; the intensity measures stay the horizontal record's (docs/model.md section 14). Default: none.

        Raises
        ------
        ParameterError
            A unit not known, or naming the file (and line) of the first one that cannot be read
            (:mod:`rocking.model.records`); vertical records not one per record, or of another dt than their
            horizontal record's, naming ``vertical_motions``.
        """
        items = [_path_and_unit(p, unit) for p in paths]
        if not 1 <= len(items) <= MAX_MOTIONS:
            raise ParameterError(f"a suite needs 1 to {MAX_MOTIONS} record files (got {len(items)})")
        verticals = _vertical_items(vertical_motions, unit, len(items))
        seen: dict[tuple, Path] = {}
        for k, (path, own) in enumerate(items):
            record = read_record(path, own)
            _warn_if_seen(seen, record, path)
            if verticals:
                paired_vertical(record, _read_vertical(*verticals[k]), _vertical_label(verticals[k][0]))
        return cls(
            files=tuple((str(p), file_sha256(p), own) for p, own in items),
            vertical_files=tuple((str(p), file_sha256(p), own) for p, own in verticals),
        )

    @classmethod
    def stochastic(
        cls, site: SiteModel, n: int, seed: int, vertical_ratio: float = 0.0, vertical_site: SiteModel | None = None
    ) -> Suite:
        """``n`` motions of the site model ``site`` drawn from ``seed`` (motion ``i`` is the same for any ``n``).

        ``vertical_ratio`` (in [0, 10]; default 0: none) gives each motion a vertical component, ``vertical_ratio``
        times a record of ``vertical_site`` (default: ``site``) of its own noise, > 0 up (docs/model.md section 14,
        :mod:`rocking.model.stochastic`); the horizontal motions are those without it.

        Raises
        ------
        ParameterError
            Naming the parameter: a site that is not a SiteModel, ``n`` or ``seed`` out of range, a ratio out of
            [0, 10], a vertical site without a ratio or of other sample times than ``site``'s.
        """
        if not isinstance(site, SiteModel):
            raise ParameterError(f"site must be a rocking.model.stochastic.SiteModel (got {type(site).__name__})")
        if not (isinstance(n, int) and not isinstance(n, bool) and 1 <= n <= MAX_MOTIONS):
            raise ParameterError(f"n must be an integer in [1, {MAX_MOTIONS}] (motions in a suite) (got {n!r})")
        if not (isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0):
            raise ParameterError(f"seed must be an integer >= 0 (got {seed!r})")
        ratio = check_in_range("vertical_ratio", vertical_ratio)
        if vertical_site is not None:
            if ratio == 0.0:
                raise ParameterError("vertical_site shapes the vertical component: give it with vertical_ratio > 0")
            check_vertical_site(site, vertical_site)
        return cls(site=site, seed=seed, n=n, vertical_ratio=ratio, vertical_site=vertical_site)

    @classmethod
    def from_pulses(cls, pulses) -> Suite:
        """The analytic pulses ``pulses`` (:class:`rocking.OneSinePulse`, :class:`rocking.OneCosinePulse`,
        :class:`rocking.RickerWavelet`, :class:`rocking.MavroeidisPapageorgiou`), each with its amplitude,
        frequency, shape and sign: the levels of a study scale their amplitudes."""
        pulses = tuple(pulses)
        if not 1 <= len(pulses) <= MAX_MOTIONS:
            raise ParameterError(f"a suite needs 1 to {MAX_MOTIONS} pulses (got {len(pulses)})")
        for i, pulse in enumerate(pulses):
            if family_of(pulse) == "sampled":
                raise ParameterError(f"pulses[{i}] is a SampledMotion: give records with Suite.from_files")
        return cls(pulses=pulses)

    def __len__(self) -> int:
        return len(self.files) or len(self.pulses) or self.n

    def name(self, i: int) -> str:
        """A label of motion ``i`` (:func:`motion_names`)."""
        return motion_names(self.record())[i]

    def motion(self, i: int):
        """Motion ``i``, made now: a :class:`SampledMotion`, or the pulse of a suite of pulses.

        Raises
        ------
        ParameterError
            If its file, or its vertical record's, changed since the suite was made.
        """
        if self.files:
            record = _unchanged(*self.files[i])
            if not self.vertical_files:
                return SampledMotion(record.acceleration, dt=record.dt)
            path = self.vertical_files[i][0]
            a_v = paired_vertical(record, _unchanged(*self.vertical_files[i]), _vertical_label(path))
            return SampledMotion(record.acceleration, dt=record.dt, a_v=a_v)
        if self.pulses:
            return self.pulses[i]
        site = self.site
        assert site is not None  # neither files nor pulses: a stochastic suite
        a = synthesize(site, record_rng(self.seed, i))
        if self.vertical_ratio == 0.0:
            return SampledMotion(a, dt=site.dt)
        a_v = self.vertical_ratio * synthesize(self.vertical_site or site, vertical_rng(self.seed, i))
        return SampledMotion(a, dt=site.dt, a_v=a_v)

    def record(self) -> dict:
        """JSON-ready description: the files and their hashes, the pulses, or the site model, seed and size."""
        if self.files:
            files: dict[str, Any] = {"files": [{"path": p, "sha256": d, "unit": u} for p, d, u in self.files]}
            if self.vertical_files:  # only then: the record, and the tiles, of a suite without stay as they were
                paired = [{"path": p, "sha256": d, "unit": u} for p, d, u in self.vertical_files]
                files["vertical"] = {"files": paired, "convention": "ddy_g > 0 up"}
            return files
        if self.pulses:
            return {
                "pulses": [
                    {"type": type(p).__name__, "family": describe(p).family, "T_g": p.T_g, **dataclasses.asdict(p)}
                    for p in self.pulses
                ]
            }
        site = self.site
        assert site is not None  # neither files nor pulses: a stochastic suite
        record: dict[str, Any] = {"stochastic": site.record(), "seed": self.seed, "n": self.n}
        if self.vertical_ratio > 0.0:  # only then: the record, and the tiles, of a suite without stay as they were
            vertical = (self.vertical_site or site).record()
            record["vertical"] = {"ratio": self.vertical_ratio, "site": vertical, "convention": "ddy_g > 0 up"}
        return record


def motion_names(record: dict) -> list[str]:
    """Labels of the motions of a suite from its :meth:`Suite.record`: each file's name,
    ``<family>-T<period in s>-<i>``, or ``stochastic-<seed>-<i>``."""
    if "files" in record:
        return [Path(f["path"]).name for f in record["files"]]
    if "pulses" in record:
        return [f"{p['family']}-T{p['T_g']:.4g}-{i}" for i, p in enumerate(record["pulses"])]
    return [f"stochastic-{record['seed']}-{i}" for i in range(record["n"])]


def vertical_names(record: dict) -> list[str] | None:
    """The names of the vertical record files of a suite from its :meth:`Suite.record`, one per motion; None
    for a suite without them."""
    files = record.get("vertical", {}).get("files")
    return None if files is None else [Path(f["path"]).name for f in files]


def _vertical_label(path) -> str:
    """How a message names a vertical record of a suite: by its option, ``vertical_motions``, and its file."""
    return f"vertical_motions {path}"


def _vertical_items(vertical_motions, unit: str | None, n: int) -> list[tuple[Path, str | None]]:
    """``(absolute path, unit)`` of each vertical record of :meth:`Suite.from_files`, one per record (none if
    ``vertical_motions`` is None)."""
    if vertical_motions is None:
        return []
    if isinstance(vertical_motions, str | os.PathLike):
        vertical_motions = [vertical_motions]
    items = [_path_and_unit(v, unit, "vertical_motions: ", "vertical_motions") for v in vertical_motions]
    if len(items) != n:
        raise ParameterError(
            f"vertical_motions must give one vertical record per record of motions, in their order "
            f"(got {len(items)} for {n})"
        )
    return items


def _read_vertical(path: Path, unit: str | None) -> Record:
    """The vertical record ``path``, a file that cannot be read refused naming ``vertical_motions``."""
    try:
        return read_record(path, unit)
    except ParameterError as exc:
        raise ParameterError(f"vertical_motions: {exc}") from None


def _unchanged(path: str, digest: str, unit: str | None) -> Record:
    """The record of a suite's file, refused if the file changed since the suite was made."""
    if file_sha256(Path(path)) != digest:
        raise ParameterError(f"{path}: changed since the suite was made (its SHA-256 differs)")
    return read_record(path, unit)


def _path_and_unit(item, unit: str | None, option: str = "", name: str = "motions") -> tuple[Path, str | None]:
    """``(absolute path, unit)`` of a path or a ``(path, unit)`` pair of :meth:`Suite.from_files`; ``option``
    begins the message of a unit not known, ``name`` (the keyword of the records) that of a ``FILE:UNIT``."""
    path, own = (item, unit) if isinstance(item, str | os.PathLike) else tuple(item)
    if own is not None and own not in UNITS:
        raise ParameterError(f"{option}unit of {path} must be one of {', '.join(UNITS)} (got {own!r})")
    _refuse_unknown_suffix(os.fspath(path), name)
    return Path(path).resolve(), own


def _refuse_unknown_suffix(path: str, name: str) -> None:
    """Refuse ``FILE:WORD``, no file, where ``FILE`` is one and ``WORD`` no unit: a unit mistyped, which
    :func:`split_unit` left in the path (a file whose name holds a colon exists, and passes)."""
    head, sep, word = path.rpartition(":")
    if sep and head and word not in UNITS and not Path(path).exists() and Path(head).is_file():
        # The message avoids the bare word "unit": the command line reads it as its --unit flag.
        raise ParameterError(f"{name} {path}: {word!r} is none of the units {', '.join(UNITS)} (and {path} is no file)")


def split_unit(text: str) -> tuple[str, str | None]:
    """``"b.txt:cm/s2"`` as ``("b.txt", "cm/s2")``: a record file of the command line and its own unit.

    Only a known unit (:data:`rocking.model.records.UNITS`) after the last ``:`` is one, so that a path holding a
    colon (``C:\\records\\a.AT2``) stays whole; ``("a.AT2", None)`` without one.
    """
    path, sep, unit = text.rpartition(":")
    return (path, unit) if sep and path and unit in UNITS else (text, None)


def of_pulses(pulses: str, periods, amplitude: float, gamma_mp: float | None = None, nu: float | None = None) -> Suite:
    """One pulse of the family ``pulses`` per period of ``periods`` (s), of amplitude ``amplitude`` (m/s^2), the
    MP pulses of oscillations ``gamma_mp`` (> 1) and phase ``nu`` (rad): each its class's ``from_period``."""
    family = pulses.replace("-", "_")
    if family not in PULSE_TYPES:
        raise ParameterError(f"pulses must be one of {', '.join(PULSE_TYPES)} (got {pulses!r})")
    if not periods:
        raise ParameterError(f"pulses {pulses} needs periods T... (s), one pulse per period")
    cls: Any = PULSE_TYPES[family][0]  # each family's class has its from_period
    fixed = PULSE_TYPES[family][1]
    shape = {k: v for k, v in (("gamma_mp", gamma_mp), ("nu", nu)) if v is not None}
    if family != "mp" and shape:
        raise ParameterError(f"gamma_mp and nu are the shape of pulses mp, not of pulses {pulses}")
    if family == "mp" and "gamma_mp" not in shape:
        raise ParameterError("pulses mp needs gamma_mp too (its oscillations, > 1)")
    return Suite.from_pulses([cls.from_period(amplitude, T, **fixed, **shape) for T in periods])


def suite_of(
    motions=None,
    *,
    unit: str | None = None,
    vertical_motions=None,
    stochastic: int | None = None,
    seed: int | None = None,
    site=None,
    pulses: str | None = None,
    periods=None,
    amplitude: float | None = None,
    gamma_mp: float | None = None,
    nu: float | None = None,
    vertical_ratio: float | None = None,
    vertical_site=None,
    g: float = 9.81,
) -> Suite:
    """The suite of a study from exactly one source, by the names of the command line's options.

    Parameters
    ----------
    motions : Suite, paths or (path, unit) pairs of records, or pulses, optional
        The motions themselves (:meth:`Suite.from_files`, :meth:`Suite.from_pulses`).
    unit : str, optional
        The unit of the record files given without their own.
    vertical_motions : paths or (path, unit) pairs of records, optional
        The vertical record of each record file of ``motions``, in their order (:meth:`Suite.from_files`).
    stochastic, seed, site : optional
        ``stochastic`` motions of the site model ``site`` (a :class:`~rocking.model.stochastic.SiteModel` or a
        mapping of its keywords over the defaults), from ``seed`` (default 0): :meth:`Suite.stochastic`.
    vertical_ratio, vertical_site : optional
        The stochastic motions' vertical component (:meth:`Suite.stochastic`); ``vertical_site`` a
        :class:`~rocking.model.stochastic.SiteModel` or a mapping of its keywords over the horizontal site's.
    pulses, periods, amplitude, gamma_mp, nu : optional
        A family of pulses (:func:`of_pulses`); ``amplitude`` default 1 g.
    g : float
        Gravity, m/s^2: the default amplitude of the pulses.

    Raises
    ------
    ParameterError
        None or several sources, or an option of another source.
    """
    sources = [k for k, v in (("motions", motions), ("stochastic", stochastic), ("pulses", pulses)) if v is not None]
    if not sources:
        raise ParameterError("a suite is needed: motions FILES..., stochastic N or pulses FAMILY")
    if len(sources) > 1:
        raise ParameterError(f"give one of motions FILES, stochastic N or pulses FAMILY (got {', '.join(sources)})")
    options = {"unit": unit, "vertical_motions": vertical_motions, "seed": seed, "site": site}
    options |= {"periods": periods, "amplitude": amplitude, "gamma_mp": gamma_mp, "nu": nu}
    options |= {"vertical_ratio": vertical_ratio, "vertical_site": vertical_site}
    foreign = [k for k, v in options.items() if v is not None and k not in OPTIONS_OF[sources[0]]]
    if foreign and sources[0] == "pulses":
        raise ParameterError(f"pulses makes its own suite: no {', '.join(foreign)}")
    if foreign:
        owners = [SOURCES[source] for source, names in OPTIONS_OF.items() if set(foreign) & set(names)]
        raise ParameterError(f"{', '.join(foreign)}: only with {' or '.join(owners)}")
    if pulses is not None:
        return of_pulses(pulses, periods, g if amplitude is None else amplitude, gamma_mp, nu)
    if stochastic is not None:
        horizontal = _site(site)
        vertical: dict[str, Any] = {"vertical_ratio": vertical_ratio} if vertical_ratio is not None else {}
        if vertical_site is not None:
            vertical["vertical_site"] = _site(vertical_site, horizontal)
        return Suite.stochastic(horizontal, stochastic, 0 if seed is None else seed, **vertical)
    return _motions(motions, unit, vertical_motions)


def _site(site, base: SiteModel | None = None) -> SiteModel:
    """A site model from None (the default), a SiteModel or a mapping of its keywords over the default's; over
    ``base``'s, its duration included, if given (a vertical site over the horizontal one)."""
    if site is None or isinstance(site, Mapping):
        over = {**DEFAULT_SITE.record(), "duration": None} if base is None else base.record()
        try:
            return SiteModel(**{**over, **(site or {})})
        except TypeError as exc:
            raise ParameterError(f"site: {exc} (keywords of rocking.model.stochastic.SiteModel)") from None
    return site


def _motions(motions, unit: str | None, vertical_motions=None) -> Suite:
    """A suite from a Suite, record files (paths or (path, unit) pairs, with their vertical records) or pulses
    (:mod:`rocking.model.motion`)."""
    if isinstance(motions, Suite):
        if vertical_motions is not None:
            raise ParameterError(
                "vertical_motions pairs record files: give them to Suite.from_files(..., vertical_motions=...)"
            )
        return motions
    if isinstance(motions, str | os.PathLike):
        motions = [motions]
    try:
        items = list(motions)
    except TypeError:
        raise ParameterError(
            f"motions must be a rocking.Suite, record files or pulses (got {type(motions).__name__})"
        ) from None
    if items and all(isinstance(m, str | os.PathLike | tuple | list) for m in items):
        return Suite.from_files(items, unit, vertical_motions)
    if vertical_motions is not None:
        raise ParameterError("vertical_motions pairs a vertical record with each record file: not with pulses")
    if unit is not None:
        raise ParameterError("unit is the unit of record files: give it with paths of records, not with pulses")
    return Suite.from_pulses(items)
