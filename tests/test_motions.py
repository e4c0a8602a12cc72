"""The ground motions of docs/model.md section 12: formulas, peaks, sampled records, batches and refusals.

Expected values are typed by hand from docs/model.md section 12; nothing expected is read from
rocking.model.motion.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rocking
from rocking import (
    Block,
    Damper,
    MavroeidisPapageorgiou,
    OneCosinePulse,
    OneSinePulse,
    ParameterError,
    RickerWavelet,
    SampledMotion,
)
from rocking.sim import c_backend
from rocking.sim.cases import pulse_cases, run_cases, sampled_cases
from rocking.sim.problem import make_problem

BLOCK = Block.reference()
DAMPER = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
A_G, W = 2.0, 3.0  # m/s^2, rad/s


def _mp_by_hand(t, gamma, nu):
    phi = W * (t - gamma * math.pi / W)
    v = (1 / gamma) * math.sin(phi / gamma) * math.cos(phi + nu) + (1 + math.cos(phi / gamma)) * math.sin(phi + nu)
    return -0.5 * v


@pytest.mark.parametrize("t", [0.1, 0.77, 1.5, 1.9])
def test_each_family_is_its_formula(t):
    """docs/model.md section 12, typed by hand, at a few points inside [0, t_p]; the sign multiplies it all."""
    u = W * (t - 8 / W) / 2
    v = W * (t - 4 * math.sqrt(6) / W) / math.sqrt(6)  # the antisymmetric wavelet's u
    u_star = math.sqrt((3 - math.sqrt(6)) / 2)
    cases = [
        (OneSinePulse(A_G, W, psi=0.3), math.sin(W * t + 0.3)),
        (OneCosinePulse(A_G, W), math.cos(W * t)),
        (RickerWavelet(A_G, W), (1 - 2 * u**2) * math.exp(-(u**2))),
        (RickerWavelet(A_G, W, antisymmetric=True),
         -v * (3 - 2 * v**2) * math.exp(-(v**2)) / (u_star * (3 - 2 * u_star**2) * math.exp(-(u_star**2)))),
        (MavroeidisPapageorgiou(A_G, W, gamma_mp=2.0, nu=0.7), _mp_by_hand(t, 2.0, 0.7)),
    ]  # fmt: skip
    for motion, f in cases:
        assert motion.acceleration(t) == pytest.approx(A_G * f, rel=1e-12, abs=1e-15), motion
        mirrored = type(motion)(**{**motion.__dict__, "sign": -1})
        assert mirrored.acceleration(t) == pytest.approx(-A_G * f, rel=1e-12, abs=1e-15), motion


def test_durations_and_zero_outside():
    """t_p: 2 pi / omega_g (cosine), 16 / omega_g (Ricker), 8 sqrt 6 / omega_g (antisymmetric Ricker),
    2 gamma pi / omega_g (MP); 0 outside [0, t_p]."""
    mp = MavroeidisPapageorgiou(A_G, W, gamma_mp=2.5)
    for motion, t_p in [
        (OneCosinePulse(A_G, W), 2 * math.pi / W),
        (RickerWavelet(A_G, W), 16 / W),
        (RickerWavelet(A_G, W, antisymmetric=True), 8 * math.sqrt(6) / W),
        (mp, 2 * 2.5 * math.pi / W),
    ]:
        assert motion.t_p == pytest.approx(t_p, rel=1e-15)
        assert motion.acceleration([-1e-9, t_p * (1 + 1e-9), 10 * t_p]).tolist() == [0.0, 0.0, 0.0]
    assert mp.acceleration(0.0) == pytest.approx(0.0, abs=1e-12) and abs(mp.acceleration(mp.t_p)) < 1e-12


def test_peak_one_shapes_peak_at_a_g():
    """One-sine, one-cosine and both Ricker wavelets peak at a_g; the MP pulse stays below it."""
    for motion in (
        OneSinePulse(A_G, W),
        OneCosinePulse(A_G, W),
        RickerWavelet(A_G, W),
        RickerWavelet(A_G, W, antisymmetric=True),
    ):
        t = np.linspace(0, motion.t_p, 200_001)
        assert np.max(np.abs(motion.acceleration(t))) == pytest.approx(A_G, rel=1e-9), motion
    anti = RickerWavelet(A_G, W, antisymmetric=True)
    t = np.linspace(0, anti.t_p, 20_001)
    # First lobe positive: the peak a_g before the centre (the two main lobes are equal: no argmax of |a|).
    assert np.max(anti.acceleration(t[t < anti.t_c])) == pytest.approx(A_G, rel=1e-6)
    mp = MavroeidisPapageorgiou(A_G, W, gamma_mp=2.0, nu=1.0)
    assert 0.5 * A_G < np.max(np.abs(mp.acceleration(np.linspace(0, mp.t_p, 20_001)))) <= A_G


PEAKED = [
    OneSinePulse(A_G, W),
    OneSinePulse(A_G, W, psi=5.5, sign=-1),
    OneCosinePulse(A_G, W),
    RickerWavelet(A_G, W, sign=-1),
    RickerWavelet(A_G, W, antisymmetric=True),
    *(MavroeidisPapageorgiou(A_G, W, gamma_mp=g, nu=nu) for g, nu in ((1.2, 0.0), (2.0, 1.0), (3.0, 4.0), (5.0, 2.5))),
    SampledMotion(np.sin(np.linspace(0.0, 7.0, 301)), dt=0.01, scale=3.0, sign=-1),
]


@pytest.mark.parametrize("motion", PEAKED, ids=lambda m: type(m).__name__)
def test_peak_is_the_largest_acceleration_on_a_fine_grid(motion):
    """rocking.model.motion.peak against a 2,000,001-point scan of the motion: never below it, and within
    1e-9 of it (the scan's own error at a smooth maximum is (step)^2 / 2 times the curvature); a sampled
    motion's peak is at a sample, its scale times the largest |sample|."""
    from rocking.model.motion import peak

    if isinstance(motion, SampledMotion):
        assert peak(motion) == 3.0 * np.max(np.abs(np.sin(np.linspace(0.0, 7.0, 301))))
        return
    scanned = np.max(np.abs(motion.acceleration(np.linspace(0.0, motion.t_p, 2_000_001))))
    assert peak(motion) >= scanned * (1 - 1e-12)
    assert peak(motion) == pytest.approx(scanned, rel=1e-9)


@pytest.mark.parametrize(("gamma", "nu"), [(1.2, 0.0), (2.0, 1.0), (3.0, 4.0), (5.0, 2.5), (8.0, 6.0)])
def test_listed_mp_extrema_are_where_the_shape_turns(gamma, nu):
    """Each listed extremum of the MP shape is a zero of its slope by central differences of the formula typed
    here (not the library's slope), and every turn of a fine scan lies next to a listed one."""
    from rocking.model.motion import mp_extrema

    def shape(phi):
        return -0.5 * (np.sin(phi / gamma) / gamma * np.cos(phi + nu) + (1 + np.cos(phi / gamma)) * np.sin(phi + nu))

    listed = mp_extrema(gamma, nu)
    h = 1e-6
    slope = (shape(listed + h) - shape(listed - h)) / (2 * h)
    assert np.max(np.abs(slope)) < 1e-8
    phi = np.linspace(-gamma * np.pi, gamma * np.pi, 400_001)
    d = np.diff(shape(phi))
    turns = phi[1:-1][np.sign(d[1:]) != np.sign(d[:-1])]
    assert len(turns) == len(listed)
    assert np.max(np.abs(turns - listed)) < 2 * (phi[1] - phi[0])


def fourier_peak_period(motion, n=4096, pad=1024) -> float:
    """Period (s) of the peak of |FFT| of ``motion`` sampled at ``n`` points on [0, t_p], zero-padded ``pad``-fold.

    The padding sets the frequency step to ``1 / (pad t_p)``; the parabola through the peak bin and its
    neighbours places the peak between bins.
    """
    t = np.linspace(0.0, motion.t_p, n)
    spectrum = np.abs(np.fft.rfft(motion.acceleration(t), n * pad))
    k = int(np.argmax(spectrum[1:])) + 1  # bin 0 (the mean) is no period
    left, mid, right = spectrum[k - 1 : k + 2]
    shift = 0.5 * (left - right) / (left - 2 * mid + right)
    dt = motion.t_p / (n - 1)
    return n * pad * dt / (k + shift)  # bin k is the frequency k / (n pad dt)


#: docs/model.md section 12, "Fourier peaks": the period of each family's spectral peak over T_g = 2 pi / omega_g.
FOURIER_PEAKS = [
    (OneSinePulse(A_G, W), 1.194),
    (OneCosinePulse(A_G, W), 0.888),
    (RickerWavelet(A_G, W), 1.0),
    (RickerWavelet(A_G, W, antisymmetric=True), 1.0),
    (MavroeidisPapageorgiou(A_G, W, gamma_mp=1.5), 0.788),
    (MavroeidisPapageorgiou(A_G, W, gamma_mp=2.0), 0.860),
    (MavroeidisPapageorgiou(A_G, W, gamma_mp=3.0), 0.927),
    (MavroeidisPapageorgiou(A_G, W, gamma_mp=5.0), 0.971),
]


@pytest.mark.parametrize(
    ("motion", "ratio"), FOURIER_PEAKS, ids=["sine", "cosine", "ricker", "ricker_anti", "mp1.5", "mp2", "mp3", "mp5"]
)
def test_fourier_peak_of_each_family(motion, ratio):
    """The period of the spectral peak is the table's multiple of T_g: T_g itself for both Ricker wavelets
    (Vassiliou and Makris 2011's T_p), whatever the family's omega_g means otherwise."""
    assert fourier_peak_period(motion) / motion.T_g == pytest.approx(ratio, abs=1.5e-3)


def test_from_nondim_sets_beta_and_Omega():
    for cls, shape in [
        (OneCosinePulse, {}),
        (RickerWavelet, {"antisymmetric": True}),
        (MavroeidisPapageorgiou, {"gamma_mp": 3.0, "nu": 0.5}),
    ]:
        motion = cls.from_nondim(BLOCK, beta=2.0, Omega=3.0, sign=-1, **shape)
        assert (motion.beta(BLOCK), motion.Omega(BLOCK), motion.sign) == (pytest.approx(2.0), pytest.approx(3.0), -1)
        assert cls.from_period(1.0, 0.5, **shape).omega_g == pytest.approx(4 * math.pi)


# --------------------------------------------------------------------------- #
# Sampled motions                                                              #
# --------------------------------------------------------------------------- #


def test_sampled_motion_interpolates_and_scales():
    a = np.array([0.0, 1.0, -2.0, 0.5])
    motion = SampledMotion(a, t=[0.0, 0.1, 0.2, 0.3 + 1e-9], scale=2.0, sign=-1)
    assert motion.dt == pytest.approx(0.1) and motion.t_p == pytest.approx(0.3)
    assert motion.acceleration([0.0, 0.05, 0.1, 0.25, 0.31]) == pytest.approx([0.0, -1.0, -2.0, 1.5, 0.0])
    assert motion.pga == 4.0 and motion.scaled(0.5).pga == 2.0 and motion.scaled_to_pga(9.0).pga == pytest.approx(9.0)
    assert motion.scaled(3.0).a is motion.a  # the samples are shared, not copied
    with pytest.raises(ValueError):
        motion.a[0] = 1.0


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"a": [0.0, np.nan, 1.0], "dt": 0.1}, r"^a must be finite: a\[1\] = nan$"),
        ({"a": [0.0, 1.0, np.inf], "dt": 0.1}, r"^a must be finite: a\[2\] = inf$"),
        ({"a": [], "dt": 0.1}, r"^a must hold at least 2 samples \(got 0\)$"),
        ({"a": [1.0, 2.0], "dt": -0.01}, r"^dt must be in \[1e-06, 10\] s \(got -0.01\)"),
        ({"a": [1.0] * 6, "t": [0.0, 0.1, 0.2, 0.33, 0.41, 0.5]}, r"^t must be uniformly spaced .*t\[3\] - t\[2\]"),
        ({"a": [1.0, 2.0, 3.0], "t": [0.1, 0.2, 0.3]}, r"^t must start at 0"),
        ({"a": [1.0, 2.0]}, r"^give exactly one of dt"),
        ({"a": [1.0, 2.0], "dt": 0.1, "scale": -1.0}, r"^scale must be >= 0"),
        ({"a": [1.0, 2.0], "dt": 0.1, "sign": 0}, r"^sign must be \+1 or -1"),
    ],
)
def test_bad_samples_are_refused_in_one_line(kwargs, message):
    with pytest.raises(ParameterError, match=message) as info:
        SampledMotion(**kwargs)
    assert "\n" not in str(info.value)


def _sampled_sine(pulse: OneSinePulse, n: int) -> SampledMotion:
    t = np.arange(n + 1) * (pulse.t_p / n)
    return SampledMotion(pulse.acceleration(t), dt=pulse.t_p / n)


def test_a_sampled_one_sine_converges_to_the_analytic_one():
    """Linear interpolation of the one-sine at dt = T/N, N = 50 ... 400: theta_max and the first impact's time
    converge to the analytic pulse's at order 2 (the interpolation error, dt^2)."""
    pulse = OneSinePulse.from_nondim(BLOCK, beta=1.3, Omega=2.0)  # rocks, no overturning: theta_max tells

    def first_impact(motion):
        r = rocking.simulate(BLOCK, DAMPER, motion, backend="c", rtol=1e-11, t_after=2.0, record=True, record_dt=0)
        h = r.history
        i = next(i for i in range(1, len(h["t"])) if h["t"][i] == h["t"][i - 1] and h["phase"][i - 1] != 0)
        return r.theta_max, h["t"][i]

    exact = np.array(first_impact(pulse))
    errors = np.array([np.abs(np.array(first_impact(_sampled_sine(pulse, n))) - exact) for n in (50, 100, 200, 400)])
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(errors[-1] < 1e-3 * exact)
    assert np.all((orders > 1.9) & (orders < 2.1)), orders  # measured 1.998 - 2.007


def test_sampled_batch_shares_one_buffer_and_is_the_single_runs():
    """sampled_cases: every case points at the motion's samples (no copy); case by case the runs of motion.scaled."""
    rng = np.random.default_rng(3)
    record = SampledMotion(np.convolve(rng.standard_normal(300), np.ones(8) / 8, "same") * 3.0, dt=0.01)
    scales, signs = np.array([0.5, 1.0, 2.0]), np.array([1, -1, 1])
    cases = sampled_cases(BLOCK, record, scales, sign=signs, gamma=0.05, h=0.05, t_after=3.0)
    packed = cases.settings["samples"]
    assert packed.buffer.ctypes.data == record.a.ctypes.data and len(set(packed.pointers().tolist())) == 1
    batch = run_cases(cases, "c", threads=2)
    for i in range(3):
        one = rocking.simulate(
            BLOCK,
            DAMPER,
            record.scaled(scales[i])
            if signs[i] > 0
            else SampledMotion(record.a, dt=record.dt, scale=scales[i], sign=-1),
            backend="c",
            t_after=3.0,
        )
        assert (bool(batch["overturned"][i]), int(batch["impacts"][i])) == (one.overturned, one.impacts)
        assert batch["theta_max"][i] == pytest.approx(one.theta_max, rel=1e-12)


@pytest.mark.parametrize("motion", ["cosine", "ricker", "ricker_anti", "mp"])
def test_pulse_cases_of_each_family_are_the_single_runs(motion):
    Omega, beta = np.array([2.0, 5.0]), np.array([2.0, 6.0])
    shape = {"gamma_mp": 2.0, "nu": 0.4} if motion == "mp" else {}
    batch = run_cases(pulse_cases(BLOCK, Omega, beta, gamma=0.05, h=0.05, motion=motion, **shape), "c", threads=1)
    cls, fixed = {
        "cosine": (OneCosinePulse, {}),
        "ricker": (RickerWavelet, {}),
        "ricker_anti": (RickerWavelet, {"antisymmetric": True}),
        "mp": (MavroeidisPapageorgiou, {"gamma_mp": 2.0, "nu": 0.4}),
    }[motion]
    for i in range(2):
        one = rocking.simulate(
            BLOCK, DAMPER, cls.from_nondim(BLOCK, beta=beta[i], Omega=Omega[i], **fixed), backend="c"
        )
        assert (bool(batch["overturned"][i]), int(batch["impacts"][i])) == (one.overturned, one.impacts)
        assert batch["theta_max"][i] == pytest.approx(one.theta_max, rel=1e-12)


# --------------------------------------------------------------------------- #
# Refusals                                                                     #
# --------------------------------------------------------------------------- #


class LouderSine(OneSinePulse):
    def acceleration(self, t):
        return 2 * super().acceleration(t)


@pytest.mark.parametrize(
    "pulse", [LouderSine(1.0, 2.0), lambda t: 0.0, "sine", None], ids=["subclass", "function", "name", "none"]
)
def test_anything_but_a_registered_motion_is_refused(pulse):
    """A subclass could override acceleration, which neither back end would ever call: refused, never replaced."""
    with pytest.raises(ParameterError, match=r"^pulse must be one of rocking.OneSinePulse, ") as info:
        rocking.simulate(BLOCK, None, pulse)
    assert "\n" not in str(info.value)
    if isinstance(pulse, LouderSine):
        assert "a subclass of rocking.OneSinePulse" in str(info.value)
        with pytest.raises(ParameterError, match="subclass"):
            make_problem(BLOCK, None, pulse)


def test_unknown_family_and_shape_options_are_refused():
    with pytest.raises(ParameterError, match=r"^motion must be one of sine, cosine, ricker, ricker_anti, mp"):
        pulse_cases(BLOCK, [2.0], [2.0], motion="triangle")
    with pytest.raises(ParameterError, match=r"^psi is the phase of the one-sine pulse"):
        pulse_cases(BLOCK, [2.0], [2.0], motion="ricker", psi=1.0)
    with pytest.raises(ParameterError, match=r"^motion 'mp' needs gamma_mp"):
        pulse_cases(BLOCK, [2.0], [2.0], motion="mp")
    with pytest.raises(ParameterError, match=r"^gamma_mp must be in \(1, 20\]"):
        pulse_cases(BLOCK, [2.0], [2.0], motion="mp", gamma_mp=0.5)
    with pytest.raises(ParameterError, match=r"^gamma_mp must be in \(1, 20\]"):
        MavroeidisPapageorgiou(1.0, 2.0, gamma_mp=1.0)
    with pytest.raises(ParameterError, match=r"^antisymmetric must be True or False"):
        RickerWavelet(1.0, 2.0, antisymmetric="yes")


def test_the_c_library_refuses_a_sampled_case_without_samples():
    """sim.c's own check (Python checks first): a sampled case whose samples are missing fails, it is not read."""
    problem = make_problem(BLOCK, None, SampledMotion([0.0, 1.0, 0.0], dt=0.1))
    lib = c_backend.library(problem.model)
    keep = []
    case = c_backend._case(problem.settings(), keep)
    case.samples = None
    result = c_backend._Result()
    assert lib.lib.rocking_simulate(problem.p.ctypes.data, case, result, None, None) == -1
