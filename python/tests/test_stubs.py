"""The .pyi stubs match the native module (mypy's stubtest), and the package type-checks."""

from __future__ import annotations

import subprocess
import sys

from conftest import ROOT


def test_stubs_match_native_module() -> None:
    r = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "carl_spec._core", "--ignore-missing-stub"],
        capture_output=True,
        text=True,
        cwd=ROOT / "python" / "tests",
    )
    assert r.returncode == 0, r.stdout + r.stderr


def test_package_type_checks() -> None:
    r = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", "-p", "carl_spec"],
        capture_output=True,
        text=True,
        cwd=ROOT / "python" / "tests",
    )
    assert r.returncode == 0, r.stdout + r.stderr
