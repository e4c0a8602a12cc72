"""The memory of Hunt-Crossley pads along a recorded history (docs/model.md section 11).

A Hunt-Crossley pad's force depends on ``v_in``, the approach speed of its contact,
which the simulators hold in the regime of the stops (docs/simulation.md, rule 6) and
do not record. A history holds what it takes to find it again: its rows are in time
order with the events included (every change of a pad's regime ends a segment, and both
sides of a jump of the velocities are rows at the same instant). A side's memory is
``max(ddelta, floor)`` of the first row (the run's start) and of the row where a contact
starts: the first row with the side's penetration > 0 after one without, or the row where
a released pad pushes again with ``ddelta >= 0`` (the mass left the pad between two rows
and came back: a new contact). After a jump that changes ``ddelta`` with the mass in the
pad it is ``max(v_in, ddelta)``: a harder strike of the same contact is met at its own speed.
"""

from __future__ import annotations

import numpy as np


def memory(model, p, history: dict) -> list[np.ndarray]:
    """``v_in`` of each Hunt-Crossley side of ``model`` on every row of ``history``, in side order.

    Parameters
    ----------
    model : Model
        The model run.
    p : sequence of float
        Its parameters.
    history : dict
        The recorded rows, by state name, in time order with the events (``Response.history``).

    Returns
    -------
    list of ndarray
        One array per Hunt-Crossley side; none for a model without.
    """
    sides = model.manifest.get("stops", [])
    floors = [side["approach_floor"] if side["law"] == "hunt-crossley" else None for side in sides]
    if not any(f is not None for f in floors):
        return []
    y = [np.asarray(history[name], dtype=float) for name in model.state]
    t = np.asarray(history["t"], dtype=float)
    ones = np.ones_like(y[0])
    gaps = [np.asarray(g) for g in model.functions.stop_gaps(ones, *y, 0 * ones, 0 * ones, *p)]
    rates = [np.asarray(r, dtype=float) for r in model.functions.stop_approach(ones, *y, 0 * ones, 0 * ones, *p)]
    jump = np.concatenate(([False], t[1:] == t[:-1]))
    memories = [max(float(rates[i][0]), f) for i, f in enumerate(floors) if f is not None]
    out = [np.empty_like(t) for _ in memories]
    # The rows where a memory may change; the others keep it (rule 6).
    inside = [g > 0.0 for g in gaps]
    candidates = np.zeros(len(t), dtype=bool)
    for i, f in enumerate(floors):
        if f is None:
            continue
        entered = np.concatenate(([False], inside[i][1:] & ~inside[i][:-1]))
        turned = np.concatenate(([False], (rates[i][1:] >= 0.0) & (rates[i][:-1] < 0.0))) & inside[i]
        changed = jump & inside[i] & np.concatenate(([False], rates[i][1:] != rates[i][:-1]))
        candidates |= entered | turned | changed
    start = 0
    for row in np.flatnonzero(candidates).tolist():
        for j in range(len(memories)):
            out[j][start:row] = memories[j]
        memories = _next_memory(model, p, y, floors, gaps, rates, jump, row, memories)
        start = row
    for j in range(len(memories)):
        out[j][start:] = memories[j]
    return out


def _next_memory(model, p, y, floors, gaps, rates, jump, row: int, memories: list[float]) -> list[float]:
    """The memories from ``row`` on, given those before it (:func:`memory`'s rules)."""
    pushing = [_contacts(model, p, y, row - 1, floors, memories), _contacts(model, p, y, row, floors, memories)]
    out, j = list(memories), 0
    for i, floor in enumerate(floors):
        if floor is None:
            continue
        rate, inside = float(rates[i][row]), gaps[i][row] > 0.0
        if jump[row]:
            if inside and rate != rates[i][row - 1]:
                out[j] = max(out[j], rate)
        elif inside and (gaps[i][row - 1] <= 0.0 or (rate >= 0.0 and not pushing[0][i] and pushing[1][i])):
            out[j] = max(rate, floor)
        j += 1
    return out


def _contacts(model, p, y, row: int, floors, memories: list[float]) -> list[bool]:
    """Whether each side pushes at ``row`` with the given memories (its contact, generated ``stop_contact``, > 0)."""
    flags = tuple(0.0 for _ in floors)
    state = [float(v[row]) for v in y]
    contacts = model.functions.stop_contact(1.0, *state, 0.0, 0.0, *p, stop_on=flags + tuple(memories))
    return [float(c) > 0.0 for c in contacts]


class WithMemory:
    """The generated functions of ``model`` with the memory ``v_in`` of each row given.

    A function called without a regime takes the indicators of its state (each side pushes
    where its contact, read with the memory, is > 0); called with the indicators alone, it
    gets the memory appended. Models without memory get their functions as they are.
    """

    def __init__(self, model, v_in: list[np.ndarray]):
        self._functions = model.functions
        self._memory = tuple(v_in)
        self._n = int(model.manifest["functions"]["stop_gaps"]["outputs"])

    def __getattr__(self, name: str):
        function = getattr(self._functions, name)
        if not self._memory:
            return function

        def with_memory(*args, stop_on=None):
            if stop_on is None:
                off = tuple(np.zeros_like(self._memory[0]) for _ in range(self._n))
                shared = args[: len(self._functions.ARGUMENTS)]  # a friction function's own inputs come after
                contacts = self._functions.stop_contact(*shared, stop_on=off + self._memory)
                stop_on = tuple((np.asarray(c) > 0.0).astype(float) for c in contacts)
            return function(*args, stop_on=tuple(stop_on)[: self._n] + self._memory)

        return with_memory
