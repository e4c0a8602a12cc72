"""Intensity measures: exact for a piecewise-linear acceleration, and the closed forms of a sine."""

from __future__ import annotations

import numpy as np
import pytest

from rocking.model.intensity import (
    arias,
    cav,
    measure,
    pga,
    pgv,
    response_spectrum,
    significant_duration,
    velocity,
)
from rocking.model.params import ParameterError
from rocking.model.records import STANDARD_GRAVITY as G

A, OMEGA, CYCLES = 2.0, 2 * np.pi * 2.0, 20  # 2 m/s^2 at 2 Hz, 20 cycles
DT = 1 / (2.0 * 200)  # 200 samples per cycle
T = np.arange(int(CYCLES * 200) + 1) * DT
SINE = A * np.sin(OMEGA * T)


def test_measures_of_a_piecewise_linear_record_are_exact():
    """a = (0, 1, -1, 0) m/s^2 at 1 s: int a^2 = 1, int |a| = 1.5 (the crossing halves a triangle), v peaks at
    0.75 m/s where a crosses zero."""
    a = np.array([0.0, 1.0, -1.0, 0.0])
    assert arias(a, 1.0) == pytest.approx(np.pi / (2 * G))
    assert cav(a, 1.0) == pytest.approx(1.5)
    np.testing.assert_allclose(velocity(a, 1.0), [0.0, 0.5, 0.5, 0.0])
    assert pgv(a, 1.0) == pytest.approx(0.75)
    assert pga(a, 1.0) == 1.0


def test_measures_of_a_sine_match_their_closed_forms():
    """a = A sin(omega t) over n cycles: PGV = 2 A / omega, I_a = pi A^2 t / (4 g), CAV = 4 n A / omega,
    D_5-95 = 0.9 t (the energy grows evenly), to the interpolation error O((omega dt)^2) = 1e-3 or less."""
    duration = T[-1]
    assert pga(SINE, DT) == pytest.approx(A)
    assert pgv(SINE, DT) == pytest.approx(2 * A / OMEGA, rel=1e-4)
    assert arias(SINE, DT) == pytest.approx(np.pi * A**2 * duration / (4 * G), rel=5e-4)
    assert cav(SINE, DT) == pytest.approx(4 * CYCLES * A / OMEGA, rel=1e-4)
    assert significant_duration(SINE, DT) == pytest.approx(0.9 * duration, rel=2e-3)
    assert measure("cav", SINE, DT) == cav(SINE, DT)


def test_response_spectrum_at_resonance_and_of_a_stiff_oscillator():
    """At resonance after 20 cycles (transient e^{-2 pi zeta 20} = 0.2 % left) the steady amplitude is
    A / (2 zeta omega^2): PSA = A / (2 zeta) = 10 A. A stiff oscillator follows the ground: PSA -> PGA."""
    psa = response_spectrum(SINE, DT, [2 * np.pi / OMEGA, 0.002], zeta=0.05)
    assert psa[0] == pytest.approx(A / (2 * 0.05), rel=0.01)
    assert psa[1] == pytest.approx(A, rel=0.01)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: pga([1.0], 0.01), r"at least 2 samples"),
        (lambda: arias([0.0, np.nan, 1.0], 0.01), r"the sample 1 of the record is not finite"),
        (lambda: cav([0.0, 1.0], 0.0), r"^dt must be > 0 s"),
        (lambda: response_spectrum([0.0, 1.0], 0.01, [-1.0]), r"periods must be > 0 s"),
        (lambda: measure("pgd", [0.0, 1.0], 0.01), r"measure must be one of pga, pgv, arias, cav"),
        (lambda: significant_duration([0.0, 0.0], 0.01), r"zero Arias intensity"),
    ],
)
def test_bad_input_is_refused_in_one_line(call, message):
    with pytest.raises(ParameterError, match=message):
        call()


def test_response_spectrum_agrees_with_an_independent_fine_time_step_solution():
    """a = 0.3 g sin(2 pi t), 10 cycles at dt = 0.005 s: PSA (5 %) at T = 0.1 .. 5 s from a separate solution of the
    oscillator under the analytic sine at dt = 1e-4 s (scipy.signal.lsim; computed once for this test); eqsig's
    Nigam-Jennings spectrum agreed with those to 3e-4 as well."""
    a = 0.3 * G * np.sin(2 * np.pi * np.arange(2001) * 0.005)
    reference = [3.06781849, 3.96074211, 4.76620522, 28.15769537, 2.38053565, 0.61035478]
    psa = response_spectrum(a, 0.005, [0.1, 0.3, 0.5, 1.0, 2.0, 5.0])
    np.testing.assert_allclose(psa, reference, rtol=5e-4)  # largest: 2.9e-4 at T = 0.1 s (20 samples a period)
