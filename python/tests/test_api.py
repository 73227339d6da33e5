"""Specs, validation, instance sets and sampling equal the CLI's; errors carry the library's message."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import carl_spec as cs
from carl_spec._wrap import load_user_spec
from conftest import ROOT, cli, cli_json


def test_list_envs_equals_cli() -> None:
    rows = cli_json("list", "--format", "json")
    assert cs.list_envs() == [r["id"] for r in rows]
    assert set(cs.list_envs(runtime_only=True)) == set(cs.RUNTIMES)
    assert "cartpole" in cs.RUNTIMES


def test_spec_equals_cli_show() -> None:
    for env in ["cartpole", "lunar_lander", "pendulum"]:
        s = cs.spec(env)
        shown = cli_json("show", env, "--format", "json")
        assert s.raw == shown
        assert s.has_runtime
        assert list(s.features) == [f["name"] for f in shown["features"]]
    cp = cs.spec("cartpole")
    assert cp.observation_space.shape == (4,)
    assert cp.action_space.n == 2
    assert cp.default_context()["masscart"] == 1.0


@pytest.mark.parametrize("env_id", cs.list_envs())
def test_every_spec_written_out_validates(env_id: str, tmp_path: Path) -> None:
    # Issue 29: an author starts from a shipped spec; what cs.spec gives is a valid spec file.
    s = cs.spec(env_id)
    path = tmp_path / f"{s.id}.json"
    path.write_text(s.to_json())
    report = cs.validate(path)
    assert report.valid and report.environments == 1, "\n".join(map(str, report.diagnostics))
    assert json.loads(cli("validate", str(path), "--format", "json"))["valid"]
    # Read back, it resolves to the same spec (but for where fragments' features came from).
    assert load_user_spec(path) == json.loads(s.to_json())


def test_spec_by_alias_and_unknown_name_suggests() -> None:
    assert cs.spec("CARLCartPoleEnv").id == "cartpole"
    with pytest.raises(cs.UnknownNameError, match='did you mean "cartpole"'):
        cs.spec("cartpol")
    with pytest.raises(KeyError):
        cs.spec("nope_nothing")
    with pytest.raises(ValueError):
        cs.spec("nope_nothing")


def test_validate_bundled_is_valid() -> None:
    report = cs.validate()
    doc = cli_json("validate", "--format", "json")
    assert report.valid and doc["valid"]
    assert report.files == doc["files"]


def _invalid_corpus() -> list[Path]:
    return sorted((ROOT / "tests" / "corpus" / "invalid").glob("*"))


@pytest.mark.parametrize("path", _invalid_corpus(), ids=lambda p: p.name)
def test_validate_invalid_corpus_equals_cli(path: Path) -> None:
    report = cs.validate(path)
    # A case whose only finding is a warning (needless-allow-out-of-bounds) is valid: exit 0.
    warning_only = path.name.startswith("needless-")
    doc = cli_json("validate", str(path), "--format", "json", ok=(0,) if warning_only else (1, 2))
    assert report.valid == warning_only
    assert report.diagnostics
    got = [(d.rule, d.file, d.line, d.col, d.message, d.help) for d in report.diagnostics]
    want = [
        (
            d["rule"],
            d["file"],
            (d.get("location") or {}).get("line"),
            (d.get("location") or {}).get("column"),
            d["message"],
            d.get("help"),
        )
        for d in doc["diagnostics"]
    ]
    assert got == want
    assert bool(report.errors) != warning_only


def test_validate_missing_path_is_an_error() -> None:
    with pytest.raises(ValueError, match="cannot read"):
        cs.validate(ROOT / "no" / "such" / "dir")


def test_validate_dir_without_specs_is_an_error_as_in_the_cli(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("not a spec")
    with pytest.raises(ValueError, match=r"no \*\.json spec files found in .*" + tmp_path.name):
        cs.validate(tmp_path)


def test_instance_sets_equal_cli_show() -> None:
    names = cs.instances.list()
    assert "lunar_lander/landing_in_space_train" in names
    for name in names[:: max(1, len(names) // 12)] + ["lunar_lander/landing_in_space_train"]:
        iset = cs.instances.load(name)
        shown = json.loads(cli("instances", "show", name, "--format", "json"))
        assert iset.raw == shown
        assert iset.qualified_name == name
        assert len(iset) == len(shown["instances"])
        assert iset.contexts == [i["context"] for i in shown["instances"]]


def test_unknown_instance_set_suggests() -> None:
    with pytest.raises(cs.UnknownNameError, match="landing_in_space_train"):
        cs.instances.load("lunar_lander/landing_in_space_trian")
    with pytest.raises(cs.UnknownNameError, match="ENV/SET"):
        cs.instances.load("no_slash")


def test_sample_equals_cli() -> None:
    s = cs.spec("pendulum")
    dist = sorted(s.distributions)[0]
    got = cs.sample("pendulum", distribution=dist, n=20, seed=3)
    shown = cli_json("sample", "pendulum", "--distribution", dist, "-n", "20", "--seed", "3", "--format", "json")
    assert got == [i["context"] for i in shown["instances"]]
    assert got == cs.sample("pendulum", distribution=dist, n=20, seed=3)
    assert got != cs.sample("pendulum", distribution=dist, n=20, seed=4)
    with pytest.raises(cs.UnknownNameError):
        cs.sample("pendulum", distribution="nope", n=2, seed=0)
