"""The command line: the same objects and results as the Python API, one flag style, plain help texts."""

from __future__ import annotations

import argparse
import functools
import json
import re
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

import rocking
from rocking import Block, Damper, Execution, Grid, OneSinePulse, Setting, Tuning
from rocking.cli.main import _print_summary, build_parser, main
from rocking.cli.options import block_from
from rocking.cli.study import setting_from, tuning_from
from rocking.model.loading import load_model
from rocking.reference.verify import verify
from rocking.study.overturning_map import overturning_map


def parsers(parser: argparse.ArgumentParser | None = None, name: str = "rocking"):
    """Every parser of the command, with its name: rocking and each subcommand (argparse keeps them in _actions)."""
    parser = parser or build_parser()
    yield name, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub_name, sub in action.choices.items():
                yield from parsers(sub, f"{name} {sub_name}")


def long_flags():
    for name, parser in parsers():
        for action in parser._actions:
            for option in action.option_strings:
                if option.startswith("--"):
                    yield name, option, action


# --- the same as Python ---------------------------------------------------------------------------


def test_simulate_sign_is_the_pulses_sign(capsys):
    """--sign -1 is OneSinePulse(..., sign=-1): the mirrored pulse, a different response on an eccentric block."""
    argv = ["simulate", "--gamma", "0.05", "--omega-ratio", "1", "--h", "0.05", "--beta", "3", "--Omega", "4"]
    assert main([*argv, "--sign", "-1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    block = Block.reference()
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1, h=0.05)
    # rocking simulate follows every run to rest (its --early-verdict does not).
    down = rocking.simulate(
        block, damper, OneSinePulse.from_nondim(block, beta=3, Omega=4, sign=-1), early_verdict=False
    )
    up = rocking.simulate(block, damper, OneSinePulse.from_nondim(block, beta=3, Omega=4), early_verdict=False)
    assert out["pulse"]["sign"] == -1
    assert out["responses"]["with damper"].pop("mass_past_edge") is (down.x_max > block.B / 2)
    assert json.dumps(out["responses"]["with damper"], sort_keys=True) == json.dumps(down.summary(), sort_keys=True)
    assert (down.overturned, down.impacts) != (up.overturned, up.impacts)
    assert main([*argv, "--sign", "0"]) == 2


@pytest.mark.parametrize("pulse, motion", [
    (["--pulse", "ricker-anti"], lambda b: rocking.RickerWavelet.from_nondim(b, beta=3, Omega=4, antisymmetric=True)),
    (["--pulse", "mp", "--gamma-mp", "2", "--nu", "0.5", "--sign", "-1"],
     lambda b: rocking.MavroeidisPapageorgiou.from_nondim(b, beta=3, Omega=4, gamma_mp=2.0, nu=0.5, sign=-1)),
])  # fmt: skip
def test_simulate_pulse_is_the_family_of_the_python_api(capsys, pulse, motion):
    """--pulse FAMILY with its shape options is that family's from_nondim; shape options of another are refused."""
    assert main(["simulate", "--no-damper", "--beta", "3", "--Omega", "4", *pulse, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    block = Block.reference()
    expected = rocking.simulate(block, None, motion(block), early_verdict=False)
    assert out["responses"]["block alone"].pop("mass_past_edge") is None  # no damper, no mass
    assert json.dumps(out["responses"]["block alone"], sort_keys=True) == json.dumps(expected.summary(), sort_keys=True)
    for bad in (["--pulse", "cosine", "--psi", "1"], ["--pulse", "mp"], ["--gamma-mp", "2"]):
        assert main(["simulate", "--beta", "3", "--Omega", "4", *bad]) == 2
        assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_simulate_with_only_H_B_M_is_rocking_simulate_of_the_same_block(capsys):
    """e not given: the Python default (0), not the reference block's (the 344 differing verdicts); h not given with
    --gamma: the studies' (rocking.Tuning), as a study of the same block runs."""
    argv = ["simulate", "--H", "1.8", "--B", "0.45", "--M", "300", "--gamma", "0.05", "--omega-ratio", "1"]
    assert main([*argv, "--beta", "3", "--Omega", "4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)

    block = Block(H=1.8, B=0.45, M=300)
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1, h=Tuning().h)
    response = rocking.simulate(block, damper, OneSinePulse.from_nondim(block, beta=3, Omega=4), early_verdict=False)
    assert out["block"] == block.as_params() and out["block"]["e"] == 0.0
    assert out["damper"] == damper.as_params() and out["damper"]["h"] == Tuning().h
    # Through JSON on both sides: nan and inf compare as text.
    assert out["responses"]["with damper"].pop("mass_past_edge") is (response.x_max > block.B / 2)
    assert json.dumps(out["responses"]["with damper"], sort_keys=True) == json.dumps(response.summary(), sort_keys=True)


@pytest.mark.parametrize(
    "block_options, block, damper_options, tuning",
    [
        (["--H", "1.8", "--B", "0.45", "--M", "300"], Block(H=1.8, B=0.45, M=300), ["--gamma", "0.05"], Tuning(0.05)),
        (
            ["--block", "reference"],
            Block.reference(),
            ["--gamma", "0.1", "--Tm-ratio", "0.8", "--zeta", "0.1", "--h", "0"],
            Tuning(0.1, omega_ratio=1 / 0.8, zeta=0.1, h=0.0),
        ),
    ],
)
def test_map_gives_the_arrays_of_the_python_study_api(block_options, block, damper_options, tuning, tmp_path, capsys):
    grids = ["--Omega", "1", "8", "5", "--beta", "1", "8", "6"]
    run = ["--workers", "1", "--no-progress", "--out", str(tmp_path / "cli")]
    assert main(["map", *block_options, *damper_options, *grids, *run]) == 0
    capsys.readouterr()

    study = overturning_map(
        Setting(block),
        tuning,
        Grid("Omega", 1.0, 8.0, 5),
        Grid("beta", 1.0, 8.0, 6),
        Execution(workers=1, progress=False),
        runs=tmp_path / "python",  # its own tiles: computed again, not read back from the command's
    )
    xr.testing.assert_identical(rocking.load(tmp_path / "cli" / "map").data, study.data)  # NaN: not computed
    config = json.loads((tmp_path / "cli" / "map.json").read_text())["config"]
    assert config["block"] == block.as_params() and config["damper"] == tuning.record()
    assert config == study.config
    assert study.data["overturned"].sel(part="bare").any()  # not a vacuous comparison


def test_omitted_options_are_the_python_defaults():
    parser = build_parser()
    args = parser.parse_args(["map"])
    assert setting_from(args) == Setting(Block.reference())  # the named default block, stated in the help
    assert tuning_from(args) == Tuning()
    args = parser.parse_args(["simulate", "--H", "1.8", "--B", "0.45", "--M", "300"])
    assert block_from(args) == Block(H=1.8, B=0.45, M=300)
    args = parser.parse_args(["simulate", "--p", "3", "--lam", "4"])
    assert block_from(args) == Block.from_nondim(p=3, lam=4)
    args = parser.parse_args(["simulate", "--block", "reference"])
    assert block_from(args) == Block.reference()


@pytest.mark.parametrize("command", ["simulate", "map", "spectrum", "optimize", "demo"])
def test_every_block_command_says_which_block_it_uses(command):
    text = dict(parsers())[f"rocking {command}"].format_help()
    assert "--block reference" in " ".join(text.split())


# --- one flag style, plain help texts, --version ---------------------------------------------------

#: Flags that keep the case of their docs/model.md symbol, and the Python parameter each one is.
SYMBOL_FLAGS = {
    "--H": (Block, "H"),
    "--B": (Block, "B"),
    "--M": (Block, "M"),
    "--Omega": (OneSinePulse.from_nondim, "Omega"),
    "--T-g": (rocking.minimum_overturning_spectrum, "T_g"),
    "--T-m": (Damper.from_nondim, "T_m"),
    "--Tm-ratio": (Tuning, "Tm_ratio"),
    "--L": (rocking.Stops, "L"),
}


def test_one_flag_style():
    """Flag = Python name with - for _; lower case but for the symbols of docs/model.md."""
    import inspect

    for name, option, action in long_flags():
        assert re.fullmatch(r"--[A-Za-z][A-Za-z0-9]*(-[A-Za-z0-9]+)*", option), (name, option)
        if option in ("--help", "--version"):
            continue
        assert action.dest == option[2:].replace("-", "_"), (name, option)
        if option != option.lower():
            assert option in SYMBOL_FLAGS, (name, option)
    for func, attribute in SYMBOL_FLAGS.values():
        assert attribute in inspect.signature(func).parameters or hasattr(func, attribute)


@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "--k_m", "1"],
        ["simulate", "--T_m", "1"],
        ["optimize", "--Tm-range", "0.1", "10", "5"],
        ["map", "--gam", "0.05"],  # abbreviations are refused: one spelling per flag
        ["simulate", "--omega", "1"],
    ],
)
def test_old_and_abbreviated_flags_are_refused(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2 and "unrecognized arguments" in capsys.readouterr().err


def test_help_texts_have_no_rst_markup():
    markup = re.compile(r"``|`|:(func|class|mod|meth|data|attr):")
    for name, parser in parsers():
        text = parser.format_help()
        assert not markup.search(text), (name, markup.search(text).group())


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.strip() == f"rocking {rocking.__version__}"


def test_python_dash_m_rocking_runs_the_command_line():
    done = subprocess.run([sys.executable, "-m", "rocking", "--version"], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == f"rocking {rocking.__version__}"


# --- simulate, verify, derive ----------------------------------------------------------------------


def test_simulate_json_with_and_without_damper(capsys):
    code = main(
        ["simulate", "--gamma", "0.05", "--omega-ratio", "1", "--beta", "2.5", "--Omega", "3", "--compare", "--json"]
    )
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out["responses"]) == {"with damper", "block alone"}
    for r in out["responses"].values():
        assert r["status"] in ("overturned", "rest", "t_max", "max_events")
        assert r["theta_max"] > 0 and r["uplifts"] >= 1
    assert out["pulse"]["beta"] == pytest.approx(2.5)
    assert out["responses"]["block alone"]["x_max"] == 0.0
    assert out["responses"]["with damper"]["x_max"] > 0.0


def test_simulate_summary_and_plot(tmp_path, capsys):
    fig = tmp_path / "response.png"
    argv = ["simulate", "--H", "2", "--B", "0.5", "--M", "1000", "--gamma", "0.05", "--T-m", "2"]
    assert main([*argv, "--beta", "3", "--Omega", "2", "--compare", "--plot", str(fig)]) == 0
    text = capsys.readouterr().out
    assert "with damper:" in text and "block alone:" in text
    assert fig.stat().st_size > 10_000


def test_simulate_run_cut_at_t_max_has_no_verdict(capsys):
    """The pulse that overturns the block at 1.87 s, cut at t_max = 1 s: no "survives", the bound and the way on
    (docs/simulation.md rule 4); the JSON keeps its data."""
    argv = ["simulate", "--beta", "3", "--Omega", "4", "--t-max", "1"]
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "survives" not in "\n".join(lines) and lines[1].startswith("  block alone: no verdict (t_max); ")
    assert lines[2] == (
        "  block alone: NO VERDICT: the run reached t_max = 1 s before overturning, rest or a final bound "
        "(docs/simulation.md rule 4); overturning later is not excluded: follow it longer (a larger --t-max)"
    )
    assert main([*argv, "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["responses"]["block alone"]
    assert (got["status"], got["overturned"]) == ("t_max", False)


def test_simulate_run_cut_at_max_events_has_no_verdict(capsys):
    """A run cut by its bound on events (the Python API's max_events) is not called a survivor either."""
    block = Block.reference()
    pulse = OneSinePulse.from_nondim(block, beta=2, Omega=6)
    response = rocking.simulate(block, None, pulse, max_events=2)
    assert response.status == "max_events" and not response.overturned
    _print_summary(block, pulse, {"block alone": response}, {"block alone": None})
    out = capsys.readouterr().out
    assert "survives" not in out and "no verdict (max_events)" in out
    assert "NO VERDICT: the run reached max_events = 2 uplifts and impacts before overturning" in out


@pytest.mark.parametrize(
    "argv, message",
    [
        (["simulate", "--beta", "2"], "a pulse needs --Omega"),
        (["simulate", "--H", "-2", "--B", "0.5", "--M", "1", "--beta", "2", "--Omega", "2"], "H must be"),
        (["simulate", "--H", "2", "--B", "0.5", "--beta", "2", "--Omega", "2"], "needs --M"),
        (["simulate", "--block", "reference", "--e", "0", "--beta", "2", "--Omega", "2"], "not both"),
        (["simulate", "--beta", "2", "--Omega", "0"], "Omega"),
        (["simulate", "--zeta", "0.1", "--beta", "2", "--Omega", "2"], "needs --gamma"),
        (["simulate", "--m", "5", "--beta", "2", "--Omega", "2"], "needs --k-m"),
        (["simulate", "--m", "5", "--k-m", "9", "--gamma", "0.1", "--beta", "2", "--Omega", "2"], "not both"),
        (["simulate", "--h", "0.05", "--beta", "2", "--Omega", "2"], "--h is the damper's guide height"),
        (["simulate", "--beta", "2", "--Omega", "2", "--rtol", "0.5"], "rtol must be in"),
    ],
)
def test_simulate_bad_input_names_the_parameter(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("rocking simulate: error:") and message in err and "Traceback" not in err


def test_verify_command_reports_agreement(capsys):
    assert main(["verify", "--cases", "200"]) == 0
    out = capsys.readouterr().out
    assert all(f"model {name}:" in out for name in ("omd", "omd_stops", "omd_stops_hc", "block"))
    assert len(re.findall(r"^\d+ passed, 0 failed", out, re.M)) == 4


@pytest.mark.parametrize("argv, message", [
    (["--cases", "0"], "--cases must be an integer in [1, 100000] (got 0)"),  # was "40 passed" having checked nothing
    (["--cases", "-5"], "--cases must be an integer in [1, 100000] (got -5)"),
    (["--cases", "100000000"], "--cases must be an integer in [1, 100000] (got 100000000)"),  # was out of memory
    (["--seed", "-1"], "--seed must be an integer >= 0 (got -1)"),
])  # fmt: skip
def test_verify_refuses_cases_and_seed_out_of_range_before_any_work(argv, message, capsys, monkeypatch):
    monkeypatch.setattr("rocking.cli.main.load_model", lambda name: pytest.fail("loaded a model"))
    assert main(["verify", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"rocking verify: error: {message}: ") and err.count("\n") == 1, err


@pytest.mark.parametrize("keywords, message", [
    ({"n": 0}, r"^n must be an integer in \[1, 100000\] \(got 0\)"),
    ({"n": 10.0}, r"^n must be an integer in \[1, 100000\] \(got 10.0\)"),
    ({"seed": -1}, r"^seed must be an integer >= 0 \(got -1\)"),
])  # fmt: skip
def test_verify_function_names_its_keywords(keywords, message):
    with pytest.raises(rocking.ParameterError, match=message):
        verify(load_model("block"), **keywords)


def test_derive_is_the_derive_packages_command_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["derive", "--help"])
    assert exc.value.code == 0 and "--variant" in capsys.readouterr().out
    assert main(["derive", "--check", "--variant", "block"]) == 0


def test_derive_without_sympy_says_how_to_install_it():
    # A fresh interpreter in which SymPy cannot be imported (None in sys.modules blocks it).
    code = "import sys; sys.modules['sympy'] = None; from rocking.cli.main import main; sys.exit(main(['derive']))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 1 and done.stdout == ""
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and 'pip install "rocking[derive]"' in lines[0] and "sympy" in lines[0]


# --- bad input never escapes as a traceback (issue 10) --------------------------------------------


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--m", "1e-300", "--k-m", "200"], "m must be 0 or in [1e-16, 1e+13] kg (got 1e-300)"),
        (["--m", "50", "--k-m", "1e12", "--beta", "3", "--Omega", "4"], "omega_m must be in [1e-3 p, 1e4 p]"),
        (["--beta", "0.5", "--Omega", "5e-324"], "Omega must be in [0.01, 1000]"),
        (["--beta", "3", "--Omega", "4", "--t-max", "nan"], "--t-max must be finite"),
        (["--beta", "3", "--Omega", "4", "--rtol", "1"], "rtol must be in [1e-12, 0.01]"),
        (["--param", "m=50", "--param", "e=10", "--beta", "3", "--Omega", "4"], "e set by the block"),
        (["--H", "1e300", "--B", "0.5", "--M", "100", "--beta", "3", "--Omega", "4"], "H must be in [0.001, 1000] m"),
    ],
)
def test_simulate_refuses_bad_input_in_one_line(argv, message, capsys):
    assert main(["simulate", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("rocking simulate: error: ") and message in err and "Traceback" not in err
    assert err.count("\n") == 1


@pytest.mark.parametrize("argv, message", [
    (["--history", "nodir/h.csv"], r"--history nodir/h\.csv: cannot write \(No such file or directory\)"),
    (["--history", "nodir/h.nc"], r"--history nodir/h\.nc: cannot write \(No such file or directory\)"),
    (["--plot", "afile/x.png"], r"--plot afile/x\.png: cannot write \(Not a directory\)"),
    (["--plot", "h.xyz"], r"--plot must end in one of \.\w+(, \.\w+)* \(got 'h\.xyz'\)"),
])  # fmt: skip
def test_simulate_refuses_an_output_it_cannot_write_before_the_run(argv, message, capsys, tmp_path, monkeypatch):
    """A missing or unwritable folder, or a figure format matplotlib lacks: one line before any run (was a
    traceback of pandas, netCDF4 or matplotlib after it)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").touch()
    # The same signature (the help reads its defaults), but no run.
    monkeypatch.setattr(
        "rocking.cli.main.simulate", functools.wraps(rocking.simulate)(lambda *a, **k: pytest.fail("ran"))
    )
    assert main(["simulate", "--beta", "3", "--Omega", "4", *argv]) == 2
    err = capsys.readouterr().err
    assert re.fullmatch(f"rocking simulate: error: {message}\n", err), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


def test_simulate_a_write_that_fails_after_the_run_is_one_line(capsys, tmp_path, monkeypatch):
    """The folder is writable but the file cannot be written (a folder of that name): one line naming the flag."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "h.csv").mkdir()
    assert main(["simulate", "--beta", "3", "--Omega", "4", "--history", "h.csv"]) == 2
    err = capsys.readouterr().err
    assert err == "rocking simulate: error: --history h.csv: cannot write (Is a directory)\n"


def test_a_reader_that_goes_away_ends_the_command_quietly():
    """rocking simulate --json | head -c 10: exit 1 without a BrokenPipeError traceback (the reader closes the
    pipe before the run prints)."""
    command = [sys.executable, "-m", "rocking", "simulate", "--beta", "3", "--Omega", "4", "--json"]
    with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as proc:
        proc.stdout.close()
        err = proc.stderr.read()
    assert proc.returncode == 1 and err == ""


# --- the whole truth of one response ----------------------------------------------------------------

#: A 0.6 m block whose unlimited damper survives the one-sine pulse only by running its mass 1.3 m out.
WIDE = [
    "simulate",
    "--H",
    "2",
    "--B",
    "0.6",
    "--M",
    "1000",
    "--gamma",
    "0.05",
    "--omega-ratio",
    "1",
    "--beta",
    "3",
    "--Omega",
    "4",
]


def test_simulate_says_the_mass_went_past_the_edge(capsys):
    """Text: a warning line naming x_max, B/2 and the way out (--stops); JSON: mass_past_edge true; the block
    alone has no mass (null)."""
    assert main([*WIDE, "--compare"]) == 0
    lines = capsys.readouterr().out.splitlines()
    warning = [line for line in lines if "past the block's edge" in line]
    assert len(warning) == 1 and warning[0].startswith("  with damper: WARNING: the damper's mass went past")
    assert "> B/2 = 0.3 m" in warning[0] and warning[0].endswith("--stops puts end stops at the edges")
    assert main([*WIDE, "--compare", "--json"]) == 0
    responses = json.loads(capsys.readouterr().out)["responses"]
    assert responses["with damper"]["mass_past_edge"] is True and responses["with damper"]["x_max"] > 0.3
    assert responses["block alone"]["mass_past_edge"] is None


def test_simulate_stops_are_stops_at_edges_with_their_contacts(capsys):
    """--stops is Damper(..., stops=Stops.at_edges(block, damper)); the text and JSON give the stop contacts and
    the bumpers' largest force; the mass stays on the block."""
    assert main([*WIDE, "--stops", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    block = Block(H=2, B=0.6, M=1000)
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1, h=Tuning().h)
    damper = Damper(damper.m, damper.k_m, damper.c, damper.h, stops=rocking.Stops.at_edges(block, damper))
    expected = rocking.simulate(block, damper, OneSinePulse.from_nondim(block, beta=3, Omega=4), early_verdict=False)
    got = out["responses"]["with damper"]
    assert out["model"] == "omd_stops" and out["damper"] == damper.as_params()
    assert got.pop("mass_past_edge") is False
    assert json.dumps(got, sort_keys=True) == json.dumps(expected.summary(), sort_keys=True)
    assert got["stop_contacts"] > 0 and got["bumper_force_max"] > 0
    assert out["units"]["bumper_force_max"] == "N" and out["units"]["mass_past_edge"] == "1"
    assert main([*WIDE, "--stops"]) == 0
    text = capsys.readouterr().out
    assert f"{expected.stop_contacts} stop contact(s), bumper force max {expected.bumper_force_max:.4g} N" in text
    assert "past the block's edge" not in text


def test_simulate_stop_options_replace_the_edges_values(capsys):
    """--L and --k-b replace at_edges' values (and imply --stops); c_b keeps the pads' damping ratio on k_b."""
    assert main([*WIDE, "--L", "0.2", "--k-b", "5e4", "--json"]) == 0
    damper = json.loads(capsys.readouterr().out)["damper"]
    assert (damper["L"], damper["k_b"]) == (0.2, 5e4)
    assert damper["c_b"] == pytest.approx(2 * 0.2 * np.sqrt(5e4 * damper["m"]))
    assert main([*WIDE, "--stops", "--c-b", "0", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["damper"]["c_b"] == 0.0


@pytest.mark.parametrize("argv, message", [
    (["--stops", "--no-damper"], "--stops: end stops of the damper's guide: give the damper"),
    (["--stops", "--model", "omd"], "--stops: end stops run on the model omd_stops (got --model omd)"),
    (["--L", "0.4"], "L must be in (0, B/2] = (0, 0.3] m"),
    # Checked before the default c_b takes its square root (was a "math domain error" traceback).
    (["--stops", "--k-b", "-1"], "error: --k-b must be in (0, 1e+30] N/m (got -1.0)"),
    (["--L", "-1", "--c-b", "0"], "error: --L must be in (0, 1000] m (got -1.0)"),
    (["--n-b", "0.5"], "error: --n-b must be in [1, 10] (got 0.5)"),
])  # fmt: skip
def test_simulate_bad_stops_are_refused_in_one_line(capsys, argv, message):
    assert main([*WIDE, *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err


def test_simulate_pendulum_stroke_is_an_angle_past_the_edge_does_not_apply(capsys):
    """The pendulum's stroke is its rod's angle: mass_past_edge is null, and the text says nothing of an edge."""
    params = [x for p in ("m=50", "l=0.5", "x_p=0", "y_p=2.55", "k_phi=0", "c_phi=5.5") for x in ("--param", p)]
    argv = ["simulate", "--model", "pendulum", *params, "--beta", "3", "--Omega", "4"]
    assert main([*argv, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["responses"]["with damper"]["mass_past_edge"] is None
    assert main(argv) == 0
    assert "edge" not in capsys.readouterr().out


def _warnings(err: str) -> list[str]:
    return [line for line in err.splitlines() if line.startswith("rocking simulate: warning: ")]


def test_simulate_warns_of_a_damper_heavier_than_half_the_block(capsys):
    assert main(["simulate", "--gamma", "0.6", "--omega-ratio", "1", "--beta", "3", "--Omega", "4"]) == 0
    assert _warnings(capsys.readouterr().err) == [
        "rocking simulate: warning: the damper's mass is 0.6 of the block's (gamma > 0.5): a damper heavier than "
        "half the block is a second body, not a damper; is m (or --gamma) right?"
    ]
    assert main(["simulate", "--gamma", "0.5", "--omega-ratio", "1", "--beta", "3", "--Omega", "4"]) == 0
    assert _warnings(capsys.readouterr().err) == []


@pytest.mark.parametrize("rows, options, expected", [
    ("0 0\n0.01 2\n0.02 -1\n0.03 0\n", ["--unit", "g"], []),  # 2 g: a strong record, nothing to say
    ("0 0\n0.01 2\n0.02 -1\n0.03 0\n", ["--unit", "g", "--pga", "50"], ["the motion's PGA is 5.1 g, above the "
                                                                         "largest ever recorded (4.36 g)"]),
    ("0 0\n0.01 350\n0.02 -200\n0.03 0\n", ["--unit", "g", "--scale", "0.01"],
     ["read in g, its PGA is 350 g (> 20 g): its values look like cm/s2"]),
    ("0 0\n0.1 0.5\n0.2 -0.2\n0.3 0\n", ["--unit", "g"], ["dt = 0.1 s (> 0.05 s): too coarse"]),
])  # fmt: skip
def test_simulate_warns_of_an_implausible_record_in_one_line(capsys, tmp_path, rows, options, expected):
    """PGA past the largest recorded after scaling, a record 'in g' that looks like cm/s2, a dt above 0.05 s:
    each a warning of one line (the run goes on); a plausible record none."""
    path = tmp_path / "record.txt"
    path.write_text(rows)
    assert main(["simulate", "--no-damper", "--motion", str(path), *options]) == 0
    warned = _warnings(capsys.readouterr().err)
    assert len(warned) == len(expected)
    for line, text in zip(warned, expected, strict=True):
        assert text in line, line


@pytest.mark.parametrize(
    ("argv", "close"),
    [
        (["simulate", "--gama", "0.05"], "--gamma"),
        (["map", "--Omga", "1", "2", "3"], "--Omega"),
        (["ida", "--scals"], "--scales"),
    ],
)
def test_a_typo_gets_the_commands_usage_and_the_close_option(argv, close, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    err = capsys.readouterr().err
    assert stop.value.code == 2
    assert err.startswith(f"usage: rocking {argv[0]} ")
    assert f"{argv[1]} (did you mean {close}?)" in err


@pytest.mark.parametrize("argv, message", [
    (["--pga", "-1"], "error: --pga must be >= 0 m/s^2 (got -1.0)"),
    (["--scale", "nan"], "error: --scale must be finite (got nan)"),
    (["--beta", "3", "--Omega", "4", "--vertical-ratio", "-1"], "--vertical-ratio must be in [0, 10] (got -1.0)"),
    (["--beta", "3", "--Omega", "4", "--vertical-ratio", "1", "--vertical-phase", "9"], "error: --vertical-phase must"),
    (["--beta", "3", "--Omega", "4", "--gamma", "0.05", "--omega-ratio", "0"], "error: --omega-ratio must be in"),
    (["--beta", "3", "--Omega", "4", "--history-dt", "1e-9", "--history", "h.csv"], "error: --history-dt must be"),
])  # fmt: skip
def test_simulate_names_the_flag_the_user_typed(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "r.csv").write_text("t,a\n0,0\n0.01,0.1\n0.02,0\n")
    motion = [] if "--beta" in argv else ["--motion", "r.csv", "--unit", "g"]
    assert main(["simulate", *motion, *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err


def test_simulate_says_why_a_run_at_t_max_below_the_barrier_is_safe(capsys):
    """A large slender block whose damper's slow decay outlasts t_max: safe, proven by its energy (status
    below_barrier)."""
    argv = ["simulate", "--lam", "8", "--p", "1", "--beta", "2", "--Omega", "7", "--gamma", "0.05"]
    argv += ["--omega-ratio", "1"]
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].startswith("  with damper: survives; ") and lines[1].endswith("(below_barrier)")
    assert lines[2].startswith("  with damper: safe at t_max = ") and "least on the way to overturning" in lines[2]
