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
    return -_probit_cost(np.array([-log_median / dispersion, 1 / dispersion]), np.log(im), *_counts(overturned))[0]


def _counts(overturned) -> tuple[np.ndarray, np.ndarray]:
    """Overturned and safe responses per level."""
    k = overturned.sum(axis=0).astype(float)
    return k, overturned.shape[0] - k


def _probit_cost(params, x, k, safe) -> tuple[float, np.ndarray, np.ndarray]:
    """Negative log-likelihood of ``P = Phi(a + b x)`` (``x = ln IM``), its gradient and Hessian in ``(a, b)``.

    The lognormal fragility is this probit model with ``b = 1 / dispersion``, ``a = -ln(median) / dispersion``;
    its cost is convex in ``(a, b)``. Logs of Phi are taken directly (``log_ndtr``), so that levels far in the
    tails do not round to log(0).
    """
    # Imported here: scipy.special takes about half a second to import, paid only by a fragility.
    from scipy import special

    a, b = params
    z = a + b * x
    log_p, log_q = special.log_ndtr(z), special.log_ndtr(-z)
    log_pdf = -0.5 * z * z - 0.5 * np.log(2 * np.pi)
    up, down = np.exp(log_pdf - log_p), np.exp(log_pdf - log_q)  # the inverse Mills ratios
    slope = k * up - safe * down
    weight = k * up * (z + up) + safe * down * (down - z)
    gradient = -np.array([np.sum(slope), np.sum(slope * x)])
    hessian = np.array([[np.sum(weight), np.sum(weight * x)], [np.sum(weight * x), np.sum(weight * x * x)]])
    return -float(np.sum(k * log_p + safe * log_q)), gradient, hessian


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
    """A lognormal fitted to too few motions, or of a degenerate dispersion (:func:`fit_warnings`)."""


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


#: Newton iterations of a fit, and the largest slope ``b = 1 / dispersion`` (a dispersion of 1e-3): levels that
#: separate the outcomes exactly have no finite maximum, the slope growing without bound.
NEWTON_STEPS, MAX_SLOPE = 100, 1e3


def _newton(start, x, k, safe) -> tuple[np.ndarray, float]:
    """The minimum of the convex :func:`_probit_cost` by Newton's method with step halving."""
    params = np.asarray(start, float)
    cost, gradient, hessian = _probit_cost(params, x, k, safe)
    for _ in range(NEWTON_STEPS):
        try:
            step = -np.linalg.solve(hessian, gradient)
        except np.linalg.LinAlgError:
            break
        for _ in range(40):
            trial = params + step
            trial_cost, trial_gradient, trial_hessian = _probit_cost(trial, x, k, safe)
            if trial_cost <= cost:
                break
            step = step / 2
        else:
            break
        params, converged = trial, abs(cost - trial_cost) <= 1e-12 * max(1.0, abs(cost))
        cost, gradient, hessian = trial_cost, trial_gradient, trial_hessian
        if converged or abs(params[1]) > MAX_SLOPE:
            break
    return params, cost


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
    fraction = overturned.mean()
    if fraction == 0:
        return {"median": np.inf, "dispersion": np.nan, "log_likelihood": 0.0, "status": "none_overturned"}
    if fraction == 1:
        return {"median": 0.0, "dispersion": np.nan, "log_likelihood": 0.0, "status": "all_overturned"}
    x = np.log(im)
    k, safe = _counts(overturned)
    spread = max(float(np.std(x)), 0.1)
    start = np.array([-float(np.median(x)) / spread, 1 / spread])
    (a, b), cost = _newton(start, x, k, safe)
    if not b > 0:
        return {"median": np.nan, "dispersion": np.nan, "log_likelihood": -cost, "status": "not_increasing"}
    status = "separated" if b > MAX_SLOPE else "fitted"
    return {"median": float(np.exp(-a / b)), "dispersion": float(1 / b), "log_likelihood": -cost, "status": status}


def fragility_curve(x, median: float, dispersion: float) -> np.ndarray:
    """``Phi(ln(x / median) / dispersion)`` at the intensities ``x``."""
    from scipy import special  # imported here, as in _probit_cost

    return special.ndtr(np.log(np.asarray(x, float) / median) / dispersion)


def _band(im, overturned, x, resamples: int, level: float, seed: int) -> dict | None:
    """:func:`bootstrap_band` of verdicts taken as certain; ``None`` if no resample can be fitted."""
    rng = np.random.default_rng(seed)
    curves, medians, dispersions, dropped = [], [], [], 0
    for _ in range(resamples):
        sample = overturned[rng.integers(0, overturned.shape[0], overturned.shape[0])]
        fit = fit_lognormal(im, sample)
        if fit["status"] not in FITTED:
            dropped += 1
            continue
        curves.append(fragility_curve(x, fit["median"], fit["dispersion"]))
        medians.append(fit["median"])
        dispersions.append(fit["dispersion"])
    if not curves:
        return None
    tails = (100 * (1 - level) / 2, 100 * (1 + level) / 2)
    low, high = np.percentile(np.asarray(curves), tails, axis=0)
    return {
        "low": low,
        "high": high,
        "median_interval": [float(v) for v in np.percentile(medians, tails)],
        "dispersion_interval": [float(v) for v in np.percentile(dispersions, tails)],
        "resamples": len(curves),
        "dropped": dropped,
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
