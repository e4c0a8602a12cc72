"""Where a response's damper mass went: its stroke against the block's edge (docs/model.md section 11).

The paper's guide is unlimited: a response may run the mass past the block's edge, ``|x| > B/2``,
which a guide on the block cannot. The maps count such cells
(:func:`rocking.study.overturning_map.saved_past_edges`); :func:`mass_past_edge` is the same test
for one response.
"""

from __future__ import annotations

from ..model.loading import Model, load_model


def stroke_unit(model: str | Model | None) -> str | None:
    """The unit of the stroke ``x_max`` (the first coordinate after ``theta``) of ``model``, from its manifest.

    ``"m"`` for a mass on a guide, ``"rad"`` for the pendulum's angle; None for the block alone
    (``model`` None or without a damper coordinate).
    """
    if model is None:
        return None
    manifest = load_model(model).manifest
    coordinates = manifest["coordinates"]
    return manifest["units"][coordinates[1]] if len(coordinates) > 1 else None


def mass_past_edge(response, half_width: float, model: str | Model | None) -> bool | None:
    """Whether the damper's mass ran past the block's edge: ``x_max > B/2`` (``half_width``, m).

    Parameters
    ----------
    response : Response
        A response of ``model``.
    half_width : float
        The block's half-width ``B/2``, m.
    model : str, Model or None
        The model the response ran on (None: the block alone).

    Returns
    -------
    bool or None
        None where it does not apply: the block alone, or a stroke that is an angle (the pendulum's
        bob swings on a rod from its hinge; no guide ends at the edge). For ``omd2`` the test is of the
        top mass, ``x1`` (``x_max``).
    """
    if stroke_unit(model) != "m":
        return None
    return bool(response.x_max > half_width)
