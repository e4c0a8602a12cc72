"""Fragility fitting and incremental dynamic analysis: the statistics, on data of a known distribution."""

from __future__ import annotations

import numpy as np
import pytest

from rocking.model.params import ParameterError
from rocking.study.fragility import bootstrap_band, fit_lognormal, fragility_curve, ida_summary

MEDIAN, DISPERSION = 0.5, 0.4  # the true median (e.g. PGA in g) and dispersion
LEVELS = np.linspace(0.1, 1.5, 15)


def _suite(n: int, seed: int) -> np.ndarray:
    """Motions whose capacities are lognormal(MEDIAN, DISPERSION): each overturns at and above its capacity."""
    capacity = MEDIAN * np.exp(DISPERSION * np.random.default_rng(seed).standard_normal(n))
    return LEVELS[None, :] >= capacity[:, None]


def test_maximum_likelihood_recovers_a_known_lognormal():
    """200 motions: the standard error of the log median is about dispersion / sqrt(n) = 0.03, of the dispersion
    about 0.02."""
    fit = fit_lognormal(LEVELS, _suite(200, seed=1))
    assert fit["status"] == "fitted"
    assert fit["median"] == pytest.approx(MEDIAN, rel=0.1)
    assert fit["dispersion"] == pytest.approx(DISPERSION, rel=0.2)
    # The fit is a maximum: moving either parameter lowers the likelihood.
    from rocking.study.fragility import log_likelihood

    data = _suite(200, seed=1)
    best = log_likelihood(np.log(fit["median"]), fit["dispersion"], LEVELS, data)
    for dlm, dd in ((0.02, 0), (-0.02, 0), (0, 0.02), (0, -0.02)):
        assert log_likelihood(np.log(fit["median"]) + dlm, fit["dispersion"] + dd, LEVELS, data) < best
    assert fit["log_likelihood"] == pytest.approx(best)


def test_bootstrap_band_covers_the_true_curve():
    x = np.linspace(0.2, 1.2, 11)
    band = bootstrap_band(LEVELS, _suite(100, seed=2), x, resamples=100, seed=3)
    true = fragility_curve(x, MEDIAN, DISPERSION)
    assert np.mean((band["low"] <= true) & (true <= band["high"])) >= 0.8
    assert band["median_interval"][0] < MEDIAN < band["median_interval"][1]
    assert band["dispersion_interval"][0] < DISPERSION < band["dispersion_interval"][1]
    assert np.all(band["low"] <= band["high"]) and band["resamples"] + band["dropped"] == 100


def test_suites_that_never_or_always_overturn_have_no_finite_fit():
    assert fit_lognormal(LEVELS, np.zeros((5, LEVELS.size), bool))["status"] == "none_overturned"
    every = fit_lognormal(LEVELS, np.ones((5, LEVELS.size), bool))
    assert every["status"] == "all_overturned" and every["median"] == 0.0 and np.isnan(every["dispersion"])
    with pytest.raises(ParameterError, match="no resample of the suite can be fitted"):
        bootstrap_band(LEVELS, np.zeros((5, LEVELS.size), bool), [0.5], resamples=5)


def test_ida_reports_non_monotone_outcomes_as_they_are():
    """A motion that overturns at 0.3, survives at 0.4 and 0.5 (a resurrection), and overturns again from 0.6."""
    levels = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7])
    overturned = np.array([[0, 0, 1, 0, 0, 1, 1], [0, 0, 0, 0, 0, 0, 0], [1, 1, 1, 1, 1, 1, 1]], bool)
    s = ida_summary(levels, overturned)
    np.testing.assert_array_equal(s["first"], [0.3, np.nan, 0.1])
    np.testing.assert_array_equal(s["last_safe"], [0.5, 0.7, np.nan])
    np.testing.assert_array_equal(s["reversals"], [1, 0, 0])


@pytest.mark.parametrize(
    ("levels", "data", "message"),
    [
        ([0.1, 0.2], np.zeros((3, 3), bool), r"overturned must be \(motions, levels\)"),
        ([0.0, 0.2], np.zeros((3, 2), bool), r"intensity levels must be > 0"),
        ([0.2, 0.1], np.zeros((3, 2), bool), r"must increase"),
    ],
)
def test_bad_stripes_are_refused(levels, data, message):
    with pytest.raises(ParameterError, match=message):
        ida_summary(levels, data)


def _sensitive_at_the_edge(overturned: np.ndarray, every: int) -> np.ndarray:
    """Sensitive: the first overturning level of every ``every``-th motion, where a verdict is closest to turning."""
    sensitive = np.zeros_like(overturned)
    rows = np.flatnonzero(overturned.any(axis=1))[::every]
    sensitive[rows, np.argmax(overturned[rows], axis=1)] = True
    return sensitive


def test_sensitive_responses_widen_the_bootstrap_band():
    """Either answer of a sensitive response is covered: the band, and the intervals, contain those of the
    verdicts as run, and are wider where the sensitive responses count."""
    x = np.linspace(0.2, 1.2, 11)
    overturned = _suite(60, seed=4)
    sensitive = _sensitive_at_the_edge(overturned, every=3)
    certain = bootstrap_band(LEVELS, overturned, x, resamples=100, seed=5)
    honest = bootstrap_band(LEVELS, overturned, x, sensitive=sensitive, resamples=100, seed=5)
    assert honest["sensitive"] == sensitive.sum() > 0 and certain["sensitive"] == 0
    assert np.all(honest["low"] <= certain["low"]) and np.all(honest["high"] >= certain["high"])
    assert np.sum(honest["high"] - honest["low"]) > np.sum(certain["high"] - certain["low"]) + 0.05
    for k in ("median_interval", "dispersion_interval"):
        assert honest[k][0] <= certain[k][0] and honest[k][1] >= certain[k][1]


def _plain_bootstrap(levels, overturned, x, resamples: int, seed: int) -> dict:
    """The band as a plain bootstrap computes it: each resample drawn in turn and fitted by :func:`fit_lognormal`,
    the resamples without a curve dropped; and the status of every resample."""
    rng, n, fits = np.random.default_rng(seed), len(overturned), []
    for _ in range(resamples):
        fits.append(fit_lognormal(levels, overturned[rng.integers(0, n, n)]))
    kept = [fit for fit in fits if fit["status"] in ("fitted", "separated")]
    tails = (100 * (1 - 0.9) / 2, 100 * (1 + 0.9) / 2)  # the 90 % band
    curves = [fragility_curve(x, fit["median"], fit["dispersion"]) for fit in kept]
    low, high = np.percentile(curves, tails, axis=0)
    return {
        "low": low,
        "high": high,
        **{f"{k}_interval": list(np.percentile([fit[k] for fit in kept], tails)) for k in ("median", "dispersion")},
        "resamples": len(kept),
        "dropped": resamples - len(kept),
        "statuses": {fit["status"] for fit in fits},
    }


def test_a_band_with_no_sensitive_response_is_the_plain_bootstrap():
    """No sensitive response: the band of every motion resampled with the seed, as a plain bootstrap draws it."""
    x = np.linspace(0.2, 1.2, 11)
    overturned = _suite(40, seed=6)
    band = bootstrap_band(LEVELS, overturned, x, resamples=50, seed=7)
    again = bootstrap_band(LEVELS, overturned, x, sensitive=np.zeros_like(overturned), resamples=50, seed=7)
    plain = _plain_bootstrap(LEVELS, overturned, x, 50, seed=7)
    for b in (band, again):
        np.testing.assert_array_equal(b["low"], plain["low"])
        np.testing.assert_array_equal(b["high"], plain["high"])
    for k in ("median_interval", "dispersion_interval"):
        assert band[k] == again[k]


_EVERY_STATUS = {"fitted", "separated", "none_overturned", "all_overturned", "not_increasing"}


@pytest.mark.parametrize(
    ("levels", "overturned", "statuses"),
    [
        (LEVELS, _suite(60, seed=8), {"fitted"}),
        # Three motions: resamples of one motion thrice, with no curve or a falling one, are dropped.
        (np.array([0.3, 0.6]), np.array([[0, 1], [1, 1], [0, 0]], bool), _EVERY_STATUS - {"separated"}),
        # Levels closer than the motions' spread separate the outcomes exactly: the slope passes MAX_SLOPE. A
        # resample with a slope near 0 has its median overflow to inf, and its curve warn of log(0): either way.
        pytest.param(
            np.array([1.0, 1.0001]),
            np.array([[0, 1], [0, 1], [1, 1], [0, 0]], bool),
            _EVERY_STATUS,
            marks=[pytest.mark.filterwarnings(f"ignore:{w}:RuntimeWarning") for w in ("overflow", "divide by zero")],
        ),
        # Equal levels: the Hessian is singular where a resample's weight is all at one level.
        (np.array([0.5, 0.5, 0.5]), np.random.default_rng(9).uniform(size=(10, 3)) < 0.5, {"fitted"}),
    ],
)
def test_the_resamples_fitted_together_are_those_fitted_one_by_one(levels, overturned, statuses):
    """The band fits all its resamples at once, each iterating on its own: it is the band of a loop of
    :func:`fit_lognormal` over the same draws, with the same resamples dropped, whatever each resample's status.

    Each resample goes through the same floating-point operations either way, and the bands agree exactly
    (measured); the tolerance of 1e-9 only leaves room for a stacked LAPACK solve rounding the last bit of a
    step otherwise, far below any resample fitted differently (its Newton stopping at another step)."""
    x = np.linspace(0.2, 1.2, 6)
    band = bootstrap_band(levels, overturned, x, resamples=200, seed=10)
    plain = _plain_bootstrap(levels, overturned, x, 200, seed=10)
    assert plain["statuses"] == statuses  # the suite covers the statuses it is here for
    assert (band["resamples"], band["dropped"]) == (plain["resamples"], plain["dropped"])
    for k in ("low", "high", "median_interval", "dispersion_interval"):
        np.testing.assert_allclose(band[k], plain[k], rtol=1e-9, atol=1e-300)


def test_the_sensitive_mask_has_the_shape_of_the_verdicts():
    with pytest.raises(ParameterError, match=r"sensitive must have the shape of overturned, \(5, 15\)"):
        bootstrap_band(LEVELS, _suite(5, seed=1), [0.5], sensitive=np.zeros((5, 3), bool), resamples=5)


def test_a_sensitive_direction_leaves_uncertain_only_the_envelopes_it_can_change():
    """(motion, level, direction): overturned in a direction that is not sensitive is certain; a sensitive
    direction makes the envelope uncertain otherwise, overturned or not."""
    from rocking.study.ida import uncertain_verdicts

    overturned = np.array([[[1, 1], [1, 0], [0, 0], [0, 1]]], bool)
    sensitive = np.array([[[1, 0], [1, 0], [0, 1], [0, 0]]], bool)
    np.testing.assert_array_equal(uncertain_verdicts(overturned, sensitive), [[False, True, True, False]])


@pytest.mark.parametrize(
    ("levels", "overturned", "status"),
    [
        (LEVELS, np.zeros((4, LEVELS.size), bool), "none_overturned"),
        (LEVELS, np.ones((4, LEVELS.size), bool), "all_overturned"),
        (np.array([0.0, 0.5]), np.array([[False, True]] * 4), "too_few_levels"),
    ],
)
def test_a_part_without_a_curve_has_its_status_and_no_median(levels, overturned, status):
    """No curve: the variables of the part hold its status's code and NaN, not the median of ``inf`` or 0."""
    from rocking.study.ida import _fit, fit_variables
    from rocking.study.vocabulary import FIT_STATUSES

    x = np.linspace(0.2, 1.2, 5)
    fit, curves = _fit(levels, overturned, np.zeros_like(overturned), x)
    values = fit_variables(fit)
    assert values["fit_status"] == FIT_STATUSES.index(status) and values["resamples"] == 0
    assert all(np.isnan(values[k]) for k in ("median", "dispersion", "median_low", "dispersion_high"))
    assert all(np.isnan(v).all() for v in curves.values())


def test_a_median_beyond_the_levels_is_placed_and_said_with_the_level_nearest_it():
    """Capacities of median 0.5: levels from 0.1 to 0.4 put the fitted median above the highest, levels from 0.6
    to 1.5 below the lowest; the levels of the suite hold it. The words name the median, that level and the fraction
    overturned there."""
    from rocking.study.fragility import median_place, median_words

    overturned = _suite(200, seed=11)
    for levels, place, side in (
        (LEVELS[:4], "above_levels", "above the highest level tested, 0.4 g,"),
        (LEVELS[5:], "below_levels", "below the lowest level tested, 0.6 g,"),
        (LEVELS, "within_levels", None),
    ):
        columns = np.isin(LEVELS, levels)
        fit = fit_lognormal(levels, overturned[:, columns])
        assert median_place(levels, fit) == place
        fraction = overturned[:, columns].mean(axis=0)
        words = median_words(place, fit["median"], levels, fraction, "g")
        if side is None:
            assert words == "" and levels.min() <= fit["median"] <= levels.max()
            continue
        end = -1 if place == "above_levels" else 0
        assert (fit["median"] > levels[end]) == (place == "above_levels")
        assert words == (
            f"the fitted median {fit['median']:.4g} g lies {side} at which "
            f"{100 * fraction[end]:.0f} % of the motions overturn the block: the median is extrapolated, not measured"
        )
    assert median_place(LEVELS, fit_lognormal(LEVELS, np.zeros((5, LEVELS.size), bool))) == "no_median"


def test_a_median_at_a_level_to_the_rounding_of_the_fit_is_within_the_levels():
    """Half the motions overturning at the highest level, none below: the fitted median is that level to rounding,
    measured there, not extrapolated."""
    from rocking.study.fragility import median_place

    levels = np.array([1.0, 2.0, 3.0])
    overturned = np.array([[0, 0, 1], [0, 0, 0]] * 2, bool)
    fit = fit_lognormal(levels, overturned)
    assert fit["median"] == pytest.approx(3.0, rel=1e-6)
    assert median_place(levels, fit) == "within_levels"
