"""What a user sees of ``rocking simulate`` and of small messages (issue 38 items 4 and 7): one run gives one
answer whatever the outputs asked for, the command's damper defaults are the studies', and short texts read well."""

from __future__ import annotations

import json
import math
import re

import pytest

from rocking.cli.main import main
from rocking.model.params import Block, Damper
from rocking.study.config import Tuning

#: A pulse under which the reference block alone ends early at the early verdict (status bounded, 2 impacts) but
#: rocks on to rest (66 impacts): the case of issue 38 item 4.
PULSE = ["--beta", "1.5", "--Omega", "8"]


def _summary(capsys, argv: list[str]) -> list[str]:
    """The response lines ``rocking simulate ARGV`` prints."""
    assert main(["simulate", *argv]) == 0
    return [line for line in capsys.readouterr().out.splitlines() if line.startswith("  ")]


def test_the_summary_is_the_same_with_and_without_a_figure_or_a_history(capsys, tmp_path):
    argv = ["--gamma", "0.05", *PULSE, "--compare"]
    plain = _summary(capsys, argv)
    drawn = _summary(capsys, [*argv, "--plot", str(tmp_path / "r.png"), "--history", str(tmp_path / "h.csv")])
    assert plain == drawn
    assert len(plain) == 2 and all("(rest)" in line for line in plain)


def test_the_early_verdict_is_asked_for_and_explained_on_its_line(capsys):
    (line,) = _summary(capsys, ["--no-damper", *PULSE, "--early-verdict"])
    assert "(bounded: from then on the energy left can no longer change the verdict" in line
    (full,) = _summary(capsys, ["--no-damper", *PULSE])
    impacts = [int(re.search(r"(\d+) impact\(s\)", s).group(1)) for s in (line, full)]
    assert impacts[0] < impacts[1] and "(rest)" in full
    # theta_max/alpha, the same to rest (rule 4).
    assert line.split(",")[0] == full.split(",")[0]


def test_early_verdict_and_follow_to_rest_are_not_given_together(capsys):
    assert main(["simulate", *PULSE, "--early-verdict", "--follow-to-rest"]) == 2
    assert "--early-verdict" in capsys.readouterr().err


def test_a_damper_relative_to_the_block_takes_the_studies_defaults(capsys):
    import json

    assert main(["simulate", "--gamma", "0.05", *PULSE, "--json"]) == 0
    damper = json.loads(capsys.readouterr().out)["damper"]
    tuning = Tuning(gamma=0.05)
    expected = Damper.from_nondim(Block.reference(), gamma=0.05, omega_ratio=tuning.omega_ratio, zeta=tuning.zeta,
                                  h=tuning.h)  # fmt: skip
    assert damper == pytest.approx(expected.as_params())
    assert (tuning.omega_ratio, tuning.zeta, tuning.h) == (1.0, 0.05, 0.05)  # docs/model.md section 9's damper


def test_a_damper_tuned_by_its_period_keeps_it_and_the_other_defaults(capsys):
    import json

    assert main(["simulate", "--gamma", "0.05", "--T-m", "1.5", *PULSE, "--json"]) == 0
    damper = json.loads(capsys.readouterr().out)["damper"]
    expected = Damper.from_nondim(Block.reference(), gamma=0.05, T_m=1.5, zeta=Tuning().zeta, h=Tuning().h)
    assert damper == pytest.approx(expected.as_params())


def test_without_gamma_the_message_names_only_what_was_given(capsys):
    assert main(["simulate", "--zeta", "0.1", *PULSE]) == 2
    err = capsys.readouterr().err
    assert "needs --gamma too (got --zeta)" in err


def test_the_help_states_the_studies_defaults(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    tuning = Tuning()
    assert f"rocking.Tuning: omega_ratio {tuning.omega_ratio:g}, zeta {tuning.zeta:g}, h {tuning.h:g} m" in text


# --- item 7: small things users notice ---------------------------------------------------------------------------


def test_a_bumper_force_that_never_rose_prints_0(capsys):
    """Pads that never push leave the largest force at -0.0: printed 0, not -0."""
    (line,) = _summary(capsys, ["--gamma", "0.05", "--stops", "--beta", "0.5", "--Omega", "4"])
    assert "0 stop contact(s), bumper force max 0 N" in line
    assert main(["simulate", "--gamma", "0.05", "--stops", "--beta", "0.5", "--Omega", "4", "--json"]) == 0
    written = json.loads(capsys.readouterr().out)["responses"]["with damper"]["bumper_force_max"]
    assert written == 0.0 and math.copysign(1.0, written) == 1.0  # JSON too: 0.0, never -0.0


def test_the_history_messages_name_each_response(capsys, tmp_path):
    path = tmp_path / "h.csv"
    assert main(["simulate", "--gamma", "0.05", *PULSE, "--compare", "--history", str(path)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert f"history (with damper) written to {path}" in err
    assert f"history (block alone) written to {tmp_path / 'h-block_alone.csv'}" in err


def test_the_envelopes_take_a_study_or_say_what_to_pass(tmp_path):
    import rocking
    from rocking.model.params import ParameterError
    from rocking.study import overturning_map, spectrum

    block = Block.reference()
    grid = {"Omega": [4.0, 6.0], "beta": [2.0, 3.0], "workers": 1, "progress": False, "runs": tmp_path, "study": True}
    study = rocking.overturning_map(block, Tuning(), **grid)
    assert overturning_map.envelope(study).equals(overturning_map.envelope(study.data))
    assert not overturning_map.envelope(study)["overturned"].sel(part="bare").isnull().any()
    with pytest.raises(
        ParameterError, match=r"^data must be a spectrum Study or its data, an xarray.Dataset \(got a map"
    ):
        spectrum.envelope(study)
    with pytest.raises(ParameterError, match=r"data must be a map Study .*\(got dict\)"):
        overturning_map.envelope({"status": 1})


@pytest.mark.parametrize("row", ["0,01;0,5", "0,01,0,5", "0,01 0,5", "0,01\t-0,5"])
def test_a_decimal_comma_is_named_as_the_cause(tmp_path, row):
    from rocking.model.params import ParameterError
    from rocking.model.records import read_record

    path = tmp_path / "record.csv"
    path.write_text(f"time [s]; a [g]\n{row}\n")
    message = "line 2: expected 2 column(s), got 4: decimal commas are not read: use a point (0.01, not 0,01)"
    with pytest.raises(ParameterError, match=re.escape(message)):
        read_record(path)


@pytest.mark.parametrize("row", ["0.01,0.5,0.3", "1,2,3"])
def test_other_extra_columns_are_not_called_decimal_commas(tmp_path, row):
    from rocking.model.params import ParameterError
    from rocking.model.records import read_record

    path = tmp_path / "record.csv"
    path.write_text(f"time [s], a [g]\n{row}\n")
    with pytest.raises(ParameterError, match=r"expected 2 column\(s\), got 3$"):
        read_record(path)


def test_reprs_show_the_lengths_a_user_typed():
    """Stops.at_edges of a 0.6 m base: L = 0.3 - 0.02 is 0.27999999999999997 in binary, shown 0.28."""
    from rocking.model.params import Stops

    block = Block(H=2.2, B=0.6, M=350.0, e=0.02)
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, h=0.05)
    stops = Stops.at_edges(block, damper)
    assert stops.L == 0.6 / 2 - 0.02 != 0.28  # the value itself is unchanged
    assert repr(stops).startswith("Stops(L=0.28, k_b=")
    text = repr(Damper(damper.m, damper.k_m, damper.c, damper.h, stops=stops))
    assert text.startswith("Damper(m=17.5, k_m=") and "h=0.05, stops=Stops(L=0.28, " in text
    assert repr(block) == "Block(H=2.2, B=0.6, M=350.0, e=0.02, I_G=151.666666667, g=9.81)"


def test_the_response_table_names_the_coordinates():
    """Response._repr_html_ (Jupyter) says |x| with or without a damper, never the generated code's q[1]."""
    import rocking

    block = Block.reference()
    pulse = rocking.OneSinePulse.from_nondim(block, beta=1.5, Omega=8)
    damper = Damper.from_nondim(block, gamma=0.05, omega_ratio=1.0, h=0.05)
    for run in (rocking.simulate(block, None, pulse), rocking.simulate(block, damper, pulse)):
        html = run._repr_html_()
        assert "q[1]" not in html and "largest |x|" in html
    bounded = rocking.simulate(block, None, pulse)
    assert bounded.status == "bounded" and "|theta| and |x| below their maxima" in bounded._repr_html_()


def test_a_record_given_twice_in_two_formats_is_warned_of(tmp_path):
    """The same samples as PEER .AT2 and as CSV (both in g): two files, one motion; the warning names both."""
    from rocking.study.suite import DuplicateMotionWarning, Suite

    values = [0.0063010, 0.0063250, -0.0012345, -0.0234567, 0.5, -0.25, 1.0e-5, 0.0]
    at2 = tmp_path / "elc.AT2"
    header = ["PEER NGA STRONG MOTION DATABASE RECORD", "El Centro", "ACCELERATION TIME SERIES IN UNITS OF G"]
    at2.write_text("\n".join([*header, "NPTS=    8, DT=   .0100 SEC", *(f"{v:15.7E}" for v in values)]) + "\n")
    csv = tmp_path / "elc.csv"
    csv.write_text("time [s], a [g]\n" + "".join(f"{k * 0.01:.2f}, {v}\n" for k, v in enumerate(values)))
    other = tmp_path / "other.csv"
    other.write_text("time [s], a [g]\n" + "".join(f"{k * 0.01:.2f}, {2 * v}\n" for k, v in enumerate(values)))
    with pytest.warns(DuplicateMotionWarning, match=r"motions .*elc\.AT2 and .*elc\.csv hold the same samples"):
        Suite.from_files([at2, other, csv])
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(Suite.from_files([at2, other])) == 2


def test_the_site_models_options_state_their_units(capsys):
    """Each option of the stochastic site model in rocking fragility --help states the unit its SiteModel
    docstring gives (the one place the model's units are declared besides the help)."""
    from rocking.cli.study import SITE_HELP
    from rocking.model.stochastic import SiteModel

    with pytest.raises(SystemExit):
        main(["fragility", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    doc = " ".join(SiteModel.__doc__.split())
    for option, (meaning, unit) in SITE_HELP.items():
        entry = re.search(rf"--{option.replace('_', '-')} \S+ site model: ([^)]*\))", text)
        assert entry and entry.group(1).startswith(meaning.replace("%%", "%")), option
        described = re.search(rf"\b{option} : float(?:, optional)? (.*?)(?= \w+ : |$)", doc).group(1)
        if unit:
            assert f", {unit} (default " in entry.group(1) and re.search(rf", {re.escape(unit)}[,; ]", described)
        else:
            assert "ratio" in described  # zeta_f, the one without a unit


def test_a_list_of_numbers_in_a_message_is_short():
    from rocking.cli.options import numbers_text

    Omega = [5.2415714285714285 + 0.5 * k for k in range(9)]
    assert numbers_text(Omega) == "5.242, 5.742, 6.242, 6.742, 7.242, 7.742 and 3 more"
    assert numbers_text([1.0, 2.5]) == "1, 2.5"
