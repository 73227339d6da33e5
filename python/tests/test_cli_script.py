"""The `carl-spec` command that `pip install` puts beside the interpreter: the Rust command line
run in-process (python/carl_spec/_cli.py), with the binary's behaviour and exit codes."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import carl_spec as cs


def script() -> str:
    """The console script of the installed package (beside this interpreter)."""
    name = "carl-spec.exe" if os.name == "nt" else "carl-spec"
    path = Path(sys.executable).parent / name
    if not path.exists():
        pytest.fail(f"the package installs no {name} script beside {Path(sys.executable).name}")
    return str(path)


def run(*args: str, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([script(), *args], capture_output=True, text=True, input=stdin, timeout=120)


def test_validate_the_bundled_specs() -> None:
    r = run("validate")
    assert r.returncode == 0, r.stderr


def test_version_is_the_package_version() -> None:
    r = run("--version")
    assert r.returncode == 0
    assert r.stdout.split() == ["carl-spec", cs.__version__]


def test_list_names_every_runtime_with_its_version() -> None:
    r = run("list", "--format", "json")
    assert r.returncode == 0, r.stderr
    rows = {row["id"]: row for row in json.loads(r.stdout)}
    for env in cs.RUNTIMES:
        assert cs.gym_id(env) == f"carl_spec/{env}-v{rows[env]['version']}"


def test_usage_errors_exit_2_and_invalid_specs_exit_1(tmp_path: Path) -> None:
    assert run("no-such-command").returncode == 2
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    r = run("validate", str(bad))
    assert r.returncode == 1
    assert "json-syntax" in r.stdout + r.stderr


def test_rollout_reads_actions_from_stdin() -> None:
    r = run("rollout", "cartpole", "--seed", "3", "--actions", "-", stdin="0\n1\n0\n")
    assert r.returncode == 0, r.stderr
    lines = [json.loads(line) for line in r.stdout.splitlines()]
    assert "reset" in lines[0] and [line["t"] for line in lines[1:]] == [1, 2, 3]


@pytest.mark.skipif(os.name == "nt", reason="POSIX signals")
def test_ctrl_c_ends_a_long_command() -> None:
    """Python's own SIGINT handler would wait for the native call; the script restores the default."""
    cmd = [script(), "bench", "cartpole", "--steps", "100000000"]
    with subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) as p:
        try:
            time.sleep(1.0)
            p.send_signal(signal.SIGINT)
            assert p.wait(timeout=60) == -signal.SIGINT  # generous: a loaded machine (CI runs jobs side by side)
        finally:
            p.kill()
