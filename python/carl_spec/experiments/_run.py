"""Trials of the paper's experiments, how they run (in turn or on Ray), and their reports.

With a checkpoint folder, every finished trial is written there at once (`<key>.json`, with the
versions that computed it) and a later run of the same trials takes it from there instead of
training again: an experiment of hours that is interrupted keeps what it finished.
"""

from __future__ import annotations

import json
import math
import os
import statistics
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import carl_spec as cs

PAPER_STEPS = 1_000_000
#: The fewest training steps of a trial, whatever the budget (a smoke test's).
MIN_STEPS = 300
FEATURES = ("g", "l", "m", "dt", "max_speed")
SIGMAS = (0.1, 0.25, 0.5)
#: The paper's Table 3 (rl-zoo3's LunarLander DQN).
DQN_HYPERPARAMETERS: dict[str, Any] = dict(
    learning_rate=6.3e-4,
    batch_size=128,
    buffer_size=50_000,
    learning_starts=0,
    gamma=0.99,
    target_update_interval=250,
    train_freq=4,
    gradient_steps=-1,
    exploration_fraction=0.12,
    exploration_final_eps=0.1,
    policy_kwargs=dict(net_arch=[256, 256]),
)
#: The paper's test-time game-over penalty (−100 → −10000), as the option's magnitude.
TEST_CRASH_PENALTY = 10_000.0
#: Surface gravity over Earth's, for ordering the planets (the set holds g_earth times these).
PLANETS = ("Pluto", "Moon", "Mars", "Earth", "Neptune", "Jupiter")


@dataclass(frozen=True)
class Trial:
    """One training run and its evaluation."""

    experiment: str
    seed: int
    steps: int
    visible: bool
    feature: str | None = None
    sigma: float | None = None
    test_episodes: int = 100
    evaluations: int = 1

    @property
    def train_set(self) -> str:
        if self.experiment == "q3":
            return "lunar_lander/landing_in_space_train"
        return f"pendulum/q1_{self.feature}_sigma_{_sigma_label(self.sigma or 0.0)}"


def _sigma_label(s: float) -> str:
    return str(s).replace(".", "_")


def trials(
    experiment: str,
    *,
    budget: float,
    seeds: int = 5,
    features: Sequence[str] = FEATURES,
    test_episodes: int = 100,
    evaluations: int = 4,
) -> list[Trial]:
    """The trials of `experiment` at `budget` (a fraction of the paper's 10^6 steps per trial)."""
    if experiment not in EXPERIMENTS:
        raise ValueError(f"no experiment {experiment!r}; experiments: {', '.join(EXPERIMENTS)}")
    if not (isinstance(budget, (int, float)) and math.isfinite(budget) and 0 < budget <= 10):
        raise ValueError(f"budget must be a number in (0, 10] (1: the paper's 10^6 steps per trial), got {budget!r}")
    if not (isinstance(seeds, int) and 1 <= seeds <= 100):
        raise ValueError(f"seeds must be an int in 1..=100, got {seeds!r}")
    unknown = [f for f in features if f not in FEATURES]
    if unknown or not features:
        raise ValueError(f"features must be some of {', '.join(FEATURES)}, got {list(features)}")
    # At least 300 steps: DDPG's 100 steps of random actions before it learns, and some learning.
    steps = max(MIN_STEPS, round(budget * PAPER_STEPS))

    def trial(seed: int, visible: bool, feature: str | None = None, sigma: float | None = None) -> Trial:
        return Trial(experiment, seed, steps, visible, feature, sigma, test_episodes, evaluations)

    if experiment == "q1":
        return [trial(s, False, f, sig) for f in features for sig in SIGMAS for s in range(seeds)]
    if experiment == "q2":
        return [trial(s, v, f, 0.5) for f in features for v in (False, True) for s in range(seeds)]
    return [trial(s, v) for v in (False, True) for s in range(seeds)]


def run_trial(trial: Trial) -> dict[str, Any]:
    """Train and evaluate one trial; its numbers (JSON-serializable)."""
    import torch
    from stable_baselines3 import DDPG, DQN

    torch.set_num_threads(1)
    start = time.perf_counter()
    if trial.experiment == "q3":
        obs_context = ["GRAVITY_Y"] if trial.visible else None
        env = cs.make("lunar_lander", instances=trial.train_set, obs_context=obs_context, selection="random")
        model = DQN("MlpPolicy", env, seed=trial.seed, verbose=0, **DQN_HYPERPARAMETERS)
        _quiet_logger(model)
        model.learn(trial.steps)
        train_seconds = time.perf_counter() - start
        test = cs.evaluate(
            model,
            instances="lunar_lander/landing_in_space_test_planets",
            episodes=trial.test_episodes,
            seed=1_000 + trial.seed,
            obs_context=obs_context,
            options={"crash_penalty": TEST_CRASH_PENALTY},
            run=trial.seed,
        )
        planets = {}
        for inst in test.instances:
            eps = [e for e in test.episodes if e.instance == inst.id]
            planets[inst.name] = {
                "gravity": inst.context["GRAVITY_Y"],
                "split": inst.split,
                "mean_return": statistics.fmean(e.return_ for e in eps),
                # Game over, as the penalty counts it: crashed, or flown out of view.
                "crash_rate": sum(e.outcome in ("crashed", "out_of_view") for e in eps) / len(eps),
                "out_of_view_rate": sum(e.outcome == "out_of_view" for e in eps) / len(eps),
                "landed_rate": sum(e.outcome == "landed" for e in eps) / len(eps),
            }
        return {"trial": asdict(trial), "train_seconds": train_seconds, "planets": planets}

    obs_context = [trial.feature] if trial.visible and trial.feature else None
    env = cs.make("pendulum", instances=trial.train_set, obs_context=obs_context)
    model = DDPG("MlpPolicy", env, seed=trial.seed, verbose=0)
    _quiet_logger(model)
    curve = []
    chunk = trial.steps // max(1, trial.evaluations)
    done = 0
    for k in range(max(1, trial.evaluations)):
        n = trial.steps - done if k == trial.evaluations - 1 else chunk
        model.learn(n, reset_num_timesteps=False)
        done += n
        # As the paper: one episode on each training instance, the mean return.
        res = cs.evaluate(model, instances=trial.train_set, episodes=1, seed=10_000 + trial.seed, obs_context=obs_context)
        curve.append({"steps": done, "mean_return": res.mean_return})
    return {"trial": asdict(trial), "train_seconds": time.perf_counter() - start, "curve": curve}


def _quiet_logger(model: Any) -> None:
    """A logger that writes nothing: without one, SB3's `learn` makes a `$TMPDIR/SB3-<date>` folder
    for every trial (SB3_LOGDIR is not seen by Ray's workers)."""
    from stable_baselines3.common.logger import Logger

    model.set_logger(Logger(folder=None, output_formats=[]))


def trial_key(trial: Trial) -> str:
    """The trial's file name in a checkpoint folder: every field that changes its numbers."""
    parts = [trial.experiment, f"seed{trial.seed}", f"steps{trial.steps}", "visible" if trial.visible else "hidden"]
    if trial.feature is not None:
        parts.append(trial.feature)
    if trial.sigma is not None:
        parts.append(f"sigma{_sigma_label(trial.sigma)}")
    if trial.experiment == "q3":
        parts.append(f"test{trial.test_episodes}")
    else:
        parts.append(f"evaluations{trial.evaluations}")
    return "-".join(parts)


def _versions() -> dict[str, str]:
    import stable_baselines3
    import torch

    return {"carl_spec": cs.__version__, "stable_baselines3": stable_baselines3.__version__, "torch": torch.__version__}


class _Checkpoint:
    """Finished trials in a folder, one JSON file each, reused only by the same trial computed by
    the same versions."""

    def __init__(self, folder: Path | None) -> None:
        self.folder = folder
        self.versions = _versions()

    def load(self, trial: Trial) -> dict[str, Any] | None:
        if self.folder is None:
            return None
        f = self.folder / f"{trial_key(trial)}.json"
        try:
            saved = json.loads(f.read_text())
        except (OSError, ValueError):
            return None
        if not isinstance(saved, dict) or saved.get("versions") != self.versions:
            return None
        result = saved.get("result")
        if not isinstance(result, dict) or result.get("trial") != asdict(trial):
            return None
        return result

    def save(self, trial: Trial, result: dict[str, Any]) -> None:
        if self.folder is None:
            return
        self.folder.mkdir(parents=True, exist_ok=True)
        f = self.folder / f"{trial_key(trial)}.json"
        tmp = f.with_name(f".{f.name}.tmp")
        tmp.write_text(json.dumps({"versions": self.versions, "result": result}, indent=1) + "\n")
        tmp.replace(f)  # atomic: an interrupted write leaves no half file under the trial's name


def _run_all(
    todo: list[Trial], ray: bool, progress: Callable[[str], None], checkpoint: Path | None = None
) -> list[dict[str, Any]]:
    store = _Checkpoint(checkpoint)
    done: dict[int, dict[str, Any]] = {}
    for i, t in enumerate(todo):
        r = store.load(t)
        if r is not None:
            done[i] = r
    if done:
        progress(f"{len(done)} of {len(todo)} trials taken from {checkpoint}")
    pending = [i for i in range(len(todo)) if i not in done]

    def finished(i: int, result: dict[str, Any]) -> None:
        done[i] = result
        store.save(todo[i], result)
        progress(f"trial {len(done)}/{len(todo)} done ({result['train_seconds']:.0f} s)")

    if not ray or not pending:
        for i in pending:
            finished(i, run_trial(todo[i]))
        return [done[i] for i in range(len(todo))]
    # Before Ray is imported: every Ray socket on 127.0.0.1, no usage report over the network.
    os.environ["RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"] = "0"
    os.environ["RAY_USAGE_STATS_ENABLED"] = "0"
    import ray as ray_mod

    started = not ray_mod.is_initialized()
    if started:
        ray_mod.init(
            address="local",
            _node_ip_address="127.0.0.1",
            include_dashboard=False,
            log_to_driver=False,
            configure_logging=False,
        )
    try:
        addresses = [n["NodeManagerAddress"] for n in ray_mod.nodes()] + [ray_mod.util.get_node_ip_address()]
        if any(a != "127.0.0.1" for a in addresses):
            raise RuntimeError(f"Ray is not bound to loopback only: {addresses}")
        remote = ray_mod.remote(num_cpus=1)(run_trial)
        running = {remote.remote(todo[i]): i for i in pending}
        while running:
            ready, _ = ray_mod.wait(list(running), num_returns=1)
            for ref in ready:
                finished(running.pop(ref), ray_mod.get(ref))
        return [done[i] for i in range(len(todo))]
    finally:
        if started:
            ray_mod.shutdown()


def _mean_std(xs: Sequence[float]) -> dict[str, float]:
    return {"mean": statistics.fmean(xs), "std": statistics.pstdev(xs) if len(xs) > 1 else 0.0, "n": len(xs)}


def _final(result: dict[str, Any]) -> float:
    return float(result["curve"][-1]["mean_return"])


def _mode(trial: dict[str, Any]) -> str:
    return "visible" if trial["visible"] else "hidden"


def _finals_by_feature_mode(results: list[dict[str, Any]]) -> dict[str, dict[str, list[float]]]:
    """q2: each feature's final returns, per context mode (hidden, visible), one per seed."""
    table: dict[str, dict[str, list[float]]] = {}
    for r in results:
        t = r["trial"]
        table.setdefault(t["feature"], {}).setdefault(_mode(t), []).append(_final(r))
    return table


def _planets_by_mode(results: list[dict[str, Any]]) -> dict[str, dict[str, dict[str, list[float]]]]:
    """q3: each planet's mean return and game-over rate, per context mode, one per seed."""
    per: dict[str, dict[str, dict[str, list[float]]]] = {}
    for r in results:
        for name, p in r["planets"].items():
            d = per.setdefault(_mode(r["trial"]), {}).setdefault(name, {"mean_return": [], "crash_rate": []})
            d["mean_return"].append(p["mean_return"])
            d["crash_rate"].append(p["crash_rate"])
    return per


def _spearman(xs: Sequence[float], ys: Sequence[float]) -> float:
    def ranks(v: Sequence[float]) -> list[float]:
        order = sorted(range(len(v)), key=lambda i: v[i])
        r = [0.0] * len(v)
        i = 0
        while i < len(order):
            j = i
            while j + 1 < len(order) and v[order[j + 1]] == v[order[i]]:
                j += 1
            for k in range(i, j + 1):
                r[order[k]] = (i + j) / 2
            i = j + 1
        return r

    rx, ry = ranks(xs), ranks(ys)
    mx, my = statistics.fmean(rx), statistics.fmean(ry)
    num = sum((a - mx) * (b - my) for a, b in zip(rx, ry))
    den = math.sqrt(sum((a - mx) ** 2 for a in rx) * sum((b - my) ** 2 for b in ry))
    return num / den if den else 0.0


def _summarize(experiment: str, results: list[dict[str, Any]]) -> dict[str, Any]:
    if experiment == "q1":
        table: dict[str, dict[str, Any]] = {}
        for r in results:
            t = r["trial"]
            table.setdefault(t["feature"], {}).setdefault(_sigma_label(t["sigma"]), []).append(_final(r))
        agg = {f: {s: _mean_std(v) for s, v in by.items()} for f, by in table.items()}
        # The paper: the wider the distribution, the harder (lower return at 0.5 than at 0.1).
        harder = {f: by["0_5"]["mean"] < by["0_1"]["mean"] for f, by in agg.items() if "0_5" in by and "0_1" in by}
        findings = [
            {
                "claim": "a wider context distribution (σ_rel 0.5 vs 0.1) lowers the final return",
                "holds": all(harder.values()),
                "numbers": {f: {"0_1": agg[f]["0_1"]["mean"], "0_5": agg[f]["0_5"]["mean"]} for f in harder},
            }
        ]
        return {"final_return": agg, "findings": findings}
    if experiment == "q2":
        agg = {f: {k: _mean_std(v) for k, v in by.items()} for f, by in _finals_by_feature_mode(results).items()}
        gain = {f: by["visible"]["mean"] - by["hidden"]["mean"] for f, by in agg.items() if {"visible", "hidden"} <= set(by)}
        top = sorted(gain, key=lambda f: gain[f], reverse=True)[:3]
        findings = [
            {
                "claim": "visible context helps most for g, l and m (σ_rel = 0.5)",
                "holds": len(gain) == len(FEATURES) and set(top) == {"g", "l", "m"},
                "numbers": {"gain_visible_minus_hidden": gain, "top3": top},
            }
        ]
        return {"final_return": agg, "findings": findings}
    gravity: dict[str, float] = {}
    split: dict[str, str] = {}
    for r in results:
        for name, p in r["planets"].items():
            gravity[name], split[name] = p["gravity"], p["split"]
    per = _planets_by_mode(results)
    agg3 = {m: {n: {k: _mean_std(v) for k, v in d.items()} for n, d in by.items()} for m, by in per.items()}
    findings = []
    for mode, by in agg3.items():
        names = sorted(by, key=lambda n: abs(gravity[n]))
        crash = [by[n]["crash_rate"]["mean"] for n in names]
        rho = _spearman([abs(gravity[n]) for n in names], crash)
        ood = [n for n in names if split[n] == "out_of_distribution"]
        best_ood = max(ood, key=lambda n: by[n]["mean_return"]["mean"]) if ood else None
        findings.append(
            {
                "claim": f"crashes grow with gravity ({mode} context)",
                "holds": rho > 0,
                "numbers": {"spearman_abs_gravity_vs_crash_rate": rho, "crash_rate": dict(zip(names, crash))},
            }
        )
        findings.append(
            {
                "claim": f"Pluto is the best out-of-distribution planet ({mode} context)",
                "holds": best_ood == "Pluto",
                "numbers": {"best_ood": best_ood, "mean_return": {n: by[n]["mean_return"]["mean"] for n in ood}},
            }
        )
    return {"planets": agg3, "gravity": gravity, "split": split, "findings": findings}


def run_experiment(
    experiment: str,
    *,
    budget: float,
    seeds: int = 5,
    features: Sequence[str] = FEATURES,
    test_episodes: int = 100,
    evaluations: int = 4,
    ray: bool = False,
    progress: Callable[[str], None] = lambda _: None,
    checkpoint: str | os.PathLike[str] | None = None,
) -> dict[str, Any]:
    """Run every trial of `experiment` and summarize them against the paper's findings.

    `checkpoint`: a folder where each finished trial is saved at once, and from which the trials
    already there (the same trial, the same versions) are taken instead of trained again."""
    todo = trials(
        experiment, budget=budget, seeds=seeds, features=features, test_episodes=test_episodes, evaluations=evaluations
    )
    start = time.perf_counter()
    results = _run_all(todo, ray, progress, Path(checkpoint) if checkpoint is not None else None)

    return {
        "experiment": experiment,
        "title": EXPERIMENTS[experiment],
        "budget": budget,
        "steps_per_trial": todo[0].steps,
        "seeds": seeds,
        "trials": len(todo),
        "seconds": time.perf_counter() - start,
        "versions": _versions(),
        "summary": _summarize(experiment, results),
        "results": results,
    }


def write_report(report: dict[str, Any], out: str | os.PathLike[str], *, figure: bool = False) -> tuple[Path, ...]:
    """`<out>/<experiment>.json` and `.md` (the markdown: the aggregates and the findings), and with
    `figure` `<experiment>.png` (needs matplotlib, see `plot_report`); returns the paths written."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"{out} exists and is not a directory")
    out.mkdir(parents=True, exist_ok=True)
    name = report["experiment"]
    j, m, png = out / f"{name}.json", out / f"{name}.md", out / f"{name}.png"
    if figure:
        from ._plot import plot_report

        fig = plot_report(report, png)  # imports matplotlib, or raises its ImportError
        import matplotlib.pyplot as plt

        plt.close(fig)
    j.write_text(json.dumps(report, indent=1) + "\n")
    lines = [
        f"# {name}: {report['title']}",
        "",
        f"Budget {report['budget']} ({report['steps_per_trial']} steps per trial), {report['seeds']} seed(s), "
        f"{report['trials']} trials, {report['seconds']:.0f} s; versions {report['versions']}.",
        "",
        "| finding (the paper's) | holds here | numbers |",
        "|---|---|---|",
    ]
    for f in report["summary"]["findings"]:
        nums = json.dumps(f["numbers"], default=lambda x: round(x, 3) if isinstance(x, float) else x)
        lines.append(f"| {f['claim']} | {'yes' if f['holds'] else 'no'} | `{nums}` |")
    if figure:
        lines += ["", f"![{name}]({png.name})"]
    m.write_text("\n".join(lines) + "\n")
    return (j, m, png) if figure else (j, m)


EXPERIMENTS = {
    "q1": "how context features change learning (DDPG, Pendulum, one feature at a time, σ_rel 0.1 / 0.25 / 0.5)",
    "q2": "hidden vs visible context (DDPG, Pendulum, σ_rel 0.5)",
    "q3": "Landing in Space (DQN, LunarLander, gravity hidden vs visible; planets; crash penalty −10000)",
}
