"""Issue 10: no input of the public Python API hangs, crashes, or escapes as a traceback.

A bounded share of ``make fuzz`` (bench/fuzz.py): the first inputs of its fixed seed on both
back ends, each in a worker process with the fuzzer's time limit.
"""

import dataclasses
import importlib.util
import time
from pathlib import Path

import numpy as np
import pytest

FUZZ = Path(__file__).resolve().parents[1] / "bench" / "fuzz.py"
N = 150


@pytest.fixture(scope="module")
def fuzz():
    spec = importlib.util.spec_from_file_location("rocking_bench_fuzz", FUZZ)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def cases(fuzz):
    return fuzz.draw_inputs(N, 20240610)


def test_the_inputs_are_reproducible(fuzz, cases):
    assert len(cases) == N
    assert fuzz.jsonable(fuzz.draw_inputs(N, 20240610)) == fuzz.jsonable(cases)


@pytest.mark.parametrize("backend", ["c", "numpy"])
def test_no_input_hangs_crashes_or_escapes(fuzz, cases, backend):
    outcomes = fuzz.run_backend(cases, backend, workers=2, timeout=10.0, progress=False)
    summary = fuzz.report(cases, outcomes, samples=3)
    counts = summary["counts"]
    bad = {k: counts[k] for k in ("hang", "crash", "nan_result", "other_exception", "failed_run")}
    assert bad == dict.fromkeys(bad, 0), summary["samples"]
    # The share exercises both sides: refused inputs and runs.
    assert counts["clean_error"] > 0 and counts["result"] > 0


# --- the instances of the issue, refused up front by the public API -----------------------------

import rocking  # noqa: E402
from rocking import Block, Damper, OneSinePulse, ParameterError  # noqa: E402

BLOCK = Block.reference()
PULSE = OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0)
DAMPER = {"m": 50.0, "k_m": 200.0, "c": 10.0, "h": 0.05}


@pytest.mark.parametrize(
    "damper, options, message",
    [
        ({**DAMPER, "k_m": 1e300}, {}, r"^k_m must be in \[0, 1e\+30\] N/m"),
        ({**DAMPER, "c": 1e12}, {}, r"^zeta must be in \[0, 10\]"),
        ({**DAMPER, "e": 10.0}, {}, r"^damper: e set by the block, not by the damper$"),
        ({**DAMPER, "foo": 1.0}, {}, r"^model 'omd' has no parameter\(s\) foo of its own"),
        ({"m": 50.0}, {}, r"^model 'omd' needs parameter\(s\) h, k_m, c$"),
        ({**DAMPER, "m": True}, {}, r"^m must be a real number \(got True\)$"),
        (True, {}, r"^damper must be a rocking\.Damper, a mapping"),
        (None, {"record_dt": 1e-9}, r"^record_dt must be <= 0 \(events only\) or >= t_max / 1e\+06"),
        (None, {"rtol": "abc"}, r"^rtol must be a real number"),
        (None, {"rtol": "1e-8"}, r"^rtol must be a real number"),
        (None, {"model": 3}, r"^model must be a model name, a folder or a rocking\.Model \(got int\)$"),
        (None, {"record": "no"}, r"^record must be True or False \(got 'no'\)$"),
        (None, {"max_events": True}, r"^max_events must be an integer \(got True\)$"),
        (None, {"early_rest": 1}, r"^early_rest must be True or False"),
        (None, {"t_after": 1e300}, r"^t_after must be in \(0, 10000\] s"),
        (None, {"t_max": float("nan")}, r"^t_max must be finite"),
        (None, {"backend": ["c"]}, r"^backend must be one of auto, c, numpy"),
        (None, {"tmax": 3.0}, r"^simulate: unknown option\(s\) tmax"),
    ],
)
def test_issue_instances_are_refused_before_any_work(damper, options, message):
    with pytest.raises(ParameterError, match=message):
        rocking.simulate(BLOCK, damper, PULSE, **options)


def test_a_damper_object_on_another_model_is_refused():
    with pytest.raises(ParameterError, match=r"model 'pendulum' has no parameter\(s\) c, h, k_m of its own"):
        rocking.simulate(BLOCK, Damper(**DAMPER), PULSE, model="pendulum")


def test_a_mapping_damper_gives_the_result_of_its_damper():
    """Valid inputs are unchanged: the omd mapping and the Damper it describes agree."""
    damper = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    r = rocking.simulate(BLOCK, damper.as_params(), PULSE, backend="c", t_after=2.0)
    assert r.status in ("rest", "overturned", "t_max")


# --- issue 23, item 3: the NumPy back end refuses up front what it cannot run within its bound -------------------

from rocking.sim import numpy_backend  # noqa: E402

LONG = [
    (rocking.OneCosinePulse.from_period(2.0, 1000.0), True),  # 14.6 s on NumPy within max_steps
    (rocking.SampledMotion(np.random.default_rng(1).normal(0.0, 1.0, 20_000), dt=0.01), False),  # 21 - 36 s
]


@pytest.mark.parametrize("pulse, record", LONG)
def test_numpy_refuses_up_front_what_it_would_take_long_over(pulse, record):
    start = time.perf_counter()
    with pytest.raises(
        ParameterError,
        match=r"^the NumPy back end plans the work of [\d,]+ .* at most 75,000: run "
        r"it on the C back end \(backend='c'\), or shorten it",
    ):
        rocking.simulate(BLOCK, None, pulse, backend="numpy", record=record)
    assert time.perf_counter() - start < 1.0
    assert rocking.simulate(BLOCK, None, pulse, backend="c", record=record).status == "rest"


def test_the_planned_work_of_a_study_response_is_far_below_the_limit():
    problem = rocking.sim.problem.make_problem(BLOCK, Damper(**DAMPER), PULSE)
    parts = numpy_backend.planned_work(problem, record=True)
    assert 0 < sum(parts.values()) < numpy_backend.PLANNED_WORK_LIMIT / 10 and parts["restarts at samples"] == 0


def test_the_parts_rule_5_counts_weigh_at_most_max_steps():
    """A run that ends at max_steps on both back ends is not refused for the work it would plan beyond."""
    problem = rocking.sim.problem.make_problem(BLOCK, None, LONG[0][0])
    numpy_backend.check_planned_work(dataclasses.replace(problem, max_steps=50_000), record=True)
    with pytest.raises(ParameterError, match=r"\(163,284 for the contact steps\)"):
        numpy_backend.check_planned_work(problem, record=False)
