"""Vertical ground motion (docs/model.md section 14): outside facts on both back ends."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

import rocking
from rocking import Block, Damper, OneSinePulse, RickerWavelet, SampledMotion, Vertical
from rocking.model.loading import load_model
from rocking.model.motion import RICKER_CUT, RICKER_PHASE, SHAPES, margin_extrema
from rocking.sim.cases import pulse_cases, run_cases
from rocking.sim.problem import resolve, vertical_of

BLOCK = Block.reference()
DAMPER = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
#: A model without flight functions (docs/model.md section 16): its runs still end with the status flight.
PENDULUM = dict(m=0.05 * BLOCK.M, l=0.5, x_p=0.0, y_p=BLOCK.H + 0.55, k_phi=0.0, c_phi=20.0)


@pytest.fixture(params=["c", "numpy"])
def backend(request) -> str:
    return request.param


#: Settings that do not follow from g, so that a block under another gravity runs with the same ones.
SAME = {"dtheta_rest": 1e-4, "energy_rest": 1e-6, "rtol": 1e-10}


def _one_sine_samples(beta: float, Omega: float, dt: float) -> tuple[np.ndarray, float]:
    """A one-sine sampled at ``dt``: the horizontal motion of the constant-vertical runs, and its length."""
    pulse = OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega)
    t = np.arange(0.0, pulse.t_p + dt / 2, dt)
    return pulse.acceleration(t), float(t[-1])


@pytest.mark.parametrize("damper", [None, DAMPER], ids=["bare", "damper"])
@pytest.mark.parametrize("a_v", [-2.5, 3.0])
def test_a_constant_vertical_acceleration_is_another_gravity(backend, damper, a_v):
    """A constant ``a_v`` over the whole run is the same block under gravity ``g + a_v``."""
    a, t_p = _one_sine_samples(3.0, 4.0, 0.002)
    shaken = SampledMotion(a, dt=0.002, a_v=np.full(a.size, a_v))
    heavier = dataclasses.replace(BLOCK, g=BLOCK.g + a_v)
    runs = [
        rocking.simulate(block, damper, motion, backend=backend, t_max=t_p, **SAME)
        for block, motion in ((BLOCK, shaken), (heavier, SampledMotion(a, dt=0.002)))
    ]
    assert runs[0].status == runs[1].status and runs[0].impacts == runs[1].impacts
    assert runs[0].uplifts == runs[1].uplifts > 0
    for name in ("theta_max", "x_max", "t_end"):
        assert getattr(runs[0], name) == pytest.approx(getattr(runs[1], name), rel=1e-7, abs=1e-12), name


@pytest.mark.parametrize(("ratio", "phase"), [(0.5, 0.0), (1.0, 0.0), (0.5, math.pi)])
def test_the_bare_block_uplifts_where_the_ground_overcomes_the_effective_gravity(backend, ratio, phase):
    """Bare symmetric block in full contact: uplift at the first ``|ddx_g| = (g + ddy_g) tan(alpha)``, here for a
    one-sine with a synchronous vertical pulse, in phase (the ground rising: later) or opposed (earlier)."""
    block = Block(H=2.0, B=0.5, M=1000.0)
    pulse = OneSinePulse.from_nondim(block, beta=1.5, Omega=3.0, vertical=Vertical(ratio, phase))
    settings = resolve(block, None, pulse, {})[2]

    def margin(t):
        return abs(pulse.acceleration(t)) - (block.g + vertical_of(settings, t)) * math.tan(block.alpha)

    grid = np.linspace(0.0, pulse.t_p, 2001)
    first = int(np.flatnonzero([margin(t) >= 0.0 for t in grid])[0])
    expected = brentq(margin, grid[first - 1], grid[first], xtol=1e-14)
    r = rocking.simulate(block, None, pulse, backend=backend, record=True, record_dt=0.01)
    events = r.events()
    uplift = float(events["t"][list(events["kind"]).index("uplift")])
    assert uplift == pytest.approx(expected, abs=1e-9)
    plain = math.asin(1 / 1.5) / pulse.omega_g  # without the vertical pulse
    assert (uplift > plain) == (phase == 0.0)


#: A vertical lead whose uplift margin peaks between two extrema of ``ddx_g``: ``(motion, family, ratio, lead,
#: Omega)``, ``motion`` the name :func:`pulse_cases` takes.
BRIEF = [("sine", OneSinePulse, 1.0, 2.0, 3.0), ("ricker", RickerWavelet, 1.0, 2.0, 3.0)]


@pytest.mark.parametrize(("motion", "family", "ratio", "lead", "Omega"), BRIEF, ids=["sine", "ricker"])
def test_a_brief_uplift_between_two_extrema_of_the_ground_is_not_stepped_over(
    backend, motion, family, ratio, lead, Omega
):
    """With a vertical lead the margin ``ddx_g - (g + ddy_g) tan(alpha)`` peaks where no extremum of ``ddx_g``
    is: scaled to peak 1e-6 above 0 there, it is positive for about 1e-3 rad of phase only, and the bare block
    uplifts at its first root (docs/model.md section 14), found here by Brent's method on the motion itself."""
    block = Block(H=2.0, B=0.5, M=1000.0)
    tan = math.tan(block.alpha)
    unit = family.from_nondim(block, beta=1.0, Omega=Omega)
    w = unit.omega_g

    def shape_margin(t):  # per unit of a_g: ddx_g - ddy_g tan(alpha), the vertical leading by lead / omega_g
        return (unit.acceleration(t) - ratio * tan * unit.acceleration(t + lead / w)) / unit.a_g

    # The pulse's largest shape margin (its highest peak on a grid of 1e-3 rad, then polished), away from its end.
    grid = np.linspace(0.0, unit.t_p - lead / w, 20001)
    top = grid[int(np.argmax(shape_margin(grid)))]
    peak = minimize_scalar(
        lambda t: -shape_margin(t), bounds=(top - 1e-3 / w, top + 1e-3 / w), method="bounded", options={"xatol": 1e-14}
    )
    beta = (1.0 + 1e-6) / float(shape_margin(peak.x))
    pulse = family.from_nondim(block, beta=beta, Omega=Omega, vertical=Vertical(ratio, lead))
    assert pulse.a_g * ratio < block.g  # the base stays on the ground

    def margin(t, direction=1.0):
        return direction * pulse.acceleration(t) - (block.g + ratio * pulse.acceleration(t + lead / w)) * tan

    ground = pulse.acceleration(grid)
    before = grid[int(np.argmax(ground[grid < peak.x]))]  # the last maximum of ddx_g before the peak
    assert margin(before) < 0.0 < margin(peak.x) and w * (peak.x - before) > 0.01
    # Nothing lifts the block earlier: the margins of both directions are negative until then.
    assert max(margin(grid[grid <= before])) < 0.0 and max(margin(grid[grid < peak.x], -1.0)) < 0.0
    expected = brentq(margin, before, peak.x, xtol=1e-15)
    r = rocking.simulate(block, None, pulse, backend=backend, record=True, record_dt=0.01)
    events = r.events()
    assert list(events["kind"][:1]) == ["uplift"]
    assert float(events["t"][0]) == pytest.approx(expected, abs=1e-11)
    # A batch lists the same extrema: its case is the single run, uplift included.
    cases = pulse_cases(block, Omega, beta, motion=motion, vertical=Vertical(ratio, lead))
    assert np.array_equal(cases.settings["extrema"].buffer, resolve(block, None, pulse, {})[2]["extrema"])
    assert run_cases(cases, backend)["uplifts"][0] == r.uplifts


@pytest.mark.parametrize(
    ("family", "gamma", "nu"), [("ricker", 0.0, 0.0), ("ricker_anti", 0.0, 0.0), ("mp", 2.0, 0.5), ("mp", 3.0, 2.0)]
)
@pytest.mark.parametrize(("ratio", "lead"), [(0.5, 1.0), (2.0, 4.0)])
def test_every_positive_peak_of_an_uplift_margin_is_listed(family, gamma, nu, ratio, lead):
    """Each local maximum of ``d s f(phi) - ratio tan_d f(phi + lead)`` above 0 (where an amplitude can lift the
    block) on a grid of 1e-4 rad is within a grid step of a listed extremum (an eccentric block's two tangents)."""
    tans = (0.2, 0.3)
    listed = margin_extrema(family, gamma, nu, ratio, lead, tans)
    half = gamma * math.pi if family == "mp" else RICKER_PHASE[family] * RICKER_CUT
    phi = np.arange(-half, half, 1e-4)
    f = SHAPES[family]
    for tan in tans:
        for ds in (1.0, -1.0):
            F = ds * f(phi, 1.0, nu, 0.0, gamma, np) - ratio * tan * f(phi + lead, 1.0, nu, 0.0, gamma, np)
            peaks = phi[1:-1][(F[1:-1] > F[:-2]) & (F[1:-1] >= F[2:]) & (F[1:-1] > 0.0)]
            assert peaks.size > 0
            assert max(np.min(abs(listed - p)) for p in peaks) < 1e-4


def test_no_vertical_component_is_bit_identical_on_the_c_path():
    """``Vertical(0)`` runs the C code path of a motion without one: the same bits."""
    for beta, Omega in ((3.0, 4.0), (1.5, 8.0)):
        runs = [
            rocking.simulate(BLOCK, DAMPER, OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega, vertical=v))
            for v in (None, Vertical(0.0))
        ]
        assert runs[0].summary() == runs[1].summary()


def test_the_energy_balances_with_the_work_of_the_vertical_ground(backend):
    """While rocking, ``E(t1) - E(t0)`` is the integral of the generated power, the work of the ground
    including ``-M ddy_g dy_G`` (docs/model.md section 2)."""
    pulse = OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0, vertical=Vertical(0.8, phase=1.0))
    r = rocking.simulate(BLOCK, DAMPER, pulse, backend=backend, record=True, record_dt=2e-5, rtol=1e-11, t_max=0.6)
    h = r.history
    model = load_model("omd")
    rocking_ = np.flatnonzero(h["phase"] == 1)
    rows = rocking_[: np.argmax(np.diff(rocking_) > 1)] if np.any(np.diff(rocking_) > 1) else rocking_
    rows = rows[2:-2]  # inside the first rocking phase, clear of uplift and impact
    t = h["t"][rows]
    y = [h[k][rows] for k in model.state]
    p = r.inputs.p
    agy = h["agy"][rows]
    np.testing.assert_array_equal(agy, vertical_of(r.inputs.settings, t))
    assert np.max(np.abs(agy)) > 1.0
    energy = model.functions.energy(1.0, *y, h["ag"][rows], agy, *p)
    power = model.functions.power(1.0, *y, h["ag"][rows], agy, *p)
    work = np.concatenate(([0.0], np.cumsum(np.diff(t) * (power[1:] + power[:-1]) / 2)))
    assert np.max(np.abs(energy - energy[0] - work)) < 1e-6 * np.max(np.abs(energy - energy[0]))


def test_where_the_ground_falls_faster_than_gravity_the_run_ends_in_flight(backend):
    """``g + ddy_g <= 0`` while the block stands or rocks, on a model without flight functions (the pendulum;
    those with them fly: tests/test_flight_numpy.py): status ``flight`` at that instant, never an answer."""
    pulse = OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0, vertical=Vertical(3.0))
    r = rocking.simulate(BLOCK, PENDULUM, pulse, model="pendulum", backend=backend)
    t, settings = r.t_end, r.inputs.settings
    assert r.status == "flight" and not r.overturned
    assert BLOCK.g + vertical_of(settings, t) == pytest.approx(0.0, abs=1e-9)
    assert BLOCK.g + vertical_of(settings, 0.999 * t) > 0.0


def test_vertical_inputs_are_checked_in_one_line():
    with pytest.raises(rocking.ParameterError, match=r"ratio must be in \[0, 10\]"):
        Vertical(-1.0)
    with pytest.raises(rocking.ParameterError, match="a_v must hold one vertical sample per sample of a"):
        SampledMotion(np.zeros(10), dt=0.01, a_v=np.zeros(9))
    with pytest.raises(rocking.ParameterError, match="vertical must be a rocking.Vertical"):
        OneSinePulse(a_g=1.0, omega_g=10.0, vertical=0.5)


def test_the_command_line_takes_a_vertical_ratio_and_a_record_pair(tmp_path, capsys):
    """``--vertical-ratio`` is ``Vertical`` of the pulse; ``--vertical FILE`` pairs records of one dt, else one line."""
    from rocking.cli.main import main

    pendulum = [x for p in ("m=50", "l=0.5", "x_p=0", "y_p=2.55", "k_phi=0", "c_phi=5.5") for x in ("--param", p)]
    argv = ["simulate", "--model", "pendulum", *pendulum, "--beta", "3", "--Omega", "4", "--vertical-ratio", "3"]
    assert main(argv) == 0  # a model without flight functions: the run ends where the ground pulls past gravity
    assert "FLIGHT: the floor's normal force reached 0" in capsys.readouterr().out
    t = np.arange(0.0, 1.0, 0.01)
    np.savetxt(tmp_path / "h.csv", np.column_stack((t, 3.0 * np.sin(2 * np.pi * t))), header="t [s], a [m/s2]")
    np.savetxt(tmp_path / "v.csv", np.column_stack((t, -2.0 * np.ones_like(t))), header="t [s], a [m/s2]")
    np.savetxt(tmp_path / "w.csv", np.column_stack((t / 2, np.ones_like(t))), header="t [s], a [m/s2]")
    pair = ["simulate", "--no-damper", "--motion", str(tmp_path / "h.csv"), "--unit", "m/s2", "--json", "--t-max", "2"]
    assert main([*pair, "--vertical", str(tmp_path / "v.csv")]) == 0
    assert main([*pair, "--vertical", str(tmp_path / "w.csv")]) == 2
    assert "the pair must share its dt" in capsys.readouterr().err
