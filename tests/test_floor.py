"""A floor with friction, the user's side (issue 37): rocking.Floor and its checks, the fields it travels in
(boundary.CASE's mu_s, mu_k; RESULT's u_max, u_end, slides), the options that ask for it (simulate, the studies,
--mu / --mu-k), saved studies, and the refusal of a back end that does not follow friction.

The physics of sliding is the back ends' (docs/model.md section 15); here, mu = inf must change nothing, bit for bit,
and a finite mu must reach the run or be refused in one line.
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np
import pytest

import rocking
from rocking import Block, Floor, OneSinePulse, ParameterError
from rocking.cli.main import build_parser, main
from rocking.cli.options import floor_from
from rocking.cli.study import GROUPS
from rocking.model.floor import check_pair
from rocking.model.loading import load_model
from rocking.sim import backends
from rocking.sim.batch import Cases
from rocking.sim.boundary import CASE, RESULT, field_named
from rocking.sim.cases import pulse_cases, run_cases, sampled_cases
from rocking.sim.problem import Problem, make_problem
from rocking.study.config import Grid, Setting, Tuning, floor_attrs
from rocking.study.overturning_map import overturning_map
from rocking.study.storage import check_fields, load, save
from rocking.study.tiles import Execution

BLOCK = Block.reference()
DAMPER = rocking.Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
#: Pulses that rock and return (beta 2), rock long with the damper, and overturn the bare block (beta 5).
PULSES = [OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega) for beta, Omega in ((2.0, 3.0), (5.0, 4.0))]
INFINITE = (
    {"floor": Floor()},
    {"floor": Floor(math.inf, math.inf)},
    {"mu": math.inf},
    {"mu": math.inf, "mu_k": math.inf},
)


# --------------------------------------------------------------------------- #
# Floor                                                                        #
# --------------------------------------------------------------------------- #


def test_a_floor_defaults_to_the_papers_and_its_kinetic_friction_to_the_static():
    assert (Floor().mu_s, Floor().mu_k, Floor().slides) == (math.inf, math.inf, False)
    assert (Floor(0.3).mu_k, Floor(0.3, 0.2).mu_k, Floor(0.3).slides) == (0.3, 0.2, True)
    assert Floor(1).settings() == {"mu_s": 1.0, "mu_k": 1.0, "e_n": 0.0} and type(Floor(1).mu_s) is float


@pytest.mark.parametrize(
    ("mu_s", "mu_k", "message"),
    [
        (0.0, None, r"^mu_s must be in \(0, inf\] \(got 0\.0\): Coulomb friction of the floor, dimensionless"),
        (-0.1, None, r"^mu_s must be in \(0, inf\] \(got -0\.1\)"),
        (math.nan, None, r"^mu_s must be in \(0, inf\] \(got nan\)"),
        (-math.inf, None, r"^mu_s must be in \(0, inf\] \(got -inf\)"),
        ("0.3", None, r"^mu_s must be a real number \(got '0\.3'\), in \(0, inf\]"),
        (True, None, r"^mu_s must be a real number \(got True\)"),
        (0.3, 0.0, r"^mu_k must be in \(0, mu_s\] \(got 0\.0\)"),
        (0.3, math.nan, r"^mu_k must be in \(0, mu_s\] \(got nan\)"),
        (0.3, 0.4, r"^mu_k must be in \(0, mu_s\] = \(0, 0\.3\] \(got 0\.4\): Coulomb's kinetic friction does not"),
        (math.inf, 0.3, r"^mu_k must be inf when mu_s is inf \(got 0\.3\): a floor that never lets the base start"),
    ],
)
def test_a_floor_out_of_range_is_refused_in_one_line_naming_the_coefficient_and_its_range(mu_s, mu_k, message):
    with pytest.raises(ParameterError, match=message) as refused:
        Floor(mu_s, mu_k)
    assert "\n" not in str(refused.value)


# --------------------------------------------------------------------------- #
# The fields                                                                   #
# --------------------------------------------------------------------------- #


def test_the_floor_and_the_slip_are_fields_of_the_boundary_with_the_papers_values_by_default():
    assert [field_named(CASE, n).default for n in ("mu_s", "mu_k")] == [math.inf, math.inf]
    assert [(f.name, f.unit, f.default) for f in RESULT[-6:-3]] == [
        ("u_max", "m", 0.0),
        ("u_end", "m", 0.0),
        ("slides", "", 0),
    ]
    problem = make_problem(BLOCK, None, PULSES[0])
    assert (problem.mu_s, problem.mu_k) == (math.inf, math.inf)
    floor = make_problem(BLOCK, None, PULSES[0], floor=Floor(0.3, 0.25))
    assert (floor.mu_s, floor.mu_k) == (0.3, 0.25)
    assert floor.settings()["mu_k"] == 0.25


def test_a_problem_and_a_batch_refuse_a_kinetic_friction_above_the_static():
    problem = make_problem(BLOCK, None, PULSES[0])
    with pytest.raises(ParameterError, match=r"^mu_k must be in \(0, mu_s\] = \(0, 0\.2\] \(got 0\.3\)"):
        Problem(model=problem.model, p=problem.p, **{**problem.settings(), "mu_s": 0.2, "mu_k": 0.3})
    with pytest.raises(ParameterError, match=r"^mu_s must be in \(0, inf\] \(got 0"):
        Problem(model=problem.model, p=problem.p, **{**problem.settings(), "mu_s": 0.0})
    cases = pulse_cases(BLOCK, [2.0, 3.0], [1.0, 2.0], floor=Floor(0.4, 0.3))
    assert cases.settings["mu_s"].tolist() == [0.4, 0.4] and cases.settings["mu_k"].tolist() == [0.3, 0.3]
    assert Cases.of([cases.problem(0), cases.problem(1)]).settings["mu_k"].tolist() == [0.3, 0.3]
    with pytest.raises(ParameterError, match=r"^mu_k must be inf when mu_s is inf \(got 0\.3\)"):
        check_pair(np.array([np.inf, np.inf]), np.array([np.inf, 0.3]))
    with pytest.raises(ParameterError, match=r"^mu_k must be in \(0, mu_s\] = \(0, 0\.2\] \(got 0\.3\)"):
        check_pair(np.array([0.5, 0.2]), 0.3)


@pytest.mark.parametrize("backend", ["c", "numpy"])
def test_an_infinite_friction_runs_bit_for_bit_as_the_run_without_a_floor(backend):
    """mu = inf is the paper's floor: each response is the one of the call without the floor argument, every
    field equal (the same back end, the same run: no tolerance); the slip fields read 0."""
    for damper in (None, DAMPER):
        for pulse in PULSES:
            before = rocking.simulate(BLOCK, damper, pulse, backend=backend).summary()
            assert (before["u_max"], before["u_end"], before["slides"]) == (0.0, 0.0, 0)
            for floor in INFINITE:
                assert rocking.simulate(BLOCK, damper, pulse, backend=backend, **floor).summary() == before, floor


def test_a_batch_with_an_infinite_friction_gives_the_batch_without():
    for cases in (
        (
            pulse_cases(BLOCK, [3.0, 4.0], [2.0, 5.0], gamma=0.05),
            pulse_cases(BLOCK, [3.0, 4.0], [2.0, 5.0], gamma=0.05, floor=Floor()),
        ),
        (sampled_cases(BLOCK, _record(), [1.0, 3.0]), sampled_cases(BLOCK, _record(), [1.0, 3.0], floor=Floor())),
    ):
        before, after = (run_cases(c, "c") for c in cases)
        assert before.keys() == after.keys() and all(before[k].tobytes() == after[k].tobytes() for k in before)
        assert not np.any(after["u_max"]) and not np.any(after["slides"])


def _record() -> rocking.SampledMotion:
    t = np.arange(0.0, 2.0, 0.01)
    return rocking.SampledMotion(np.sin(2 * np.pi * t) * 3.0, 0.01)


# --------------------------------------------------------------------------- #
# Asking for a floor, and the back ends that refuse it                         #
# --------------------------------------------------------------------------- #


def test_floor_and_its_shorthand_together_are_refused():
    with pytest.raises(ParameterError, match=r"^give floor= or its shorthand mu= \(with mu_k=\), not both$"):
        rocking.simulate(BLOCK, None, PULSES[0], floor=Floor(0.3), mu=0.3)
    with pytest.raises(ParameterError, match=r"^mu_k is the kinetic friction beside mu=: give mu"):
        rocking.simulate(BLOCK, None, PULSES[0], mu_k=0.3)
    with pytest.raises(ParameterError, match=r"^floor must be a rocking.Floor or None \(got 0.3\)$"):
        rocking.simulate(BLOCK, None, PULSES[0], floor=0.3)


def test_a_finite_friction_is_refused_by_a_back_end_that_does_not_follow_it():
    """Each back end that follows no friction (its flag in rocking.sim.backends) refuses a finite mu, a run or a
    batch, naming one that does; while none does, every choice, "auto" included, is refused."""
    able = [name for name, backend in backends.BACKENDS.items() if backend.friction]
    for name in [n for n in backends.BACKENDS if n not in able] + ([] if able else ["auto"]):
        expected = (
            f"the {backends.LABELS[name]} back end does not follow a floor with friction yet (mu_s = 0.3): "
            f"backend={able[0]!r}"
            if able
            else "no back end follows a floor with friction yet (mu_s = 0.3): give mu = inf (the default), the "
            "paper's floor"
        )
        with pytest.raises(ParameterError) as refused:
            rocking.simulate(BLOCK, None, PULSES[0], mu=0.3, backend=name)
        assert str(refused.value) == expected
        if name != "auto":
            with pytest.raises(ParameterError) as refused:
                run_cases(pulse_cases(BLOCK, [2.0], [2.0], floor=Floor(0.3)), name)
            assert str(refused.value) == expected


def test_the_refusal_names_the_back_end_that_follows_friction_and_auto_picks_it(monkeypatch):
    """Once a back end follows friction (its flag, declared once in rocking.sim.backends), the others name it."""
    monkeypatch.setattr(backends.BACKENDS["c"], "friction", False)
    monkeypatch.setattr(backends.BACKENDS["numpy"], "friction", True)
    with pytest.raises(ParameterError) as refused:
        rocking.simulate(BLOCK, None, PULSES[0], mu=0.3, backend="c")
    assert (
        str(refused.value) == "the C back end does not follow a floor with friction yet (mu_s = 0.3): backend='numpy'"
    )
    omd = load_model("omd")
    assert backends.for_floor("auto", 0.3, omd) == "numpy" and backends.for_floor("auto", math.inf, omd) == "auto"
    assert backends.for_floor("c", np.array([np.inf, np.inf]), omd) == "c"
    with pytest.raises(ParameterError, match=r"^the C back end does not follow .*\(mu_s = 0\.5\): backend='numpy'$"):
        backends.for_floor("c", np.array([np.inf, 0.5]), omd)


class _Spy:
    """A back end that follows friction and keeps the settings of its runs; the C back end runs them on the paper's
    floor (it follows no friction yet): the settings are what is checked, not the numbers."""

    friction = True

    def __init__(self):
        self.settings: list[dict] = []
        self.real = backends.BACKENDS["c"]

    def simulate(self, model, p, settings, record=False):
        self.settings.append(settings)
        return self.real.simulate(model, p, {**settings, "mu_s": math.inf, "mu_k": math.inf}, record)


def test_simulate_passes_mu_and_mu_k_to_the_run_from_python_and_the_command_line(monkeypatch, capsys):
    spy = _Spy()
    monkeypatch.setitem(backends.BACKENDS, "c", spy)
    rocking.simulate(BLOCK, None, PULSES[0], mu=0.5, mu_k=0.4, backend="c")
    rocking.simulate(BLOCK, None, PULSES[0], floor=Floor(0.6), backend="c")
    assert (
        main(["simulate", "--beta", "2", "--Omega", "3", "--mu", "0.3", "--mu-k", "0.2", "--backend", "c", "--json"])
        == 0
    )
    payload = json.loads(capsys.readouterr().out)
    assert [(s["mu_s"], s["mu_k"]) for s in spy.settings] == [(0.5, 0.4), (0.6, 0.6), (0.3, 0.2)]
    assert {"u_max", "u_end", "slides"} <= set(payload["responses"]["block alone"])
    assert payload["units"]["u_max"] == "m" and payload["units"]["slides"] == "1"
    assert payload["floor"] == {"mu_s": 0.3, "mu_k": 0.2, "e_n": 0.0}


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--mu", "0"], r"^--mu must be in \(0, inf\] \(got 0\.0\)"),
        (["--mu", "nan"], r"^--mu must be in \(0, inf\] \(got nan\)"),
        (["--mu", "0.3", "--mu-k", "0.4"], r"^--mu-k must be in \(0, --mu\] = \(0, 0\.3\] \(got 0\.4\)"),
        (["--mu-k", "0.4"], r"^--mu-k needs --mu \(the static\) too$"),
        (["--mu", "inf", "--mu-k", "0.4"], r"^--mu-k must be inf when mu_s is inf"),
    ],
)
def test_the_command_lines_floor_is_refused_by_its_flags(argv, message):
    args = build_parser().parse_args(["map", *argv])
    with pytest.raises(ParameterError, match=message):
        floor_from(args)


def test_every_study_of_pulses_and_motions_takes_mu_and_mu_k():
    (commands,) = (a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name in ("simulate", "map", "spectrum", "optimize", "design", "ida", "fragility"):
        options = {a.dest: a for a in commands.choices[name]._actions}
        assert {"mu", "mu_k"} <= set(options), name
        assert options["mu"].help.startswith("Coulomb friction of the floor, static (kinetic: --mu-k, default = --mu)")
    args = build_parser().parse_args(["map", "--mu", "0.3", "--mu-k", "0.2"])
    assert GROUPS["floor"].collect(args, {}) == {"floor": Floor(0.3, 0.2)}
    assert GROUPS["floor"].collect(build_parser().parse_args(["map"]), {}) == {}
    required = {
        rocking.overturning_map: {},
        rocking.minimum_overturning_spectrum: {},
        rocking.optimal_damper: {"gammas": [0.05], "Omega": [2.0], "beta": [1.0]},
        rocking.design: {},
        rocking.incremental_dynamic_analysis: {"scales": [1.0]},
        rocking.fragility: {"levels": [1.0]},
    }
    for function, arguments in required.items():  # each builds its Setting with the floor of mu, mu_k
        with pytest.raises(ParameterError, match=r"^mu_k must be in \(0, mu_s\] = \(0, 0\.3\] \(got 0\.4\)"):
            function(BLOCK, mu=0.3, mu_k=0.4, progress=False, **arguments)


def test_a_study_command_with_a_finite_friction_is_refused_in_one_line(capsys, tmp_path, monkeypatch):
    monkeypatch.setattr(backends.BACKENDS["c"], "friction", False)  # the refusal of a back end that does not follow it
    code = main(["map", "--mu", "0.3", "--Omega", "2", "3", "2", "--beta", "1", "2", "2", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code != 0 and err.count("\n") == 1
    assert "a floor with friction yet (mu_s = 0.3)" in err  # not followed by C, or by any back end


# --------------------------------------------------------------------------- #
# Saved studies                                                                #
# --------------------------------------------------------------------------- #

SMALL = {"Omega": Grid("Omega", 2.0, 4.0, 2), "beta": Grid("beta", 1.0, 3.0, 2)}


def _map(tmp_path, setting: Setting):
    return overturning_map(
        setting,
        Tuning(),
        SMALL["Omega"],
        SMALL["beta"],
        Execution(workers=1, progress=False),
        runs=tmp_path / "runs",
        full=True,
    )


def test_a_setting_records_a_finite_floor_and_nothing_for_the_papers():
    assert "floor" not in Setting(BLOCK).record() and Setting(BLOCK) == Setting(BLOCK, floor=None)
    floor = Setting(BLOCK, floor=Floor(0.3, 0.2))
    assert floor.record()["floor"] == {"mu_s": 0.3, "mu_k": 0.2}
    assert floor.pulse_args() == {"floor": Floor(0.3, 0.2)} and Setting(BLOCK).pulse_args() == {}
    assert floor_attrs({})["mu_s"] == math.inf and floor_attrs(floor.record())["mu_k"] == 0.2
    with pytest.raises(ParameterError, match=r"^floor must be a rocking.Floor or None"):
        Setting(BLOCK, floor=0.3)


def test_a_study_saved_before_the_floor_loads_with_the_papers(tmp_path):
    study = _map(tmp_path, Setting(BLOCK))
    save(study, tmp_path)
    record = json.loads((tmp_path / "map.json").read_text())
    assert "floor" not in record["config"]  # what every study saved before the floor holds
    loaded = load(tmp_path / "map")
    assert (loaded.data.attrs["mu_s"], loaded.data.attrs["mu_k"]) == (math.inf, math.inf)
    assert study.to_dataset().attrs["mu_s"] == math.inf


def test_a_study_with_a_floor_is_saved_and_loads_with_it(tmp_path, monkeypatch):
    """The plumbing only: the C back end is let run the floor's cases as the paper's floor (it follows no
    friction yet), so the responses are the no-slip ones; the floor must travel into the cases, the record, the
    Dataset and back, and a saved floor out of range is refused."""
    spy = []
    run = backends.BACKENDS["c"].simulate_cases

    def simulate_cases(cases, threads=1, lanes=True):
        spy.append((cases.settings["mu_s"].copy(), cases.settings["mu_k"].copy()))
        return run(cases, threads, lanes)

    monkeypatch.setattr(backends.BACKENDS["c"], "friction", True, raising=False)
    monkeypatch.setattr(backends.BACKENDS["c"], "simulate_cases", simulate_cases, raising=False)
    study = _map(tmp_path, Setting(BLOCK, floor=Floor(0.5, 0.4)))
    assert spy and all(np.all(s == 0.5) and np.all(k == 0.4) for s, k in spy)
    save(study, tmp_path)
    loaded = load(tmp_path / "map")
    assert loaded.config["floor"] == {"mu_s": 0.5, "mu_k": 0.4}
    assert (loaded.data.attrs["mu_s"], loaded.data.attrs["mu_k"]) == (0.5, 0.4)
    config = json.loads((tmp_path / "map.json").read_text())["config"]
    check_fields("map", config)
    for floor, refused in (
        ({"mu_s": 0.5, "mu_k": 0.6}, r"^setting: mu_k must be in \(0, mu_s\] = \(0, 0\.5\] \(got 0\.6\)"),
        ({"mu_s": 0.5}, r"^setting: floor: no mu_k in it"),
        ({"mu_s": math.inf, "mu_k": math.inf}, r"^setting: floor: .* is what a study records by leaving floor out"),
        (0.5, r"^setting: floor must be an object of e_n, mu_k, mu_s"),
    ):
        with pytest.raises(ParameterError, match=refused):
            check_fields("map", {**config, "floor": floor})


def test_a_study_run_with_mu_inf_saves_plain_json_and_reruns_from_it(tmp_path, capsys):
    """``--mu inf`` is valid (the paper's floor): the saved command keeps it as the text "inf", which strict JSON
    holds and ``--config`` reads back."""
    grids = ["--Omega", "2", "3", "2", "--beta", "1", "2", "2", "--full", "--no-progress"]
    assert main(["map", "--mu", "inf", *grids, "--out", str(tmp_path / "a")]) == 0

    def refuse(constant):
        raise ValueError(f"not JSON: {constant}")

    record = json.loads((tmp_path / "a" / "map.json").read_text(), parse_constant=refuse)
    assert record["command"]["options"]["mu"] == "inf" and "floor" not in record["config"]
    assert main(["map", "--config", str(tmp_path / "a" / "map.json"), "--out", str(tmp_path / "b")]) == 0
    assert f"map: the configuration of {tmp_path / 'a' / 'map.json'}, rerun exactly" in capsys.readouterr().out
