"""Output files written whole: a temporary file in the target's folder, renamed over it.

Every output of rocking (a study's data and figures, a response's figure and history) goes through
:func:`replace_file`: a reader, or a rerun after Ctrl-C or a killed process, sees the old file, no file, or the
whole new one; a symbolic link in the target's place is replaced, never followed; a full disk raises
:class:`DiskFull` naming the file, and nothing partial stays behind. Below the simulator and the studies, so that
both write alike (``rocking.study.files`` adds the reading side and the lock on a study's name).
"""

from __future__ import annotations

import errno
import os
import secrets
import shutil
from collections.abc import Callable
from contextlib import suppress
from pathlib import Path

#: errno values of a full disk: no space left, or the user's quota used up.
FULL = frozenset({errno.ENOSPC, errno.EDQUOT})

#: Free bytes below which a failed write that carries no errno (the NetCDF library's "HDF error") is
#: a full disk: a write that does not fit fills the disk to its last blocks before it fails.
FULL_MARGIN = 1 << 20

#: Mode of a new file before the umask (os.open applies it, as for any file a program creates).
NEW_FILE_MODE = 0o666


class DiskFull(OSError):
    """No space left on the disk (or quota used up) writing ``path``; nothing partial is left behind.

    Attributes
    ----------
    path : Path
        The file that did not fit (its final name, not a temporary one).
    kept : int or None
        Finished tiles of the study kept on disk, when known: a rerun resumes from them.
    """

    def __init__(self, path: str | Path, kept: int | None = None) -> None:
        super().__init__(errno.ENOSPC, "No space left on device", str(path))
        self.path, self.kept = Path(path), kept

    def __str__(self) -> str:
        kept = f": {self.kept} tiles kept" if self.kept is not None else ""
        return f"disk full writing {self.path}{kept}"


def is_full(exc: BaseException, folder: Path | None = None) -> bool:
    """True if ``exc`` says the disk is full: its errno, or (``folder`` given) a library's error without one
    (RuntimeError, OSError) while ``folder``'s disk is full (:func:`no_space`)."""
    if isinstance(exc, OSError) and exc.errno in FULL:
        return True
    if folder is None or not isinstance(exc, (RuntimeError, OSError)) or getattr(exc, "errno", None):
        return False
    return no_space(folder)


def no_space(folder: Path) -> bool:
    """True if the disk of ``folder`` has less than :data:`FULL_MARGIN` bytes free (False if it cannot tell)."""
    try:
        return shutil.disk_usage(folder).free < FULL_MARGIN
    except OSError:
        return False


def _new_file(path: Path) -> int:
    """Create ``path`` (it must not exist), open for writing, with mode 0666 less the umask."""
    return os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), NEW_FILE_MODE)


def write_file(path: Path, write: Callable, mode: str = "wb") -> None:
    """Create ``path`` and write it through ``write(file)``; ``mode``: ``"wb"``, or ``"w"`` (UTF-8 text)."""
    fd = _new_file(path)
    with os.fdopen(fd, "wb") if "b" in mode else os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
        write(f)


def atomic_write(path: Path, write: Callable, mode: str = "wb") -> None:
    """Write through ``write(file)`` to a temporary file next to ``path``, then rename it over ``path``
    (:func:`replace_file`).

    Parameters
    ----------
    path : Path
        The file to write; its folder must exist.
    write : callable
        ``write(file)``, given the open temporary file.
    mode : {"wb", "w"}, optional
        Binary, or text (UTF-8, newlines as written).

    Raises
    ------
    DiskFull
        If the disk is full; the temporary file is removed.
    """
    replace_file(path, lambda tmp: write_file(tmp, write, mode))


def replace_file(path: Path, make: Callable[[Path], None]) -> None:
    """``make(tmp)`` creates the new file at a temporary name next to ``path``; it is then renamed over ``path``.

    The one way rocking writes an output file (a study's files are made so in a temporary folder, then renamed).

    Raises
    ------
    DiskFull
        If the disk is full; the temporary file is removed.

    Notes
    -----
    A reader (or a rerun after Ctrl-C or a killed process) sees either the old
    file, or no file, or the whole new one. A symbolic link at ``path`` is
    replaced by the new file: the file it points at is never written. The file
    gets the mode of any new file (0666 less the umask; :func:`write_file`), not
    a temporary file's 0600. No fsync: it would cost as much as a small tile's
    work, and only a power cut can leave a damaged file, which :func:`rocking.load` and
    :func:`rocking.study.tiles.load_tile` refuse.
    """
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(8)}.tmp")
    try:
        make(tmp)
        os.replace(tmp, path)
    except BaseException as exc:
        # Ctrl-C may come just after the rename (the signal is handled when os.replace returns): no tmp then.
        with suppress(FileNotFoundError):
            os.unlink(tmp)
        if is_full(exc):
            raise DiskFull(path) from None
        raise


def write_netcdf(dataset, path: Path) -> None:
    """Write ``dataset`` as NetCDF-4 into the new file ``path``, made in memory first.

    The NetCDF library that fails to write a file (a full disk) keeps it open and refuses the next file of
    the process ("NetCDF: HDF error"); in memory it never writes the disk, and a full disk is the OSError of
    :func:`write_file`. An xarray that writes NetCDF-4 to files only (before 2025) writes the file itself:
    a full disk is then told by the free space left beside the partial file (:func:`is_full`).
    """
    try:
        data = dataset.to_netcdf(engine="netcdf4")
    except ValueError:  # "invalid engine for creating bytes": an older xarray
        dataset.to_netcdf(path, engine="netcdf4")
        return
    write_file(path, lambda f: f.write(data))
