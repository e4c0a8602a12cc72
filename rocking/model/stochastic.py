"""Synthetic ground accelerations: the site-based stochastic model of Rezaeian and Der Kiureghian (2008).

The acceleration is a filtered white noise, modulated in time and high-pass filtered
(Rezaeian, S. and Der Kiureghian, A., 2008, "A stochastic ground motion model with
separable temporal and spectral nonstationarities", Earthquake Engng Struct. Dyn. 37,
1565-1584):

    a(t) = q(t) * sum_i h(t - t_i; omega_f(t_i)) u_i / sigma_f(t)

- ``u_i``: independent standard normal pulses at the sample times ``t_i``;
- ``h(t; omega) = omega / sqrt(1 - zeta_f^2) exp(-zeta_f omega t) sin(omega sqrt(1 - zeta_f^2) t)``,
  ``t >= 0``: the impulse response of a linear oscillator whose frequency is that of the
  pulse's own time, ``omega_f(tau) = omega_mid + omega' (tau - t_mid)`` (spectral
  nonstationarity), with a constant damping ratio ``zeta_f``;
- ``sigma_f(t)``: the standard deviation of the sum, so that the filtered noise has unit
  variance and the modulating function alone sets the intensity;
- ``q(t) = alpha_1 t^(alpha_2 - 1) exp(-alpha_3 t)``: a gamma-shaped modulating function
  (temporal nonstationarity), fixed by the expected Arias intensity ``I_a``, the
  significant duration ``D_5-95`` and the time ``t_mid`` at which 45 % of ``I_a`` is reached
  (:func:`modulating_parameters`);
- the result is the acceleration response of a critically damped oscillator of frequency
  ``omega_c`` driven by it (a high-pass filter, so that velocity and displacement return
  to zero; :func:`high_pass`).

A suite is reproducible from a seed: motion ``i`` draws its noise from the ``i``-th child of
``numpy.random.SeedSequence(seed)``, so it is the same in a suite of any size.

**Vertical component** (docs/model.md sections 12 and 14): a simple model, not a fit. The vertical
acceleration of motion ``i`` is ``ratio`` times a record of the same model with its own site
parameters (default: the horizontal site's), drawn from its own noise
(:func:`vertical_rng`: independent of the horizontal one, which stays what it was without a vertical
component), at the same sample times:

    ddy_g(t) = ratio * a_v(t),   a_v: a record of the vertical site

so with the default site the vertical has the horizontal's spectral and temporal shape and the expected Arias
intensity ``ratio^2`` times the horizontal's. Near-fault vertical components are richer in high
frequencies (Bozorgnia and Campbell 2004): give the vertical site a higher ``f_mid`` for them.

Units SI: m/s^2, s, Hz for the site's frequencies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .params import ParameterError, check_real

#: Kernel length of the filter, in decay times ``1 / (zeta_f omega_f)``: ``exp(-12)`` of its envelope is left.
KERNEL_DECAYS = 12.0
#: Lowest filter frequency, Hz: ``omega_f`` falls with time (``omega' < 0``) and is held at this floor.
F_FLOOR = 0.3
#: Largest filter kernel kept between the motions of a site, in numbers (64 MB): a suite reuses it for
#: every motion instead of evaluating ``exp`` and ``sin`` again; a larger one is evaluated for each motion.
KERNEL_CACHE = 8_000_000


def _positive(name: str, value, unit: str) -> float:
    x = check_real(name, value)
    if not x > 0:
        raise ParameterError(f"{name} must be > 0 {unit} (got {value!r})")
    return x


@dataclass(frozen=True)
class SiteModel:
    """The parameters of the model of Rezaeian and Der Kiureghian (2008) for one site and earthquake.

    Parameters
    ----------
    arias : float
        Expected Arias intensity ``I_a``, m/s, > 0.
    d595 : float
        Significant duration ``D_5-95``, s, > 0: from 5 % to 95 % of ``I_a``.
    t_mid : float
        Time at which 45 % of ``I_a`` is reached, s, > 0.
    f_mid : float
        Filter frequency at ``t_mid``, Hz, > 0.
    f_slope : float
        Rate of change of the filter frequency, Hz/s (usually negative).
    zeta_f : float
        Damping ratio of the filter, in (0, 1).
    f_c : float, optional
        Corner of the high-pass filter, Hz, > 0. Default 0.1 Hz.
    dt : float, optional
        Time step of the samples, s, > 0. Default 0.005 s.
    duration : float, optional
        Length of the record, s; default ``t_mid + 2 D_5-95`` (beyond 99.9 % of ``I_a`` for
        the usual shapes).

    Raises
    ------
    ParameterError
        Naming the parameter and its range.
    """

    arias: float
    d595: float
    t_mid: float
    f_mid: float
    f_slope: float
    zeta_f: float
    f_c: float = 0.1
    dt: float = 0.005
    duration: float | None = None

    def __post_init__(self) -> None:
        for name, unit in (
            ("arias", "m/s"),
            ("d595", "s"),
            ("t_mid", "s"),
            ("f_mid", "Hz"),
            ("f_c", "Hz"),
            ("dt", "s"),
        ):
            object.__setattr__(self, name, _positive(name, getattr(self, name), unit))
        object.__setattr__(self, "f_slope", check_real("f_slope", self.f_slope))
        zeta = check_real("zeta_f", self.zeta_f)
        if not 0 < zeta < 1:
            raise ParameterError(f"zeta_f must be in (0, 1) (got {self.zeta_f!r})")
        object.__setattr__(self, "zeta_f", zeta)
        duration = self.t_mid + 2 * self.d595 if self.duration is None else _positive("duration", self.duration, "s")
        if not duration > self.t_mid:
            raise ParameterError(f"duration must exceed t_mid = {self.t_mid:g} s (got {duration!r})")
        if duration / self.dt > 1e6:
            raise ParameterError(f"duration / dt must be at most 1e6 samples (got {duration / self.dt:.3g})")
        object.__setattr__(self, "duration", float(duration))

    @property
    def times(self) -> np.ndarray:
        """The sample times ``t_k = k dt``, s, up to ``duration``."""
        assert self.duration is not None  # __post_init__ stores the default in place of None
        return np.arange(int(round(self.duration / self.dt)) + 1) * self.dt

    def record(self) -> dict:
        """JSON-ready description."""
        return {
            k: getattr(self, k)
            for k in ("arias", "d595", "t_mid", "f_mid", "f_slope", "zeta_f", "f_c", "dt", "duration")
        }


#: A default site: values of the order of the medians Rezaeian and Der Kiureghian (2010, Earthquake Engng Struct.
#: Dyn. 39, 1155-1180) report for the NGA records (I_a about 0.05 s g, D_5-95 of 10 - 20 s, f_mid about 5 Hz
#: falling by about 0.1 Hz/s, zeta_f of 0.2 - 0.3); not a fit to any site, and not checked against the paper
#: here. Give a site's own values for a real study.
DEFAULT_SITE = SiteModel(arias=0.0468 * 9.81, d595=17.3, t_mid=12.4, f_mid=5.87, f_slope=-0.089, zeta_f=0.213)


@lru_cache(maxsize=16)
def modulating_parameters(arias: float, d595: float, t_mid: float, g: float = 9.81) -> tuple[float, float, float]:
    """``(alpha_1, alpha_2, alpha_3)`` of ``q(t) = alpha_1 t^(alpha_2 - 1) exp(-alpha_3 t)`` for the expected
    Arias intensity ``arias`` (m/s), the significant duration ``d595`` and ``t_mid`` (s).

    ``q^2`` is a gamma density of shape ``k = 2 alpha_2 - 1`` and rate ``2 alpha_3`` up to its scale, so the
    cumulative Arias intensity is that distribution: ``D_5-95 / t_mid`` fixes ``k``, then ``t_mid`` the rate,
    and ``E[I_a] = pi / (2 g) int q^2 dt`` (unit-variance noise) the scale ``alpha_1``.

    Raises
    ------
    ParameterError
        If no gamma shape gives the ratio ``d595 / t_mid`` (it must lie within the shapes' range).
    """
    # Imported here: scipy.stats takes about a second to import, paid only by those who use it.
    from scipy import optimize, special, stats

    def ratio(k: float) -> float:
        return (stats.gamma.ppf(0.95, k) - stats.gamma.ppf(0.05, k)) / stats.gamma.ppf(0.45, k)

    low, high = 1.0 + 1e-6, 200.0  # k = 1: q constant at t = 0; k = 200: a narrow burst
    target = d595 / t_mid
    if not ratio(high) <= target <= ratio(low):
        raise ParameterError(
            f"d595 / t_mid must lie in [{ratio(high):.3g}, {ratio(low):.3g}] for a gamma-shaped modulating "
            f"function (got {d595:g} / {t_mid:g} = {target:.3g})"
        )
    k = optimize.brentq(lambda k: ratio(k) - target, low, high, xtol=1e-12)
    rate = stats.gamma.ppf(0.45, k) / t_mid
    alpha_1 = math.sqrt(arias * 2 * g / math.pi * rate**k / special.gamma(k))
    return alpha_1, (k + 1) / 2, rate / 2


def modulating_function(t, alphas) -> np.ndarray:
    """``q(t) = alpha_1 t^(alpha_2 - 1) exp(-alpha_3 t)``, 0 at ``t <= 0``."""
    alpha_1, alpha_2, alpha_3 = alphas
    t = np.asarray(t, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = alpha_1 * np.power(t, alpha_2 - 1) * np.exp(-alpha_3 * t)
    return np.where(t > 0, q, 0.0)


def filter_frequency(site: SiteModel, t) -> np.ndarray:
    """``omega_f(t) = 2 pi (f_mid + f_slope (t - t_mid))``, rad/s, held at or above :data:`F_FLOOR`."""
    return 2 * np.pi * np.maximum(site.f_mid + site.f_slope * (np.asarray(t, float) - site.t_mid), F_FLOOR)


def _kernel_rows(site: SiteModel, lags: range) -> np.ndarray:
    """``h(k dt; omega_f(t_i))`` for the lags ``k`` and the sources ``t_i``, row ``k`` over ``i < n - k``
    (zero beyond): the pulses of ``t_i`` reach ``t_{i+k}``."""
    t = site.times
    n, dt, zeta = t.size, site.dt, site.zeta_f
    omega = filter_frequency(site, t)
    root = math.sqrt(1 - zeta**2)
    rows = np.zeros((len(lags), n))
    for row, k in zip(rows, lags):
        w = omega[: n - k]
        row[: n - k] = w / root * np.exp(-zeta * w * k * dt) * np.sin(w * root * k * dt)
    return rows


def kernel_length(site: SiteModel) -> int:
    """Lags of the filter's kernel: :data:`KERNEL_DECAYS` decay times of the slowest filter of the record."""
    n = site.times.size
    slowest = float(filter_frequency(site, site.times).min())
    return min(n, int(math.ceil(KERNEL_DECAYS / (site.zeta_f * slowest) / site.dt)) + 1)


@lru_cache(maxsize=2)
def _kernel(site: SiteModel) -> tuple[np.ndarray | None, np.ndarray]:
    """The site's kernel rows (None if larger than :data:`KERNEL_CACHE`) and ``sigma_f`` at the sample times."""
    length, n = kernel_length(site), site.times.size
    rows = _kernel_rows(site, range(length)) if length * n <= KERNEL_CACHE else None
    variance = np.zeros(n)
    for k in range(length):
        h = rows[k, : n - k] if rows is not None else _kernel_rows(site, range(k, k + 1))[0, : n - k]
        variance[k:] += h * h
    return rows, np.sqrt(variance)


def filtered_noise(site: SiteModel, u) -> np.ndarray:
    """The unit-variance filtered noise ``sum_i h(t - t_i; omega_f(t_i)) u_i / sigma_f(t)`` at the sample times.

    The kernel is cut after :data:`KERNEL_DECAYS` decay times of the slowest filter of the record; it and
    ``sigma_f`` depend on the site alone, so they are made once for the motions of a suite.
    """
    rows, sigma = _kernel(site)
    n = sigma.size
    total = np.zeros(n)
    for k in range(kernel_length(site)):
        h = rows[k, : n - k] if rows is not None else _kernel_rows(site, range(k, k + 1))[0, : n - k]
        total[k:] += h * u[: n - k]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(sigma > 0, total / sigma, 0.0)


def high_pass(a, dt: float, f_c: float) -> np.ndarray:
    """The acceleration of a critically damped oscillator of frequency ``f_c`` driven by ``a`` (linear between
    samples, at rest at ``t = 0``): ``x'' + 2 omega_c x' + omega_c^2 x = a``, returned ``x''``.

    Exact for the piecewise-linear input, and run at C speed: in the coordinates ``xi = (x, x' + omega_c x)``
    of the double pole's Jordan form, ``xi_2' = -omega_c xi_2 + a`` and ``xi_1' = -omega_c xi_1 + xi_2``, so
    the exact step (a first-order hold, :func:`_jordan_step`) is two first-order recursions of the pole
    ``exp(-omega_c dt)``, each a ``scipy.signal.lfilter``. Not the transfer function ``s^2 / (s + omega_c)^2``
    in ``z``: the double root near 1 of its denominator loses digits as ``1 / (omega_c dt)^2``.
    """
    from scipy import signal  # imported here, as in modulating_parameters

    u = np.asarray(a, float)
    omega = 2 * np.pi * f_c
    phi, before, after = _jordan_step(float(dt), float(f_c))
    pole = [1.0, -phi[1, 1]]
    drive = np.zeros_like(u)
    drive[1:] = before[1] * u[:-1] + after[1] * u[1:]
    xi_2 = signal.lfilter([1.0], pole, drive)
    drive[1:] = phi[0, 1] * xi_2[:-1] + before[0] * u[:-1] + after[0] * u[1:]
    xi_1 = signal.lfilter([1.0], [1.0, -phi[0, 0]], drive)
    return omega**2 * xi_1 - 2 * omega * xi_2 + u


@lru_cache(maxsize=16)
def _jordan_step(dt: float, f_c: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The exact step ``xi_k = Phi xi_(k-1) + G_0 a_(k-1) + G_1 a_k`` of :func:`high_pass`'s oscillator in
    Jordan coordinates for an input linear over the step: ``(Phi, G_0, G_1)``, from the exponential of the
    system augmented with the input and its slope."""
    from scipy.linalg import expm

    omega = 2 * np.pi * f_c
    m = np.zeros((4, 4))
    m[:2, :2] = np.array([[-omega, 1.0], [0.0, -omega]]) * dt
    m[1, 2] = dt
    m[2, 3] = 1.0
    e = expm(m)
    return e[:2, :2], e[:2, 2] - e[:2, 3], e[:2, 3]


def synthesize(site: SiteModel, rng: np.random.Generator, g: float = 9.81) -> np.ndarray:
    """One record of the model at the sample times :attr:`SiteModel.times`, m/s^2."""
    t = site.times
    q = modulating_function(t, modulating_parameters(site.arias, site.d595, site.t_mid, g))
    return high_pass(q * filtered_noise(site, rng.standard_normal(t.size)), site.dt, site.f_c)


def record_rng(seed: int, i: int) -> np.random.Generator:
    """The generator of record ``i`` of the suite of ``seed``: the ``i``-th child of ``SeedSequence(seed)``."""
    return np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(i),)))


def vertical_rng(seed: int, i: int) -> np.random.Generator:
    """The generator of the vertical component of record ``i`` of the suite of ``seed``: ``SeedSequence(seed)``'s
    child ``(i, 1)``, a stream of its own beside the horizontal one's (:func:`record_rng`)."""
    return np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(i), 1)))


def check_vertical_site(site: SiteModel, vertical: SiteModel) -> SiteModel:
    """``vertical`` if it is a :class:`SiteModel` with the sample times of ``site`` (the vertical and horizontal
    samples of a motion pair up one to one), else a one-line :class:`ParameterError`."""
    if not isinstance(vertical, SiteModel):
        raise ParameterError(
            f"vertical_site must be a rocking.model.stochastic.SiteModel (got {type(vertical).__name__})"
        )
    if (vertical.dt, vertical.duration) != (site.dt, site.duration):
        raise ParameterError(
            f"vertical_site must have the horizontal site's dt = {site.dt:g} s and duration = {site.duration:g} s "
            f"(got {vertical.dt:g} s and {vertical.duration:g} s): one vertical sample per horizontal one"
        )
    return vertical


def suite(site: SiteModel, n: int, seed: int, g: float = 9.81) -> list[np.ndarray]:
    """``n`` records of ``site``, reproducible from ``seed``: record ``i`` is the same in a suite of any size.

    Returns
    -------
    list of ndarray
        The accelerations, m/s^2, at the sample times :attr:`SiteModel.times`.
    """
    if not (isinstance(n, (int, np.integer)) and not isinstance(n, bool) and 1 <= n <= 100_000):
        raise ParameterError(f"n must be an integer in [1, 100000] (motions in a suite) (got {n!r})")
    if not (isinstance(seed, (int, np.integer)) and not isinstance(seed, bool) and seed >= 0):
        raise ParameterError(f"seed must be an integer >= 0 (got {seed!r})")
    return [synthesize(site, record_rng(seed, i), g) for i in range(int(n))]
