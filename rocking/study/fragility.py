"""Fragility: the probability of overturning against an intensity measure, from a suite of motions.

The data are stripes: every motion of a suite scaled to each of several levels of an
intensity measure ``IM`` (incremental dynamic analysis, :func:`ida_summary`), each
response overturning or not. The fragility curve is the lognormal distribution

    P(overturn | IM = x) = Phi( ln(x / theta) / beta )

fitted by maximum likelihood to the counts of every stripe (binomial likelihood, Baker
2015, "Efficient analytical fragility function fitting using dynamic structural
analysis", Earthquake Spectra 31(1), 579-599): it uses every response, and needs no
single "collapse intensity" per motion, which a non-monotone response does not have.
Its confidence band is a bootstrap over the motions (the suite is the sample):
:func:`bootstrap_band`.
"""

from __future__ import annotations

import numpy as np
from scipy import optimize, stats

from ..model.params import ParameterError


def _stripes(im, overturned) -> tuple[np.ndarray, np.ndarray]:
    im = np.asarray(im, float)
    overturned = np.asarray(overturned, bool)
    if overturned.ndim != 2 or overturned.shape[1] != im.size:
        raise ParameterError(f"overturned must be (motions, levels) with one level per IM value (got "
                             f"{overturned.shape} for {im.size} levels)")  # fmt: skip
    if not (np.isfinite(im).all() and (im > 0).all()):
        raise ParameterError(f"the intensity levels must be > 0 (got {im!r})")
    return im, overturned


def log_likelihood(log_theta: float, beta: float, im, overturned) -> float:
    """Binomial log-likelihood of the lognormal fragility ``(exp(log_theta), beta)`` for the responses
    ``overturned`` (motions, levels) at the levels ``im``."""
    p = stats.norm.cdf((np.log(im) - log_theta) / beta)
    p = np.clip(p, 1e-300, 1 - 1e-16)
    k = overturned.sum(axis=0)
    n = overturned.shape[0]
    return float(np.sum(k * np.log(p) + (n - k) * np.log1p(-p)))


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
        ``theta`` (the median, in the unit of ``im``), ``beta`` (the dispersion, of ``ln IM``),
        ``log_likelihood``, and ``status``: ``"fitted"``, or ``"none overturned"`` / ``"all overturned"``
        (no finite fit: ``theta`` is then beyond the levels, given as ``inf`` or 0, ``beta`` nan).
    """
    im, overturned = _stripes(im, overturned)
    fraction = overturned.mean()
    if fraction == 0:
        return {"theta": np.inf, "beta": np.nan, "log_likelihood": 0.0, "status": "none overturned"}
    if fraction == 1:
        return {"theta": 0.0, "beta": np.nan, "log_likelihood": 0.0, "status": "all overturned"}
    x = np.log(im)
    start = np.array([np.median(x), max(np.std(x), 0.1)])

    def cost(params):
        return -log_likelihood(params[0], np.exp(params[1]), im, overturned)

    best = optimize.minimize(cost, [start[0], np.log(start[1])], method="Nelder-Mead",
                             options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 5000})  # fmt: skip
    return {
        "theta": float(np.exp(best.x[0])),
        "beta": float(np.exp(best.x[1])),
        "log_likelihood": float(-best.fun),
        "status": "fitted",
    }


def fragility_curve(x, theta: float, beta: float) -> np.ndarray:
    """``Phi(ln(x / theta) / beta)`` at the intensities ``x``."""
    return stats.norm.cdf(np.log(np.asarray(x, float) / theta) / beta)


def bootstrap_band(im, overturned, x, *, resamples: int = 400, level: float = 0.9, seed: int = 0) -> dict:
    """A confidence band of the fitted fragility at ``x``: refits on the suite resampled by motion.

    Returns
    -------
    dict
        ``low``, ``high`` (the band at ``x``), ``theta`` and ``beta`` intervals, and ``resamples`` used
        (resamples with no overturning or only overturning have no fit and are dropped, counted in
        ``dropped``).
    """
    im, overturned = _stripes(im, overturned)
    rng = np.random.default_rng(seed)
    curves, thetas, betas, dropped = [], [], [], 0
    for _ in range(resamples):
        sample = overturned[rng.integers(0, overturned.shape[0], overturned.shape[0])]
        fit = fit_lognormal(im, sample)
        if fit["status"] != "fitted":
            dropped += 1
            continue
        curves.append(fragility_curve(x, fit["theta"], fit["beta"]))
        thetas.append(fit["theta"])
        betas.append(fit["beta"])
    if not curves:
        raise ParameterError("no resample of the suite can be fitted: every motion overturns, or none does")
    tails = (100 * (1 - level) / 2, 100 * (1 + level) / 2)
    low, high = np.percentile(np.asarray(curves), tails, axis=0)
    return {
        "low": low,
        "high": high,
        "theta_interval": [float(v) for v in np.percentile(thetas, tails)],
        "beta_interval": [float(v) for v in np.percentile(betas, tails)],
        "resamples": len(curves),
        "dropped": dropped,
    }


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
