"""Studies past beta_f (issue 39, docs/model.md section 16): the landings' restitution e_n reaches the user, a
response that flew is a class of its own (it flew and landed, or flew and overturned), and a vertical study keeps
the flight results."""

import math

import pytest

import rocking
from rocking.cli.main import main
from rocking.study.config import Setting, config_hash

BLOCK = rocking.Block.reference()


def test_a_setting_passes_a_floor_whose_landings_bounce_even_where_it_never_slides():
    plastic, bouncing = Setting(BLOCK), Setting(BLOCK, floor=rocking.Floor(e_n=0.4))
    assert plastic.floor_args() == {} and "floor" not in plastic.record()
    assert bouncing.floor_args() == {"floor": rocking.Floor(math.inf, math.inf, 0.4)}
    # JSON has no inf: the floor that never slides is said by leaving mu_s, mu_k out, a plastic one by leaving e_n out.
    assert bouncing.record()["floor"] == {"e_n": 0.4}
    assert Setting(BLOCK, floor=rocking.Floor(0.5, 0.4)).record()["floor"] == {"mu_s": 0.5, "mu_k": 0.4}
    assert Setting(BLOCK, floor=rocking.Floor(0.5, 0.4, 1.0)).record()["floor"] == {
        "mu_s": 0.5,
        "mu_k": 0.4,
        "e_n": 1.0,
    }
    assert config_hash(plastic.record()) != config_hash(bouncing.record())


def test_the_command_line_takes_the_landings_restitution_and_a_saved_study_keeps_it(tmp_path, capsys):
    argv = ["map", "--Omega", "4", "4", "1", "--beta", "2", "3", "2", "--full", "--workers", "1", "--no-progress"]
    assert main([*argv, "--vertical-ratio", "0.5", "--e-n", "0.5", "--out", str(tmp_path)]) == 0
    saved = rocking.load(tmp_path / "map.nc")
    assert saved.config["floor"] == {"e_n": 0.5}
    assert saved.data.attrs["e_n"] == 0.5 and math.isinf(saved.data.attrs["mu_s"])
    assert main([*argv, "--e-n", "1.5", "--out", str(tmp_path / "bad")]) == 2
    assert "rocking map: error: --e-n must be in [0, 1] (got 1.5)" in capsys.readouterr().err


@pytest.mark.parametrize("floor", [{"e_n": 2.0}, {"mu_s": 0.5}, {}, {"e_n": 0.0}])
def test_a_saved_floor_is_read_back_only_as_a_study_records_it(floor):
    from rocking.study.storage import _setting

    config = {**Setting(BLOCK).record(), "floor": floor}
    with pytest.raises(rocking.ParameterError, match=r"^(e_n must be in \[0, 1\]|floor: )"):
        _setting(config)
