"""Python does what the command line does: every option of a study command is a keyword of its function."""

import argparse
import inspect
import warnings

import numpy as np
import pytest

import rocking
from rocking.cli.main import build_parser, main
from rocking.model.stochastic import SiteModel
from rocking.study.api import runs_folder

#: Each study command and its Python function.
FUNCTIONS = {
    "map": rocking.overturning_map,
    "spectrum": rocking.minimum_overturning_spectrum,
    "optimize": rocking.optimal_damper,
    "design": rocking.design,
    "threshold": rocking.threshold_map,
    "ida": rocking.incremental_dynamic_analysis,
    "fragility": rocking.fragility,
    "friction": rocking.friction_map,
}

#: Commands of the command line only, and why.
COMMANDS_ONLY = {
    "demo": "runs map, spectrum, design and threshold on their default grids, one after the other",
    "redraw": "draws the figures of saved files: rocking.plot.figures.redraw(path)",
}

#: Options that build one object, given to the function as that object or a mapping of its keywords: the
#: keyword, and the constructors whose parameters the options are.
OBJECTS = {
    "block": (rocking.Block, rocking.Block.from_nondim),
    "damper": (rocking.Tuning, rocking.Variant),
    "site": (SiteModel,),
}

#: Options that are another form of a keyword, and why.
FORMS = {
    "Tm_ratio": "the damper's period, damper={'Tm_ratio': ...}: omega_ratio = 1 / Tm_ratio (a keyword elsewhere)",
    "param": "--param NAME=VALUE, repeated: the mapping of rocking.Variant(model, params), damper=Variant(...)",
    "levels_log": "levels=rocking.Grid('levels', MIN, MAX, N, log=True)",
    "scales_log": "scales=rocking.Grid('scales', MIN, MAX, N, log=True)",
}

#: Options of the command line only, and why.
COMMAND_LINE_ONLY = {
    "out": "the folder of the files the command writes; Python returns the data (runs=: where the tiles are kept)",
    "no_progress": "progress=False",
    "formats": "the formats of the figure the command draws; Python returns the data: rocking.plot.figures.draw",
    "pdf": "--formats png,pdf",
    "config": "reruns a saved study with its options; in Python, call the function again",
    "help": "argparse's",
}


def _options(command: str) -> list[str]:
    (commands,) = (a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return [a.dest for a in commands.choices[command]._actions if a.option_strings]


def _keyword_of(name: str, keywords) -> bool:
    """``name`` is a keyword, or a parameter of an object the function takes by its keyword."""
    if name in keywords:
        return True
    return any(
        keyword in keywords and any(name in inspect.signature(make).parameters for make in makes)
        for keyword, makes in OBJECTS.items()
    )


def test_every_study_command_has_its_function_or_says_why():
    (commands,) = (a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    studies = set(FUNCTIONS) | set(COMMANDS_ONLY)
    assert studies <= set(commands.choices)


@pytest.mark.parametrize("command", sorted(FUNCTIONS))
def test_every_option_is_a_keyword_of_the_function(command):
    keywords = inspect.signature(FUNCTIONS[command]).parameters
    missing = [
        "--" + name.replace("_", "-")
        for name in _options(command)
        if not _keyword_of(name, keywords) and name not in FORMS and name not in COMMAND_LINE_ONLY
    ]
    assert not missing, f"rocking {command}: options without a keyword of {FUNCTIONS[command].__name__}: {missing}"


@pytest.mark.parametrize("command", sorted(FUNCTIONS))
def test_the_explained_exceptions_are_options_of_some_command(command):
    # A stale entry would excuse an option that no longer exists.
    every = {name for c in FUNCTIONS for name in _options(c)}
    assert set(FORMS) <= every and set(COMMAND_LINE_ONLY) <= every


def test_the_mp_spectrum_in_python_is_the_command_lines(tmp_path, capsys):
    block = rocking.Block.reference()
    ds = rocking.minimum_overturning_spectrum(
        block, None, Omega=[4.0], beta=rocking.Grid("beta", 0.5, 8.0, 4), pulse="mp", gamma_mp=2.0, nu=0.5,
        runs=tmp_path / "p", workers=1, progress=False,
    )  # fmt: skip
    argv = ["spectrum", "--Omega", "4", "4", "1", "--beta", "0.5", "8", "4", "--workers", "1", "--no-progress"]
    assert main([*argv, "--pulse", "mp", "--gamma-mp", "2", "--nu", "0.5", "--out", str(tmp_path / "c")]) == 0
    saved = rocking.load(tmp_path / "c" / "spectrum.nc").data
    assert np.array_equal(ds["beta_min"].values, saved["beta_min"].values, equal_nan=True)
    assert np.isfinite(ds["beta_min"].sel(part="bare")).any()


def test_the_damper_mapping_takes_the_period_as_the_command_line_does(tmp_path):
    block = rocking.Block.reference()
    by_period, by_frequency = (
        rocking.overturning_map(block, damper, Omega=[4.0], beta=[3.0], runs=tmp_path, workers=1, progress=False)
        for damper in ({"Tm_ratio": 2.0}, {"omega_ratio": 0.5})
    )
    assert by_period["overturned"].equals(by_frequency["overturned"])
    with pytest.raises(rocking.ParameterError, match=r"^Tm_ratio must be > 0 \(got -1\)$"):
        rocking.overturning_map(block, {"Tm_ratio": -1}, Omega=[4.0], beta=[3.0], runs=tmp_path, progress=False)


def test_studies_from_python_keep_their_tiles_in_the_users_cache_and_say_so(monkeypatch, tmp_path, capsys):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    assert runs_folder() == tmp_path / "cache" / "rocking" / "runs"
    block = rocking.Block.reference()
    rocking.overturning_map(block, None, Omega=[4.0], beta=[3.0], workers=1)
    assert any(runs_folder().iterdir()) and not (tmp_path / "out").exists()
    assert f"rocking.overturning_map: tiles kept in {runs_folder()} (runs= to choose)" in capsys.readouterr().err


def _records(tmp_path) -> tuple:
    """One motion, written twice without a unit: in g and in cm/s^2."""
    t = np.arange(0.0, 2.0, 0.01)
    a_g = 0.3 * np.sin(2 * np.pi * t) * (t < 1.0)
    paths = tmp_path / "in_g.txt", tmp_path / "in_gal.txt"
    for path, a in zip(paths, (a_g, a_g * 980.665)):
        path.write_text("".join(f"{ti:.2f} {ai:.9g}\n" for ti, ai in zip(t, a)))
    return paths


def test_each_record_file_carries_its_own_unit(tmp_path):
    in_g, in_gal = _records(tmp_path)
    suite = rocking.Suite.from_files([(in_g, "g"), in_gal], unit="cm/s2")
    first, second = suite.motion(0), suite.motion(1)
    assert np.allclose(first.a, second.a, rtol=1e-8) and abs(first.a).max() == pytest.approx(0.3 * 9.80665, 1e-6)
    with pytest.raises(rocking.ParameterError, match=r"^unit of .*in_g.txt must be one of g, .* \(got 'gal'\)$"):
        rocking.Suite.from_files([(in_g, "gal")])


def test_the_command_line_gives_a_file_its_unit_and_log_levels(tmp_path):
    in_g, in_gal = _records(tmp_path)
    argv = ["ida", "--motions", f"{in_g}:g", f"{in_gal}:cm/s2", "--scales-log", "0.5", "8", "3", "--check", "none"]
    assert main([*argv, "--workers", "1", "--no-progress", "--out", str(tmp_path / "c")]) == 0
    data = rocking.load(tmp_path / "c" / "ida.nc").data
    assert np.allclose(data["level"].values, [0.5, 2.0, 8.0])
    assert data["im"].values[0] == pytest.approx(data["im"].values[1], rel=1e-8)
    assert np.array_equal(data["overturned"][:, 0].values, data["overturned"][:, 1].values)


@pytest.mark.parametrize("motions, option", [
    (["--motions", "in_g.txt:ft"], "--motions"),
    (["--motions", "in_g.txt:g", "--vertical-motions", "in_g.txt:ft"], "--vertical-motions"),
])  # fmt: skip
def test_a_mistyped_unit_after_a_record_is_named_as_a_unit(tmp_path, monkeypatch, capsys, motions, option):
    """FILE:ft with FILE a record: refused as a unit, by its option (was: "/abs/in_g.txt:ft: cannot be read")."""
    _records(tmp_path)
    monkeypatch.chdir(tmp_path)
    assert main(["ida", *motions, "--scales", "0.25", "4", "2", "--no-progress", "--out", "c"]) == 2
    assert capsys.readouterr().err == (
        f"rocking ida: error: {option} in_g.txt:ft: 'ft' is none of the units g, m/s2, cm/s2 (and in_g.txt:ft is "
        "no file)\n"
    )


def test_a_record_whose_name_holds_a_colon_still_reads(tmp_path, monkeypatch):
    """The Python API names the keyword; a file that exists is read whatever its name."""
    in_g, _ = _records(tmp_path)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(rocking.ParameterError, match=r"^motions in_g\.txt:ft: 'ft' is none of the units g, "):
        rocking.Suite.from_files(["in_g.txt:ft"])
    (tmp_path / "in_g.txt:ft").write_bytes(in_g.read_bytes())
    suite = rocking.Suite.from_files(["in_g.txt:ft"], unit="g")
    assert suite.files[0][0] == str(tmp_path / "in_g.txt:ft")


def test_a_lognormal_of_few_motions_or_no_dispersion_is_warned(tmp_path, capsys):
    from rocking.study.fragility import MIN_DISPERSION, MIN_MOTIONS, fit_warnings

    assert fit_warnings(MIN_MOTIONS, {"status": "fitted", "dispersion": 0.3}) == []
    assert fit_warnings(MIN_MOTIONS, {"status": "none_overturned", "dispersion": float("nan")}) == []
    (few,) = fit_warnings(2, {"status": "fitted", "dispersion": 0.3})
    assert few.startswith("the lognormal is fitted to 2 motions, fewer than 10: its dispersion is uncertain by about")
    (flat,) = fit_warnings(MIN_MOTIONS, {"status": "fitted", "dispersion": MIN_DISPERSION / 2})
    assert flat.startswith("the fitted dispersion 0.025 is below 0.05")
    in_g, in_gal = _records(tmp_path)  # the same record twice, as the user did
    argv = ["fragility", "--motions", f"{in_g}:g", f"{in_gal}:cm/s2", "--levels", "1", "4", "7", "--check", "none"]
    assert main([*argv, "--workers", "1", "--no-progress", "--out", str(tmp_path / "c")]) == 0
    err = capsys.readouterr().err.splitlines()
    assert "rocking fragility: warning: block alone: the lognormal is fitted to 2 motions, fewer than 10" in err[0]
    assert any("the fitted dispersion" in line and "below 0.05" in line for line in err)


def test_the_fit_is_data_named_median_and_dispersion_and_the_motions_by_name(tmp_path):
    """The fit and the counts of each part are variables (the summary is empty), saved and read back; the
    FitWarning of three motions points at this call."""
    from rocking.study.fragility import fit_lognormal
    from rocking.study.ida import envelope

    block = rocking.Block.reference()
    pulses = [rocking.RickerWavelet.from_period(3.0, T) for T in (0.5, 1.0, 2.0)]
    levels = [1.0, 2.0, 4.0, 8.0]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        study = rocking.fragility(
            block, {"gamma": 0.05}, motions=pulses, levels=levels, im="amplitude", runs=tmp_path,
            workers=1, progress=False, study=True,
        )  # fmt: skip
    fit_warned = [w for w in caught if issubclass(w.category, rocking.FitWarning)]
    assert fit_warned and {w.filename for w in fit_warned} == {__file__}
    data = study.data
    fit = fit_lognormal(levels, envelope(data)["overturned"].sel(part="bare").values.astype(bool))
    assert fit["status"] == "fitted" and study.summary == {}
    assert data["motion"].values.tolist() == ["ricker-T0.5-0", "ricker-T1-1", "ricker-T2-2"]
    assert data["median"].attrs["units"] == "m/s^2" and data["dispersion"].attrs["units"] == "1"
    bare = data.sel(part="bare")
    assert float(bare["median"]) == pytest.approx(fit["median"])
    assert float(bare["dispersion"]) == pytest.approx(fit["dispersion"])
    assert float(bare["log_likelihood"]) == pytest.approx(fit["log_likelihood"])
    assert bare["median_low"] <= bare["median"] <= bare["median_high"]
    assert bare["dispersion_low"] <= bare["dispersion"] <= bare["dispersion_high"]
    status = data["fit_status"].attrs
    assert status["flag_meanings"].split()[int(bare["fit_status"])] == "fitted" and int(bare["resamples"]) > 0
    rocking.save(study, tmp_path / "out")
    again = rocking.load(tmp_path / "out" / "fragility.nc").data
    for k in ("median", "dispersion", "fit_status", "resamples", "undetermined", "sensitive_responses", "reversals"):
        np.testing.assert_array_equal(again[k].values, data[k].values)
    table = (tmp_path / "out" / "fragility-fit.csv").read_text().splitlines()
    assert table[0].startswith("part,median [m/s^2],dispersion [1],") and table[1].startswith("bare,")
    assert "fit_status [1],fit_status_text," in table[0] and ",fitted," in table[1]


def test_study_csv_headers_carry_units_and_codes_their_words(tmp_path):
    study = rocking.minimum_overturning_spectrum(
        rocking.Block.reference(), None, Omega=[2.0, 6.0], beta=[0.5, 2, 4, 8, 15], runs=tmp_path / "r",
        workers=1, progress=False, study=True,
    )  # fmt: skip
    rocking.save(study, tmp_path / "o")
    header, first = ((tmp_path / "o" / "spectrum.csv").read_text().splitlines()[i].split(",") for i in (0, 1))
    assert header[:4] == ["Omega [1]", "T_g [s]", "bare_beta_min [1]", "bare_beta_min_lower_bound [1]"]
    flag, text = header.index("bare_flag [1]"), header.index("bare_flag_text")
    assert text == flag + 1
    meanings = study.data["flag"].attrs["flag_meanings"].split()
    assert first[text] == meanings[list(study.data["flag"].attrs["flag_values"]).index(int(first[flag]))]
    study = rocking.overturning_map(
        rocking.Block.reference(), None, Omega=[4.0], beta=[3.0], runs=tmp_path / "r", workers=1, progress=False,
        study=True,
    )  # fmt: skip
    rocking.save(study, tmp_path / "o")
    header = (tmp_path / "o" / "map.csv").read_text().splitlines()[0].split(",")
    assert {"bare_theta_max [rad]", "damper_x_max [m]", "damper_bumper_force_max [N]"} <= set(header)


def test_the_suite_keywords_make_the_command_lines_suite():
    from rocking.cli.study import _suite_from
    from rocking.study.suite import suite_of

    (commands,) = (a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    parse = commands.choices["fragility"].parse_args
    args = parse(["--stochastic", "3", "--seed", "4", "--d595", "5", "--duration", "30"])
    assert _suite_from(args) == suite_of(stochastic=3, seed=4, site={"d595": 5.0, "duration": 30.0})
    args = parse(["--pulses", "mp", "--periods", "0.5", "1", "--gamma-mp", "2", "--nu", "0.3", "--amplitude", "2"])
    assert _suite_from(args) == suite_of(pulses="mp", periods=[0.5, 1.0], gamma_mp=2.0, nu=0.3, amplitude=2.0)
    block = rocking.Block.reference()
    with pytest.raises(rocking.ParameterError, match=r"^periods: only with pulses FAMILY$"):
        rocking.fragility(block, stochastic=2, periods=[1.0], levels=[1.0], progress=False)
    with pytest.raises(rocking.ParameterError, match=r"^im must be one of pga, pgv, .*, amplitude \(got 'sa'\)$"):
        rocking.fragility(block, stochastic=2, im="sa", levels=[1.0], progress=False)
