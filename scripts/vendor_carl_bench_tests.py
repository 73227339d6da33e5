#!/usr/bin/env python3
"""Vendor carl-bench 1.1.1's own test suite (automl/CARL `test/*.py` at the v1.1.1 tag) into
python/tests/carl_bench_suite/, changing only the import prefix `carl.` -> `carl_spec.compat.`.

    python scripts/vendor_carl_bench_tests.py /path/to/CARL      # a clone of github.com/automl/CARL

The rewrite is mechanical: every `carl` module reference (`import carl`, `from carl.x import`,
`carl.envs.__all__`) becomes the `carl_spec.compat` one; nothing else changes. The LICENSE
(Apache-2.0) is copied alongside. `--check` verifies the vendored files instead of writing them.
See python/tests/carl_bench_suite/PROVENANCE.md.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

REPO = "https://github.com/automl/CARL"
TAG = "v1.1.1"
COMMIT = "0eb3bb2d5648e088e99a10376296b88d59dc2630"  # the v1.1.1 tag (pyproject.toml version = "1.1.1")
DEST = Path(__file__).resolve().parents[1] / "python" / "tests" / "carl_bench_suite"

# `carl` as a module name: not part of a longer name or attribute (`my_carl`, `x.carl`).
_DOTTED = re.compile(r"(?<![\w.])carl\.(?=\w)")
_BARE_IMPORT = re.compile(r"^(\s*)import carl\s*$", re.MULTILINE)


def rewrite(text: str) -> str:
    """carl-bench's test file with only its import prefix changed."""
    text = _BARE_IMPORT.sub(r"\1import carl_spec.compat", text)
    return _DOTTED.sub("carl_spec.compat.", text)


def git(clone: Path, *args: str) -> str:
    return subprocess.run(["git", "-C", str(clone), *args], check=True, capture_output=True, text=True).stdout


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("clone", type=Path, help="a git clone (or bare mirror) of automl/CARL")
    ap.add_argument("--check", action="store_true", help="compare with the vendored files instead of writing")
    args = ap.parse_args()
    tagged = git(args.clone, "rev-parse", f"{TAG}^{{commit}}").strip()
    if tagged != COMMIT:
        print(f"{TAG} is {tagged} in this clone, expected {COMMIT}", file=sys.stderr)
        return 1
    files = {"LICENSE": git(args.clone, "show", f"{COMMIT}:LICENSE")}
    for name in git(args.clone, "ls-tree", "--name-only", COMMIT, "test/").split():
        if name.endswith(".py"):
            files[Path(name).name] = rewrite(git(args.clone, "show", f"{COMMIT}:{name}"))
    stale = []
    for name, text in sorted(files.items()):
        path = DEST / name
        if args.check:
            if not path.exists() or path.read_text(encoding="utf-8") != text:
                stale.append(name)
        else:
            DEST.mkdir(parents=True, exist_ok=True)
            path.write_text(text, encoding="utf-8")
    if stale:
        print(f"differs from {REPO}@{COMMIT} (rewritten): {', '.join(stale)}", file=sys.stderr)
        return 1
    print(f"{'checked' if args.check else 'wrote'} {len(files)} files ({REPO}@{COMMIT})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
