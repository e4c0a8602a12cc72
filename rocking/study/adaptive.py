"""Adaptive maps: a coarse lattice of cells, refined only where the outcome classes of neighbours differ.

An overturning map is made of a few regions of one outcome each (safe, overturned without impact, after one
impact, ...), and computing every cell spends most of its work inside them. An adaptive map refines like a
quadtree, on each part's (bare block, damped block) own classes:

1. it computes the corners of blocks of ``coarse x coarse`` cells (``coarse`` a power of two; the last block
   of each axis is clipped to the grid, so any grid size works);
2. a block whose computed cells (its corners, and any cell of its edges that a refined neighbour computed)
   all share one class is a *leaf*; any other block is split in four, and the corners of the halves (its
   edge midpoints and centre) are computed next. A leaf that later sees a cell of another class on its
   edges is split too; this goes on down to blocks one cell wide, whose cells are all computed;
3. at the end, the cells of each leaf that were not computed take its class.

Each round of corners is one batch of tiles for :func:`rocking.study.tiles.run_tiles` (resumable, on local
workers or Dask): which cells a round computes follows from the classes found before, so a rerun of the same
configuration asks for the same tiles and loads them.

The class of a response is its outcome (:func:`rocking.study.overturning_map.outcome`: safe, or the impacts
before overturning) or, for a response without a verdict (status ``max_events``, ``max_steps``), a class of
its own (:func:`rocking.study.overturning_map.response_classes`), so that such responses are never filled
in. A cell's class is the classes of all the directions of its pulse together: the per-direction outcomes
are complete too.

Without more, an adaptive map misses a feature of another class that falls entirely between the computed
cells of a leaf: an island, or a tongue or band narrower than the coarse step. So, once every block is a leaf,
a *verification* (``verify``, a power of two, the coarse step by default; 0: none) samples the leaves:

4. round after round, of step ``s`` = ``verify``, ``verify / 2``, ..., 2, it computes the cells of the lattice
   offset by half a step from the corners, ``(s/2 + a s, s/2 + b s)``, and of the grid's edges (where no block
   lies beyond) at ``s/2 + a s``: the first round everywhere, with every cell of the edges of the coarse blocks
   (the rows and columns of every ``coarse``-th index, :func:`line_mask`), the next ones within ``max(s, HALO)``
   cells of a class boundary of the map so far and within twice that of a *hit* (a cell whose class its leaf
   did not have). A leaf that holds a hit is split and refined as in step 2 before the next round;
5. then rounds of step 1 compute every cell next to a class boundary, until one finds no hit.

What a verified map guarantees: every region of one class that extends over ``coarse`` cells or more along
``Omega`` or ``beta`` holds a computed cell (its indices along that axis are consecutive, and any ``coarse`` of
them hold an edge of the blocks), and so does every region that holds a square of ``verify x verify`` cells
(any ``verify`` consecutive indices hold one of the first lattice); such a region is found, and traced: rounds
of step 1 end only when every boundary between classes of the result lies between two computed cells, so a
region found is found whole, however thin (a filament one cell wide and many long, issue 35). A region
smaller than that, inside one coarse block, is found if it lies near a boundary found before (within ``max(s,
HALO)`` cells, holding an ``s x s`` square); one smaller and farther away can be missed: the summary counts the
cells of each class that were inferred, not computed (:func:`rocking.study.overturning_map.inferred_counts`).
That bound is deterministic, not statistical; how often the rest happens is measured (bench/adaptive.py).
The edges cost ``2 / coarse`` of the grid. ``coarse=1`` (or a full map) computes every cell.
"""

from __future__ import annotations

from itertools import product

import numpy as np

from ..model.params import ParameterError
from .config import is_count

#: Default coarse step of an adaptive map, cells: on the 400 x 400 bench maps, the full map's classification from
#: about a fifth of its responses, the edges of the blocks verified (bench/adaptive.py).
COARSE = 16

#: Largest coarse step: a block of more cells than a grid has values is the whole grid already.
MAX_COARSE = 2**17


def check_coarse(coarse) -> int:
    """``coarse`` as an int, or a ParameterError unless it is a power of two in [1, :data:`MAX_COARSE`]."""
    ok = is_count(coarse) and 1 <= coarse <= MAX_COARSE and (int(coarse) & (int(coarse) - 1)) == 0
    if not ok:
        raise ParameterError(f"coarse must be a power of two (1, 2, 4, ...) in [1, {MAX_COARSE}] (got {coarse!r})")
    return int(coarse)


def check_verify(verify, coarse: int) -> int:
    """``verify`` as an int, or a ParameterError unless it is 0 (no verification) or a power of two in
    [1, ``coarse``]: the first step of the verification's offset lattice."""
    ok = is_count(verify) and (verify == 0 or 1 <= verify <= coarse and (int(verify) & (int(verify) - 1)) == 0)
    if not ok:
        raise ParameterError(f"verify must be 0 or a power of two in [1, coarse = {coarse}] (got {verify!r})")
    return int(verify)


def near(shape: tuple[int, int], rows: np.ndarray, cols: np.ndarray, radius) -> np.ndarray:
    """The cells of a ``shape`` grid within ``radius`` cells, along each axis, of any cell ``(rows, cols)``;
    ``radius`` an int, or one per axis: the maximum filter of the cells given over a window of ``2 radius + 1``
    cells, one axis at a time, in NumPy (scipy.ndimage's costs a command 0.25 s of CPU to import)."""
    hit = np.zeros(shape, bool)
    hit[rows, cols] = True
    for axis, r in enumerate(np.broadcast_to(radius, 2)):
        hit = _within(hit, int(r), axis)
    return hit


def _within(hit: np.ndarray, radius: int, axis: int) -> np.ndarray:
    """The cells within ``radius`` cells of a cell of ``hit`` along ``axis`` (none beyond the grid's edges)."""
    n = hit.shape[axis]
    # before[k]: the cells of hit before index k along the axis; a window's count is a difference of two.
    before = np.concatenate(
        [np.zeros_like(hit.take([0], axis), dtype=np.int64), np.cumsum(hit, axis, dtype=np.int64)], axis
    )
    i = np.arange(n)
    return before.take(np.minimum(i + radius + 1, n), axis) > before.take(np.maximum(i - radius, 0), axis)


#: Cells around a class boundary that every verification round of a step of 2 or more searches: rocking maps
#: scatter slivers of other outcomes near their boundaries (a 1 x 4 sliver 3 cells from one on a 400 x 400
#: map of a cosine pulse with stops, issue 25), farther than the fine steps' own reach.
HALO = 4


def halo(step: int) -> int:
    """The cells around the class boundaries that a verification round of ``step`` searches: ``max(step,
    HALO)``, and 1 at step 1, which computes every cell there; twice that around the hits of the round."""
    return max(step, HALO) if step > 1 else 1


def offset_lattice(n: int, step: int) -> np.ndarray:
    """The indices ``step // 2 + a step`` of an axis of ``n`` values, and its two ends: the lattice of the
    verification, half a step off the corners of the blocks, and along the grid's edges, where no block lies
    beyond."""
    return np.unique(np.concatenate([np.arange(step // 2, n, step), [0, n - 1]]))


def line_mask(shape: tuple[int, int], step: int) -> np.ndarray:
    """The cells of a ``shape`` grid on the lines of every ``step``-th index of either axis and on its last
    (the edges of the blocks of ``step`` cells): a region that extends over ``step`` cells or more along an axis
    holds one (its indices along that axis are consecutive, and ``step`` of them hold a multiple of ``step``)."""
    mask = np.zeros(shape, bool)
    for axis, n in enumerate(shape):
        lines = np.unique(np.append(np.arange(0, n, step), n - 1))
        mask[(slice(None),) * axis + (lines,)] = True
    return mask


def boundary(classes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns of the cells of ``classes`` (``(n, m, k)``) whose class differs from a neighbour's."""
    differ = np.zeros(classes.shape[:2], bool)
    rows = (classes[1:] != classes[:-1]).any(axis=-1)
    cols = (classes[:, 1:] != classes[:, :-1]).any(axis=-1)
    differ[1:] |= rows
    differ[:-1] |= rows
    differ[:, 1:] |= cols
    differ[:, :-1] |= cols
    return np.nonzero(differ)


def guarantee(refinement: dict, spacing: tuple[float, float], every_cell: bool = False) -> str:
    """What a map of ``refinement`` (its ``config["refinement"]``) can miss, in cells and in the largest grid
    ``spacing`` (``(dOmega, dbeta)``): the deterministic bound of :class:`Refinement`, no statistical one.
    ``refinement["edges"]``: whether the verification computed the edges of the coarse blocks (maps of
    earlier versions did not).

    ``every_cell``: whether the adaptive map computed every cell (a grid its refinement covered whole); its
    bound in cells would then speak of regions larger than the grid, so the text says that nothing was missed.
    """
    if not refinement["adaptive"]:
        return "full map: every cell computed"
    if every_cell:
        return "every cell computed (the refinement covered the whole grid): nothing missed"
    size, coarse = refinement["verify"] or refinement["coarse"], refinement["coarse"]
    extent = f"{size} x {size} cells ({size * spacing[0]:.3g} in Omega x {size * spacing[1]:.3g} in beta)"
    if not refinement["verify"]:
        return f"unverified: a region of another class inside {extent} can be missed"
    smaller = "is found, whole; smaller ones only near class boundaries"
    if not refinement.get("edges"):  # a map of an earlier version: a verification of points only
        return f"every region of one class holding {extent} {smaller}"
    reach = (
        f"{coarse} cells along Omega or beta ({coarse * spacing[0]:.3g} in Omega, {coarse * spacing[1]:.3g} in beta)"
    )
    held = "" if size == coarse else f", or holding {extent},"
    return f"every region of one class extending over {reach}{held} {smaller}"


def _spans(n: int, step: int) -> list[tuple[int, int]]:
    """First and last index of the blocks of ``step`` cells along an axis of ``n`` values, the last clipped."""
    return [(start, min(start + step, n - 1)) for start in range(0, max(n - 1, 1), step)]


def split(blocks: np.ndarray) -> np.ndarray:
    """The halves of each block of ``blocks`` (``(B, 4)``) along each axis where it is more than one step wide:
    four blocks, or two, or the block itself; the halves share the middle index."""
    i0, i1, j0, j1 = blocks.T
    im, jm = (i0 + i1) // 2, (j0 + j1) // 2
    rows, cols = i1 - i0 > 1, j1 - j0 > 1
    im, jm = np.where(rows, im, i1), np.where(cols, jm, j1)
    quarters = [
        (np.ones_like(rows), (i0, im, j0, jm)),
        (rows, (im, i1, j0, jm)),
        (cols, (i0, im, jm, j1)),
        (rows & cols, (im, i1, jm, j1)),
    ]
    return np.concatenate([np.stack(corners, axis=1)[keep] for keep, corners in quarters]).reshape(-1, 4)


def _box_sums(values: np.ndarray, blocks: np.ndarray) -> np.ndarray:
    """The sum of ``values`` (``(n, m)``) over each block of ``blocks`` (``(B, 4)``, last indices included)."""
    table = np.zeros((values.shape[0] + 1, values.shape[1] + 1), np.int64)
    np.cumsum(values, axis=0, out=table[1:, 1:])
    np.cumsum(table[1:, 1:], axis=1, out=table[1:, 1:])
    i0, i1, j0, j1 = blocks.T
    return table[i1 + 1, j1 + 1] - table[i0, j1 + 1] - table[i1 + 1, j0] + table[i0, j0]


class Refinement:
    """The refinement of one part of a map: which cells are computed, their classes, its blocks.

    Parameters
    ----------
    shape : (int, int, int)
        Omega values, beta values, classes per cell (one per direction of the pulse).
    coarse : int
        The coarse step, a power of two (:func:`check_coarse`).
    verify : int, optional
        The first step of the verification (:func:`check_verify`); 0 (default): none.

    Attributes
    ----------
    computed : ndarray of bool, ``shape[:2]``
        The cells computed so far.
    classes : ndarray of int, ``shape``
        Their classes (:func:`rocking.study.overturning_map.response_classes`); after :meth:`fill`, every
        cell's.
    active : ndarray of int, ``(B, 4)``
        Blocks of cells (each the first and last index along Omega, then along beta, all included) whose
        corners are computed next (:meth:`pending`), then judged (:meth:`update`).
    leaves : ndarray of int, ``(L, 4)``
        Blocks whose computed cells share one class.
    step : int
        The step of the next verification round; 0 once the verification is over.
    suspect : ndarray of bool, ``shape[:2]``
        Where the next verification round looks besides the class boundaries: everywhere at first, then
        around the hits of the round before.
    probes : (rows, cols, classes) or None
        The cells of the verification round under way and the classes their leaves gave them.
    """

    def __init__(self, shape: tuple[int, int, int], coarse: int, verify: int = 0) -> None:
        n, m, k = shape
        self.computed = np.zeros((n, m), bool)
        self.classes = np.zeros((n, m, k), np.int64)
        spans = [(r, c) for r, c in product(_spans(n, coarse), _spans(m, coarse))]
        self.active = np.array([(*r, *c) for r, c in spans], np.int64).reshape(-1, 4)
        self.leaves = np.zeros((0, 4), np.int64)
        self.step = check_verify(verify, coarse)
        self.suspect = np.ones((n, m), bool)
        self.lines = coarse if self.step >= 1 else 0
        self.probes: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    @property
    def done(self) -> bool:
        """Whether every block is a leaf and the verification is over: nothing left to compute."""
        return not len(self.active) and self.step < 1

    def pending(self) -> tuple[np.ndarray, np.ndarray]:
        """Rows and columns of the cells to compute next, in sorted order: the corners of the active blocks not
        computed yet or, once every block is a leaf, the probes of the verification (:meth:`verification`)."""
        if not len(self.active) and self.step >= 1:
            return self.verification()
        blocks = self.active
        rows = np.concatenate([blocks[:, 0], blocks[:, 0], blocks[:, 1], blocks[:, 1]])
        cols = np.concatenate([blocks[:, 2], blocks[:, 3], blocks[:, 2], blocks[:, 3]])
        return self._new(np.ravel_multi_index((rows, cols), self.computed.shape))

    def _new(self, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The cells (flat indices) not computed yet, once each, sorted, as rows and columns."""
        cells = np.unique(cells)
        cells = cells[~self.computed.ravel()[cells]]
        return np.unravel_index(cells, self.computed.shape)

    def verification(self) -> tuple[np.ndarray, np.ndarray]:
        """The probes of one verification round: the cells of the lattice offset by half the step,
        ``(step // 2 + a step, step // 2 + b step)``, that lie in the suspect region and were not computed.

        Each probe's class, as the leaves would fill it in, is kept: :meth:`update` compares the computed one.
        """
        n, m = self.computed.shape
        rows, cols = np.meshgrid(offset_lattice(n, self.step), offset_lattice(m, self.step), indexing="ij")
        cells = np.ravel_multi_index((rows.ravel(), cols.ravel()), (n, m))
        filled = self.leaf_classes()
        suspect = self.suspect | near(self.computed.shape, *boundary(filled), halo(self.step))
        cells = cells[suspect.ravel()[cells]]
        if self.lines:  # the first round: the edges of the coarse blocks too
            cells = np.concatenate([cells, np.flatnonzero(line_mask((n, m), self.lines))])
            self.lines = 0
        rows, cols = self._new(cells)
        self.probes = (rows, cols, filled[rows, cols])
        return rows, cols

    def record(self, rows, cols, classes) -> None:
        """The classes (``(cells, k)``) of the computed cells ``(rows, cols)``."""
        self.computed[rows, cols] = True
        self.classes[rows, cols] = classes

    def uniform(self, blocks: np.ndarray) -> np.ndarray:
        """Whether the computed cells of each block (``(B, 4)``, corners computed) share its first corner's class.

        Exact, in integers: for the ``t`` computed values ``x`` of a block and its corner's ``c``,
        ``sum((x - c)**2) = sum(x**2) - 2 c sum(x) + t c**2`` is 0 only if every ``x`` is ``c``.
        """
        count = _box_sums(self.computed, blocks)
        same = np.ones(len(blocks), bool)
        for k in range(self.classes.shape[-1]):
            x = np.where(self.computed, self.classes[..., k], 0)
            c = self.classes[blocks[:, 0], blocks[:, 2], k]
            same &= _box_sums(x * x, blocks) - 2 * c * _box_sums(x, blocks) + count * c * c == 0
        return same

    def update(self) -> None:
        """Judge the active blocks and the leaves once their corners (or probes) are computed: a block whose
        computed cells share one class is (or stays) a leaf; another is split, unless all its cells are computed.

        After a verification round, probes of a class their leaf did not give are *hits*: the next round, once
        the blocks split around them are leaves again, verifies at half the step (:func:`halo`) near the
        boundaries and the hits; rounds of step 1 repeat until one finds no hit, which ends the verification.
        """
        if self.probes is not None:
            rows, cols, expected = self.probes
            hits = (self.classes[rows, cols] != expected).any(axis=1)
            self.suspect = near(self.computed.shape, rows[hits], cols[hits], 2 * halo(self.step))
            self.step = self.step // 2 if self.step > 1 else 1 if hits.any() else 0
            self.probes = None
        blocks = np.concatenate([self.active, self.leaves])
        blocks = blocks[(blocks[:, 1] - blocks[:, 0] > 1) | (blocks[:, 3] - blocks[:, 2] > 1)]
        same = self.uniform(blocks)
        self.leaves, self.active = blocks[same], split(blocks[~same])

    def fill(self) -> np.ndarray:
        """Give the cells of each leaf that were not computed its class; the mask of those cells.

        The leaves that hold a cell agree on its class: two leaves share at most a stretch of an edge, and
        the corners of the smaller one, computed, lie on that stretch.
        """
        filled = ~self.computed
        self.classes = self.leaf_classes()
        return filled

    def leaf_classes(self) -> np.ndarray:
        """The class of every cell: its own where computed, else its leaf's (a copy of :attr:`classes`).

        Raises
        ------
        AssertionError
            If a cell is neither computed nor in a leaf (every block is a leaf only once :attr:`active` is empty).
        """
        i0, i1, j0, j1 = self.leaves.T
        heights, widths = i1 - i0 + 1, j1 - j0 + 1
        areas = heights * widths
        leaf = np.repeat(np.arange(len(self.leaves)), areas)
        local = np.arange(areas.sum()) - np.repeat(np.cumsum(areas) - areas, areas)
        rows, cols = i0[leaf] + local // widths[leaf], j0[leaf] + local % widths[leaf]
        new = ~self.computed[rows, cols]
        classes, covered = self.classes.copy(), self.computed.copy()
        covered[rows, cols] = True
        classes[rows[new], cols[new]] = self.classes[i0, j0][leaf[new]]
        if not covered.all():
            raise AssertionError("adaptive map: a cell is neither computed nor in a leaf")
        return classes


def refine(classify, shape: tuple[int, int, int], coarse: int, verify: int = 0) -> tuple[np.ndarray, np.ndarray, int]:
    """The classes of every cell of a map, computed adaptively (:class:`Refinement`): the whole refinement of
    one part, for a ``classify`` that computes cells at once (a map runs both parts' rounds as tiles instead).

    Parameters
    ----------
    classify : callable
        ``classify(rows, cols)`` -> the classes (``(cells, shape[2])``, int) of the cells ``(rows[i], cols[i])``;
        called once per round.
    shape : (int, int, int)
        Omega values, beta values, classes per cell.
    coarse, verify : int
        The coarse step (:func:`check_coarse`) and the first step of the verification (:func:`check_verify`).

    Returns
    -------
    classes : ndarray of int, ``shape``
        The class of every cell.
    computed : ndarray of bool, ``shape[:2]``
        The cells computed.
    rounds : int
        Calls of ``classify``.
    """
    refinement, rounds = Refinement(shape, coarse, verify), 0
    while not refinement.done:
        rows, cols = refinement.pending()
        if rows.size:
            refinement.record(rows, cols, classify(rows, cols))
            rounds += 1
        refinement.update()
    refinement.fill()
    return refinement.classes, refinement.computed, rounds
