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
#: A spectrum's scan outcome where the run ended in flight (``g + ddy_g`` reached 0 with a vertical component,
#: docs/model.md section 14): no verdict, and none at the amplitudes above it.
FLIGHT = -2

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
