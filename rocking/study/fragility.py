"""Fragility: the probability of overturning against an intensity measure, from a suite of motions.

The data are stripes: every motion of a suite scaled to each of several levels of an
intensity measure ``IM`` (incremental dynamic analysis, :func:`ida_summary`), each
response overturning or not. The fragility curve is the lognormal distribution

    P(overturn | IM = x) = Phi( ln(x / median) / dispersion )

fitted by maximum likelihood to the counts of every stripe (binomial likelihood, Baker
2015, "Efficient analytical fragility function fitting using dynamic structural
analysis", Earthquake Spectra 31(1), 579-599): it uses every response, and needs no
single "collapse intensity" per motion, which a non-monotone response does not have.
Its confidence band is a bootstrap over the motions (the suite is the sample):
:func:`bootstrap_band`, widened to cover either answer of the responses sensitive to the
integrator's tolerance.
"""

from __future__ import annotations

import numpy as np

from ..model.params import ParameterError
from .vocabulary import FIT_STATUSES


def _stripes(im, overturned) -> tuple[np.ndarray, np.ndarray]:
    im = np.asarray(im, float)
    overturned = np.asarray(overturned, bool)
    if overturned.ndim != 2 or overturned.shape[1] != im.size:
        raise ParameterError(
            f"overturned must be (motions, levels) with one level per IM value (got "
            f"{overturned.shape} for {im.size} levels)"
        )
    if not (np.isfinite(im).all() and (im > 0).all()):
        raise ParameterError(f"the intensity levels must be > 0 (got {im!r})")
    return im, overturned


def log_likelihood(log_median: float, dispersion: float, im, overturned) -> float:
    """Binomial log-likelihood of the lognormal fragility of median ``exp(log_median)`` and ``dispersion`` for
    the responses ``overturned`` (motions, levels) at the levels ``im``."""
    k, safe = _counts(overturned)
    params = np.array([[-log_median / dispersion, 1 / dispersion]])
    return -float(_probit_cost(params, np.log(im), k[None], safe[None])[0][0])


def _counts(overturned) -> tuple[np.ndarray, np.ndarray]:
    """Overturned and safe responses per level."""
    k = overturned.sum(axis=0).astype(float)
    return k, overturned.shape[0] - k


def _probit_cost(params, x, k, safe) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Negative log-likelihoods of ``P = Phi(a + b x)`` (``x = ln IM``), their gradients and Hessians in ``(a, b)``,
    of several suites at once.

    The lognormal fragility is this probit model with ``b = 1 / dispersion``, ``a = -ln(median) / dispersion``;
    its cost is convex in ``(a, b)``. Logs of Phi are taken directly (``log_ndtr``), so that levels far in the
    tails do not round to log(0).

    Parameters
    ----------
    params : ndarray, shape (r, 2)
        ``(a, b)`` of each of ``r`` suites.
    x : ndarray, shape (m,)
        The log levels, shared by the suites.
    k, safe : ndarray, shape (r, m)
        Each suite's overturned and safe responses per level.

    Returns
    -------
    cost : ndarray, shape (r,)
    gradient : ndarray, shape (r, 2)
    hessian : ndarray, shape (r, 2, 2)
    """
    # Imported here: scipy.special takes about half a second to import, paid only by a fragility.
    from scipy import special

    z = params[:, :1] + params[:, 1:] * x
    log_p, log_q = special.log_ndtr(z), special.log_ndtr(-z)
    log_pdf = -0.5 * z * z - 0.5 * np.log(2 * np.pi)
    up, down = np.exp(log_pdf - log_p), np.exp(log_pdf - log_q)  # the inverse Mills ratios
    slope = k * up - safe * down
    weight = k * up * (z + up) + safe * down * (down - z)
    # Sums along the levels, each suite's as np.sum of its own row: a suite's fit does not depend on the others.
    gradient = -np.stack([np.sum(slope, axis=1), np.sum(slope * x, axis=1)], axis=1)
    cross = np.sum(weight * x, axis=1)
    hessian = np.stack([np.sum(weight, axis=1), cross, cross, np.sum(weight * x * x, axis=1)], axis=1).reshape(-1, 2, 2)
    return -np.sum(k * log_p + safe * log_q, axis=1), gradient, hessian


#: Statuses of a fit that gives a curve.
FITTED = FIT_STATUSES[:2]

#: Fewest motions a lognormal is fitted to without a :class:`FitWarning`. The dispersion of a lognormal fitted to
#: ``n`` motions has a standard error of about ``dispersion / sqrt(2 n)`` (each motion one sample of its log capacity):
#: below 10 motions more than a fifth of the dispersion itself.
MIN_MOTIONS = 10
#: Smallest dispersion fitted without a :class:`FitWarning`. Record-to-record dispersions of overturning are of
#: order 0.2 to 0.6; below 0.05 the motions overturn the block at one level to within 5 %: copies of one record,
#: or levels too coarse to tell the motions apart, and the fit then describes the levels, not the suite.
MIN_DISPERSION = 0.05


class FitWarning(UserWarning):
    """A lognormal fitted to too few motions, or of a degenerate dispersion (:func:`fit_warnings`); a median
    outside the levels tested (:func:`median_words`)."""


def fit_warnings(motions: int, fit) -> list[str]:
    """Why the fit ``fit`` of :func:`fit_lognormal` to ``motions`` motions is not to be trusted, if it is not.

    Returns
    -------
    list of str
        A sentence for fewer than :data:`MIN_MOTIONS` motions, one for a dispersion below :data:`MIN_DISPERSION`
        (or outcomes the levels separate exactly); empty for a fit without a curve, which its status tells.
    """
    if fit["status"] not in FITTED:
        return []
    out = []
    if motions < MIN_MOTIONS:
        out.append(
            f"the lognormal is fitted to {motions} motions, fewer than {MIN_MOTIONS}: its dispersion is uncertain "
            f"by about {1 / np.sqrt(2 * motions):.0%} of itself; use more motions"
        )
    if fit["status"] == "separated" or fit["dispersion"] < MIN_DISPERSION:
        out.append(
            f"the fitted dispersion {fit['dispersion']:.3g} is below {MIN_DISPERSION:g}: the motions overturn the "
            "block at one level (copies of one record, or levels too coarse to tell them apart); the curve "
            "describes the levels, not the suite"
        )
    return out


#: Where a fitted median lies against the levels it was fitted to (the codes of an IDA's ``median_extrapolated``):
#: within them (measured), above the highest or below the lowest (extrapolated by the lognormal's shape, which
#: nothing tested there supports), or nowhere (the fit gives no curve).
MEDIAN_PLACES = ("within_levels", "above_levels", "below_levels", "no_median")
#: A median within this fraction of the highest or lowest level is at that level: half the motions overturning the
#: block at a level puts the fitted median there, to the rounding of the fit (3 * (1 + 1.5e-16) measured), and no
#: level is given to a millionth.
MEDIAN_RTOL = 1e-6


def median_place(levels, fit) -> str:
    """Where the median of ``fit`` (:func:`fit_lognormal`'s) lies against the ``levels`` it was fitted to: one of
    :data:`MEDIAN_PLACES`, to within :data:`MEDIAN_RTOL`."""
    if fit["status"] not in FITTED:
        return "no_median"
    levels = np.asarray(levels, float)
    if fit["median"] > levels.max() * (1 + MEDIAN_RTOL):
        return "above_levels"
    if fit["median"] < levels.min() * (1 - MEDIAN_RTOL):
        return "below_levels"
    return "within_levels"


def median_words(place: str, median: float, levels, fraction, unit: str = "") -> str:
    """An extrapolated median in words: the median, the level tested nearest to it and the fraction of the motions
    that overturn the block there; empty for a median within the levels or none.

    Parameters
    ----------
    place : str
        :func:`median_place` of the fit.
    median : float
        The fitted median, in the unit of the levels.
    levels, fraction : array_like, shape (m,)
        The levels fitted and the fraction of the motions overturning the block at each.
    unit : str
        The unit of the levels, for the words ("" for a scale factor).
    """
    if place not in ("above_levels", "below_levels"):
        return ""
    levels, fraction = np.asarray(levels, float), np.asarray(fraction, float)
    end = int(np.argmax(levels) if place == "above_levels" else np.argmin(levels))
    side = "above the highest" if place == "above_levels" else "below the lowest"
    space = f" {unit}" if unit else ""
    return (
        f"the fitted median {median:.4g}{space} lies {side} level tested, {levels[end]:.4g}{space}, at which "
        f"{100 * fraction[end]:.0f} % of the motions overturn the block: the median is extrapolated, not measured"
    )


#: Newton iterations of a fit, and the largest slope ``b = 1 / dispersion`` (a dispersion of 1e-3): levels that
#: separate the outcomes exactly have no finite maximum, the slope growing without bound.
NEWTON_STEPS, MAX_SLOPE = 100, 1e3


def _newton_steps(hessian, gradient) -> tuple[np.ndarray, np.ndarray]:
    """Newton's steps ``-hessian^-1 gradient`` of several suites, and which suites have one.

    Parameters
    ----------
    hessian : ndarray, shape (r, 2, 2)
    gradient : ndarray, shape (r, 2)

    Returns
    -------
    step : ndarray, shape (r, 2)
    solvable : ndarray of bool, shape (r,)
        False where the Hessian is singular: that suite's Newton iterations stop.
    """
    try:
        return -np.linalg.solve(hessian, gradient[..., None])[..., 0], np.ones(len(gradient), bool)
    except np.linalg.LinAlgError:
        # A stacked solve fails as a whole if any Hessian is singular (rare: levels that are all equal, or whose
        # weights all but one underflow); solving the suites one by one tells which.
        step, solvable = np.zeros_like(gradient), np.ones(len(gradient), bool)
        for i in range(len(gradient)):
            try:
                step[i] = -np.linalg.solve(hessian[i], gradient[i])
            except np.linalg.LinAlgError:
                solvable[i] = False
        return step, solvable


#: Tries of a Newton step, halved after each that raises the cost, before the fit gives up.
STEP_TRIES = 40


def _halved_steps(params, step, cost, x, k, safe) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """Each suite's Newton step from ``params``, halved until the cost there is no higher than ``cost``.

    Parameters
    ----------
    params, step : ndarray, shape (r, 2)
    cost : ndarray, shape (r,)
    x, k, safe
        As :func:`_probit_cost`'s.

    Returns
    -------
    moved : ndarray of bool, shape (r,)
        Whether one of the :data:`STEP_TRIES` steps made the cost no higher.
    trial : tuple of ndarray
        The params of the suites that moved, and :func:`_probit_cost` there.
    """
    moved = np.zeros(len(params), bool)
    trial = [params.copy(), cost.copy(), np.zeros_like(params), np.zeros((len(params), 2, 2))]
    pending, step = np.arange(len(params)), step.copy()
    for _ in range(STEP_TRIES):
        if not pending.size:
            break
        there = params[pending] + step[pending]
        values = (there, *_probit_cost(there, x, k[pending], safe[pending]))
        lower = values[1] <= cost[pending]
        for kept, value in zip(trial, values, strict=True):
            kept[pending[lower]] = value[lower]
        moved[pending[lower]] = True
        pending = pending[~lower]
        step[pending] = step[pending] / 2
    return moved, tuple(trial)


def _newton(start, x, k, safe) -> tuple[np.ndarray, np.ndarray]:
    """The minima of the convex :func:`_probit_cost` of several suites by Newton's method with step halving.

    Each suite iterates on its own, the suites only computed together: it stops when its cost changes by less
    than 1e-12 of itself, its slope ``b`` passes :data:`MAX_SLOPE`, its Hessian is singular, its step halved
    :data:`STEP_TRIES` times still raises its cost, or after :data:`NEWTON_STEPS` steps.

    Parameters
    ----------
    start : array_like, shape (2,)
        ``(a, b)`` every suite starts from.
    x, k, safe
        As :func:`_probit_cost`'s.

    Returns
    -------
    params : ndarray, shape (r, 2)
    cost : ndarray, shape (r,)
    """
    params = np.tile(np.asarray(start, float), (len(k), 1))
    state = [params, *_probit_cost(params, x, k, safe)]  # params, cost, gradient, Hessian of every suite
    params, cost, gradient, hessian = state
    active = np.arange(len(k))
    for _ in range(NEWTON_STEPS):
        if not active.size:
            break
        step, solvable = _newton_steps(hessian[active], gradient[active])
        active, step = active[solvable], step[solvable]
        moved, trial = _halved_steps(params[active], step, cost[active], x, k[active], safe[active])
        active, before = active[moved], cost[active[moved]]
        for kept, value in zip(state, trial, strict=True):
            kept[active] = value[moved]
        converged = np.abs(before - cost[active]) <= 1e-12 * np.maximum(1.0, np.abs(before))
        active = active[~(converged | (np.abs(params[active, 1]) > MAX_SLOPE))]
    return params, cost


def _fits(x, k, safe) -> dict:
    """:func:`fit_lognormal` of several suites at the same levels, from their counts.

    Parameters
    ----------
    x : ndarray, shape (m,)
        The log levels.
    k, safe : ndarray, shape (r, m)
        Each suite's overturned and safe responses per level.

    Returns
    -------
    dict of ndarray, each (r,)
        ``median``, ``dispersion``, ``log_likelihood`` as :func:`fit_lognormal`'s, and ``status``: the index of
        each fit's status in :data:`~rocking.study.vocabulary.FIT_STATUSES`.
    """
    r = len(k)
    median, dispersion, log_likelihood = np.full(r, np.nan), np.full(r, np.nan), np.zeros(r)
    status = np.full(r, FIT_STATUSES.index("fitted"))
    none, every = k.sum(axis=1) == 0, safe.sum(axis=1) == 0
    median[none], status[none] = np.inf, FIT_STATUSES.index("none_overturned")
    median[every], status[every] = 0.0, FIT_STATUSES.index("all_overturned")
    mixed = np.flatnonzero(~(none | every))
    spread = max(float(np.std(x)), 0.1)
    start = np.array([-float(np.median(x)) / spread, 1 / spread])
    params, cost = _newton(start, x, k[mixed], safe[mixed])
    a, b = params.T
    log_likelihood[mixed] = -cost
    increasing = b > 0  # False for a NaN slope too: no curve
    status[mixed[~increasing]] = FIT_STATUSES.index("not_increasing")
    status[mixed[b > MAX_SLOPE]] = FIT_STATUSES.index("separated")
    a, b, mixed = a[increasing], b[increasing], mixed[increasing]
    median[mixed], dispersion[mixed] = np.exp(-a / b), 1 / b
    return {"median": median, "dispersion": dispersion, "log_likelihood": log_likelihood, "status": status}


def fit_lognormal(im, overturned) -> dict:
    """The maximum-likelihood lognormal fragility of responses at intensity levels.

    Parameters
    ----------
    im : array_like, shape (m,)
        The intensity levels (> 0), in the unit of the measure.
    overturned : array_like of bool, shape (n, m)
        Whether each of ``n`` motions overturns the block at each level.

    Returns
    -------
    dict
        ``median`` (in the unit of ``im``), ``dispersion`` (the standard deviation of ``ln IM``),
        ``log_likelihood``, and ``status`` (one of :data:`~rocking.study.vocabulary.FIT_STATUSES`):
        ``"fitted"``; ``"separated"`` (the levels separate the outcomes exactly: the likelihood grows as the
        dispersion falls to 0, given at ``1 / MAX_SLOPE``); ``"none_overturned"`` / ``"all_overturned"`` (no
        finite fit: the median is then given as ``inf`` or 0, the dispersion nan); or ``"not_increasing"`` (the
        fraction overturned falls with the level).
    """
    im, overturned = _stripes(im, overturned)
    k, safe = _counts(overturned)
    fit = _fits(np.log(im), k[None], safe[None])
    return {
        **{key: float(fit[key][0]) for key in ("median", "dispersion", "log_likelihood")},
        "status": FIT_STATUSES[fit["status"][0]],
    }


def fragility_curve(x, median, dispersion) -> np.ndarray:
    """``Phi(ln(x / median) / dispersion)`` at the intensities ``x`` (broadcast against ``median`` and
    ``dispersion``)."""
    from scipy import special  # imported here, as in _probit_cost

    return special.ndtr(np.log(np.asarray(x, float) / median) / dispersion)


def _resampled_counts(overturned, resamples: int, rng) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_counts` of ``resamples`` suites resampled by motion, with replacement.

    The draws are those of ``rng.integers(0, n, n)`` called once per resample, in order: one call of all of them
    continues the generator's stream as the calls one after the other would.

    Returns
    -------
    k, safe : ndarray, shape (resamples, m)
    """
    n = overturned.shape[0]
    draws = rng.integers(0, n, (resamples, n))
    times = np.bincount((n * np.arange(resamples)[:, None] + draws).ravel(), minlength=resamples * n)
    # Counts of at most n * n responses, exact in floating point: the product is done by BLAS.
    k = times.reshape(resamples, n).astype(float) @ overturned.astype(float)
    return k, n - k


def _band(im, overturned, x, resamples: int, level: float, seed: int) -> dict | None:
    """:func:`bootstrap_band` of verdicts taken as certain; ``None`` if no resample can be fitted."""
    fit = _fits(np.log(im), *_resampled_counts(overturned, resamples, np.random.default_rng(seed)))
    curve = np.isin(fit["status"], [FIT_STATUSES.index(status) for status in FITTED])
    if not curve.any():
        return None
    medians, dispersions = fit["median"][curve], fit["dispersion"][curve]
    per_resample = (-1,) + (1,) * np.ndim(x)  # a curve at x for each resample
    curves = fragility_curve(x, medians.reshape(per_resample), dispersions.reshape(per_resample))
    tails = (100 * (1 - level) / 2, 100 * (1 + level) / 2)
    low, high = np.percentile(curves, tails, axis=0)
    return {
        "low": low,
        "high": high,
        "median_interval": [float(v) for v in np.percentile(medians, tails)],
        "dispersion_interval": [float(v) for v in np.percentile(dispersions, tails)],
        "resamples": int(curve.sum()),
        "dropped": int(resamples - curve.sum()),
    }


def bootstrap_band(
    im, overturned, x, *, sensitive=None, resamples: int = 400, level: float = 0.9, seed: int = 0
) -> dict:
    """A confidence band of the fitted fragility at ``x``: refits on the suite resampled by motion.

    A sensitive response (docs/simulation.md, "Sensitivity to the tolerance") has two answers, one
    per tolerance, and no reason to prefer either: the band is then the envelope of three bands on
    the same resamples (the same ``seed``), of the verdicts as run, of every sensitive response
    counted as overturning, and of every one counted as safe. It is at least as wide as the band of
    the verdicts as run, and is that band where no response is sensitive.

    Parameters
    ----------
    im : array_like, shape (m,)
        The intensity levels (> 0).
    overturned : array_like of bool, shape (n, m)
        The verdicts as run.
    x : array_like
        Where the band is given, in the unit of ``im``.
    sensitive : array_like of bool, shape (n, m), optional
        The responses whose verdict the tolerance may change; default none.
    resamples, level, seed
        Bootstrap resamples, the band's confidence level, the seed of the resampling.

    Returns
    -------
    dict
        ``low``, ``high`` (the band at ``x``), ``median_interval`` and ``dispersion_interval`` (the
        envelopes of the three bands' intervals), ``resamples`` used and ``dropped`` (resamples with no
        overturning or only overturning have no fit), both of the verdicts as run, and
        ``sensitive``: the number of sensitive responses.

    Raises
    ------
    ParameterError
        No resample of the verdicts as run can be fitted, or ``sensitive`` is not of the shape of
        ``overturned``.
    """
    im, overturned = _stripes(im, overturned)
    sensitive = np.zeros_like(overturned) if sensitive is None else np.asarray(sensitive, bool)
    if sensitive.shape != overturned.shape:
        raise ParameterError(f"sensitive must have the shape of overturned, {overturned.shape} (got {sensitive.shape})")
    band = _band(im, overturned, x, resamples, level, seed)
    if band is None:
        raise ParameterError("no resample of the suite can be fitted: every motion overturns, or none does")
    band["sensitive"] = int(sensitive.sum())
    if not sensitive.any():
        return band
    for verdicts in (overturned | sensitive, overturned & ~sensitive):
        # A variant with no fit (every response now overturning, or none) adds no curve to the envelope.
        other = _band(im, verdicts, x, resamples, level, seed)
        if other is None:
            continue
        band["low"], band["high"] = np.minimum(band["low"], other["low"]), np.maximum(band["high"], other["high"])
        for k in ("median_interval", "dispersion_interval"):
            band[k] = [min(band[k][0], other[k][0]), max(band[k][1], other[k][1])]
    return band


def ida_summary(scales, overturned) -> dict:
    """What the incremental dynamic analysis of each motion shows, non-monotone outcomes reported as they are.

    Parameters
    ----------
    scales : array_like, shape (m,)
        Increasing scale factors (or intensity levels).
    overturned : array_like of bool, shape (n, m)

    Returns
    -------
    dict of ndarray, each (n,)
        ``first`` (the first level that overturns, nan if none), ``last_safe`` (the highest level that
        does not overturn, nan if every level overturns), ``reversals`` (how many times the outcome goes
        from overturned back to safe as the level rises: a "resurrection", 0 for a monotone motion).
    """
    scales, overturned = _stripes(scales, overturned)
    if np.any(np.diff(scales) <= 0):
        raise ParameterError("the levels of an incremental dynamic analysis must increase")
    any_over = overturned.any(axis=1)
    first = np.where(any_over, scales[np.argmax(overturned, axis=1)], np.nan)
    safe = ~overturned
    last = safe.shape[1] - 1 - np.argmax(safe[:, ::-1], axis=1)
    last_safe = np.where(safe.any(axis=1), scales[last], np.nan)
    reversals = np.sum(overturned[:, :-1] & safe[:, 1:], axis=1)
    return {"first": first, "last_safe": last_safe, "reversals": reversals}
