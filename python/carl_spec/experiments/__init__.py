"""The CARL paper's experiments (Benjamins et al. 2021, Section 5), reproduced with
Stable-Baselines3 and the paper's hyperparameters (its Appendix):

* `q1`: how each context feature changes learning: DDPG (SB3 defaults, MlpPolicy) on Pendulum,
  trained on 100 instances varying one feature (`g`, `l`, `m`, `dt`, `max_speed`) with
  σ_rel ∈ {0.1, 0.25, 0.5} (the sets `pendulum/q1_<feature>_sigma_<σ>`), context hidden;
* `q2`: hidden vs visible context: the same at σ_rel = 0.5, the varied feature hidden or appended
  to the observation;
* `q3`: Landing in Space: DQN (the rl-zoo3 hyperparameters of the paper's Table 3) trained on
  `lunar_lander/landing_in_space_train` with gravity hidden or visible, tested on the six planets
  (`landing_in_space_test_planets`) with the crash penalty raised to −10000.

`budget` scales the training steps of every trial (1.0: the paper's 10^6); `seeds` the number of
training seeds (the paper: 5). Trials run one after another, or in parallel on a local Ray bound
to 127.0.0.1 (`ray=True`). Each experiment returns a report (JSON-serializable dict) with the
per-trial numbers, the aggregates and the paper's findings each marked as holding or not, with
the numbers that decide it; `write_report` writes it as JSON and markdown, and with
`figure=True` as a PNG figure (`plot_report`; needs matplotlib, the `plot` extra). With `checkpoint`
(the command line: `<out>/trials`), each finished trial is saved at once and a run of the same
trials later takes it from there, so an interrupted run of hours resumes where it stopped.

    python -m carl_spec.experiments q3 --budget 0.05 --seeds 2 --out results/
"""

from __future__ import annotations

from ._plot import plot_report
from ._run import EXPERIMENTS, Trial, run_experiment, run_trial, trials, write_report

__all__ = ["EXPERIMENTS", "Trial", "plot_report", "run_experiment", "run_trial", "trials", "write_report"]
