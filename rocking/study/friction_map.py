"""The regime map of a floor with friction: what pulses of one frequency do to the block over ``(mu, beta)``.

Shenton (1996, "Criteria for initiation of slide, rock, and slide-rock rigid-body modes", J. Eng. Mech.
122(7)) charts the mode a rigid block takes against the friction coefficient and the amplitude of the ground
motion. Here each cell of a grid of floors ``mu`` (static, equal to the kinetic: ``rocking.Floor(mu)``,
docs/model.md section 15) and pulse amplitude ratios ``beta = a_g / (g tan alpha)`` at one frequency ratio
``Omega = omega_g / p`` is one response (in each direction of the pulse), and its *regime*
(:data:`rocking.study.vocabulary.REGIMES`): rest, rocks, slides, slides and rocks, overturns. Starting from
rest, a symmetric block begins to slide when ``mu < B/H`` and to rock when ``mu > B/H`` (Shenton's initiation
rule; its figure draws that line), once the pulse's acceleration passes ``mu g`` or ``g tan alpha``.

Every cell is computed (the map is not adaptive: its regions are few and wide, and its grids small). The
cells are cut into tiles of ``tile`` floors x amplitudes, each one call of
:func:`rocking.study.overturning_map.respond` per floor, run by :func:`rocking.study.tiles.run_tiles`: kept
under ``runs`` (a rerun loads them), with its progress bar and its interruption.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np

from ..model.floor import Floor
from ..model.params import Block, ParameterError
from ..sim.problem import STATUS
from . import directions
from .config import Grid, Setting, Tuning, Variant, is_number, part_config
from .dataset import coordinate_attrs, field_attrs
from .directions import SIGN_NAMES, choose
from .overturning_map import (
    _check_tile,
    check_damper,
    check_study,
    preflight,
    reached_t_max,
    respond,
    undetermined,
    warn_t_max,
    warn_undetermined,
)
from .result import Study
from .tiles import LOCAL, Execution, Task, run_folder, run_tiles
from .vocabulary import REGIMES, combined_regime, regime, resolution_of

#: Result fields kept per response.
FIELDS = ("overturned", "impacts", "theta_max", "status", "u_max", "u_end", "slides")

#: The dimensions of every variable of a regime map's data (:func:`friction_data`), coordinates included.
DIMS = {
    "mu": ("mu",),
    "beta": ("beta",),
    "sign": ("sign",),
    "a_g": ("beta",),
    **dict.fromkeys((*FIELDS, "regime"), ("mu", "beta", "sign")),
}

#: Default tile: floors x amplitudes per call (some 0.1 s per response on the NumPy back end).
TILE = (4, 16)


def check_Omega(Omega) -> float:
    """The fixed pulse frequency ratio as a float > 0, else a one-line :class:`ParameterError`."""
    if not (is_number(Omega) and 0.0 < float(Omega) < math.inf):
        raise ParameterError(f"Omega must be a finite number > 0, the pulses' omega_g / p (got {Omega!r})")
    return float(Omega)


def friction_tile(payload: Any) -> dict:
    """One tile: ``(setting, damper_or_None, Omega, mu_values, beta_values, signs)`` -> arrays ``(nmu, nbeta,
    nsigns)`` of :data:`FIELDS`, each floor ``rocking.Floor(mu)``."""
    setting, damper, Omega, mu, beta, signs = payload
    rows = [
        respond(dataclasses.replace(setting, floor=Floor(m)), Omega, beta[:, None], damper, np.asarray(signs)[None])
        for m in mu
    ]
    return {k: np.stack([row[k] for row in rows]) for k in FIELDS}


def friction_map(
    setting: Setting,
    Omega: float,
    mu: Grid,
    beta: Grid,
    execution: Execution = LOCAL,
    *,
    damper: Tuning | Variant | None = None,
    runs: str | Path = "out/runs",
    tile: tuple[int, int] = TILE,
    directions: str = "auto",
    on_tile=None,
) -> Study:
    """The regime of the block (alone, or with ``damper``) under pulses of ``Omega`` over ``mu x beta``.

    Parameters
    ----------
    setting : Setting
        Block, pulse family and solver; its floor must be the paper's (the grid ``mu`` sets each cell's), its
        back end one that follows friction (both do).
    Omega : float
        The pulses' frequency ratio ``omega_g / p``.
    mu, beta : Grid
        The floors' friction (static = kinetic, ``> 0``) and the pulses' amplitude ratios
        ``a_g / (g tan alpha)``.
    execution : Execution
        Where the tiles run.
    damper : Tuning, Variant or None
        The damper on the block; ``None`` (default): the block alone.
    runs : path
        Folder of the run folders (finished tiles, for resuming).
    tile : (int, int)
        Floors x amplitudes per tile.
    directions : {"auto", "both", "positive", "negative"}
        Signs of the pulses (:func:`rocking.study.directions.choose`).

    Returns
    -------
    Study
        Kind ``"friction"``; its data (:func:`friction_data`) hold :data:`FIELDS` and ``regime`` of every
        response, dimensions ``(mu, beta, sign)``.

    Raises
    ------
    ParameterError
        For a floor given in ``setting``, a bad ``Omega``, grid or tile.
    """
    check_study(setting, execution, runs, mu=mu, beta=beta)
    Omega = check_Omega(Omega)
    if setting.floor.slides:
        raise ParameterError("a friction map sets each cell's floor from its mu grid: give the setting no floor")
    if damper is not None:
        check_damper(damper)
    tile = _check_tile(tile)
    chosen = choose(directions, setting.block, damper)
    signs = chosen["signs"]
    m, b = mu.values(), beta.values()
    record = None if damper is None else damper.record()
    case_args = None if damper is None else damper.case_args()
    grids = {"pulse_Omega": Omega, "mu": mu.record(), "beta": beta.record(), "tile": list(tile), "signs": signs}
    part = "bare" if damper is None else "damper"
    folder = run_folder(runs, part_config("friction", part, setting, damper=record, **grids))
    preflight(dataclasses.replace(setting, floor=Floor(float(m[0]))), case_args)

    shape = (m.size, b.size, len(signs))
    fields = {k: np.zeros(shape, bool if k == "overturned" else np.int64) for k in ("overturned", "impacts")}
    fields.update({k: np.zeros(shape, np.int64) for k in ("status", "slides")})
    fields.update({k: np.full(shape, np.nan) for k in ("theta_max", "u_max", "u_end")})
    tasks, where = [], {}
    for i in range(0, m.size, tile[0]):
        for j in range(0, b.size, tile[1]):
            rows, cols = slice(i, i + tile[0]), slice(j, j + tile[1])
            expect = dict.fromkeys(FIELDS, (m[rows].size, b[cols].size, len(signs)))
            payload = (setting, case_args, Omega, m[rows], b[cols], signs)
            task = Task(folder / f"tile-{i}-{j}.npz", friction_tile, payload, expect)
            tasks.append(task)
            where[task.path] = (rows, cols)

    def place(task: Task, arrays: dict) -> None:
        rows, cols = where[task.path]
        for k in FIELDS:
            fields[k][rows, cols] = arrays[k]

    stats = run_tiles(tasks, place, execution, backend=setting.backend, desc="friction map", on_tile=on_tile)
    resolution = resolution_of(setting.rtol, setting.block.alpha)
    fields["regime"] = regime(fields["overturned"], fields["theta_max"], fields["u_max"], resolution)
    config = {"kind": "friction", **setting.record(), **({} if damper is None else {"damper": record})}
    config.update(grids, directions=chosen)
    data = friction_data(config, m, b, signs, fields)
    warn_undetermined("friction map", int(undetermined(fields["status"]).sum()))
    warn_t_max("friction map", int(reached_t_max(fields["status"]).sum()), setting.t_after)
    return Study(
        "friction",
        config,
        data,
        summary={**friction_summary(data, setting.block.B / setting.block.H), "directions": chosen},
        run={**stats.record(), "run_folders": {part: folder.name}, "responses": int(np.prod(shape))},
        tabulate=friction_tables,
    )


def friction_data(config: dict, mu, beta, signs, fields: dict):
    """A regime map's results as labelled data: the :data:`FIELDS` and ``regime`` of every response, ``(mu, beta,
    sign)``, with the amplitudes in SI terms and the pulses' frequency (``Omega``, ``T_g``) as attributes."""
    import xarray as xr

    block = Block(**config["block"])
    coords = {
        "mu": ("mu", mu, coordinate_attrs("mu", config)),
        "beta": ("beta", beta, coordinate_attrs("beta", config)),
        "a_g": ("beta", block.a_g(np.asarray(beta)), coordinate_attrs("a_g", config)),
        "sign": ("sign", np.array(signs), coordinate_attrs("sign", config)),
    }
    variables = {k: (DIMS[k], v, field_attrs(k, config)) for k, v in fields.items()}
    return xr.Dataset(variables, coords=coords, attrs=friction_attrs(config))


def friction_attrs(config: dict) -> dict:
    """Attributes of a regime map's Dataset (``config``: its configuration): the pulses' one frequency, ratio and
    period, and the floor of each cell, in words."""
    Omega = config["pulse_Omega"]
    return {
        "Omega": Omega,
        "T_g": 2 * math.pi / (Omega * Block(**config["block"]).p),
        "pulse_frequency": "every pulse's Omega = omega_g / p (1) and period T_g = 2 pi / omega_g (s)",
        "floor": "each cell's floor: Coulomb friction mu_s = mu_k = mu (docs/model.md section 15)",
    }


def envelope(data):
    """A regime map's responses over both directions of each pulse, ``(mu, beta)``: the ``regime`` of both
    together (:func:`rocking.study.vocabulary.combined_regime`), overturned in either, the largest
    ``theta_max`` and ``u_max``."""
    by_sign = data.transpose(..., "sign")
    dims = by_sign["regime"].dims[:-1]
    out = {
        "regime": combined_regime(by_sign["regime"].values),
        "overturned": by_sign["overturned"].values.any(axis=-1),
        **{k: directions.largest(by_sign[k].values) for k in ("theta_max", "u_max")},
    }
    return data.drop_dims("sign").assign({k: (dims, v, data[k].attrs) for k, v in out.items()})


def friction_summary(data, slenderness: float) -> dict:
    """Cell counts of each regime (of both directions together), runs without a verdict or at ``t_max``, and
    Shenton's boundary ``mu = B/H`` between sliding and rocking first (``slenderness``)."""
    env = envelope(data)
    codes = env["regime"].values
    status = data["status"].values
    return {
        "cells": int(codes.size),
        **{name: int((codes == code).sum()) for code, name in REGIMES.items()},
        "undetermined": int(undetermined(status).any(axis=-1).sum()),
        "t_max": int((status == STATUS.index("t_max")).any(axis=-1).sum()),
        "B_over_H": slenderness,
    }


def friction_tables(data, config: dict) -> dict:
    """One CSV row per cell: the floor, the pulse, the regime of both directions together (and of each), the
    largest rotation and slip, the residual displacement of each direction."""
    env = envelope(data)
    mu, beta = np.meshgrid(data["mu"].values, data["beta"].values, indexing="ij")
    a_g = np.broadcast_to(data["a_g"].values, mu.shape)
    words = np.array([*REGIMES.values(), "not_computed"], object)
    table = {"mu": mu, "beta": beta, "a_g": a_g, "regime": words[env["regime"].values]}
    table.update({k: env[k].values for k in ("theta_max", "u_max")})
    for i, sign in enumerate(data["sign"].values):
        by_sign = data.isel(sign=i)
        table[f"regime_{SIGN_NAMES[sign]}"] = words[by_sign["regime"].values]
        table[f"u_end_{SIGN_NAMES[sign]}"] = by_sign["u_end"].values
    return {"friction": {k: np.ravel(v) for k, v in table.items()}}
