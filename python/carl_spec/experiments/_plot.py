"""An experiment report's figure (matplotlib, the optional extra `carl-spec[plot]`):

* `q1`: the final return against σ_rel, one line per feature, and the learning curves at σ_rel 0.5;
* `q2`: the final return of each feature's agents, context hidden and visible, every seed a dot;
* `q3`: game over (crashed or out of view) and the mean return on each planet, ordered by |g|,
  hidden and visible, every seed a dot, the training planets shaded.

Bars and lines are means over the training seeds; the dots show their spread.
"""

from __future__ import annotations

import os
import statistics
from typing import Any

from .._matplotlib import pyplot
from ._run import _final, _finals_by_feature_mode, _planets_by_mode

_MODES = ("hidden", "visible")


def plot_report(report: dict[str, Any], path: str | os.PathLike[str] | None = None) -> Any:
    """The figure of `report` (as `run_experiment` returns it); saved to `path` when given."""
    plt = pyplot("The experiment's figure")
    draw = {"q1": _q1, "q2": _q2, "q3": _q3}[report["experiment"]]
    fig = draw(plt, report)
    fig.suptitle(
        f"{report['experiment']}: {report['steps_per_trial']:,} steps per trial, "
        f"{report['seeds']} seed(s) (budget {report['budget']:g})",
        fontsize=10,
    )
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def _q1(plt: Any, report: dict[str, Any]) -> Any:
    fig, (a, b) = plt.subplots(1, 2, figsize=(10.5, 3.9), constrained_layout=True)
    by: dict[str, dict[float, list[dict[str, Any]]]] = {}
    for r in report["results"]:
        t = r["trial"]
        by.setdefault(t["feature"], {}).setdefault(t["sigma"], []).append(r)
    for i, (feature, sig) in enumerate(by.items()):
        sigmas = sorted(sig)
        finals = [[_final(r) for r in sig[s]] for s in sigmas]
        a.plot(sigmas, [statistics.fmean(f) for f in finals], "o-", color=f"C{i}", label=feature)
        for s, f in zip(sigmas, finals):
            a.plot([s] * len(f), f, ".", color=f"C{i}", alpha=0.4)
        widest = sig[sigmas[-1]]
        steps = [p["steps"] for p in widest[0]["curve"]]
        curves = [[p["mean_return"] for p in r["curve"]] for r in widest]
        b.plot(steps, [statistics.fmean(c) for c in zip(*curves)], "o-", color=f"C{i}", label=feature)
    a.set_xlabel("σ_rel of the training distribution")
    a.set_ylabel("final mean return (training instances)")
    a.set_title("final return against the distribution's width")
    a.legend(fontsize=8)
    b.set_xlabel("training steps")
    b.set_ylabel("mean return (training instances)")
    b.set_title("learning curves at the widest σ_rel")
    return fig


def _q2(plt: Any, report: dict[str, Any]) -> Any:
    fig, ax = plt.subplots(figsize=(7.5, 3.9), constrained_layout=True)
    by = _finals_by_feature_mode(report["results"])
    width = 0.38
    for k, mode in enumerate(_MODES):
        for i, by_mode in enumerate(by.values()):
            xs = by_mode.get(mode, [])
            if not xs:
                continue
            x = i + (k - 0.5) * width
            ax.bar(x, statistics.fmean(xs), width, color=f"C{k}", alpha=0.55, label=mode if i == 0 else None)
            ax.plot([x] * len(xs), xs, ".", color="black", alpha=0.6)
    ax.set_xticks(range(len(by)), list(by))
    ax.set_xlabel("the varied feature (σ_rel 0.5)")
    ax.set_ylabel("final mean return (training instances)")
    ax.set_title("context hidden vs visible")
    ax.legend(fontsize=8)
    return fig


def _q3(plt: Any, report: dict[str, Any]) -> Any:
    s = report["summary"]
    gravity, split = s["gravity"], s["split"]
    names = sorted(gravity, key=lambda n: abs(gravity[n]))
    per = _planets_by_mode(report["results"])
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.9), constrained_layout=True)
    xs = range(len(names))
    labels = [f"{n}\n{gravity[n]:.2f}" for n in names]
    for ax, key, ylabel in (
        (axes[0], "crash_rate", "game over (crashed or out of view)"),
        (axes[1], "mean_return", "mean return (penalty −10000)"),
    ):
        for i, n in enumerate(names):
            if split[n] == "in_distribution":
                ax.axvspan(i - 0.5, i + 0.5, color="0.9", zorder=0)
        for k, mode in enumerate(m for m in _MODES if m in per):
            vals = [per[mode][n][key] for n in names]
            ax.plot(xs, [statistics.fmean(v) for v in vals], "o-", color=f"C{k}", label=f"gravity {mode}")
            for i, v in enumerate(vals):
                ax.plot([i] * len(v), v, ".", color=f"C{k}", alpha=0.4)
        ax.set_xticks(list(xs), labels, fontsize=8)
        ax.set_xlabel("planet, gravity (m/s²); shaded: inside the training distribution")
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=8)
    axes[0].set_ylim(-0.03, 1.03)
    axes[0].set_title("game over per planet")
    axes[1].set_title("return per planet")
    return fig
