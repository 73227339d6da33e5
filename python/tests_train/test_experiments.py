"""The paper's experiments (`carl_spec.experiments`) at a smoke budget: every experiment runs end
to end (sequentially and on a loopback Ray), writes its report, and states each of the paper's
findings with the numbers deciding it; bad arguments are refused."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path
from typing import Any

import pytest

from carl_spec.experiments import _run, run_experiment, trials, write_report
from carl_spec.experiments.__main__ import main


def check_report(report: dict[str, Any], tmp_path: Path) -> None:
    findings = report["summary"]["findings"]
    assert findings and all(isinstance(f["holds"], bool) and f["numbers"] for f in findings)
    j, m = write_report(report, tmp_path)
    assert json.loads(j.read_text())["experiment"] == report["experiment"]
    assert "| finding (the paper's) | holds here | numbers |" in m.read_text()


def test_q1_sequential(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Trials write no SB3 logs: without SB3_LOGDIR (Ray's workers do not see the tier's), SB3 would
    # make a `SB3-<date>` folder in the system temp for every trial.
    monkeypatch.delenv("SB3_LOGDIR", raising=False)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    report = run_experiment("q1", budget=0.0001, seeds=1, features=["g"], evaluations=1)
    assert not list(tmp_path.glob("SB3-*"))
    assert report["trials"] == 3 and report["steps_per_trial"] == 300  # the fewest a trial trains
    assert set(report["summary"]["final_return"]["g"]) == {"0_1", "0_25", "0_5"}
    check_report(report, tmp_path)
    # q1's figure (q2's and q3's are drawn from the docs' reports in python/tests).
    png = write_report(report, tmp_path, figure=True)[2]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.xdist_group("ray")  # one loopback Ray per worker: keep its tests together
def test_q2_on_loopback_ray(loopback_ray: Any, tmp_path: Path) -> None:
    report = run_experiment("q2", budget=0.0003, seeds=1, features=["dt"], evaluations=1, ray=True)
    assert set(report["summary"]["final_return"]["dt"]) == {"hidden", "visible"}
    check_report(report, tmp_path)


def test_q3_planets_and_crashes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    report = run_experiment("q3", budget=0.001, seeds=1, test_episodes=2, checkpoint=tmp_path / "trials")
    planets = report["summary"]["planets"]["hidden"]
    assert set(planets) == {"Pluto", "Moon", "Mars", "Earth", "Neptune", "Jupiter"}
    for p in planets.values():
        assert 0.0 <= p["crash_rate"]["mean"] <= 1.0
    claims = [f["claim"] for f in report["summary"]["findings"]]
    assert any("Pluto" in c for c in claims) and any("crashes grow with gravity" in c for c in claims)
    check_report(report, tmp_path)

    # Every finished trial was saved: the same run again trains nothing and reports the same.
    assert sorted(f.name for f in (tmp_path / "trials").iterdir()) == [
        "q3-seed0-steps1000-hidden-test2.json",
        "q3-seed0-steps1000-visible-test2.json",
    ]

    def no_training(trial: Any) -> Any:
        raise AssertionError(f"trained {trial} again")

    monkeypatch.setattr(_run, "run_trial", no_training)
    again = run_experiment("q3", budget=0.001, seeds=1, test_episodes=2, checkpoint=tmp_path / "trials")
    assert again["results"] == report["results"] and again["summary"] == report["summary"]
    # Another budget is other trials: nothing of the folder is taken for them.
    with pytest.raises(AssertionError, match="trained"):
        run_experiment("q3", budget=0.0011, seeds=1, test_episodes=2, checkpoint=tmp_path / "trials")


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(experiment="q4", budget=0.1), "no experiment"),
        (dict(experiment="q1", budget=0), "budget"),
        (dict(experiment="q1", budget=float("nan")), "budget"),
        (dict(experiment="q1", budget=0.1, seeds=0), "seeds"),
        (dict(experiment="q1", budget=0.1, features=["gravity"]), "features"),
    ],
)
def test_bad_arguments_are_refused(kwargs: dict[str, Any], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        trials(**kwargs)


def test_the_command_line_exits_2_on_bad_input(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["q1", "--budget", "-1", "--out", str(tmp_path)]) == 2
    assert "budget" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
    a_file = tmp_path / "results"
    a_file.write_text("mine")
    assert main(["q3", "--budget", "0.001", "--out", str(a_file)]) == 2
    assert "not a directory" in capsys.readouterr().err
    assert a_file.read_text() == "mine"
