#!/usr/bin/env python3
"""Steps per second through the Python API, each workload beside its anchor in the same run.

    python python/bench/bench_python_api.py [--seconds S] [--rounds R] [--only NAME ...]
    python python/bench/bench_python_api.py --fixed-steps K --only NAME    # for callgrind

Every workload runs `R` rounds; in each round the anchor and carl-spec are timed for ~S seconds
each, one after the other (the order alternates between rounds), so both see the same machine
load. The physics workloads time carl-spec over exactly the batch steps the Rust `VecEnv` anchor
times (same reset, same actions, same window after the reset: `same_window`). Printed: one JSON
line per workload with the median rate of each side, their ratio and the load average before
and after. Anchors: Gymnasium 1.x's NumPy `CartPoleVectorEnv`, Gymnasium's CartPole through
`gymnasium.make`, envpool (if importable) and the Rust `VecEnv` itself, twice: `carl-spec bench`
(the binary in target/release or $CARL_SPEC_BIN, a process of its own) and the same batch's
native loop in this process, timed in short chunks (40 per side and round) alternating with
carl-spec's along one run (`chunked_pair`). Names: import, vec_cartpole, make_cartpole,
lunar_lander, bipedal_walker, half_cheetah, ant.

`--fixed-steps K` times nothing: it resets the physics workload's batch (1 thread) with seed 0
and runs K batch steps of the bench actions, for an instruction count that does not depend on the
machine's load (README, "Speed through the Python API"):
    valgrind --tool=callgrind python python/bench/bench_python_api.py --fixed-steps K --only NAME
Instructions per batch step = (I(K2) - I(K1)) / (K2 - K1) (start-up cancels out). With `--native`
the same K batch steps run in the batch's native loop (`VecEnv.native_steps`): the difference is
what the binding, its outputs and the Python loop add per batch step.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

if TYPE_CHECKING:
    from carl_spec import CarlVectorEnv

ROOT = Path(__file__).resolve().parents[2]


def timed(step: Callable[[], None], steps_per_call: int, seconds: float) -> float:
    """Environment steps per second of `step` called for ~`seconds`."""
    for _ in range(3):
        step()
    n, t0 = 0, time.perf_counter()
    while (t := time.perf_counter() - t0) < seconds:
        for _ in range(10):
            step()
        n += 10
    return n * steps_per_call / t


def interleaved(sides: dict[str, Callable[[], float | dict[str, float]]], rounds: int) -> dict[str, Any]:
    """Each side's median over `rounds` rounds (alternating order), plus the load average. A side
    may time several things at once and return their rates by name (`chunked_pair`)."""
    load_before = os.getloadavg()[0]
    rates: dict[str, list[float]] = {}
    order = list(sides)
    for r in range(rounds):
        for side in order if r % 2 == 0 else order[::-1]:
            got = sides[side]()
            for name, rate in (got if isinstance(got, dict) else {side: got}).items():
                rates.setdefault(name, []).append(rate)
    names = list(rates)
    out: dict[str, Any] = {k: round(statistics.median(v)) for k, v in rates.items()}
    out["runs"] = {k: [round(x) for x in v] for k, v in rates.items()}
    # carl-spec over each anchor round by round (both timed back to back), then the median: robust
    # to the machine's speed drifting between rounds.
    ours = [k for k in names if k.startswith("carl_spec")]
    out["paired_ratio_medians"] = {
        f"{a}/{b}": round(statistics.median(x / y for x, y in zip(rates[a], rates[b])), 3)
        for a in ours
        for b in names
        if b not in ours
    }
    out["load_average"] = [round(load_before, 1), round(os.getloadavg()[0], 1)]
    return out


def cycle(actions: list[Any], fn: Callable[[Any], Any]) -> Callable[[], None]:
    i = [0]

    def step() -> None:
        i[0] = (i[0] + 1) % len(actions)
        fn(actions[i[0]])

    return step


def vec_cartpole(seconds: float, rounds: int) -> dict[str, Any]:
    import carl_spec as cs
    from gymnasium.envs.classic_control.cartpole import CartPoleVectorEnv

    n = 1024
    rng = np.random.default_rng(0)
    acts = [rng.integers(0, 2, size=n) for _ in range(64)]
    ref = CartPoleVectorEnv(num_envs=n)
    ref.reset(seed=0)
    same = cs.make_vec("cartpole", n, autoreset_mode="same_step", threads=1)
    same.reset(seed=0)
    nxt = cs.make_vec("cartpole", n, autoreset_mode="next_step", threads=1)
    nxt.reset(seed=0)
    row = interleaved(
        {
            "gymnasium_CartPoleVectorEnv": lambda: timed(cycle(acts, ref.step), n, seconds),
            "carl_spec_next_step": lambda: timed(cycle(acts, nxt.step), n, seconds),
            "carl_spec_same_step": lambda: timed(cycle(acts, same.step), n, seconds),
        },
        rounds,
    )
    g = row["gymnasium_CartPoleVectorEnv"]
    return {
        "workload": "make_vec('cartpole', 1024), 1 thread",
        **row,
        "ratio_next_step": round(row["carl_spec_next_step"] / g, 2),
        "ratio_same_step": round(row["carl_spec_same_step"] / g, 2),
    }


def make_cartpole(seconds: float, rounds: int) -> dict[str, Any]:
    import gymnasium

    import carl_spec  # noqa: F401  (registers carl_spec/*)

    def side(gym_id: str) -> Callable[[], float]:
        env = gymnasium.make(gym_id)
        env.reset(seed=0)
        rng = np.random.default_rng(0)
        acts = [int(a) for a in rng.integers(0, 2, size=256)]

        def act(a: int) -> None:
            _, _, term, trunc, _ = env.step(a)
            if term or trunc:
                env.reset()

        return lambda: timed(cycle(acts, act), 1, seconds)

    row = interleaved({"gymnasium_CartPole-v1": side("CartPole-v1"), "carl_spec": side("carl_spec/cartpole-v0")}, rounds)
    return {
        "workload": "gymnasium.make cartpole, 1 env",
        **row,
        "ratio": round(row["carl_spec"] / row["gymnasium_CartPole-v1"], 2),
    }


def rust_vec_rate(env_id: str, n: int, threads: int, batch_steps: int) -> float:
    """`carl-spec bench`'s VecEnv rate over `batch_steps` timed batch steps (see `same_window`)."""
    binary = os.environ.get("CARL_SPEC_BIN", str(ROOT / "target" / "release" / "carl-spec"))
    out = subprocess.run(
        [binary, "bench", env_id, "--num-envs", str(n), "--threads", str(threads), "--steps", str(n * batch_steps)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return float(json.loads(out.strip().splitlines()[-1])["vec_steps_per_sec"])


def bench_actions(space: Any, n: int) -> list[np.ndarray]:
    """The very batches `carl-spec bench` cycles through (src/bench.rs `ActionTable`: NumPy's
    `default_rng(0x5eed)`, uniform in the box, min(64, 65536 // n) batches), so both sides run the
    same episodes: a physics step's cost depends on the state (contacts, resets)."""
    rng = np.random.default_rng(0x5EED)
    batches = max(1, min(64, 65536 // n))
    if not hasattr(space, "low"):  # Discrete: raw 64-bit draws modulo n
        raw = np.array([rng.bit_generator.random_raw() for _ in range(batches * n)], dtype=np.uint64)
        draws = (space.start + (raw % np.uint64(space.n)).astype(np.int64)).reshape(batches, n)
        return list(draws)
    low, high = space.low.astype(np.float64), space.high.astype(np.float64)
    dim = low.size
    values = low.repeat(1)[np.arange(batches * n * dim) % dim]
    span = (high - low)[np.arange(batches * n * dim) % dim]
    flat = (values + span * rng.random(batches * n * dim)).astype(np.float32)
    return [b.reshape(n, dim) for b in flat.reshape(batches, n * dim)]


def warmup_steps(batch_steps: int) -> int:
    """Untimed batch steps `carl-spec bench` runs before its timed ones (src/bench.rs
    `vec_steps_per_sec`)."""
    return min(max(batch_steps // 10, 1), 1000)


def same_window(venv: "CarlVectorEnv", acts: list[np.ndarray], batch_steps: int) -> float:
    """Steps per second of `venv` over exactly the steps `carl-spec bench --steps n*batch_steps`
    times: reset with seed 0, `warmup_steps` untimed batch steps, then `batch_steps` timed, the
    action batches taken in the same order (batch 1 first). A physics step's cost depends on the
    episode's phase (BipedalWalker: ~20 % more per step after a few hundred steps, walkers down
    with many contacts), so both sides must time the same window of the same episodes."""
    venv.reset(seed=0)
    step = cycle(acts, venv.step)
    for _ in range(warmup_steps(batch_steps)):
        step()
    t0 = time.perf_counter()
    for _ in range(batch_steps):
        step()
    return batch_steps * venv.num_envs / (time.perf_counter() - t0)


def native_run(venv: "CarlVectorEnv", acts: list[np.ndarray], first: int, k: int) -> None:
    """`k` batch steps in the batch's native loop (`VecEnv.native_steps`), the action batches
    cycled from batch `first`."""
    f = first % len(acts)
    venv._core.native_steps(acts[f:] + acts[:f], k)


def chunked_pair(venv: "CarlVectorEnv", acts: list[np.ndarray], batch_steps: int, chunk: int) -> dict[str, float]:
    """carl-spec through the Python API (`venv.step`) and the same batch's native loop
    (`VecEnv.native_steps`), `batch_steps` timed batch steps each, in alternating chunks of
    `chunk` batch steps along one run from reset(seed=0) (after `warmup_steps` untimed ones), the
    actions cycled on across chunks. Machine speed drifts over seconds (rounds a few seconds
    apart differ by up to ~20 %); short alternating chunks see the same drift, so the ratio of
    the two sums is the Python layer's own cost."""
    venv.reset(seed=0)
    at = [0]

    def python(k: int) -> None:
        for _ in range(k):
            at[0] = (at[0] + 1) % len(acts)
            venv.step(acts[at[0]])

    def native(k: int) -> None:
        native_run(venv, acts, at[0] + 1, k)
        at[0] = (at[0] + k) % len(acts)

    python(warmup_steps(batch_steps))
    sides = {"carl_spec": python, "rust_VecEnv_in_process": native}
    spent = dict.fromkeys(sides, 0.0)
    done, turn = 0, 0
    while done < batch_steps:
        k = min(chunk, batch_steps - done)
        for name in list(sides) if turn % 2 == 0 else list(sides)[::-1]:
            t0 = time.perf_counter()
            sides[name](k)
            spent[name] += time.perf_counter() - t0
        done, turn = done + k, turn + 1
    return {name: batch_steps * venv.num_envs / t for name, t in spent.items()}


def vec_physics(env_id: str, envpool_id: str | None, n: int, threads: int, seconds: float, rounds: int) -> dict[str, Any]:
    import carl_spec as cs

    venv = cs.make_vec(env_id, n, autoreset_mode="same_step", threads=threads)
    venv.reset(seed=0)
    acts = bench_actions(venv.single_action_space, n)
    # Batch steps per round: what carl-spec does in ~`seconds` from a reset, fixed for every round
    # and both sides.
    batch_steps = max(20, round(seconds * same_window(venv, acts, 20) / n))
    # carl-spec and its in-process native anchor in alternating chunks of one run, 40 per side.
    chunk = max(1, batch_steps // 40)
    sides: dict[str, Callable[[], float | dict[str, float]]] = {
        "carl_spec+rust_VecEnv_in_process": lambda: chunked_pair(venv, acts, batch_steps, chunk),
        "rust_VecEnv": lambda: rust_vec_rate(env_id, n, threads, batch_steps),
    }
    if envpool_id is not None:
        try:
            import envpool
        except ImportError:
            envpool = None  # type: ignore[assignment]
        if envpool is not None:

            def envpool_rate() -> float:
                # Built and closed within its own turn: envpool's worker threads must not compete
                # with the other sides' turns in this process.
                pool = envpool.make_gymnasium(envpool_id, num_envs=n, num_threads=threads, seed=0)
                pool.reset()
                pool.action_space.seed(0)
                pacts = [np.stack([pool.action_space.sample() for _ in range(n)]) for _ in range(16)]
                try:
                    return timed(cycle(pacts, pool.step), n, seconds)
                finally:
                    pool.close()

            sides["envpool"] = envpool_rate
    row = interleaved(sides, rounds)
    out = {
        "workload": f"make_vec('{env_id}', {n}), {threads} threads",
        "timed_batch_steps": batch_steps,
        "chunk_batch_steps": chunk,
        **row,
    }
    out["fraction_of_rust_VecEnv"] = round(row["carl_spec"] / row["rust_VecEnv"], 3)
    out["fraction_of_rust_VecEnv_in_process"] = round(row["carl_spec"] / row["rust_VecEnv_in_process"], 3)
    if "envpool" in row:
        out["ratio_to_envpool"] = round(row["carl_spec"] / row["envpool"], 2)
    return out


PHYSICS = {
    "lunar_lander": ("lunar_lander", "LunarLander-v3", 64, 2),
    "bipedal_walker": ("bipedal_walker", "BipedalWalker-v3", 64, 2),
    "half_cheetah": ("half_cheetah", "HalfCheetah-v5", 16, 2),
    "ant": ("ant", "Ant-v5", 16, 2),
}


def fixed_steps(name: str, k: int, native: bool) -> None:
    """`k` batch steps of a physics workload from reset(seed=0) on 1 thread, untimed; `native`:
    the same steps by the batch's native loop (`VecEnv.native_steps`), for the binding's share."""
    import carl_spec as cs

    env_id, _, n, _ = PHYSICS[name]
    venv = cs.make_vec(env_id, n, autoreset_mode="same_step", threads=1)
    venv.reset(seed=0)
    acts = bench_actions(venv.single_action_space, n)
    if native:
        native_run(venv, acts, 1, k)  # `cycle` takes batch 1 first
        return
    step = cycle(acts, venv.step)
    for _ in range(k):
        step()


def import_and_make(rounds: int) -> dict[str, Any]:
    """`import carl_spec; cs.make("cartpole")` in fresh processes: the total, and NumPy +
    Gymnasium alone (imported first in the same process), which any Gymnasium environment pays."""
    code = (
        "import time; t0 = time.perf_counter(); import numpy, gymnasium; t1 = time.perf_counter(); "
        "import carl_spec as cs; cs.make('cartpole'); t2 = time.perf_counter(); print(t2 - t0, t2 - t1)"
    )
    # An installed package has its bytecode compiled (pip does it); an editable build under
    # PYTHONDONTWRITEBYTECODE=1 would compile carl_spec's sources in every timed run.
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    subprocess.run([sys.executable, "-c", code], capture_output=True, check=True, env=env)
    total, own = [], []
    for _ in range(max(rounds, 5)):
        a, b = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env).stdout.split()
        total.append(float(a))
        own.append(float(b))
    return {
        "workload": "import carl_spec; cs.make('cartpole') (fresh process)",
        "seconds_median": round(statistics.median(total), 3),
        "numpy_and_gymnasium_median": round(statistics.median(t - o for t, o in zip(total, own)), 3),
        "beyond_numpy_and_gymnasium_median": round(statistics.median(own), 3),
        "seconds_all": [round(x, 3) for x in total],
        "load_average": round(os.getloadavg()[0], 1),
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seconds", type=float, default=1.0, help="time per side per round")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--only", nargs="*", default=None)
    p.add_argument("--fixed-steps", type=int, default=None, metavar="K", help="run K batch steps untimed (callgrind)")
    p.add_argument("--native", action="store_true", help="with --fixed-steps: the same steps by the native loop")
    args = p.parse_args()
    s, r = args.seconds, args.rounds
    if args.fixed_steps is not None:
        if not args.only or any(name not in PHYSICS for name in args.only):
            p.error(f"--fixed-steps needs --only with names among {', '.join(PHYSICS)}")
        for name in args.only:
            fixed_steps(name, args.fixed_steps, args.native)
        return
    work: dict[str, Callable[[], dict[str, Any]]] = {
        "import": lambda: import_and_make(r),
        "vec_cartpole": lambda: vec_cartpole(s, r),
        "make_cartpole": lambda: make_cartpole(s, r),
    }
    for name, (env_id, envpool_id, n, threads) in PHYSICS.items():
        work[name] = functools.partial(vec_physics, env_id, envpool_id, n, threads, s, r)
    for name, run in work.items():
        if args.only is None or name in args.only:
            print(json.dumps(run()), flush=True)


if __name__ == "__main__":
    main()
