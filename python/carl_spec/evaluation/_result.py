"""What `evaluate` returns: per-episode records, per-instance aggregates and provenance, as JSON."""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from collections.abc import Iterable, Iterator, Sequence
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


class Episodes(Sequence[Episode]):
    """A result's episodes as columns: NumPy arrays `instance`, `episode`, `seed` (int64 / uint64),
    `return_` (float64), `length` (int64), `terminated`, `truncated` (bool) and the lists
    `outcome` and `context_seed` (None where absent). Indexing and iterating give `Episode`
    tuples, made on first use: `evaluate` fills the columns in one go, so producing a result
    costs no Python object per episode. Equal to any sequence of the same episodes."""

    __slots__ = ("instance", "episode", "seed", "return_", "length", "terminated", "truncated", "outcome", "context_seed", "_rows")

    def __init__(
        self,
        instance: Any,
        episode: Any,
        seed: Any,
        return_: Any,
        length: Any,
        terminated: Any,
        truncated: Any,
        outcome: list[str | None] | None = None,
        context_seed: list[int | None] | None = None,
    ) -> None:
        self.instance = np.asarray(instance, dtype=np.int64)
        n = len(self.instance)
        self.episode = np.asarray(episode, dtype=np.int64)
        self.seed = np.asarray(seed, dtype=np.uint64)
        self.return_ = np.asarray(return_, dtype=np.float64)
        self.length = np.asarray(length, dtype=np.int64)
        self.terminated = np.asarray(terminated, dtype=np.bool_)
        self.truncated = np.asarray(truncated, dtype=np.bool_)
        self.outcome: list[str | None] = [None] * n if outcome is None else list(outcome)
        self.context_seed: list[int | None] = [None] * n if context_seed is None else list(context_seed)
        columns = (self.episode, self.seed, self.return_, self.length, self.terminated, self.truncated)
        if any(len(c) != n for c in (*columns, self.outcome, self.context_seed)):
            raise ValueError("the episode columns differ in length")
        self._rows: list[Episode] | None = None

    @staticmethod
    def of(episodes: Iterable[Episode]) -> Episodes:
        """The columns of some `Episode` tuples (returned as they are if already columns)."""
        if isinstance(episodes, Episodes):
            return episodes
        rows = list(episodes)
        cols = list(zip(*rows)) if rows else [()] * len(Episode._fields)
        out = Episodes(*cols)
        out._rows = rows
        return out

    def rows(self) -> list[Episode]:
        """The episodes as `Episode` tuples (made once)."""
        if self._rows is None:
            self._rows = list(
                map(
                    Episode,
                    self.instance.tolist(),
                    self.episode.tolist(),
                    self.seed.tolist(),
                    self.return_.tolist(),
                    self.length.tolist(),
                    self.terminated.tolist(),
                    self.truncated.tolist(),
                    self.outcome,
                    self.context_seed,
                )
            )
        return self._rows

    def take(self, index: np.ndarray) -> Episodes:
        """The episodes at `index` (an integer array), as columns."""
        ix = index.tolist()
        return Episodes(
            self.instance[index],
            self.episode[index],
            self.seed[index],
            self.return_[index],
            self.length[index],
            self.terminated[index],
            self.truncated[index],
            [self.outcome[i] for i in ix],
            [self.context_seed[i] for i in ix],
        )

    def __len__(self) -> int:
        return len(self.instance)

    def __getitem__(self, i: Any) -> Any:
        return self.rows()[i]

    def __iter__(self) -> Iterator[Episode]:
        return iter(self.rows())

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Sequence) or isinstance(other, (str, bytes)):
            return NotImplemented
        return len(self) == len(other) and all(a == b for a, b in zip(self.rows(), other))

    __hash__ = None  # type: ignore[assignment]  # mutable-looking, like a list

    def __repr__(self) -> str:
        return f"Episodes({len(self)} episodes)"


def _summary(instance: Instance, episodes: Episodes) -> InstanceSummary:
    r = episodes.return_
    outcomes: dict[str, int] = {}
    for w in episodes.outcome:
        if w is not None:
            outcomes[w] = outcomes.get(w, 0) + 1
    return InstanceSummary(
        instance=instance,
        episodes=len(episodes),
        mean=float(r.mean()),
        std=float(r.std()),
        median=float(np.median(r)),
        min=float(r.min()),
        max=float(r.max()),
        mean_length=float(episodes.length.mean()),
        terminated=int(episodes.terminated.sum()),
        truncated=int(episodes.truncated.sum()),
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
    #: Any sequence of `Episode`s; kept as `Episodes` (columns).
    episodes: Sequence[Episode]
    _by_instance: dict[int, np.ndarray] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        eps = Episodes.of(self.episodes)
        object.__setattr__(self, "episodes", eps)
        ids = np.array([i.id for i in self.instances], dtype=np.int64)
        known = np.isin(eps.instance, ids)
        if not known.all():
            e = eps[int(np.flatnonzero(~known)[0])]
            raise ValueError(f"episode {e} refers to instance {e.instance}, which this result does not list")
        # Each instance's episodes, in the order they are listed (a stable sort by instance).
        order = np.argsort(eps.instance, kind="stable")
        sorted_ids = eps.instance[order]
        starts = np.searchsorted(sorted_ids, ids, side="left")
        ends = np.searchsorted(sorted_ids, ids, side="right")
        empty = np.flatnonzero(starts == ends)
        if len(empty):
            raise ValueError(f"instance {int(ids[empty[0]])} has no episode")
        by = {int(k): order[a:b] for k, a, b in zip(ids.tolist(), starts.tolist(), ends.tolist())}
        object.__setattr__(self, "_by_instance", by)

    @property
    def env(self) -> str:
        return str(self.provenance["env"])

    @property
    def _episodes(self) -> Episodes:
        return self.episodes  # type: ignore[return-value]  # __post_init__ made it Episodes

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
        eps = self._episodes
        return [_summary(i, eps.take(self._by_instance[i.id])) for i in self.instances]

    def returns(self, instance: int | str) -> np.ndarray:
        """The returns of one instance's episodes, by id or name, in episode order."""
        inst = self._instance(instance)
        returns: np.ndarray = self._episodes.return_[self._by_instance[inst.id]]
        return returns

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
        r = self._episodes.return_
        return np.array([r[self._by_instance[i.id]].mean() for i in self.instances])

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
