"""The platform wheel ships the compiled simulator: installed where there is no compiler, it runs on C."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent

# One pytest-xdist worker for the module (make test: --dist loadgroup): its fixture builds the wheel once.
pytestmark = pytest.mark.xdist_group("wheel")
MAP = (
    "import rocking; ds = rocking.overturning_map(rocking.Block.reference(), dict(gamma=0.05), Omega=[2.0, 4.0], "
    "beta=[2.0, 6.0], backend='c', workers=1, progress=False, runs={runs!r}); "
    "print(ds['theta_max'].sel(part='damper').values.ravel().tolist())"
)
WHERE = "from rocking.sim import cbuild; import rocking; print(cbuild.build(rocking.load_model('omd')))"


@pytest.fixture(scope="module")
def wheel_venv(tmp_path_factory):
    """A fresh venv with the wheel installed, borrowing this environment's dependencies (not its rocking)."""
    tmp = tmp_path_factory.mktemp("wheel")
    # Built from a copy: setuptools works in the source's build/, where an earlier build cut short leaves files
    # that fail the next one ("dist-info already exists").
    source = tmp / "source"
    shutil.copytree(
        ROOT,
        source,
        ignore=shutil.ignore_patterns(".git", ".venv", "build", "out", "*.egg-info", "__pycache__", "*.so", "_build"),
    )
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check"]
    subprocess.run([*pip, "wheel", "--quiet", "--no-deps", "--wheel-dir", str(tmp / "dist"), str(source)], check=True)
    (wheel,) = (tmp / "dist").glob("rocking-*.whl")
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(tmp / "venv")], check=True)
    python = tmp / "venv" / "bin" / "python"
    site = subprocess.run(
        [python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    subprocess.run([*pip, "install", "--quiet", "--no-deps", "--target", site, str(wheel)], check=True)
    # numpy, scipy, ... from here: a path line only, so that this environment's editable rocking is not seen.
    (Path(site) / "borrowed.pth").write_text(sysconfig.get_path("purelib") + "\n")
    return python, tmp


def test_the_wheel_runs_a_map_on_c_without_a_compiler(wheel_venv):
    python, tmp = wheel_venv
    cache = tmp / "cache"
    env = {**os.environ, "CC": str(tmp / "no-such-compiler"), "ROCKING_CACHE_DIR": str(cache), "PATH": "/nonexistent"}
    where = subprocess.run([python, "-c", WHERE], env=env, capture_output=True, text=True, cwd=tmp)
    assert where.returncode == 0, where.stderr
    assert "/rocking/sim/prebuilt/omd-" in where.stdout and str(tmp / "venv") in where.stdout
    run = subprocess.run(
        [python, "-W", "error::UserWarning", "-c", MAP.format(runs=str(tmp / "runs"))],
        env=env,
        capture_output=True,
        text=True,
        cwd=tmp,
    )
    assert run.returncode == 0, run.stderr
    assert not list(cache.glob("*.so"))  # nothing compiled: the wheel's library ran
    here = subprocess.run(
        [sys.executable, "-c", MAP.format(runs=str(tmp / "runs-here"))], capture_output=True, text=True, check=True
    )
    np.testing.assert_allclose(json.loads(run.stdout), json.loads(here.stdout), rtol=1e-9)


def test_the_wheel_marks_the_package_typed(wheel_venv):
    python, tmp = wheel_venv
    where = subprocess.run(
        [python, "-c", "import rocking, pathlib; print(pathlib.Path(rocking.__file__).parent / 'py.typed')"],
        capture_output=True,
        text=True,
        cwd=tmp,
    )
    assert where.returncode == 0, where.stderr
    assert Path(where.stdout.strip()).is_file()
    assert str(tmp / "venv") in where.stdout
