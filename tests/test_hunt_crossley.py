"""Hunt-Crossley end stops (docs/model.md section 11), on both back ends.

The outside facts: a mass that meets a fixed Hunt-Crossley pad, ``F = k_b delta^n (1 + chi_b ddelta / v_in)``,
with nothing else acting on it, leaves with the restitution ``e`` that solves
``chi_b (1 + e) = ln((1 + chi_b) / (1 - chi_b e))`` whatever ``n``, ``k_b``, the mass and ``v_in``
(docs/model.md section 11; its forward form ``e = (1 + W0(-(1 + chi_b) exp(-(1 + chi_b)))) / chi_b`` with
Lambert's W). ``Stops(e_b=...)`` gives the model ``chi_b = hunt_crossley_damping(e_b)``: one impact
integrated here by hand, with SciPy and nothing of the project's, must restitute ``e_b`` itself (1e-6), and
the runtime's rebound must be the same. Without damping (``e_b = 1``) the pad is elastic,
``k_b delta^(n+1) / (n+1)`` its energy: the total is constant across contacts.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import lambertw

import rocking
from rocking import Block, Damper, OneSinePulse, ParameterError, Stops, load_model
from rocking.model.checks import RANGES
from rocking.model.params import hunt_crossley_damping, hunt_crossley_restitution
from rocking.sim.problem import make_problem
from rocking.sim.run import run

BACKENDS = ("numpy", "c")
REFERENCE = Block.reference()
STILL = OneSinePulse(a_g=0.0, omega_g=2 * math.pi)
#: A free 1 kg mass (no spring, no dashpot) 0.1 m from either pad, moving at V0.
FREE = {"m": 1.0, "h": 0.05, "k_m": 0.0, "c": 0.0, "L": 0.1}
V0 = 0.5
K_B = 1e4


@pytest.fixture(params=BACKENDS)
def backend(request) -> str:
    return request.param


def free_mass(chi_b: float, n: float, t_max: float, k_m: float = 0.0, v0: float = V0, record_dt=None):
    """The free mass at x = 0 moving at ``v0`` towards the upper pad of damping factor ``chi_b`` (the model's
    parameters by name), the block on its base, no ground motion."""
    return make_problem(
        REFERENCE,
        {**FREE, "k_m": k_m, "k_b": K_B, "n_b": n, "chi_b": chi_b},
        STILL,
        model="omd_stops_hc",
        rtol=1e-11,
        t_max=t_max,
        record_dt=record_dt,
        y0=np.array([0.0, 0.0, 0.0, v0]),
        energy_rest=0.0,
        early_rest=False,
    )


def rebound_by_hand(
    chi: float, n: float, k: float = K_B, m: float = FREE["m"], v0: float = V0, rtol: float = 1e-12
) -> tuple[float, float]:
    """``(e, tau)``: the restitution and duration of one impact of a mass ``m`` at ``v0`` on a fixed pad
    ``k delta^n (1 + chi ddelta / v0)``, the law integrated here (SciPy, nothing of the project's)."""

    def law(t, y):
        delta, rate = y
        return [rate, -max(0.0, k * max(delta, 0.0) ** n * (1.0 + chi * rate / v0)) / m]

    def leaves(t, y):
        return y[0] if t > 0.0 else 1.0

    def lets_go(t, y):
        return 1.0 + chi * y[1] / v0

    leaves.terminal = lets_go.terminal = True
    leaves.direction = lets_go.direction = -1
    # The contact lasts about (m / k)^(1/(n+1)) v0^(-(n-1)/(n+1)) times a number of order 1 (the law's time scale).
    scale = (m / (k * v0 ** (n - 1))) ** (1.0 / (n + 1))
    sol = solve_ivp(law, (0.0, 1e3 * scale), [0.0, v0], "DOP853", rtol=rtol, atol=1e-15 * v0, events=[leaves, lets_go])
    return -sol.y[1, -1] / v0, sol.t[-1]


#: Restitutions over [0.1, 0.99]: a rubber ball to a dead pad.
RESTITUTIONS = np.linspace(0.1, 0.99, 12)


@pytest.mark.parametrize("n", [1.0, 1.5, 2.5])
def test_one_impact_on_the_pad_restitutes_e_b(n):
    """The damping factor of e_b, integrated by hand (rtol 1e-11) on one impact of a mass on a fixed pad, gives
    back e_b to 1e-6 over [0.1, 0.99], whatever the mass, stiffness and speed (drawn at random)."""
    rng = np.random.default_rng(7)
    for e_b in RESTITUTIONS:
        k, m, v0 = 10 ** rng.uniform(2, 8), 10 ** rng.uniform(-1, 2), 10 ** rng.uniform(-2, 1)
        e, _ = rebound_by_hand(hunt_crossley_damping(e_b), n, k=k, m=m, v0=v0, rtol=1e-11)
        assert e == pytest.approx(e_b, abs=1e-6), (e_b, n, k, m, v0)


def test_the_restitution_is_the_closed_form_with_lambert_w():
    """hunt_crossley_restitution is e = (1 + W0(-(1 + chi) exp(-(1 + chi)))) / chi, the forward closed form, to
    1e-12 where it is well conditioned (chi >= 0.05: away from W's branch point at chi = 0); and
    hunt_crossley_damping is its inverse to the last bits over the whole range of e_b."""
    for chi in np.geomspace(0.05, 1e3, 40):
        closed = (1.0 + lambertw(-(1.0 + chi) * np.exp(-(1.0 + chi))).real) / chi
        assert hunt_crossley_restitution(chi) == pytest.approx(closed, rel=1e-12, abs=1e-15)
    for e_b in (*np.geomspace(1e-3, 1.0, 60), 1.0 - 1e-9, 1.0 - 1e-14):
        chi = hunt_crossley_damping(e_b)
        assert hunt_crossley_restitution(chi) == pytest.approx(e_b, rel=4e-15)


def test_the_damping_factor_at_its_edges():
    """0 for an elastic pad; as e_b -> 1, 3 (1 - e_b) / 2 (Lankarani & Nikravesh's factor) to first order and
    3 (1 - e_b) (2 - e_b) / 2 to second (the series of the equation), to the last bits however near 1; 1 / e_b
    to the last bit as e_b -> 0 (1 - chi e_b ~ exp(-1 / e_b)), so the range of chi_b is that of e_b;
    decreasing in between."""
    assert hunt_crossley_damping(1.0) == 0.0 and hunt_crossley_restitution(0.0) == 1.0
    for e_b in (0.999, 0.9999, 1 - 1e-6, 1 - 1e-10, 1 - 1e-13):
        eps = 1.0 - e_b
        assert hunt_crossley_damping(e_b) == pytest.approx(1.5 * eps * (1 + eps), rel=eps**2 + 4e-16)
    assert hunt_crossley_damping(0.01) == 100.0
    assert hunt_crossley_damping(RANGES["e_b"].low) == RANGES["chi_b"].high
    chis = [hunt_crossley_damping(e) for e in np.linspace(1e-3, 1.0, 200)]
    assert np.all(np.diff(chis) < 0)
    for bad in (0.0, -0.5, 1.0 + 1e-12, 5e-4, math.nan, math.inf, "0.5", True):
        with pytest.raises(ParameterError, match=r"^e_b must be .*\[0\.001, 1\]") as info:
            hunt_crossley_damping(bad)
        assert "\n" not in str(info.value)
    for bad in (-1e-9, 1001.0, math.inf):
        with pytest.raises(ParameterError, match=r"^chi_b must be .*\[0, 1000\]"):
            hunt_crossley_restitution(bad)


def free_mass_with_stops(e_b: float, n: float, t_max: float):
    """The free mass of :func:`free_mass` on a rocking.Damper whose Stops have the restitution ``e_b``."""
    stops = Stops(L=FREE["L"], k_b=K_B, law="hunt-crossley", n=n, e_b=e_b)
    damper = Damper(m=FREE["m"], k_m=0.0, c=0.0, h=FREE["h"], stops=stops)
    return make_problem(
        REFERENCE,
        damper,
        STILL,
        rtol=1e-11,
        t_max=t_max,
        y0=np.array([0.0, 0.0, 0.0, V0]),
        energy_rest=0.0,
        early_rest=False,
    )


@pytest.mark.parametrize("e_b", [0.1, 0.57, 0.9])
@pytest.mark.parametrize("n", [1.0, 1.5])
def test_a_mass_rebounds_from_a_pad_with_its_restitution(backend, e_b, n):
    """The simulator, the block at rest: a free mass on the guide strikes a pad of Stops(e_b=...) once and
    leaves at -e_b V0 (1e-6); the same as the law by hand (1e-7), and the mass then coasts."""
    e, tau = rebound_by_hand(hunt_crossley_damping(e_b), n)
    t_end = FREE["L"] / V0 + tau + 0.05  # the mass is 0.05 e V0 past the pad's release, far from the other pad
    r = run(free_mass_with_stops(e_b, n, t_end), backend=backend, record=True)
    assert (r.status, r.uplifts, r.stop_contacts) == ("t_max", 0, 1)
    rebound = -r.history["dx"][-1] / V0
    assert rebound == pytest.approx(e, rel=1e-7)
    assert rebound == pytest.approx(e_b, abs=1e-6)
    assert r.history["x"][-1] == pytest.approx(FREE["L"] - e * V0 * (t_end - FREE["L"] / V0 - tau), rel=1e-6)


def test_the_force_has_no_jump_at_contact_and_pushes_only(backend):
    """The recorded F_b starts from 0 at the gap's closing, never pulls, and its peak is the law's."""
    chi, n = hunt_crossley_damping(0.6), 1.5
    e, tau = rebound_by_hand(chi, n)
    r = run(free_mass(chi, n, FREE["L"] / V0 + tau + 0.01, record_dt=1e-5), backend=backend, record=True)
    h = r.history
    delta = h["x"] - FREE["L"]
    forces = K_B * np.maximum(delta, 0.0) ** n * (1.0 + chi * h["dx"] / V0)
    assert forces.min() >= -1e-9 * forces.max()
    assert r.bumper_force_max == pytest.approx(forces.max(), rel=1e-3)
    first = np.flatnonzero(delta > 0.0)[0]
    assert forces[first] <= K_B * (V0 * 1e-5) ** n * 3  # one sample into the contact: delta ~ V0 dt


def test_elastic_pads_keep_the_energy_and_damped_pads_only_take_it(backend):
    """A spring and Hunt-Crossley pads, no dashpot: with e_b = 1 the energy, k_b delta^(n+1)/(n+1) included, is
    constant over contacts (1e-8); with e_b = 0.5 it never rises (events add none) and falls at each contact.
    The energy is evaluated here at the recorded states, not by the runtime."""
    model = load_model("omd_stops_hc")
    for e_b in (1.0, 0.5):
        chi = hunt_crossley_damping(e_b)
        r = run(free_mass(chi, 1.5, 3.0, k_m=50.0, v0=0.8, record_dt=2e-4), backend=backend, record=True)
        assert r.uplifts == 0 and r.stop_contacts >= 3
        h = r.history
        state = [h[k] for k in model.state]
        params = {**REFERENCE.as_params(), **FREE, "k_m": 50.0, "k_b": K_B, "n_b": 1.5, "chi_b": chi}
        # Both pads counted wherever delta > 0: a pad never lets go before delta = 0 here (its release needs a
        # receding speed of v_in / chi = 0.70 v_in, the mass leaves at about e_b v_in), and the energy does not
        # depend on v_in.
        pushing = (1.0, 1.0, V0, V0)
        energy = model.functions.energy(1.0, *state, 0.0, 0.0, *model.param_vector(params), stop_on=pushing)
        scale = 0.5 * FREE["m"] * 0.8**2
        if e_b == 1.0:
            assert np.ptp(energy) <= 1e-8 * scale
        else:
            assert np.all(np.diff(energy) <= 1e-9 * scale)
            # Each contact takes (1 - e^2) of the kinetic energy it starts with; the spring keeps k_m L^2 / 2.
            assert energy[0] - energy[-1] > 0.1 * scale


def test_both_back_ends_agree_on_blocks_with_hunt_crossley_stops():
    """Random dampers with the stops of Stops.at_edges(law="hunt-crossley") under one-sine pulses: the same
    verdict, impacts and contacts, theta_max and x_max within 1e-6 (the integrators' global error at rtol 1e-10)."""
    rng = np.random.default_rng(25)
    for _ in range(6):
        damper = Damper.from_nondim(REFERENCE, gamma=rng.uniform(0.02, 0.1), omega_ratio=rng.uniform(0.5, 2), h=0.05)
        stops = Stops.at_edges(REFERENCE, damper, law="hunt-crossley", e_b=rng.uniform(0.3, 0.9))
        pulse = OneSinePulse.from_nondim(REFERENCE, beta=rng.uniform(3, 12), Omega=rng.uniform(3, 10))
        damper = dataclasses.replace(damper, stops=stops)
        a, b = (rocking.simulate(REFERENCE, damper, pulse, backend=be, rtol=1e-10) for be in BACKENDS)
        assert (a.overturned, a.impacts, a.stop_contacts) == (b.overturned, b.impacts, b.stop_contacts)
        assert a.theta_max == pytest.approx(b.theta_max, rel=1e-6)
        assert a.x_max == pytest.approx(b.x_max, rel=1e-6)
        assert a.bumper_force_max == pytest.approx(b.bumper_force_max, rel=1e-5)


def test_stops_refuse_bad_hunt_crossley_parameters():
    """Each bad value is refused in one line naming the parameter and its range."""
    with pytest.raises(ParameterError, match=r"e_b must be given with law='hunt-crossley'"):
        Stops(L=0.2, k_b=1e5, law="hunt-crossley")
    with pytest.raises(ParameterError, match=r"e_b .*\[0.001, 1\]"):
        Stops(L=0.2, k_b=1e5, law="hunt-crossley", e_b=1.2)
    with pytest.raises(ParameterError, match=r"n .*\[1, 10\]"):
        Stops(L=0.2, k_b=1e5, law="hunt-crossley", e_b=0.5, n=0.5)
    with pytest.raises(ParameterError, match=r"c_b must be 0 with law='hunt-crossley'"):
        Stops(L=0.2, k_b=1e5, c_b=10.0, law="hunt-crossley", e_b=0.5)
    with pytest.raises(ParameterError, match=r"law must be one of kelvin-voigt, hunt-crossley"):
        Stops(L=0.2, k_b=1e5, law="hertz")
    with pytest.raises(ParameterError, match=r"e_b is a parameter of law='hunt-crossley'"):
        Stops(L=0.2, k_b=1e5, e_b=0.5)
    # The model's parameters given by name (make_problem, --param) pass the same checks, chi_b in its own range.
    with pytest.raises(ParameterError, match=r"chi_b must be in \[0, 1000\]"):
        free_mass(-0.5, 1.5, 1.0)
    with pytest.raises(ParameterError, match=r"n must be in \[1, 10\]"):
        free_mass(0.5, 0.8, 1.0)


def test_at_edges_gives_the_kelvin_voigt_pads_force_at_full_depth():
    """k_b of the Hunt-Crossley pads: k_b depth^n equals the Kelvin-Voigt pads' k_b depth."""
    damper = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, h=0.05)
    kv = Stops.at_edges(REFERENCE, damper)
    hc = Stops.at_edges(REFERENCE, damper, law="hunt-crossley", e_b=0.6, n=1.5)
    assert (hc.law, hc.n, hc.e_b, hc.L) == ("hunt-crossley", 1.5, 0.6, kv.L)
    assert hc.as_params() == {"L": kv.L, "k_b": hc.k_b, "n_b": 1.5, "chi_b": hunt_crossley_damping(0.6)}
    assert hc.k_b * 0.02**1.5 == pytest.approx(kv.k_b * 0.02, rel=1e-12)
    assert dataclasses.replace(damper, stops=hc).model == "omd_stops_hc"


def test_the_default_pads_of_both_laws_restitute_alike():
    """Stops.at_edges' Kelvin-Voigt pad (zeta_b = 0.2, only pushes: it lets go where k_b delta + c_b ddelta falls
    to 0) and its Hunt-Crossley pad restitute the same, one impact on each integrated by hand (1e-6)."""
    from rocking.model.params import BUMPER_DAMPING_RATIO, BUMPER_RESTITUTION

    damper = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1.0, h=0.05)
    kv = Stops.at_edges(REFERENCE, damper)
    zeta = kv.c_b / (2 * math.sqrt(kv.k_b * damper.m))
    assert zeta == pytest.approx(BUMPER_DAMPING_RATIO, rel=1e-12)

    def law(t, y):
        return [y[1], -max(0.0, kv.k_b * max(y[0], 0.0) + kv.c_b * y[1]) / damper.m]

    def lets_go(t, y):  # the mass leaves (delta = 0) or the pad lets go, whichever first
        return min(y[0], kv.k_b * y[0] + kv.c_b * y[1]) if t > 0.0 else 1.0

    lets_go.terminal, lets_go.direction = True, -1
    sol = solve_ivp(law, (0.0, 1.0), [0.0, V0], "DOP853", rtol=1e-11, atol=1e-15, events=[lets_go])
    restitution = -sol.y[1, -1] / V0
    assert restitution == pytest.approx(BUMPER_RESTITUTION, abs=1e-8)
    hc = Stops.at_edges(REFERENCE, damper, law="hunt-crossley")
    assert hc.e_b == BUMPER_RESTITUTION
    assert rebound_by_hand(hc.as_params()["chi_b"], hc.n)[0] == pytest.approx(restitution, abs=1e-6)


def test_the_law_with_a_memory_matches_model_md_by_hand():
    """With a regime given (each side's flag and an approach speed v_in of an earlier start, not the state's),
    the generated forces, contact, accelerations and power are section 11's, typed by hand in
    rocking.reference.paper, to 1e-12 (rocking verify checks them with the memory of the state)."""
    from rocking.reference import paper
    from rocking.reference.verify import random_cases, rel_error

    model = load_model("omd_stops_hc")
    floor = model.manifest["stops"][0]["approach_floor"]
    rng = np.random.default_rng(3)
    for s in (1, -1):
        v = random_cases(rng, 2000, s, stops=True, hunt_crossley=True)
        v_in = tuple(10 ** rng.uniform(-3, 0.5, 2000) for _ in range(2))
        stops = {k: v[k] for k in ("L", "k_b", "n_b", "chi_b")} | {"floor": floor, "v_in": v_in}
        x, dx = v["x"], v["dx"]
        contact = paper.stop_contact(x, dx, **stops)
        regime = (*(np.where(c > 0, 1.0, 0.0) for c in contact), *v_in)
        args = (v["s"], *(v[k] for k in model.state), v["ag"], v["agy"], *(v[k] for k in model.parameters))
        hand = {
            "stop_contact": contact,
            "stop_forces": paper.stop_forces(x, dx, **stops),
            "contact_accel": (paper.contact_accel(x, dx, v["ag"], v["m"], v["k_m"], v["c"], **stops),),
            "power": (
                paper.power(
                    s,
                    *(v[k] for k in ("theta", "x", "dtheta", "dx", "ag", "agy", "M", "B", "H", "e", "m", "h", "c")),
                    **stops,
                ),
            ),
        }
        assert sum(np.count_nonzero(r) for r in regime[:2]) > 200  # pads pushing in many cases
        for name, expected in hand.items():
            got = getattr(model.functions, name)(*args, stop_on=regime)
            got = got if isinstance(got, tuple) else (got,)
            index = slice(1, None) if name == "contact_accel" else slice(None)
            for a, b in zip(got[index], expected):
                assert rel_error(a, b) <= 1e-12, name


def test_below_the_floor_a_contact_is_that_of_a_stiffer_restitution(backend):
    """A contact slower than the floor v_f: the runtime records v_in = v_f, so its law is k_b delta^n (1 + chi
    ddelta / v_f) = that of a pad of damping factor chi v0 / v_f met at v0 (the rebound of the law does not
    depend on the speed): the mass leaves at -e v0, e that pad's restitution, integrated by hand."""
    floor = load_model("omd_stops_hc").manifest["stops"][0]["approach_floor"]
    e_b, n, v0 = 0.5, 1.5, 0.1 * floor
    chi = hunt_crossley_damping(e_b)
    e, _ = rebound_by_hand(chi * v0 / floor, n, v0=v0)
    assert e == pytest.approx(hunt_crossley_restitution(chi * v0 / floor), abs=1e-8)
    problem = dataclasses.replace(free_mass(chi, n, 3.0, v0=v0), y0=np.array([0.0, FREE["L"] - 1e-7, 0.0, v0]))
    r = run(problem, backend=backend, record=True)
    assert (r.status, r.stop_contacts) == ("t_max", 1)
    # To 1e-5: the runtime's absolute tolerance on a speed of 0.1 mm/s, as in the test below.
    assert -r.history["dx"][-1] / v0 == pytest.approx(e, rel=1e-5)
    assert abs(e - e_b) > 0.4  # the floor matters: the pad restitutes e(chi / 10) = 0.91, not e_b = 0.5


def test_a_run_that_starts_inside_a_pad_starts_its_contact(backend):
    """The mass at rest 1 mm into a pad: the contact starts at t = 0 with v_in at the floor, so the pad pushes
    with k_b delta^n at first, lets go once the mass recedes at v_f / chi, and adds no energy."""
    model = load_model("omd_stops_hc")
    floor = model.manifest["stops"][0]["approach_floor"]
    chi, n, depth = hunt_crossley_damping(0.5), 1.5, 1e-3
    problem = dataclasses.replace(
        free_mass(chi, n, 0.05, record_dt=1e-5), y0=np.array([0.0, FREE["L"] + depth, 0.0, 0.0])
    )
    r = run(problem, backend=backend, record=True)
    assert r.bumper_force_max == pytest.approx(K_B * depth**n, rel=1e-9)
    leaving = -r.history["dx"][-1]
    # Released where ddelta = -v_f / chi: to 1e-4, the integrator's absolute tolerance on a speed of 1 mm/s.
    assert leaving == pytest.approx(floor / chi, rel=1e-4)
    assert 0.5 * FREE["m"] * leaving**2 < K_B * depth ** (n + 1) / (n + 1)


def test_simulate_with_hunt_crossley_pads_is_the_python_api(capsys):
    """--bumper-law hunt-crossley --e-b 0.8 is Stops.at_edges(..., law="hunt-crossley", e_b=0.8); --e-b implies
    the law; a Kelvin-Voigt pad's option with it, or a bad value, is refused in one line."""
    from rocking.cli.main import main

    argv = ["simulate", "--gamma", "0.05", "--omega-ratio", "1", "--h", "0.05", "--beta", "10", "--Omega", "7.5"]
    damper = Damper.from_nondim(REFERENCE, gamma=0.05, omega_ratio=1, h=0.05)
    stops = Stops.at_edges(REFERENCE, damper, law="hunt-crossley", e_b=0.8)
    pulse = OneSinePulse.from_nondim(REFERENCE, beta=10, Omega=7.5)
    expected = rocking.simulate(REFERENCE, dataclasses.replace(damper, stops=stops), pulse).summary()
    for options in (["--bumper-law", "hunt-crossley", "--e-b", "0.8"], ["--e-b", "0.8", "--n-b", "1.5"]):
        assert main([*argv, *options, "--json"]) == 0
        out = json.loads(capsys.readouterr().out)["responses"]["with damper"]
        out.pop("mass_past_edge")
        assert out == json.loads(json.dumps(expected))
    for options, message in (
        (["--e-b", "0.8", "--bumper-law", "kelvin-voigt"], "--e-b: parameters of the Hunt-Crossley pads"),
        (["--bumper-law", "hunt-crossley", "--c-b", "3"], "--c-b must be 0 with law='hunt-crossley'"),
        (["--e-b", "0"], r"--e-b must be in \[0.001, 1\]"),
    ):
        assert main([*argv, *options]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and re.search(message, err[0]), err


def test_the_history_finds_each_contacts_approach_speed_again(backend):
    """Response.to_dataset with Hunt-Crossley pads: F_b and ddx are those of the law with each contact's own v_in
    (the approach speed at its start), not those of a contact starting at each sample: against the law
    written here with v_in read off the first sample into each contact, and the mass's m ddx = -F_b."""
    chi, n = hunt_crossley_damping(0.6), 1.5
    _, tau = rebound_by_hand(chi, n)
    t_end = FREE["L"] / V0 + tau + 0.02
    r = run(free_mass(chi, n, t_end, record_dt=1e-4), backend=backend, record=True)
    ds = r.to_dataset(dt=1e-4)
    x, dx = ds["x"].values, ds["dx"].values
    delta = x - FREE["L"]
    law = K_B * np.maximum(delta, 0.0) ** n * (1.0 + chi * dx / V0)  # v_in = V0: no force before
    inside = (delta > 0.0) & (law > 0.0)
    assert inside.sum() > 100 and np.any(dx[inside] < -0.3 * V0)  # the pad pushes while the mass leaves too
    assert np.allclose(ds["F_b"].values, np.where(inside, law, 0.0), rtol=1e-6, atol=1e-9 * law.max())
    assert np.allclose(FREE["m"] * ds["ddx"].values, -ds["F_b"].values, rtol=1e-9, atol=1e-9 * law.max())


def test_a_spec_states_its_pads_law_as_data():
    """The [[stops]] keys of each law, checked before any derivation, each error in one line naming the stop."""
    from rocking.derive.spec import VARIANTS_DIR, SpecError, parse_spec, tomllib  # tomli on Python 3.10

    base = tomllib.loads((VARIANTS_DIR / "omd_stops_hc.toml").read_text())
    assert parse_spec(base).stops[0].law == "hunt-crossley"
    stop = base["stops"][0]
    for change, message in (
        ({"law": "hertz"}, "unknown law 'hertz'; choose one of kelvin-voigt, hunt-crossley"),
        ({"damping": "0"}, "damping is not a key of the hunt-crossley law"),
        ({"approach_floor": 0}, "approach_floor must be a number > 0"),
        ({"damping_factor": None}, "missing required key 'damping_factor'"),
        ({"restitution": "0.5"}, "unknown key(s) restitution"),
    ):
        table = {k: v for k, v in {**stop, **change}.items() if v is not None}
        with pytest.raises(SpecError, match=re.escape(message)):
            parse_spec({**base, "stops": [table]})
    kelvin_voigt = {k: v for k, v in stop.items() if k not in ("law", "exponent", "damping_factor")}
    with pytest.raises(SpecError, match=re.escape("exponent is not a key of the kelvin-voigt law")):
        parse_spec({**base, "stops": [{**kelvin_voigt, "damping": "0", "exponent": "2"}]})
