"""A spec is data from a stranger: hostile specs are refused in one line, execute nothing and delete nothing.

Each payload of the corpus tries to create a sentinel file; each run of
``rocking.derive`` writes into a folder that holds a previous derivation's
manifest and files of the user's. A refused spec must leave both untouched.
The generated code is held to the same rule once written: the templates escape
free text, and a hand-edited generated file is refused when the model loads.
"""

from __future__ import annotations

import dataclasses
import json
import re
import shutil
import subprocess
import time
from pathlib import Path

import pytest
import sympy

from rocking.derive import names, watchdog
from rocking.derive import spec as spec_module
from rocking.derive.build import build, write
from rocking.derive.cli import main
from rocking.derive.cost import Cost, expression_cost, spec_entries
from rocking.derive.expressions import parse_expression
from rocking.derive.spec import SpecError, parse_spec, registered_variants, variant_spec
from rocking.model.loading import ModelError, load_model
from rocking.sim import cbuild
from rocking.sim.cbuild import CBuildError

SENTINEL = "SENTINEL"

#: A sound spec; each case of the corpus changes one entry of it.
BASE = {
    "name": '"probe"',
    "title": '"Probe"',
    "coordinates": '["x"]',
    "m_doc": '"mass"',
    "m_unit": '"kg"',
    "m_valid": '">= 0"',
    "k_name": "k",
    "body": '"mass"',
    "mass": '"m"',
    "position": '["x", "H"]',
    "stiffness": '"k"',
    "stretch": '"x"',
    "damping": '"k"',
    "rate_of": '"x"',
    "law": '"momentum"',
}
TEMPLATE = """\
name = {name}
title = {title}
coordinates = {coordinates}
[parameters.m]
doc = {m_doc}
unit = {m_unit}
valid = {m_valid}
[parameters.{k_name}]
[[bodies]]
name = {body}
mass = {mass}
position = {position}
[[springs]]
stiffness = {stiffness}
stretch = {stretch}
acts_on = {body}
[[dashpots]]
damping = {damping}
rate_of = {rate_of}
acts_on = {body}
[impact]
x = {law}
"""

_TOUCH = f"__import__('os').system('touch {SENTINEL}')"


def s(text: str) -> str:
    """``text`` (or a list of texts) as a TOML basic string (or array): JSON's escapes are TOML's."""
    return json.dumps(text, ensure_ascii=False)


#: (id, changes to BASE, a fragment of the expected message).
CORPUS = [
    # Expressions: the reproduced payload, then every way out of arithmetic.
    ("import-payload", {"mass": s(f"{_TOUCH} + m")}, "not allowed"),
    ("attribute", {"mass": s("m.__class__.__base__")}, "attribute access"),
    ("dunder-name", {"mass": s("__builtins__")}, "unknown symbol(s) __builtins__"),
    ("lambda", {"mass": s(f"(lambda: {_TOUCH})()")}, "not allowed"),
    ("string-literal", {"mass": s("'m'")}, "strings not allowed"),
    ("f-string", {"mass": s(f'f"{{{_TOUCH}}}"')}, "f-strings not allowed"),
    ("huge-exponent", {"mass": s("10**10**10")}, "exponent above 64"),
    ("huge-power-tower", {"mass": s("(((9**60)**60)**60)**60 * m")}, "too large"),
    ("deep-nesting", {"mass": s("(m*" * 30 + "m" + ")" * 30)}, "levels of nesting"),
    ("deep-calls", {"mass": s("sin(" * 40 + "m" + ")" * 40)}, "levels of nesting"),
    ("long-expression", {"mass": s("+".join(["m"] * 250))}, "characters, at most"),
    ("comparison", {"mass": s("m if m > 0 else 0")}, "not allowed"),
    ("subscript", {"mass": s("m[0]")}, "indexing not allowed"),
    ("keyword-argument", {"mass": s("sin(x=m)")}, "keyword or starred"),
    ("starred-argument", {"mass": s("atan2(*m)")}, "keyword or starred"),
    ("unknown-function", {"mass": s("system(x)")}, "a call of something other than"),
    ("eval-call", {"mass": s("eval('1') + m")}, "not allowed"),
    ("getattr-call", {"mass": s("getattr(m, 'x')")}, "not allowed"),
    ("walrus", {"mass": s("(y := m)")}, "not allowed"),
    ("comprehension", {"mass": s("[i for i in m]")}, "not allowed"),
    ("complex-literal", {"mass": s("1j*m")}, "complex constants"),
    ("infinite-literal", {"mass": s("1e999*m")}, "non-finite"),
    ("division-by-zero", {"mass": s("m/0")}, "not a finite real expression"),
    ("imaginary", {"mass": s("sqrt(-1)*m")}, "not a finite real expression"),
    ("xor-power", {"mass": s("m^2")}, "use ** for powers"),
    ("unicode-expression", {"mass": s("ｍ")}, "other than printable ASCII"),
    ("newline-in-expression", {"mass": s("m\n+ k")}, "other than printable ASCII"),
    ("boolean-mass", {"mass": "true"}, "expected an expression"),
    ("toml-nan-mass", {"mass": "nan"}, "not a finite number"),
    # Names that break the generated code or collide.
    ("param-p", {"k_name": "p"}, "'p' is reserved"),
    ("param-cst", {"k_name": "cst"}, "'cst' is reserved"),
    ("param-int", {"k_name": "int"}, "'int' is reserved"),
    ("param-float", {"k_name": "float"}, "'float' is reserved"),
    ("param-INFINITY", {"k_name": "INFINITY"}, "'INFINITY' is reserved"),
    ("param-numpy", {"k_name": "numpy"}, "'numpy' is reserved"),
    ("param-while", {"k_name": "while"}, "'while' is reserved"),
    ("param-lambda", {"k_name": "lambda"}, "'lambda' is reserved"),
    ("param-sin", {"k_name": "sin"}, "'sin' is reserved"),
    ("param-dunder", {"k_name": "__class__"}, "is not a valid symbol name"),
    ("param-nfkc-H", {"k_name": s("ℌ")}, "Python would read it as 'H'"),
    ("param-macro-prefix", {"k_name": "probe_NQ"}, "'probe_' are the model's C names"),
    ("param-velocity", {"k_name": "dx"}, "'dx' is the velocity of coordinate 'x'"),
    ("param-dtheta", {"k_name": "dtheta"}, "velocity of coordinate 'theta'"),
    ("coordinate-y", {"coordinates": '["x", "y"]'}, "'y' is reserved"),
    ("derived-c-keyword", {"coordinates": '["x", "ouble"]'}, "would be named 'double'"),
    ("model-math", {"name": s("math")}, "model name 'math' is reserved"),
    ("model-sim", {"name": s("sim")}, "model name 'sim' is reserved"),
    ("model-stdlib", {"name": s("stdlib")}, "model name 'stdlib' is reserved"),
    ("model-rocking", {"name": s("rocking")}, "model name 'rocking' is reserved"),
    ("model-long", {"name": s("a" * 300)}, "name must be an identifier"),
    ("model-dotdot", {"name": s("../evil")}, "name must be an identifier"),
    ("model-slash", {"name": s("a/b")}, "name must be an identifier"),
    ("model-nfkc", {"name": s("ｏｍｄ")}, "name must be an identifier"),
    # Free text that would close a docstring or a comment.
    ("title-docstring", {"title": s(f'"""; {_TOUCH}; """')}, "spec: title"),
    (
        "title-c-constructor",
        {"title": s(f'x */\n__attribute__((constructor)) static void f(void) {{ system("touch {SENTINEL}"); }}\n/*')},
        "spec: title",
    ),
    ("title-too-long", {"title": s("t" * 500)}, "at most 120 allowed"),
    ("title-number", {"title": "5"}, "title must be a string"),
    ("unit-newline", {"m_unit": s("kg\nimport os")}, "parameters.m unit"),
    ("doc-backslash", {"m_doc": s("mass \\N{BELL}")}, "parameters.m doc"),
    ("doc-c-comment", {"m_doc": s("mass */ int x; /*")}, "parameters.m doc"),
    ("doc-escape-sequence", {"m_doc": s("mass \x1b[2J")}, "parameters.m doc"),
    ("valid-quote", {"m_valid": s('>= 0"')}, "parameters.m valid"),
    ("body-name-newline", {"body": s("mass\nx")}, "bodies[0] name"),
    ("impact-law-newline", {"law": s("momentum\nx")}, "unknown law"),
    # Structure that is not what a spec holds.
    ("position-not-list", {"position": '"x"'}, "position must be a list"),
    ("coordinates-not-list", {"coordinates": '"x"'}, "coordinates must be a list"),
]

#: Short specs whose derivation would run for minutes or hours (issue 23), each refused at once by the
#: bounds on an expression's degree, expanded terms and nesting (rocking.derive.cost), or by the
#: grammar's bound on exponents: (id, changes to BASE, a fragment of the expected message).
_DEGREE = "its degree in the coordinates and their functions is"
_NESTING = "its nesting of functions of the coordinates is"
_TERMS = "its number of terms once expanded is"
_ARGUMENT = "its degree of what a function or a fractional power of the coordinates is taken of is"
EXPENSIVE = [
    (
        "issue-23",
        {"position": s(["sin(x)**40*cos(x)**40 + x", "H + k*cos(x)**30"])},
        f"position x: 'x + sin(x)**40*cos(x)**40' is too costly to derive: {_DEGREE} 80",
    ),
    (
        "cos-power-in-height",
        {"position": s(["x", "H + k*cos(x)**30"])},
        f"position y: 'H + k*cos(x)**30' is too costly to derive: {_DEGREE} 30",
    ),
    ("sin-power", {"position": s(["x + k*sin(x)**64", "H"])}, f"{_DEGREE} 64"),
    ("tan-power", {"position": s(["x + k*tan(x)**20", "H"])}, f"{_DEGREE} 20"),
    ("power-in-argument", {"position": s(["x + k*sin(x**40)", "H"])}, f"{_DEGREE} 40"),
    ("negative-power", {"position": s(["x + k/(1 + x**2)**30", "H"])}, f"{_DEGREE} 60"),
    (
        "product-of-sums",
        {"position": s(["x*(x + 1)*(x + 2)*(x + 3)*(x + 4)*(x + 5)*(x + 6)*(x + 7)", "H"])},
        f"{_DEGREE} 8",
    ),
    (
        "sqrt-of-long-sum",
        {"position": s(["x", "H + sqrt(1 + " + " + ".join(f"x**{i}" for i in range(1, 9)) + ")"])},
        f"{_DEGREE} 8",
    ),
    ("multinomial-position", {"position": s(["(x + k + m + H + B + M)**12", "H"])}, f"{_DEGREE} 12"),
    ("nested-trig", {"position": s(["x + k*sin(cos(sin(x)))", "H"])}, f"{_NESTING} 3"),
    ("exp-exp-exp", {"position": s(["x + k*exp(exp(exp(x)))", "H"])}, f"{_NESTING} 3"),
    ("nested-atan", {"position": s(["x + k*atan(atan(atan(atan(x))))", "H"])}, f"{_NESTING} 4"),
    ("huge-exponent-of-coordinate", {"position": s(["x**(10**6)", "H"])}, "an exponent above 64 in size not allowed"),
    # Issue 36: shapes within the bounds of issue 23 whose derivation ran past a minute (CPU time, the omd spec).
    (
        "sin-of-atan",
        {"position": s(["x + k*sin(atan(x))", "H"])},
        f"position x: 'k*x/sqrt(x**2 + 1) + x' is too costly to derive: {_ARGUMENT} 2",
    ),
    ("cos-of-atan", {"position": s(["x + k*cos(atan(x))", "H"])}, f"{_ARGUMENT} 2"),
    ("sqrt-of-square", {"position": s(["x", "H + k*sqrt(1 + x**2)"])}, f"{_ARGUMENT} 2"),
    ("trig-sum-degree-6", {"position": s(["x + k*(sin(x) + cos(x))**6", "H"])}, f"{_DEGREE} 6"),
    ("trig-product-degree-6", {"position": s(["x + k*sin(x)**3*cos(x)**3", "H"])}, f"{_DEGREE} 6"),
    ("trig-power-degree-6", {"position": s(["x + k*sin(x)**6", "H"])}, f"{_DEGREE} 6"),
    ("trig-of-trig", {"position": s(["x + k*sin(cos(x))", "H"])}, f"{_NESTING} 2"),
    ("exp-of-sin", {"position": s(["x", "H + k*exp(sin(x))"])}, f"{_NESTING} 2"),
    (
        "multinomial-mass",
        {"mass": s("(m + k + H + B + M + g)**16")},
        f"body 'mass' mass: '(B + H + M + g + k + m)**16' is too costly to derive: {_TERMS} 20349",
    ),
    (
        "power-in-potential",
        {"stretch": s("x**40")},
        f"spring 'springs0' stretch: 'x**40' is too costly to derive: {_DEGREE} 40",
    ),
    ("trig-power-in-potential", {"stretch": s("x + sin(x)**30")}, f"{_DEGREE} 30"),
    (
        "trig-power-in-damping",
        {"rate_of": s("x + sin(x)**30")},
        f"dashpot 'dashpots0' rate_of: 'x + sin(x)**30' is too costly to derive: {_DEGREE} 30",
    ),
    (
        "multinomial-damping",
        {"damping": s("(m + k + H + B + M + g)**16")},
        f"dashpot 'dashpots0' damping: '(B + H + M + g + k + m)**16' is too costly to derive: {_TERMS} 20349",
    ),
]
#: Seconds within which an expensive spec must be refused (the bounds answer in milliseconds).
REFUSED_WITHIN = 30.0


def _spec_text(changes: dict, sentinel: Path) -> str:
    return TEMPLATE.format(**{**BASE, **changes}).replace(SENTINEL, str(sentinel))


def _previous_derivation(out: Path) -> dict[str, bytes]:
    """A folder as an earlier derivation left it, plus files of the user's; its files and their bytes."""
    out.mkdir(parents=True)
    files = {
        "model.py": b"# an earlier model\n",
        "old.c": b"/* an earlier model */\n",
        "notes.txt": b"my notes\n",
        "analysis.py": b"print('my analysis')\n",
    }
    manifest = {"model": "old", "sha256": {"model.py": "0" * 64, "old.c": "0" * 64}, "files": {"numpy": "model.py"}}
    files["manifest.json"] = json.dumps(manifest).encode()
    for name, data in files.items():
        (out / name).write_bytes(data)
    return files


def _run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


#: A line of the derivation's progress: a stage that ended, or one still running (rocking.derive.watchdog).
PROGRESS = re.compile(r"derive \w+: [a-zA-Z ]+ \.\.\. (\d+\.\d s|still running after \d+ s.*)")


def _assert_refused(code: int, out: str, err: str, fragment: str) -> None:
    """Exit code 2 and one line of error, after nothing but lines of progress (a refusal after a derivation)."""
    assert code == 2, (code, out, err)
    *progress, error = err.splitlines()
    assert all(PROGRESS.fullmatch(line) for line in progress), err
    assert error.startswith("error: ") and err.endswith("\n"), err
    assert fragment in err, err
    assert "derived in" not in out and "Traceback" not in err


@pytest.mark.parametrize("changes, fragment", [c[1:] for c in CORPUS], ids=[c[0] for c in CORPUS])
def test_hostile_spec_is_refused_and_runs_nothing(tmp_path, monkeypatch, capsys, changes, fragment):
    monkeypatch.chdir(tmp_path)  # a relative payload path would land here
    sentinel = tmp_path / "pwned"
    spec = tmp_path / "spec.toml"
    spec.write_text(_spec_text(changes, sentinel), encoding="utf-8")
    out = tmp_path / "out"
    before = _previous_derivation(out)
    _assert_refused(*_run(capsys, "--spec", spec, "--out", out), fragment)
    assert not sentinel.exists() and not (tmp_path / SENTINEL).exists(), "a payload was executed"
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before, "a file was written or deleted"


def test_the_corpus_is_large_and_its_payloads_are_live(tmp_path, monkeypatch):
    """At least 30 hostile specs; the sound base derives; the payload would create the sentinel if evaluated."""
    assert len(CORPUS) >= 30 and len({c[0] for c in CORPUS}) == len(CORPUS)
    parse_spec_text = _spec_text({}, tmp_path / "pwned")
    import tomllib

    assert parse_spec(tomllib.loads(parse_spec_text)).name == "probe"
    monkeypatch.chdir(tmp_path)
    eval(_TOUCH.replace(SENTINEL, str(tmp_path / "live")))  # noqa: S307 - the control: this payload is real
    assert (tmp_path / "live").exists()


@pytest.mark.parametrize("changes, fragment", [c[1:] for c in EXPENSIVE], ids=[c[0] for c in EXPENSIVE])
def test_expensive_spec_is_refused_at_once_in_one_line(tmp_path, capsys, changes, fragment):
    """A short spec that would keep SymPy busy for hours is refused in one line, well within the time allowed."""
    spec = tmp_path / "spec.toml"
    spec.write_text(_spec_text(changes, tmp_path / "pwned"), encoding="utf-8")
    out = tmp_path / "out"
    before = _previous_derivation(out)
    start = time.perf_counter()
    refused = _run(capsys, "--spec", spec, "--out", out)
    assert time.perf_counter() - start < REFUSED_WITHIN
    _assert_refused(*refused, fragment)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before, "a file was written or deleted"


def test_the_expensive_corpus_is_large_and_the_bounds_measure_what_they_say():
    """At least 10 expensive specs, none already in the hostile corpus; the measures of a few expressions."""
    assert len(EXPENSIVE) >= 10 and len({c[0] for c in EXPENSIVE} | {c[0] for c in CORPUS}) == len(EXPENSIVE) + len(
        CORPUS
    )
    x, m = (sympy.Symbol(n, real=True) for n in ("x", "m"))
    varying = frozenset({x})
    for expr, expected in (
        (x + sympy.sin(x) ** 40 * sympy.cos(x) ** 40, Cost(80, 2, 1, 1)),
        ((x + m) ** 3, Cost(3, 4, 0, 0)),
        (m * sympy.exp(sympy.exp(x)), Cost(1, 1, 2, 1)),
        (sympy.sqrt(m**2 - x**2), Cost(2, 2, 1, 2)),
        ((m + 1) ** 5 * sympy.sin(m), Cost(0, 6, 0, 0)),
        (x + m * sympy.sin(sympy.atan(x)), Cost(3, 3, 1, 2)),  # SymPy's x/sqrt(x**2 + 1)
        (m * sympy.sin(x) ** 3 * sympy.cos(x) ** 3, Cost(6, 1, 1, 1)),
    ):
        assert expression_cost(expr, varying) == expected, expr
    for name in registered_variants():  # the shipped models are well within the bounds
        spec = variant_spec(name)
        varying = frozenset(sympy.Symbol(c, real=True) for c in spec.coordinates)
        for where, expr in spec_entries(spec):
            cost = expression_cost(expr, varying)
            assert cost.degree <= 2 and cost.terms <= 2 and cost.nesting <= 1 and cost.argument <= 1, (name, where)


def test_a_stage_past_its_time_limit_is_stopped_in_one_line(tmp_path, monkeypatch, capsys):
    """The backstop: with the static bounds lifted, issue 23's spec is stopped at the stage that runs past
    --stage-limit, in one line naming the stage and the spec's costliest expression, and nothing is written."""
    monkeypatch.setattr(spec_module, "check_spec_cost", lambda spec: None)
    spec = tmp_path / "spec.toml"
    spec.write_text(_spec_text(EXPENSIVE[0][1], tmp_path / "pwned"), encoding="utf-8")
    out = tmp_path / "out"
    start = time.perf_counter()
    refused = _run(capsys, "--spec", spec, "--out", out, "--stage-limit", "2")
    assert time.perf_counter() - start < REFUSED_WITHIN
    _assert_refused(
        *refused, "ran past its limit of 2 s of CPU time; its costliest expression is body 'mass' position x"
    )
    assert re.search(r"error: derive probe: stage '[a-z ]+' ran past", refused[2]), refused[2]
    assert "--stage-limit SECONDS" in refused[2] and not out.exists()


def _probe(tmp_path: Path):
    spec = tmp_path / "spec.toml"
    spec.write_text(_spec_text({}, tmp_path / "pwned"), encoding="utf-8")
    return spec_module.load_spec(spec)


def _stages(*work):
    """A stand-in for derive's build: each of ``work`` one stage, then no files."""

    def build(spec, options, stage):
        for i, step in enumerate(work):
            stage(f"stage {'abcdefgh'[i]}")
            step()
        return watchdog.Built(spec.name, {}, 0.0)

    return build


def _spin(seconds: float = 60.0) -> None:
    end = time.process_time() + seconds
    while time.process_time() < end:
        pass


@pytest.mark.skipif(not watchdog.cpu_limited(), reason="the limit is the clock's where there is no RLIMIT_CPU")
def test_a_stage_limit_is_cpu_time_not_the_clocks(tmp_path, monkeypatch):
    """Issue 36: a stage that waits (a loaded machine's clock runs on, the CPU time does not) is not stopped at
    its limit's seconds of the clock; one that computes is stopped once it has used its limit of CPU time, by
    the child itself, in one line naming the stage."""
    spec = _probe(tmp_path)
    monkeypatch.setattr(watchdog, "build", _stages(lambda: time.sleep(2.5), lambda: time.sleep(0.1)))
    assert watchdog.build_bounded(spec, None, limit=1.0).files == {}
    monkeypatch.setattr(watchdog, "build", _stages(lambda: time.sleep(0.1), _spin))
    start = time.perf_counter()
    with pytest.raises(watchdog.DerivationFailed, match=r"stage 'stage b' ran past its limit of 1 s of CPU time;"):
        watchdog.build_bounded(spec, None, limit=1.0)
    assert time.perf_counter() - start < REFUSED_WITHIN


def test_a_failed_write_leaves_the_previous_derivation_whole(tmp_path, monkeypatch):
    """Issue 36: the files are written into a temporary folder, then renamed into place: a disk that fills on
    the third file leaves the previous model's files as they were, and no temporary folder."""
    out = tmp_path / "out"
    before = _previous_derivation(out)
    built = dataclasses.replace(build(variant_spec("block")), name="old")
    written = []
    real = Path.write_text

    def fill(path, text, *args, **kwargs):
        written.append(path)
        if len(written) == 3:
            raise OSError(28, "No space left on device")
        return real(path, text, *args, **kwargs)

    monkeypatch.setattr(Path, "write_text", fill)
    with pytest.raises(SpecError, match=f"cannot write {out}: No space left on device"):
        write(built, out)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("__import__('os').system('true')", "attribute access"),
        ("__import__('os')", "a call of something other than"),
        ("().__class__.__bases__[0].__subclasses__()", "not allowed"),
        ("m if m else m", "conditional expressions"),
        ("-" * 100 + "m", "levels of nesting"),
        ("m**x**300", "exponent above"),
        ("2**(10**5)", "exponent above"),
        ("log(0)", "not a finite real"),
        ("sin(m, m)", "takes 1 argument"),
        ("m +", "cannot parse"),
        ("m\0", "printable ASCII"),
    ],
)
def test_expression_grammar_refuses_everything_but_arithmetic(text, fragment):
    import sympy

    known = {n: sympy.Symbol(n, real=True) for n in ("m", "x")}
    with pytest.raises(SpecError, match=re.escape(fragment)) as refused:
        parse_expression(text, "here", known)
    assert "\n" not in str(refused.value)


def test_expression_grammar_builds_what_sympy_built():
    """The grammar reads shipped expressions exactly as ``parse_expr`` did (so generated/ is unchanged)."""
    import sympy

    names_ = ("x", "m", "H", "h", "R_t", "l", "phi", "x_p", "y_p", "u", "incl", "g", "k")
    known = {n: sympy.Symbol(n, real=True) for n in names_}
    for text in (
        "H + h + x**2/(2*R_t)",
        "x_p + l*sin(phi)",
        "y_p - l*cos(phi)",
        "H/2 + u*sin(incl)",
        "u - m*g*sin(incl)/k",
        "0.5*m + 1.25e-3*x - 3",
        "-m**-2 + sqrt(abs(x)) + atan2(x, H) + exp(-h)*log(m) + pi",
        "1/3*m",
    ):
        expected = sympy.parse_expr(text, local_dict={"abs": sympy.Abs, **known})  # trusted text, the reference
        assert sympy.srepr(parse_expression(text, "t", known)) == sympy.srepr(expected), text


# --- --out: only a new or empty folder, or a previous derivation's ----------------------------------------


def _mine(tmp_path: Path) -> Path:
    spec = tmp_path / "mine.toml"
    spec.write_text('name = "mine"\ntitle = "my bare block"\n', encoding="utf-8")
    return spec


def test_out_refuses_a_folder_of_the_users(tmp_path, capsys):
    out = tmp_path / "work"
    out.mkdir()
    (out / "notes.txt").write_text("keep")
    (out / "analysis.py").write_text("keep")
    _assert_refused(*_run(capsys, "--spec", _mine(tmp_path), "--out", out), "holds no manifest.json")
    assert sorted(p.name for p in out.iterdir()) == ["analysis.py", "notes.txt"]
    (tmp_path / "file").write_text("keep")
    _assert_refused(*_run(capsys, "--spec", _mine(tmp_path), "--out", tmp_path / "file"), "is not a folder")
    assert (tmp_path / "file").read_text() == "keep"


def test_out_replaces_only_what_the_previous_manifest_lists(tmp_path, capsys):
    spec = _mine(tmp_path)
    out = tmp_path / "models" / "mine"
    code, stdout, err = _run(capsys, "--spec", spec, "--out", out)  # a new folder
    assert code == 0 and "mine: derived in" in stdout, err
    written = {p.name for p in out.iterdir()}
    assert written == {"manifest.json", "model.py", "mine.c", "mine.h", "EQUATIONS.md"}

    # Files of the user's next to it survive a new derivation; a file of the old one it no longer has goes.
    (out / "notes.txt").write_text("keep")
    victim = tmp_path / "victim.txt"
    victim.write_text("keep")
    manifest = json.loads((out / "manifest.json").read_text())
    manifest["sha256"].update({"stale.c": "0" * 64, "../victim.txt": "0" * 64})
    (out / "manifest.json").write_text(json.dumps(manifest))
    (out / "stale.c").write_text("old")
    outside = tmp_path / "outside.py"
    outside.write_text("keep")
    (out / "model.py").unlink()
    (out / "model.py").symlink_to(outside)  # replaced as a link, never written through
    assert _run(capsys, "--spec", spec, "--out", out)[0] == 0
    assert {p.name for p in out.iterdir()} == written | {"notes.txt"}
    assert (out / "notes.txt").read_text() == victim.read_text() == outside.read_text() == "keep"
    assert not (out / "model.py").is_symlink()

    # A file of the user's under the name of a generated file, not in the manifest: refused, untouched.
    other = tmp_path / "other"
    _previous_derivation(other)
    (other / "mine.c").write_text("my own C")
    _assert_refused(*_run(capsys, "--spec", spec, "--out", other), "mine.c is not listed in its manifest.json")
    assert (other / "mine.c").read_text() == "my own C"


# --- the generated code, once written ----------------------------------------------------------------------


def _strip_c_comments(text: str) -> str:
    return re.sub(r"/\*.*?\*/", "", text, flags=re.S)


def test_templates_escape_free_text_even_past_the_checks(tmp_path, monkeypatch):
    """Defence in depth: a title and a doc that got past the checks still cannot close a docstring or a comment."""
    monkeypatch.chdir(tmp_path)
    sentinel = tmp_path / "pwned"
    spec = variant_spec("omd")
    hostile_title = f'x """; {_TOUCH}; """ */\n__attribute__((constructor)) static void f(void) {{}}\n/* \\'
    hostile_title = hostile_title.replace(SENTINEL, str(sentinel))
    m = dataclasses.replace(spec.parameters[0], doc='"""\n' + _TOUCH.replace(SENTINEL, str(sentinel)), unit="*/ ??/")
    spec = dataclasses.replace(spec, name="esc", title=hostile_title, parameters=(m, *spec.parameters[1:]))
    files = build(spec).files
    namespace: dict = {}
    exec(compile(files["model.py"], "model.py", "exec"), namespace)  # noqa: S102 - the module must be inert
    assert not sentinel.exists()
    assert namespace["__doc__"].startswith('x """; __import__(')  # the text, shown and inert
    for name in ("esc.c", "esc.h"):
        code = _strip_c_comments(files[name])
        assert "__attribute__" not in code and "??/" not in files[name], name
    cc = cbuild.compiler()
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    run = subprocess.run(
        [*cc, "-std=c99", "-Wall", "-Werror", "-fsyntax-only", str(tmp_path / "esc.c")], capture_output=True, text=True
    )
    assert run.returncode == 0, run.stderr


@pytest.fixture
def omd_copy(tmp_path) -> Path:
    folder = tmp_path / "omd"
    shutil.copytree(load_model("omd").folder, folder, ignore=shutil.ignore_patterns("__pycache__"))
    return folder


@pytest.mark.parametrize("edited", ["omd.c", "omd.h", "model.py"])
def test_a_hand_edited_generated_file_is_refused_at_load(omd_copy, tmp_path, edited):
    assert load_model(omd_copy).coordinates == ("theta", "x")  # the copy as written loads
    sentinel = tmp_path / "pwned"
    path = omd_copy / edited
    payload = f"\nopen({str(sentinel)!r}, 'w')\n" if edited == "model.py" else "\n/* edited */\n"
    path.write_text(path.read_text() + payload)
    # Loaded once per process: the copy loaded above keeps the code checked then; a fresh load is refused.
    fresh = shutil.copytree(omd_copy, tmp_path / "fresh")
    with pytest.raises(
        ModelError, match=rf"{re.escape(edited)}: does not match the SHA-256.*re-derive it: rocking derive"
    ):
        load_model(fresh)
    assert not sentinel.exists()


def test_a_c_file_edited_after_its_model_was_loaded_is_not_compiled(omd_copy, tmp_path):
    model = load_model(omd_copy)
    (omd_copy / "omd.c").write_text((omd_copy / "omd.c").read_text() + "\n/* edited */\n")
    with pytest.raises(CBuildError, match=r"omd.c: does not match the SHA-256"):
        cbuild.build(model, cache=tmp_path / "cache")


def test_a_manifest_cannot_point_outside_its_folder(omd_copy, tmp_path):
    manifest = json.loads((omd_copy / "manifest.json").read_text())
    manifest["files"]["numpy"] = "../evil.py"
    (omd_copy / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(ModelError, match="files.numpy is not a file name"):
        load_model(omd_copy)
    (omd_copy / "manifest.json").write_text("{not json")
    with pytest.raises(ModelError, match="not a readable manifest"):
        load_model(omd_copy)


def test_a_shipped_model_names_the_make_target_to_rederive(tmp_path, monkeypatch):
    from rocking.model import loading

    folder = tmp_path / "omd"
    shutil.copytree(load_model("omd").folder, folder, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(loading, "GENERATED", tmp_path)
    (folder / "omd.c").write_text("int x;\n")
    with pytest.raises(ModelError, match="omd.c: .*make derive"):
        load_model(folder)


# --- the declared reserved names -----------------------------------------------------------------------------


def test_reserved_names_cover_the_generated_code_and_the_simulator():
    """The C arguments of the templates and every identifier prefix of the simulator's C sources are reserved."""
    templates = Path(names.__file__).parent / "templates"
    c_template = (templates / "model.c.j2").read_text()
    arguments = set(re.findall(r"(?:double|double \*|const double \*)\s*(\w+)[,)]", c_template))
    assert {"s", "y", "ag", "p", "cst", "out"} <= arguments <= names.GENERATED_NAMES
    identifiers = set()
    for path in cbuild.CSRC.iterdir():
        text = re.sub(r"//[^\n]*", "", _strip_c_comments(path.read_text()))
        identifiers |= set(re.findall(r"\b[A-Za-z_]\w*\b", re.sub(r'"[^"\n]*"', "", text)))
    # A leading underscore is C's own (_POSIX_C_SOURCE): a spec name cannot start with one.
    prefixes = {i.split("_")[0].lower() for i in identifiers if "_" in i.strip("_") and not i.startswith("_")}
    assert prefixes <= names.RUNTIME_C_PREFIXES, sorted(prefixes - names.RUNTIME_C_PREFIXES)
    for shipped in ("block", "omd", "omd2", "pendulum"):
        assert names.check_model_name(shipped) == shipped


def test_write_refuses_a_folder_of_the_users_from_python_too(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "analysis.py").write_text("keep")
    with pytest.raises(SpecError, match="holds no manifest.json"):
        write(build(variant_spec("block")), out)
    assert [p.name for p in out.iterdir()] == ["analysis.py"]
