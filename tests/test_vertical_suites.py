"""Suites of record files paired with vertical records (docs/model.md section 14): an IDA of a pair is the single
runs of that pair at each scale, a vertical of zeros is no vertical, bad pairs are refused in one line naming the
option, and the configuration and the Dataset name the vertical files."""

import json

import numpy as np
import pytest

import rocking
from rocking.cli.main import main
from rocking.model.intensity import pga
from rocking.model.records import read_record
from rocking.plot.figures import _suite_label
from rocking.study.ida import envelope
from rocking.study.overturning_map import FIELDS
from rocking.study.suite import Suite, suite_of

BLOCK = rocking.Block.reference()
SCALES = [0.5, 1.5, 3.0]
DT = 0.01

# One record per suite: its lognormal is warned of, which these tests do not look at.
pytestmark = pytest.mark.filterwarnings("ignore::rocking.FitWarning")


def _at2(path, a, dt=DT):
    """A PEER .AT2 file of the accelerations ``a`` (in g) at ``dt``."""
    header = ["PEER NGA STRONG MOTION DATABASE RECORD", "test", "ACCELERATION TIME SERIES IN UNITS OF G"]
    header.append(f"NPTS= {len(a)}, DT= {dt:.4f} SEC")
    body = "\n".join("".join(f"{v:15.7E}" for v in a[i : i + 5]) for i in range(0, len(a), 5))
    path.write_text("\n".join(header) + "\n" + body + "\n")
    return path


@pytest.fixture
def pair(tmp_path):
    """A horizontal record and a vertical one of the same dt, the vertical shorter (0 after its end)."""
    t = np.arange(301) * DT
    h = 0.25 * np.sin(2 * np.pi * 1.2 * t) * np.exp(-(((t - 1.5) / 0.8) ** 2))
    v = 0.15 * np.sin(2 * np.pi * 3.0 * t[:250] + 0.4)
    return _at2(tmp_path / "h.AT2", h), _at2(tmp_path / "v.AT2", v)


def _ida(tmp_path, motions, scales=SCALES, **keywords):
    return rocking.incremental_dynamic_analysis(
        BLOCK, {"gamma": 0.05}, scales=scales, motions=motions, directions="both", check="none", t_after=5.0,
        runs=tmp_path / "runs", workers=1, progress=False, study=True, **keywords,
    )  # fmt: skip


def test_an_ida_of_a_pair_is_the_single_runs_of_the_pair_at_each_scale(tmp_path, pair):
    h, v = pair
    study = _ida(tmp_path, [h], vertical_motions=[v])
    horizontal, vertical = read_record(h), read_record(v)
    a_v = np.concatenate((vertical.acceleration, np.zeros(horizontal.acceleration.size - vertical.acceleration.size)))
    damper = rocking.Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    data = study.data
    uplifted = 0
    for part, run in (("bare", None), ("damper", damper)):
        for j, scale in enumerate(SCALES):
            for sign in (1, -1):
                motion = rocking.SampledMotion(horizontal.acceleration, dt=DT, a_v=a_v, sign=sign).scaled(scale)
                one = rocking.simulate(BLOCK, run, motion, t_after=5.0)
                cell = data.sel(part=part, motion="h.AT2", level=data["level"].values[j], sign=sign)
                assert cell["theta_max"].item() == one.theta_max and cell["impacts"].item() == one.impacts
                assert bool(cell["overturned"]) == one.overturned
                uplifted += one.theta_max > 0
    assert uplifted > 0  # the pair rocks the block: the comparison is not of blocks at rest
    plain = _ida(tmp_path, [h])
    assert not np.array_equal(plain.data["theta_max"].values, data["theta_max"].values)


def test_a_vertical_record_of_zeros_is_no_vertical_record(tmp_path, pair):
    h, _ = pair
    zeros = _at2(tmp_path / "zeros.AT2", np.zeros(301))
    plain, zero = _ida(tmp_path / "a", [h]), _ida(tmp_path / "b", [h], vertical_motions=[zeros])
    for name in FIELDS:
        assert np.array_equal(plain.data[name].values, zero.data[name].values, equal_nan=True), name
    assert "vertical" not in plain.config["suite"] and zero.config["suite"]["vertical"]["files"][0]["path"] == str(
        zeros.resolve()
    )
    # The figure's title says the records carry vertical ones.
    assert _suite_label(zero.config["suite"]) == "1 record with its vertical record"
    assert _suite_label(plain.config["suite"]) == "1 record"


def test_a_fragility_of_pairs_scales_to_the_measure_of_the_horizontal_record(tmp_path, pair):
    h, v = pair
    data = rocking.fragility(
        BLOCK, None, levels=[1.0, 2.0], motions=[h], vertical_motions=[v], check="none", runs=tmp_path,
        workers=1, progress=False,
    )  # fmt: skip
    record = read_record(h)
    assert data["im"].item() == pytest.approx(pga(record.acceleration, record.dt), rel=1e-12)
    assert data["vertical_motion"].values.tolist() == ["v.AT2"] and "vertical" in data["vertical_motion"].long_name
    assert envelope(data)["overturned"].dims == ("part", "motion", "level")


def test_bad_pairs_are_refused_in_one_line_naming_the_option(tmp_path, pair):
    h, v = pair
    other = _at2(tmp_path / "other.AT2", np.zeros(301), dt=0.005)
    cases = [
        ({"vertical_motions": [v, v]}, r"^vertical_motions must give one vertical record per record of motions"),
        ({"vertical_motions": [tmp_path / "none.AT2"]}, r"^vertical_motions: .*none\.AT2"),
        ({"vertical_motions": [other]}, r"^vertical_motions .*other\.AT2: dt = 0\.005 s, the horizontal record's is"),
        ({"vertical_motions": [(v, "gal")]}, r"^vertical_motions: unit of .*v\.AT2 must be one of g, "),
    ]
    for keywords, message in cases:
        with pytest.raises(rocking.ParameterError, match=message) as caught:
            suite_of([h], **keywords)
        assert "\n" not in str(caught.value)
    with pytest.raises(rocking.ParameterError, match=r"^vertical_motions: only with motions FILES$"):
        suite_of(stochastic=2, vertical_motions=[v])
    with pytest.raises(rocking.ParameterError, match=r"^pulses makes its own suite: no vertical_motions$"):
        suite_of(pulses="sine", periods=[1.0], vertical_motions=[v])
    with pytest.raises(rocking.ParameterError, match=r"^vertical_motions pairs record files: give them to Suite"):
        suite_of(Suite.from_files([h]), vertical_motions=[v])


def test_a_vertical_record_changed_after_the_suite_was_made_is_refused(tmp_path, pair):
    h, v = pair
    suite = Suite.from_files([h], vertical_motions=[(v, "g")])
    assert suite.record()["vertical"]["files"][0]["unit"] == "g" and suite.motion(0).a_v is not None
    v.write_text(v.read_text().replace("E-01", "E-02", 1))
    with pytest.raises(rocking.ParameterError, match=r"v\.AT2: changed since the suite was made"):
        suite.motion(0)


def test_the_command_line_pairs_the_records_and_records_the_pair(tmp_path, pair, capsys):
    h, v = pair
    argv = ["ida", "--motions", str(h), "--scales", "0.5", "3", "3", "--directions", "both", "--check", "none"]
    argv += ["--t-after", "5", "--workers", "1", "--no-progress"]
    assert main([*argv, "--vertical-motions", f"{v}:g", "--out", str(tmp_path / "c")]) == 0
    assert "ida: motions of sign +1 and -1" in capsys.readouterr().out  # records, not pulses
    saved = rocking.load(tmp_path / "c" / "ida.nc")
    (vertical,) = saved.config["suite"]["vertical"]["files"]
    assert vertical == {"path": str(v.resolve()), "sha256": rocking.model.records.file_sha256(v), "unit": "g"}
    assert saved.data["vertical_motion"].values.tolist() == ["v.AT2"]
    header, row = (tmp_path / "c" / "ida-motions.csv").read_text().splitlines()[:2]
    assert header.split(",")[:2] == ["motion", "vertical_motion"] and row.split(",")[:2] == ["h.AT2", "v.AT2"]
    python = _ida(tmp_path, [h], scales=rocking.Grid("scales", 0.5, 3.0, 3), vertical_motions=[v])
    assert np.array_equal(saved.data["theta_max"].values, python.data["theta_max"].values)
    record = json.loads((tmp_path / "c" / "ida.json").read_text())
    assert record["command"]["options"]["vertical_motions"] == [f"{v}:g"]
    capsys.readouterr()
    assert main(["ida", "--config", str(tmp_path / "c" / "ida.json"), "--out", str(tmp_path / "again")]) == 0
    assert f"ida: the configuration of {tmp_path / 'c' / 'ida.json'}, rerun exactly" in capsys.readouterr().out
    other = _at2(tmp_path / "other.AT2", np.zeros(301), dt=0.005)
    bad = [
        (["--vertical-motions", str(v), str(v)], "error: --vertical-motions must give one vertical record per record"),
        (["--vertical-motions", str(tmp_path / "none.AT2")], "error: --vertical-motions: "),
        (["--vertical-motions", str(other)], "error: --vertical-motions "),
    ]
    for extra, message in bad:
        assert main([*argv, *extra, "--out", str(tmp_path / "bad")]) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1, err
    assert main(["ida", "--stochastic", "2", "--vertical-motions", str(v), "--out", str(tmp_path / "bad")]) == 2
    assert "error: --vertical-motions: only with --motions FILES" in capsys.readouterr().err
