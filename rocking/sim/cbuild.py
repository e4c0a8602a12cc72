"""Build the C back end: ``rocking/sim/csrc/sim.c`` with one generated model, as a cached shared library.

The library is compiled at first use into a cache directory (``~/.cache/rocking``,
or ``$ROCKING_CACHE_DIR``) and found there afterwards without running the compiler.

Names and keys
--------------
A library is ``<prefix>-<source key>-<compiler key>.so``:

- the *source key* is the SHA-256 of what decides the library's behaviour: the C
  sources and headers, :data:`CFLAGS`, the arguments of ``$CC`` after the program
  (``CC="cc -DX"`` builds another library than ``CC=cc``) and the platform;
- the *compiler key* is the SHA-256 of the compiler program's resolved path, size
  and modification time, read with :func:`os.stat`.

Trade-off: the compiler's ``--version`` is not part of the key, because reading it
means running the compiler, and a cached library must stay usable when the
compiler is broken or gone (``CC=/nonexistent``, ``CC=false``, a machine that shares
the cache but has no compiler). The program's size and modification time stand in
for its version: an upgrade in place changes them, hence the key; a compiler whose
driver stays the same while its back end changes (a ``ccache`` wrapper, an
upgraded ``cc1`` behind an unchanged ``gcc``) is not noticed: clear the cache then.
The version is recorded in the sidecar (below), for the record only. When the
compiler cannot be found or does not run (not when it runs and rejects the code),
any valid library of the same source key is used, whichever compiler built it:
the same sources and flags, possibly not bit for bit what the requested compiler
would have produced.

Trust
-----
Loading a library runs its code, so the cache follows the rule of ssh's keys and
Python's bytecode cache: whoever can write it can already run code as you. The
cache folder must belong to the user (or to root, who can run anything anyway)
and not be writable by group or others (:func:`check_private`; it is created
``0700``): otherwise the C back end is refused in one line, naming the folder and
the fix, before any library in it is read. A library or sidecar that is a
symbolic link, belongs to someone else or is writable by group or others is
built again, never loaded. The sidecar, in the same protected folder, is the
index that says which sources, flags and compiler a library was built from: a
library whose sidecar does not carry the key it is looked up by is built again,
never loaded.

Integrity
---------
Each library has a sidecar, ``<library>.json``, written after a successful compile:
the library's SHA-256 and size, its source key, the compiler's command and version.
A library is used only if it matches its sidecar; otherwise (a truncated file,
which would kill the process with SIGBUS when loaded, a flipped byte, a missing or
unreadable sidecar) it is built again. Hashing a library of some 100 kB costs
well under a millisecond.

Concurrency
-----------
Several threads and processes may build the same library at once (a parallel test
run, the workers of a study). Checking a library needs no lock. Building it is done
under a lock held across threads (a :class:`threading.Lock` per library) and
processes (:func:`fcntl.flock` on ``.<library>.lock`` where :mod:`fcntl` exists), and
the library is checked again once the lock is held, so it is compiled once. The
compiler writes into a temporary file of the cache directory, the sidecar too, and
both are renamed into place with :func:`os.replace`, which is atomic: a reader never
sees half a file, and a process that has loaded the old file keeps it (a rename
does not change the file it mapped). The library is renamed first: in between, a
reader finds it does not match the old sidecar and waits for the lock.

Any failure to create or write the cache is a :class:`CBuildError` naming the
folder, so that ``backend="auto"`` falls back to NumPy.

No ``-march=native``: the cache may be shared between machines.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import json
import os
import shlex
import shutil
import stat
import subprocess
import sys
import tempfile
import threading
import warnings
from pathlib import Path
from types import SimpleNamespace

try:  # POSIX only; without it concurrent processes are still safe, only duplicated.
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]  # typeshed's module is always there; None marks its absence

__all__ = [
    "CFLAGS",
    "CSRC",
    "CBuildError",
    "PrebuiltWarning",
    "build",
    "build_command",
    "build_key",
    "cache_dir",
    "check_private",
    "compiler",
    "lock",
    "prebuilt_refusal",
]

#: The package's C sources (package data).
CSRC = Path(__file__).resolve().parent / "csrc"

#: Libraries of the built-in models compiled into a platform wheel (``make wheel``, setup.py), with their
#: sidecars: used before the cache, so that an installed wheel needs no compiler. Absent in a checkout.
PREBUILT = Path(__file__).resolve().parent / "prebuilt"

#: The package's own code beside :data:`PREBUILT`: this module and its folder. Whoever can write them runs code
#: as the package's users already; the wheel's libraries are trusted only as far as they are.
CODE = (Path(__file__).resolve().parent, Path(__file__).resolve())

#: Flags of every build: portable (no -march=native), position independent.
CFLAGS = ("-std=c99", "-O2", "-fPIC", "-shared", "-Wall", "-Wextra")

#: The header lanes.c includes, written beside the staged sources at build time (:func:`_lanes_model`).
LANES_MODEL = "lanes_model.h"

#: Part of the source key: bump to invalidate every cached library.
_KEY_VERSION = b"rocking-cbuild-2"

#: Lengths of the source and compiler keys in a library's name (hex digits).
_SOURCE_DIGITS, _COMPILER_DIGITS = 24, 12

_SIDECAR_FORMAT = 1

_TIMEOUT = 300  # seconds for one compiler call


class CBuildError(RuntimeError):
    """The C back end cannot be built: no compiler, the compiler failed (its message included), or no cache."""


class _CompilerUnavailable(CBuildError):
    """The compiler cannot be found or run: a cached library of the same sources may stand in for a build."""


def cache_dir() -> Path:
    """Where libraries are cached: ``$ROCKING_CACHE_DIR``, else ``~/.cache/rocking``.

    Raises
    ------
    CBuildError
        If ``$ROCKING_CACHE_DIR`` is not set and there is no home directory.
    """
    env = os.environ.get("ROCKING_CACHE_DIR")
    if env:
        return Path(env).expanduser()
    try:
        return Path.home() / ".cache" / "rocking"
    except (RuntimeError, KeyError, OSError):  # no $HOME and no password entry
        raise CBuildError(
            "no home directory for the C library cache: set ROCKING_CACHE_DIR to a writable folder"
        ) from None


def compiler() -> list[str]:
    """The C compiler's command: ``$CC`` (split like a shell would), else ``cc`` or ``gcc`` on ``PATH``.

    Raises
    ------
    CBuildError
        If ``$CC`` cannot be split, or is empty and neither ``cc`` nor ``gcc`` is found.
    """
    env = _split_cc()
    if env:
        return env
    for name in ("cc", "gcc"):
        path = shutil.which(name)
        if path:
            return [path]
    raise _CompilerUnavailable("no C compiler found: set $CC or install cc/gcc (e.g. `apt-get install gcc`)")


def _run(cmd: list[str]) -> subprocess.CompletedProcess:
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=_TIMEOUT, check=False)
    except FileNotFoundError:
        raise _CompilerUnavailable(
            f"C compiler {cmd[0]!r} not found (from $CC or PATH): cannot build the C back end"
        ) from None
    except OSError as exc:  # not executable, not a program (ENOEXEC), ...
        raise _CompilerUnavailable(f"C compiler {cmd[0]!r} cannot be run ({exc.strerror or exc}): fix $CC") from None
    except subprocess.TimeoutExpired:
        raise CBuildError(f"C compiler timed out after {_TIMEOUT} s: {shlex.join(cmd)}") from None


def _first_line(text: str) -> str:
    return next((line.strip() for line in text.splitlines() if line.strip()), "")


def _compiler_version(cc: list[str]) -> str:
    """The first line of ``cc --version``; run only when a library is to be compiled."""
    proc = _run([*cc, "--version"])
    if proc.returncode != 0:
        said = _first_line(proc.stderr or proc.stdout)
        raise _CompilerUnavailable(
            f"C compiler {shlex.join(cc)!r} does not run (`--version` exit {proc.returncode}"
            f"{': ' + said if said else ''}): fix $CC or unset it"
        )
    return _first_line(proc.stdout + proc.stderr)


def _sources(model, csrc: Path) -> dict[str, Path]:
    return {
        "sim.c": csrc / "sim.c",
        "sim.h": csrc / "sim.h",
        "boundary.h": csrc / "boundary.h",
        "phases.h": csrc / "phases.h",
        "lanes.c": csrc / "lanes.c",
        "lanes.h": csrc / "lanes.h",
        "lanes_kernel.h": csrc / "lanes_kernel.h",
        model.c_source.name: model.c_source,
        model.c_header.name: model.c_header,
    }


def _lanes_model(model) -> str:
    """The header of the model's right-hand side over lanes (rocking.sim.lanes_rhs), derived from its C source."""
    try:
        text = model.c_source.read_text()
    except OSError as exc:
        raise CBuildError(f"cannot read C source {model.c_source}: {exc.strerror or exc}") from None
    return _lanes_rhs().vector_rhs(text, model.c_prefix)


def _lanes_rhs():
    """rocking/sim/lanes_rhs.py, read by path: this module needs the standard library alone (setup.py)."""
    spec = importlib.util.spec_from_file_location(
        "_rocking_lanes_rhs", Path(__file__).resolve().parent / "lanes_rhs.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def build_command(model, output: Path, *, cc: list[str] | None = None, csrc: Path | None = None) -> list[str]:
    """The compiler command that builds ``model``'s library into ``output``."""
    cc = compiler() if cc is None else list(cc)
    csrc = CSRC if csrc is None else Path(csrc)
    return [
        *cc,
        *CFLAGS,
        f"-I{csrc}",
        f"-I{model.c_header.parent}",
        f'-DROCKING_MODEL_HEADER="{model.c_header.name}"',
        *([f'-DROCKING_LANES_MODEL="{LANES_MODEL}"'] if (csrc / LANES_MODEL).exists() else []),
        str(csrc / "sim.c"),
        str(model.c_source),
        "-o",
        str(output),
        "-lm",
    ]


def _digest(*parts: tuple[str, bytes]) -> str:
    digest = hashlib.sha256(_KEY_VERSION)
    for label, data in parts:
        # Length-prefixed, so that no two different inputs hash alike.
        for part in (label.encode(), data):
            digest.update(len(part).to_bytes(8, "little"))
            digest.update(part)
    return digest.hexdigest()


def _source_key(model, cc_args, csrc: Path) -> str:
    """SHA-256 of the sources, headers, flags (``$CC``'s arguments included) and platform.

    The output path and the source folders are left out: the key must not depend on
    where the package or the cache is.
    """
    parts = []
    hashes = model.manifest.get("sha256", {})
    for name, path in _sources(model, csrc).items():
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise CBuildError(f"cannot read C source {path}: {exc.strerror or exc}") from None
        if path.parent == model.folder and hashes.get(name) != hashlib.sha256(data).hexdigest():
            # The model was checked when it was loaded: a file edited since is not compiled.
            raise CBuildError(f"{path}: does not match the SHA-256 its manifest.json records (edited by hand?)")
        parts.append((f"source {name}", data))
    machine = os.uname().machine if hasattr(os, "uname") else ""
    return _digest(
        *parts,
        ("lanes model", _lanes_model(model).encode()),
        ("flags", "\0".join(CFLAGS).encode()),
        ("cc arguments", "\0".join(cc_args).encode()),
        ("header", model.c_header.name.encode()),
        ("platform", f"{sys.platform} {machine}".encode()),
    )


def _compiler_key(cc: list[str]) -> tuple[str, str]:
    """SHA-256 of the compiler program's resolved path, size and modification time, and that path.

    Stands in for the compiler's version without running it (see the module's docstring).
    """
    found = shutil.which(cc[0])  # a path is checked as it is, a bare name looked up on PATH
    if found is None:
        raise _CompilerUnavailable(
            f"C compiler {cc[0]!r} not found or not executable (from $CC or PATH): cannot build the C back end"
        )
    try:
        real = os.path.realpath(found)
        stat = os.stat(real)
    except OSError as exc:
        raise _CompilerUnavailable(f"C compiler {cc[0]!r} cannot be read ({exc.strerror or exc}): fix $CC") from None
    return _digest(("compiler", f"{real}\0{stat.st_size}\0{stat.st_mtime_ns}".encode())), real


def _name(model, source: str, tool: str) -> str:
    return f"{model.c_prefix}-{source[:_SOURCE_DIGITS]}-{tool[:_COMPILER_DIGITS]}.so"


def build_key(model, *, cc: list[str] | None = None, csrc: Path | str | None = None) -> str:
    """The key in the name of ``model``'s library: ``<source key>-<compiler key>`` (truncated SHA-256s, hex).

    Computed without running the compiler (see the module's docstring).

    Raises
    ------
    CBuildError
        If the compiler is not found, or a source cannot be read.
    """
    cc = compiler() if cc is None else list(cc)
    csrc = CSRC if csrc is None else Path(csrc)
    source = _source_key(model, cc[1:], csrc)
    tool, _ = _compiler_key(cc)
    return f"{source[:_SOURCE_DIGITS]}-{tool[:_COMPILER_DIGITS]}"


def _sidecar(library: Path) -> Path:
    return library.with_name(library.name + ".json")


def _file_digest(path: Path) -> tuple[str, int]:
    """SHA-256 (hex) and size of a file."""
    digest = hashlib.sha256()
    size = 0
    with open(path, "rb") as handle:
        for chunk in iter(lambda: handle.read(1 << 20), b""):
            digest.update(chunk)
            size += len(chunk)
    return digest.hexdigest(), size


def _uid() -> int | None:
    """The effective user id (``None`` where the platform has none)."""
    return os.geteuid() if hasattr(os, "geteuid") else None


def _private_file(path: Path) -> bool:
    """Whether ``path`` is a regular file (not a link) of the user's (or root's), writable by no one else."""
    info = os.lstat(path)
    mine = _uid() is None or info.st_uid in (_uid(), 0)
    return stat.S_ISREG(info.st_mode) and mine and not info.st_mode & 0o022


def check_private(folder: Path) -> None:
    """Refuse a cache folder that someone else could write: the user's (or root's), not writable by group or others.

    Raises
    ------
    CBuildError
        In one line, naming the folder, its owner or mode, and the fix.
    """
    try:
        info = os.stat(folder)
    except OSError as exc:
        raise _cache_error(folder, exc) from None
    if _uid() is not None and info.st_uid not in (_uid(), 0):
        raise CBuildError(
            f"the C library cache {folder} belongs to uid {info.st_uid}, not to you (uid {_uid()}) or root: a library "
            "there could run code as you; set ROCKING_CACHE_DIR to a folder of your own"
        )
    if info.st_mode & 0o022:
        raise CBuildError(
            f"the C library cache {folder} is writable by group or others (mode {stat.S_IMODE(info.st_mode):04o}): "
            f"a library planted there would run as you; chmod go-w {folder} or set ROCKING_CACHE_DIR"
        )


def _valid(library: Path, source: str, private: bool = True) -> bool:
    """Whether ``library`` exists and matches its sidecar, which was written for ``source``.

    Anything short of that (no file, no or a damaged sidecar, another size or hash,
    either file a link, someone else's or writable by others) is ``False``: the
    library is built again rather than loaded, since loading a truncated one kills
    the process and loading a planted one runs its code. ``private=False`` (the wheel's own folder, as trusted
    as the package's code beside it) leaves out the owner and mode, which the installer's umask decides.
    """
    try:
        if private and not (_private_file(library) and _private_file(_sidecar(library))):
            return False
        record = json.loads(_sidecar(library).read_text(encoding="utf-8"))
        if record["source_key"] != source or os.stat(library).st_size != record["size"]:
            return False
        return _file_digest(library) == (record["sha256"], record["size"])
    except (OSError, ValueError, KeyError, TypeError):
        return False


def _any_valid(folder: Path, model, source: str, private: bool = True) -> Path | None:
    """The newest valid library of ``source`` in ``folder``, whichever compiler built it, or ``None``."""
    stem = f"{model.c_prefix}-{source[:_SOURCE_DIGITS]}-"
    try:
        names = [name for name in os.listdir(folder) if name.startswith(stem) and name.endswith(".so")]
    except OSError:
        return None
    candidates = []
    for name in names:
        with contextlib.suppress(OSError):
            candidates.append((os.stat(folder / name).st_mtime_ns, name))
    for _, name in sorted(candidates, reverse=True):
        if _valid(folder / name, source, private):
            return folder / name
    return None


def _prebuilt(model, source: str) -> Path | None:
    """The wheel's library of ``source`` (:data:`PREBUILT`), if its folder is as trusted as the package's code
    (:func:`prebuilt_refusal`; else a :class:`PrebuiltWarning` and ``None``) and the library matches its sidecar.

    Held to the rule of the cache, measured against the package's code rather than the user: the folder, the
    library and its sidecar writable by no one who cannot write :data:`CODE` (the installer's umask may leave
    them group-writable only where the code is), not links, the library's key and hash checked before it is loaded.
    """
    if not os.path.lexists(PREBUILT):
        return None
    refused = prebuilt_refusal(PREBUILT)
    if refused:
        warnings.warn(f"the C libraries shipped in {PREBUILT} are not used: {refused}", PrebuiltWarning, stacklevel=3)
        return None
    return _any_valid(PREBUILT, model, source, private=False)


class PrebuiltWarning(UserWarning):
    """The wheel's C libraries are not loaded: their folder is not as trusted as the package's code (why is said);
    the cache builds them instead."""


def _writers(info: os.stat_result) -> set[tuple]:
    """Who may write a file or folder with the status ``info``: its owner, its group if it is group-writable,
    anyone if it is writable by others."""
    who: set[tuple] = {("uid", info.st_uid)}
    if info.st_mode & 0o020:
        who.add(("gid", info.st_gid))
    if info.st_mode & 0o002:
        who.add(("others",))
    return who


def _trusted_writers() -> set[tuple]:
    """Who may write the package's :data:`CODE` (and root, who can run anything anyway)."""
    allowed = {("uid", 0)}
    for path in CODE:
        allowed |= _writers(os.stat(path))
    return allowed


def _untrusted(path: Path, allowed: set[tuple]) -> str | None:
    """What lets someone outside ``allowed`` write ``path`` (its owner, group or others), or None."""
    info = os.stat(path)
    extra = _writers(info) - allowed
    if ("others",) in extra:
        return f"{path} is writable by others (mode {stat.S_IMODE(info.st_mode):04o})"
    if any(kind == "uid" for kind, *_ in extra):
        return f"{path} belongs to uid {info.st_uid}, not to the owner of the package's code (or root)"
    if extra:
        mode = stat.S_IMODE(info.st_mode)
        return f"{path} is writable by group {info.st_gid} (mode {mode:04o}), which cannot write the package's code"
    return None


def prebuilt_refusal(folder: Path) -> str | None:
    """Why the wheel's folder ``folder`` and its files are not trusted to be loaded, or None: a link out of the
    package, or someone who cannot write the package's code (:data:`CODE`) can write it or a file in it."""
    try:
        real = Path(os.path.realpath(folder))
        package = Path(os.path.realpath(CODE[0])).parent
        if os.path.islink(folder) and package not in real.parents:
            return f"{folder} is a symbolic link to {real}, out of the package {package}"
        allowed = _trusted_writers()
        for path in (real, *sorted(real.iterdir())):
            if path.is_symlink():
                return f"{path} is a symbolic link"
            why = _untrusted(path, allowed)
            if why:
                return why
    except OSError as exc:
        return f"{folder} cannot be read ({exc.strerror or exc})"
    return None


def _cache_error(folder: Path, exc: OSError) -> CBuildError:
    return CBuildError(
        f"cannot write the C library cache {folder} ({exc.strerror or exc}): set ROCKING_CACHE_DIR to a writable folder"
    )


_THREAD_LOCKS: dict[str, threading.Lock] = {}
_THREAD_LOCKS_GUARD = threading.Lock()
#: The paths whose lock the current thread holds: taken again, a lock is already held (a caller's).
_HELD = threading.local()


@contextlib.contextmanager
def lock(path: Path):
    """An exclusive lock on ``path``, across the threads of this process and, where fcntl exists, across processes.

    flock alone would do between threads on a local file system (each call opens its
    own file description), but not where it is emulated with per-process locks (NFS).
    The lock is reentrant within a thread (a save that draws its figures under its caller's lock). The lock file
    is opened read-only and never through a symbolic link: a link planted in its place (at a user's file) is an
    OSError, and no file is written or created through it. It is removed when the lock is released.
    """
    key = os.path.abspath(path)
    held = _HELD.__dict__.setdefault("paths", set())
    if key in held:
        yield
        return
    with _THREAD_LOCKS_GUARD:
        thread_lock = _THREAD_LOCKS.setdefault(key, threading.Lock())
    with thread_lock:
        if fcntl is None:  # pragma: no cover - Windows
            held.add(key)
            try:
                yield
            finally:
                held.discard(key)
            return
        handle = _locked(path)
        try:
            held.add(key)
            yield
        finally:
            held.discard(key)
            # Removed while held: a waiter holding the old file finds it gone once it gets it, and opens anew.
            with contextlib.suppress(OSError):
                os.unlink(path)
            os.close(handle)  # releases the flock


def _locked(path: Path) -> int:
    """A descriptor of the lock file ``path`` (created if needed, never through a link), flocked exclusively: the
    file that is at ``path`` once the lock is held (a holder removes it when done)."""
    flags = os.O_RDONLY | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC
    while True:
        handle = os.open(path, flags, 0o666)
        try:
            fcntl.flock(handle, fcntl.LOCK_EX)
            there = os.stat(path, follow_symlinks=False)
            if os.path.samestat(there, os.fstat(handle)):
                return handle
        except FileNotFoundError:
            pass
        except BaseException:
            os.close(handle)
            raise
        os.close(handle)


def _compile(cmd: list[str]) -> None:
    proc = _run(cmd)
    if proc.returncode != 0:
        raise CBuildError(
            f"C compiler failed (exit {proc.returncode}):\n  {shlex.join(cmd)}\n{(proc.stderr or proc.stdout).strip()}"
        )


def _temporary(folder: Path, prefix: str) -> Path:
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=prefix, suffix=".tmp")
    os.close(fd)
    return Path(tmp)


def _staged(model, csrc: Path, folder: Path) -> SimpleNamespace:
    """Copies of the sources of ``model``'s library in ``folder`` (``csrc/``, ``model/``), and the model as
    ``build_command`` sees it there.

    The compiler reads these copies, whose key is checked against the one the library is named by, and searches
    no other folder of the user's for an ``#include``: a file beside the sources (a stray ``math.h``) or
    changed after they were hashed never reaches the library.
    """
    (folder / "csrc").mkdir()
    (folder / "model").mkdir()
    for name, path in _sources(model, csrc).items():
        (folder / ("model" if path.parent == model.folder else "csrc") / name).write_bytes(path.read_bytes())
    (folder / "csrc" / LANES_MODEL).write_text(_lanes_model(model))
    staged = folder / "model"
    return SimpleNamespace(
        folder=staged,
        manifest=model.manifest,
        c_prefix=model.c_prefix,
        c_source=staged / model.c_source.name,
        c_header=staged / model.c_header.name,
    )


def _compile_into(model, library: Path, source: str, cc: list[str], version: str, csrc: Path) -> None:
    """Compile ``library`` and its sidecar; the caller holds the lock. OSError: the cache cannot be written."""
    temporaries = []
    try:
        tmp_library = _temporary(library.parent, f".{library.stem}-")
        temporaries.append(tmp_library)
        tmp_sidecar = _temporary(library.parent, f".{library.name}.json-")
        temporaries.append(tmp_sidecar)
        with tempfile.TemporaryDirectory(dir=library.parent, prefix=".sources-") as staging:
            staged = _staged(model, csrc, Path(staging))
            if _source_key(staged, cc[1:], Path(staging) / "csrc") != source:
                raise CBuildError(f"the C sources of {model.c_prefix} changed while its library was being built")
            _compile(build_command(staged, tmp_library, cc=cc, csrc=Path(staging) / "csrc"))
        sha256, size = _file_digest(tmp_library)
        record = {
            "format": _SIDECAR_FORMAT,
            "library": library.name,
            "sha256": sha256,
            "size": size,
            "source_key": source,
            "compiler": shlex.join(cc),
            "compiler_version": version,
            "flags": list(CFLAGS),
        }
        tmp_sidecar.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
        for tmp in (tmp_library, tmp_sidecar):
            os.chmod(tmp, 0o644)  # mkstemp made them 0600; read-only for all, as a wheel ships them
        # The library first: until the sidecar follows, readers see a mismatch and wait for the lock.
        os.replace(tmp_library, library)
        os.replace(tmp_sidecar, _sidecar(library))
    finally:
        for tmp in temporaries:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)


def build(model, *, cache: Path | str | None = None, csrc: Path | str | None = None) -> Path:
    """The shared library of ``sim.c`` with ``model``'s generated C, built at first use.

    A cached library that matches its sidecar is returned without running the
    compiler; a damaged one is built again. If the compiler cannot be found or run,
    a valid cached library of the same sources and flags built by another compiler
    is returned instead (see the module's docstring).

    Parameters
    ----------
    model : Model
        A generated model (``model.c_source`` / ``model.c_header`` are compiled in).
    cache : path, optional
        Cache directory; default :func:`cache_dir`.
    csrc : path, optional
        Folder holding ``sim.c`` and ``sim.h``; default the package's :data:`CSRC`.

    Returns
    -------
    Path
        The library, ``<cache>/<prefix>-<source key>-<compiler key>.so``, checked against its sidecar; or
        the one of the same sources a platform wheel ships in :data:`PREBUILT`.

    Raises
    ------
    CBuildError
        If there is no usable compiler and no library to stand in, the compiler
        fails (the message includes its output), or the cache directory cannot be
        created or written (one line, naming the folder).
    """
    csrc = CSRC if csrc is None else Path(csrc)
    folder = cache_dir() if cache is None else Path(cache).expanduser()
    # $CC is split without running anything: its arguments are known even when its program is not.
    source = _source_key(model, _cc_arguments(), csrc)
    shipped = _prebuilt(model, source)
    if shipped is not None:
        return shipped
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    except OSError as exc:
        raise _cache_error(folder, exc) from None
    check_private(folder)
    try:
        cc = compiler()
        tool, _ = _compiler_key(cc)
    except _CompilerUnavailable as exc:
        return _stand_in(folder, model, source, exc)
    library = folder / _name(model, source, tool)
    if _valid(library, source):
        return library
    try:
        version = _compiler_version(cc)
    except _CompilerUnavailable as exc:
        return _stand_in(folder, model, source, exc)
    try:
        with lock(folder / f".{library.name}.lock"):
            if not _valid(library, source):  # another thread or process may have built it while this one waited
                _compile_into(model, library, source, cc, version, csrc)
    except OSError as exc:
        raise _cache_error(folder, exc) from None
    return library


def _split_cc() -> list[str]:
    """``$CC`` split like a shell would (empty if unset)."""
    env = os.environ.get("CC", "").strip()
    try:
        return shlex.split(env)
    except ValueError as exc:  # an unbalanced quote
        raise CBuildError(f"$CC={env!r} cannot be split like a shell would ({exc}): fix $CC or unset it") from None


def _cc_arguments() -> list[str]:
    """The arguments of ``$CC`` after its program (none without ``$CC``): ``compiler()[1:]``."""
    return _split_cc()[1:]


def _stand_in(folder: Path, model, source: str, exc: _CompilerUnavailable) -> Path:
    """A valid cached library of ``source`` built by any compiler, else the reason there is none (one line)."""
    library = _any_valid(folder, model, source)
    if library is None:
        raise CBuildError(str(exc)) from None
    return library
