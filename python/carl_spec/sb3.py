"""Stable-Baselines3 over carl-spec: a `VecEnv` whose batch steps in one call into Rust.

    from stable_baselines3 import PPO
    from carl_spec.sb3 import CarlSB3VecEnv
    venv = CarlSB3VecEnv("cartpole", 8, instances="cartpole/...", selection="random")
    PPO("MlpPolicy", venv).learn(100_000)

The batch runs Gymnasium's same-step autoreset, which is SB3's convention: the observation
returned for a finished environment is the first of its next episode, the last one is in
`infos[i]["terminal_observation"]`, and `infos[i]["TimeLimit.truncated"]` tells a time limit
(bootstrap) from a true end. Needs the `sb3` extra (stable-baselines3).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import gymnasium
import numpy as np

try:
    from stable_baselines3.common.vec_env.base_vec_env import VecEnv, VecEnvIndices, VecEnvObs, VecEnvStepReturn
except ImportError as e:  # pragma: no cover - depends on the installed extras
    raise ImportError("carl_spec.sb3 needs stable-baselines3: pip install 'carl-spec[sb3]'") from e

from .env import CarlEnv
from .vector import CarlVectorEnv

__all__ = ["CarlSB3VecEnv"]


class CarlSB3VecEnv(VecEnv):  # type: ignore[misc]  # VecEnv is Any where SB3 is not installed
    """`num_envs` carl-spec environments as an SB3 `VecEnv`.

    Takes the arguments of `carl_spec.make_vec` (without `autoreset_mode`, which is always
    same-step here), or an existing same-step `CarlVectorEnv` as `env`. Seeding follows SB3:
    `seed(s)` makes the next `reset()` seed environment `i` with `s + i`; a batch never seeded
    draws OS entropy. `render_mode="rgb_array"` renders each environment from its state and
    context (for runtimes that can render).
    """

    def __init__(self, env: str | CarlVectorEnv, num_envs: int | None = None, *, render_mode: str | None = None, **make_vec_kwargs: Any) -> None:
        if isinstance(env, CarlVectorEnv):
            if num_envs is not None or make_vec_kwargs:
                raise ValueError("pass either a CarlVectorEnv or make_vec arguments, not both")
            if env.metadata["autoreset_mode"] != gymnasium.vector.AutoresetMode.SAME_STEP:
                raise ValueError("CarlSB3VecEnv needs a CarlVectorEnv made with autoreset_mode='same_step' (SB3's convention)")
            self.venv = env
        else:
            if num_envs is None:
                raise ValueError("num_envs is required with an environment name")
            if "autoreset_mode" in make_vec_kwargs:
                raise ValueError("CarlSB3VecEnv always uses autoreset_mode='same_step' (SB3's convention); drop the argument")
            self.venv = CarlVectorEnv(env, num_envs, autoreset_mode="same_step", **make_vec_kwargs)
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self._render_mode = render_mode
        self._renderers: dict[Any, CarlEnv] = {}
        self._actions: np.ndarray | None = None
        super().__init__(self.venv.num_envs, self.venv.single_observation_space, self.venv.single_action_space)
        if render_mode is not None:
            self._renderer(0)  # refuse a runtime without a renderer now, not at the first render()

    # -- stepping ------------------------------------------------------------------------------

    def reset(self) -> VecEnvObs:
        seeds, options = self._seeds, self._options
        if all(s is None for s in seeds):
            seed: int | list[int | None] | None = None
        elif (first := seeds[0]) is not None and all(s == first + i for i, s in enumerate(seeds)):
            seed = first  # SB3's seed(s) layout is the batch's own: one call
        else:
            seed = list(seeds)
        if any(options):
            if any(o != options[0] for o in options):
                raise ValueError("carl-spec resets the batch with one options dict; set_options() per environment differs")
            obs, infos = self.venv.reset(seed=seed, options=options[0])
        else:
            obs, infos = self.venv.reset(seed=seed)
        self.reset_infos = self._split_infos(infos)
        self._reset_seeds()
        self._reset_options()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self) -> VecEnvStepReturn:
        if self._actions is None:
            raise RuntimeError("step_wait() without step_async()")
        actions, self._actions = self._actions, None
        obs, rewards, terminated, truncated, vinfos = self.venv.step(actions)
        dones = terminated | truncated
        time_limit = truncated & ~terminated
        infos = self._split_infos(vinfos)
        for i, info in enumerate(infos):
            info["TimeLimit.truncated"] = bool(time_limit[i])
        if "final_obs" in vinfos:
            for j in np.flatnonzero(dones):
                infos[j]["terminal_observation"] = vinfos["final_obs"][j]
        return obs, rewards.astype(np.float32), dones, infos

    def _split_infos(self, infos: dict[str, Any]) -> list[dict[str, Any]]:
        out: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        if "instance_id" in infos:
            for i, iid in enumerate(infos["instance_id"].tolist()):
                out[i]["instance_id"] = iid
        return out

    def close(self) -> None:
        self.venv.close()

    # -- attributes and methods ------------------------------------------------------------------

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        """Per-environment attributes (`context`, `instance_id`, the single spaces, `render_mode`),
        else the batch's attribute of that name for each index."""
        idx = list(self._get_indices(indices))
        if attr_name == "render_mode":
            return [self._render_mode for _ in idx]
        if attr_name == "observation_space":
            return [self.venv.single_observation_space for _ in idx]
        if attr_name == "action_space":
            return [self.venv.single_action_space for _ in idx]
        if attr_name == "context":
            return [self._context(i) for i in idx]
        if attr_name == "instance_id":
            ids = self.venv._core.instance_ids()
            return [int(ids[i]) for i in idx]
        if attr_name.startswith("_") or not hasattr(self.venv, attr_name):
            raise AttributeError(f"carl-spec environments have no attribute {attr_name!r}")
        value = getattr(self.venv, attr_name)
        return [value for _ in idx]

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        """Environments of one batch share their Python attributes: only all at once."""
        idx = list(self._get_indices(indices))
        if sorted(idx) != list(range(self.num_envs)):
            raise ValueError(f"set_attr({attr_name!r}): the environments of a carl-spec batch share attributes; pass indices=None")
        if attr_name.startswith("_") or attr_name in ("num_envs", "observation_space", "action_space", "metadata"):
            raise AttributeError(f"set_attr({attr_name!r}): not settable on a carl-spec batch")
        setattr(self.venv, attr_name, value)

    def env_method(self, method_name: str, *method_args: Any, indices: VecEnvIndices = None, **method_kwargs: Any) -> list[Any]:
        """`context_info`, `render` and `get_wrapper_attr` per environment (the batch has no
        per-environment Python objects to call anything else on)."""
        idx = list(self._get_indices(indices))
        if method_name == "context_info":
            return [self.venv.context_info(i) for i in idx]
        if method_name == "render":
            return [self._image(i) for i in idx]
        if method_name == "get_wrapper_attr":
            return self.get_attr(method_args[0], idx)
        raise AttributeError(f"carl-spec environments have no method {method_name!r} (env_method supports context_info, render, get_wrapper_attr)")

    def env_is_wrapped(self, wrapper_class: type[gymnasium.Wrapper], indices: VecEnvIndices = None) -> list[bool]:
        # The batch steps in Rust: no Gymnasium wrapper sits inside it.
        return [False for _ in self._get_indices(indices)]

    # -- rendering -----------------------------------------------------------------------------

    def get_images(self) -> Sequence[np.ndarray | None]:
        return [self._image(i) for i in range(self.num_envs)]

    def _context(self, i: int) -> dict[str, float] | None:
        info = self.venv.context_info(i)
        if info is not None:
            return dict(info["context"])
        ctx = self.venv._ctor["context"]
        return None if ctx is None else dict(ctx)

    def _renderer(self, i: int) -> CarlEnv:
        # A single env with environment i's context, set to its state, draws environment i.
        ctx = self._context(i)
        key = None if ctx is None else tuple(sorted(ctx.items()))
        r = self._renderers.get(key)
        if r is None:
            c = self.venv._ctor
            r = CarlEnv(
                c["env"],
                context=ctx,
                obs_context=c["obs_context"],
                options=c.get("options"),
                # A context the batch drew from its set or distribution was checked there (a set
                # may declare contexts outside the bounds): draw it as the batch runs it.
                allow_out_of_bounds=bool(c.get("allow_out_of_bounds")) or self.venv.context_info(i) is not None,
                specs_dir=c["specs_dir"],
                render_mode="rgb_array",
            )
            r.reset(seed=0)
            if len(self._renderers) > 64:
                self._renderers.clear()
            self._renderers[key] = r
        return r

    def _image(self, i: int) -> np.ndarray | None:
        if self._render_mode != "rgb_array":
            return None
        state = self.venv._core.state(i)
        if state is None:
            raise RuntimeError(f"{self.venv._ctor['env']}: environment {i} has no readable state to render from")
        r = self._renderer(i)
        r.set_state(state)
        return r.render()

    def _get_indices(self, indices: VecEnvIndices) -> list[int]:
        idx = [int(i) for i in super()._get_indices(indices)]
        for i in idx:
            if not 0 <= int(i) < self.num_envs:
                raise IndexError(f"environment index {i} out of range for {self.num_envs} environments")
        return idx
