"""rna_design from Python and the CLI: the targets chosen with the `target_structure_ids` option
(bad ids refused with the reason), and the finished design in the info of an episode's last step."""

from __future__ import annotations

import pickle
import subprocess
from typing import Any

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import carl_spec as cs

from conftest import cli, cli_path

END_KEYS = {
    "target_id",
    "target_structure",
    "sequence",
    "folded_structure",
    "hamming_distance",
    "hamming_distance_folded",
    "normalized_hamming_distance",
    "improvement_folds",
}


def hamming(a: str, b: str) -> int:
    return sum(x != y for x, y in zip(a, b))


def episode(env: cs.CarlEnv, seed: int | None, rng: np.random.Generator) -> tuple[float, dict[str, Any], int]:
    env.reset(seed=seed)
    steps = 0
    while True:
        _, reward, terminated, truncated, info = env.step(int(rng.integers(4)))
        steps += 1
        assert not truncated
        if terminated:
            return float(reward), info, steps
        assert not END_KEYS & set(info), "the design is reported at the episode's end only"


def test_target_ids_choose_the_targets_and_the_last_info_holds_the_design() -> None:
    env = cs.make("rna_design", options={"target_structure_ids": [1, 5]})
    rng = np.random.default_rng(0)
    seen = set()
    for k in range(6):
        reward, info, steps = episode(env, 3 if k == 0 else None, rng)
        assert END_KEYS <= set(info)
        target, seq, fold = info["target_structure"], info["sequence"], info["folded_structure"]
        seen.add(info["target_id"])
        assert len(seq) == len(fold) == len(target) and set(seq) <= set("ACGU")
        assert set(fold) <= set(".()") and set(target) <= set(".()")
        assert info["hamming_distance_folded"] == hamming(fold, target)
        assert info["hamming_distance"] <= info["hamming_distance_folded"]
        assert info["normalized_hamming_distance"] == info["hamming_distance"] / len(target)
        assert reward == pytest.approx(1.0 - info["normalized_hamming_distance"])
        # One action per unpaired site and per pair.
        assert steps == len(target) - target.count(")")
        # Paired sites carry the pair the action placed.
        stack = []
        for i, c in enumerate(target):
            if c == "(":
                stack.append(i)
            elif c == ")":
                assert seq[stack.pop()] + seq[i] in {"GC", "CG", "AU", "UA"}
    assert seen == {1, 5}
    # Eterna100 puzzle 1 is the hairpin "(((((......)))))".
    single = cs.make("rna_design", options={"target_structure_ids": [1]})
    _, info, _ = episode(single, 0, rng)
    assert (info["target_id"], info["target_structure"]) == (1, "(((((......)))))")
    again = pickle.loads(pickle.dumps(env))
    assert again.reset(seed=3)[0].tolist() == env.reset(seed=3)[0].tolist()


def test_bad_target_ids_are_refused_with_the_reason() -> None:
    with pytest.raises(ValueError, match=r"no target with id 101 \(ids are 1\.\.=100\)"):
        cs.make("rna_design", options={"target_structure_ids": [1, 101]})
    with pytest.raises(ValueError, match=r"rfam_taneda: no target with id 30 \(ids are 1\.\.=29\)"):
        cs.make_vec("rna_design", 2, context={"dataset": "rfam_taneda"}, options={"target_structure_ids": [30]})
    for bad in ([], [1.5], [-2], "one", True):
        with pytest.raises(ValueError, match="non-empty list of whole numbers"):
            cs.make("rna_design", options={"target_structure_ids": bad})
    with pytest.raises(ValueError, match=r"give it as an option instead \(Python: options="):
        cs.make("rna_design", context={"target_structure_ids": [1]})


@pytest.mark.parametrize("mode", ["next_step", "same_step"])
def test_make_vec_reports_the_design_as_sync_vector_env_does(mode: str) -> None:
    kw: dict[str, Any] = {"options": {"target_structure_ids": [1, 2, 5]}}
    n = 3
    ours = cs.make_vec("rna_design", n, autoreset_mode=mode, **kw)
    ref = SyncVectorEnv(
        [lambda: cs.make("rna_design", **kw) for _ in range(n)],
        autoreset_mode=AutoresetMode.NEXT_STEP if mode == "next_step" else AutoresetMode.SAME_STEP,
    )
    np.testing.assert_array_equal(ours.reset(seed=4)[0], ref.reset(seed=4)[0])
    rng = np.random.default_rng(1)
    ended = 0
    for t in range(120):
        actions = rng.integers(4, size=n)
        a, ra, ta, _, ia = ours.step(actions)
        b, rb, tb, _, ib = ref.step(actions)
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(ra, rb)
        np.testing.assert_array_equal(ta, tb)
        x, y = (ia.get("final_info", {}), ib.get("final_info", {})) if mode == "same_step" else (ia, ib)
        for key in END_KEYS:
            assert (key in x) == (key in y), (t, key)
            if key in y:
                np.testing.assert_array_equal(x[f"_{key}"], y[f"_{key}"])
                np.testing.assert_array_equal(x[key][y[f"_{key}"]], y[key][y[f"_{key}"]])
                assert x[key].dtype == y[key].dtype
        ended += int(ta.sum())
    assert ended >= n


def test_cli_option_sets_the_targets() -> None:
    out = cli("rollout", "rna_design", "--option", "target_structure_ids=1", "--seed", "0")
    assert '"terminated":true' in out.splitlines()[-1]
    r = subprocess.run(
        [str(cli_path()), "rollout", "rna_design", "--option", "target_structure_ids=1,0"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2 and "no target with id 0 (ids are 1..=100)" in r.stderr, r.stderr
