"""Build the C back end: ``rocking/csrc/sim.c`` with one generated model, as a cached shared library.

The library is compiled at first use into a cache directory (``~/.cache/rocking``,
or ``$ROCKING_CACHE_DIR``) under a name keyed by the SHA-256 of everything that
goes into it: the C sources and headers, the flags, the compiler's command and
its ``--version``. A changed source, flag or compiler gives a new key, hence a
new build; an unchanged one is loaded as it is.

Several processes may build the same library at once (a parallel test run, the
workers of a study): each compiles into its own temporary file in the cache
directory and renames it into place with :func:`os.replace`, which is atomic, so
a reader never sees half a library. Where :mod:`fcntl` exists a lock file also
keeps them from compiling the same thing twice.

No ``-march=native``: the cache may be shared between machines.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

try:  # POSIX only; without it concurrent builds are still safe, only duplicated.
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None

__all__ = ["CFLAGS", "CSRC", "CBuildError", "build", "build_command", "build_key", "cache_dir", "compiler"]

#: The package's C sources (package data).
CSRC = Path(__file__).resolve().parent / "csrc"

#: Flags of every build: portable (no -march=native), position independent.
CFLAGS = ("-std=c99", "-O2", "-fPIC", "-shared", "-Wall", "-Wextra")

#: Part of the key: bump to invalidate every cached library.
_KEY_VERSION = b"rocking-cbuild-1"

_TIMEOUT = 300  # seconds for one compiler call


class CBuildError(RuntimeError):
    """The C back end cannot be built: no compiler, or the compiler failed (its message included)."""


def cache_dir() -> Path:
    """Where libraries are cached: ``$ROCKING_CACHE_DIR``, else ``~/.cache/rocking``."""
    env = os.environ.get("ROCKING_CACHE_DIR")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "rocking"


def compiler() -> list[str]:
    """The C compiler's command: ``$CC`` (split like a shell would), else ``cc`` or ``gcc`` on ``PATH``.

    Raises
    ------
    CBuildError
        If ``$CC`` is empty and neither ``cc`` nor ``gcc`` is found.
    """
    env = os.environ.get("CC", "").strip()
    if env:
        return shlex.split(env)
    for name in ("cc", "gcc"):
        path = shutil.which(name)
        if path:
            return [path]
    raise CBuildError("no C compiler found: set $CC or install cc/gcc (e.g. `apt-get install gcc`)")


def _run(cmd: list[str]) -> subprocess.CompletedProcess:
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=_TIMEOUT, check=False)
    except FileNotFoundError:
        raise CBuildError(f"C compiler {cmd[0]!r} not found (from $CC or PATH): cannot build the C back end") from None
    except PermissionError as exc:
        raise CBuildError(f"C compiler {cmd[0]!r} cannot be run: {exc}") from None
    except subprocess.TimeoutExpired:
        raise CBuildError(f"C compiler timed out after {_TIMEOUT} s: {shlex.join(cmd)}") from None


def _compiler_version(cc: list[str]) -> str:
    proc = _run([*cc, "--version"])
    if proc.returncode != 0:
        raise CBuildError(
            f"C compiler {shlex.join(cc)!r} does not run (`--version` exit {proc.returncode}):\n{proc.stderr.strip()}"
        )
    return proc.stdout + proc.stderr


def _sources(model, csrc: Path) -> dict[str, Path]:
    return {
        "sim.c": csrc / "sim.c",
        "sim.h": csrc / "sim.h",
        "boundary.h": csrc / "boundary.h",
        model.c_source.name: model.c_source,
        model.c_header.name: model.c_header,
    }


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
        str(csrc / "sim.c"),
        str(model.c_source),
        "-o",
        str(output),
        "-lm",
    ]


def build_key(model, *, cc: list[str] | None = None, csrc: Path | None = None) -> str:
    """SHA-256 (hex) of the sources, headers, flags, compiler command and compiler version.

    Raises
    ------
    CBuildError
        If the compiler is missing or does not run, or a source cannot be read.
    """
    cc = compiler() if cc is None else list(cc)
    csrc = CSRC if csrc is None else Path(csrc)
    digest = hashlib.sha256(_KEY_VERSION)

    def add(label: str, data: bytes) -> None:
        # Length-prefixed, so that no two different inputs hash alike.
        for part in (label.encode(), data):
            digest.update(len(part).to_bytes(8, "little"))
            digest.update(part)

    for name, path in _sources(model, csrc).items():
        try:
            add(f"source {name}", path.read_bytes())
        except OSError as exc:
            raise CBuildError(f"cannot read C source {path}: {exc}") from None
    # The command with the output path and source folders left out: the key must
    # not depend on where the package or the cache is.
    add("flags", "\0".join(CFLAGS).encode())
    add("header", model.c_header.name.encode())
    add("compiler", "\0".join(cc).encode())
    add("version", _compiler_version(cc).encode())
    add("platform", f"{sys.platform} {os.uname().machine if hasattr(os, 'uname') else ''}".encode())
    return digest.hexdigest()


@contextlib.contextmanager
def _lock(path: Path):
    """An exclusive lock on ``path`` where fcntl exists; nothing otherwise."""
    if fcntl is None:  # pragma: no cover - Windows
        yield
        return
    with open(path, "a+b") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def _compile(cmd: list[str]) -> None:
    proc = _run(cmd)
    if proc.returncode != 0:
        raise CBuildError(
            f"C compiler failed (exit {proc.returncode}):\n  {shlex.join(cmd)}\n{(proc.stderr or proc.stdout).strip()}"
        )


def build(model, *, cache: Path | str | None = None, csrc: Path | str | None = None) -> Path:
    """The shared library of ``sim.c`` with ``model``'s generated C, built at first use.

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
        The library, ``<cache>/<prefix>-<key>.so``.

    Raises
    ------
    CBuildError
        If there is no compiler, it fails (the message includes its output), or
        the cache directory cannot be written.
    """
    cc = compiler()
    csrc = CSRC if csrc is None else Path(csrc)
    folder = cache_dir() if cache is None else Path(cache).expanduser()
    key = build_key(model, cc=cc, csrc=csrc)
    library = folder / f"{model.c_prefix}-{key[:32]}.so"
    if library.is_file():
        return library
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CBuildError(f"cannot create the C cache directory {folder}: {exc}") from None
    with _lock(folder / f".{library.name}.lock"):
        if library.is_file():  # another process built it while this one waited
            return library
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{library.stem}-", suffix=".tmp")
        os.close(fd)
        try:
            _compile(build_command(model, Path(tmp), cc=cc, csrc=csrc))
            os.chmod(tmp, 0o644)  # mkstemp made it private; the cache may be shared
            os.replace(tmp, library)
        finally:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(tmp)
    return library
