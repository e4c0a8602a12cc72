"""The closed form of pure sliding (rocking.reference.sliding) against an integration and outside figures."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rocking
from rocking.model.checks import ParameterError
from rocking.reference.sliding import one_sine_sliding, slide_rock

G = 9.81


def integrated(a_g, omega_g, mu_s, mu_k, sign):
    """Peak and residual slip by solve_ivp: stick while |ddx_g| <= mu_s g, slide by Coulomb's law, each
    episode ended by the event du = 0 (an integration, not the closed form)."""
    T = 2 * np.pi / omega_g
    ag = lambda t: sign * a_g * np.sin(omega_g * t) if t <= T else 0.0  # noqa: E731
    t, u, peak = 0.0, 0.0, 0.0
    ts = np.linspace(0, T, 200001)
    while True:
        after = ts[(ts >= t) & (np.abs(sign * a_g * np.sin(omega_g * ts)) > mu_s * G)]
        if after.size == 0:
            return peak, u
        t0 = after[0]
        if abs(ag(t)) > mu_s * G:  # an episode that ends beyond the static friction reverses at once
            t0 = t
        elif t0 > t:  # the crossing to the grid's resolution, then exactly
            t0 = (np.arcsin(mu_s * G / a_g) + np.pi * np.floor(omega_g * t0 / np.pi)) / omega_g
        d = -np.sign(ag(t0))

        def rhs(t, y, d=d):
            return [y[1], -ag(t) - mu_k * G * d]

        def stop(t, y, d=d, t0=t0):
            return y[1] if t > t0 + 1e-9 else d

        stop.terminal, stop.direction = True, -d
        sol = solve_ivp(rhs, (t0, T), [u, 0.0], rtol=1e-12, atol=1e-15, events=stop, max_step=T / 2000)
        u, v, t = sol.y[0, -1], sol.y[1, -1], sol.t[-1]
        if sol.status != 1:  # sliding at the pulse's end: a constant deceleration stops it
            tau = abs(v) / (mu_k * G)
            u, t = u + v * tau - mu_k * G * d * tau**2 / 2, T + tau
        peak = max(peak, abs(u))
        if t >= T:
            return peak, u


@pytest.mark.parametrize(
    ("a_g", "omega_g", "mu_s", "mu_k", "sign"),
    [
        (0.4 * G, 4 * np.pi, 0.2, 0.2, 1),
        (0.4 * G, 4 * np.pi, 0.3, 0.25, -1),
        (0.8 * G, 6.0, 0.2, 0.15, 1),
        (0.3 * G, 20.0, 0.1, 0.1, -1),
    ],
)
def test_closed_form_matches_an_integration(a_g, omega_g, mu_s, mu_k, sign):
    r = one_sine_sliding(a_g, omega_g, mu_s, mu_k, sign=sign)
    peak, end = integrated(a_g, omega_g, mu_s, mu_k, sign)
    assert r.slides >= 1
    assert r.u_max == pytest.approx(peak, rel=1e-8, abs=1e-12)
    assert r.u_end == pytest.approx(end, rel=1e-8, abs=1e-12)


def test_the_issue_figures_of_an_independent_sliding_model():
    # Issue 37: an independent sliding-only model gives 31.45 mm peak and 1.57 mm residual slip for the block
    # H = 2, B = 0.5 under a_g = 0.4 g, T = 0.5 s at mu = 0.2 (both given to four digits).
    r = one_sine_sliding(0.4 * G, 2 * np.pi / 0.5, 0.2)
    assert r.u_max * 1e3 == pytest.approx(31.45, abs=0.005)
    assert r.u_end * 1e3 == pytest.approx(1.57, abs=0.005)
    assert r.t_start == pytest.approx(np.arcsin(0.2 / 0.4) / (4 * np.pi), rel=1e-15)
    assert r.slides == 2  # forward, then back while the pulse reverses


def test_no_slip_below_the_static_friction():
    r = one_sine_sliding(0.19 * G, 10.0, 0.2)
    assert (r.slides, r.u_max, r.u_end) == (0, 0.0, 0.0) and np.isnan(r.t_start)


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"mu_s": -0.1}, "mu_s"),
        ({"mu_k": 0.5}, "mu_k"),
        ({"a_g": np.nan}, "a_g"),
        ({"omega_g": 0}, "omega_g"),
        ({"sign": 2}, "sign"),
    ],
)
def test_bad_input_is_one_line(kwargs, word):
    args = {"a_g": 3.0, "omega_g": 10.0, "mu_s": 0.2, **kwargs}
    with pytest.raises(ParameterError, match=rf"^{word} must be"):
        one_sine_sliding(**args)


def _block(mu, **kw):
    M, B, H = 1000.0, 0.5, 2.0
    return slide_rock(M, M * (B**2 + H**2) / 12, B, H, 0.0, G, 0.4 * G, 4 * np.pi, mu, **kw)


def test_slide_rock_reference_slides_alone_as_the_closed_form():
    r, closed = _block(0.2), one_sine_sliding(0.4 * G, 4 * np.pi, 0.2)
    assert (r.uplifts, r.status, r.slides) == (0, "rest", closed.slides)
    assert r.u_max == pytest.approx(closed.u_max, rel=1e-8)
    assert r.u_end == pytest.approx(closed.u_end, rel=1e-8)


def test_slide_rock_reference_rocks_as_the_project_where_the_floor_holds():
    """mu = 0.7 never slips (issue 37's table: rocking from mu = 0.3): the project's response (mu = inf)."""
    r = _block(0.7, t_after=3.0)
    block = rocking.Block(H=2.0, B=0.5, M=1000.0)
    p = rocking.simulate(block, None, rocking.OneSinePulse(a_g=0.4 * G, omega_g=4 * np.pi), rtol=1e-11, t_max=0.5 + 3.0)
    assert (r.slides, r.u_max, r.uplifts) == (0, 0.0, p.uplifts)
    assert r.theta_max == pytest.approx(p.theta_max, rel=1e-7)


def test_slide_rock_reference_slides_and_rocks_near_b_over_h():
    """Issue 37's table: at mu = 0.26 (just above B/H = 0.25) the block lifts and its pivot slips."""
    r = _block(0.26)
    assert r.uplifts >= 1 and r.slides >= 1 and r.u_max > 1e-3 and 0.1 < r.theta_max / np.arctan(0.25) < 0.36


@pytest.mark.parametrize(("mu", "first"), [(0.2, "slides"), (0.24, "slides"), (0.26, "rocks"), (0.4, "rocks")])
def test_shenton_initiation_from_rest_under_a_slow_ramp(mu, first):
    """Shenton 1996: a symmetric bare block slides first if mu_s < B/H, rocks first if mu_s > B/H (B/H = 0.25);
    a slow one-sine (T = 20 s) is a ramp at its start."""
    M, B, H = 1000.0, 0.5, 2.0
    r = slide_rock(M, M * (B**2 + H**2) / 12, B, H, 0.0, G, 0.3 * G, 2 * np.pi / 20, mu, t_after=0.0)
    assert r.first == first
