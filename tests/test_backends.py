"""The back-end registry (rocking.sim.backends): every back end by name, one interface, "auto" in one place."""

from __future__ import annotations

import numpy as np
import pytest

import rocking
from rocking import ParameterError
from rocking.sim import backends, c_backend, numpy_backend
from rocking.sim.backends import BACKENDS, NAMES
from rocking.sim.boundary import STATUS
from rocking.sim.cases import pulse_cases, run_cases
from rocking.sim.problem import RESULT_FIELDS, make_problem, resolve

BLOCK = rocking.Block.reference()
DAMPER = rocking.Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
PULSE = rocking.OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0)


def test_the_names():
    assert tuple(BACKENDS) == ("c", "numpy") and NAMES == ("auto", "c", "numpy")


@pytest.mark.parametrize("name, module", [("c", c_backend), ("numpy", numpy_backend)])
def test_one_run_is_the_back_end_s_own(name, module):
    """Through the registry, a run is its module's run on the same problem (the same code: the same bits)."""
    model, p, settings = resolve(BLOCK, DAMPER, PULSE, {})
    through = BACKENDS[name].simulate(model, p, settings, record=True)
    direct = module.simulate(make_problem(BLOCK, DAMPER, PULSE), record=True)
    assert through.summary() == direct.summary()
    assert all(np.array_equal(through.history[k], direct.history[k]) for k in direct.history)


@pytest.mark.parametrize("name", ["auto", "c", "numpy"])
def test_a_run_knows_its_inputs_and_the_back_end_that_ran_it(name):
    r = backends.simulate(name, *resolve(BLOCK, DAMPER, PULSE, {}))
    assert r.inputs.backend == ("c" if name == "auto" else name)
    assert r.inputs.model.name == "omd" and r.inputs.settings["t_p"] == PULSE.t_p


@pytest.mark.parametrize("name", ["c", "numpy"])
def test_a_batch_is_the_runs_of_its_cases(name):
    cases = pulse_cases(BLOCK, [2.0, 4.0], [2.0, 3.0], gamma=0.05, t_after=2.0)
    batch = run_cases(cases, name)
    assert set(batch) == set(RESULT_FIELDS) and all(len(v) == len(cases) for v in batch.values())
    for i in range(len(cases)):
        one = BACKENDS[name].simulate(cases.model, cases.p[i], cases.problem(i).settings())
        assert one.status == STATUS[batch["status"][i]]
        assert one.impacts == batch["impacts"][i]
        np.testing.assert_allclose(one.theta_max, batch["theta_max"][i], rtol=1e-12)


@pytest.mark.parametrize("backend", ["auto", "C", None])
def test_a_batch_refuses_another_name_in_one_line(backend):
    cases = pulse_cases(BLOCK, [2.0], [2.0])
    with pytest.raises(ParameterError, match=rf"^backend must be 'c' or 'numpy' \(got {backend!r}\)$"):
        run_cases(cases, backend)


def test_halted_stops_the_c_runs_inside_and_no_later_one():
    cases = pulse_cases(BLOCK, [2.0], [2.0], gamma=0.05)
    with backends.halted(), pytest.raises(KeyboardInterrupt):
        run_cases(cases, "c")
    assert len(run_cases(cases, "c")["status"]) == 1
