#!/usr/bin/env python3
"""Single-file PPO in the style of CleanRL's ppo.py, over one batched `carl_spec.make_vec`.

    python python/examples/cleanrl_ppo.py --env cartpole --autoreset-mode next_step --seed 0

Both Gymnasium autoreset modes are handled the way each needs:
- next_step: the step after an episode's end only resets (its action is ignored, its reward is 0),
  so that transition is masked out of the loss; the observation returned at the end IS the last
  one, so a time-limit truncation bootstraps from the value of the next row.
- same_step: the observation returned at an end is already the next episode's first; the last
  one is `infos["final_obs"][i]`, whose value bootstraps a truncated episode.
Defaults are rl-zoo's CartPole-v1 PPO hyperparameters (8 envs x 32 steps, 20 epochs of one
256-sample minibatch, linear learning-rate and clip schedules).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch
from torch import nn
from torch.distributions import Categorical

import carl_spec as cs


@dataclass
class Args:
    env: str = "cartpole"
    autoreset_mode: str = "next_step"
    seed: int = 0
    total_timesteps: int = 100_000
    num_envs: int = 8
    num_steps: int = 32
    learning_rate: float = 1e-3
    gamma: float = 0.98
    gae_lambda: float = 0.8
    num_minibatches: int = 1
    update_epochs: int = 20
    clip_coef: float = 0.2
    ent_coef: float = 0.0
    vf_coef: float = 0.5
    max_grad_norm: float = 0.5
    env_kwargs: dict[str, Any] | None = None


def layer(i: int, o: int, std: float = float(np.sqrt(2))) -> nn.Linear:
    lin = nn.Linear(i, o)
    nn.init.orthogonal_(lin.weight, std)
    nn.init.constant_(lin.bias, 0.0)
    return lin


class Agent(nn.Module):
    def __init__(self, obs_dim: int, n_actions: int) -> None:
        super().__init__()
        self.critic = nn.Sequential(layer(obs_dim, 64), nn.Tanh(), layer(64, 64), nn.Tanh(), layer(64, 1, 1.0))
        self.actor = nn.Sequential(layer(obs_dim, 64), nn.Tanh(), layer(64, 64), nn.Tanh(), layer(64, n_actions, 0.01))

    def value(self, x: torch.Tensor) -> torch.Tensor:
        return self.critic(x).squeeze(-1)

    def act(self, x: torch.Tensor, action: torch.Tensor | None = None) -> tuple[torch.Tensor, ...]:
        dist = Categorical(logits=self.actor(x))
        if action is None:
            action = dist.sample()
        return action, dist.log_prob(action), dist.entropy(), self.value(x)

    def greedy(self, x: torch.Tensor) -> torch.Tensor:
        return self.actor(x).argmax(-1)


def train(args: Args) -> Agent:
    torch.manual_seed(args.seed)
    envs = cs.make_vec(args.env, args.num_envs, autoreset_mode=args.autoreset_mode, **(args.env_kwargs or {}))
    next_step = args.autoreset_mode == "next_step"
    obs_dim = int(np.prod(envs.single_observation_space.shape))
    agent = Agent(obs_dim, int(envs.single_action_space.n))
    opt = torch.optim.Adam(agent.parameters(), lr=args.learning_rate, eps=1e-5)
    T, N = args.num_steps, args.num_envs
    obs_b = torch.zeros((T, N, obs_dim))
    act_b = torch.zeros((T, N), dtype=torch.long)
    logp_b, rew_b, val_b = torch.zeros((T, N)), torch.zeros((T, N)), torch.zeros((T, N))
    term_b, end_b, valid_b = torch.zeros((T, N)), torch.zeros((T, N)), torch.ones((T, N))
    next_obs = torch.as_tensor(envs.reset(seed=args.seed)[0])
    prev_end = torch.zeros(N)  # next_step: the env ended at the previous step, this one only resets
    num_updates = args.total_timesteps // (T * N)
    batch = T * N
    mb = batch // args.num_minibatches
    for update in range(num_updates):
        frac = 1.0 - update / num_updates
        opt.param_groups[0]["lr"] = frac * args.learning_rate
        clip = frac * args.clip_coef
        for t in range(T):
            obs_b[t] = next_obs
            valid_b[t] = 1.0 - prev_end if next_step else 1.0
            with torch.no_grad():
                action, logp, _, value = agent.act(next_obs)
            act_b[t], logp_b[t], val_b[t] = action, logp, value
            o, r, term, trunc, infos = envs.step(action.numpy())
            reward = torch.as_tensor(r, dtype=torch.float32)
            end = np.logical_or(term, trunc)
            if not next_step and trunc.any():
                # same_step: bootstrap a time limit from the last observation of the episode.
                idx = np.flatnonzero(trunc & ~term)
                if len(idx):
                    final = torch.as_tensor(np.stack([infos["final_obs"][i] for i in idx]))
                    with torch.no_grad():
                        reward[idx] += args.gamma * agent.value(final)
            rew_b[t] = reward
            term_b[t] = torch.as_tensor(term, dtype=torch.float32)
            end_b[t] = torch.as_tensor(end, dtype=torch.float32)
            prev_end = end_b[t]
            next_obs = torch.as_tensor(o)
        with torch.no_grad():
            next_value = agent.value(next_obs)
            adv = torch.zeros((T, N))
            last = torch.zeros(N)
            for t in reversed(range(T)):
                v_next = next_value if t == T - 1 else val_b[t + 1]
                if next_step:
                    # The row after an end holds the episode's last observation: terminated -> 0,
                    # truncated -> its value. The GAE chain stops at every end.
                    delta = rew_b[t] + args.gamma * v_next * (1.0 - term_b[t]) - val_b[t]
                else:
                    # same_step: truncation is already folded into the reward.
                    delta = rew_b[t] + args.gamma * v_next * (1.0 - end_b[t]) - val_b[t]
                last = delta + args.gamma * args.gae_lambda * (1.0 - end_b[t]) * last
                last = last * valid_b[t]
                adv[t] = last
            ret = adv + val_b
        b_obs, b_act, b_logp = obs_b.reshape(batch, obs_dim), act_b.reshape(batch), logp_b.reshape(batch)
        b_adv, b_ret, b_valid = adv.reshape(batch), ret.reshape(batch), valid_b.reshape(batch).bool()
        b_obs, b_act, b_logp, b_adv, b_ret = (x[b_valid] for x in (b_obs, b_act, b_logp, b_adv, b_ret))
        n = len(b_act)
        for _ in range(args.update_epochs):
            perm = torch.randperm(n)
            for start in range(0, n, mb):
                i = perm[start : start + mb]
                _, logp, ent, value = agent.act(b_obs[i], b_act[i])
                ratio = (logp - b_logp[i]).exp()
                a = b_adv[i]
                a = (a - a.mean()) / (a.std() + 1e-8)
                pg = torch.max(-a * ratio, -a * ratio.clamp(1 - clip, 1 + clip)).mean()
                v_loss = 0.5 * ((value - b_ret[i]) ** 2).mean()
                loss = pg - args.ent_coef * ent.mean() + args.vf_coef * 2 * v_loss
                opt.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
                opt.step()
    envs.close()
    return agent


def evaluate(agent: Agent, env: str, episodes: int = 20, seed: int = 10_000, greedy: bool = True, **env_kwargs: Any) -> list[float]:
    """Returns of the first episode of each of `episodes` environments of one batch, with the
    greedy (argmax) or the sampled policy."""
    envs = cs.make_vec(env, episodes, autoreset_mode="same_step", **env_kwargs)
    obs, _ = envs.reset(seed=seed)
    returns = np.zeros(episodes)
    alive = np.ones(episodes, dtype=bool)
    while alive.any():
        with torch.no_grad():
            x = torch.as_tensor(obs)
            a = (agent.greedy(x) if greedy else agent.act(x)[0]).numpy()
        obs, r, term, trunc, _ = envs.step(a)
        returns += r * alive
        alive &= ~(term | trunc)
    envs.close()
    return returns.tolist()


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for f, default in Args().__dict__.items():
        if f != "env_kwargs":
            p.add_argument("--" + f.replace("_", "-"), type=type(default), default=default)
    args = Args(**vars(p.parse_args()))
    torch.set_num_threads(1)
    t0 = time.perf_counter()
    agent = train(args)
    greedy, sampled = evaluate(agent, args.env), evaluate(agent, args.env, greedy=False)
    print(f"{args.env} {args.autoreset_mode} seed {args.seed}: mean return over {len(greedy)} episodes greedy "
          f"{np.mean(greedy):.1f}, sampled {np.mean(sampled):.1f} ({time.perf_counter() - t0:.1f}s)")


if __name__ == "__main__":
    main()
