"""`python -m carl_spec.experiments EXPERIMENT [--budget B] [--seeds N] [--ray] --out DIR [--figure]`:
run one of the paper's experiments (q1, q2, q3, or all) and write its report (JSON and markdown;
with --figure a PNG figure too). Each finished trial is saved in DIR/trials at once; running the
same command again (after an interruption) takes those trials from there and trains only the
others."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .._matplotlib import pyplot
from ._run import EXPERIMENTS, FEATURES, run_experiment, write_report


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m carl_spec.experiments", description=__doc__)
    p.add_argument("experiment", choices=[*EXPERIMENTS, "all"])
    p.add_argument("--budget", type=float, default=0.01, help="training steps per trial, as a fraction of the paper's 10^6")
    p.add_argument("--seeds", type=int, default=5, help="training seeds per configuration (the paper: 5)")
    p.add_argument("--features", default=",".join(FEATURES), help="q1/q2: the Pendulum features, comma-separated")
    p.add_argument("--test-episodes", type=int, default=100, help="q3: episodes per planet and seed (the paper: 100)")
    p.add_argument("--evaluations", type=int, default=4, help="q1/q2: evaluations along training")
    p.add_argument("--ray", action="store_true", help="run the trials in parallel on a local Ray bound to 127.0.0.1")
    p.add_argument("--out", required=True, help="directory for <experiment>.json and .md")
    p.add_argument("--figure", action="store_true", help="also draw <experiment>.png (needs matplotlib: the plot extra)")
    a = p.parse_args(argv)
    names = list(EXPERIMENTS) if a.experiment == "all" else [a.experiment]

    def progress(message: str) -> None:
        print(f"{a.experiment}: {message}", file=sys.stderr, flush=True)

    out = Path(a.out)
    if out.exists() and not out.is_dir():
        print(f"error: --out {out} exists and is not a directory", file=sys.stderr)
        return 2
    try:
        if a.figure:  # before hours of training, not after
            pyplot("--figure")
        for name in names:
            report = run_experiment(
                name,
                budget=a.budget,
                seeds=a.seeds,
                features=[f.strip() for f in a.features.split(",") if f.strip()],
                test_episodes=a.test_episodes,
                evaluations=a.evaluations,
                ray=a.ray,
                progress=progress,
                checkpoint=out / "trials",
            )
            for path in write_report(report, a.out, figure=a.figure):
                print(path)
    except (ValueError, ImportError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
