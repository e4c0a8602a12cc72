"""The build and cache of the C back end (rocking.sim.cbuild): keys, integrity, cache errors, broken compilers.

A library is built once per module (``warm``) and copied for each test that damages
it, so that only tests about compiling compile. Loading a damaged library may kill
the process (SIGBUS), so the test that loads one runs it in a subprocess.
"""

from __future__ import annotations

import ctypes
import json
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import textwrap
import threading
import warnings
from pathlib import Path

import pytest

import rocking
from rocking import BackendWarning, Block, OneSinePulse, load_model
from rocking.sim import c_backend, cbuild
from rocking.sim.cbuild import CBuildError

ROOT = Path(__file__).resolve().parent.parent
MODEL = "block"  # the smallest model: the fastest to compile
BLOCK = Block.reference()
PULSE = OneSinePulse.from_nondim(BLOCK, beta=3.0, Omega=4.0)


@pytest.fixture(scope="module")
def warm(tmp_path_factory) -> Path:
    """A cache holding the library of MODEL, built once; copy it (``cache``) before changing it."""
    folder = tmp_path_factory.mktemp("warm")
    cbuild.build(load_model(MODEL), cache=folder)
    return folder


@pytest.fixture
def cache(warm, tmp_path) -> Path:
    """This test's copy of the warm cache."""
    return Path(shutil.copytree(warm, tmp_path / "cache"))


@pytest.fixture
def compiles(monkeypatch) -> list:
    """The compiler commands cbuild runs during the test (they still run)."""
    calls = []
    compile_ = cbuild._compile

    def counted(cmd):
        calls.append(cmd)
        compile_(cmd)

    monkeypatch.setattr(cbuild, "_compile", counted)
    return calls


@pytest.fixture
def unloaded(monkeypatch):
    """No C library loaded yet in this process, so that c_backend builds (and finds) it again."""
    monkeypatch.setattr(c_backend, "_LIBRARIES", {})


def library_of(folder: Path) -> Path:
    (library,) = folder.glob("*.so")
    return library


def sidecar(library: Path) -> dict:
    return json.loads(library.with_name(library.name + ".json").read_text())


def sha256(path: Path) -> str:
    return cbuild._file_digest(path)[0]


def leftovers(folder: Path) -> list[Path]:
    return list(folder.glob("*.tmp"))


def no_compiler_runs(monkeypatch):
    def refuse(cmd):
        raise AssertionError(f"the compiler was run: {shlex.join(cmd)}")

    monkeypatch.setattr(cbuild, "_run", refuse)


def response_fields(r) -> tuple:
    return r.overturned, r.theta_max, r.impacts, r.status, r.t_end


# --------------------------------------------------------------------------- #
# Keys and the cache                                                           #
# --------------------------------------------------------------------------- #


def test_a_cached_library_is_used_without_running_the_compiler(warm, monkeypatch):
    model = load_model(MODEL)
    library = library_of(warm)
    assert library.name == f"{MODEL}-{cbuild.build_key(model)}.so"
    record = sidecar(library)
    assert record["sha256"] == sha256(library) and record["size"] == library.stat().st_size
    assert record["compiler"] == shlex.join(cbuild.compiler()) and record["compiler_version"]
    no_compiler_runs(monkeypatch)
    assert cbuild.build(model, cache=warm) == library
    monkeypatch.setenv("ROCKING_CACHE_DIR", str(warm))
    assert cbuild.cache_dir() == warm and cbuild.build(model) == library
    assert not leftovers(warm)


def test_the_key_follows_the_sources_flags_and_compiler(tmp_path, monkeypatch):
    model = load_model(MODEL)
    key = cbuild.build_key(model)
    source, tool = key.split("-")
    # Not where the sources are: a copy gives the same key.
    csrc = Path(shutil.copytree(cbuild.CSRC, tmp_path / "csrc"))
    assert cbuild.build_key(model, csrc=csrc) == key
    for name in ("sim.c", "sim.h", "boundary.h", "phases.h"):
        original = (csrc / name).read_text()
        (csrc / name).write_text(original + "\n/* changed */\n")
        assert cbuild.build_key(model, csrc=csrc).split("-")[0] != source, name
        (csrc / name).write_text(original)
    assert cbuild.build_key(load_model("omd")).split("-")[0] != source
    # Arguments of $CC are flags: part of the source key.
    cc = cbuild.compiler()
    assert cbuild.build_key(model, cc=[*cc, "-DROCKING_NO_SHORTCUTS"]).split("-")[0] != source
    # Another compiler program, or the same one changed (its size or time stands in for its version).
    wrapper = tmp_path / "wrapped-cc"
    wrapper.write_text(f'#!/bin/sh\nexec {shlex.join(cc)} "$@"\n')
    wrapper.chmod(0o755)
    other = cbuild.build_key(model, cc=[str(wrapper)])
    assert other.split("-")[0] == source and other.split("-")[1] != tool
    os.utime(wrapper, ns=(0, 0))
    assert cbuild.build_key(model, cc=[str(wrapper)]) != other


def test_another_compiler_builds_its_own_library(cache, tmp_path, monkeypatch, compiles):
    model = load_model(MODEL)
    first = library_of(cache)
    wrapper = tmp_path / "wrapped-cc"
    wrapper.write_text(f'#!/bin/sh\nexec {shlex.join(cbuild.compiler())} "$@"\n')
    wrapper.chmod(0o755)
    monkeypatch.setenv("CC", str(wrapper))
    second = cbuild.build(model, cache=cache)
    assert second != first and len(compiles) == 1 and compiles[0][0] == str(wrapper)
    assert sidecar(second)["compiler"] == str(wrapper) and cbuild._valid(first, sidecar(first)["source_key"])


def test_cache_dir_without_a_home_is_a_cbuilderror(monkeypatch):
    monkeypatch.delenv("ROCKING_CACHE_DIR", raising=False)

    def no_home():
        raise RuntimeError("Could not determine home directory.")

    monkeypatch.setattr(Path, "home", staticmethod(no_home))
    with pytest.raises(CBuildError, match="ROCKING_CACHE_DIR"):
        cbuild.cache_dir()


# --------------------------------------------------------------------------- #
# Integrity: a damaged library is built again, never loaded                    #
# --------------------------------------------------------------------------- #


def truncate(library: Path) -> None:
    os.truncate(library, library.stat().st_size // 2)


def flip_a_byte(library: Path) -> None:
    data = bytearray(library.read_bytes())
    data[len(data) // 2] ^= 0xFF
    library.write_bytes(data)


def remove_the_sidecar(library: Path) -> None:
    library.with_name(library.name + ".json").unlink()


def garble_the_sidecar(library: Path) -> None:
    library.with_name(library.name + ".json").write_text('{"sha256": ')


DAMAGES = {
    "truncated": truncate,
    "flipped byte": flip_a_byte,
    "no sidecar": remove_the_sidecar,
    "garbled sidecar": garble_the_sidecar,
}


@pytest.mark.parametrize("damage", list(DAMAGES), ids=list(DAMAGES))
def test_a_damaged_library_is_built_again(cache, compiles, damage):
    library = library_of(cache)
    good = sidecar(library)
    DAMAGES[damage](library)
    assert cbuild.build(load_model(MODEL), cache=cache) == library
    assert len(compiles) == 1
    record = sidecar(library)
    assert record["sha256"] == sha256(library) and record["size"] == good["size"]
    assert not leftovers(cache)


RUN = textwrap.dedent(
    """
    import rocking
    from rocking.sim import c_backend
    block = rocking.Block.reference()
    for beta, Omega in ((1.0, 2.0), (3.0, 4.0), (6.0, 8.0)):
        r = rocking.simulate(block, None, rocking.OneSinePulse.from_nondim(block, beta=beta, Omega=Omega), backend="c")
        print(r.overturned, repr(r.theta_max), r.impacts, r.status, repr(r.t_end))
    print(c_backend.library("block").path)
    """
)


def run_in_a_subprocess(code: str, *args: str, **env) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code, *args],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONPATH": str(ROOT), **env},
        check=False,
    )


def test_a_truncated_library_is_rebuilt_not_loaded(cache):
    """Loading the truncated library would kill the process with SIGBUS: it is built again, with the same results."""
    library = library_of(cache)
    before = run_in_a_subprocess(RUN, ROCKING_CACHE_DIR=str(cache))
    assert before.returncode == 0, before.stderr
    assert before.stdout.splitlines()[-1] == str(library)
    truncate(library)
    after = run_in_a_subprocess(RUN, ROCKING_CACHE_DIR=str(cache))
    assert after.returncode == 0, f"exit {after.returncode}: {after.stderr}"
    assert after.stdout == before.stdout
    assert sidecar(library)["sha256"] == sha256(library)


# --------------------------------------------------------------------------- #
# Concurrent builders                                                          #
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize("start", ["empty", "truncated"])
def test_concurrent_threads_compile_once(cache, compiles, start):
    if start == "empty":
        for path in cache.iterdir():
            path.unlink()
    else:
        truncate(library_of(cache))
    model = load_model(MODEL)
    barrier = threading.Barrier(4)
    found, errors = [], []

    def build():
        try:
            barrier.wait()
            found.append(cbuild.build(model, cache=cache))
        except Exception as exc:  # reported below, not lost in the thread
            errors.append(exc)

    threads = [threading.Thread(target=build) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors and len(set(found)) == 1 and len(compiles) == 1
    assert sidecar(found[0])["sha256"] == sha256(found[0]) and not leftovers(cache)


BUILD_AND_LOAD = textwrap.dedent(
    """
    import ctypes, sys
    from rocking import load_model
    from rocking.sim import cbuild
    compiled = []
    compile_ = cbuild._compile
    cbuild._compile = lambda cmd: (compiled.append(cmd), compile_(cmd))
    model = load_model("block")
    lib = cbuild.build(model, cache=sys.argv[1])
    assert ctypes.CDLL(str(lib)).rocking_model_ny() == len(model.state)
    print(lib, len(compiled))
    """
)


@pytest.mark.parametrize("start", ["empty", "truncated"])
def test_concurrent_processes_compile_once(cache, start):
    """Several processes build at once: one compiles, none loads a damaged or half-written library."""
    if start == "empty":
        for path in cache.iterdir():
            path.unlink()
    else:
        truncate(library_of(cache))
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", BUILD_AND_LOAD, str(cache)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
        )
        for _ in range(4)
    ]
    outputs = [p.communicate(timeout=120) for p in procs]
    assert all(p.returncode == 0 for p in procs), [(p.returncode, err) for p, (_, err) in zip(procs, outputs)]
    paths, counts = zip(*(out.split() for out, _ in outputs))
    assert len(set(paths)) == 1 and sum(map(int, counts)) == 1
    assert len(list(cache.glob("*.so"))) == 1 and not leftovers(cache)


# --------------------------------------------------------------------------- #
# A cache that cannot be written                                               #
# --------------------------------------------------------------------------- #


def unwritable(tmp_path: Path, how: str) -> Path:
    """A cache folder that cannot be created or written, even by root: a file, or a path under one."""
    file = tmp_path / "a-file"
    file.write_text("not a folder\n")
    return file / "cache" if how == "under a file" else file


def permissions_ignored() -> bool:
    """Whether this process writes into a read-only folder anyway (root, or CAP_DAC_OVERRIDE).

    Tried rather than read from os.geteuid(): root without the capability respects permissions.
    """
    folder = Path(tempfile.mkdtemp(prefix="rocking-permissions-"))
    try:
        folder.chmod(0o555)
        try:
            (folder / "probe").touch()
        except PermissionError:
            return False
        return True
    finally:
        folder.chmod(0o755)
        shutil.rmtree(folder)


#: Capabilities that let root write into a read-only folder.
_OVERRIDES = "-dac_override,-dac_read_search"


def respecting_permissions(code: str, env: dict | None = None) -> subprocess.CompletedProcess:
    """Run ``code`` in a Python child that respects file permissions, and return it.

    For root (``permissions_ignored()``) the child runs without the capabilities that
    override them (util-linux ``setpriv``), so that a read-only folder is read-only to
    it as it is to any user.
    """
    prefix = []
    if permissions_ignored():
        setpriv = shutil.which("setpriv")
        assert setpriv, "root ignores permissions here, and util-linux setpriv is missing to drop that"
        prefix = [setpriv, "--bounding-set", _OVERRIDES, "--inh-caps", _OVERRIDES]
    child = textwrap.dedent(code)
    run_env = {**os.environ, **(env or {})}
    return subprocess.run([*prefix, sys.executable, "-c", child], capture_output=True, text=True, env=run_env)


def read_only(tmp_path: Path) -> Path:
    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o555)
    return folder


UNWRITABLE = ["under a file", "a file"]


@pytest.mark.parametrize("how", UNWRITABLE)
def test_an_unwritable_cache_is_a_one_line_cbuilderror(tmp_path, how):
    folder = unwritable(tmp_path, how)
    with pytest.raises(CBuildError) as info:
        cbuild.build(load_model(MODEL), cache=folder)
    message = str(info.value)
    assert "\n" not in message and str(folder) in message and "set ROCKING_CACHE_DIR" in message, message
    assert not list(tmp_path.rglob("*.tmp"))


def test_a_read_only_cache_is_a_one_line_cbuilderror(tmp_path):
    folder = read_only(tmp_path)
    child = respecting_permissions(
        f"""
        from rocking import load_model
        from rocking.sim import cbuild
        try:
            cbuild.build(load_model({MODEL!r}), cache={str(folder)!r})
        except cbuild.CBuildError as exc:
            print(exc)
        """
    )
    message = child.stdout
    assert child.returncode == 0 and message.count("\n") == 1, (child.stdout, child.stderr)
    assert str(folder) in message and "set ROCKING_CACHE_DIR" in message, message
    assert not list(folder.iterdir())


@pytest.mark.parametrize("how", UNWRITABLE)
def test_auto_falls_back_to_numpy_when_the_cache_is_unwritable(tmp_path, monkeypatch, unloaded, how):
    monkeypatch.setenv("ROCKING_CACHE_DIR", str(unwritable(tmp_path, how)))
    with pytest.warns(BackendWarning, match="ROCKING_CACHE_DIR"):
        r = rocking.simulate(BLOCK, None, PULSE, backend="auto")
    assert response_fields(r) == response_fields(rocking.simulate(BLOCK, None, PULSE, backend="numpy"))
    with pytest.raises(CBuildError, match="ROCKING_CACHE_DIR"):
        rocking.simulate(BLOCK, None, PULSE, backend="c")


def test_auto_falls_back_to_numpy_when_the_cache_is_read_only(tmp_path):
    child = respecting_permissions(
        """
        import warnings
        import rocking
        from rocking import BackendWarning, Block, OneSinePulse
        from rocking.sim.cbuild import CBuildError
        block = Block.reference()
        pulse = OneSinePulse.from_nondim(block, beta=3.0, Omega=4.0)
        fields = lambda r: (r.overturned, r.theta_max, r.impacts, r.status, r.t_end)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            auto = rocking.simulate(block, None, pulse, backend="auto")
        assert [w.category for w in caught] == [BackendWarning], caught
        assert "ROCKING_CACHE_DIR" in str(caught[0].message)
        assert fields(auto) == fields(rocking.simulate(block, None, pulse, backend="numpy"))
        try:
            rocking.simulate(block, None, pulse, backend="c")
        except CBuildError as exc:
            assert "ROCKING_CACHE_DIR" in str(exc)
        else:
            raise AssertionError("backend='c' ran without a writable cache")
        print("ok")
        """,
        env={"ROCKING_CACHE_DIR": str(read_only(tmp_path))},
    )
    assert child.returncode == 0 and child.stdout == "ok\n", child.stderr


def test_a_read_only_warm_cache_is_used(cache):
    library = library_of(cache)
    cache.chmod(0o555)
    try:
        child = respecting_permissions(
            f"""
            from rocking import load_model
            from rocking.sim import cbuild
            def refuse(cmd):
                raise AssertionError("the compiler was run")
            cbuild._run = refuse
            print(cbuild.build(load_model({MODEL!r}), cache={str(cache)!r}))
            """
        )
    finally:
        cache.chmod(0o755)
    assert child.returncode == 0 and child.stdout == f"{library}\n", child.stderr


# --------------------------------------------------------------------------- #
# A broken compiler                                                            #
# --------------------------------------------------------------------------- #


def break_the_compiler(monkeypatch, tmp_path: Path, how: str) -> None:
    if how == "no compiler on PATH":
        monkeypatch.delenv("CC", raising=False)
        empty = tmp_path / "empty-bin"
        empty.mkdir(exist_ok=True)
        monkeypatch.setenv("PATH", str(empty))
    else:
        monkeypatch.setenv("CC", how)


BROKEN = ["/nonexistent/cc", "false", "no compiler on PATH"]


@pytest.mark.parametrize("how", BROKEN)
def test_a_broken_compiler_uses_the_cached_library(cache, tmp_path, monkeypatch, unloaded, how):
    library = library_of(cache)
    monkeypatch.setenv("ROCKING_CACHE_DIR", str(cache))
    reference = rocking.simulate(BLOCK, None, PULSE, backend="c")
    monkeypatch.setattr(c_backend, "_LIBRARIES", {})
    break_the_compiler(monkeypatch, tmp_path, how)
    assert cbuild.build(load_model(MODEL)) == library
    with warnings.catch_warnings():
        warnings.simplefilter("error", BackendWarning)
        r = rocking.simulate(BLOCK, None, PULSE, backend="auto")
    assert response_fields(r) == response_fields(reference)
    assert c_backend.library(MODEL).path == library


COLD = {
    "/nonexistent/cc": r"C compiler '/nonexistent/cc' not found",
    "false": r"C compiler 'false' does not run \(`--version` exit 1",
    "no compiler on PATH": r"no C compiler found: set \$CC",
    # Its flags differ from the warm library's: that one cannot stand in.
    "/nonexistent/cc -DROCKING_NO_SHORTCUTS": r"C compiler '/nonexistent/cc' not found",
}


@pytest.mark.parametrize("how", list(COLD))
def test_a_broken_compiler_without_a_cached_library_is_a_one_line_cbuilderror(
    cache, tmp_path, monkeypatch, unloaded, how
):
    if "-D" not in how:
        for path in cache.iterdir():
            path.unlink()
    break_the_compiler(monkeypatch, tmp_path, how)
    with pytest.raises(CBuildError, match=COLD[how]) as info:
        cbuild.build(load_model(MODEL), cache=cache)
    assert "\n" not in str(info.value)
    monkeypatch.setenv("ROCKING_CACHE_DIR", str(cache))
    with pytest.warns(BackendWarning, match=COLD[how]):
        rocking.simulate(BLOCK, None, PULSE, backend="auto")


def test_compiler_failure_carries_its_message(tmp_path):
    csrc = Path(shutil.copytree(cbuild.CSRC, tmp_path / "csrc"))
    source = (csrc / "sim.c").read_text()
    (csrc / "sim.c").write_text(source.replace("static double ode_ag(", "static double ode_ag(int broken,", 1))
    with pytest.raises(CBuildError) as info:
        cbuild.build(load_model(MODEL), cache=tmp_path / "cache", csrc=csrc)
    message = str(info.value)
    assert "C compiler failed" in message and "sim.c" in message and "error" in message
    left = [path.name for path in (tmp_path / "cache").iterdir() if not path.name.endswith(".lock")]
    assert not left, left


# --------------------------------------------------------------------------- #
# The wheel's prebuilt libraries (issue 36, item 4)                            #
# --------------------------------------------------------------------------- #

from tests.planted import plant_library  # noqa: E402


@pytest.fixture
def package(warm, tmp_path, monkeypatch) -> Path:
    """A package's code (``sim/``, 0755, its ``cbuild.py`` 0644) with a ``prebuilt`` folder beside it holding a
    genuine library of MODEL, as a wheel installs it; cbuild looks there. Returns the prebuilt folder."""
    code = tmp_path / "site" / "rocking" / "sim"
    code.mkdir(parents=True)
    (code / "cbuild.py").write_text("# the package's code\n")
    (code / "cbuild.py").chmod(0o644)
    code.chmod(0o755)
    prebuilt = code / "prebuilt"
    prebuilt.mkdir(mode=0o755)
    library = library_of(warm)
    for path in (library, library.with_name(library.name + ".json")):
        shutil.copy(path, prebuilt / path.name)
        (prebuilt / path.name).chmod(0o644)
    monkeypatch.setattr(cbuild, "CODE", (code, code / "cbuild.py"))
    monkeypatch.setattr(cbuild, "PREBUILT", prebuilt)
    return prebuilt


def _planted(folder: Path, sentinel: Path) -> Path:
    """The prebuilt library of MODEL in ``folder`` replaced by one whose constructor creates ``sentinel``, its
    sidecar updated to match (hash, size, the source key it is looked up by)."""
    library = library_of(folder)
    plant_library(library, sentinel, sidecar(library)["source_key"])
    return library


def test_a_genuine_prebuilt_library_is_used_without_the_cache(package, tmp_path, monkeypatch):
    no_compiler_runs(monkeypatch)
    assert cbuild.prebuilt_refusal(package) is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no PrebuiltWarning
        assert cbuild.build(load_model(MODEL), cache=tmp_path / "cache") == library_of(package)
    assert not (tmp_path / "cache").exists()


def test_the_control_a_planted_library_in_a_trusted_folder_would_run(package, tmp_path):
    """The attack is live: a planted library with a matching sidecar, in a folder as trusted as the code, is
    returned, and loading it runs its constructor. What refuses it below is its folder alone."""
    planted = _planted(package, tmp_path / "PWNED")
    assert cbuild.build(load_model(MODEL), cache=tmp_path / "cache") == planted
    ctypes.CDLL(str(planted))
    assert (tmp_path / "PWNED").exists()


PREBUILT_ATTACKS = ["world-writable", "group-writable", "foreign owner", "symlink to a world-writable /tmp folder",
                    "writable library"]  # fmt: skip


@pytest.mark.parametrize("attack", PREBUILT_ATTACKS)
def test_a_planted_prebuilt_library_is_refused_before_it_is_loaded(
    package, warm, tmp_path, monkeypatch, unloaded, attack
):
    """Issue 36: the wheel's folder held to the trust of the package's code; a planted library there with a
    matching sidecar is never loaded (its constructor never runs): one warning line, and the cache's library runs.
    """
    sentinel = tmp_path / "PWNED"
    folder = package
    if attack == "symlink to a world-writable /tmp folder":
        folder = Path(tempfile.mkdtemp(prefix="prebuilt-", dir="/tmp"))
        shutil.copytree(package, folder, dirs_exist_ok=True)
        folder.chmod(0o777)
        shutil.rmtree(package)
        package.symlink_to(folder)
        monkeypatch.setattr(cbuild, "PREBUILT", package)
    planted = _planted(folder, sentinel)
    if attack == "world-writable":
        folder.chmod(0o777)
    elif attack == "group-writable":
        folder.chmod(0o775)
    elif attack == "foreign owner":
        if os.geteuid() != 0:
            pytest.skip("changing a folder's owner needs root")
        os.chown(folder, 65534, 65534)
    elif attack == "writable library":
        planted.chmod(0o666)
    why = {
        "world-writable": r"is writable by others \(mode 0777\)",
        "group-writable": r"is writable by group \d+ \(mode 0775\), which cannot write the package's code",
        "foreign owner": r"belongs to uid 65534, not to the owner of the package's code",
        "symlink to a world-writable /tmp folder": r"is a symbolic link to /tmp/prebuilt-\w+, out of the package",
        "writable library": r"\.so is writable by others \(mode 0666\)",
    }[attack]
    cache = Path(shutil.copytree(warm, tmp_path / "cache"))
    monkeypatch.setenv("ROCKING_CACHE_DIR", str(cache))
    with pytest.warns(cbuild.PrebuiltWarning, match=f"^the C libraries shipped in .* are not used: .*{why}") as record:
        response = rocking.simulate(BLOCK, None, PULSE, backend="c")
    assert len(record) == 1 and "\n" not in str(record[0].message)
    assert response.status and not sentinel.exists(), "the planted library's constructor ran"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cbuild.PrebuiltWarning)
        assert cbuild.build(load_model(MODEL)) == library_of(cache)
    if attack == "symlink to a world-writable /tmp folder":
        shutil.rmtree(folder)
