"""Evaluation and generalization reports: `carl_spec.evaluate` and `carl_spec.report`.

    import carl_spec as cs
    train = [cs.evaluate(agent(s), instances="lunar_lander/landing_in_space_train", run=s) for s in seeds]
    test = [cs.evaluate(agent(s), instances="lunar_lander/landing_in_space_test_planets", run=s) for s in seeds]
    rep = cs.report(train=train, test=test)
    rep.save("out", figure=True)      # out/report.json, .md, .png
"""

from __future__ import annotations

from ._report import Report, report
from ._result import Episode, Episodes, EvaluationResult, Instance, InstanceSummary
from ._run import SEED_RULE, episode_seed, evaluate
from ._stats import aggregate_iqm, aggregate_mean, aggregate_median, score_distribution, stratified_resamples

__all__ = [
    "Episode",
    "Episodes",
    "EvaluationResult",
    "Instance",
    "InstanceSummary",
    "Report",
    "SEED_RULE",
    "aggregate_iqm",
    "aggregate_mean",
    "aggregate_median",
    "episode_seed",
    "evaluate",
    "report",
    "score_distribution",
    "stratified_resamples",
]
