"""The report's figure (matplotlib, the optional extra `carl-spec[plot]`, imported only when drawn)."""

from __future__ import annotations

import os
from typing import Any

from .._matplotlib import pyplot
from ._stats import METRICS

_LABELS = {"mean": "mean", "median": "median", "iqm": "IQM"}


def plot_report(data: dict[str, Any], path: str | os.PathLike[str] | None) -> Any:
    plt = pyplot("Report.plot")
    groups = data["groups"]
    keys = list(groups)
    rows = [r for k in keys if "/" not in k for r in groups[k]["per_instance"]]
    feats = sorted({f for r in rows for f in r["context"]})
    varied = [f for f in feats if len({r["context"].get(f) for r in rows}) > 1]
    panels = 3 if len(varied) == 1 else 2
    fig, axes = plt.subplots(1, panels, figsize=(5.0 * panels, 3.8), constrained_layout=True)
    colors = {k: f"C{i}" for i, k in enumerate(keys)}

    # Aggregates: one row per (metric, group), the estimate and its interval.
    ax = axes[0]
    y = 0.0
    ticks: list[float] = []
    labels: list[str] = []
    for m in METRICS:
        for k in keys:
            a = groups[k]["aggregates"][m]
            ax.plot(a["ci"], [y, y], color=colors[k], linewidth=5, alpha=0.45, solid_capstyle="butt")
            ax.plot([a["estimate"]], [y], "|", color=colors[k], markersize=14)
            ticks.append(y)
            labels.append(f"{_LABELS[m]}, {groups[k]['title']}")
            y -= 1
        y -= 0.5
    ax.set_yticks(ticks, labels, fontsize=8)
    ax.set_xlabel("return")
    pct = f"{100 * data['statistics']['confidence']:g} %"
    ax.set_title(f"aggregates ({pct} intervals)")

    # Performance profiles.
    ax = axes[1]
    tau = data["tau"]
    for k in keys:
        p = groups[k]["profile"]
        ax.plot(tau, p["fraction"], color=colors[k], label=groups[k]["title"])
        ax.fill_between(tau, p["ci_low"], p["ci_high"], color=colors[k], alpha=0.2, linewidth=0)
    ax.set_xlabel(r"return threshold $\tau$")
    ax.set_ylabel(r"fraction of runs x instances > $\tau$")
    ax.set_ylim(-0.02, 1.02)
    ax.legend(fontsize=8)
    ax.set_title("performance profile")

    # Each instance's mean return (and interval over runs) against the one varied feature.
    if panels == 3:
        ax = axes[2]
        f = varied[0]
        for k in keys:
            if "/" in k:
                continue
            pts = [(r["context"][f], r["mean"], r["ci"], r["name"]) for r in groups[k]["per_instance"] if f in r["context"]]
            pts.sort(key=lambda t: t[0])
            xs = [t[0] for t in pts]
            ys = [t[1] for t in pts]
            err = [[t[1] - t[2][0] for t in pts], [t[2][1] - t[1] for t in pts]]
            ax.errorbar(xs, ys, yerr=err, fmt="o", markersize=3, color=colors[k], label=k, alpha=0.8)
            for x_, y_, _, name in pts:
                if name and len(pts) <= 12:
                    ax.annotate(name, (x_, y_), fontsize=7, xytext=(3, 3), textcoords="offset points")
        ax.set_xlabel(f)
        ax.set_ylabel("mean return per instance")
        ax.legend(fontsize=8)
        ax.set_title(f"return against {f}")
    fig.suptitle(f"{data['env']} ({data.get('gym_id')})", fontsize=10)
    if path is not None:
        fig.savefig(os.fspath(path), dpi=120)
    return fig
