"""The site-based stochastic ground motions of Rezaeian and Der Kiureghian (2008)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate

from rocking.model.params import ParameterError
from rocking.model.stochastic import DEFAULT_SITE, SiteModel, modulating_function, modulating_parameters, suite

G = 9.81
#: The default site of rocking.model.stochastic (DEFAULT_SITE).
SITE = DEFAULT_SITE


@pytest.fixture(scope="module")
def records():
    return suite(SITE, 16, seed=7)


def _arias_curve(a, dt):
    cumulative = np.cumsum(np.asarray(a) ** 2) * dt * np.pi / (2 * G)
    return cumulative, cumulative / cumulative[-1]


def test_modulating_function_carries_the_arias_intensity_duration_and_midpoint():
    alphas = modulating_parameters(SITE.arias, SITE.d595, SITE.t_mid)
    t = np.linspace(0, 200, 400_001)
    cumulative = integrate.cumulative_trapezoid(modulating_function(t, alphas) ** 2, t, initial=0) * np.pi / (2 * G)
    assert cumulative[-1] == pytest.approx(SITE.arias, rel=1e-6)
    t5, t45, t95 = (np.interp(x * cumulative[-1], cumulative, t) for x in (0.05, 0.45, 0.95))
    assert (t95 - t5, t45) == pytest.approx((SITE.d595, SITE.t_mid), rel=1e-5)


def test_suite_has_the_sites_intensity_duration_and_frequency(records):
    """Over 16 records: the mean Arias intensity, D_5-95 and t_mid of the site (the high-pass filter takes a few
    per cent of the energy); zero crossings near t_mid at about twice the filter frequency f_mid (a narrow-band
    process crosses zero twice per cycle); velocity back to about zero at the end."""
    dt, t = SITE.dt, SITE.times
    arias, d595, t_mid, rate = [], [], [], []
    for a in records:
        cumulative, fraction = _arias_curve(a, dt)
        arias.append(cumulative[-1])
        t5, t45, t95 = (t[np.searchsorted(fraction, x)] for x in (0.05, 0.45, 0.95))
        d595.append(t95 - t5)
        t_mid.append(t45)
        window = (t > SITE.t_mid - 2) & (t < SITE.t_mid + 2)
        rate.append(np.count_nonzero(np.diff(np.sign(a[window])) != 0) / 4.0)
        assert abs(np.sum(a) * dt) < 0.05 * np.max(np.abs(np.cumsum(a) * dt))
    assert np.mean(arias) == pytest.approx(SITE.arias, rel=0.1)
    assert np.mean(d595) == pytest.approx(SITE.d595, rel=0.05)
    assert np.mean(t_mid) == pytest.approx(SITE.t_mid, rel=0.05)
    assert np.mean(rate) == pytest.approx(2 * SITE.f_mid, rel=0.15)


def test_suite_is_reproducible_and_each_record_independent_of_the_suites_size(records):
    again = suite(SITE, 3, seed=7)
    for a, b in zip(again, records[:3]):
        np.testing.assert_array_equal(a, b)
    assert not np.array_equal(records[0], records[1])
    assert not np.array_equal(suite(SITE, 1, seed=8)[0], records[0])


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"arias": -1.0}, r"^arias must be > 0 m/s"),
        ({"zeta_f": 1.0}, r"^zeta_f must be in \(0, 1\)"),
        ({"dt": float("nan")}, r"^dt"),
        ({"d595": 1.0}, r"^d595 / t_mid must lie in"),
        ({"duration": 5.0}, r"^duration must exceed t_mid"),
    ],
)
def test_bad_site_parameters_are_refused_naming_them(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        site = SiteModel(**{**SITE.record(), "duration": None, **kwargs})
        modulating_parameters(site.arias, site.d595, site.t_mid)


@pytest.mark.parametrize(("n", "seed"), [(0, 1), (2.5, 1), (True, 1), (2, -1), (2, "a")])
def test_bad_suite_size_or_seed_is_refused(n, seed):
    with pytest.raises(ParameterError, match=r"^(n|seed) must be an integer"):
        suite(SITE, n, seed)


@pytest.mark.parametrize(("dt", "f_c"), [(0.005, 0.1), (0.001, 0.05), (0.02, 0.2)])
def test_high_pass_is_the_exact_response_to_a_piecewise_linear_input(dt, f_c):
    """A ramp a = t drives x'' + 2 w x' + w^2 x = t from rest to x'' = t exp(-w t) (solved by hand); white
    noise, linear between samples, agrees with scipy.signal.lsim's first-order hold (another algorithm: a
    state-space loop) to 1e-11 of the peak."""
    from scipy import signal

    from rocking.model.stochastic import high_pass

    t = np.arange(4001) * dt
    w = 2 * np.pi * f_c
    exact = t * np.exp(-w * t)
    np.testing.assert_allclose(high_pass(t, dt, f_c), exact, rtol=0, atol=1e-11 * exact.max())
    noise = np.random.default_rng(3).standard_normal(t.size)
    system = signal.StateSpace([[0.0, 1.0], [-(w**2), -2 * w]], [[0.0], [1.0]], [[-(w**2), -2 * w]], [[1.0]])
    reference = signal.lsim(system, noise, t, interp=True)[1]
    np.testing.assert_allclose(high_pass(noise, dt, f_c), reference, rtol=0, atol=1e-11 * np.abs(reference).max())


def test_the_kept_kernel_gives_the_bits_of_the_kernel_made_for_each_motion(monkeypatch):
    """The site's kernel is kept between the motions of a suite when it is small enough; made again for each
    motion otherwise: the same operations, the same bits."""
    from rocking.model import stochastic

    site = SiteModel(arias=0.3, d595=6.0, t_mid=4.0, f_mid=4.0, f_slope=-0.1, zeta_f=0.3, dt=0.01)
    kept = suite(site, 2, seed=11)
    stochastic._kernel.cache_clear()
    monkeypatch.setattr(stochastic, "KERNEL_CACHE", 0)
    assert stochastic._kernel(site)[0] is None
    for a, b in zip(suite(site, 2, seed=11), kept):
        np.testing.assert_array_equal(a, b)
    stochastic._kernel.cache_clear()
