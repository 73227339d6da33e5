"""Training for real: the single-file CleanRL-style PPO (python/examples/cleanrl_ppo.py) over
`make_vec`, in both autoreset forms, reaches a greedy 20-episode mean of 450 on CartPole."""

from __future__ import annotations

import importlib.util
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import torch

PATH = Path(__file__).resolve().parents[1] / "examples" / "cleanrl_ppo.py"
spec = importlib.util.spec_from_file_location("cleanrl_ppo", PATH)
assert spec is not None and spec.loader is not None
cleanrl_ppo = importlib.util.module_from_spec(spec)
sys.modules["cleanrl_ppo"] = cleanrl_ppo
spec.loader.exec_module(cleanrl_ppo)


STOCHASTIC_BAR = 400


@pytest.mark.parametrize("mode", ["next_step", "same_step"])
def test_cleanrl_ppo_cartpole_reaches_450(mode: str) -> None:
    t0 = time.perf_counter()
    torch.manual_seed(0)
    untrained = float(np.mean(cleanrl_ppo.evaluate(cleanrl_ppo.Agent(4, 2), "cartpole", greedy=False)))
    agent = cleanrl_ppo.train(cleanrl_ppo.Args(autoreset_mode=mode, seed=0))
    greedy = float(np.mean(cleanrl_ppo.evaluate(agent, "cartpole")))
    sampled = float(np.mean(cleanrl_ppo.evaluate(agent, "cartpole", greedy=False)))
    print(f"CleanRL PPO cartpole {mode} seed 0: greedy {greedy:.1f}, sampled {sampled:.1f}, untrained sampled {untrained:.1f} "
          f"({time.perf_counter() - t0:.0f}s)")
    # Against the same evaluation of an untrained agent (~20): the bars measure learning.
    assert untrained < 100, untrained
    assert greedy >= 450, f"{mode}: greedy 20-episode mean {greedy} < 450"
    assert sampled >= STOCHASTIC_BAR, f"{mode}: sampled-policy 20-episode mean {sampled} < {STOCHASTIC_BAR}"
