"""The experiments' figures (`carl_spec.experiments.plot_report`, `write_report(figure=True)`),
drawn from the reports in the docs: they need matplotlib only, not the training venv."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import pytest

from carl_spec.experiments import plot_report, write_report
from carl_spec.experiments.__main__ import main

DATA = Path(__file__).resolve().parents[2] / "docs" / "assets" / "data" / "experiments"
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("name", sorted(p.stem for p in DATA.glob("q*.json")))
def test_each_report_in_the_docs_draws_its_figure(name: str, tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    report = json.loads((DATA / f"{name}.json").read_text())
    paths = write_report(report, tmp_path, figure=True)
    assert [p.name for p in paths] == [f"{name}.json", f"{name}.md", f"{name}.png"]
    assert paths[2].read_bytes()[:8] == PNG
    assert f"![{name}]({name}.png)" in paths[1].read_text()
    fig = plot_report(report)
    # Every seed is drawn: the dots of a panel count the trials' numbers.
    dots = sum(len(line.get_xdata()) for ax in fig.axes for line in ax.lines if line.get_linestyle() == "None")
    per_trial = {"q1": 1, "q2": 1, "q3": 2 * 6}[name]
    assert dots == per_trial * len(report["results"])
    plt.close(fig)


def test_without_matplotlib_the_figure_is_refused_before_training(
    tmp_path: Path, monkeypatch: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    report = json.loads((DATA / "q3.json").read_text())
    with pytest.raises(ImportError, match=r"needs matplotlib.*pip install 'carl-spec\[plot\]'"):
        write_report(report, tmp_path, figure=True)
    assert not list(tmp_path.iterdir())  # nothing half-written
    # The command line checks first, so hours of training are not lost at the end.
    assert main(["q3", "--budget", "0.001", "--seeds", "1", "--out", str(tmp_path / "out"), "--figure"]) == 2
    assert "--figure needs matplotlib" in capsys.readouterr().err
    assert not (tmp_path / "out" / "trials").exists()
