"""`carl_spec.report`: the generalization report over training seeds (train vs test sets)."""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ._result import EvaluationResult
from ._stats import AGGREGATES, METRICS, bootstrap, percentile_interval, score_distribution

#: The `format` of a report's JSON document.
FORMAT = "carl-spec-report/1"

METHOD = (
    "Agarwal et al. 2021 (Deep RL at the Edge of the Statistical Precipice): score = a run's mean "
    "return on an instance; mean and median over instances of the mean over runs, IQM = 25 % trimmed "
    "mean of all run x instance scores, run-score distribution for the performance profile; intervals "
    "by stratified bootstrap over runs within each instance, percentile method; the gap's interval "
    "from independent resamples of both groups"
)

_SPLIT_TITLES = {"in_distribution": "in distribution", "out_of_distribution": "out of distribution"}


def _runs(what: str, value: EvaluationResult | Sequence[EvaluationResult] | None) -> list[EvaluationResult]:
    if value is None:
        return []
    runs = [value] if isinstance(value, EvaluationResult) else list(value)
    for k, r in enumerate(runs):
        if not isinstance(r, EvaluationResult):
            raise TypeError(
                f"report: {what}[{k}] is a {type(r).__name__}, not an EvaluationResult (what carl_spec.evaluate returns)"
            )
    if not runs and value is not None:
        raise ValueError(f"report: {what} is an empty list; give one evaluation per training seed")
    return runs


def _same(what: str, runs: list[EvaluationResult], key: str, label: str) -> None:
    first = runs[0].provenance.get(key)
    for k, r in enumerate(runs[1:], 1):
        other = r.provenance.get(key)
        if other != first:
            raise ValueError(
                f"report: {what} mixes {label}: run 0 has {_show(first)}, run {k} has {_show(other)}; "
                "a report compares evaluations of one protocol"
            )


def _show(x: Any) -> str:
    return json.dumps(x, sort_keys=True) if isinstance(x, (dict, list)) else repr(x)


def _check_group(what: str, runs: list[EvaluationResult]) -> None:
    _same(what, runs, "env", "environments")
    _same(what, runs, "env_version", "environment versions")
    _same(what, runs, "carl_spec_version", "carl-spec versions")
    _same(what, runs, "source", "sets (or distributions, contexts)")
    _same(what, runs, "options", "environment options")
    _same(what, runs, "obs_context", "visible context features (obs_context)")
    _same(what, runs, "context_noise", "context noise")
    ids = [(i.id, i.name, i.split) for i in runs[0].instances]
    contexts = [i.context for i in runs[0].instances]
    for k, r in enumerate(runs[1:], 1):
        if [(i.id, i.name, i.split) for i in r.instances] != ids:
            raise ValueError(f"report: {what} run {k} evaluated other instances than run 0")
        if [i.context for i in r.instances] != contexts:
            raise ValueError(
                f"report: {what} run {k} drew other contexts than run 0 (evaluation seeds "
                f"{r.provenance.get('seed')!r} and {runs[0].provenance.get('seed')!r}); a report compares runs on the "
                "same instances: evaluate every run of a distribution with the same seed"
            )
    labels = [r.provenance.get("run") for r in runs]
    seen: dict[Any, int] = {}
    for k, lab in enumerate(labels):
        if lab is not None and lab in seen:
            raise ValueError(f"report: {what} holds run {lab!r} twice (runs {seen[lab]} and {k}); one evaluation per run")
        seen[lab] = k


@dataclass(frozen=True)
class _Group:
    key: str  # "train", "test", "test/out_of_distribution", ...
    title: str
    runs: list[EvaluationResult]
    columns: list[int]  # instance positions in the runs' instance lists

    def scores(self) -> np.ndarray:
        """(runs, instances) mean returns."""
        return np.stack([r.scores[self.columns] for r in self.runs])


def report(
    train: EvaluationResult | Sequence[EvaluationResult] | None = None,
    test: EvaluationResult | Sequence[EvaluationResult] | None = None,
    *,
    reps: int = 2000,
    confidence: float = 0.95,
    seed: int = 0,
    tau: Sequence[float] | np.ndarray | None = None,
) -> Report:
    """The generalization report: per-instance tables, aggregates with intervals, the gap.

    `train` and `test` are `carl_spec.evaluate` results, one per training seed (run), each list
    evaluated with one protocol (same environment and version, carl-spec version, set, options,
    visible features; anything else is refused, naming what differs). Both sides must be of the
    same environment and version. For each side, and for each `split` label of a set that defines
    them (in / out of distribution): mean, median and interquartile mean (IQM) of the runs'
    per-instance mean returns with `confidence` intervals from `reps` stratified bootstrap
    resamples over runs (Agarwal et al. 2021; `seed` seeds the resampling); the generalization
    gap train - test with its interval; the performance profile (fraction of run x instance scores
    above each `tau`, default 51 values over the observed range). `Report.to_json()`,
    `.to_markdown()`, `.save(dir)` and `.plot()` write it out."""
    tr = _runs("train", train)
    te = _runs("test", test)
    if not tr and not te:
        raise ValueError("report: give train= and/or test= (carl_spec.evaluate results, one per training seed)")
    if isinstance(reps, bool) or not isinstance(reps, (int, np.integer)) or reps < 1:
        raise ValueError(f"report: reps must be a positive integer, got {reps!r}")
    if not 0.0 < float(confidence) < 1.0:
        raise ValueError(f"report: confidence must be in (0, 1), got {confidence!r}")
    for what, runs in (("train", tr), ("test", te)):
        if runs:
            _check_group(what, runs)
    if tr and te:
        a, b = tr[0].provenance, te[0].provenance
        for key, label in (("env", "environments"), ("env_version", "environment versions"),
                           ("carl_spec_version", "carl-spec versions"), ("options", "environment options")):
            if a.get(key) != b.get(key):
                raise ValueError(f"report: train and test differ in {label}: {_show(a.get(key))} vs {_show(b.get(key))}")

    groups: list[_Group] = []
    for key, runs in (("train", tr), ("test", te)):
        if not runs:
            continue
        n = len(runs[0].instances)
        groups.append(_Group(key, key, runs, list(range(n))))
        splits = [i.split for i in runs[0].instances]
        order = {lab: k for k, lab in enumerate(_SPLIT_TITLES)}
        labels = sorted((s for s in dict.fromkeys(splits) if s is not None), key=lambda s: (order.get(s, len(order)), s))
        if labels and len(set(splits)) > 1:
            for lab in labels:
                cols = [k for k, s in enumerate(splits) if s == lab]
                groups.append(_Group(f"{key}/{lab}", f"{key}, {_SPLIT_TITLES.get(lab, lab)}", runs, cols))

    all_scores = np.concatenate([g.scores().ravel() for g in groups])
    if tau is None:
        lo, hi = float(all_scores.min()), float(all_scores.max())
        tau_grid = np.linspace(lo, hi, 51) if hi > lo else np.array([lo])
    else:
        tau_grid = np.asarray(tau, dtype=np.float64).ravel()
        if tau_grid.size == 0 or not np.isfinite(tau_grid).all():
            raise ValueError("report: tau must be a non-empty list of finite thresholds")

    boots: dict[str, dict[str, np.ndarray]] = {}
    out_groups: dict[str, Any] = {}
    for gi, g in enumerate(groups):
        x = g.scores()
        rng = np.random.default_rng([int(seed), gi])
        b = bootstrap(x, reps=int(reps), rng=rng, tau=tau_grid)
        boots[g.key] = b
        agg = {}
        for m in METRICS:
            lo_, hi_ = percentile_interval(b[m], confidence)
            agg[m] = {"estimate": AGGREGATES[m](x), "ci": [float(lo_), float(hi_)]}
        plo, phi = percentile_interval(b["profile"], confidence)
        out_groups[g.key] = {
            "title": g.title,
            "source": g.runs[0].source_name,
            "runs": len(g.runs),
            "instances": len(g.columns),
            "aggregates": agg,
            "profile": {
                "fraction": score_distribution(x, tau_grid).tolist(),
                "ci_low": np.asarray(plo).tolist(),
                "ci_high": np.asarray(phi).tolist(),
            },
            "per_instance": _per_instance(g, x, confidence, int(reps), np.random.default_rng([int(seed), gi, 1])),
        }
    gaps: dict[str, Any] = {}
    if tr and te:
        for g in groups:
            if not g.key.startswith("test"):
                continue
            gap = {}
            for m in METRICS:
                diff = boots["train"][m] - boots[g.key][m]
                lo_, hi_ = percentile_interval(diff, confidence)
                est = out_groups["train"]["aggregates"][m]["estimate"] - out_groups[g.key]["aggregates"][m]["estimate"]
                gap[m] = {"estimate": est, "ci": [float(lo_), float(hi_)]}
            gaps[g.key] = gap

    def side(runs: list[EvaluationResult]) -> dict[str, Any] | None:
        if not runs:
            return None
        p = runs[0].provenance
        return {
            "source": p["source"],
            "runs": [r.provenance.get("run") for r in runs],
            "evaluation_seeds": [r.provenance.get("seed") for r in runs],
            "episodes": p.get("episodes"),
            "obs_context": p.get("obs_context"),
            "policy": p.get("policy"),
        }

    first = (tr or te)[0].provenance
    doc = {
        "format": FORMAT,
        "env": first["env"],
        "env_version": first["env_version"],
        "gym_id": first.get("gym_id"),
        "carl_spec_version": first["carl_spec_version"],
        "options": first.get("options"),
        "train": side(tr),
        "test": side(te),
        "statistics": {"method": METHOD, "reps": int(reps), "confidence": float(confidence), "seed": int(seed)},
        "tau": tau_grid.tolist(),
        "groups": out_groups,
        "gap": gaps,
    }
    return Report(doc)


def _per_instance(g: _Group, x: np.ndarray, confidence: float, reps: int, rng: np.random.Generator) -> list[dict[str, Any]]:
    """One row per instance: the mean over runs of the runs' mean returns, its bootstrap interval
    over runs, each run's score, and the outcomes counted over every run's episodes."""
    runs = g.runs
    m = x.shape[0]
    rows = []
    idx = rng.integers(0, m, size=(reps, m))
    summaries = [r.summary() for r in runs]
    for c, col in enumerate(g.columns):
        inst = runs[0].instances[col]
        vals = x[:, c]
        lo, hi = percentile_interval(vals[idx].mean(axis=1), confidence)
        outcomes: dict[str, int] = {}
        episodes = 0
        for summary in summaries:
            s = summary[col]
            episodes += s.episodes
            for k, v in s.outcomes.items():
                outcomes[k] = outcomes.get(k, 0) + v
        rows.append({
            "instance": inst.id,
            "name": inst.name,
            "split": inst.split,
            "context": inst.context,
            "mean": float(vals.mean()),
            "ci": [float(lo), float(hi)],
            "run_scores": vals.tolist(),
            "episodes": episodes,
            "outcomes": dict(sorted(outcomes.items())),
        })
    return rows


class Report:
    """A generalization report (`carl_spec.report`): `data` is its JSON document."""

    def __init__(self, data: dict[str, Any]) -> None:
        if data.get("format") != FORMAT:
            raise ValueError(f"not a carl-spec report (format {data.get('format')!r}, expected {FORMAT!r})")
        self.data = data

    @property
    def groups(self) -> dict[str, Any]:
        """`{"train": ..., "test": ..., "test/out_of_distribution": ...}`: aggregates, profile, per instance."""
        return dict(self.data["groups"])

    @property
    def gap(self) -> dict[str, Any]:
        """`{test group: {metric: {"estimate", "ci"}}}`: train minus that group."""
        return dict(self.data["gap"])

    def aggregate(self, group: str, metric: str) -> tuple[float, float, float]:
        """(estimate, ci low, ci high) of a metric (`mean`, `median`, `iqm`) of a group."""
        a = self.data["groups"][group]["aggregates"][metric]
        return a["estimate"], a["ci"][0], a["ci"][1]

    def to_json(self, path: str | os.PathLike[str] | None = None, *, indent: int | None = 1) -> str:
        text = json.dumps(self.data, indent=indent, allow_nan=False) + "\n"
        if path is not None:
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        return text

    @staticmethod
    def from_json(text: str) -> Report:
        return Report(json.loads(text))

    def to_markdown(self) -> str:
        d = self.data
        st = d["statistics"]
        pct = f"{100 * st['confidence']:g} %"
        lines = [f"# Generalization report: {d['env']} (`{d.get('gym_id')}`), carl-spec {d['carl_spec_version']}", ""]
        for key in ("train", "test"):
            s = d[key]
            if s is None:
                continue
            src = s["source"]
            what = src.get("name") if src["kind"] != "context" else json.dumps(src["context"], sort_keys=True)
            extra = f" (content hash `{src['content_hash']}`)" if src.get("content_hash") else ""
            lines.append(
                f"- **{key}**: {src['kind']} `{what}`{extra}; {len(s['runs'])} run(s) {_labels(s['runs'])}, "
                f"evaluation seeds {s['evaluation_seeds']}, {s['episodes'] or 1} episode(s) per instance, "
                f"visible context {s['obs_context']!r}, policy {s['policy']}"
            )
        if d.get("options"):
            lines.append(f"- options: `{json.dumps(d['options'], sort_keys=True)}`")
        lines += [
            f"- statistics: {st['reps']} stratified bootstrap resamples over runs, {pct} percentile intervals, "
            f"seed {st['seed']} (Agarwal et al. 2021)",
            "",
            f"## Aggregate returns ({pct} intervals)",
            "",
            "| group | runs | instances | mean | median | IQM |",
            "|---|---|---|---|---|---|",
        ]
        for g in d["groups"].values():
            a = g["aggregates"]
            lines.append(f"| {g['title']} | {g['runs']} | {g['instances']} | " + " | ".join(_ci(a[m]) for m in METRICS) + " |")
        runs = [g["runs"] for g in d["groups"].values()]
        if runs and min(runs) < 2:
            lines += ["", "With one run, the intervals have zero width: they vary runs (training seeds), so evaluate several."]
        if d["gap"]:
            lines += ["", f"## Generalization gap: train minus test ({pct} intervals)", "",
                      "| test group | mean | median | IQM |", "|---|---|---|---|"]
            for key, gap in d["gap"].items():
                lines.append(f"| {d['groups'][key]['title']} | " + " | ".join(_ci(gap[m]) for m in METRICS) + " |")
        for key, g in d["groups"].items():
            if "/" in key:
                continue
            rows = g["per_instance"]
            feats = sorted({k for r in rows for k in r["context"]})
            has_out = any(r["outcomes"] for r in rows)
            head = ["id", "name", "split", *feats, "mean return", f"{pct} interval", "episodes"] + (["outcomes"] if has_out else [])
            lines += ["", f"## Per instance: {key}", "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
            for r in rows:
                cells = [str(r["instance"]), r["name"] or "", r["split"] or "", *[_num(r["context"].get(k)) for k in feats]]
                cells += [_num(r["mean"]), f"[{_num(r['ci'][0])}, {_num(r['ci'][1])}]", str(r["episodes"])]
                if has_out:
                    cells.append(", ".join(f"{k} {v}" for k, v in r["outcomes"].items()))
                lines.append("| " + " | ".join(cells) + " |")
        tau = d["tau"]
        picks = sorted({0, len(tau) // 4, len(tau) // 2, (3 * len(tau)) // 4, len(tau) - 1})
        lines += ["", "## Performance profile: fraction of run x instance scores above tau", "",
                  "| group | " + " | ".join(f"tau = {_num(tau[i])}" for i in picks) + " |",
                  "|---|" + "---|" * len(picks)]
        for g in d["groups"].values():
            p = g["profile"]
            lines.append(f"| {g['title']} | " + " | ".join(f"{p['fraction'][i]:.2f}" for i in picks) + " |")
        return "\n".join(lines) + "\n"

    def save(self, directory: str | os.PathLike[str], *, stem: str = "report", figure: bool = False) -> list[str]:
        """Write `STEM.json` and `STEM.md` into `directory` (created if missing), and with
        `figure=True` `STEM.png` (needs matplotlib); returns the paths written."""
        os.makedirs(directory, exist_ok=True)
        paths = [os.path.join(directory, f"{stem}.json"), os.path.join(directory, f"{stem}.md")]
        self.to_json(paths[0])
        with open(paths[1], "w", encoding="utf-8") as f:
            f.write(self.to_markdown())
        if figure:
            paths.append(os.path.join(directory, f"{stem}.png"))
            self.plot(paths[-1])
        return paths

    def plot(self, path: str | os.PathLike[str] | None = None) -> Any:
        """A matplotlib figure: aggregate intervals per group, performance profiles and (for one
        varied feature) each instance's mean return against that feature. Needs matplotlib
        (`pip install 'carl-spec[plot]'`); written to `path` if given."""
        from ._plot import plot_report

        return plot_report(self.data, path)

    def __repr__(self) -> str:
        gs = ", ".join(
            f"{k}: IQM {g['aggregates']['iqm']['estimate']:.4g}" for k, g in self.data["groups"].items()
        )
        return f"Report({self.data['env']}: {gs})"


def _labels(runs: list[Any]) -> str:
    return "" if all(r is None for r in runs) else f"({', '.join(str(r) for r in runs)})"


def _ci(a: dict[str, Any]) -> str:
    return f"{_num(a['estimate'])} [{_num(a['ci'][0])}, {_num(a['ci'][1])}]"


def _num(x: Any) -> str:
    if x is None:
        return ""
    if isinstance(x, (float, np.floating)):
        x = float(x)
        if not math.isfinite(x):
            return str(x)
        return f"{x:.4g}" if abs(x) < 1e5 else f"{x:.3e}"
    return str(x)
