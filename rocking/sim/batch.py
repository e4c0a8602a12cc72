"""What a batch of runs is given: :class:`Cases`, one row per run of one model, from rest.

The batch counterpart of :class:`~rocking.sim.problem.Problem`, checked against the same table
(:data:`rocking.sim.boundary.CASE`); the cases of a batch share the arrays of a motion
(:class:`Packed`): one buffer of samples for every scale, not a copy per case. Built by
:mod:`rocking.sim.cases`, run by a back end (:mod:`rocking.sim.backends`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..model.floor import check_pair
from ..model.loading import Model
from ..model.motion import FAMILIES
from ..model.params import ParameterError
from . import boundary
from .boundary import CASE, DOUBLES, SERIES
from .problem import Problem, check_motion


@dataclass(frozen=True)
class Packed:
    """The arrays of one :data:`~rocking.sim.boundary.SERIES` setting over a batch, in one buffer.

    Case ``i``'s array starts at ``buffer[offset[i]]`` (its length is the setting's count): cases
    that share an array point to the same values, none is copied per case.

    Attributes
    ----------
    buffer : ndarray
        The values, 1-D, C-contiguous.
    offset : ndarray of int64
        Where each case's array starts.
    """

    buffer: np.ndarray
    offset: np.ndarray

    @classmethod
    def shared(cls, array, n: int) -> Packed:
        """One array (or ``None``: none) shared by ``n`` cases."""
        buffer = np.zeros(0) if array is None else np.ascontiguousarray(array, dtype=float).reshape(-1)
        return cls(buffer, np.zeros(n, dtype=np.int64))

    @classmethod
    def of(cls, arrays) -> Packed:
        """The arrays of the cases (``None`` where a case has none), each distinct array object stored once."""
        start, parts, offset, size = {}, [], [], 0
        for a in arrays:
            if a is not None and id(a) not in start:
                start[id(a)] = size
                parts.append(np.asarray(a, dtype=float).reshape(-1))
                size += parts[-1].size
            offset.append(0 if a is None else start[id(a)])
        return cls(np.concatenate(parts) if parts else np.zeros(0), np.array(offset, dtype=np.int64))

    def row(self, i: int, count: int) -> np.ndarray | None:
        """Case ``i``'s array of ``count`` values (a view), ``None`` if it has none."""
        return self.buffer[self.offset[i] : self.offset[i] + count] if count else None

    def pointers(self) -> np.ndarray:
        """The address of each case's array (0, C's NULL, for an empty buffer)."""
        if self.buffer.size == 0:
            return np.zeros(len(self.offset), dtype=np.uintp)
        return (self.buffer.ctypes.data + self.buffer.itemsize * self.offset).astype(np.uintp)


def _packed(name: str, value, counts: np.ndarray) -> Packed:
    """A SERIES setting of a batch as :class:`Packed`, checked: every case's array inside the buffer, finite."""
    n = len(counts)
    packed = value if isinstance(value, Packed) else Packed.shared(value, n)
    offset = np.asarray(packed.offset, dtype=np.int64)
    buffer = np.ascontiguousarray(packed.buffer, dtype=float).reshape(-1)
    if offset.shape != (n,) or np.any(offset < 0) or np.any(offset + counts > buffer.size):
        raise ParameterError(f"cases: {name} must hold n_{name} values for every case (buffer of {buffer.size})")
    if not np.all(np.isfinite(buffer)):
        raise ParameterError(f"cases: {name} must be finite: {name}[{np.flatnonzero(~np.isfinite(buffer))[0]}] is not")
    return Packed(buffer, offset)


@lru_cache(maxsize=1024)
def _check_one(name: str, value: float) -> None:
    """:func:`~rocking.sim.boundary.check` of the setting ``name`` holding ``value`` in every case, remembered when
    it passes (an exception is not cached: a value out of range raises each time)."""
    boundary.check(name, np.array([value]))


def _checked(name: str, array: np.ndarray, column: np.ndarray) -> np.ndarray:
    """``column``, the setting ``name`` broadcast from ``array`` to every case, if it passes its check.

    Most settings of a batch are one number for every case, the same from one batch to the next: a study builds
    thousands of small batches, and checking each of their columns anew cost about as much as building them. One
    number is checked once per process (the check is elementwise: one value passes as a column of it does, and
    fails with the same message); an empty column has nothing to check.
    """
    if array.ndim == 0 and column.size:
        _check_one(name, float(array))
        return column
    return boundary.check(name, column)


@dataclass(frozen=True)
class Cases:
    """Resolved inputs of ``n`` runs of one model, from rest: one row per run.

    Attributes
    ----------
    model : Model
        The generated model.
    p : ndarray, shape (n, np)
        Parameters in the model's order.
    settings : dict of ndarray
        Every field of :data:`rocking.sim.boundary.CASE` but ``y0`` by name:
        shape ``(n,)``, or ``(n, ny)`` for ``atol``; a :class:`Packed` (or one
        array shared by every case, or ``None``) for ``samples`` and ``extrema``.
        A field with a default may be left out. Checked on construction against
        the table's ranges.
    """

    model: Model
    p: np.ndarray
    settings: dict

    def __post_init__(self) -> None:
        p = np.asarray(self.p, dtype=float)
        width = len(self.model.parameters)
        if p.ndim != 2 or p.shape[1] != width:
            raise ParameterError(
                f"cases: p must have shape (n, {width}), one column per parameter "
                f"{tuple(self.model.parameters)} (got shape {p.shape})"
            )
        n = len(p)
        columns: dict = {}  # the checked columns, then the Packed series
        for f in CASE:
            if f.name == "y0" or f.kind == SERIES:
                continue
            value = self.settings.get(f.name, None if f.required else f.default)
            if value is None:
                raise ParameterError(f"cases: the setting {f.name} is missing")
            shape = (n, len(self.model.state)) if f.kind == DOUBLES else (n,)
            try:
                array = np.asarray(value, dtype=float)
                column = np.ascontiguousarray(np.broadcast_to(array, shape))
            except ValueError:
                raise ParameterError(
                    f"cases: {f.name} must broadcast to shape {shape} (got {np.shape(value)})"
                ) from None
            columns[f.name] = _checked(f.name, array, column)
        for f in CASE:
            if f.kind == SERIES:
                columns[f.name] = _packed(f.name, self.settings.get(f.name), columns[f.count].astype(np.int64))
        for code in np.unique(columns["motion"]).astype(int):
            at = columns["motion"] == code
            check_motion(FAMILIES[code], columns["n_samples"][at], columns["pulse_dt"][at], columns["n_extrema"][at])
        check_pair(columns["mu_s"], columns["mu_k"])
        unknown = sorted(set(self.settings) - set(columns))
        if unknown:
            raise ParameterError(f"cases: unknown setting(s) {', '.join(unknown)}")
        if np.any(~np.isfinite(columns["atol"]) | (columns["atol"] < 0)):
            raise ParameterError("atol must be finite and >= 0")
        object.__setattr__(self, "p", np.ascontiguousarray(p))
        object.__setattr__(self, "settings", columns)

    def __len__(self) -> int:
        return len(self.p)

    def problem(self, i: int) -> Problem:
        """Case ``i`` as a :class:`Problem` (for the NumPy back end)."""
        settings = {}
        for f in CASE:
            if f.kind == SERIES:
                settings[f.name] = self.settings[f.name].row(i, int(self.settings[f.count][i]))
            elif f.name != "y0":
                settings[f.name] = self.settings[f.name][i]
        return Problem(model=self.model, p=self.p[i], **settings)

    @classmethod
    def of(cls, problems) -> Cases:
        """The problems of one model, from rest, as one batch.

        Raises
        ------
        ParameterError
            If the list is empty, the problems differ in model, or one starts
            elsewhere than at rest.
        """
        problems = list(problems)
        if not problems:
            raise ParameterError("no problems given")
        folders = {pr.model.folder for pr in problems}
        if len(folders) > 1:
            raise ParameterError(f"a batch needs one model for all problems (got {sorted(str(f) for f in folders)})")
        if any(pr.y0 is not None for pr in problems):
            raise ParameterError("a batch runs from rest: y0 must be None in every problem")
        settings = {
            f.name: Packed.of([getattr(pr, f.name) for pr in problems])
            if f.kind == SERIES
            else np.array([getattr(pr, f.name) for pr in problems])
            for f in CASE
            if f.name != "y0"
        }
        return cls(problems[0].model, np.array([pr.p for pr in problems]), settings)
