"""Specs, validation, instance sets and sampling: the library's data as Python objects."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from typing import Any

from gymnasium import spaces

from . import _core
from ._args import check_int, check_name, check_seed
from ._spaces import space_from_json

PathLike = str | os.PathLike[str]


def _dir(specs_dir: PathLike | None) -> str | None:
    return None if specs_dir is None else os.fspath(specs_dir)


def list_envs(*, runtime_only: bool = False, specs_dir: PathLike | None = None) -> list[str]:
    """Environment ids (those with a Rust runtime only, if asked)."""
    rows = json.loads(_core.list_envs_json(_dir(specs_dir)))
    return [r["id"] for r in rows if r["runtime"] or not runtime_only]


@dataclass(frozen=True)
class Spec:
    """One environment's resolved spec (`carl-spec show ID --format json`).

    `raw` is that document; `to_json()` writes it as a spec file of its own, which
    `cs.validate` / `carl-spec validate` accept, so an author can start from a shipped spec
    (the file leaves out `from_fragment`, the shared fragment a resolved feature was included
    from). What the runtime adds (its Gymnasium spaces at the default context) is kept apart,
    in `runtime_spaces`: it is no part of the spec language."""

    id: str
    aliases: list[str]
    family: str
    description: str
    max_episode_steps: int | None
    features: dict[str, dict[str, Any]]
    distributions: dict[str, dict[str, Any]]
    instance_sets: dict[str, dict[str, Any]]
    raw: dict[str, Any] = field(repr=False)
    #: `{"observation": space, "action": space}` as the native module describes them (None
    #: without a runtime).
    runtime_spaces: dict[str, Any] | None = field(default=None, repr=False)

    @property
    def has_runtime(self) -> bool:
        return self.runtime_spaces is not None

    @property
    def observation_space(self) -> spaces.Space[Any] | None:
        """The runtime's observation space at the default context (None without a runtime)."""
        rs = self.runtime_spaces
        return None if rs is None else space_from_json(rs["observation"])

    @property
    def action_space(self) -> spaces.Space[Any] | None:
        rs = self.runtime_spaces
        return None if rs is None else space_from_json(rs["action"])

    def default_context(self) -> dict[str, Any]:
        return {n: f["default"] for n, f in self.features.items() if "default" in f}

    def to_json(self, indent: int | None = 2) -> str:
        """The spec as the text of a spec file (it validates as it is; edit it to make your own)."""
        doc = dict(self.raw)
        doc["features"] = [{k: v for k, v in f.items() if k != "from_fragment"} for f in self.raw["features"]]
        return json.dumps(doc, indent=indent) + "\n"


def spec(env: str, *, specs_dir: PathLike | None = None) -> Spec:
    """The resolved spec of `env` (id or alias)."""
    raw = json.loads(_core.spec_json(check_name("env", env), _dir(specs_dir)))
    runtime_spaces = raw.pop("runtime_spaces", None)
    return Spec(
        id=raw["id"],
        aliases=raw.get("aliases", []),
        family=raw["family"],
        description=raw["description"],
        max_episode_steps=raw.get("max_episode_steps"),
        features={f["name"]: f for f in raw["features"]},
        distributions=raw.get("distributions", {}),
        instance_sets=raw.get("instance_sets", {}),
        raw=raw,
        runtime_spaces=runtime_spaces,
    )


@dataclass(frozen=True)
class Diagnostic:
    """One validator finding, located like the CLI's (1-based line and column)."""

    severity: str
    rule: str
    message: str
    file: str
    pointer: str
    line: int | None
    col: int | None
    help: str | None

    def __str__(self) -> str:
        where = self.file if self.line is None else f"{self.file}:{self.line}:{self.col}"
        return f"{where}: {self.severity}[{self.rule}]: {self.message}"


@dataclass(frozen=True)
class ValidationReport:
    valid: bool
    files: int
    environments: int
    diagnostics: list[Diagnostic]

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "error"]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "warning"]

    def __bool__(self) -> bool:
        return self.valid


def validate(*paths: PathLike) -> ValidationReport:
    """Validate spec files or directories (none: the bundled specs), like `carl-spec validate`."""
    doc = json.loads(_core.validate_json([os.fspath(p) for p in paths]))
    diags = []
    for d in doc["diagnostics"]:
        loc = d.get("location") or {}
        diags.append(
            Diagnostic(
                severity=d["severity"],
                rule=d["rule"],
                message=d["message"],
                file=d["file"],
                pointer=d["pointer"],
                line=loc.get("line"),
                col=loc.get("column"),
                help=d.get("help"),
            )
        )
    return ValidationReport(doc["valid"], doc["files"], doc["environments"], diags)


@dataclass(frozen=True)
class InstanceSet:
    """A frozen instance set (`carl-spec instances show ENV/SET`): contexts by instance id."""

    env: str
    name: str
    description: str
    features: list[str]
    contexts: list[dict[str, Any]]
    names: list[str | None]
    splits: list[str | None]
    content_hash: str
    raw: dict[str, Any] = field(repr=False)

    @property
    def qualified_name(self) -> str:
        return f"{self.env}/{self.name}"

    def __len__(self) -> int:
        return len(self.contexts)


def _instance_set(raw: dict[str, Any]) -> InstanceSet:
    inst = raw["instances"]
    return InstanceSet(
        env=raw["env"],
        name=raw["set"],
        description=raw["description"],
        features=raw["features"],
        contexts=[i["context"] for i in inst],
        names=[i.get("name") for i in inst],
        splits=[i.get("split") for i in inst],
        content_hash=raw["content_hash"],
        raw=raw,
    )


class instances:  # noqa: N801 - a namespace: cs.instances.load(...), cs.instances.list()
    """Frozen instance sets by name."""

    @staticmethod
    def list(*, specs_dir: PathLike | None = None) -> list[str]:
        return _core.instance_sets(_dir(specs_dir))

    @staticmethod
    def load(name: str, *, specs_dir: PathLike | None = None) -> InstanceSet:
        """`ENV/SET`, checked against its hash and its spec."""
        return _instance_set(json.loads(_core.load_instances_json(check_name("instances", name), _dir(specs_dir))))


def sample(
    env: str, *, distribution: str, n: int, seed: int, specs_dir: PathLike | None = None
) -> list[dict[str, Any]]:
    """`n` contexts (the varied features only) drawn from a named distribution, as
    `carl-spec sample ENV --distribution D -n N --seed S`."""
    n = check_int("n", n)
    checked = check_seed(seed)
    if checked is None:
        raise ValueError("seed must be a non-negative int below 2**64, got None")
    raw = json.loads(_core.sample_json(check_name("env", env), check_name("distribution", distribution), n, checked, _dir(specs_dir)))
    return [i["context"] for i in raw["instances"]]
