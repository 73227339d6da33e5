"""What `evaluate` accepts as a policy, and the check of its first batch of actions."""

from __future__ import annotations

import sys
import types
from contextlib import contextmanager
from typing import Any, Callable, Iterator

import numpy as np
from gymnasium import spaces

#: A batch of observations in, a batch of actions out.
BatchPolicy = Callable[[Any], Any]


def _torch_module(policy: Any) -> Any:
    """`torch` if `policy` is a `torch.nn.Module` (torch is never imported here for others)."""
    torch = sys.modules.get("torch")
    if torch is not None and isinstance(policy, torch.nn.Module):
        return torch
    return None


def describe(policy: Any) -> str:
    """What the provenance records of a policy: its kind and class."""
    cls = type(policy)
    name = f"{cls.__module__}.{cls.__qualname__}"
    if _torch_module(policy) is not None:
        return f"torch module {name}"
    if callable(getattr(policy, "predict", None)):
        return f"model {name} (.predict)"
    if isinstance(policy, (types.FunctionType, types.BuiltinFunctionType)):
        return f"function {getattr(policy, '__module__', None)}.{getattr(policy, '__qualname__', '?')}"
    return f"callable {name}"


@contextmanager
def batch_policy(
    policy: Any, action_space: spaces.Space[Any], observation_space: spaces.Space[Any], deterministic: bool
) -> Iterator[BatchPolicy]:
    """`policy` as a function of a batch of observations: an object with `.predict(obs,
    deterministic=...)` (a Stable-Baselines3 model), a `torch.nn.Module` (called on a float32
    tensor on its parameters' device, in eval mode and without gradients; for a Discrete space its
    output is `(batch, n)` scores and the action their argmax), or any callable."""
    torch = _torch_module(policy)
    if torch is not None:
        if isinstance(observation_space, spaces.Dict):
            raise TypeError(
                "evaluate: a torch module is called on one float tensor, but this environment's observations "
                f"are a dict ({observation_space}); wrap the module in a function of the dict of arrays"
            )
        params = list(policy.parameters())
        device = params[0].device if params else torch.device("cpu")
        discrete = isinstance(action_space, spaces.Discrete)
        checked = [False]

        def act(obs: Any) -> Any:
            with torch.no_grad():
                out = policy(torch.as_tensor(obs, dtype=torch.float32, device=device))
            if not hasattr(out, "detach"):
                raise TypeError(f"evaluate: the torch module returned {type(out).__name__}, not a tensor")
            if discrete:
                if not checked[0]:
                    n = action_space.n  # type: ignore[attr-defined]
                    if out.ndim != 2 or out.shape[1] != n:
                        raise ValueError(
                            f"evaluate: for {action_space} a torch module returns one score per action, shape "
                            f"(batch, {n}), whose argmax is the action; got shape {tuple(out.shape)}"
                        )
                    checked[0] = True
                return (out.argmax(dim=1) + int(action_space.start)).cpu().numpy()  # type: ignore[attr-defined]
            return out.detach().cpu().numpy()

        was_training = policy.training
        policy.eval()
        try:
            yield act
        finally:
            policy.train(was_training)
        return
    predict = getattr(policy, "predict", None)
    if callable(predict):
        model_space = getattr(policy, "observation_space", None)
        if isinstance(model_space, spaces.Box) and isinstance(observation_space, spaces.Box):
            if model_space.shape != observation_space.shape:
                raise ValueError(
                    f"evaluate: the model observes shape {model_space.shape}, this evaluation's observations have "
                    f"shape {observation_space.shape}; evaluate with the obs_context (visible context features) "
                    "the model was trained with"
                )

        def act_predict(obs: Any) -> Any:
            return predict(obs, deterministic=deterministic)[0]

        yield act_predict
        return
    if callable(policy):
        yield policy
        return
    raise TypeError(
        "evaluate: the policy must be a function of a batch of observations, a model with "
        f".predict(obs, deterministic=True) (Stable-Baselines3) or a torch.nn.Module; got {type(policy).__name__}"
    )


def check_actions(actions: Any, space: spaces.Space[Any], num_envs: int, env: str) -> np.ndarray:
    """The first batch of actions, checked against the action space: shape, type and bounds. The
    error says what was expected; the array is returned as the batch will take it."""
    where = f"evaluate({env}): the policy's first batch of actions"
    try:
        a = np.asarray(actions)
    except Exception as e:  # a ragged list, an object NumPy cannot hold as an array
        raise ValueError(f"{where} is not an array ({type(actions).__name__}: {e})") from None
    if isinstance(space, spaces.Discrete):
        want = (num_envs,)
        if a.shape != want:
            hint = " (drop the last axis: actions.reshape(-1))" if a.shape == (num_envs, 1) else ""
            raise ValueError(
                f"{where} has shape {a.shape}; {space} takes one integer per environment, shape {want}{hint}"
            )
        if a.dtype == np.bool_ or not np.issubdtype(a.dtype, np.integer):
            hint = " (for scores or probabilities, take their argmax)" if np.issubdtype(a.dtype, np.floating) else ""
            raise ValueError(f"{where} are {a.dtype}; {space} takes integers{hint}")
        lo, hi = int(space.start), int(space.start) + int(space.n) - 1
        bad = np.flatnonzero((a < lo) | (a > hi))
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"{where}: environment {i} got action {a[i]}, outside {space} (valid: {lo}..{hi})")
        return a
    if isinstance(space, spaces.Box):
        box_shape: tuple[int, ...] = (num_envs, *space.shape)
        if a.shape != box_shape:
            raise ValueError(
                f"{where} has shape {a.shape}; {space} takes shape {box_shape} (num_envs={num_envs} rows of {space.shape})"
            )
        if a.dtype == np.bool_ or not (np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)):
            raise ValueError(f"{where} are {a.dtype}; {space} takes real numbers ({space.dtype})")
        x = a.astype(space.dtype)
        if not np.isfinite(x).all():
            i = int(np.flatnonzero(~np.isfinite(x).reshape(num_envs, -1).all(axis=1))[0])
            raise ValueError(f"{where}: environment {i} got a NaN or infinite action {a[i]}")
        outside = (x < space.low) | (x > space.high)
        if outside.any():
            i, *j = (int(k) for k in np.argwhere(outside)[0])
            comp = tuple(j)
            raise ValueError(
                f"{where}: environment {i} got {float(a[(i, *comp)]):.6g} for component {comp if len(comp) != 1 else comp[0]}, "
                f"outside the action space's bounds [{float(space.low[comp]):.6g}, {float(space.high[comp]):.6g}] "
                f"({space}); clip the policy's output (np.clip(actions, space.low, space.high))"
            )
        return a
    # Dict action spaces are not shipped by any runtime; check membership row by row.
    return a
