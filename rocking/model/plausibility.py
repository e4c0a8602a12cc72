"""Plausibility checks: inputs that are valid but unlikely to be what the user meant, as warnings.

A valid input is run; one far outside what a building or a record is warns with a
:class:`PlausibilityWarning` (the command line shows it as one line): a damper heavier than half
the block, a record scaled past the largest acceleration ever recorded, a record said to be in g
whose values look like cm/s^2, a record sampled too coarsely for the pulses that overturn blocks.

Units SI: m/s^2, s.
"""

from __future__ import annotations

import warnings

from .motion import SampledMotion

#: Largest mass ratio m/M that is plausible: a tuned mass damper is a few per cent of its structure;
#: past half the block the "damper" is a second body, and the model's massless guide a poor idealisation.
GAMMA_MAX = 0.5
#: The largest peak ground acceleration recorded, in g (Iwate-Miyagi Nairiku 2008).
PGA_RECORDED_MAX = 4.36
#: A record "in g" whose peak exceeds this many g is almost surely in cm/s^2 (980 times too strong).
PGA_UNIT_SUSPECT = 20.0
#: Coarsest plausible sample spacing, s: 20 samples per second leave a 0.2 s pulse 4 samples.
DT_MAX = 0.05


class PlausibilityWarning(UserWarning):
    """A valid input far outside what a building or a record is: probably not what was meant."""


def _warn(message: str, stacklevel: int = 1) -> None:
    """Warn ``message``, attributed to the frame ``stacklevel`` above the check that calls this (1: its caller)."""
    warnings.warn(message, PlausibilityWarning, stacklevel=stacklevel + 2)


def check_mass_ratio(gamma: float, *, stacklevel: int = 1) -> None:
    """Warn if the damper's mass ratio ``gamma = m / M`` exceeds :data:`GAMMA_MAX`."""
    if gamma > GAMMA_MAX:
        _warn(
            f"the damper's mass is {gamma:.3g} of the block's (gamma > {GAMMA_MAX:g}): a damper heavier than "
            "half the block is a second body, not a damper; is m (or --gamma) right?",
            stacklevel,
        )


def check_pga(pga: float, g: float, *, stacklevel: int = 1) -> None:
    """Warn if a motion's peak ``pga`` (m/s^2) exceeds the largest recorded, :data:`PGA_RECORDED_MAX` g of ``g``."""
    if pga > PGA_RECORDED_MAX * g:
        _warn(
            f"the motion's PGA is {pga / g:.3g} g, above the largest ever recorded ({PGA_RECORDED_MAX:g} g); "
            "is the scale right?",
            stacklevel,
        )


def check_run(block, model, p, pulse, *, stacklevel: int = 1) -> None:
    """Warn of an implausible run: the damper's mass ratio (:func:`check_mass_ratio`), a sampled motion's
    scaled peak (:func:`check_pga`).

    Parameters
    ----------
    block : rocking.Block
        The block.
    model : rocking.Model
        The model run.
    p : sequence of float
        Its parameters, in the order of ``model.parameters``.
    pulse : object
        The ground motion; only a :class:`~rocking.model.motion.SampledMotion`'s peak is checked (a
        pulse's amplitude is what the studies vary).
    stacklevel : int
        The frame the warning names, counted from the caller of this function.
    """
    values = dict(zip(model.parameters, p, strict=True))
    # The damper's mass is every attached body's: each parameter in kg that the block does not set.
    own = set(model.own_parameters)
    kg = [q["name"] for q in model.manifest["parameters"] if q["unit"] == "kg" and q["name"] in own]
    check_mass_ratio(sum(float(values[k]) for k in kg) / block.M, stacklevel=stacklevel + 1)
    if isinstance(pulse, SampledMotion):
        check_pga(pulse.pga, block.g, stacklevel=stacklevel + 1)


def check_record(pga_g: float, dt: float, unit: str | None, name: str = "the record") -> None:
    """Warn of a record read in g whose peak exceeds :data:`PGA_UNIT_SUSPECT` g, or sampled above :data:`DT_MAX`.

    Parameters
    ----------
    pga_g : float
        The record's peak, in g.
    dt : float
        Its sample spacing, s.
    unit : str or None
        The unit the file was read in (``"g"``, ``"m/s2"``, ``"cm/s2"``).
    name : str
        The record, as the warning names it.
    """
    if unit == "g" and pga_g > PGA_UNIT_SUSPECT:
        _warn(
            f"{name}: read in g, its PGA is {pga_g:.4g} g (> {PGA_UNIT_SUSPECT:g} g): its values look like "
            "cm/s2; give --unit cm/s2 (or state it in the header)"
        )
    if dt > DT_MAX:
        _warn(
            f"{name}: dt = {dt:g} s (> {DT_MAX:g} s): too coarse to resolve the short pulses that overturn "
            "blocks; the motion is linear between samples"
        )
