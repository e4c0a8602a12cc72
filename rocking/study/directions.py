"""The directions of the pulses a study runs, and the envelope of the responses over them.

An earthquake does not choose the direction of its pulse. A study therefore runs
every pulse in both directions (``sign = +1`` and ``-1``, :class:`rocking.OneSinePulse`)
and reports the *envelope*: the worse of the two responses of each cell, the
smaller of the two ``beta_min``. The damper's gain is the ratio of the envelopes.

When the block (``e = 0``) and its damper (the ``omd`` damper, with or without its
symmetric stops) are symmetric about the block's centre line, the mirrored pulse
gives the mirrored response (docs/model.md 10.6): one direction is enough, and
``"auto"`` (the default) runs the positive one only and says so. A
:class:`~rocking.study.config.Variant` may be any model: ``"auto"`` runs both.
"""

from __future__ import annotations

from functools import reduce

import numpy as np

from ..model.params import Block, ParameterError
from .config import Tuning
from .dataset import field_attrs

#: The choices of a study's ``directions``, and the signs of the pulses each runs (``"auto"``: see
#: :func:`choose`).
SIGNS = {"both": (1, -1), "positive": (1,), "negative": (-1,)}
DIRECTIONS = ("auto", *SIGNS)

#: Name of each sign in the columns of tables (``bare_outcome_pos``).
SIGN_NAMES = {1: "pos", -1: "neg"}


def symmetric(block: Block, tuning) -> bool:
    """Whether the block and its damper are mirror-symmetric: ``e = 0`` and a :class:`Tuning` or no damper.

    ``tuning``: a :class:`Tuning`, a :class:`~rocking.study.config.Variant` or ``None`` (the ``omd``
    damper of a study that searches it).
    """
    return block.e == 0.0 and (tuning is None or isinstance(tuning, Tuning))


def choose(directions: str, block: Block, tuning=None) -> dict:
    """The signs a study runs, with the reason: a JSON-ready record.

    Parameters
    ----------
    directions : {"auto", "both", "positive", "negative"}
        ``"auto"``: both, unless :func:`symmetric` makes one enough.
    block : Block
    tuning : Tuning, Variant or None
        The study's damper (``None``: the ``omd`` damper).

    Returns
    -------
    dict
        ``directions`` (as given), ``signs`` (list of +1/-1), ``reason`` (one sentence).

    Raises
    ------
    ParameterError
        For any other value of ``directions``.
    """
    if not isinstance(directions, str) or directions not in DIRECTIONS:
        raise ParameterError(f"directions must be one of {', '.join(DIRECTIONS)} (got {directions!r})")
    if directions != "auto":
        return {"directions": directions, "signs": list(SIGNS[directions]), "reason": "as asked"}
    if symmetric(block, tuning):
        reason = (
            "the block (e = 0) and the damper are symmetric: the mirrored pulse gives the mirrored response "
            "(docs/model.md 10.6), so the positive direction is enough"
        )
        return {"directions": directions, "signs": [1], "reason": reason}
    why = f"the block is eccentric (e = {block.e:g} m)" if block.e != 0.0 else "the damper may not be symmetric"
    return {"directions": directions, "signs": [1, -1], "reason": f"{why}: both directions, the envelope reported"}


def repeat(values, signs) -> np.ndarray:
    """Each of ``values`` once per sign: the columns ``(value, sign)`` in the order of :func:`sign_column`."""
    return np.repeat(np.asarray(values), len(signs), axis=0)


def sign_column(n: int, signs) -> np.ndarray:
    """The signs of ``n`` values repeated by :func:`repeat`: shape ``(n len(signs),)``."""
    return np.tile(np.asarray(signs, np.int64), n)


def worst(overturned, impacts, theta_max, unknown) -> np.ndarray:
    """Index, along the last axis (the signs), of the worse response of each cell.

    Worse: overturned (sooner: fewer impacts first) before without a verdict (``unknown``)
    before safe (the larger ``theta_max``). Ties go to the first sign.
    """
    overturned, unknown = np.asarray(overturned, bool), np.asarray(unknown, bool)
    # theta_max of a block that does not overturn is below pi, so the three classes do not overlap; a theta_max
    # not computed (NaN, a cell an adaptive map filled in) ranks below any, never above an overturned direction.
    safe = np.nan_to_num(np.asarray(theta_max, float), nan=-1.0)
    # The impacts of a safe direction do not count (and are NOT_COMPUTED, -1, where not computed).
    sooner = 1.0 / (1.0 + np.maximum(np.asarray(impacts), 0))
    score = np.where(overturned, 20.0 + sooner, np.where(unknown, 10.0, safe))
    return np.argmax(score, axis=-1)


def take(values, index) -> np.ndarray:
    """``values[..., index]`` cell by cell (``index`` from :func:`worst`)."""
    return np.take_along_axis(np.asarray(values), np.asarray(index)[..., None], axis=-1)[..., 0]


def largest(values) -> np.ndarray:
    """The largest of ``values`` along the last axis (NaN if any is): a few directions, compared slice by slice,
    which is many times faster than a reduction along a short last axis."""
    values = np.asarray(values)
    return reduce(np.maximum, (values[..., i] for i in range(1, values.shape[-1])), np.array(values[..., 0]))


#: Fields of a response taken from the worse direction; the others are the largest over the directions.
FROM_WORST = ("impacts", "status", "flew")


def response_envelope(by_sign: dict, unknown) -> dict:
    """The envelope of responses over the directions (last axis of every array).

    ``by_sign``: arrays of :data:`rocking.study.overturning_map.FIELDS`, ``(..., n_signs)``;
    ``unknown``: where a response has no verdict, same shape. Returns the fields ``(...)``:
    ``overturned`` if in any direction, ``impacts`` and ``status`` of the worse direction
    (:func:`worst`), the maxima (``theta_max``, ``x_max``, ``stop_contacts``,
    ``bumper_force_max``) the largest over the directions; and ``worst_sign_index``.
    """
    index = worst(by_sign["overturned"], by_sign["impacts"], by_sign["theta_max"], unknown)
    out = {"overturned": np.asarray(by_sign["overturned"], bool).any(axis=-1)}
    for k, v in by_sign.items():
        if k in FROM_WORST:
            out[k] = take(v, index)
        elif k != "overturned":
            out[k] = largest(v)
    out["worst_sign_index"] = index
    return out


def study_data(data, kinds: tuple[str, ...]):
    """The responses an ``envelope`` of the studies ``kinds`` reduces: ``data`` as it is (an
    :class:`xarray.Dataset`), or the ``data`` of a :class:`rocking.study.result.Study` of one of ``kinds``.

    Raises
    ------
    ParameterError
        For a study of another kind, or anything else, in one line naming what to pass.
    """
    import xarray as xr

    from .result import Study

    what = " or ".join(kinds)
    if isinstance(data, xr.Dataset):
        return data
    if isinstance(data, Study) and data.kind in kinds:
        return data.data
    got = f"a {data.kind} Study" if isinstance(data, Study) else type(data).__name__
    raise ParameterError(f"data must be a {what} Study or its data, an xarray.Dataset (got {got})")


def envelope(data, unknown):
    """The envelope of labelled responses over the directions: ``data`` (an :class:`xarray.Dataset` of the
    fields of :func:`response_envelope`) reduced over its dimension ``sign``.

    ``unknown``: where a response has no verdict (an :class:`xarray.DataArray` of the same dimensions).
    Returns the fields without ``sign``, their attributes kept, and ``worst_sign``: the sign of the direction
    that governs each cell.
    """
    import xarray as xr

    by_sign = data.transpose(..., "sign")
    dims = by_sign["overturned"].dims[:-1]
    reduced = response_envelope(
        {k: v.values for k, v in by_sign.data_vars.items()}, unknown.transpose(*dims, "sign").values
    )
    index = reduced.pop("worst_sign_index")
    out = xr.Dataset(
        {k: (dims, v, by_sign[k].attrs) for k, v in reduced.items()}, coords=by_sign.drop_dims("sign").coords
    )
    out["worst_sign"] = (dims, by_sign["sign"].values[index], field_attrs("worst_sign", {}))
    return out


def beta_min_envelope(by_sign: dict) -> dict:
    """The envelope of :func:`rocking.study.spectrum.beta_min` over the directions (last axis).

    The smallest ``beta_min``; its ``beta_safe``, ``flag`` and ``impacts`` (those of the
    governing direction); ``undetermined`` summed; with a vertical component ``flown`` summed and the governing
    direction's ``beta_min_flew``; ``scan_outcome`` (``(..., n_signs, m)``)
    the worse outcome per scan amplitude (overturned in either direction, with the fewer
    impacts); and ``worst_sign_index``.
    """
    index = np.argmin(by_sign["beta_min"], axis=-1)
    out = {k: take(by_sign[k], index) for k in ("beta_min", "beta_safe", "flag", "impacts")}
    out["undetermined"] = np.sum(by_sign["undetermined"], axis=-1)
    if "flown" in by_sign:  # a vertical component: the flights summed, whether the governing beta_min's flew
        out["flown"] = np.sum(by_sign["flown"], axis=-1)
        out["beta_min_flew"] = take(by_sign["beta_min_flew"], index)
    if "scan_outcome" in by_sign:
        scan = np.asarray(by_sign["scan_outcome"])
        over = scan >= 0
        fewest = np.min(np.where(over, scan, np.iinfo(np.int64).max), axis=-2)
        out["scan_outcome"] = np.where(over.any(axis=-2), fewest, scan.min(axis=-2))
    out["worst_sign_index"] = index
    return out
