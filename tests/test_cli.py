"""The command line: simulate (summary, JSON, figure), verify, and clear errors."""

from __future__ import annotations

import json

import pytest

from rocking.cli.main import main


def test_simulate_json_with_and_without_damper(capsys):
    code = main(
        ["simulate", "--gamma", "0.05", "--omega-ratio", "1", "--beta", "2.5", "--Omega", "3", "--compare", "--json"]
    )
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out["responses"]) == {"with damper", "block alone"}
    for r in out["responses"].values():
        assert r["status"] in ("overturned", "rest", "t_max", "max_events")
        assert r["theta_max"] > 0 and r["uplifts"] >= 1
    assert out["pulse"]["beta"] == pytest.approx(2.5)
    assert out["responses"]["block alone"]["x_max"] == 0.0
    assert out["responses"]["with damper"]["x_max"] > 0.0


def test_simulate_summary_and_plot(tmp_path, capsys):
    fig = tmp_path / "response.png"
    code = main(
        [
            "simulate",
            "--H",
            "2",
            "--B",
            "0.5",
            "--gamma",
            "0.05",
            "--T_m",
            "2",
            "--beta",
            "3",
            "--Omega",
            "2",
            "--compare",
            "--plot",
            str(fig),
        ]
    )
    assert code == 0
    text = capsys.readouterr().out
    assert "with damper:" in text and "block alone:" in text
    assert fig.stat().st_size > 10_000


@pytest.mark.parametrize(
    "argv, message",
    [
        (["simulate", "--beta", "2"], "a pulse is needed"),
        (["simulate", "--H", "-2", "--B", "0.5", "--beta", "2", "--Omega", "2"], "H must be"),
        (["simulate", "--beta", "2", "--Omega", "0"], "Omega"),
        (["simulate", "--gamma", "0.05", "--beta", "2", "--Omega", "2"], "T_m"),
        (["simulate", "--beta", "2", "--Omega", "2", "--rtol", "0.5"], "rtol must be in"),
    ],
)
def test_simulate_bad_input_names_the_parameter(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "rocking: error:" in err and message in err


def test_verify_command_reports_agreement(capsys):
    assert main(["verify", "--cases", "200"]) == 0
    out = capsys.readouterr().out
    assert "model omd" in out and "model block" in out and "22 passed, 0 failed" in out
