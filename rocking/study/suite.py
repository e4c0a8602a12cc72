"""A suite of ground motions for incremental dynamic analysis and fragility: record files, the stochastic
model, or analytic pulses.

A suite is a recipe, not the motions: :meth:`Suite.motion` builds motion ``i`` where it is
used (in a tile, on any worker), so a study of thousands of motions holds one at a time.
Files are read once when the suite is made, to refuse a bad file at once and to record its
SHA-256; a file changed afterwards is refused when a tile reads it. A stochastic motion
is drawn from the ``i``-th child of its seed (:func:`rocking.model.stochastic.record_rng`).
A suite of pulses holds the pulses themselves (a few numbers each): near-fault motions
of uncertain period, say, for a fragility against the pulse's amplitude.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

from ..model.motion import SampledMotion, describe, family_of
from ..model.params import ParameterError
from ..model.records import UNITS, file_sha256, read_record
from ..model.stochastic import SiteModel, record_rng, synthesize

#: Largest number of motions in a suite.
MAX_MOTIONS = 100_000


@dataclass(frozen=True)
class Suite:
    """Ground motions for a study, made one at a time by :meth:`motion`.

    Use :meth:`from_files` or :meth:`stochastic`.

    Attributes
    ----------
    files : tuple of (str, str)
        Absolute path and SHA-256 of each record file (empty for a stochastic suite).
    unit : str or None
        The unit of the accelerations of column files (``.AT2`` files are in g); None: the one each header states.
    site : SiteModel or None
        The stochastic model (None for files).
    seed, n : int
        The seed and the number of motions of a stochastic suite.
    pulses : tuple
        The analytic pulses of a suite of pulses (:meth:`from_pulses`).
    """

    files: tuple = ()
    unit: str | None = None
    site: SiteModel | None = None
    seed: int = 0
    n: int = 0
    pulses: tuple = ()

    @classmethod
    def from_files(cls, paths, unit: str | None = None) -> Suite:
        """The records of ``paths`` (``.AT2``, or columns of time and acceleration in ``unit`` or the unit their
        header states), each read now.

        Raises
        ------
        ParameterError
            Naming the file (and line) of the first one that cannot be read (:mod:`rocking.model.records`).
        """
        paths = [Path(p).resolve() for p in paths]
        if not 1 <= len(paths) <= MAX_MOTIONS:
            raise ParameterError(f"a suite needs 1 to {MAX_MOTIONS} record files (got {len(paths)})")
        if unit is not None and unit not in UNITS:
            raise ParameterError(f"unit must be one of {', '.join(UNITS)} (got {unit!r})")
        for path in paths:
            read_record(path, unit)
        return cls(files=tuple((str(p), file_sha256(p)) for p in paths), unit=unit)

    @classmethod
    def stochastic(cls, site: SiteModel, n: int, seed: int) -> Suite:
        """``n`` motions of the site model ``site`` drawn from ``seed`` (motion ``i`` is the same for any ``n``)."""
        if not isinstance(site, SiteModel):
            raise ParameterError(f"site must be a rocking.model.stochastic.SiteModel (got {type(site).__name__})")
        if not (isinstance(n, int) and not isinstance(n, bool) and 1 <= n <= MAX_MOTIONS):
            raise ParameterError(f"n must be an integer in [1, {MAX_MOTIONS}] (motions in a suite) (got {n!r})")
        if not (isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0):
            raise ParameterError(f"seed must be an integer >= 0 (got {seed!r})")
        return cls(site=site, seed=seed, n=n)

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
            If its file changed since the suite was made.
        """
        if self.files:
            path, digest = self.files[i]
            if file_sha256(Path(path)) != digest:
                raise ParameterError(f"{path}: changed since the suite was made (its SHA-256 differs)")
            record = read_record(path, self.unit)
            return SampledMotion(record.acceleration, dt=record.dt)
        if self.pulses:
            return self.pulses[i]
        return SampledMotion(synthesize(self.site, record_rng(self.seed, i)), dt=self.site.dt)

    def record(self) -> dict:
        """JSON-ready description: the files and their hashes, the pulses, or the site model, seed and size."""
        if self.files:
            return {"files": [{"path": p, "sha256": d} for p, d in self.files], "unit": self.unit}
        if self.pulses:
            return {
                "pulses": [
                    {"type": type(p).__name__, "family": describe(p).family, "T_g": p.T_g, **dataclasses.asdict(p)}
                    for p in self.pulses
                ]
            }
        return {"stochastic": self.site.record(), "seed": self.seed, "n": self.n}


def motion_names(record: dict) -> list[str]:
    """Labels of the motions of a suite from its :meth:`Suite.record`: each file's name,
    ``<family>-T<period in s>-<i>``, or ``stochastic-<seed>-<i>``."""
    if "files" in record:
        return [Path(f["path"]).name for f in record["files"]]
    if "pulses" in record:
        return [f"{p['family']}-T{p['T_g']:.4g}-{i}" for i, p in enumerate(record["pulses"])]
    return [f"stochastic-{record['seed']}-{i}" for i in range(record["n"])]
