"""The C back end: build and cache, the integrator's accuracy, the phase machine, batches, histories.

References are independent of sim.c: analytic uplift times (model.md section
10 item 2), the exact solution of the damper's linear oscillator in full
contact (matrix exponential), and SciPy's DOP853 at tight tolerance on the
generated NumPy functions.
"""

from __future__ import annotations

import ctypes
import dataclasses
import math
import os
import shlex
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from rocking import Block, Damper, OneSinePulse, load_model
from rocking.sim import cbuild
from rocking.sim import c_backend as cb
from rocking.sim.cbuild import CBuildError
from rocking.sim.problem import STATUS, make_problem

ROOT = Path(__file__).resolve().parent.parent
BLOCK = Block.reference()
DAMPER = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, h=0.05)

pytestmark = pytest.mark.skipif(
    shutil.which(os.environ.get("CC", "").split()[0] if os.environ.get("CC") else "cc") is None
    and shutil.which("gcc") is None,
    reason="no C compiler",
)


def problem(beta, Omega, damper=None, psi=0.0, **settings):
    pulse = OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega, psi=psi)
    return make_problem(BLOCK, damper, pulse, **settings)


def same(a, b) -> bool:
    """Bitwise-equal results, nan included."""
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


# --------------------------------------------------------------------------- #
# Build and cache                                                              #
# --------------------------------------------------------------------------- #


def test_build_is_cached_and_keyed_by_the_sources(tmp_path, monkeypatch):
    model = load_model("block")
    lib = cbuild.build(model, cache=tmp_path)
    assert lib.is_file() and lib.parent == tmp_path and lib.name.startswith("block-")

    def no_compiler(cmd):
        raise AssertionError("a cached library was compiled again")

    monkeypatch.setattr(cbuild, "_compile", no_compiler)
    assert cbuild.build(model, cache=tmp_path) == lib
    monkeypatch.setenv("ROCKING_CACHE_DIR", str(tmp_path))
    assert cbuild.cache_dir() == tmp_path and cbuild.build(model) == lib
    assert not list(tmp_path.glob("*.tmp")), "a temporary file was left behind"

    # Any change of a source gives a new key, hence a new library.
    csrc = tmp_path / "csrc"
    shutil.copytree(cbuild.CSRC, csrc)
    assert cbuild.build_key(model, csrc=csrc) == cbuild.build_key(model)
    with open(csrc / "sim.c", "a") as f:
        f.write("\n/* changed */\n")
    assert cbuild.build_key(model, csrc=csrc) != cbuild.build_key(model)
    assert cbuild.build_key(load_model("omd")) != cbuild.build_key(model)


def test_concurrent_builds_from_several_processes(tmp_path):
    code = textwrap.dedent(
        """
        import ctypes, sys
        from rocking import load_model
        from rocking.sim import cbuild
        lib = cbuild.build(load_model("omd"), cache=sys.argv[1])
        assert ctypes.CDLL(str(lib)).rocking_model_ny() == 4
        print(lib)
        """
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", code, str(tmp_path)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
        )
        for _ in range(4)
    ]
    outputs = [p.communicate(timeout=120) for p in procs]
    assert all(p.returncode == 0 for p in procs), [err for _, err in outputs]
    assert len({out.strip() for out, _ in outputs}) == 1
    assert len(list(tmp_path.glob("*.so"))) == 1
    assert not list(tmp_path.glob("*.tmp"))


def test_missing_compiler_raises_cbuilderror(tmp_path, monkeypatch):
    monkeypatch.setenv("CC", str(tmp_path / "no-such-cc"))
    with pytest.raises(CBuildError, match="no-such-cc.*not found"):
        cbuild.build(load_model("block"), cache=tmp_path)


def test_compiler_failure_carries_its_message(tmp_path):
    csrc = tmp_path / "csrc"
    shutil.copytree(cbuild.CSRC, csrc)
    source = (csrc / "sim.c").read_text()
    (csrc / "sim.c").write_text(source.replace("static double ode_ag(", "static double ode_ag(int broken,", 1))
    with pytest.raises(CBuildError) as info:
        cbuild.build(load_model("block"), cache=tmp_path / "cache", csrc=csrc)
    message = str(info.value)
    assert "C compiler failed" in message and "sim.c" in message and "error" in message
    assert not list((tmp_path / "cache").glob("*.so"))
    assert not list((tmp_path / "cache").glob("*.tmp"))


def test_strict_warnings_compile(tmp_path):
    """sim.c is clean C99 under -Wall -Wextra -Werror -pedantic, for every model, both ways of naming the model."""
    cc = cbuild.compiler()
    for name in ("omd", "block"):
        model = load_model(name)
        for how in (
            [f'-DROCKING_MODEL_HEADER="{model.c_header.name}"'],
            ["-DROCKING_GENERIC_NAMES", "-include", str(model.c_header)],
        ):
            cmd = [
                *cc,
                "-std=c99",
                "-Wall",
                "-Wextra",
                "-Werror",
                "-pedantic",
                "-O2",
                "-fPIC",
                "-c",
                f"-I{cbuild.CSRC}",
                f"-I{model.folder}",
                *how,
                str(cbuild.CSRC / "sim.c"),
                "-o",
                str(tmp_path / f"{name}.o"),
            ]
            proc = subprocess.run(cmd, capture_output=True, text=True)
            assert proc.returncode == 0, proc.stderr


@pytest.mark.parametrize("n_constants", [11, 0])
def test_sim_is_model_independent(tmp_path, n_constants):
    """sim.c compiles strictly against any generic model header: here three coordinates, declarations only."""
    names = ["mass_matrix", "forcing", "rocking_accel", "contact_accel", "impact"]
    scalars = ["uplift", "energy", "power", "uplift_energy", "critical_angle", "critical_tangent"]
    args = "double s, const double *y, double ag, const double *p"
    prepared = "const double *y, double ag, const double *cst"
    lines = ["#ifndef STUB3_H", "#define STUB3_H", "void stub3_prepare(double s, const double *p, double *cst);"]
    lines += [f"void stub3_{n}({args}, double *out);" for n in names]
    lines += [f"void stub3_{n}_prepared({prepared}, double *out);" for n in names]
    lines += [f"double stub3_{n}({args});" for n in scalars]
    lines += [f"double stub3_{n}_prepared({prepared});" for n in scalars]
    lines += ["#ifdef ROCKING_GENERIC_NAMES", "#define MODEL_NQ 3", "#define MODEL_NY 6", "#define MODEL_NP 7"]
    lines += [f"#define MODEL_NK {n_constants}", "#define model_prepare stub3_prepare"]
    lines += [f"#define model_{n} stub3_{n}" for n in names + scalars]
    lines += [f"#define model_{n}_prepared stub3_{n}_prepared" for n in names + scalars]
    lines += ["#endif", "#endif", ""]
    (tmp_path / "stub3.h").write_text("\n".join(lines))
    cmd = [*cbuild.compiler(), "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2", "-c",
           f"-I{cbuild.CSRC}", f"-I{tmp_path}", '-DROCKING_MODEL_HEADER="stub3.h"', str(cbuild.CSRC / "sim.c"),
           "-o", str(tmp_path / "sim3.o")]  # fmt: skip
    proc = subprocess.run(cmd, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_library_matches_the_model():
    for name in ("omd", "block"):
        assert cb.available(name)
        lib = cb.library(name)
        model = load_model(name)
        assert (lib.lib.rocking_model_nq(), lib.lib.rocking_model_ny(), lib.lib.rocking_model_np()) == (
            model.nq,
            len(model.state),
            len(model.parameters),
        )


def test_first_step_rule_is_the_numpy_back_end_s():
    """docs/simulation.md (Integration): both back ends start a half-cycle after an impact alike."""
    from rocking.sim import numpy_backend

    fraction = cb.library("omd").lib.rocking_first_step_fraction
    fraction.restype, fraction.argtypes = ctypes.c_double, []
    assert fraction() == numpy_backend.FIRST_STEP_FRACTION


# --------------------------------------------------------------------------- #
# The integrator against independent references                               #
# --------------------------------------------------------------------------- #


def _free_rocking_reference(p, theta0):
    """First impact of free rocking about A from rest at theta0: DOP853 at rtol 1e-13."""
    functions = load_model("block").functions

    def rhs(t, y):
        return [y[1], functions.rocking_accel(1.0, y[0], y[1], 0.0, *p)[0]]

    def impact(t, y):
        return y[0]

    impact.terminal, impact.direction = True, -1
    sol = solve_ivp(
        rhs, (0.0, 10.0), [theta0, 0.0], method="DOP853", rtol=1e-13, atol=1e-15, events=impact, dense_output=True
    )
    return sol.t_events[0][0], sol.sol


@pytest.mark.parametrize("theta0", [0.05, 0.2])
def test_free_rocking_first_impact_converges_with_rtol(theta0):
    errors = {}
    for rtol in (1e-6, 1e-8, 1e-10):
        pr = problem(0.0, 1.0, rtol=rtol, max_events=1, t_max=10.0)
        if rtol == 1e-6:
            t_ref, dense = _free_rocking_reference(pr.p, theta0)
        r = cb.simulate(pr, record=True, y0=[theta0, 0.0], phase0=1)
        assert (r.status, r.impacts, r.uplifts) == ("max_events", 1, 0)
        errors[rtol] = abs(r.t_end - t_ref)
        # The recorded samples come from the dense output: as accurate as the steps.
        h = r.history
        inside = h["t"] < r.t_end
        assert np.max(np.abs(h["theta"][inside] - dense(h["t"][inside])[0])) < 100 * rtol * BLOCK.alpha
        assert r.theta_max == pytest.approx(theta0, abs=1e-15)
    # Global error proportional to the tolerance: ~100x smaller per 100x smaller rtol.
    assert errors[1e-8] < 1e-7
    assert errors[1e-8] < errors[1e-6] / 30 and errors[1e-10] < errors[1e-8] / 30


def test_contact_phase_damper_matches_the_exact_oscillator():
    """Below the uplift thresholds the damper is a linear oscillator under -m ag(t): exact by expm."""
    # early_rest=False: the damper is followed to t_max (no uplift is ever possible here).
    pr = dataclasses.replace(problem(0.5, 3.0, DAMPER, psi=0.4, rtol=1e-9, t_max=None, t_after=4.0), early_rest=False)
    r = cb.simulate(pr, record=True)
    assert r.uplifts == 0 and r.impacts == 0 and r.status == "t_max"
    h = r.history
    assert np.all(h["phase"] == 0) and np.all(h["theta"] == 0) and np.all(h["dtheta"] == 0)

    m, k, c = (DAMPER.m, DAMPER.k_m, DAMPER.c)
    w = pr.omega_g

    def system(a):  # z = (x, dx, sin(w t + psi), cos(w t + psi))
        return np.array([[0, 1, 0, 0], [-k / m, -c / m, -a, 0], [0, 0, 0, w], [0, 0, -w, 0]], dtype=float)

    z0 = np.array([0.0, 0.0, math.sin(pr.psi), math.cos(pr.psi)])
    z_p = expm(system(pr.a_g) * pr.t_p) @ z0
    exact = np.array(
        [expm(system(pr.a_g) * t) @ z0 if t <= pr.t_p else expm(system(0.0) * (t - pr.t_p)) @ z_p for t in h["t"]]
    )
    scale = np.max(np.abs(exact[:, 0]))
    assert np.max(np.abs(h["x"] - exact[:, 0])) < 1e-6 * scale
    assert np.max(np.abs(h["dx"] - exact[:, 1])) < 1e-6 * scale * DAMPER.omega_m

    # The largest |x| lies between samples: the exact one on a fine grid (error ~ x'' dt^2 / 2).
    def fine(a, z, duration, dt=1e-4):
        step, zs = expm(system(a) * dt), [z]
        for _ in range(int(duration / dt)):
            zs.append(step @ zs[-1])
        return np.array(zs)

    x_max = max(np.max(np.abs(fine(pr.a_g, z0, pr.t_p)[:, 0])), np.max(np.abs(fine(0.0, z_p, pr.t_max - pr.t_p)[:, 0])))
    assert r.x_max == pytest.approx(x_max, rel=1e-6)  # extrema located on the dense output
    assert r.x_max > scale


@pytest.mark.parametrize(("beta", "pivot"), [(2.0, 1), (1.0, -1)])
def test_uplift_time_of_the_bare_block_is_analytic(beta, pivot):
    pr = problem(beta, 2.0, max_events=1)
    r = cb.simulate(pr, record=True)
    assert (r.status, r.uplifts) == ("max_events", 1)
    g, B, H, e = BLOCK.g, BLOCK.B, BLOCK.H, BLOCK.e
    if pivot == 1:  # a_g sin(w t) first reaches g (B + 2 e) / H
        t_up = math.asin(g * (B + 2 * e) / H / pr.a_g) / pr.omega_g
    else:  # below that, -a_g sin(w t) first reaches g (B - 2 e) / H, in the second half
        t_up = (math.pi + math.asin(g * (B - 2 * e) / H / pr.a_g)) / pr.omega_g
    assert r.t_end == pytest.approx(t_up, abs=1e-9)
    assert r.history["phase"][-1] == pivot and r.history["t"][-1] == r.t_end


def test_pulse_starting_above_the_threshold_lifts_at_once():
    pr = problem(2.0, 2.0, psi=1.2, max_events=1)
    r = cb.simulate(pr)
    assert (r.status, r.uplifts, r.t_end) == ("max_events", 1, 0.0)


# --------------------------------------------------------------------------- #
# The phase machine                                                            #
# --------------------------------------------------------------------------- #


def test_moderate_pulse_rocks_and_comes_to_rest():
    r = cb.simulate(problem(1.5, 8.0), record=True)
    assert r.status == "rest" and not r.overturned and math.isnan(r.t_overturn)
    assert r.uplifts >= 1 and r.impacts > 5
    assert 0 < r.theta_max < BLOCK.alpha and math.isnan(r.t_critical)
    h = r.history
    assert h["phase"][-1] == 0 and h["t"][-1] == r.t_end
    # Every impact is recorded before and after, at one instant: a pivot change or rest.
    same_t = np.flatnonzero(np.diff(h["t"]) == 0)
    impacts = [i for i in same_t if h["phase"][i] != 0]
    assert len(impacts) == r.impacts
    for i in impacts:
        assert h["theta"][i] == 0 and h["theta"][i + 1] == 0
        assert h["phase"][i + 1] in (0, -h["phase"][i])
        assert abs(h["dtheta"][i + 1]) < abs(h["dtheta"][i])  # the impact dissipates
    # The last impact was slower than dtheta_rest: full contact with dtheta = 0.
    last = impacts[-1]
    assert h["phase"][last + 1] == 0 and h["dtheta"][last + 1] == 0


def test_damped_damper_reaches_rest_by_energy():
    damper = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.3, h=0.05)
    pr = dataclasses.replace(problem(1.5, 4.0, damper), early_rest=False)  # energy_rest alone
    r = cb.simulate(pr, record=True)
    assert r.status == "rest" and r.t_end < pr.t_max and r.t_end > pr.t_p
    model = pr.model
    y_end = np.array([r.history[name][-1] for name in model.state])
    energy = model.call("energy", 1.0, y_end, 0.0, pr.p) - model.call("energy", 1.0, np.zeros(4), 0.0, pr.p)
    # The rest event is located: the energy above rest is at the threshold, not below it by a step.
    assert energy == pytest.approx(pr.energy_rest, rel=1e-6)
    assert r.x_max > 0


def test_early_rest_ends_a_safe_run_at_the_damper_s_next_extremum():
    """docs/simulation.md rule 4: below the uplift energy after the pulse, the run ends at the next extremum of x."""
    pr = problem(0.5, 3.0, DAMPER, rtol=1e-9, t_max=None, t_after=4.0)  # below both uplift thresholds
    early = cb.simulate(pr, record=True)
    full = cb.simulate(dataclasses.replace(pr, early_rest=False))
    assert (early.status, full.status) == ("rest", "t_max")
    # Safe from the pulse's end on: the run ends within half a damped period of the damper.
    wd = DAMPER.omega_m * math.sqrt(1 - DAMPER.zeta**2)
    assert pr.t_p < early.t_end < pr.t_p + math.pi / wd
    # ... at an extremum of x, which here is the largest |x| of the whole run (settling matters).
    h = early.history
    assert h["t"][-1] == early.t_end and h["phase"][-1] == 0
    assert abs(h["dx"][-1]) < 1e-9 * DAMPER.omega_m * early.x_max
    assert abs(h["x"][-1]) == pytest.approx(early.x_max, rel=1e-12)
    assert early.x_max == pytest.approx(full.x_max, rel=1e-9)
    assert (early.theta_max, early.uplifts, early.impacts) == (full.theta_max, full.uplifts, full.impacts) == (0, 0, 0)


def test_early_rest_after_rocking_keeps_the_verdict_and_the_maxima():
    damper = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.1, h=0.05)
    pr = problem(1.5, 4.0, damper)
    early = cb.simulate(pr, record=True)
    full = cb.simulate(dataclasses.replace(pr, early_rest=False))
    assert early.status == "rest" and early.impacts > 0 and early.t_end < full.t_end
    assert abs(early.history["dx"][-1]) < 1e-9 * damper.omega_m * early.x_max
    for name in ("overturned", "theta_max", "t_critical", "impacts", "uplifts"):
        assert same(getattr(early, name), getattr(full, name)), name
    assert early.x_max == pytest.approx(full.x_max, rel=1e-9)


def test_strong_pulse_overturns():
    r = cb.simulate(problem(3.0, 2.0, DAMPER), record=True)
    assert r.status == "overturned" and r.overturned
    assert r.t_end == r.t_overturn and r.t_critical < r.t_overturn
    assert r.theta_max == pytest.approx(math.pi / 2, abs=1e-12)
    assert abs(r.history["theta"][-1]) == pytest.approx(math.pi / 2, abs=1e-12)


def test_max_events_ends_the_run():
    r = cb.simulate(problem(1.5, 8.0, max_events=3))
    assert r.status == "max_events" and r.uplifts + r.impacts == 3


def test_t_max_ends_the_run():
    pr = problem(1.5, 8.0, DAMPER, t_max=2.0)
    r = cb.simulate(pr)
    assert r.status == "t_max" and r.t_end == 2.0


def test_mirror_symmetry():
    """(e, x, theta, ag) -> (-e, -x, -theta, -ag) maps solutions onto solutions (model.md 10.6)."""
    pr = problem(2.5, 5.0, DAMPER, t_max=None, t_after=5.0)
    p = pr.p.copy()
    p[list(pr.model.parameters).index("e")] *= -1
    mirror = dataclasses.replace(pr, p=p, a_g=-pr.a_g)
    a, b = cb.simulate(pr, record=True), cb.simulate(mirror, record=True)
    assert (a.status, a.impacts, a.uplifts) == (b.status, b.impacts, b.uplifts)
    assert a.theta_max == pytest.approx(b.theta_max, rel=1e-6)
    assert a.x_max == pytest.approx(b.x_max, rel=1e-6)
    flips = {(pa, pb) for pa, pb in zip(a.history["phase"], b.history["phase"])}
    assert flips <= {(0, 0), (1, -1), (-1, 1)}


def test_invalid_initial_state():
    pr = problem(0.0, 1.0)
    with pytest.raises(ValueError, match="initial state"):
        cb.simulate(pr, y0=[0.1, 0.0], phase0=0)
    with pytest.raises(ValueError, match="initial state"):
        cb.simulate(pr, y0=[0.1, 0.0], phase0=-1)
    with pytest.raises(ValueError, match="y0 must hold 2"):
        cb.simulate(pr, y0=[0.1], phase0=1)


def test_settings_that_would_never_end_are_refused():
    pr = problem(2.0, 2.0, DAMPER)
    for change, message in [
        ({"contact_max_step": 0.0}, "contact_max_step must be finite and > 0"),
        ({"t_max": math.inf}, "t_max must be finite"),
        ({"rtol": 0.0}, "rtol must be"),
        ({"atol": -pr.atol}, "atol must be"),
        ({"energy_rest": -1.0}, "energy_rest must be finite and >= 0"),
    ]:
        with pytest.raises(ValueError, match=message):
            cb.simulate(dataclasses.replace(pr, **change))


def test_non_finite_input_fails_cleanly():
    pr = problem(2.0, 2.0, DAMPER)
    p = pr.p.copy()
    p[list(pr.model.parameters).index("m")] = np.nan
    with pytest.raises(cb.SimulationError, match="failed"):
        cb.simulate(dataclasses.replace(pr, p=p))


# --------------------------------------------------------------------------- #
# History                                                                      #
# --------------------------------------------------------------------------- #


def test_history_layout_and_buffer_retry(monkeypatch):
    pr = problem(2.0, 6.0, DAMPER, t_max=None, t_after=3.0)
    r = cb.simulate(pr, record=True)
    h = r.history
    assert list(h) == ["t", *pr.model.state, "phase", "ag"]
    n = len(h["t"])
    assert all(len(v) == n for v in h.values()) and n > pr.t_max / pr.record_dt
    assert h["t"][0] == 0.0 and h["t"][-1] == r.t_end
    assert np.all(np.diff(h["t"]) >= 0)
    assert set(np.unique(h["phase"])) <= {-1, 0, 1}
    assert np.array_equal(h["ag"], pr.ground_acceleration(h["t"]))
    assert pr.t_p in h["t"]  # the pulse's end is a breakpoint
    assert r.impacts > 0 and r.status == "t_max"
    events = np.flatnonzero(np.diff(h["t"]) == 0)  # impacts: before and after at one instant
    assert len(events) >= r.impacts + r.uplifts
    grid = h["t"][(h["t"] > 0) & (np.abs(h["t"] / pr.record_dt - np.round(h["t"] / pr.record_dt)) < 1e-9)]
    assert len(grid) >= int(pr.t_max / pr.record_dt) - 1

    # Too small a first buffer: the run is repeated with the size it reported.
    monkeypatch.setattr(cb, "_history_capacity", lambda problem: 7)
    again = cb.simulate(pr, record=True)
    assert again.summary() == r.summary()
    assert all(same(again.history[k], h[k]) for k in h)
    no_history = cb.simulate(pr)
    assert no_history.history is None and no_history.summary() == r.summary()


# --------------------------------------------------------------------------- #
# Batches                                                                      #
# --------------------------------------------------------------------------- #


def _map(n_omega, n_beta, damper=DAMPER):
    grid = [(beta, Omega) for Omega in np.linspace(1, 10, n_omega) for beta in np.linspace(1, 10, n_beta)]
    return [problem(beta, Omega, damper) for beta, Omega in grid]


def test_batch_equals_single_runs():
    problems = _map(4, 5) + [problem(1.5, 8.0, DAMPER, psi=0.5), problem(0.5, 3.0, DAMPER)]
    batch = cb.simulate_batch(**cb.batch_arguments(problems), threads=1)
    assert set(batch) == set(cb.RESULT_FIELDS)
    assert batch["overturned"].dtype == bool and batch["status"].dtype == np.int64
    assert len(set(batch["status"].tolist())) >= 2  # the map holds different outcomes
    for i, pr in enumerate(problems):
        r = cb.simulate(pr)
        for name in cb.RESULT_FIELDS:
            expected = STATUS.index(r.status) if name == "status" else getattr(r, name)
            assert same(batch[name][i], expected), (i, name)


def test_threads_give_identical_results():
    args = cb.batch_arguments(_map(6, 5))
    one = cb.simulate_batch(**args, threads=1)
    three = cb.simulate_batch(**args, threads=3)
    default = cb.simulate_batch(**args)
    for name in cb.RESULT_FIELDS:
        assert same(one[name], three[name]) and same(one[name], default[name])


def test_shortcuts_change_no_result(tmp_path, monkeypatch):
    """sim.c skips work it can prove useless (extrema that cannot raise a maximum, atan2 far below
    the critical angle, pow where the step factor is saturated): built without them, it gives the
    same results bit for bit, on a map of the reference block and its damper and on eccentric blocks."""
    eccentric = [Block(H=2.0, B=0.5, M=1000.0, e=e) for e in (-0.2, 0.2)]
    problems = _map(8, 8) + [
        make_problem(
            block,
            Damper.from_nondim(block, gamma=0.1, omega_ratio=0.8, h=0.05),
            OneSinePulse.from_nondim(block, beta=beta, Omega=3.0, psi=psi),
        )
        for block in eccentric
        for beta in (1.5, 2.5, 4.0)
        for psi in (0.0, 2.0)
    ]
    args = cb.batch_arguments(problems)
    fast = cb.simulate_batch(**args, threads=1)
    monkeypatch.setenv("CC", shlex.join([*cbuild.compiler(), "-DROCKING_NO_SHORTCUTS"]))
    model = load_model("omd")
    monkeypatch.setitem(
        cb._LIBRARIES, (model.folder, model.c_prefix), cb._Library(model, cbuild.build(model, cache=tmp_path))
    )
    plain = cb.simulate_batch(**args, threads=1)
    assert np.any(fast["overturned"]) and not np.all(fast["overturned"]) and np.any(np.isfinite(fast["t_critical"]))
    for name in cb.RESULT_FIELDS:
        assert same(fast[name], plain[name]), name


def test_batch_of_the_bare_block_and_broadcasting():
    problems = _map(3, 3, damper=None)
    args = cb.batch_arguments(problems)
    assert args["model"].name == "block"
    full = cb.simulate_batch(**args, threads=1)
    # Rows and values shared by every run may be given once.
    args.update(p=args["p"][0], atol=args["atol"][0], dtheta_rest=float(args["dtheta_rest"][0]))
    shared = cb.simulate_batch(**args, threads=2)
    for name in cb.RESULT_FIELDS:
        assert same(full[name], shared[name])


def test_batch_argument_errors():
    args = cb.batch_arguments(_map(2, 2))
    with pytest.raises(ValueError, match="p must have shape"):
        cb.simulate_batch(**{**args, "p": args["p"][:, :3]})
    with pytest.raises(ValueError, match="different lengths"):
        cb.simulate_batch(**{**args, "a_g": args["a_g"][:3]})
    with pytest.raises(ValueError, match="contact_max_step must be finite and > 0"):
        cb.simulate_batch(**{**args, "contact_max_step": np.zeros(4)})
    with pytest.raises(ValueError, match="max_events"):
        cb.simulate_batch(**{**args, "max_events": 0})
    with pytest.raises(ValueError, match="threads"):
        cb.simulate_batch(**args, threads=0)
    with pytest.raises(ValueError, match="one rtol"):
        cb.batch_arguments([problem(2, 2, DAMPER), problem(2, 2, DAMPER, rtol=1e-6)])
    with pytest.raises(ValueError, match="one model"):
        cb.batch_arguments([problem(2, 2, DAMPER), problem(2, 2)])
    with pytest.raises(ValueError, match="one early_rest"):
        cb.batch_arguments([problem(2, 2, DAMPER), dataclasses.replace(problem(2, 2, DAMPER), early_rest=False)])


def test_batch_without_early_rest_equals_single_runs():
    problems = [dataclasses.replace(pr, early_rest=False) for pr in _map(3, 3) + [problem(0.5, 3.0, DAMPER)]]
    args = cb.batch_arguments(problems)
    assert args["early_rest"] is False
    batch = cb.simulate_batch(**args, threads=1)
    early = cb.simulate_batch(**{**args, "early_rest": True}, threads=1)
    assert np.all(batch["t_end"] >= early["t_end"]) and np.any(batch["t_end"] > early["t_end"])
    for i, pr in enumerate(problems):
        r = cb.simulate(pr)
        for name in cb.RESULT_FIELDS:
            expected = STATUS.index(r.status) if name == "status" else getattr(r, name)
            assert same(batch[name][i], expected), (i, name)
