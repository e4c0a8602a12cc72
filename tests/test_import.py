"""``import rocking`` is quick: the heavy libraries load when a function needs them, not at import."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import time
from importlib import metadata
from pathlib import Path

import pytest

import rocking
from rocking.cli import BLAS_THREADS
from rocking.study.config import RECORDED_PACKAGES, installed_version

#: Libraries ``import rocking`` must not load: each costs from a tenth of a second to a second (tqdm 15 ms, with the
#: asyncio its notebook support imports: a study imports it only for a progress bar shown).
HEAVY = ("scipy", "pandas", "xarray", "matplotlib", "dask", "netCDF4", "sympy", "jinja2", "tqdm")

#: ``import rocking`` against ``import numpy``, which it needs anyway (best of several runs each): 2.6 measured
#: on the 2-core development machine while it ran other work (4.8 s in all before the lazy imports of SciPy).
RATIO = 4.0


def _best(code: str, runs: int = 3) -> float:
    best = float("inf")
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True)
        best = min(best, time.perf_counter() - start)
    return best


def test_import_loads_no_heavy_library():
    code = "import sys, rocking; print(' '.join(sorted({m.split('.')[0] for m in sys.modules})))"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = set(run.stdout.split())
    assert not loaded & set(HEAVY), sorted(loaded & set(HEAVY))


def test_import_costs_little_more_than_numpy():
    assert _best("import rocking") < RATIO * _best("import numpy")


ROCKING = Path(rocking.__file__).resolve().parent

#: The subpackages of rocking/, each a parameter of the test of circles.
SUBPACKAGES = tuple(sorted(p.parent.name for p in ROCKING.glob("*/__init__.py")))

#: Subpackages whose circle another branch removes: the test fails there until it lands (strict: then it must pass).
PENDING: dict[str, str] = {}


def _module_name(path: Path, base: Path) -> str:
    parts = path.relative_to(base).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imported(node: ast.AST, package: str, modules: set[str]) -> set[str]:
    """The modules of ``modules`` that an import statement ``node`` of a module in ``package`` loads."""
    if isinstance(node, ast.Import):
        return {alias.name for alias in node.names} & modules
    if not isinstance(node, ast.ImportFrom):
        return set()
    if node.level:
        base = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
        base = f"{base}.{node.module}" if node.module else base
    else:
        base = node.module or ""
    # ``from package import name``: the submodule when ``name`` is one, else the package itself.
    found = {f"{base}.{alias.name}" for alias in node.names} & modules
    return found if len(found) == len(node.names) else found | ({base} & modules)


def import_graph(root: Path = ROCKING, scripts: bool = False) -> dict[str, set[str]]:
    """Module -> the modules of ``root`` it imports, at any depth of its code (function-level imports too).

    ``root`` is a package, or with ``scripts`` a folder of scripts that import each other by their bare
    names (bench/ puts itself on ``sys.path``).
    """
    base = root if scripts else root.parent
    files = {_module_name(path, base): path for path in sorted(root.rglob("*.py"))}
    modules = set(files)
    graph = {}
    for name, path in files.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        graph[name] = set().union(*(_imported(node, package, modules) for node in ast.walk(tree))) - {name}
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (each a circle of imports), sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def test_circles_finds_a_planted_circle(tmp_path):
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "sub" / "__init__.py").write_text("")
    (package / "a.py").write_text("def f():\n    from .sub import b\n")
    (package / "sub" / "b.py").write_text("from pkg import c\n")
    (package / "c.py").write_text("import pkg.a\nfrom .sub import b as _\n")
    (package / "d.py").write_text("from . import a\n")
    graph = import_graph(package)
    assert graph["pkg.a"] == {"pkg.sub.b"} and graph["pkg.d"] == {"pkg.a"}
    assert circles(graph) == [["pkg.a", "pkg.c", "pkg.sub.b"]]


@pytest.mark.parametrize(
    "subpackage",
    [
        pytest.param(name, marks=pytest.mark.xfail(strict=True, reason=PENDING[name])) if name in PENDING else name
        for name in SUBPACKAGES
    ],
)
def test_no_import_circle(subpackage):
    graph = import_graph()
    prefix = f"rocking.{subpackage}."
    inside = [c for c in circles(graph) if any(m.startswith(prefix) or m == prefix[:-1] for m in c)]
    assert not inside, _described(inside, graph)


def test_no_import_circle_in_bench():
    graph = import_graph(ROCKING.parent / "bench", scripts=True)
    found = circles(graph)
    assert not found, _described(found, graph)


def _described(found: list[list[str]], graph: dict[str, set[str]]) -> str:
    """Each circle's modules, and what each imports inside it."""
    return "\n".join(
        "circle of " + ", ".join(c) + ": " + "; ".join(f"{m} imports {sorted(graph[m] & set(c))}" for m in c)
        for c in found
    )


# --- a command's start (issue 40: its fixed cost) -------------------------------------------------


def _heavy_after(code: str) -> list[str]:
    """The libraries of :data:`HEAVY` that ``code`` imports in a new interpreter (a module set to None, which
    cannot be imported, is not imported)."""
    probe = f"{code}\nimport sys\nprint('imported:', *(m for m in {HEAVY!r} if sys.modules.get(m) is not None))"
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    last = run.stdout.splitlines()[-1].split()
    assert last[0] == "imported:", run.stdout
    return last[1:]


def test_the_command_line_and_its_help_import_no_heavy_library():
    assert _heavy_after("from rocking.cli.main import build_parser\nbuild_parser().format_help()") == []


def test_simulate_without_a_figure_imports_no_heavy_library():
    code = "from rocking.cli.main import main\nassert main(['simulate', '--beta', '3', '--Omega', '4']) == 0"
    assert _heavy_after(code) == []


def test_a_map_command_hides_dask_from_xarray_and_writes_its_figure_as_png_only(tmp_path):
    """In the command's own process (main() reads sys.argv) an adaptive map imports what it writes with (xarray
    and NetCDF, matplotlib for its figure) and no more: no SciPy, and xarray builds its Datasets without Dask;
    the figure is a PNG, a PDF only on request (--pdf, --formats)."""
    argv = ["rocking", "map", "--Omega", "1", "10", "2", "--beta", "1", "10", "2", "--workers", "1"]
    argv += ["--no-progress", "--out", str(tmp_path)]
    code = f"import sys\nsys.argv = {argv!r}\nfrom rocking.cli.main import main\nassert main() == 0"
    assert sorted(_heavy_after(code)) == ["matplotlib", "netCDF4", "pandas", "xarray"]
    assert sorted(p.name for p in tmp_path.glob("map.*")) == ["map.csv", "map.json", "map.nc", "map.png"]


def test_dask_stays_importable_when_a_dask_scheduler_is_asked_for():
    code = (
        "import argparse, sys\nfrom rocking.cli.main import hide_dask\n"
        "hide_dask(argparse.Namespace(scheduler=None, dask_workers=2))\nimport dask\n"
        "hide_dask(argparse.Namespace(command='simulate'))\nassert sys.modules['dask'] is dask"
    )
    assert "dask" in _heavy_after(code)


def test_without_a_dask_scheduler_the_command_hides_dask():
    code = (
        "import argparse\nfrom rocking.cli.main import hide_dask\n"
        "hide_dask(argparse.Namespace(scheduler=None, dask_workers=None))\n"
        "try:\n    import dask\nexcept ModuleNotFoundError:\n    pass\nelse:\n    raise AssertionError('dask imported')"
    )
    assert _heavy_after(code) == []


def test_import_rocking_loads_no_numpy_and_its_names_load_at_first_use():
    code = "import sys, rocking; print('numpy' in sys.modules, rocking.Block.__module__, 'numpy' in sys.modules)"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.split() == ["False", "rocking.model.params", "True"]


def test_public_names_for_type_checkers_are_those_imported_at_first_use():
    """rocking/__init__.py's imports for type checkers name each name of PUBLIC from its module, and no other."""
    tree = ast.parse(Path(rocking.__file__).read_text(encoding="utf-8"))
    (block,) = [n for n in tree.body if isinstance(n, ast.If) and ast.unparse(n.test) == "TYPE_CHECKING"]
    imported = {alias.name: "." + node.module for node in block.body for alias in node.names}
    assert imported == rocking.PUBLIC
    assert sorted(dir(rocking)) == sorted(set(dir(rocking)) | set(rocking.__all__))
    with pytest.raises(AttributeError, match="no attribute 'simulated'"):
        rocking.simulated  # noqa: B018


def _blas_threads(code: str, environ: dict | None = None) -> list[str]:
    """OPENBLAS_NUM_THREADS and OMP_NUM_THREADS after ``code`` in a new interpreter without them (but ``environ``)."""
    env = {k: v for k, v in os.environ.items() if k not in BLAS_THREADS} | (environ or {})
    probe = f"{code}\nimport os\nprint(*(os.environ.get(name, '-') for name in {BLAS_THREADS!r}))"
    return subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, check=True, env=env
    ).stdout.split()


def test_the_command_starts_one_blas_thread_unless_told_otherwise():
    """The command's process (rocking.cli imported before NumPy) sets one BLAS thread before NumPy loads; a variable
    given is kept, and a process that loaded NumPy first is left alone."""
    assert _blas_threads("import rocking.cli.main") == ["1", "1"]
    assert _blas_threads("import rocking.cli.main", {"OMP_NUM_THREADS": "3"}) == ["1", "3"]
    assert _blas_threads("import numpy, rocking.cli.main") == ["-", "-"]


def test_preload_in_a_callers_process_neither_imports_nor_freezes():
    code = (
        "import gc, sys\nfrom rocking.cli import preload\npreload('xarray')\n"
        "print('xarray' in sys.modules, gc.get_freeze_count(), gc.isenabled())"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.split() == ["False", "0", "True"]


def test_a_map_command_loads_its_libraries_frozen_and_collects_the_rest(tmp_path):
    """In the command's own process the study's libraries load with the collector paused and are frozen; the
    collector runs again afterwards (for what the study and its figure make), and the files are written."""
    argv = ["rocking", "map", "--Omega", "1", "10", "2", "--beta", "1", "10", "2", "--workers", "1"]
    argv += ["--no-progress", "--out", str(tmp_path)]
    code = (
        f"import gc, sys\nsys.argv = {argv!r}\nfrom rocking.cli.main import main\nassert main() == 0\n"
        "import weakref\nclass Cycle: pass\nc = Cycle(); c.me = c; dead = weakref.ref(c); del c\ngc.collect()\n"
        "print(gc.isenabled(), gc.get_freeze_count() > 100_000, dead() is None)"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.split()[-3:] == ["True", "True", "True"]
    assert sorted(p.name for p in tmp_path.glob("map.*")) == ["map.csv", "map.json", "map.nc", "map.png"]


def test_a_command_that_loads_no_library_freezes_what_it_loaded():
    code = (
        "import gc, sys\nsys.argv = ['rocking', 'simulate', '--beta', '3', '--Omega', '4']\n"
        "from rocking.cli.main import main\nassert main() == 0\nprint(gc.isenabled(), gc.get_freeze_count() > 10_000)"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.split()[-2:] == ["True", "True"]


@pytest.mark.parametrize("package", [*RECORDED_PACKAGES, "xarray", "rocking", "no-such-package"])
def test_a_version_read_from_the_metadata_header_is_importlib_metadatas(package):
    try:
        expected = metadata.version(package)
    except metadata.PackageNotFoundError:
        expected = None
    assert installed_version(package) == expected
