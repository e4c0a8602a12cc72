"""The memory of Hunt-Crossley pads along a recorded history (docs/model.md section 11).

A Hunt-Crossley pad's force depends on ``v_in``, the approach speed of its contact,
which the simulators hold in the regime of the stops (docs/simulation.md, rule 6) and
do not record. A history holds what it takes to find it again: its rows are in time
order with the events included, so the row of a new contact is the first row with the
side's penetration > 0 after one without, the state on the side after the gap's
closing where the simulator recorded it. From there to the next such row the side's
memory is ``max(ddelta, floor)`` of that row; before any contact, that of the first
row (the run's start).
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
    floors = [side["approach_floor"] for side in model.manifest.get("stops", []) if side["law"] == "hunt-crossley"]
    if not floors:
        return []
    y = [np.asarray(history[name], dtype=float) for name in model.state]
    ones = np.ones_like(y[0])
    sides = model.manifest.get("stops", [])
    gaps = model.functions.stop_gaps(ones, *y, 0 * ones, 0 * ones, *p)
    rates = model.functions.stop_approach(ones, *y, 0 * ones, 0 * ones, *p)
    out = []
    for side, gap, rate in zip(sides, gaps, rates):
        if side["law"] != "hunt-crossley":
            continue
        inside = np.asarray(gap) > 0.0
        starts = np.concatenate(([True], inside[1:] & ~inside[:-1]))
        last = np.maximum.accumulate(np.where(starts, np.arange(len(starts)), 0))
        out.append(np.maximum(np.asarray(rate, dtype=float), side["approach_floor"])[last])
    return out


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
                contacts = self._functions.stop_contact(*args, stop_on=off + self._memory)
                stop_on = tuple((np.asarray(c) > 0.0).astype(float) for c in contacts)
            return function(*args, stop_on=tuple(stop_on)[: self._n] + self._memory)

        return with_memory
