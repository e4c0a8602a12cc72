"""Maps and spectra with a vertical component (docs/model.md section 14): every cell is a single run of the same
pulse with the same :class:`rocking.Vertical`, ratio 0 is the study without, and the Dataset and the figures say so."""

import math

import numpy as np
import pytest
from matplotlib.container import ErrorbarContainer

import rocking
from rocking.cli.main import main
from rocking.plot.figures import vertical_spectra_figure
from rocking.study.config import Setting, Variant, flight_beta
from rocking.study.overturning_map import UndeterminedWarning
from rocking.study.spectrum import envelope, safe_windows
from rocking.study.vocabulary import ABOVE, BRACKETED, FLIGHT

BLOCK = rocking.Block.reference()
OMEGA, BETA = [2.0, 4.0, 8.0], [1.0, 2.5, 4.5]


def _map(tmp_path, **vertical):
    return rocking.overturning_map(
        BLOCK, {"gamma": 0.05}, Omega=OMEGA, beta=BETA, full=True, runs=tmp_path, workers=1, progress=False,
        study=True, **vertical,
    )  # fmt: skip


def test_each_cell_of_a_map_with_a_vertical_component_is_a_single_run_with_it(tmp_path):
    plain, study = _map(tmp_path), _map(tmp_path, vertical_ratio=0.8, vertical_phase=0.5)
    data = study.data
    assert not np.array_equal(plain.data["theta_max"].values, data["theta_max"].values)
    vertical = rocking.Vertical(0.8, 0.5)
    damper = rocking.Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    for Omega in OMEGA:
        for beta in BETA:
            for sign in data["sign"].values.tolist():
                pulse = rocking.OneSinePulse.from_nondim(BLOCK, beta=beta, Omega=Omega, sign=sign, vertical=vertical)
                for part, run in (("bare", None), ("damper", damper)):
                    r = rocking.simulate(BLOCK, run, pulse)
                    cell = data.sel(part=part, Omega=Omega, beta=beta, sign=sign)
                    # The map's batch runs in lanes: its maxima to issue 40's bound (tests/test_lanes.py).
                    assert cell["theta_max"].item() == pytest.approx(r.theta_max, rel=1e-7)
                    assert cell["impacts"].item() == r.impacts
    assert data.attrs["vertical_ratio"] == 0.8 and data.attrs["vertical_phase"] == 0.5
    assert "> 0 up" in data.attrs["vertical_component"] and plain.data.attrs["vertical_ratio"] == 0.0
    assert study.config["vertical"] == {"ratio": 0.8, "phase": 0.5} and "vertical" not in plain.config


def test_ratio_zero_is_the_study_without_a_vertical_component(tmp_path):
    plain, zero = _map(tmp_path / "a"), _map(tmp_path / "b", vertical_ratio=0.0)
    assert plain.config == zero.config
    for name in ("theta_max", "status", "impacts", "x_max"):
        assert np.array_equal(plain.data[name].values, zero.data[name].values, equal_nan=True)


#: A pendulum damper whose bob hangs at the omd's mass point (H + h), gamma = 0.05, tuned near p, zeta = 0.05: a model
#: without flight functions (tests/test_study_variants.py).
PENDULUM_L = 0.5
PENDULUM = {
    "m": 0.05 * BLOCK.M,
    "l": PENDULUM_L,
    "x_p": 0.0,
    "y_p": BLOCK.H + 0.05 + PENDULUM_L,
    "k_phi": max(0.05 * BLOCK.M * PENDULUM_L**2 * (BLOCK.p**2 - BLOCK.g / PENDULUM_L), 0.0),
    "c_phi": 2 * 0.05 * 0.05 * BLOCK.M * PENDULUM_L**2 * BLOCK.p,
}


def test_a_spectrum_reads_a_flight_model_past_beta_f_and_a_model_without_flight_up_to_it(tmp_path):
    beta = rocking.Grid("beta", 0.5, 8.0, 16)
    with pytest.warns(UndeterminedWarning, match="status flight"):
        study = rocking.minimum_overturning_spectrum(
            BLOCK, Variant("pendulum", PENDULUM), Omega=[10.0], beta=beta, vertical_ratio=1.0, runs=tmp_path,
            workers=1, progress=False, study=True, directions="positive",
        )  # fmt: skip
    # A one-sine in phase: g + ddy_g <= 0 once ratio beta tan(alpha) >= 1, beta >= 4 on the reference block.
    assert flight_beta(BLOCK, study.config) == pytest.approx(1.0 / BLOCK.tan_alpha, rel=1e-9)
    assert flight_beta(BLOCK, {}) == math.inf
    bare, damped = (study.data.sel(part=part, sign=1, Omega=10.0) for part in ("bare", "damper"))
    # The block alone flies (docs/model.md section 16): its column is read to its end, its runs past beta_f fly and
    # land to a verdict, and it overturns above beta_f = 4 after a flight.
    assert not (bare["scan_outcome"] == FLIGHT).any() and bare["flag"] == BRACKETED
    assert bare["beta_min"] > 4.0 and bare["beta_min_flew"] == 1 and bare["flown"] > 0
    # The pendulum has no flight functions: at Omega = 10 it survives up to beta = 4, past it every run of the scan
    # (4.5 .. 8) ends with status flight, without a verdict, and beta_min is not reached in the scan.
    assert damped["flag"] == ABOVE and damped["undetermined"] == np.count_nonzero(beta.values() > 4.0)
    # The lower bound is the last amplitude with a verdict, below the flights, which are no safe window.
    assert np.isnan(damped["beta_min"]) and damped["beta_min_lower_bound"] == 4.0  # censored
    assert (damped["scan_outcome"].sel(beta_scan=slice(4.5, None)) == FLIGHT).all()
    assert damped["flown"] == 0 and len(safe_windows(envelope(study.data), "damper")) == 0
    # Its figure draws that lower bound, a filled triangle at beta = 4, with its legend entry, and rings the block
    # alone's beta_min.
    fig = vertical_spectra_figure([study])
    bounds = [c for ax in fig.axes for c in ax.containers if isinstance(c, ErrorbarContainer)]
    assert bounds and all(c.lines[0].get_ydata().tolist() == [4.0] for c in bounds)
    labels = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert any(label.startswith("lower bound") and "beta_f" in label for label in labels)
    assert any(label.startswith("ringed") for label in labels)


@pytest.mark.parametrize(
    ("vertical", "message"),
    [
        ({"vertical_ratio": -0.5}, r"^vertical_ratio must be in \[0, 10\] \(got -0.5\)"),
        ({"vertical_ratio": math.inf}, r"^vertical_ratio must be finite \(got inf\)"),
        ({"vertical_ratio": 1.0, "vertical_phase": 7.0}, r"^vertical_phase must be in \[0, 2 pi\) = .* \(got 7.0\)"),
        ({"vertical_phase": 1.0}, r"^vertical_phase is the lead of the vertical component: give it with"),
    ],
)
def test_a_bad_vertical_component_is_refused_naming_it(vertical, message):
    with pytest.raises(rocking.ParameterError, match=message):
        Setting(BLOCK, **vertical)


def test_the_command_line_map_takes_the_vertical_component(tmp_path, capsys):
    argv = ["map", "--Omega", "4", "4", "1", "--beta", "2", "3", "2", "--full", "--workers", "1", "--no-progress"]
    assert main([*argv, "--vertical-ratio", "0.5", "--vertical-phase", "1", "--out", str(tmp_path)]) == 0
    saved = rocking.load(tmp_path / "map.nc")
    assert saved.config["vertical"] == {"ratio": 0.5, "phase": 1.0}
    assert saved.data.attrs["vertical_ratio"] == 0.5
    assert main([*argv, "--vertical-ratio", "-1", "--out", str(tmp_path / "bad")]) == 2
    assert "rocking map: error: --vertical-ratio must be in [0, 10]" in capsys.readouterr().err


def test_a_history_records_the_vertical_ground_acceleration_beside_the_horizontal(tmp_path):
    vertical = rocking.Vertical(0.6, 1.0)
    pulse = rocking.OneSinePulse.from_nondim(BLOCK, beta=1.5, Omega=3.0, sign=-1, vertical=vertical)
    ds = rocking.simulate(BLOCK, None, pulse, record=True).to_dataset()
    t = ds["t"].values
    on = t <= pulse.t_p
    # ddy_g = ratio a_g sin(omega_g t + phase) of the sine at psi = 0, unsigned by the pulse's direction.
    expected = vertical.ratio * pulse.a_g * np.sin(pulse.omega_g * t[on] + vertical.phase)
    assert np.allclose(ds["a_gy"].values[on], expected, rtol=0, atol=1e-12 * pulse.a_g)
    assert np.all(ds["a_gy"].values[~on] == 0.0) and np.allclose(ds["a_g"].values[on], pulse.acceleration(t[on]))
    assert ds["a_gy"].attrs["units"] == "m/s^2" and "> 0 up" in ds["a_gy"].attrs["long_name"]
    plain = rocking.simulate(BLOCK, None, rocking.OneSinePulse.from_nondim(BLOCK, beta=1.5, Omega=3.0), record=True)
    assert not plain.to_dataset()["a_gy"].values.any()
    rocking.sim.history.write(plain, tmp_path / "h.csv")
    assert "a_gy [m/s^2]" in (tmp_path / "h.csv").read_text().splitlines()[0]


def test_a_stochastic_suite_takes_a_vertical_component_of_its_own_noise():
    site = rocking.model.stochastic.SiteModel(arias=0.5, d595=4.0, t_mid=3.0, f_mid=4.0, f_slope=-0.1, zeta_f=0.2)
    plain, with_vertical = (
        rocking.study.suite.suite_of(stochastic=3, seed=7, site=site, **v) for v in ({}, {"vertical_ratio": 0.7})
    )
    assert "vertical" not in plain.record() and with_vertical.record()["vertical"]["ratio"] == 0.7
    for i in range(3):
        h, m = plain.motion(i), with_vertical.motion(i)
        assert np.array_equal(h.a, m.a) and m.a_v.shape == m.a.shape  # the horizontal motion is unchanged
        own = rocking.model.stochastic.synthesize(site, rocking.model.stochastic.vertical_rng(7, i))
        assert np.array_equal(m.a_v, 0.7 * own) and not np.allclose(m.a_v, 0.7 * m.a)
    higher = rocking.study.suite.suite_of(stochastic=1, site=site, vertical_ratio=1.0, vertical_site={"f_mid": 8.0})
    assert higher.vertical_site.f_mid == 8.0 and higher.vertical_site.duration == site.duration
    with pytest.raises(rocking.ParameterError, match=r"^vertical_ratio must be in \[0, 10\] \(got -1.0\)"):
        rocking.study.suite.suite_of(stochastic=2, vertical_ratio=-1.0)
    with pytest.raises(rocking.ParameterError, match=r"^vertical_site must have the horizontal site's dt"):
        rocking.study.suite.suite_of(stochastic=2, site=site, vertical_ratio=0.5, vertical_site={"dt": 0.01})
    with pytest.raises(rocking.ParameterError, match=r"^pulses makes its own suite: no vertical_ratio$"):
        rocking.study.suite.suite_of(pulses="sine", periods=[1.0], vertical_ratio=0.5)


def test_the_runs_of_a_sampled_motion_carry_its_vertical_component():
    t = np.arange(0.0, 3.0, 0.01)
    motion = rocking.SampledMotion(3.0 * np.sin(2 * np.pi * t), dt=0.01, a_v=4.0 * np.sin(3 * np.pi * t + 0.3))
    cases = rocking.sim.cases.sampled_cases(BLOCK, motion, [0.5, 2.0, 3.0], sign=-1, gamma=0.05)
    result = rocking.sim.cases.run_cases(cases, "c")
    damper = rocking.Damper.from_nondim(BLOCK, gamma=0.05, omega_ratio=1.0, zeta=0.05, h=0.05)
    for k, scale in enumerate((0.5, 2.0, 3.0)):
        one = rocking.simulate(
            BLOCK,
            damper,
            rocking.SampledMotion(motion.a, 0.01, a_v=motion.a_v, scale=scale, sign=-1),
        )
        status = rocking.sim.boundary.STATUS[result["status"][k]]
        # The batch runs in lanes: its maxima to issue 40's bound (tests/test_lanes.py), counts identical.
        assert result["theta_max"][k] == pytest.approx(one.theta_max, rel=1e-7) and status == one.status
        assert result["flights"][k] == one.flights and result["jump_max"][k] == pytest.approx(one.jump_max, rel=1e-7)
    # 0.5 x 4 m/s^2 < g: on the floor; 3 x 4 m/s^2 > g: the omd flies (docs/model.md section 16), no status flight.
    assert result["flights"][0] == 0 and result["flights"][2] > 0
    assert rocking.sim.boundary.STATUS[result["status"][2]] != "flight"


def test_the_command_line_suite_takes_a_vertical_ratio(tmp_path, capsys):
    argv = [
        "fragility",
        "--stochastic",
        "2",
        "--duration",
        "6",
        "--t-mid",
        "2",
        "--d595",
        "3",
        "--levels",
        "1",
        "3",
        "2",
    ]
    argv += ["--check", "none", "--workers", "1", "--no-progress"]
    assert main([*argv, "--vertical-ratio", "0.5", "--out", str(tmp_path)]) == 0
    assert rocking.load(tmp_path / "fragility.nc").config["suite"]["vertical"]["ratio"] == 0.5
    assert main([*argv, "--vertical-ratio", "20", "--out", str(tmp_path / "bad")]) == 2
    assert "error: --vertical-ratio must be in [0, 10]" in capsys.readouterr().err


def test_the_map_lines_count_the_cells_that_flew_and_those_without_a_verdict_per_part(tmp_path, capsys):
    # beta_f = 4 at ratio 1: the cells at beta 5 and 6 leave the floor unless they overturn first. The block alone
    # flies and lands (docs/model.md section 16); the pendulum has no flight functions: no verdict there.
    pendulum = [x for name, value in PENDULUM.items() for x in ("--param", f"{name}={value!r}")]
    argv = ["map", "--Omega", "10", "10", "1", "--beta", "2", "6", "3", "--full", "--workers", "1", "--no-progress"]
    argv += ["--model", "pendulum", *pendulum, "--directions", "positive"]
    assert main([*argv, "--vertical-ratio", "1", "--out", str(tmp_path)]) == 0
    s = rocking.load(tmp_path / "map.nc").summary
    out = capsys.readouterr().out
    assert s["bare_undetermined"] == 0 and 0 < s["damper_undetermined"] <= s["cells"]
    words = f"0 cells alone and {s['damper_undetermined']} with the damper without a verdict"
    assert words in out
    flew = s["bare_flies_and_lands"] + s["bare_flies_and_overturns"]
    assert flew > 0 and s["damper_flies_and_lands"] + s["damper_flies_and_overturns"] == 0
    assert f"map: the base flew in {flew} cells alone ({s['bare_flies_and_overturns']} then overturned)" in out
