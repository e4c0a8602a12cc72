"""Every output is written as a study's data are (issue 36, item 1): a temporary file in its folder renamed over
it, a symbolic link in its place replaced and never followed; two saves of one study name into one folder take
turns under a lock on the name, so that the figures beside the data are always those of that data."""

from __future__ import annotations

import builtins
import hashlib
import io
import json
import multiprocessing
import os
import threading
from pathlib import Path

import pytest
from matplotlib.figure import Figure

import rocking.cli.study
from rocking import Block, ParameterError
from rocking.cli.main import main
from rocking.plot import figures
from rocking.plot.figures import draw, redraw
from rocking.study import files
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import overturning_map
from rocking.study.storage import save
from rocking.study.tiles import Execution

SERIAL = Execution(workers=1, progress=False)
ROUNDS = 5
MINE = b"a file of the user's, not a figure\n"
PNG = b"\x89PNG\r\n\x1a\n"


def _map(runs: Path, gamma: float):
    """A small map (2 x 3 cells): its damper's mass ratio ``gamma`` tells two of them apart."""
    return overturning_map(
        Setting(Block.reference()),
        Tuning(gamma),
        Grid("Omega", 2.0, 6.0, 2),
        Grid("beta", 1.0, 6.0, 3),
        SERIAL,
        runs=runs,
    )


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    """Two different small maps."""
    runs = tmp_path_factory.mktemp("runs")
    return _map(runs, 0.05), _map(runs, 0.2)


@pytest.fixture
def small_figure(monkeypatch):
    """A map's figure that costs little to draw, and tells the two maps apart (by their damper): what is tested is
    how figures are written, not drawn (a map's figure takes seconds on a loaded machine)."""

    def drawn(study, **kwargs) -> Figure:
        fig = Figure(figsize=(1.0, 1.0))
        fig.text(0.1, 0.5, f"gamma = {study.config['damper']['gamma']:g}")
        return fig

    monkeypatch.setitem(figures.FIGURES, "map", drawn)


def _victim(folder: Path) -> Path:
    victim = folder / "victim.txt"
    victim.write_bytes(MINE)
    return victim


def _planted_link(path: Path, victim: Path) -> None:
    path.unlink(missing_ok=True)
    path.symlink_to(victim)


def _assert_replaced(path: Path, victim: Path, magic: bytes) -> None:
    """The link at ``path`` was replaced by a new file (``magic`` its first bytes); the file it pointed at is as
    it was."""
    assert victim.read_bytes() == MINE, "the file behind the link was written"
    assert not path.is_symlink() and path.read_bytes().startswith(magic)


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def test_redraw_replaces_a_linked_figure_and_never_writes_through_it(studies, tmp_path, small_figure):
    out = tmp_path / "study"
    save(studies[0], out, "map")
    draw(studies[0], out, "map")
    victim = _victim(tmp_path)
    _planted_link(out / "map.png", victim)
    _planted_link(out / "map.pdf", victim)
    redraw(out / "map.json", ("png", "pdf"))
    _assert_replaced(out / "map.png", victim, PNG)
    _assert_replaced(out / "map.pdf", victim, b"%PDF")
    assert not _leftovers(out)


def test_a_command_saving_into_out_replaces_linked_files_and_never_writes_through_them(studies, tmp_path, small_figure):
    out = tmp_path / "out"
    out.mkdir()
    victim = _victim(tmp_path)
    for name in ("map.pdf", "map.png", "map.nc", "map.csv", "map.json"):
        _planted_link(out / name, victim)
    rocking.cli.study._report(studies[0], out, ("png", "pdf"), "map")
    for name, magic in (("map.png", PNG), ("map.pdf", b"%PDF"), ("map.nc", b"\x89HDF"), ("map.json", b"{")):
        _assert_replaced(out / name, victim, magic)
    assert not _leftovers(out)


def test_a_link_planted_as_the_lock_of_a_name_is_refused_in_one_line(studies, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    victim = _victim(tmp_path)
    _planted_link(out / ".map.lock", victim)
    with pytest.raises(ParameterError, match=r"cannot lock .*\.map\.lock against another save of map") as info:
        save(studies[0], out, "map")
    assert "\n" not in str(info.value) and victim.read_bytes() == MINE
    assert not (out / "map.json").exists()


OUTPUTS = [("--plot", "fig.png", PNG), ("--plot", "fig.pdf", b"%PDF"), ("--history", "h.csv", b"t [s]"),
           ("--history", "h.nc", b"\x89HDF")]  # fmt: skip


@pytest.mark.parametrize("option, name, magic", OUTPUTS)
def test_simulate_replaces_a_linked_output_and_never_writes_through_it(tmp_path, monkeypatch, option, name, magic):
    monkeypatch.chdir(tmp_path)
    victim = _victim(tmp_path)
    _planted_link(tmp_path / name, victim)
    assert main(["simulate", "--beta", "3", "--Omega", "4", option, name]) == 0
    _assert_replaced(tmp_path / name, victim, magic)
    assert not _leftovers(tmp_path)


# --- two writers of one name ------------------------------------------------------------------------------------


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _snapshot(out: Path) -> tuple[str, str]:
    """The configuration's hash of the study saved in ``out`` and its PNG's, read under the lock on its name."""
    with files.name_lock(out, "map"):
        return json.loads((out / "map.json").read_text())["config_sha256"], _sha256(out / "map.png")


def _saver(study, out: Path, rounds: int, expected: dict, queue) -> None:
    """Save ``study`` as ``map`` into ``out`` ``rounds`` times, as the study commands do, checking after each save
    that the PNG there is the one of the data there."""
    wrong = 0
    for _ in range(rounds):
        rocking.cli.study._report(study, out, ("png",), "map")
        config, png = _snapshot(out)
        wrong += expected[config] != png
    queue.put(wrong)


def test_two_processes_saving_one_name_leave_the_figure_of_the_data_there(studies, tmp_path, small_figure):
    """2 processes x 5 saves of two different maps under one name into one folder: after every save, and at the
    end, map.png is the picture of the study whose map.json and map.nc are there, and readable."""
    expected = {}
    for i, study in enumerate(studies):  # each study's own PNG, drawn alone
        alone = tmp_path / f"alone-{i}"
        save(study, alone, "map")
        draw(study, alone, "map")
        expected[_snapshot(alone)[0]] = _sha256(alone / "map.png")
    assert len(set(expected.values())) == 2  # the two pictures differ: a mix would show
    out = tmp_path / "out"
    out.mkdir()
    context = multiprocessing.get_context("fork")
    queue = context.Queue()
    savers = [context.Process(target=_saver, args=(study, out, ROUNDS, expected, queue)) for study in studies]
    for saver in savers:
        saver.start()
    for saver in savers:
        saver.join(timeout=300)
    assert [saver.exitcode for saver in savers] == [0, 0]
    assert [queue.get(timeout=5) for _ in savers] == [0, 0]
    config, png = _snapshot(out)
    assert expected[config] == png and (out / "map.png").read_bytes().startswith(PNG)
    assert not _leftovers(out)


def test_the_lock_of_a_name_is_held_across_threads_and_reentrant(tmp_path):
    """A second thread waits for the lock a first holds; the holder may take it again (a save under its caller's
    lock); the lock's file is removed once released."""
    order = []

    def wait() -> None:
        with files.name_lock(tmp_path, "map"):
            order.append("got")

    with files.name_lock(tmp_path, "map"):
        with files.name_lock(tmp_path, "map"):  # reentrant: no deadlock
            order.append("held")
        waiter = threading.Thread(target=wait)
        waiter.start()
        waiter.join(timeout=0.5)
        assert waiter.is_alive() and order == ["held"]  # waits while the lock is held
        order.append("released")
    waiter.join(timeout=10)
    assert order == ["held", "released", "got"] and not list(tmp_path.iterdir())


# --- inputs: files of the kernel and devices, huge records (issue 36, item 5) -----------------------------------

#: Regular files of the kernel: /proc/kmsg waits for the kernel's messages (and, read by root, consumes them).
KERNEL_FILES = [p for p in ("/proc/kmsg", "/proc/self/status", "/sys/kernel/notes") if os.path.isfile(p)]


def _readers(tmp_path: Path) -> dict:
    """Every reader of an input file, each given a path: a record, a saved study (its .json or its .nc), a spec."""
    from rocking.derive.spec import SpecError, load_spec
    from rocking.model.records import read_record
    from rocking.study.storage import load

    def study_nc(path: str) -> None:  # a saved study whose .nc is a link to the file
        (tmp_path / "s.json").write_text("{}")
        (tmp_path / "s.nc").unlink(missing_ok=True)
        (tmp_path / "s.nc").symlink_to(path)
        load(tmp_path / "s.json")

    return {
        "record": (lambda path: read_record(path, "g"), ParameterError),
        "study json": (lambda path: files.read_json(Path(path)), ValueError),
        "study nc": (study_nc, ParameterError),
        "spec": (load_spec, SpecError),
    }


@pytest.mark.parametrize("reader", ["record", "study json", "study nc", "spec"])
def test_a_file_of_the_kernel_is_never_read_as_an_input(tmp_path, monkeypatch, reader):
    read, error = _readers(tmp_path)[reader]
    opened = []
    for module in (os, io, builtins):  # every way a file is opened: none of them may open the kernel's
        real = module.open

        def spy(path, *args, real=real, **kwargs):
            opened.append(str(path))
            return real(path, *args, **kwargs)

        monkeypatch.setattr(module, "open", spy)
    assert KERNEL_FILES
    for path in KERNEL_FILES:
        link = tmp_path / "innocent.csv"
        link.unlink(missing_ok=True)
        link.symlink_to(path)
        for given in (path, str(link)):
            with pytest.raises(error, match=r"is a file of the kernel or a device.* under /(proc|sys): not an input"):
                read(given)
    assert not [p for p in opened if p.startswith(("/proc", "/sys")) or "innocent" in p]


def test_a_csv_of_too_many_rows_is_refused_before_any_row_is_parsed(tmp_path, monkeypatch):
    """A file of columns of more rows than MAX_SAMPLES (here lowered to 50,000: 60,000 rows, 1 MB) is refused
    from a count of its lines, before any row is parsed (was: 4.1 million rows parsed for ~50 s)."""
    from rocking.model import records

    monkeypatch.setattr(records, "MAX_SAMPLES", 50_000)
    monkeypatch.setattr(records, "_row", lambda *a: pytest.fail("a row was parsed"))
    path = tmp_path / "long.csv"
    path.write_text("# a comment\ntime [s], a [g]\n" + "".join(f"{0.01 * i:.2f},0.001\n" for i in range(60_000)))
    with pytest.raises(ParameterError, match=r"long.csv: more than the 50000 samples .* got 60001 lines") as info:
        records.read_columns(path)
    assert "\n" not in str(info.value)
