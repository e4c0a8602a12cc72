"""The derivation: spec checks, options, reproducibility and freshness of generated/."""

from __future__ import annotations

import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy

import rocking.generated
from rocking.derive.build import GENERATED
from rocking.derive.cli import main
from rocking.derive.codegen import MANIFEST_FORMAT, NumpyGenerator, hoist_constants, model_context
from rocking.derive.equations import derive
from rocking.derive.spec import (
    BLOCK_PARAMETERS,
    VARIANTS_DIR,
    SpecError,
    parse_spec,
    registered_variants,
    variant_spec,
)
from rocking.reference import paper

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = GENERATED.parent


def test_generated_folder_is_fresh_and_derived_byte_for_byte_in_a_new_process():
    """generated/ equals a fresh derivation of every registered variant (CI fails when stale), derived in a new
    process with another hash seed: one derivation of every variant checks both."""
    for name in registered_variants():
        manifest = json.loads((GENERATED / name / "manifest.json").read_text())
        assert manifest["sympy"] == sympy.__version__, (
            f"generated/{name} was written with SymPy {manifest['sympy']}, this is {sympy.__version__}: "
            "install constraints.txt"
        )
    env = dict(os.environ, PYTHONHASHSEED="12345")
    run = subprocess.run(
        [sys.executable, "-m", "rocking.derive", "--check"], cwd=ROOT, env=env, capture_output=True, text=True
    )
    assert run.returncode == 0, f"generated/ is stale: run `make derive`\n{run.stdout}{run.stderr}"
    assert run.stdout.count("up to date") == len(registered_variants())


def test_generated_package_declares_the_manifest_format_and_the_block_parameters():
    """The runtime reads the format and the block's parameters from generated/, not from derive."""
    assert rocking.generated.MANIFEST_FORMAT == MANIFEST_FORMAT
    block = [p[0] for p in BLOCK_PARAMETERS]
    for name in registered_variants():
        manifest = json.loads((GENERATED / name / "manifest.json").read_text())
        assert manifest["format"] == MANIFEST_FORMAT
        assert manifest["block_parameters"] == block == [p["name"] for p in manifest["parameters"]][:6]
    spec = variant_spec("omd")
    homogeneous = model_context(derive(spec, {"inertia": "homogeneous"}), spec)
    assert homogeneous.block_parameters == ("M", "B", "H", "e", "g")


@pytest.mark.parametrize("name", ["block", "omd", "pendulum", "omd2"])
def test_every_file_follows_the_one_table_of_functions(name):
    """model.py, the C header and source, EQUATIONS.md and manifest.json hold the same functions,
    in the same order (the manifest's keys are sorted)."""
    folder = GENERATED / name
    manifest = json.loads((folder / "manifest.json").read_text())
    python = re.findall(r"^def ([a-z]\w*)\(", (folder / "model.py").read_text(), re.M)
    header = re.findall(rf"^\w+ {name}_(\w+)\(double s, const double \*y,", (folder / f"{name}.h").read_text(), re.M)
    source = re.findall(rf"^\w+ {name}_(\w+)\(double s, const double \*y,", (folder / f"{name}.c").read_text(), re.M)
    latex = re.findall(r"^## `(\w+)`$", (folder / "EQUATIONS.md").read_text(), re.M)
    friction = 8 if manifest["friction"] else 0  # the functions of a floor with friction come after the others
    flight = 8 if manifest["flight"] else 0  # those of flight and landing last
    assert python == header == source == latex and len(python) == 20 + friction + flight
    assert sorted(python) == sorted(manifest["functions"]) == list(manifest["functions"])


def _numpy_module(spec, options):
    """Derive ``spec`` with ``options`` in memory and import its NumPy module."""
    eq = derive(spec, options)
    text = NumpyGenerator(model_context(eq, spec)).files()["model.py"]
    module_spec = importlib.util.spec_from_loader("alt_model", loader=None)
    module = importlib.util.module_from_spec(module_spec)
    exec(compile(text, "alt_model", "exec"), module.__dict__)
    return eq, module


def test_impact_option_velocity_matches_hand_derivation():
    """impact=velocity keeps dx and conserves only the angular momentum about the new pivot."""
    eq, mod = _numpy_module(variant_spec("omd"), {"impact": "velocity"})
    assert eq.options["impact_laws"] == {"x": "velocity"}
    rng = np.random.default_rng(3)
    from rocking.reference.verify import random_cases, rel_error

    for s in (1, -1):
        v = random_cases(rng, 500, s)
        args = [v[k] for k in ("M", "I_G", "B", "H", "e", "g", "m", "h", "k_m", "c")]
        got = mod.impact(v["s"], 0 * v["x"], v["x"], v["dtheta"], v["dx"], v["ag"], v["agy"], *args)
        ref = paper.impact(
            s, v["x"], v["dtheta"], v["dx"], v["M"], v["I_G"], v["B"], v["H"], v["e"], v["m"], v["h"], law="velocity"
        )
        assert rel_error(got[0], ref[0]) < 1e-12
        assert np.array_equal(got[1], v["dx"])


def test_homogeneous_inertia_option_drops_I_G():
    eq, mod = _numpy_module(variant_spec("omd"), {"inertia": "homogeneous"})
    assert "I_G" not in mod.PARAMETERS
    eq_free, free = _numpy_module(variant_spec("omd"), None)
    M, B, H, e, g, m, h, k, c = 800.0, 0.5, 2.0, 0.02, 9.81, 40.0, 0.05, 500.0, 10.0
    I_G = M * (B**2 + H**2) / 12
    state = (0.1, 0.02, -0.3, 0.4)
    a = mod.rocking_accel(1.0, *state, 3.0, 0.0, M, B, H, e, g, m, h, k, c)
    b = free.rocking_accel(1.0, *state, 3.0, 0.0, M, I_G, B, H, e, g, m, h, k, c)
    np.testing.assert_allclose(a, b, rtol=1e-14)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"impact": "bounce"}, "option impact: unknown value 'bounce'"),
        ({"inertia": "solid"}, "option inertia: unknown value 'solid'"),
        ({"friction": "on"}, "unknown option 'friction'"),
    ],
)
def test_unknown_option_is_rejected(options, message):
    with pytest.raises(SpecError, match=message):
        derive(variant_spec("omd"), options)


BASE = {
    "name": "probe",
    "coordinates": ["x"],
    "parameters": {"m": {}, "k": {}},
    "bodies": [{"name": "mass", "mass": "m", "position": ["x", "H"]}],
    "springs": [{"name": "spring", "stiffness": "k", "stretch": "x", "acts_on": "mass"}],
}


#: A stop on the probe's travel, each test changes one entry.
STOP = {"travel": "x", "gap": "k", "stiffness": "k", "damping": "m", "acts_on": "mass"}


def _with(**changes):
    data = json.loads(json.dumps(BASE))
    data.update(changes)
    return data


@pytest.mark.parametrize(
    "data, message",
    [
        (_with(coordinates=["x", "z"]), "coordinate\\(s\\) z appear in no energy"),
        (_with(bodies=[{"name": "mass", "mass": -2, "position": ["x", "H"]}]), "mass must be >= 0"),
        (
            _with(springs=[{"name": "spring", "stiffness": "k", "stretch": "x", "acts_on": "bob"}]),
            "acts on unknown body 'bob'",
        ),
        (_with(bodies=[{"name": "mass", "mass": "m", "position": ["x + z", "H"]}]), "unknown symbol\\(s\\) z"),
        (_with(bodies=[{"name": "mass", "mass": "m", "position": ["x"]}]), "position must be a list of two"),
        (_with(impact={"x": "stick"}), "unknown law 'stick'"),
        (_with(parameters={"m": {}, "k": {}, "B": {}}), "'B' is reserved"),
        (_with(parameters={"m": {}, "k": {}, "cst0": {}}), "'cst0' is reserved \\(names cse<digits> and cst<digits>"),
        (_with(colour="red"), "unknown key\\(s\\) colour"),
        (_with(name="2probe"), "name must be an identifier, got '2probe'"),
        ({k: v for k, v in BASE.items() if k != "name"}, "spec: missing required key 'name'"),
        (_with(coordinates=["x", "m"]), "a name is declared twice"),
        (_with(parameters={"m": {}, "k": {}, "bad name": {}}), "'bad name' is not a valid symbol name"),
        (_with(parameters={"m": {"colour": "red"}, "k": {}}), "parameters.m: unknown key\\(s\\) colour"),
        (_with(bodies=[{"name": "mass", "mass": "m"}]), "body 'mass': missing required key 'position'"),
        (_with(bodies=[{"name": "mass", "mass": "m", "position": ["x", "H"], "inertia": -1}]), "inertia must be >= 0"),
        (_with(bodies=[BASE["bodies"][0], BASE["bodies"][0]]), "two bodies have the same name"),
        (_with(bodies=[{"name": "mass", "mass": "m + (", "position": ["x", "H"]}]), "body 'mass' mass: cannot parse"),
        (_with(springs=[{"stiffness": "k", "stretch": "x"}]), "spring 'springs0': missing required key 'acts_on'"),
        (_with(dashpots=[{"damping": "k", "rate_of": "x", "acts_on": "bob"}]), "dashpot 'dashpots0': acts on unknown"),
        (
            _with(dashpots=[{"damping": "k", "rate": "x", "acts_on": "mass"}]),
            "dashpots\\[0\\]: unknown key\\(s\\) rate",
        ),
        (_with(impact={"y": "momentum"}), "impact: 'y' is not a coordinate"),
        (_with(stops=[dict(STOP, sides="left")]), "stop 'stops0': unknown sides 'left'; choose one of both"),
        (_with(stops=[dict(STOP, travel="H")]), "travel 'H' moves with no coordinate of x"),
        (_with(stops=[dict(STOP, acts_on="bob")]), "stop 'stops0': acts on unknown body 'bob'"),
        (_with(stops=[dict(STOP, gap="__import__('os')")]), "stop 'stops0' gap: a call of something other than"),
        (_with(stops=[dict(STOP, depth="1")]), "stops\\[0\\]: unknown key\\(s\\) depth"),
        (_with(stops=[{k: v for k, v in STOP.items() if k != "stiffness"}]), "missing required key 'stiffness'"),
        (_with(stops="x"), "spec: stops must be a list"),
        # A bumper inside the free travel, or one that releases energy (issue 23): refused, with the ranges read.
        (_with(stops=[dict(STOP, gap="-k")]), "stop 'stops0' gap: '-k' is not shown >= 0 .* \\(k >= 0\\)"),
        (_with(stops=[dict(STOP, stiffness="k - m")]), "stop 'stops0' stiffness: 'k - m' is not shown >= 0"),
        (_with(stops=[dict(STOP, damping="-m")]), "stop 'stops0' damping: '-m' is not shown >= 0"),
        (
            _with(parameters={"m": {}, "k": {"valid": "any"}}, stops=[dict(STOP, gap="k")]),
            "stop 'stops0' gap: 'k' is not shown >= 0 .* \\(k: any\\)",
        ),
        (_with(stops=[dict(STOP, gap="x")]), "stop 'stops0' gap: 'x' is not shown >= 0 .* \\(x: a coordinate\\)"),
    ],
)
def test_inconsistent_spec_is_rejected_before_derivation(data, message):
    with pytest.raises(SpecError, match=message):
        parse_spec(data)


def test_parsed_spec_keeps_every_entry():
    data = _with(
        title="Probe",
        dashpots=[{"name": "damper", "damping": "k/10", "rate_of": "x", "acts_on": "mass"}],
        impact={"x": "velocity"},
    )
    spec = parse_spec(data, source="text")
    x, m, k, H = (sympy.Symbol(n, real=True) for n in ("x", "m", "k", "H"))
    assert (spec.name, spec.title, spec.coordinates, spec.source) == ("probe", "Probe", ("x",), "text")
    assert [(p.name, p.unit, p.valid) for p in spec.parameters] == [("m", "", ">= 0"), ("k", "", ">= 0")]
    assert [(b.name, b.mass, b.position) for b in spec.bodies] == [("mass", m, (x, H))]
    assert [(e.name, e.coefficient, e.measure, e.acts_on) for e in spec.springs] == [("spring", k, x, "mass")]
    assert [(e.name, e.coefficient, e.measure) for e in spec.dashpots] == [("damper", k / 10, x)]
    assert spec.impact == {"x": "velocity"}
    assert parse_spec(BASE).impact == {"x": "momentum"}


def test_hoisting_gathers_the_constants_of_a_sum_and_keeps_the_value():
    x, dx, a, b, c, s = sympy.symbols("x dx a b c s", real=True)
    exprs = [a * x + b * x + c * sympy.sin(x) * s, (a + b) / (c + a * x**2) + a * x * dx]
    constants, hoisted = hoist_constants(exprs, [x, dx])
    assert [e for _, e in constants] == [a + b, c * s, c, a]
    k = {sym: e for sym, e in constants}
    assert hoisted[0] == sympy.Symbol("cst0", real=True) * x + sympy.Symbol("cst1", real=True) * sympy.sin(x)
    for original, split in zip(exprs, hoisted):
        assert sympy.simplify(split.subs(k) - original) == 0
    assert all(not (e.free_symbols & {x, dx}) for e in k.values())


def test_hoisting_goes_into_the_branches_and_conditions_of_a_piecewise():
    x, a, b = sympy.symbols("x a b", real=True)
    expr = sympy.Piecewise(((a + b) * x, a * b > 0), (sympy.nan, True))
    constants, (hoisted,) = hoist_constants([expr], [x])
    k = dict(constants)
    assert hoisted.free_symbols == {x} | set(k)  # neither a nor b is left to a prepared function
    for values, value in (({a: 1.0, b: 2.0, x: 3.0}, "9.00000000000000"), ({a: -1.0, b: 2.0, x: 3.0}, "nan")):
        assert str(hoisted.subs(k).subs(values)) == str(expr.subs(values)) == value


def test_registered_variants_include_the_paper_model_and_the_bare_block():
    assert {"omd", "block"} <= set(registered_variants())
    with pytest.raises(SpecError, match="unknown variant 'nope'"):
        variant_spec("nope")


def test_command_line_builds_a_user_spec_into_a_folder(tmp_path):
    spec = tmp_path / "probe.toml"
    spec.write_text(
        'name = "probe"\ncoordinates = ["x"]\n[parameters.m]\n[parameters.k]\n'
        '[[bodies]]\nname = "mass"\nmass = "m"\nposition = ["x", "H"]\n'
        '[[springs]]\nstiffness = "k"\nstretch = "x"\nacts_on = "mass"\n'
    )
    out = tmp_path / "model"
    run = subprocess.run(
        [sys.executable, "-m", "rocking.derive", "--spec", str(spec), "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    assert {"manifest.json", "model.py", "probe.c", "probe.h", "EQUATIONS.md"} <= {p.name for p in out.iterdir()}
    bad = subprocess.run(
        [sys.executable, "-m", "rocking.derive", "--variant", "omd", "--option", "impact=bounce"],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert bad.returncode == 2 and "option impact: unknown value 'bounce'" in bad.stderr


def test_main_takes_the_program_name_of_the_command_that_delegates_to_it(capsys):
    assert main(["--variant", "nope"], prog="rocking derive") == 2
    assert "unknown variant 'nope'" in capsys.readouterr().err
    with pytest.raises(SystemExit) as stop:
        main(["--spec", "my.toml"], prog="rocking derive")
    assert stop.value.code == 2
    assert capsys.readouterr().err.startswith("usage: rocking derive")


def _installed_layout(tmp_path: Path) -> Path:
    """The files a wheel of the project installs, laid out by setuptools (build_py) from a copy of the sources.

    The copy keeps the checkout clean (setuptools writes build metadata next to
    the sources); which folders to copy is read from pyproject.toml.
    """
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", pyproject["project"]["readme"]):
        shutil.copy2(ROOT / name, src / name)
    ignore = shutil.ignore_patterns("__pycache__", "*.so", "*.egg-info")
    for folder in sorted({p.split("/")[0] for p in pyproject["tool"]["setuptools"]["package-dir"].values()}):
        shutil.copytree(ROOT / folder, src / folder, ignore=ignore)
    site = tmp_path / "site"
    setup = [sys.executable, "-c", "from setuptools import setup; setup()", "-q", "build_py", "--build-lib", str(site)]
    run = subprocess.run(setup, cwd=src, capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    return site


def test_installed_package_derives_a_spec_from_any_folder(tmp_path):
    """Installed (no checkout, no editable install on the path), ``python -m rocking.derive --spec --out``
    works from an unrelated folder, writes what the checkout writes, and finds its own generated models."""
    site = _installed_layout(tmp_path)
    spec = tmp_path / "spec" / "mine.toml"
    spec.parent.mkdir()
    shutil.copy2(VARIANTS_DIR / "block.toml", spec)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = dict(os.environ, PYTHONPATH=str(site))

    def python(*args):
        return subprocess.run([sys.executable, *args], cwd=elsewhere, env=env, capture_output=True, text=True)

    where = python("-c", "import rocking.derive.build as b; print(b.__file__); print(b.GENERATED)")
    assert where.returncode == 0, where.stderr
    assert where.stdout.split() == [str(site / "rocking" / "derive" / "build.py"), str(site / "rocking" / "generated")]
    out = tmp_path / "out"
    run = python("-m", "rocking.derive", "--spec", str(spec), "--out", str(out))
    assert run.returncode == 0, run.stdout + run.stderr
    assert "block: derived in" in run.stdout
    assert json.loads((out / "manifest.json").read_text())["model"] == "block"
    for path in (GENERATED / "block").iterdir():
        if path.is_file():  # not the bytecode cache `make setup` compiles
            assert (out / path.name).read_text() == path.read_text(), path.name
    check = python("-m", "rocking.derive", "--check", "--variant", "block")
    assert check.returncode == 0 and "up to date" in check.stdout, check.stdout + check.stderr


def test_a_negative_gap_is_refused_in_one_line_naming_the_stop_the_field_and_the_expression(tmp_path, capsys):
    """``gap = "-L"`` used to derive and simulate a bumper inside the free travel (issue 23); sound stops parse."""
    text = (VARIANTS_DIR / "omd_stops.toml").read_text()
    assert parse_spec(tomllib.loads(text)).stops[0].gap == sympy.Symbol("L", real=True)
    spec = tmp_path / "bad.toml"
    spec.write_text(text.replace('gap = "L"', 'gap = "-L"'))
    out = tmp_path / "out"
    assert main(["--spec", str(spec), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: stop 'bumpers' gap: '-L' is not shown >= 0") and err.count("\n") == 1, err
    assert "(L > 0)" in err and not out.exists()


def test_progress_goes_to_stderr_stage_by_stage_and_leaves_the_files_as_derived_in_process(tmp_path, capsys):
    """--verbose prints one line per stage; the files written by the child process are generated/'s, byte for byte."""
    out = tmp_path / "block"
    assert main(["--variant", "block", "--out", str(out), "--verbose"]) == 0
    captured = capsys.readouterr()
    stages = re.findall(r"^derive block: ([a-zA-Z ]+) \.\.\. \d+\.\d s$", captured.err, re.M)
    assert len(stages) == captured.err.count("\n"), captured.err
    assert stages[1:4] == ["energies", "equations of motion", "rocking accelerations"] and stages[-1] == "LaTeX"
    assert "block: derived in" in captured.out and captured.out.count("\n") == 1
    assert {p.name: p.read_bytes() for p in out.iterdir()} == {
        p.name: p.read_bytes() for p in (GENERATED / "block").iterdir() if p.is_file()
    }
    for bad in ("-1", "nan", "soon"):
        with pytest.raises(SystemExit):
            main(["--variant", "block", "--stage-limit", bad])
        assert "--stage-limit: must be a number of seconds >= 0" in capsys.readouterr().err


def test_one_sided_stops_derive_only_their_side():
    """A stop with sides = "upper" has one penetration, x - L; its bumper's energy, force and dissipation
    follow docs/model.md section 11 on that side only."""
    data = _with(
        parameters={"m": {}, "k": {}, "L": {}, "k_b": {}, "c_b": {}},
        stops=[{"travel": "x", "gap": "L", "stiffness": "k_b", "damping": "c_b", "sides": "upper", "acts_on": "mass"}],
    )
    eq = derive(parse_spec(data))
    x, dx, L, k_b, c_b, k = sympy.symbols("x dx L k_b c_b k", real=True)
    assert eq.stop_gaps == [x - L]
    # The energy takes the regime of the stops as an input; here that of each state.
    regime = {on: indicator for (on, *_), indicator in zip(eq.system.stops, eq.stop_regime)}
    for value, inside in ((0.9, True), (1.2, False), (-5.0, True)):
        at = {x: value, dx: 0.3, L: 1.0, k_b: 50.0, c_b: 2.0, k: 3.0}
        force = float(eq.stop_forces[0].subs(at))
        assert force == (0.0 if inside else pytest.approx(50.0 * (value - 1.0) + 2.0 * 0.3))
        bumper = 0.0 if inside else 50.0 * (value - 1.0) ** 2 / 2
        stored = float((eq.energy - eq.energy.subs(k_b, 0)).xreplace(regime).subs(at))
        assert stored == pytest.approx(bumper, abs=1e-12)


def test_vertical_ground_acceleration_enters_as_gravity_and_not_the_impact():
    """docs/model.md section 14: Lagrange's equations on the absolute positions hold ``ddy_g`` beside ``g`` alone
    (the equivalence of a vertical ground acceleration and gravity), the impact map not at all (finite ground
    accelerations give no impulse), and every built-in variant takes vertical motion."""
    from rocking.derive.equations import lagrange, still, vertical_as_gravity
    from rocking.derive.mechanics import ag, agy, build_system

    sysm = build_system(variant_spec("omd"))
    residuals = lagrange(sysm)
    assert all(r.has(agy) for r in residuals) and vertical_as_gravity(residuals, sysm)
    g = sysm.params[[p.name for p in sysm.params].index("g")]
    assert all(sympy.expand(r - w.xreplace({g: g + agy})) == 0 for r, w in zip(residuals, still(residuals)))
    eq = derive(variant_spec("omd"))
    assert not any(v.has(agy) or v.has(ag) for v in eq.impact)
    assert eq.power.has(agy) and not eq.energy.has(agy)
    for name in registered_variants():
        assert json.loads((GENERATED / name / "manifest.json").read_text())["vertical"], name
