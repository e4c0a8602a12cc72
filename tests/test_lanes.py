"""The C batch in lanes (rocking/sim/csrc/lanes.h, issue 40): the scalar path's verdicts, impacts and statuses.

The lanes run sim.c's own phase machine per case and compute the stages of its rocking steps over vectors; an
element differs from the scalar stages only by the last bits of sin and cos (fdlibm's kernels against libm's).
The bound held here is issue 40's: theta_max and x_max within 1e-7 relative of the scalar path (measured on the
50 x 50 bench map: 1e-10, bench/lanes.py), every discrete result identical. Never bit equality with the scalar
path (two sin implementations); bit equality only between runs of the lanes themselves (same library, the same
operations per element whatever the vector width).
"""

from __future__ import annotations

import numpy as np
import pytest

from rocking import Block, Damper, Floor, Stops, Vertical
from rocking.sim import c_backend as cb
from rocking.sim.cases import Cases, pulse_cases
from rocking.sim.lanes_rhs import vector_rhs
from rocking.sim.problem import RESULT_FIELDS

pytestmark = [
    pytest.mark.skipif(not cb.available("omd"), reason="the C back end cannot be built here"),
    pytest.mark.skipif(cb.available("omd") and cb.lanes("omd") == 0, reason="no lanes on this machine"),
]

BLOCK = Block.reference()
#: issue 40's bound on theta_max and x_max against the scalar path, relative.
BOUND = 1e-7
#: The results that must be identical (the discrete ones).
DISCRETE = ("status", "overturned", "impacts", "uplifts", "stop_contacts", "slides")


def grid(n: int):
    Omega, beta = np.meshgrid(np.linspace(1, 10, n), np.linspace(1, 10, n), indexing="ij")
    return Omega, beta


def bench_map(n: int, **options) -> Cases:
    """The bench map of `make bench` (bench/bench_map.py) on an n x n grid."""
    return pulse_cases(BLOCK, *grid(n), gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05, rtol=1e-8, **options)


def stops_map(n: int) -> Cases:
    """bench/stops_map.py's map: the damper with its stops at the block's edges."""
    damper = Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    params = {**damper.as_params(), **Stops.at_edges(BLOCK, damper).as_params()}
    return pulse_cases(BLOCK, *grid(n), model="omd_stops", params=params, rtol=1e-8)


#: Dampers of the other variants (tests/test_variants.py's): omd2 integrates 6 components, which the lanes write
#: back by a 4 x 4 transpose and 2 more, or 3 of 2 x 2.
VARIANTS = {
    "pendulum": dict(m=50.0, l=0.4, x_p=0.05, y_p=2.3, k_phi=60.0, c_phi=8.0),
    "omd2": dict(m1=40.0, h=0.05, k1=300.0, c1=11.0, m2=30.0, k2=500.0, c2=9.0),
}


def variant_map(name: str, n: int) -> Cases:
    return pulse_cases(BLOCK, *grid(n), model=name, params=VARIANTS[name], rtol=1e-8)


def no_early_verdict(cases: Cases) -> Cases:
    return Cases(cases.model, cases.p, {**cases.settings, "early_verdict": False})


def assert_scalar_results(lanes: dict, scalar: dict) -> float:
    """The discrete results identical, theta_max and x_max within BOUND; the largest relative difference."""
    for name in DISCRETE:
        assert np.array_equal(lanes[name], scalar[name]), name
    worst = 0.0
    for name in ("theta_max", "x_max"):
        a, b = lanes[name], scalar[name]
        assert np.array_equal(np.isnan(a), np.isnan(b)), name
        scale = np.maximum(np.abs(b), np.finfo(float).tiny)
        worst = max(worst, float(np.nanmax(np.abs(a - b) / scale)))
    assert worst <= BOUND, worst
    return worst


def same_bits(a: dict, b: dict) -> bool:
    return all(np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f") for k in RESULT_FIELDS)


@pytest.mark.parametrize(
    "cases",
    [
        pytest.param(lambda: bench_map(9), id="bench"),
        pytest.param(lambda: stops_map(6), id="stops"),
        pytest.param(lambda: no_early_verdict(bench_map(6)), id="early-verdict-off"),
        pytest.param(lambda: bench_map(5, psi=0.7), id="phase"),
        pytest.param(lambda: bench_map(4, motion="ricker"), id="ricker"),
        pytest.param(lambda: bench_map(4, vertical=Vertical(0.5)), id="vertical"),
        pytest.param(lambda: bench_map(4, floor=Floor(0.4)), id="friction"),
        pytest.param(lambda: pulse_cases(BLOCK, *grid(5)), id="bare-block"),
        pytest.param(lambda: variant_map("pendulum", 4), id="pendulum"),
        pytest.param(lambda: variant_map("omd2", 5), id="omd2"),
    ],
)
def test_lanes_give_the_scalar_verdicts(cases):
    """Lanes against the scalar path: each map holds overturns and safe responses; every case identical in its
    discrete results, theta_max and x_max within the bound."""
    cases = cases()
    scalar = cb.simulate_cases(cases, threads=1, lanes=False)
    lanes = cb.simulate_cases(cases, threads=1)
    assert np.any(scalar["overturned"]) and not np.all(scalar["overturned"])
    assert_scalar_results(lanes, scalar)


@pytest.mark.parametrize("cases", [lambda: bench_map(6), lambda: variant_map("omd2", 4)], ids=["omd", "omd2"])
def test_lanes_do_not_depend_on_the_width_or_the_cut(monkeypatch, cases):
    """A case's lanes results are a function of the case alone: the same bits with AVX-512, AVX2 or SSE2 vectors
    (ROCKING_LANES_ISA), in one batch or in chunks on threads."""
    cases = cases()
    widths = {}
    for isa in ("sse2", "avx2", "avx512", ""):
        monkeypatch.setenv("ROCKING_LANES_ISA", isa)
        widths[cb.lanes(cases.model)] = cb.simulate_cases(cases, threads=1)
    assert 2 in widths
    if len(widths) < 2:
        pytest.skip("SSE2 alone on this CPU: one width")
    first = next(iter(widths.values()))
    assert all(same_bits(first, other) for other in widths.values())
    assert same_bits(first, cb.simulate_cases(cases, threads=3))


@pytest.mark.parametrize("cases", [lambda: bench_map(5), lambda: stops_map(4)], ids=["bench", "stops"])
def test_a_case_does_not_depend_on_its_neighbours(cases):
    """A vector keeps the values of its lanes' segments (constants, tolerances, pulse) from step to step, gathered
    again when a lane starts a segment or a case: a case's results are the same bits in the batch, in the batch
    reversed (other cases beside it and before it in its lane) and alone (a batch of one). The stops map changes
    the model's constants within a run (a pad's regime)."""
    cases = cases()
    together = cb.simulate_cases(cases, threads=1)
    reversed_ = cb.simulate_cases(Cases.of([cases.problem(i) for i in range(len(cases))][::-1]), threads=1)
    assert same_bits(together, {k: v[::-1] for k, v in reversed_.items()})
    for i in (0, len(cases) // 2, len(cases) - 1):
        alone = cb.simulate_cases(Cases.of([cases.problem(i)]), threads=1)
        assert same_bits({k: v[i : i + 1] for k, v in together.items()}, alone)


def test_each_case_steps_with_its_own_tolerance():
    """Cases of two tolerances in one batch, alternating: each case's results are the same bits as in a batch of
    its tolerance alone (a vector's tolerances are gathered again with its segment values)."""
    cases = bench_map(6)
    rtol = np.where(np.arange(len(cases)) % 2 == 0, 1e-8, 1e-6)
    mixed = Cases(cases.model, cases.p, {**cases.settings, "rtol": rtol})
    together = cb.simulate_cases(mixed, threads=1)
    for value in (1e-8, 1e-6):
        at = np.flatnonzero(rtol == value)
        alone = cb.simulate_cases(Cases.of([mixed.problem(i) for i in at]), threads=1)
        assert same_bits({k: v[at] for k, v in together.items()}, alone)


def test_the_switch_is_the_scalar_path(monkeypatch):
    """ROCKING_LANES=0 turns the lanes off: the batch is then lanes=False's, which is rocking_simulate's bit for bit
    (tests/test_c_backend.py); the keyword is checked."""
    cases = bench_map(5)
    scalar = cb.simulate_cases(cases, threads=1, lanes=False)
    assert not same_bits(cb.simulate_cases(cases, threads=1), scalar)  # the lanes do run by default
    monkeypatch.setenv("ROCKING_LANES", "0")
    assert cb.lanes("omd") == 0
    assert same_bits(cb.simulate_cases(cases, threads=1), scalar)
    with pytest.raises(ValueError, match="lanes must be True or False"):
        cb.simulate_cases(cases, lanes=1)


def test_a_model_the_lanes_cannot_evaluate_runs_scalar():
    """A Hunt-Crossley pad's accelerations hold pow and fmax: the lanes refuse the model (its batch is scalar),
    and the rewriting of a straight-line body keeps its operations in order (tests/test_lanes.py's maps check
    the rewritten code against the scalar path)."""
    from rocking import load_model

    hc = load_model("omd_stops_hc")
    assert vector_rhs(hc.c_source.read_text(), hc.c_prefix).splitlines()[1] == "#define LANES_MODEL 0"
    assert cb.lanes(hc) == 0
    omd = load_model("omd")
    header = vector_rhs(omd.c_source.read_text(), omd.c_prefix)
    assert "#define LANES_MODEL 1" in header and "LANES_SINCOS(theta, &lanes_theta_s, &lanes_theta_c)" in header
    assert "out[1] = cse7*cst17+cse8*cst16;" in header
    assert "#define LANES_CONTACT 1" in header  # full contact over vectors too
    block = load_model("block")
    # The bare block's ddtheta = 0 in full contact: a double, added to zeros to make a vector.
    assert "out[0] = (VD){0} + (0);" in vector_rhs(block.c_source.read_text(), block.c_prefix)


def test_the_stop_flag_stops_the_lanes():
    """A stop flag set before the call ends every case STOPPED, in lanes as in the scalar loop."""
    import ctypes

    cases = bench_map(3)
    lib = cb.library("omd")
    stop = ctypes.c_int32(1)
    out = np.zeros(len(cases), dtype=cb.RESULT_DTYPE)
    lib.lib.rocking_simulate_batch_lanes(
        len(cases), cases.p, cb._records(cases), out, ctypes.byref(lib.control(stop)), 1
    )
    assert np.all(out["status"] == cb.boundary.STOPPED.value)
