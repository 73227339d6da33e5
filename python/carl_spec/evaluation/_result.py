"""What `evaluate` returns: per-episode records, per-instance aggregates and provenance, as JSON."""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

#: The `format` of an evaluation's JSON document.
FORMAT = "carl-spec-evaluation/1"


@dataclass(frozen=True)
class Instance:
    """One instance evaluated: its index in the set (the draw's number for a distribution), name,
    split label (`in_distribution` / `out_of_distribution` where the set defines them) and the
    context features that the set (distribution, fixed context) sets."""

    id: int
    name: str | None
    split: str | None
    context: dict[str, Any]


class Episode(NamedTuple):
    """One episode: its instance, its index among that instance's episodes, the seed it was reset
    with, its return (`return_`; `"return"` in JSON), length and how it ended. `outcome` is the
    environment's own verdict (`info["outcome"]` at the episode's last step: landed, crashed,
    solved, timed_out, ...), None where the environment defines none; a distribution's draw also
    records `context_seed`. (An immutable named tuple: one is made per episode, five times faster
    than a frozen dataclass.)"""

    instance: int
    episode: int
    seed: int
    return_: float
    length: int
    terminated: bool
    truncated: bool
    outcome: str | None = None
    context_seed: int | None = None

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "instance": self.instance,
            "episode": self.episode,
            "seed": self.seed,
            "return": self.return_,
            "length": self.length,
            "terminated": self.terminated,
            "truncated": self.truncated,
            "outcome": self.outcome,
        }
        if self.context_seed is not None:
            d["context_seed"] = self.context_seed
        return d

    @staticmethod
    def from_dict(d: dict[str, Any]) -> Episode:
        return Episode(
            instance=int(d["instance"]),
            episode=int(d["episode"]),
            seed=int(d["seed"]),
            return_=float(d["return"]),
            length=int(d["length"]),
            terminated=bool(d["terminated"]),
            truncated=bool(d["truncated"]),
            outcome=d.get("outcome"),
            context_seed=None if d.get("context_seed") is None else int(d["context_seed"]),
        )


@dataclass(frozen=True)
class InstanceSummary:
    """An instance's episodes aggregated: return statistics, mean length, how many terminated or
    were truncated, and the count of each outcome (empty where the environment defines none)."""

    instance: Instance
    episodes: int
    mean: float
    std: float
    median: float
    min: float
    max: float
    mean_length: float
    terminated: int
    truncated: int
    outcomes: dict[str, int]

    def to_dict(self) -> dict[str, Any]:
        return {
            "instance": self.instance.id,
            "name": self.instance.name,
            "split": self.instance.split,
            "context": self.instance.context,
            "episodes": self.episodes,
            "mean": self.mean,
            "std": self.std,
            "median": self.median,
            "min": self.min,
            "max": self.max,
            "mean_length": self.mean_length,
            "terminated": self.terminated,
            "truncated": self.truncated,
            "outcomes": self.outcomes,
        }


def _summary(instance: Instance, episodes: list[Episode]) -> InstanceSummary:
    r = np.array([e.return_ for e in episodes], dtype=np.float64)
    outcomes: dict[str, int] = {}
    for e in episodes:
        if e.outcome is not None:
            outcomes[e.outcome] = outcomes.get(e.outcome, 0) + 1
    return InstanceSummary(
        instance=instance,
        episodes=len(episodes),
        mean=float(r.mean()),
        std=float(r.std()),
        median=float(np.median(r)),
        min=float(r.min()),
        max=float(r.max()),
        mean_length=float(np.mean([e.length for e in episodes])),
        terminated=sum(e.terminated for e in episodes),
        truncated=sum(e.truncated for e in episodes),
        outcomes=dict(sorted(outcomes.items())),
    )


@dataclass(frozen=True)
class EvaluationResult:
    """A policy's episodes on every instance of a set (a distribution's draws, a fixed context).

    `provenance` says what produced them: `env`, `env_version` and `gym_id`, `carl_spec_version`,
    the `source` (`{"kind": "instances", "name": "ENV/SET", "content_hash": ...}`,
    `{"kind": "distribution", "name": ..., "draws": n}` or `{"kind": "context", "context": {...}}`),
    the evaluation `seed` and the rule that derives each episode's seed from it, `episodes` per
    instance, `options`, `obs_context`, `context_noise`, the `policy`'s class, `deterministic`, an
    optional `run` label (a training seed) and `num_envs` / `threads` (which do not change the
    results). `to_json()` / `from_json()` round-trip exactly."""

    provenance: dict[str, Any]
    instances: list[Instance]
    episodes: list[Episode]
    _by_instance: dict[int, list[Episode]] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        by: dict[int, list[Episode]] = {i.id: [] for i in self.instances}
        for e in self.episodes:
            if e.instance not in by:
                raise ValueError(f"episode {e} refers to instance {e.instance}, which this result does not list")
            by[e.instance].append(e)
        for k, eps in by.items():
            if not eps:
                raise ValueError(f"instance {k} has no episode")
        object.__setattr__(self, "_by_instance", by)

    @property
    def env(self) -> str:
        return str(self.provenance["env"])

    @property
    def source_name(self) -> str:
        """`ENV/SET`, `ENV distribution NAME` or `ENV context {...}`: what was evaluated."""
        s = self.provenance["source"]
        if s["kind"] == "instances":
            return str(s["name"])
        if s["kind"] == "distribution":
            return f"{self.env} distribution {s['name']}"
        return f"{self.env} context {json.dumps(s['context'], sort_keys=True)}"

    def summary(self) -> list[InstanceSummary]:
        """Per-instance aggregates, in instance order."""
        return [_summary(i, self._by_instance[i.id]) for i in self.instances]

    def returns(self, instance: int | str) -> np.ndarray:
        """The returns of one instance's episodes, by id or name, in episode order."""
        inst = self._instance(instance)
        return np.array([e.return_ for e in self._by_instance[inst.id]], dtype=np.float64)

    def _instance(self, key: int | str) -> Instance:
        for i in self.instances:
            if (isinstance(key, str) and i.name == key) or (not isinstance(key, str) and i.id == key):
                return i
        names = ", ".join(str(i.name if i.name is not None else i.id) for i in self.instances[:20])
        raise KeyError(f"no instance {key!r} in {self.source_name}; instances: {names}")

    def records(self) -> list[dict[str, Any]]:
        """One flat row per episode with its instance's name, split and context beside the
        episode's fields (`pandas.DataFrame(result.records())` makes a table of them; the JSON
        keeps each instance's context once, in `instances`)."""
        by_id = {i.id: i for i in self.instances}
        rows = []
        for e in self.episodes:
            inst = by_id[e.instance]
            row = e.to_dict()
            row.update(name=inst.name, split=inst.split, context=dict(inst.context))
            rows.append(row)
        return rows

    @property
    def scores(self) -> np.ndarray:
        """The mean return of each instance, in instance order (the report's per-task score)."""
        return np.array([np.mean([e.return_ for e in self._by_instance[i.id]]) for i in self.instances])

    @property
    def mean_return(self) -> float:
        """The mean over instances of each instance's mean return."""
        return float(self.scores.mean())

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": FORMAT,
            "provenance": self.provenance,
            "instances": [
                {"id": i.id, "name": i.name, "split": i.split, "context": i.context} for i in self.instances
            ],
            "summary": [s.to_dict() for s in self.summary()],
            "episodes": [e.to_dict() for e in self.episodes],
        }

    def to_json(self, path: str | os.PathLike[str] | None = None, *, indent: int | None = 1) -> str:
        """The result as JSON text (the per-instance summary included for readers; `from_json`
        recomputes it from the episodes); written to `path` as well if given."""
        text = json.dumps(self.to_dict(), indent=indent, allow_nan=False) + "\n"
        if path is not None:
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        return text

    @staticmethod
    def from_json(text: str) -> EvaluationResult:
        """A result from `to_json`'s text."""
        d = json.loads(text)
        if not isinstance(d, dict) or d.get("format") != FORMAT:
            got = d.get("format") if isinstance(d, dict) else type(d).__name__
            raise ValueError(f"not a carl-spec evaluation (format {got!r}, expected {FORMAT!r})")
        return EvaluationResult(
            provenance=d["provenance"],
            instances=[Instance(int(i["id"]), i.get("name"), i.get("split"), dict(i["context"])) for i in d["instances"]],
            episodes=[Episode.from_dict(e) for e in d["episodes"]],
        )

    @staticmethod
    def load(path: str | os.PathLike[str]) -> EvaluationResult:
        """A result from a file `to_json(path)` wrote."""
        with open(path, encoding="utf-8") as f:
            return EvaluationResult.from_json(f.read())

    def table(self) -> str:
        """The per-instance aggregates as a Markdown table."""
        feats = sorted({k for i in self.instances for k in i.context})
        head = ["id", "name", "split", *feats, "episodes", "mean return", "std", "min", "max", "mean length", "outcomes"]
        rows = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for s in self.summary():
            ctx = [_num(s.instance.context.get(k)) for k in feats]
            out = ", ".join(f"{k} {v}" for k, v in s.outcomes.items())
            cells = [str(s.instance.id), s.instance.name or "", s.instance.split or "", *ctx, str(s.episodes)]
            cells += [_num(s.mean), _num(s.std), _num(s.min), _num(s.max), _num(s.mean_length), out]
            rows.append("| " + " | ".join(cells) + " |")
        return "\n".join(rows) + "\n"

    def __repr__(self) -> str:
        n = len(self.instances)
        return (
            f"EvaluationResult({self.source_name}: {n} instance{'s' * (n != 1)}, {len(self.episodes)} episodes, "
            f"mean return {self.mean_return:.4g}, seed {self.provenance.get('seed')})"
        )


def _num(x: Any) -> str:
    if x is None:
        return ""
    if isinstance(x, float):
        if math.isfinite(x) and x == int(x) and abs(x) < 1e15:
            return f"{x:.1f}"
        return f"{x:.4g}"
    return str(x)
