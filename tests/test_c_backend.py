"""What only the C back end has: the build and its cache, the library's checks at load, batches, threads,
the shortcuts of sim.c, the history buffer and the failure of a run.

The rules of docs/simulation.md, on both back ends, are in tests/test_contract.py.
"""

from __future__ import annotations

import dataclasses
import os
import shlex
import shutil
import signal
import subprocess
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from rocking import Block, Damper, OneSinePulse, ParameterError, load_model, simulate
from rocking.sim import boundary, cbuild
from rocking.sim import c_backend as cb
from rocking.sim.cases import Cases, pulse_cases
from rocking.sim.cbuild import CBuildError
from rocking.sim.problem import RESULT_FIELDS, STATUS, make_problem
from tests.planted import plant_model

ROOT = Path(__file__).resolve().parent.parent
BLOCK = Block.reference()
DAMPER = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, h=0.05)


def problem(beta, Omega, damper=None, psi=0.0, **settings):
    pulse = OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega, psi=psi)
    return make_problem(BLOCK, damper, pulse, **settings)


def same(a, b) -> bool:
    """Bitwise-equal results, nan included."""
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


# --------------------------------------------------------------------------- #
# Build and cache                                                              #
# --------------------------------------------------------------------------- #


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
    """sim.c compiles strictly against any generic model header: here three coordinates and two stop sides,
    declarations only."""
    names = ["mass_matrix", "forcing", "rocking_accel", "contact_accel", "impact"]
    names += ["stop_gaps", "stop_forces", "stop_contact"]
    scalars = ["uplift", "energy", "power", "uplift_energy", "critical_angle", "critical_tangent"]
    scalars += ["least_potential", "least_stroke_potential"]
    args = "double s, const double *y, double ag, const double *p"
    prepared = "const double *y, double ag, const double *cst"
    lines = ["#ifndef STUB3_H", "#define STUB3_H"]
    lines += ["void stub3_prepare(double s, const double *on, const double *p, double *cst);"]
    lines += [f"void stub3_{n}({args}, double *out);" for n in names]
    lines += [f"void stub3_{n}_prepared({prepared}, double *out);" for n in names]
    lines += [f"double stub3_{n}({args});" for n in scalars]
    lines += [f"double stub3_{n}_prepared({prepared});" for n in scalars]
    lines += ["#ifdef ROCKING_GENERIC_NAMES", "#define MODEL_NQ 3", "#define MODEL_NY 6", "#define MODEL_NP 7"]
    lines += [f"#define MODEL_NK {n_constants}", "#define MODEL_NSTOPS 2", "#define model_prepare stub3_prepare"]
    lines += ["#define MODEL_P_GRAVITY 5"]
    lines += [f"#define model_{n} stub3_{n}" for n in names + scalars]
    lines += [f"#define model_{n}_prepared stub3_{n}_prepared" for n in names + scalars]
    lines += ["#endif", "#endif", ""]
    (tmp_path / "stub3.h").write_text("\n".join(lines))
    cmd = [
        *cbuild.compiler(),
        "-std=c99",
        "-Wall",
        "-Wextra",
        "-Werror",
        "-pedantic",
        "-O2",
        "-c",
        f"-I{cbuild.CSRC}",
        f"-I{tmp_path}",
        '-DROCKING_MODEL_HEADER="stub3.h"',
        str(cbuild.CSRC / "sim.c"),
        "-o",
        str(tmp_path / "sim3.o"),
    ]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


# --------------------------------------------------------------------------- #
# The library's checks at load                                                 #
# --------------------------------------------------------------------------- #


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
        assert lib.lib.rocking_api_version() == boundary.API_VERSION


def _swap_lines(text: str, a: str, b: str) -> str:
    """``text`` with its (single) lines containing ``a`` and ``b`` exchanged."""
    lines = text.split("\n")
    (i,) = [k for k, line in enumerate(lines) if a in line]
    (j,) = [k for k, line in enumerate(lines) if b in line]
    lines[i], lines[j] = lines[j], lines[i]
    return "\n".join(lines)


#: A change of csrc/boundary.h that the Python tables do not know of, and what the loader must name.
TAMPERED_HEADERS = {
    "a constant": (
        lambda h: h.replace("ROCKING_FIRST_STEP_FRACTION 0.25", "ROCKING_FIRST_STEP_FRACTION 0.3"),
        "constants",
    ),
    "a status code": (lambda h: h.replace("ROCKING_T_MAX = 2,", "ROCKING_T_MAX = 7,"), "constants"),
    "a phase code": (lambda h: h.replace("ROCKING_PIVOT_A_PRIME = -1,", "ROCKING_PIVOT_A_PRIME = 2,"), "constants"),
    "rocking_case field order": (
        lambda h: _swap_lines(h, "double omega_g;", "double psi;"),
        "rocking_case offsets and size",
    ),
    "rocking_case field type": (
        lambda h: h.replace("int32_t early_rest;", "int64_t early_rest;"),
        "rocking_case offsets and size",
    ),
    "rocking_result field order": (
        lambda h: _swap_lines(h, "double t_overturn;", "double t_critical;"),
        "rocking_result offsets and size",
    ),
    "the API version": (
        lambda h: h.replace(f"ROCKING_SIM_API_VERSION {boundary.API_VERSION}", "ROCKING_SIM_API_VERSION 999"),
        r"\(api, nq, ny, np\) = \(999,",
    ),
}


@pytest.fixture(scope="module")
def tampered_libraries(tmp_path_factory) -> dict:
    """sim.c of the model "block" built once per change of TAMPERED_HEADERS (in parallel: each is a compiler run)."""
    model = load_model("block")

    def build(change: str):
        folder = tmp_path_factory.mktemp("tampered")
        csrc = folder / "csrc"
        shutil.copytree(cbuild.CSRC, csrc)
        header = (csrc / "boundary.h").read_text()
        tampered = TAMPERED_HEADERS[change][0](header)
        assert tampered != header, f"{change}: the change did not apply: update this test to the generated header"
        (csrc / "boundary.h").write_text(tampered)
        return cbuild.build(model, cache=folder / "cache", csrc=csrc)  # it compiles: only the check can tell

    with ThreadPoolExecutor(max_workers=4) as pool:
        return dict(zip(TAMPERED_HEADERS, pool.map(build, TAMPERED_HEADERS)))


@pytest.mark.parametrize("change", list(TAMPERED_HEADERS), ids=list(TAMPERED_HEADERS))
def test_a_library_whose_layout_or_constants_differ_is_refused(tampered_libraries, change):
    """sim.c built against a boundary.h that differs from rocking.sim.boundary's tables is refused at load."""
    path = tampered_libraries[change]
    with pytest.raises(CBuildError, match=TAMPERED_HEADERS[change][1]) as info:
        cb._Library(load_model("block"), path)
    assert str(path) in str(info.value)


# --------------------------------------------------------------------------- #
# One run: failure and the history buffer                                     #
# --------------------------------------------------------------------------- #


def test_non_finite_input_fails_cleanly():
    pr = problem(2.0, 2.0, DAMPER)
    p = pr.p.copy()
    p[list(pr.model.parameters).index("m")] = np.nan
    with pytest.raises(cb.SimulationError, match="failed"):
        cb.simulate(dataclasses.replace(pr, p=p))
    with pytest.raises(cb.SimulationError, match="failed on 1 of 2 runs"):
        cb.simulate_cases(Cases.of([pr, dataclasses.replace(pr, p=p)]), threads=1)


def test_history_buffer_too_small_is_retried(monkeypatch):
    """Too small a first buffer: the run is repeated with the size it reported, same history."""
    pr = problem(2.0, 6.0, DAMPER, t_max=None, t_after=3.0)
    r = cb.simulate(pr, record=True)
    monkeypatch.setattr(cb, "_history_capacity", lambda problem: 7)
    again = cb.simulate(pr, record=True)
    assert len(r.history["t"]) > 7
    assert again.summary() == r.summary()
    assert list(again.history) == list(r.history)
    assert all(same(again.history[k], r.history[k]) for k in r.history)


# --------------------------------------------------------------------------- #
# One call without a Problem                                                   #
# --------------------------------------------------------------------------- #

PULSE = OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0)


@pytest.mark.parametrize(
    "options",
    [
        {"rtol": 0.5},
        {"rtol": True},
        {"t_max": -1.0},
        {"t_max": 1e5},
        {"t_after": 0.0},
        {"dtheta_rest": 0.0},
        {"energy_rest": -1.0},
        {"energy_rest": float("nan")},
        {"max_events": 0},
        {"max_events": 2.0},
        {"record_dt": 1e-9},
        {"record_dt": "0.1"},
        {"early_rest": 1},
        {"phase0": 2},
        {"phase0": 1},
        {"y0": [0.1, 0.0, 0.0, 0.0]},
        {"y0": [0.0, 0.0, 0.0]},
        {"model": 3},
        {"model": "pendulum"},
    ],
)
def test_a_single_call_refuses_what_a_problem_refuses(options):
    """simulate hands C the settings of the run without a Problem: it refuses what a Problem does, in the same words."""
    with pytest.raises(ParameterError) as built:
        make_problem(BLOCK, DAMPER, PULSE, **options)
    with pytest.raises(ParameterError) as simulated:
        simulate(BLOCK, DAMPER, PULSE, backend="c", **options)
    assert str(simulated.value) == str(built.value)


@pytest.mark.parametrize(
    "damper, options",
    [
        (DAMPER, {}),
        (None, {}),
        (DAMPER.as_params(), {"model": "omd"}),
        (DAMPER, {"rtol": 1e-6, "t_max": 3.0}),
        (DAMPER, {"energy_rest": 0.0, "early_rest": False}),
        (DAMPER, {"dtheta_rest": 0.01, "max_events": 5}),
        (DAMPER, {"y0": [0.01, 0.0, 0.0, 0.0], "phase0": 1}),
        (DAMPER, {"record_dt": 0.01}),
    ],
)
def test_a_single_call_runs_the_problem_of_make_problem(damper, options):
    """The settings simulate hands C are those of make_problem's Problem: the same response, bit for bit."""
    r = simulate(BLOCK, damper, PULSE, backend="c", record=True, **options)
    expected = cb.simulate(make_problem(BLOCK, damper, PULSE, **options), record=True)
    assert r.summary() == expected.summary()
    assert list(r.history) == list(expected.history)
    assert all(same(r.history[k], expected.history[k]) for k in r.history)


# --------------------------------------------------------------------------- #
# Batches                                                                      #
# --------------------------------------------------------------------------- #


def _map(n_omega, n_beta, damper=DAMPER, **settings):
    grid = [(beta, Omega) for Omega in np.linspace(1, 10, n_omega) for beta in np.linspace(1, 10, n_beta)]
    return [problem(beta, Omega, damper, **settings) for beta, Omega in grid]


def _assert_batch_is_single_runs(batch: dict, problems) -> None:
    assert set(batch) == set(RESULT_FIELDS)
    for i, pr in enumerate(problems):
        r = cb.simulate(pr)
        for name in RESULT_FIELDS:
            expected = STATUS.index(r.status) if name == "status" else getattr(r, name)
            assert same(batch[name][i], expected), (i, name)


def test_batch_equals_single_runs():
    """simulate_cases(Cases.of(problems), lanes=False) gives each problem's simulate(), bit for bit, whatever differs
    per case (the lanes: tests/test_lanes.py)."""
    problems = _map(4, 5) + [
        problem(1.5, 8.0, DAMPER, psi=0.5, rtol=1e-6),
        problem(0.5, 3.0, DAMPER, max_events=3),
        dataclasses.replace(problem(0.5, 3.0, DAMPER), early_rest=False),
        dataclasses.replace(problem(1.5, 4.0, DAMPER), early_rest=False, dtheta_rest=0.0),
        problem(2.5, 5.0, DAMPER, t_max=2.0, record_dt=0.5),
    ]
    batch = cb.simulate_cases(Cases.of(problems), threads=1, lanes=False)
    assert batch["overturned"].dtype == bool and batch["status"].dtype == np.int64
    assert len(set(batch["status"].tolist())) >= 3  # the map holds different outcomes
    _assert_batch_is_single_runs(batch, problems)
    # Without the early rest a run ends no sooner, with the same verdict.
    early = cb.simulate_cases(
        Cases.of(dataclasses.replace(pr, early_rest=True) for pr in problems), threads=1, lanes=False
    )
    assert np.all(batch["t_end"] >= early["t_end"]) and np.any(batch["t_end"] > early["t_end"])
    assert same(batch["overturned"], early["overturned"])


def test_batch_of_the_bare_block():
    problems = _map(3, 3, damper=None)
    cases = Cases.of(problems)
    assert cases.model.name == "block" and len(cases) == 9
    _assert_batch_is_single_runs(cb.simulate_cases(cases, threads=2, lanes=False), problems)


def test_pulse_cases_are_the_problems_of_make_problem():
    """pulse_cases builds, without a Problem per case, the cases of make_problem: same results."""
    Omega, beta = np.meshgrid([2.0, 5.0], [1.5, 3.0, 6.0])
    cases = pulse_cases(BLOCK, Omega, beta, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    problems = [problem(b, o, DAMPER) for o, b in zip(Omega.ravel(), beta.ravel())]
    _assert_batch_is_single_runs(cb.simulate_cases(cases, threads=1, lanes=False), problems)


def test_threads_give_identical_results():
    cases = Cases.of(_map(6, 5))
    one = cb.simulate_cases(cases, threads=1)
    three = cb.simulate_cases(cases, threads=3)
    default = cb.simulate_cases(cases)
    for name in RESULT_FIELDS:
        assert same(one[name], three[name]) and same(one[name], default[name])


def test_settings_shared_by_every_case_may_be_given_once():
    cases = Cases.of(_map(3, 3, damper=None))
    full = cb.simulate_cases(cases, threads=1)
    settings = dict(cases.settings)
    settings.update(atol=settings["atol"][0], dtheta_rest=float(settings["dtheta_rest"][0]), rtol=1e-8)
    del settings["early_rest"]  # a field with a default may be left out
    shared = Cases(cases.model, cases.p, settings)
    assert shared.settings["atol"].shape == (9, 2) and np.all(shared.settings["early_rest"] == 1)
    again = cb.simulate_cases(shared, threads=2)
    for name in RESULT_FIELDS:
        assert same(full[name], again[name]), name


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
    cases = Cases.of(problems)
    fast = cb.simulate_cases(cases, threads=1)
    monkeypatch.setenv("CC", shlex.join([*cbuild.compiler(), "-DROCKING_NO_SHORTCUTS"]))
    model = load_model("omd")
    monkeypatch.setitem(
        cb._LIBRARIES, (model.folder, model.c_prefix), cb._Library(model, cbuild.build(model, cache=tmp_path))
    )
    plain = cb.simulate_cases(cases, threads=1)
    assert np.any(fast["overturned"]) and not np.all(fast["overturned"]) and np.any(np.isfinite(fast["t_critical"]))
    for name in RESULT_FIELDS:
        assert same(fast[name], plain[name]), name


def test_cases_errors():
    problems = _map(2, 2)
    cases = Cases.of(problems)
    with pytest.raises(ParameterError, match="no problems given"):
        Cases.of([])
    with pytest.raises(ParameterError, match="one model"):
        Cases.of([problem(2, 2, DAMPER), problem(2, 2)])
    with pytest.raises(ParameterError, match="from rest: y0 must be None"):
        Cases.of([problem(2, 2, DAMPER), problem(2, 2, DAMPER, y0=[0.0, 0.1, 0.0, 0.0])])
    with pytest.raises(ParameterError, match="the setting a_g is missing"):
        Cases(cases.model, cases.p, {k: v for k, v in cases.settings.items() if k != "a_g"})
    with pytest.raises(ParameterError, match="unknown setting"):
        Cases(cases.model, cases.p, {**cases.settings, "y0": np.zeros((4, 4))})
    with pytest.raises(ParameterError, match=r"a_g must broadcast to shape \(4,\)"):
        Cases(cases.model, cases.p, {**cases.settings, "a_g": cases.settings["a_g"][:3]})
    # The checks of the table, with the same messages as a Problem's.
    with pytest.raises(ParameterError, match=r"contact_max_step must be finite and > 0 \(got 0\)"):
        Cases(cases.model, cases.p, {**cases.settings, "contact_max_step": np.zeros(4)})
    with pytest.raises(ParameterError, match=r"max_events must be an integer in \[1, 1e\+08\] \(got 0\)"):
        Cases(cases.model, cases.p, {**cases.settings, "max_events": 0})
    with pytest.raises(ParameterError, match=r"t_max must be in \(0, 30000\] s \(got inf\)"):
        Cases(cases.model, cases.p, {**cases.settings, "t_max": np.inf})
    with pytest.raises(ParameterError, match="atol must be finite and >= 0"):
        Cases(cases.model, cases.p, {**cases.settings, "atol": -cases.settings["atol"]})
    with pytest.raises(ValueError, match="threads"):
        cb.simulate_cases(cases, threads=0)


def test_one_value_for_every_case_is_checked_as_its_column():
    """A setting given as one number is checked once per process, remembered when it passes: it is refused, each
    time, as the column of that number is, with the same message, and passes as the column does."""
    cases = Cases.of(_map(2, 2))

    def refusal(value) -> str:
        with pytest.raises(ParameterError) as refused:
            Cases(cases.model, cases.p, {**cases.settings, "max_events": value})
        return str(refused.value)

    for value in (0, 2.5, -1.0, np.nan, 1e9):
        assert refusal(value) == refusal(value) == refusal(np.full(len(cases), value))
    for _ in range(2):
        batch = Cases(cases.model, cases.p, {**cases.settings, "max_events": 500, "rtol": 1e-7})
        np.testing.assert_array_equal(batch.settings["max_events"], np.full(len(cases), 500.0))
        assert batch.settings["rtol"].flags.c_contiguous and np.all(batch.settings["rtol"] == 1e-7)


def test_cases_refuse_parameters_of_the_wrong_length():
    """p must hold one value per model parameter in every row: sim.c reads model_np() of them per case."""
    cases = Cases.of(_map(2, 2))
    with pytest.raises(ParameterError, match=r"\bp\b"):
        Cases(cases.model, cases.p[:, :3], cases.settings)
    with pytest.raises(ParameterError, match=r"\bp\b"):
        Cases(cases.model, np.hstack([cases.p, cases.p]), cases.settings)


# --------------------------------------------------------------------------- #
# Stopping a running call                                                      #
# --------------------------------------------------------------------------- #


def _slow_cases(n: int = 4) -> Cases:
    """Cases that would run for minutes: a stiff undamped damper (period ~3e-4 s) under a pulse below the
    uplift thresholds, followed for 1e4 s in full contact, with no bound on the work (and no rest)."""
    cases = pulse_cases(BLOCK, [4.0] * n, [0.5] * n, gamma=0.05, omega_ratio=1e4, zeta=0.0, h=0.05, t_after=1e4)
    return Cases(cases.model, cases.p, {**cases.settings, "max_steps": 1 << 62, "early_rest": 0, "energy_rest": 0.0})


def _stop_after(seconds: float, stop=cb.request_stop) -> threading.Timer:
    timer = threading.Timer(seconds, stop)
    timer.start()
    return timer


@pytest.mark.parametrize("threads", [1, 2])
def test_request_stop_ends_a_running_batch_and_later_calls_run(threads):
    """request_stop from another thread: the batch raises KeyboardInterrupt at once; the next batch runs normally."""
    timer = _stop_after(0.3)
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        cb.simulate_cases(_slow_cases(), threads=threads)
    assert time.perf_counter() - start < 2.0
    timer.join()
    cases = pulse_cases(BLOCK, [2.0, 4.0], [2.0, 3.0], gamma=0.05, h=0.05)
    statuses = cb.simulate_cases(cases, threads=threads)["status"]
    assert set(statuses) <= {STATUS.index("rest"), STATUS.index("overturned")}


def test_request_stop_ends_a_running_simulate_and_a_stop_before_a_call_does_not_touch_it():
    cb.request_stop()  # nothing running: no effect on the calls that follow
    slow = _slow_cases(1).problem(0)
    timer = _stop_after(0.3)
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        cb.simulate(slow)
    assert time.perf_counter() - start < 2.0
    timer.join()
    assert cb.simulate(problem(2.0, 2.0, DAMPER)).status in ("rest", "overturned")


def test_a_call_that_starts_while_halted_stops_at_once_and_later_calls_run():
    """A study's interruption: a worker thread may start a tile's C call after the stop; halted() stops it too."""
    start = time.perf_counter()
    with cb.halted():
        worker = ThreadPoolExecutor(1).submit(cb.simulate_cases, _slow_cases(1), 1)
        with pytest.raises(KeyboardInterrupt):
            worker.result(timeout=30)
    assert time.perf_counter() - start < 2.0
    statuses = cb.simulate_cases(pulse_cases(BLOCK, [2.0], [2.0], gamma=0.05, h=0.05), threads=1)["status"]
    assert set(statuses) <= {STATUS.index("rest"), STATUS.index("overturned")}


def _sigint() -> None:
    """Ctrl-C as a terminal sends it: SIGINT to the process."""
    os.kill(os.getpid(), signal.SIGINT)


@pytest.mark.parametrize("threads", [1, 2])
def test_ctrl_c_in_the_main_thread_stops_a_batch(threads):
    """SIGINT while C runs for the main thread: stopped at once, KeyboardInterrupt, Python's handler back."""
    assert threading.current_thread() is threading.main_thread()
    handler = signal.getsignal(signal.SIGINT)
    timer = _stop_after(0.3, _sigint)
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        cb.simulate_cases(_slow_cases(2), threads=threads)
    assert time.perf_counter() - start < 2.0
    timer.join()
    assert not cb._RUNNING  # every flag unregistered
    assert signal.getsignal(signal.SIGINT) is handler


def test_ctrl_c_stops_a_single_run_and_a_program_handler_still_runs():
    """SIGINT during one rocking.simulate: the program's own SIGINT handler is what runs, once, at once."""
    slow = _slow_cases(1).problem(0)
    calls = []

    class Handled(Exception):
        pass

    def handler(signum, frame):
        calls.append(signum)
        raise Handled

    previous = signal.signal(signal.SIGINT, handler)
    try:
        timer = _stop_after(0.3, _sigint)
        start = time.perf_counter()
        with pytest.raises(Handled):
            cb.simulate(slow)
        assert time.perf_counter() - start < 2.0
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert calls == [signal.SIGINT]


def test_an_ignored_sigint_stays_ignored_during_a_run():
    problem = make_problem(BLOCK, None, OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0))
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        ignoring = cb.simulate(problem)
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)
    assert ignoring.summary() == cb.simulate(problem).summary()


def test_the_stop_flag_changes_no_result():
    """Results with a flag that is never set are those of a direct call without control (NULL)."""
    cases = pulse_cases(BLOCK, np.linspace(1, 10, 6), np.linspace(1, 10, 6), gamma=0.05, h=0.05)
    records = cb._records(cases)
    direct = np.zeros(len(cases), dtype=cb.RESULT_DTYPE)
    cb.library().lib.rocking_simulate_batch(len(cases), cases.p, records, direct, None)
    via = cb.simulate_cases(cases, threads=1)
    for name in RESULT_FIELDS:
        assert same(direct[name].astype(RESULT_FIELDS[name]), via[name])


def test_a_folder_named_like_a_built_in_model_does_not_shadow_it(tmp_path, monkeypatch):
    """A built-in model's name means the installed model whatever the working directory: a planted ``omd/``
    there (its manifest updated to vouch for the payload) is never run."""
    from rocking.model.loading import GENERATED

    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    pulse = OneSinePulse.from_nondim(block, beta=2.0, Omega=4.0)
    installed = make_problem(block, damper, pulse).model
    plant_model(GENERATED / "omd", tmp_path / "omd", tmp_path / "PWNED")
    monkeypatch.chdir(tmp_path)
    assert make_problem(block, damper, pulse).model.folder == installed.folder
    assert load_model("omd").folder == installed.folder
    assert not (tmp_path / "PWNED").exists()
