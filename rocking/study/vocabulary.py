"""The words of the studies' results that more than one module reads: codes of flags, outcomes and statuses.

A leaf: it imports nothing of :mod:`rocking.study`, so that the studies, their labels
(:mod:`rocking.study.dataset`) and their figures share one definition of each code.
"""

from __future__ import annotations

import numpy as np

#: The parts of a study (the values of its coordinate ``part``), and what each is.
PART_NAMES = {
    "bare": "block alone",
    "damper": "block with the damper",
    "unlimited": "damper on an unlimited guide",
    "stops": "damper with end stops",
}

#: Outcome of a response that does not overturn (otherwise: the impacts before overturning).
SAFE = -1
#: A spectrum's scan outcome where the run ended in flight (the floor's normal force reached 0 on a model without
#: flight functions, docs/model.md sections 14, 16): no verdict, and none at the amplitudes above it. A flight
#: model's runs fly and land to a verdict: they never end so.
FLIGHT = -2

#: The regime of a response on a floor with friction (docs/model.md section 15), by code: it never left rest
#: (no uplift, no slip), rocked (the base lifted, ``theta_max > 0``) without slipping, slid without lifting (the
#: base slipped, ``slides > 0``), did both, or overturned (whatever it did before). The names are CF
#: ``flag_meanings`` (no spaces); :func:`regime_label` gives them in words.
REST, ROCKS, SLIDES, SLIDES_AND_ROCKS, OVERTURNS = range(5)  # bits: lifted 1, slipped 2
REGIMES = {REST: "rest", ROCKS: "rocks", SLIDES: "slides", SLIDES_AND_ROCKS: "slides_and_rocks", OVERTURNS: "overturns"}

#: Value of the integer fields (``impacts``, ``stop_contacts``, ``status``) of a cell of an adaptive map that
#: was not computed, where its class does not give them (the float fields are NaN there).
NOT_COMPUTED = -1

#: How ``beta_min`` was found (:func:`rocking.study.spectrum.beta_min`): the first scan amplitude overturns
#: already (an upper bound), bisected, or no scan amplitude overturns (a lower bound).
BELOW, BRACKETED, ABOVE = -1, 0, 1
#: What each flag makes of ``beta_min``, in words: the tables' ``*_beta_min_is`` columns, the datasets' key.
FLAG_WORDS = {BELOW: "upper_bound", BRACKETED: "bracketed", ABOVE: "lower_bound"}

#: Outcomes of :func:`rocking.study.optimize.threshold_frequency`, in the order of the ``<kind>_status`` arrays.
THRESHOLD_STATUSES = ("bracketed", "below_range", "above_range", "undefined")

#: Outcomes of a lognormal fit (:func:`rocking.study.fragility.fit_lognormal`), in the order of the codes of an
#: IDA's ``fit_status``; the first two give a curve.
FIT_STATUSES = ("fitted", "separated", "none_overturned", "all_overturned", "not_increasing", "too_few_levels")


def flag_words(flag) -> np.ndarray:
    """:data:`FLAG_WORDS` of each flag of ``flag``."""
    return np.array([FLAG_WORDS[BELOW], FLAG_WORDS[BRACKETED], FLAG_WORDS[ABOVE]], object)[np.asarray(flag) + 1]


def regime(overturned, theta_max, u_max, resolution: float = 0.0) -> np.ndarray:
    """The :data:`REGIMES` code of each response from its ``overturned``, ``theta_max`` (rad) and ``u_max`` (m).

    The base lifted where ``theta_max`` passes ``resolution``, and slipped where ``u_max`` does: the integrator's
    absolute tolerance on both, ``rtol alpha`` (:func:`resolution_of`). Below it a motion is round-off, not
    resolved: on Shenton's line ``mu = B/H`` a sliding block's ``theta_max`` is some 1e-17 alpha, and where
    ``a_g = mu g`` exactly a slip's ``u_max`` some 1e-32 m.
    """
    lifted, slipped = np.asarray(theta_max) > resolution, np.asarray(u_max) > resolution
    moved = np.where(slipped, np.where(lifted, SLIDES_AND_ROCKS, SLIDES), np.where(lifted, ROCKS, REST))
    return np.where(overturned, OVERTURNS, moved)


def resolution_of(rtol: float, alpha: float) -> float:
    """The integrator's absolute tolerance on ``theta`` (rad), ``rtol alpha`` (rocking.sim.problem.default_settings),
    which the NumPy back end gives the slip ``u`` (m) too: what :func:`regime` tells from no motion."""
    return rtol * alpha


def regime_label(code: int) -> str:
    """A regime's name in words: ``"slides and rocks"``."""
    return REGIMES[code].replace("_", " ")


def combined_regime(codes, axis: int = -1) -> np.ndarray:
    """The regime of responses taken together along ``axis`` (the directions of a pulse): ``overturns`` if any
    overturns, else :data:`NOT_COMPUTED` if any was not computed, else what any did (the codes of
    ``rest``, ``rocks``, ``slides`` and ``slides_and_rocks`` are the bits lifted 1, slipped 2: their union)."""
    codes = np.asarray(codes)
    moved = np.bitwise_or.reduce(np.where(codes >= 0, codes, 0), axis=axis)
    unknown = (codes == NOT_COMPUTED).any(axis=axis)
    return np.where((codes == OVERTURNS).any(axis=axis), OVERTURNS, np.where(unknown, NOT_COMPUTED, moved))
