"""Aggregate estimators and stratified bootstrap intervals, in NumPy only.

They follow Agarwal et al. 2021, "Deep Reinforcement Learning at the Edge of the Statistical
Precipice" (NeurIPS), as their library `rliable` computes them, without its dependencies (SciPy,
arch):

* scores are a matrix `(runs, tasks)`: here a run is one training seed, a task one instance of a set,
  a score the run's mean return on that instance;
* mean = mean over tasks of the per-task mean over runs (`rliable.metrics.aggregate_mean`);
* median = median over tasks of the per-task mean over runs (`aggregate_median`);
* IQM = the 25 % trimmed mean of all `runs x tasks` scores (`aggregate_iqm`, which is
  `scipy.stats.trim_mean(scores, 0.25, axis=None)`: `int(0.25 * N)` scores cut at each end);
* the run-score distribution (performance profile) at `tau` = the fraction of all scores above
  `tau` (`rliable.library.run_score_deviation`);
* intervals: stratified bootstrap over runs (each task's column resampled with replacement on its
  own, `rliable.library.StratifiedBootstrap` with `task_bootstrap=False`), percentile method
  (`get_interval_estimates(method="percentile")`).

Checked against hand-computed values in python/tests/test_evaluation.py (and against `rliable`
itself where it is installed).
"""

from __future__ import annotations

from typing import Iterator

import numpy as np

#: The estimators a report computes, in the order it shows them.
METRICS = ("mean", "median", "iqm")


def _matrix(scores: np.ndarray) -> np.ndarray:
    x = np.asarray(scores, dtype=np.float64)
    if x.ndim != 2 or x.shape[0] < 1 or x.shape[1] < 1:
        raise ValueError(f"scores must be a (runs, tasks) matrix with at least one of each, got shape {x.shape}")
    if not np.isfinite(x).all():
        raise ValueError("scores hold a NaN or an infinity; every run must have a finite score on every task")
    return x


def aggregate_mean(scores: np.ndarray) -> float:
    """Mean over tasks of the per-task mean over runs."""
    return float(np.mean(np.mean(_matrix(scores), axis=0)))


def aggregate_median(scores: np.ndarray) -> float:
    """Median over tasks of the per-task mean over runs."""
    return float(np.median(np.mean(_matrix(scores), axis=0)))


def _trim(n: int) -> tuple[int, int]:
    low = int(0.25 * n)
    return low, n - low


def aggregate_iqm(scores: np.ndarray) -> float:
    """Interquartile mean: the mean of all scores after cutting `int(0.25 * N)` from each end."""
    flat = np.sort(_matrix(scores), axis=None)
    low, high = _trim(flat.size)
    return float(np.mean(flat[low:high]))


def score_distribution(scores: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """The fraction of all scores strictly above each `tau` (the run-score distribution)."""
    flat = np.sort(_matrix(scores), axis=None)
    tau = np.asarray(tau, dtype=np.float64)
    return 1.0 - np.searchsorted(flat, tau, side="right") / flat.size


AGGREGATES = {"mean": aggregate_mean, "median": aggregate_median, "iqm": aggregate_iqm}


def stratified_resamples(x: np.ndarray, reps: int, rng: np.random.Generator, budget: int = 1 << 22) -> Iterator[np.ndarray]:
    """Stratified bootstrap resamples of `x` (runs, tasks), `(chunk, runs, tasks)` at a time: in
    each, every task's column is `runs` draws with replacement from that task's runs."""
    runs, tasks = x.shape
    chunk = max(1, min(reps, budget // (runs * tasks)))
    cols = np.arange(tasks)
    done = 0
    while done < reps:
        c = min(chunk, reps - done)
        idx = rng.integers(0, runs, size=(c, runs, tasks))
        yield x[idx, cols]
        done += c


def bootstrap(
    scores: np.ndarray, *, reps: int, rng: np.random.Generator, tau: np.ndarray | None = None
) -> dict[str, np.ndarray]:
    """Each metric of `METRICS` on `reps` stratified resamples (`{metric: (reps,)}`), and with
    `tau` the score distribution on each (`"profile": (reps, len(tau))`)."""
    x = _matrix(scores)
    if reps < 1:
        raise ValueError(f"reps must be at least 1, got {reps}")
    out: dict[str, list[np.ndarray]] = {m: [] for m in METRICS}
    if tau is not None:
        tau = np.asarray(tau, dtype=np.float64)
        out["profile"] = []
    n = x.size
    low, high = _trim(n)
    for b in stratified_resamples(x, reps, rng):
        task_means = b.mean(axis=1)  # (c, tasks)
        out["mean"].append(task_means.mean(axis=1))
        out["median"].append(np.median(task_means, axis=1))
        flat = np.sort(b.reshape(len(b), n), axis=1)
        out["iqm"].append(flat[:, low:high].mean(axis=1))
        if tau is not None:
            above = np.stack([n - np.searchsorted(row, tau, side="right") for row in flat])
            out["profile"].append(above / n)
    return {k: np.concatenate(v) for k, v in out.items()}


def percentile_interval(replicates: np.ndarray, confidence: float) -> tuple[np.ndarray, np.ndarray]:
    """The percentile bootstrap interval: the `(1 - confidence) / 2` and `(1 + confidence) / 2`
    quantiles of the replicates (along the first axis)."""
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence}")
    tail = (1.0 - confidence) / 2.0
    lo, hi = np.percentile(replicates, [100.0 * tail, 100.0 * (1.0 - tail)], axis=0)
    return lo, hi
