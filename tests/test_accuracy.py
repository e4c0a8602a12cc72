"""The tolerance check of ``rocking.simulate`` (issue 25, item 1).

docs/simulation.md, "Sensitivity to the tolerance".
"""

import json

import numpy as np
import pytest

import rocking
from rocking.cli.main import main
from rocking.sim import accuracy, boundary, run
from rocking.study import ida as ida_module
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.ida import envelope, incremental_dynamic_analysis
from rocking.study.suite import Suite
from rocking.study.tiles import Execution

BACKENDS = ["c", "numpy"]

# The case of issue 25: a bare eccentric block under white noise, 100+ impacts; C at rtol 1e-8 gives a
# theta_max 4.3 times below those of every other tolerance from 1e-6 to 1e-12.
BLOCK = rocking.Block(H=3.1597847506851258, B=0.9313975019469038, M=131.3667739110528, e=-0.16218004607891312)
NOISE = rocking.SampledMotion(
    np.random.default_rng(36630).normal(0, 2.0, 1000), dt=0.02, scale=1.1631753337122157, sign=-1
)
# The case of issue 35: C at 1e-8 and at 1e-10 both overturn (they agree, by chance); 1e-11 and 1e-12
# agree to 1 % on a safe 0.064 rad.
CHANCE = rocking.SampledMotion(np.random.default_rng(144).normal(0, 2.0, 1000), dt=0.02, scale=1.1, sign=-1)


def _sampled_sine(beta: float) -> rocking.SampledMotion:
    """A one-sine pulse of the reference block (Omega 4) as a record: a few impacts, a response that is not
    sensitive."""
    pulse = rocking.OneSinePulse.from_nondim(rocking.Block.reference(), beta=beta, Omega=4.0)
    t = np.linspace(0, 2 * np.pi / pulse.omega_g, 201)
    return rocking.SampledMotion(pulse.a_g * np.sin(pulse.omega_g * t), dt=t[1] - t[0])


def _counted(monkeypatch) -> list:
    """The ``(rtol, a_g)`` of every run of rocking.simulate."""
    runs, real = [], run._run
    monkeypatch.setattr(
        run,
        "_run",
        lambda model, p, case, *args: runs.append((case["rtol"], case["a_g"])) or real(model, p, case, *args),
    )
    return runs


def _results(r) -> dict:
    """The results of a run, without the tolerance check's."""
    return {k: v for k, v in r.summary().items() if k not in {f.name for f in boundary.CHECKED}}


def test_the_issue_35_case_agrees_by_chance_and_is_flagged(monkeypatch):
    """rtol 1e-8 and 1e-10 both overturn, but not alike: the ladder goes down to 1e-12 and reports its
    safe answer, with the spread of its runs."""
    once = {rtol: rocking.simulate(BLOCK, None, CHANCE, backend="c", rtol=rtol, check="none") for rtol in (1e-8, 1e-10)}
    assert once[1e-8].overturned and once[1e-10].overturned  # the old check's two runs agree
    fine, coarse = (rocking.simulate(BLOCK, None, CHANCE, backend="c", rtol=r, check="none") for r in (1e-12, 1e-11))
    assert not fine.overturned and coarse.theta_max == pytest.approx(fine.theta_max, rel=0.01)  # converged: safe
    assert fine.theta_max == pytest.approx(0.064, abs=5e-4)  # docs/simulation.md, Sensitivity to the tolerance
    runs = _counted(monkeypatch)
    r = rocking.simulate(BLOCK, None, CHANCE, backend="c")
    assert r.sensitive and not r.overturned and r.summary() == {**fine.summary(), **_checked(r)}
    # Its two runs at 1e-12 disagree too: chaotic, six more there for its spread.
    assert [rtol for rtol, _ in runs] == [1e-8, 1e-10, 1e-10, *[1e-12] * 8]
    a_g = runs[0][1]
    factors = [1, 1, 1 + 1e-9, 1, 1 + 1e-9, *(1 + k * 1e-9 for k in range(2, 8))]
    assert [a for _, a in runs] == [a_g * f for f in factors]
    assert r.check_runs == 11 and r.theta_max_low <= r.theta_max < r.theta_max_high == pytest.approx(np.pi / 2)
    assert 0 < r.overturned_fraction < 1


def _checked(r) -> dict:
    return {f.name: r.summary()[f.name] for f in boundary.CHECKED}


def test_the_issue_25_case_is_sensitive_and_reports_the_tightest_run():
    loose = rocking.simulate(BLOCK, None, NOISE, backend="c", check="none")
    tight = rocking.simulate(BLOCK, None, NOISE, backend="c", rtol=1e-12, check="none")
    r = rocking.simulate(BLOCK, None, NOISE, backend="c")  # checked by default: a sampled motion
    assert not loose.sensitive and r.sensitive
    assert abs(loose.theta_max - tight.theta_max) > 0.5 * tight.theta_max  # the case is what the issue says
    assert r.theta_max == tight.theta_max and r.impacts == tight.impacts  # the same back end: the same run
    assert r.theta_max_low == loose.theta_max and r.theta_max_high >= r.theta_max
    assert r.summary()["sensitive"] is True


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_response_that_is_not_sensitive_costs_the_first_rung_only(backend, monkeypatch):
    """Its runs at rtol / 100 follow its trajectory: the ladder stops there; it is the run at rtol, with the
    spread of its three runs."""
    motion = _sampled_sine(1.5)
    loose = rocking.simulate(rocking.Block.reference(), None, motion, backend=backend, check="none")
    runs = _counted(monkeypatch)
    r = rocking.simulate(rocking.Block.reference(), None, motion, backend=backend)
    assert [rtol for rtol, _ in runs] == [1e-8, 1e-10, 1e-10]
    assert not r.sensitive and _results(r) == _results(loose) and 0 < r.theta_max < 0.5
    assert r.check_runs == 3 and r.overturned_fraction == 0.0
    assert r.theta_max_low <= r.theta_max <= r.theta_max_high <= r.theta_max_low * (1 + accuracy.SAME_FRACTION)
    assert np.isnan(loose.theta_max_low) and np.isnan(loose.overturned_fraction) and loose.check_runs == 1


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_pulse_is_not_run_again_by_default(backend, monkeypatch):
    block = rocking.Block.reference()
    pulse = rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=4.0)
    runs = _counted(monkeypatch)
    assert not rocking.simulate(block, None, pulse, backend=backend).sensitive
    assert [rtol for rtol, _ in runs] == [1e-8]
    rocking.simulate(block, None, pulse, backend=backend, check="tolerance")
    assert [rtol for rtol, _ in runs] == [1e-8, 1e-8, 1e-10, 1e-10]
    rocking.simulate(block, None, _sampled_sine(1.5), backend=backend, rtol=1e-6)  # sampled: checked by default
    assert [rtol for rtol, _ in runs[4:]] == [1e-6, 1e-10, 1e-10]  # the first rung: at most 1e-10


@pytest.mark.parametrize("backend", BACKENDS)
def test_check_none_turns_it_off(backend):
    r = rocking.simulate(BLOCK, None, NOISE, backend=backend, rtol=1e-6, check="none")
    assert not r.sensitive and r.check_runs == 1 and np.isnan(r.theta_max_high)
    again = rocking.simulate(BLOCK, None, NOISE, backend=backend, rtol=1e-6, check="none")
    assert r.summary() == again.summary()  # the run at rtol, bit for bit: the same back end


def test_a_pulse_checked_on_demand_is_compared():
    block = rocking.Block.reference()
    pulse = rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=4.0)
    plain = rocking.simulate(block, None, pulse, backend="c")
    checked = rocking.simulate(block, None, pulse, backend="c", check="tolerance")
    assert not checked.sensitive and _results(checked) == _results(plain)  # a one-sine pulse's response does not move


def test_rerecord_keeps_the_checks_results():
    r = rocking.simulate(BLOCK, None, CHANCE, backend="c", record=True)
    again = run.rerecord(r, 0.05)
    assert _checked(again) == _checked(r) and again.theta_max == r.theta_max


@pytest.mark.parametrize("check", ["Tolerance", "", 1, True, ["none"]])
def test_bad_values_of_check_are_refused_in_one_line(check):
    with pytest.raises(rocking.ParameterError, match=r"^check must be one of none, tolerance \(got .*\)$"):
        rocking.simulate(BLOCK, None, NOISE, check=check)


def test_the_tighter_tolerance_is_floored_at_the_smallest_valid_one():
    assert accuracy.tighter_rtol(1e-8) == 1e-10
    assert accuracy.tighter_rtol(1e-11) == accuracy.RTOL_MIN == 1e-12
    boundary.check("rtol", accuracy.RTOL_MIN)
    with pytest.raises(rocking.ParameterError, match="rtol must be"):
        boundary.check("rtol", accuracy.RTOL_MIN * (1 - 1e-15))


def test_the_ladder_goes_down_by_two_decades_from_at_most_1e_10_to_the_smallest_rtol():
    assert accuracy.ladder(1e-8) == (1e-8, 1e-10, 1e-12)
    assert accuracy.ladder(1e-6) == (1e-6, 1e-10, 1e-12) and accuracy.ladder(0.01) == (0.01, 1e-10, 1e-12)
    assert accuracy.ladder(1e-9) == pytest.approx((1e-9, 1e-11, 1e-12), rel=1e-15)
    assert accuracy.ladder(3e-12) == (3e-12, 1e-12) and accuracy.ladder(1e-12) == (1e-12,)


def test_the_ladder_closes_each_response_of_a_batch_on_its_own():
    """Three responses: one whose first rung follows it (closed there), one whose runs met by chance (both
    overturned, other impacts: open to the last rung) and one that moves (sensitive, its tightest run reported)."""
    table = {  # rtol: (overturned, theta_max, impacts) of the three responses; the perturbed runs alike
        1e-8: ([0, 1, 0], [0.1, np.pi / 2, 0.2], [3, 40, 50]),
        1e-10: ([0, 1, 0], [0.1, np.pi / 2, 0.1], [3, 41, 60]),
        1e-12: ([0, 0, 0], [0.1, 0.06, 0.1], [3, 70, 60]),
    }

    def run_at(rtol, factor):
        over, theta, impacts = table[rtol]
        return {"overturned": np.array(over, bool), "theta_max": np.array(theta), "x_max": np.zeros(3),
                "impacts": np.array(impacts), "status": np.array([1, 1, 1]), "t_end": np.full(3, 20.0)}  # fmt: skip

    done = accuracy.tolerance_check(run_at, 1e-8)
    assert len(done.runs) == 5 and done.counted.sum(axis=0).tolist() == [3, 5, 5]
    assert done.results["sensitive"].tolist() == [False, True, True]
    assert done.reported.tolist() == [0, 3, 3]
    out = accuracy.checked_fields(run_at, 1e-8)
    assert out["theta_max"].tolist() == [0.1, 0.06, 0.1] and out["check_runs"].tolist() == [3, 5, 5]
    assert out["overturned_fraction"].tolist() == [0.0, 0.6, 0.0]
    assert out["theta_max_low"].tolist() == [0.1, 0.06, 0.1] and out["theta_max_high"].tolist() == [0.1, np.pi / 2, 0.2]


def test_at_the_smallest_rtol_there_is_nothing_to_compare_with():
    r = rocking.simulate(BLOCK, None, NOISE, backend="c", rtol=1e-12)
    assert not r.sensitive
    assert r.summary() == rocking.simulate(BLOCK, None, NOISE, backend="c", rtol=1e-12, check="none").summary()


def test_sensitive_compares_the_verdict_and_the_maxima_elementwise():
    loose = {
        "overturned": np.array([0, 1, 0, 0, 0]),
        "theta_max": np.array([0.1, 1.0, 0.1, 0.1, 0.0]),
        "x_max": np.array([0.2, 0.2, 0.2, 0.23, 0.0]),
    }
    tight = {
        "overturned": np.array([0, 0, 0, 0, 0]),
        "theta_max": np.array([0.105, 1.0, 0.12, 0.1, 0.0]),
        "x_max": np.array([0.21, 0.2, 0.2, 0.2, 0.0]),
    }
    assert accuracy.sensitive(loose, tight).tolist() == [False, True, True, True, False]
    assert accuracy.sensitive({k: v[0] for k, v in loose.items()}, {k: v[0] for k, v in tight.items()}) is False


def _noise_file(tmp_path):
    """The issue's white noise as a CSV record in m/s2, before its scale and sign (exact: 18 digits)."""
    path = tmp_path / "noise.csv"
    t = np.arange(NOISE.n) * NOISE.dt
    np.savetxt(path, np.column_stack([t, NOISE.a]), delimiter=",", header="time [s], a [m/s2]", comments="")
    return path


def test_rocking_simulate_prints_and_writes_the_flag(tmp_path, capsys):
    dims = [f"--H={BLOCK.H!r}", f"--B={BLOCK.B!r}", f"--M={BLOCK.M!r}", f"--e={BLOCK.e!r}"]
    motion = ["--motion", str(_noise_file(tmp_path)), f"--scale={NOISE.scale!r}", "--sign=-1"]
    argv = ["simulate", *dims, *motion, "--backend", "c"]
    assert main([*argv, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    expected = rocking.simulate(BLOCK, None, NOISE, backend="c", early_verdict=False).summary()  # as the command
    assert out["responses"]["block alone"] == {**expected, "mass_past_edge": None}  # no damper: no stroke
    assert out["responses"]["block alone"]["sensitive"] is True
    assert out["units"]["sensitive"] == "1"
    assert main(argv) == 0
    assert "block alone: SENSITIVE to the tolerance" in capsys.readouterr().out
    assert main([*argv, "--check", "none", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["responses"]["block alone"]["sensitive"] is False


def test_ida_reports_the_sensitive_responses_per_level(tmp_path):
    """The issue's case as a record of an IDA at its own scale: its response in its own direction is
    the checked rocking.simulate's, marked; the fraction per level is in the Dataset and the table."""
    path = _noise_file(tmp_path)
    suite = Suite.from_files([path], unit="m/s2")
    levels = Grid("scales", NOISE.scale, NOISE.scale, 1)
    serial = Execution(workers=1, progress=False)
    study = incremental_dynamic_analysis(
        Setting(BLOCK), Tuning(0.05), suite, levels, serial, directions="both", runs=tmp_path / "runs"
    )
    bare = study.data.sel(part="bare", sign=-1)
    assert bare["sensitive"].values[0, 0] and bare["theta_max"].values[0, 0] == pytest.approx(
        rocking.simulate(BLOCK, None, NOISE, backend="c").theta_max, rel=1e-12
    )
    both = envelope(study.data)
    for part in ("bare", "damper"):
        sensitive = study.data["sensitive"].sel(part=part).values
        np.testing.assert_array_equal(study.data["sensitive_fraction"].sel(part=part), sensitive.mean(axis=(0, 2)))
        np.testing.assert_array_equal(
            study.tables["ida"][f"{part}_sensitive"], both["sensitive"].sel(part=part).values.ravel()
        )
        np.testing.assert_array_equal(study.data["sensitive_responses"].sel(part=part), sensitive.sum(axis=(1, 2)))
    ds = study.to_dataset()
    fraction = ds["sensitive_fraction"]
    assert fraction.dims == ("part", "level") and fraction.attrs["units"] == "1"
    assert float(fraction.sel(part="bare")[0]) >= 0.5


def test_an_ida_of_pulses_runs_each_response_once(tmp_path, monkeypatch):
    block = rocking.Block.reference()
    pulses = [rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=Omega) for Omega in (3.0, 5.0)]
    calls = []
    real = ida_module.run_cases
    monkeypatch.setattr(ida_module, "run_cases", lambda cases, **kw: calls.append(len(cases)) or real(cases, **kw))
    study = incremental_dynamic_analysis(
        Setting(block),
        Tuning(0.05),
        Suite.from_pulses(pulses),
        Grid("scales", 0.5, 2.0, 3),
        Execution(workers=1, progress=False),
        runs=tmp_path,
    )
    assert sum(calls) == study.run["responses"]  # each response once: none again
    assert len(calls) == study.run["tiles_computed"]  # one batch a tile
    # Not checked: no response is marked sensitive or not, and the fraction is unknown (NaN), not 0.
    assert "sensitive" not in study.data and np.isnan(study.data["sensitive_fraction"]).all()


def _counted_runs(monkeypatch) -> list:
    """The batches the IDA's tiles run, by their number of cases."""
    calls, real = [], ida_module.run_cases
    monkeypatch.setattr(ida_module, "run_cases", lambda cases, **kw: calls.append(len(cases)) or real(cases, **kw))
    return calls


def _responses(data) -> int:
    """The responses of an IDA's data: parts, motions, levels and directions."""
    return int(np.prod([data.sizes[dim] for dim in ("part", "motion", "level", "sign")]))


def test_ida_check_turns_the_tolerance_check_on_for_pulses_and_off_for_records(tmp_path, monkeypatch):
    """check="tolerance" runs a pulse's responses again; check="none" runs a record's once, so that the
    issue's sensitive case is not flagged."""
    block = rocking.Block.reference()
    pulses = [rocking.OneSinePulse.from_nondim(block, beta=3.0, Omega=Omega) for Omega in (3.0, 5.0)]
    calls = _counted_runs(monkeypatch)
    few = {"workers": 1, "progress": False, "backend": "c"}
    ds = rocking.incremental_dynamic_analysis(
        block, {"gamma": 0.05}, motions=pulses, scales=[0.5, 2.0], check="tolerance", runs=tmp_path / "p", **few
    )
    assert sum(calls) == 3 * _responses(ds)  # each response: its run and the first rung's two, none again
    assert json.loads(ds.attrs["config"])["check"] == "tolerance"
    calls.clear()
    path = _noise_file(tmp_path)
    ds = rocking.incremental_dynamic_analysis(
        BLOCK, None, motions=[path], unit="m/s2", scales=[NOISE.scale], directions="both", check="none",
        runs=tmp_path / "r", **few,
    )  # fmt: skip
    assert sum(calls) == _responses(ds) and "sensitive" not in ds  # not checked: not marked either way
    checked = rocking.incremental_dynamic_analysis(
        BLOCK, None, motions=[path], unit="m/s2", scales=[NOISE.scale], directions="both", runs=tmp_path / "r", **few
    )
    assert checked["sensitive"].sel(part="bare").any()  # the default for a record: checked


def test_ida_refuses_an_unknown_check_before_any_run(tmp_path, monkeypatch):
    calls = _counted_runs(monkeypatch)
    pulse = rocking.OneSinePulse.from_nondim(rocking.Block.reference(), beta=3.0, Omega=3.0)
    with pytest.raises(rocking.ParameterError, match=r"^check must be one of none, tolerance \(got 'fast'\)$"):
        rocking.incremental_dynamic_analysis(
            rocking.Block.reference(), motions=[pulse], scales=[1.0], check="fast", runs=tmp_path, progress=False
        )
    assert calls == []


def test_cli_ida_check(tmp_path, monkeypatch, capsys):
    """rocking ida --check tolerance checks a suite of pulses; a value not of --check's is refused."""
    calls = _counted_runs(monkeypatch)
    argv = ["ida", "--pulses", "sine", "--periods", "0.5", "1", "--scales", "0.5", "2", "2", "--workers", "1"]
    argv += ["--no-progress", "--t-after", "5", "--out", str(tmp_path)]
    assert main([*argv, "--check", "tolerance"]) == 0
    assert sum(calls) == 3 * _responses(rocking.load(tmp_path / "ida.json").data)
    assert rocking.load(tmp_path / "ida.json").config["check"] == "tolerance"
    assert "responses sensitive to the tolerance" in capsys.readouterr().out
    calls.clear()
    assert main([*argv, "--check", "none"]) == 0
    assert sum(calls) == _responses(rocking.load(tmp_path / "ida.json").data)
    with pytest.raises(SystemExit):
        main([*argv, "--check", "fast"])
    assert "--check: invalid choice: 'fast' (choose from" in capsys.readouterr().err
