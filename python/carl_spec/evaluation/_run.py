"""`carl_spec.evaluate`: a policy on every instance of a set, batched in one `make_vec`."""

from __future__ import annotations

import json
import os
from typing import Any, Mapping

import numpy as np

from .. import _core
from .._errors import UnknownNameError
from ._policy import batch_policy, check_actions, describe
from ._result import Episode, Episodes, EvaluationResult, Instance

#: How each episode's seed derives from the evaluation's seed (recorded in the provenance).
SEED_RULE = (
    "mix = SplitMix64's output function (x + 0x9E3779B97F4A7C15, then the xor-shift-multiply "
    "finalizer, mod 2^64); h = mix(mix(mix(seed mod 2^64) ^ instance) ^ episode) >> 1; "
    "instance sets: seed = h - h mod n + instance (a seeded reset of a set with round-robin "
    "selection plays instance seed mod n); distributions (instance = the draw's number) and fixed "
    "contexts (instance 0): seed = h"
)

_U64 = np.uint64


def _mix(x: np.ndarray) -> np.ndarray:
    """SplitMix64's output function on uint64 arrays (wrapping arithmetic)."""
    z = x + _U64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> _U64(30))) * _U64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> _U64(27))) * _U64(0x94D049BB133111EB)
    return z ^ (z >> _U64(31))


def episode_seeds(seed: int, instances: np.ndarray, episodes: np.ndarray, n_instances: int | None) -> np.ndarray:
    """The reset seeds of many episodes at once (`SEED_RULE`), as uint64."""
    base = _mix(np.array([seed % 2**64], dtype=np.uint64))
    h = _mix(_mix(base ^ instances.astype(np.uint64)) ^ episodes.astype(np.uint64)) >> _U64(1)
    if n_instances:
        n = _U64(n_instances)
        h = h - h % n + instances.astype(np.uint64)
    return h


def _episode_seeds(seed: int, instances: np.ndarray, episodes: np.ndarray, n_instances: int | None) -> np.ndarray:
    """`episode_seeds` computed by the binding (the CLI's own function: NumPy's dozen passes over
    the columns cost more than the rest of a short evaluation's bookkeeping)."""
    seeds: np.ndarray = _core.episode_seeds(seed % 2**64, instances, episodes, n_instances or None)
    return seeds


def episode_seed(seed: int, instance: int, episode: int, n_instances: int | None) -> int:
    """The reset seed of one episode: a function of (seed, instance, episode) only, never of the
    batch, so any `num_envs` plays the same episodes (see `SEED_RULE`; `n_instances`: the set's
    size, None for a distribution or a fixed context)."""
    return int(episode_seeds(seed, np.array([instance]), np.array([episode]), n_instances)[0])


def _plain(x: Any) -> Any:
    """Options and contexts as JSON values (tuples as lists, NumPy scalars as numbers)."""
    if isinstance(x, Mapping):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if hasattr(x, "tolist"):
        return x.tolist()
    return x


def _spec_doc(env: str, specs_dir: str | None) -> dict[str, Any]:
    doc: dict[str, Any] = json.loads(_core.spec_json(env, specs_dir))
    return doc


def _canonical(env: str, specs_dir: str | None) -> str:
    """The environment's id (an alias resolved, an unknown name refused with the valid ones)."""
    if env in _core.VERSIONS and specs_dir is None:
        return env
    return str(_spec_doc(env, specs_dir)["id"])


def evaluate(
    policy: Any,
    env: str | None = None,
    *,
    instances: Any = None,
    distribution: str | None = None,
    context: Mapping[str, Any] | None = None,
    episodes: int | None = None,
    draws: int | None = None,
    seed: int = 0,
    num_envs: int | None = None,
    options: Mapping[str, Any] | None = None,
    obs_context: list[str] | bool | None = None,
    context_noise: Mapping[str, Any] | None = None,
    allow_out_of_bounds: bool = False,
    threads: int = 1,
    deterministic: bool = True,
    run: str | int | None = None,
    specs_dir: str | os.PathLike[str] | None = None,
) -> EvaluationResult:
    """Run `policy` on every instance of a set, `episodes` episodes each, in one batched `make_vec`.

    `policy` maps a batch of observations `(num_envs, ...)` to a batch of actions: a function, a
    model with `.predict(obs, deterministic=True)` (Stable-Baselines3), or a `torch.nn.Module`
    (called on a float32 tensor; for a Discrete action space the argmax of its `(batch, n)`
    output). The first batch of actions is checked against the action space (shape, type, bounds).

    What is evaluated, one of:

    * `instances="ENV/SET"` (or an `InstanceSet`, or `env=` with `instances="SET"`): every instance,
      `episodes` (default 10) episodes each;
    * `env=` with `distribution="NAME"`: `draws` (default 100) contexts drawn from the spec's
      distribution, one episode each (each draw is an instance of the result);
    * `env=` with `context={...}` (or nothing: the default context): `episodes` episodes.

    Deterministic: each episode's reset seed is a function of `(seed, instance, episode)` alone
    (`SEED_RULE`), so the same seed gives the same results, and any `num_envs` (default: up to 16)
    or `threads` the same per-episode results (provided the policy's action for an observation does
    not depend on the rest of the batch). `options`, `obs_context`, `context_noise` and
    `allow_out_of_bounds` are `make_vec`'s. `run` labels the result (e.g. the training seed) for
    `carl_spec.report`. The loop runs in the binding (`VecEnv.play`): per batch step Python only
    calls the policy. `carl-spec evaluate` plays the same episodes (same seed rule) from the
    command line.
    """
    from .. import make_vec
    from ..specs import InstanceSet
    from ..specs import instances as iset_api

    sdir = None if specs_dir is None else os.fspath(specs_dir)
    given = [k for k, v in (("instances", instances), ("distribution", distribution), ("context", context)) if v is not None]
    if len(given) > 1:
        raise ValueError(f"evaluate takes one of instances=, distribution= or context=, got {' and '.join(given)}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"evaluate: seed must be a non-negative integer, got {seed!r}")
    seed = int(seed)
    env_id = None
    if env is not None:
        if not isinstance(env, str):
            raise TypeError(f"evaluate: env must be an environment id (a string), got {type(env).__name__}")
        env_id = _canonical(env, sdir)

    # What to evaluate: the instances, the source given to make_vec, the provenance of the source.
    make_source: dict[str, Any]
    if instances is not None:
        if draws is not None:
            raise ValueError("evaluate: draws= is for distribution=; an instance set takes episodes=")
        if isinstance(instances, InstanceSet):
            iset = instances
            fresh = iset_api.load(iset.qualified_name, specs_dir=specs_dir)
            if fresh.content_hash != iset.content_hash:
                raise ValueError(
                    f"evaluate: the InstanceSet {iset.qualified_name} given (hash {iset.content_hash}) is not the one "
                    f"make_vec loads by that name (hash {fresh.content_hash}); pass the specs_dir it came from"
                )
        elif isinstance(instances, str):
            name = instances
            if "/" not in name:
                if env_id is None:
                    raise ValueError(f"evaluate: instances={name!r} needs its environment: 'ENV/{name}' or env=")
                name = f"{env_id}/{name}"
            iset = iset_api.load(name, specs_dir=specs_dir)
        else:
            raise TypeError(f"evaluate: instances must be 'ENV/SET' or an InstanceSet, got {type(instances).__name__}")
        set_env = _canonical(iset.env, sdir)
        if env_id is not None and set_env != env_id:
            raise ValueError(
                f"evaluate: the instance set {iset.qualified_name} belongs to {set_env}, not to {env_id}; "
                f"evaluate {env_id} on one of its own sets (carl_spec.instances.list())"
            )
        env_id = set_env
        n = len(iset)
        inst = [Instance(k, iset.names[k], iset.splits[k], dict(iset.contexts[k])) for k in range(n)]
        per = 10 if episodes is None else episodes
        per_n = _count("episodes", per)
        jobs = (np.tile(np.arange(n, dtype=np.int64), per_n), np.repeat(np.arange(per_n, dtype=np.int64), n))
        # Job e * n + k (episode e of instance k) is the result's row k * per_n + e.
        order: np.ndarray | None = np.arange(n * per_n, dtype=np.int64).reshape(per_n, n).T.ravel()
        make_source = dict(instances=iset.qualified_name, selection="round_robin")
        source: dict[str, Any] = {"kind": "instances", "name": iset.qualified_name, "content_hash": iset.content_hash}
        n_mod: int | None = n
    elif distribution is not None:
        if env_id is None:
            raise ValueError(f"evaluate: distribution={distribution!r} needs env=")
        if episodes is not None:
            raise ValueError("evaluate: a distribution is evaluated on `draws` contexts, one episode each; pass draws=")
        dists = _spec_doc(env_id, sdir).get("distributions", {})
        if distribution not in dists:
            raise UnknownNameError(
                f"evaluate: {env_id} has no distribution {distribution!r}; its distributions: {', '.join(dists) or 'none'}"
            )
        n = _count("draws", 100 if draws is None else draws)
        feats = list(dists[distribution].get("features", {}))
        inst = [Instance(k, None, None, {}) for k in range(n)]  # contexts filled in as drawn
        jobs = (np.arange(n, dtype=np.int64), np.zeros(n, dtype=np.int64))
        order = None  # the jobs are in the result's order
        make_source = dict(distribution=distribution)
        source = {"kind": "distribution", "name": distribution, "draws": n}
        n_mod = None
    else:
        if env_id is None:
            raise ValueError("evaluate: say what to evaluate: instances='ENV/SET', or env= with distribution= or context=")
        if draws is not None:
            raise ValueError("evaluate: draws= is for distribution=; a fixed context takes episodes=")
        ctx = _plain(dict(context)) if context is not None else {}
        inst = [Instance(0, None, None, ctx)]
        per = 10 if episodes is None else episodes
        per_n = _count("episodes", per)
        jobs = (np.zeros(per_n, dtype=np.int64), np.arange(per_n, dtype=np.int64))
        order = None
        make_source = dict(context=ctx or None, allow_out_of_bounds=allow_out_of_bounds)
        source = {"kind": "context", "context": ctx}
        n_mod = None
    if allow_out_of_bounds and "context" not in make_source:
        raise ValueError("evaluate: allow_out_of_bounds is for a fixed context (a set declares its own)")

    total = len(jobs[0])
    if num_envs is None:
        num_envs = min(16, total)
    elif isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
        raise ValueError(f"evaluate: num_envs must be a positive integer, got {num_envs!r}")
    num_envs = min(int(num_envs), total)

    venv = make_vec(
        env_id,
        num_envs,
        autoreset_mode="disabled",
        obs_context=obs_context,
        options=None if options is None else dict(options),
        context_noise=None if context_noise is None else dict(context_noise),
        threads=threads,
        specs_dir=specs_dir,
        **make_source,
    )
    seeds = _episode_seeds(seed, jobs[0], jobs[1], n_mod)
    records: list[Episodes | None] = [None]
    draws_seen: dict[int, tuple[dict[str, Any], int]] = {}
    try:
        with batch_policy(policy, venv.single_action_space, venv.single_observation_space, deterministic) as act:
            core = getattr(venv, "_core", None)
            if hasattr(core, "play"):
                # The loop in Rust: Python runs only the policy, once per batch step; the episodes
                # come back in the result's order.
                _play_native(
                    core, venv, act, jobs, seeds, records, draws_seen, env_id, n_mod is not None, distribution is not None, order
                )
            else:
                _play(venv, act, jobs, seeds.tolist(), records, draws_seen, env_id, distribution is not None)
                assert records[0] is not None
                # Episodes in (instance, episode) order (the jobs are listed episode-major).
                records[0] = records[0].take(np.lexsort((records[0].episode, records[0].instance)))
    finally:
        venv.close()

    played = records[0]
    assert played is not None
    if distribution is not None:
        inst = [Instance(k, None, None, {f: draws_seen[k][0][f] for f in feats}) for k in range(n)]
        played.context_seed = [draws_seen[k][1] for k in played.instance.tolist()]
    provenance = {
        "carl_spec_version": _core.VERSION,
        "env": env_id,
        "env_version": int(_core.VERSIONS[env_id]),
        "gym_id": f"carl_spec/{env_id}-v{int(_core.VERSIONS[env_id])}",
        "source": source,
        "seed": seed,
        "seed_rule": SEED_RULE,
        "episodes": None if distribution is not None else per,
        "options": _plain(dict(options)) if options is not None else None,
        "obs_context": _plain(obs_context),
        "context_noise": _plain(dict(context_noise)) if context_noise is not None else None,
        "policy": describe(policy),
        "deterministic": deterministic,
        "run": run,
        "num_envs": num_envs,
        "threads": threads,
    }
    return EvaluationResult(provenance=provenance, instances=inst, episodes=played)


def _count(what: str, n: Any) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"evaluate: {what} must be a positive integer, got {n!r}")
    return int(n)


def _play_native(
    core: Any,
    venv: Any,
    act: Any,
    jobs: tuple[np.ndarray, np.ndarray],
    seeds: np.ndarray,
    records: list[Episodes | None],
    draws_seen: dict[int, tuple[dict[str, Any], int]],
    env_id: str,
    is_set: bool,
    drawing: bool,
    order: np.ndarray | None,
) -> None:
    """`_play` in the binding (`VecEnv.play`): the same jobs, seeds and episodes, put in
    `records[0]` as one `Episodes` in the result's order (`order`: the jobs in that order, None
    if they are); a set's jobs name their instance, which the seed's round robin would pick
    too."""
    n = venv.num_envs

    def check(actions: Any) -> Any:
        return check_actions(actions, venv.single_action_space, n, env_id)

    rets, lens, terms, truncs, words, contexts = core.play(act, check, seeds, jobs[0] if is_set else None, drawing, order)
    instances, episodes = jobs
    if order is not None:
        instances, episodes, seeds = instances[order], episodes[order], seeds[order]
    records[0] = Episodes(instances, episodes, seeds, rets, lens, terms, truncs, words)
    if drawing:
        for k, (ctx, context_seed) in zip(instances.tolist(), contexts):
            draws_seen[k] = (ctx, int(context_seed))


def _play(
    venv: Any,
    act: Any,
    job_columns: tuple[np.ndarray, np.ndarray],
    seeds: list[int],
    records: list[Episodes | None],
    draws_seen: dict[int, tuple[dict[str, Any], int]],
    env_id: str,
    drawing: bool,
) -> None:
    """Step the batch until every job (instance, episode) has finished one episode. Environment i
    starts job i; whenever an episode ends its environment is reset (autoreset disabled) with the
    next job's seed. Once the jobs run out, finished environments replay their last seed so the
    batch can go on stepping; those episodes are not recorded. The episodes go to `records[0]`,
    in job order."""
    n = venv.num_envs
    jobs = list(zip(job_columns[0].tolist(), job_columns[1].tolist()))
    total = len(jobs)
    played: list[Episode | None] = [None] * total
    job_of = list(range(n))  # the job each environment plays (-1: idle)
    next_job = n
    ret = np.zeros(n, dtype=np.float64)
    start = np.zeros(n, dtype=np.int64)
    obs, infos = venv.reset(seed=[seeds[j] for j in job_of])
    _check_started(venv, infos, jobs, job_of, range(n), draws_seen, drawing)
    step = venv.step
    t = 0
    remaining = total
    first = True
    while remaining:
        actions = act(obs)
        if first:
            actions = check_actions(actions, venv.single_action_space, n, env_id)
            first = False
        obs, reward, terminated, truncated, infos = step(actions)
        ret += reward
        t += 1
        # A bool array's bytes searched for a 1: a fraction of ndarray.any()'s cost (paid at
        # every batch step).
        if not (1 in terminated.tobytes() or 1 in truncated.tobytes()):
            continue
        done = np.flatnonzero(terminated | truncated)
        reset_seeds: list[int | None] = [None] * n
        started = []
        outcome = infos.get("outcome")
        has_outcome = infos.get("_outcome")
        # Per finished episode, Python lists rather than NumPy scalars (indexing an array is
        # several times slower than a list, and here every batch step ends episodes).
        done_l = done.tolist()
        rets = ret[done].tolist()
        starts = start[done].tolist()
        terms = terminated[done].tolist()
        truncs = truncated[done].tolist()
        words: list[str | None] = [None] * len(done_l)
        if outcome is not None:
            has = has_outcome[done].tolist() if has_outcome is not None else [True] * len(done_l)
            words = [str(w) if h else None for w, h in zip(outcome[done].tolist(), has)]
        for i, r_i, s_i, te, tr, out in zip(done_l, rets, starts, terms, truncs, words):
            j = job_of[i]
            if j >= 0:
                k, e = jobs[j]
                played[j] = Episode(k, e, seeds[j], r_i, t - s_i, te, tr, out)
                remaining -= 1
                if next_job < total:
                    job_of[i] = next_job
                    next_job += 1
                    started.append(i)
                    reset_seeds[i] = seeds[job_of[i]]
                else:
                    job_of[i] = -1
                    reset_seeds[i] = seeds[j]
            else:
                reset_seeds[i] = seeds[0]
        ret[done] = 0.0
        start[done] = t
        if not remaining:
            break
        mask = np.zeros(n, dtype=np.bool_)
        mask[done] = True
        obs, infos = venv.reset(seed=reset_seeds, options={"reset_mask": mask})
        if started:
            _check_started(venv, infos, jobs, job_of, started, draws_seen, drawing)
    records[0] = Episodes.of(e for e in played if e is not None)


def _check_started(
    venv: Any,
    infos: dict[str, Any],
    jobs: list[tuple[int, int]],
    job_of: list[int],
    envs: Any,
    draws_seen: dict[int, tuple[dict[str, Any], int]],
    drawing: bool,
) -> None:
    """After a reset: each environment plays the instance its job names (a set's round robin
    picks instance seed mod n), and a distribution's draws are recorded."""
    ids = infos.get("instance_id")
    for i in envs:
        k = jobs[job_of[i]][0]
        if ids is not None and not drawing and int(ids[i]) != k:
            raise RuntimeError(
                f"evaluate: environment {i} was reset to play instance {k} but plays {int(ids[i])}; "
                "the batch's instance selection differs from what evaluate relies on (round robin from the seed)"
            )
        if drawing:
            info = venv.context_info(i)
            draws_seen[k] = (info["context"], int(info["context_seed"]))
