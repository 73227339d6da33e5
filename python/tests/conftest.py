"""Shared helpers: the repository root and the `carl-spec` CLI built by `cargo test --release`."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
CLASSIC = ["cartpole", "pendulum", "mountain_car", "mountain_car_continuous", "acrobot"]


def cli_path() -> Path:
    p = Path(os.environ.get("CARL_SPEC_BIN", ROOT / "target" / "release" / "carl-spec"))
    if not p.exists():
        pytest.fail(f"{p} not found: build it with `cargo build --release` (scripts/test-all does)")
    return p


def cli(*args: str, ok: tuple[int, ...] = (0,)) -> str:
    r = subprocess.run([str(cli_path()), *args], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode in ok, f"carl-spec {' '.join(args)} exited {r.returncode}: {r.stderr}"
    return r.stdout


def cli_json(*args: str, ok: tuple[int, ...] = (0,)) -> Any:
    return json.loads(cli(*args, ok=ok))


@pytest.fixture(autouse=True, scope="session")
def sb3_logs_in_tmp(tmp_path_factory: pytest.TempPathFactory) -> Any:
    """Stable-Baselines3 makes `$TMPDIR/SB3-<date>` for every model it builds unless SB3_LOGDIR
    names a folder (carl-bench's suite trains a few when SB3 is installed, as in the training
    venv): the session's logs go to a pytest temp folder, nothing to the system temp."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("SB3_LOGDIR", str(tmp_path_factory.mktemp("sb3-logs")))
        yield
