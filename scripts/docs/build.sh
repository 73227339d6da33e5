#!/usr/bin/env bash
# Build the documentation site strictly (every warning fails: broken links, missing anchors, pages
# outside the navigation) into target/site, with the pinned tools of python/requirements-docs.txt
# in .venv-docs/ (override with CARL_SPEC_DOCS_VENV). Needs the built CLI (CARL_SPEC_BIN, default
# target/release/carl-spec): the environment pages, the spec-language reference and the statistics
# are generated from it at build time (scripts/docs/hooks.py). Open target/site/index.html, or
# serve it: `.venv-docs/bin/mkdocs serve`.
set -euo pipefail
cd "$(dirname "$0")/../.."
python="${PYTHON:-python3}"
venv="${CARL_SPEC_DOCS_VENV:-.venv-docs}"
[ -x "$venv/bin/python" ] || "$python" -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r python/requirements-docs.txt
export CARL_SPEC_BIN="${CARL_SPEC_BIN:-$PWD/target/release/carl-spec}"
[ -x "$CARL_SPEC_BIN" ] || { echo "$CARL_SPEC_BIN not found: cargo build --release --bin carl-spec" >&2; exit 1; }
NO_MKDOCS_2_WARNING=1 "$venv/bin/mkdocs" build --strict --site-dir target/site
