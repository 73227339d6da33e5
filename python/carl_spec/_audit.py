"""`carl_spec.audit`: does each feature of a user's spec really do what its `affects` claims?

The Python counterpart of `carl-spec audit` (src/audit/) for environments the user wraps with
`cs.wrap`. For every feature, the env is built under the default context and under the values
the Rust audit perturbs that one feature to (`probes::perturbed_values`, through the binding),
fed the same seeds, the same base states and the same actions, and compared exactly:

* **dynamics**: the internal state after one step from the same state with the same action;
* **reward**, **termination**: the reward / `terminated` flag of that transition. A difference
  counts as direct only when both next states are equal; otherwise it may be a consequence of the
  changed dynamics and is recorded as *via dynamics* (consistent with either claim);
* **observation**: the observation returned for equal next states;
* **initial_state**: the state after `reset(seed)` for several seeds.

Internal state is read and written with `get_state(env)` / `set_state(env, state)`, by default
`env.unwrapped.state` (Gymnasium's classic-control convention). Without state access the audit
falls back to trajectories compared through observations: the observation stands for the state,
so dynamics and observation effects cannot be told apart (observation is then reported n/a).

A probe where either env returns a non-finite reward, observation or state (NaN, ±inf) is not
compared (NaN differs from everything, itself included, and would read as an effect); it is
listed in `report.non_finite`, and the audit fails: a context inside the spec's bounds must keep
the env finite.

Verdicts as in the Rust audit: claimed and measured -> ok (the claim held); claimed but never
measured -> missing_effect (a dead claim: carl-bench's dead features are exactly this);
measured but not claimed -> undeclared_effect.
"""

from __future__ import annotations

import copy
import json
import os
from dataclasses import dataclass, field
from typing import Any, Callable

import gymnasium
import numpy as np
from gymnasium import spaces

from . import _core
from ._wrap import ApplyFn, EnvFactory, PathLike, load_user_spec, wrap

EFFECTS = ("dynamics", "reward", "termination", "initial_state", "observation", "task_generation")
GetState = Callable[[gymnasium.Env[Any, Any]], Any]
SetState = Callable[[gymnasium.Env[Any, Any], Any], None]


@dataclass
class EffectResult:
    """One (feature, effect) cell: what was claimed, what was measured, and the evidence."""

    effect: str
    claimed: bool
    measured: str  # changed | via_dynamics | unchanged | not_applicable
    verdict: str  # ok | missing_effect | undeclared_effect | not_applicable
    max_abs_diff: float = 0.0
    at_value: float | None = None
    compared: int = 0
    differing: int = 0
    via_dynamics: int = 0

    @property
    def held(self) -> bool | None:
        """For a claimed effect: whether the claim held (None when it cannot be measured)."""
        if self.verdict == "not_applicable":
            return None
        return self.verdict == "ok"


@dataclass
class FeatureAudit:
    name: str
    default: Any
    values: list[float]
    claimed: list[str]
    effects: dict[str, EffectResult] = field(default_factory=dict)
    skipped: str | None = None


@dataclass
class AuditReport:
    env: str
    mode: str  # "state" (get/set state) or "trajectory" (observations stand for the state)
    base_states: int
    actions: int
    reset_seeds: int
    features: list[FeatureAudit]
    contradictions: list[str]
    #: Probes where the env returned a non-finite reward, observation or state (NaN or ±inf), one
    #: line per context: such a probe is not compared (NaN differs from everything, itself
    #: included), and the audit does not pass: a context inside the spec's bounds must keep the
    #: env finite.
    non_finite: list[str] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return not self.contradictions and not self.non_finite

    def feature(self, name: str) -> FeatureAudit:
        for f in self.features:
            if f.name == name:
                return f
        raise KeyError(name)

    def __str__(self) -> str:
        lines = [
            f"audit of {self.env} ({self.mode} probes: {self.base_states} states x {self.actions} actions, "
            f"{self.reset_seeds} reset seeds)"
        ]
        for f in self.features:
            if f.skipped:
                lines.append(f"  {f.name}: skipped ({f.skipped})")
                continue
            cells = [
                f"{e.effect}={e.verdict}"
                for e in f.effects.values()
                if e.claimed or e.verdict not in ("ok", "not_applicable")
            ]
            lines.append(f"  {f.name}: " + (", ".join(cells) if cells else "claims nothing, changes nothing"))
        lines.extend(f"  ! {c}" for c in self.contradictions)
        lines.extend(f"  ! non-finite output: {n}" for n in self.non_finite)
        if self.passed:
            lines.append("PASSED")
        else:
            failed = [f"{len(self.contradictions)} contradiction(s)"] if self.contradictions else []
            if self.non_finite:
                failed.append(f"non-finite output under {len(self.non_finite)} context(s)")
            lines.append("FAILED: " + ", ".join(failed))
        return "\n".join(lines)


def _default_get_state(env: gymnasium.Env[Any, Any]) -> Any:
    return env.unwrapped.state  # type: ignore[attr-defined]


def _default_set_state(env: gymnasium.Env[Any, Any], state: Any) -> None:
    env.unwrapped.state = np.array(state, dtype=np.float64)  # type: ignore[attr-defined]


def _flat(x: Any) -> np.ndarray:
    if isinstance(x, dict):
        return np.concatenate([_flat(x[k]) for k in sorted(x)]) if x else np.zeros(0)
    return np.asarray(x, dtype=np.float64).reshape(-1)


def _diff(a: Any, b: Any) -> float:
    """Largest absolute difference; exact equality is 0 (NaN == NaN), shape or finiteness
    mismatches are infinite."""
    x, y = _flat(a), _flat(b)
    if x.shape != y.shape:
        return float("inf")
    same = (x == y) | (np.isnan(x) & np.isnan(y))
    if same.all():
        return 0.0
    d = np.abs(x - y)[~same]
    return float("inf") if np.isnan(d).any() else float(d.max())


def probe_actions(space: spaces.Space[Any]) -> list[Any]:
    """The Rust audit's action set: every discrete action; for a Box, 5 points of a 1-D range, a
    3-per-axis grid up to 3 dimensions, else the centre and each axis's extremes."""
    if isinstance(space, spaces.Discrete):
        return [np.int64(int(space.start) + i) for i in range(int(space.n))]
    if not isinstance(space, spaces.Box):
        raise ValueError(f"audit probes Discrete and Box action spaces, got {space}")
    low, high = space.low.reshape(-1).astype(np.float64), space.high.reshape(-1).astype(np.float64)
    low, high = np.where(np.isfinite(low), low, -1.0), np.where(np.isfinite(high), high, 1.0)

    def at(t: np.ndarray) -> Any:
        return (low + (high - low) * t).astype(space.dtype).reshape(space.shape)

    dims = low.size
    if dims == 1:
        return [at(np.array([t])) for t in (0.0, 0.25, 0.5, 0.75, 1.0)]
    if dims <= 3:
        grid = np.array(np.meshgrid(*[[0.0, 0.5, 1.0]] * dims, indexing="ij")).reshape(dims, -1).T
        return [at(t) for t in grid]
    out = [at(np.full(dims, 0.5))]
    for i in range(dims):
        for t in (0.0, 1.0):
            v = np.full(dims, 0.5)
            v[i] = t
            out.append(at(v))
    return out


@dataclass
class _Acc:
    max: float = 0.0
    at: float | None = None
    compared: int = 0
    differing: int = 0
    via: int = 0

    def direct(self, d: float, value: float) -> None:
        self.compared += 1
        if d != 0.0:
            self.differing += 1
            if self.at is None or d > self.max:
                self.max, self.at = d, value

    def via_dynamics(self, d: float) -> None:
        if d != 0.0:
            self.via += 1


class _Prober:
    """Runs the probes on one env (built for one context)."""

    def __init__(self, env: gymnasium.Env[Any, Any], get_state: GetState | None, set_state: SetState | None):
        self.env, self.get, self.set = env, get_state, set_state
        #: Non-finite outputs seen: what ("reward", "observation", "state") -> (count, first value).
        self.non_finite: dict[str, tuple[int, str]] = {}

    def finite(self, **outputs: Any) -> bool:
        """Whether every output is finite; the non-finite ones are recorded."""
        ok = True
        for what, x in outputs.items():
            values = _flat(x)
            if not np.isfinite(values).all():
                ok = False
                count, first = self.non_finite.get(what, (0, ""))
                bad = values[~np.isfinite(values)][0]
                self.non_finite[what] = (count + 1, first or str(bad))
        return ok

    def non_finite_text(self) -> str | None:
        if not self.non_finite:
            return None
        return "; ".join(f"{what} {first} ({n} probe(s))" for what, (n, first) in self.non_finite.items())

    def state(self) -> np.ndarray:
        assert self.get is not None
        return np.array(self.get(self.env), dtype=np.float64).reshape(-1)

    def base_states(self, seeds: int, steps: int) -> list[np.ndarray]:
        states = []
        for seed in range(seeds):
            self.env.reset(seed=seed)
            states.append(self.state())
            space = copy.deepcopy(self.env.action_space)
            space.seed(0x5EED_0000 + seed)
            for _ in range(steps):
                _, _, terminated, truncated, _ = self.env.step(space.sample())
                s = self.state()
                if np.isfinite(s).all():
                    states.append(s)
                if terminated or truncated:
                    break
        return states

    def state_responses(self, states: list[np.ndarray], actions: list[Any], seeds: int) -> dict[str, Any]:
        steps = []
        for s in states:
            for a in actions:
                self.env.reset(seed=0)
                assert self.set is not None
                self.set(self.env, s.copy())
                obs, reward, terminated, _, _ = self.env.step(a)
                state = self.state()
                ok = self.finite(reward=float(reward), observation=obs, state=state)
                steps.append((state, float(reward), bool(terminated), _flat(obs), ok))
        initial = []
        for seed in range(seeds):
            obs, _ = self.env.reset(seed=seed)
            state = self.state()
            initial.append((state, _flat(obs), self.finite(observation=obs, state=state)))
        return {"steps": steps, "initial": initial}

    def trajectory_responses(self, seeds: int, steps: int) -> dict[str, Any]:
        """Per seed: the reset observation, then (obs, reward, terminated) along fixed actions."""
        runs = []
        for seed in range(seeds):
            obs, _ = self.env.reset(seed=seed)
            space = copy.deepcopy(self.env.action_space)
            space.seed(0x5EED_0000 + seed)
            run: list[tuple[np.ndarray, float, bool]] = []
            if self.finite(observation=obs):
                run.append((_flat(obs), 0.0, False))
                for _ in range(steps):
                    obs, reward, terminated, truncated, _ = self.env.step(space.sample())
                    if not self.finite(reward=float(reward), observation=obs):
                        break  # the run ends at its first non-finite output (never compared)
                    run.append((_flat(obs), float(reward), bool(terminated)))
                    if terminated or truncated:
                        break
            runs.append(run)
        return {"runs": runs}


def _compare_state(base: dict[str, Any], pert: dict[str, Any], value: float, accs: dict[str, _Acc]) -> None:
    for (sa, ra, ta, oa, fa), (sb, rb, tb, ob, fb) in zip(base["steps"], pert["steps"]):
        if not (fa and fb):
            continue  # a non-finite output is reported as such, never read as a change
        dyn = _diff(sa, sb)
        accs["dynamics"].direct(dyn, value)
        r, t = abs(ra - rb) if ra != rb else 0.0, 0.0 if ta == tb else 1.0
        if dyn == 0.0:
            accs["reward"].direct(r, value)
            accs["termination"].direct(t, value)
            accs["observation"].direct(_diff(oa, ob), value)
        else:
            accs["reward"].via_dynamics(r)
            accs["termination"].via_dynamics(t)
    for (sa, oa, fa), (sb, ob, fb) in zip(base["initial"], pert["initial"]):
        if not (fa and fb):
            continue
        d = _diff(sa, sb)
        accs["initial_state"].direct(d, value)
        if d == 0.0:
            accs["observation"].direct(_diff(oa, ob), value)


def _compare_trajectories(base: dict[str, Any], pert: dict[str, Any], value: float, accs: dict[str, _Acc]) -> None:
    for run_a, run_b in zip(base["runs"], pert["runs"]):
        if not (run_a and run_b):
            continue  # a reset observation that is not finite
        accs["initial_state"].direct(_diff(run_a[0][0], run_b[0][0]), value)
        for i in range(1, min(len(run_a), len(run_b))):
            if _diff(run_a[i - 1][0], run_b[i - 1][0]) != 0.0:
                break  # the trajectories have diverged: later steps start from different states
            (oa, ra, ta), (ob, rb, tb) = run_a[i], run_b[i]
            dyn = _diff(oa, ob)
            accs["dynamics"].direct(dyn, value)
            r, t = abs(ra - rb) if ra != rb else 0.0, 0.0 if ta == tb else 1.0
            if dyn == 0.0:
                accs["reward"].direct(r, value)
                accs["termination"].direct(t, value)
            else:
                accs["reward"].via_dynamics(r)
                accs["termination"].via_dynamics(t)


def _judge(effect: str, claimed: bool, acc: _Acc, applicable: bool) -> EffectResult:
    if not applicable:
        measured = "not_applicable"
    elif acc.differing:
        measured = "changed"
    elif acc.via:
        measured = "via_dynamics"
    else:
        measured = "unchanged"
    if measured == "not_applicable":
        verdict = "not_applicable"
    elif claimed and measured == "unchanged":
        verdict = "missing_effect"
    elif not claimed and measured == "changed":
        verdict = "undeclared_effect"
    else:
        verdict = "ok"
    return EffectResult(effect, claimed, measured, verdict, acc.max, acc.at, acc.compared, acc.differing, acc.via)


_WHAT = {
    "dynamics": "the next state",
    "reward": "the reward",
    "termination": "the termination flag",
    "initial_state": "the initial state",
    "observation": "the observation",
}


def _num(x: float) -> str:
    return f"{x:.4g}"


def audit(
    factory: EnvFactory,
    spec: PathLike,
    *,
    env_id: str | None = None,
    apply: ApplyFn | None = None,
    attributes: dict[str, str] | None = None,
    get_state: GetState | None = None,
    set_state: SetState | None = None,
    seeds: int = 5,
    steps: int = 40,
) -> AuditReport:
    """Check every `affects` claim of the user's spec against `factory()`'s environment.

    `apply`/`attributes` are `cs.wrap`'s. `get_state`/`set_state` read and write the internal
    state (default: `env.unwrapped.state` when the env has one; else trajectory mode). `seeds`
    reset seeds, each followed by up to `steps` random actions (fixed seeds), give the base
    states. Returns an `AuditReport`; `report.passed` is False when a claim failed.
    """
    spec_path = os.fspath(spec)
    doc = load_user_spec(spec_path, env_id)
    rows = {r["name"]: r for r in json.loads(_core.audit_values_json(spec_path, env_id))}

    def build(context: dict[str, Any]) -> gymnasium.Env[Any, Any]:
        return wrap(factory, spec_path, env_id=env_id, context=context, apply=apply, attributes=attributes)

    base_env = build({})
    base_env.reset(seed=0)
    if get_state is None and set_state is None and hasattr(base_env.unwrapped, "state"):
        get_state, set_state = _default_get_state, _default_set_state
    state_mode = get_state is not None and set_state is not None
    if (get_state is None) != (set_state is None):
        raise ValueError("give both get_state and set_state, or neither")
    prober = _Prober(base_env, get_state, set_state)
    actions = probe_actions(base_env.action_space)
    if state_mode:
        states = prober.base_states(seeds, steps)
        reference = prober.state_responses(states, actions, seeds)
    else:
        states = []
        reference = prober.trajectory_responses(seeds, steps)

    features = []
    contradictions = []
    non_finite = []
    if (text := prober.non_finite_text()) is not None:
        non_finite.append(f"default context: {text}")
    for f in doc["features"]:
        row = rows[f["name"]]
        fa = FeatureAudit(f["name"], f.get("default"), list(row["values"]), list(f.get("affects", [])), skipped=row["skipped"])
        features.append(fa)
        if fa.skipped:
            continue
        accs = {e: _Acc() for e in EFFECTS}
        for x in fa.values:
            try:
                p = _Prober(build({f["name"]: x}), get_state, set_state)
                answers = p.state_responses(states, actions, seeds) if state_mode else p.trajectory_responses(seeds, steps)
            except Exception as err:
                raise RuntimeError(f"{doc['id']}: the env failed under {f['name']} = {x}: {type(err).__name__}: {err}") from err
            if (text := p.non_finite_text()) is not None:
                non_finite.append(f"{f['name']} = {_num(x)}: {text}")
            if state_mode:
                _compare_state(reference, answers, x, accs)
            else:
                _compare_trajectories(reference, answers, x, accs)
        for e in EFFECTS:
            applicable = e != "task_generation" and (state_mode or e != "observation")
            fa.effects[e] = res = _judge(e, e in fa.claimed, accs[e], applicable)
            values = ", ".join(_num(v) for v in fa.values)
            if res.verdict == "missing_effect":
                contradictions.append(
                    f"{fa.name} claims {e} but changing it never changed {_WHAT[e]} "
                    f"(values {values}; {res.compared} probes)"
                )
            elif res.verdict == "undeclared_effect":
                contradictions.append(
                    f"{fa.name} changes {_WHAT[e]} (max |d| {_num(res.max_abs_diff)} at {fa.name} = "
                    f"{_num(res.at_value or 0.0)}, {res.differing}/{res.compared} probes) but does not claim {e}"
                )
    return AuditReport(
        env=str(doc["id"]),
        mode="state" if state_mode else "trajectory",
        base_states=len(states),
        actions=len(actions),
        reset_seeds=seeds,
        features=features,
        contradictions=contradictions,
        non_finite=non_finite,
    )
