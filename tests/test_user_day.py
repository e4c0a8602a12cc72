"""What a user sees of ``rocking simulate`` and of small messages (issue 38 items 4 and 7): one run gives one
answer whatever the outputs asked for, the command's damper defaults are the studies', and short texts read well."""

from __future__ import annotations

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
