"""carl_spec.evaluate with the training tier's frameworks: an SB3 model and a torch module.

The five lines the docs show (docs/guides/evaluation.md): train briefly, evaluate on the train and
test sets, report."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import torch
from stable_baselines3 import DQN

import carl_spec as cs
from carl_spec.sb3 import CarlSB3VecEnv

PLANETS = "lunar_lander/landing_in_space_test_planets"


def test_sb3_model_in_five_lines(tmp_path: Any) -> None:
    model = DQN("MlpPolicy", CarlSB3VecEnv("lunar_lander", 4, instances="lunar_lander/landing_in_space_train"), seed=0, device="cpu").learn(2_000)
    train = cs.evaluate(model, instances="lunar_lander/landing_in_space_train", episodes=1, seed=0, run=0)
    test = cs.evaluate(model, instances=PLANETS, episodes=2, seed=0, run=0)
    rep = cs.report(train=train, test=test, reps=200)
    paths = rep.save(tmp_path)
    assert [p.rsplit("/", 1)[1] for p in paths] == ["report.json", "report.md"]
    assert test.provenance["policy"].startswith("model stable_baselines3.dqn.dqn.DQN")
    # The model's greedy actions are what evaluate played: same seed, same episodes, any batch.
    again = cs.evaluate(model, instances=PLANETS, episodes=2, seed=0, run=0, num_envs=3)
    assert again.episodes == test.episodes
    assert set(rep.groups) == {"train", "test", "test/in_distribution", "test/out_of_distribution"}


def test_torch_module() -> None:
    torch.manual_seed(0)
    net = torch.nn.Sequential(torch.nn.Linear(8, 16), torch.nn.Tanh(), torch.nn.Linear(16, 4))
    net.train()
    r = cs.evaluate(net, instances=PLANETS, episodes=2, seed=1, num_envs=4)
    assert net.training, "evaluate restores the module's mode"
    assert r.provenance["policy"].startswith("torch module torch.nn.modules.container.Sequential")

    def by_hand(obs: np.ndarray) -> np.ndarray:
        with torch.no_grad():
            return net(torch.as_tensor(obs, dtype=torch.float32)).argmax(dim=1).numpy()

    assert cs.evaluate(by_hand, instances=PLANETS, episodes=2, seed=1, num_envs=4).episodes == r.episodes
    wrong = torch.nn.Linear(8, 3)
    with pytest.raises(ValueError, match=r"for Discrete\(4\) a torch module returns one score per action, shape \(batch, 4\).*got shape \(4, 3\)"):
        cs.evaluate(wrong, instances=PLANETS, episodes=1, num_envs=4)
    box = torch.nn.Linear(3, 1)
    c = cs.evaluate(lambda o: np.clip(box(torch.as_tensor(o, dtype=torch.float32)).detach().numpy(), -2, 2), "pendulum", episodes=2)
    assert len(c.episodes) == 2


def test_train_here_test_there(tmp_path: Any) -> None:
    """Train on the train set with GRAVITY_Y visible, then `set_env` / `DQN.load(path, env=...)`
    on the test planets: SB3 compares the observation spaces, which no longer depend on the set."""
    kw: dict[str, Any] = dict(obs_context=["GRAVITY_Y"])
    train_env = cs.make("lunar_lander", instances="lunar_lander/landing_in_space_train", **kw)
    test_env = cs.make("lunar_lander", instances=PLANETS, **kw)
    model = DQN("MlpPolicy", train_env, seed=0, device="cpu", learning_starts=100).learn(300)
    model.set_env(test_env)
    model.save(tmp_path / "dqn")
    loaded = DQN.load(tmp_path / "dqn", env=test_env, device="cpu")
    assert loaded.observation_space == test_env.observation_space
    r = cs.evaluate(loaded, instances=PLANETS, episodes=1, seed=0, **kw)
    assert len(r.episodes) == 6 and all(e.outcome is not None for e in r.episodes)
