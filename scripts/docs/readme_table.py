#!/usr/bin/env python3
"""The README's environment table, generated from the specs through the built `carl-spec`.

    python3 scripts/docs/readme_table.py            # prints the table
    python3 scripts/docs/readme_table.py --write    # replaces it in README.md, between the markers
    python3 scripts/docs/readme_table.py --check    # exit 1 when README.md's table is not current

One row per environment (`carl-spec list`): its versioned id (`<id>-v<version>`, linking to the
hand-written half of its page in its family's crate), family, number of context features, engine
(the spec's `engine`) and fidelity to its reference (the page's front matter). Adding an
environment, or bumping a version, changes the table by running this script; python/tests/test_docs.py
fails while README.md's table is not what it prints.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
import gen_pages  # noqa: E402

ROOT = gen_pages.ROOT
BEGIN = "<!-- generated: environment table (scripts/docs/readme_table.py --write) -->"
END = "<!-- end of the generated environment table -->"
# Registry order of the families (crates/carl-spec/src/envs/registry.rs); a family not listed
# here follows, alphabetically.
FAMILY_ORDER = ("classic_control", "box2d", "brax", "dmc", "rna_design", "mario")


def specs(bin_: Path | None = None) -> list[dict[str, Any]]:
    bin_ = bin_ or gen_pages.binary()
    ids = [e["id"] for e in json.loads(gen_pages.run(bin_, "list", "--format", "json"))]
    out = [json.loads(gen_pages.run(bin_, "show", i, "--format", "json")) for i in ids]

    def key(s: dict[str, Any]) -> tuple[int, str, str]:
        f = s["family"]
        return (FAMILY_ORDER.index(f) if f in FAMILY_ORDER else len(FAMILY_ORDER), f, s["id"])

    return sorted(out, key=key)


def table(bin_: Path | None = None, root: Path = ROOT) -> str:
    rows = ["| environment | family | features | engine | fidelity |", "|---|---|---:|---|---|"]
    for s in specs(bin_):
        page = gen_pages.env_doc(root, s).relative_to(root).as_posix()
        versioned = f"{s['id']}-v{s.get('version', 0)}"
        engine = f"`{s['engine']}`" if s.get("engine") else "–"
        fidelity = gen_pages.env_meta(root, s)["fidelity"]
        rows.append(f"| [`{versioned}`]({page}) | `{s['family']}` | {len(s['features'])} | {engine} "
                    f"| {gen_pages.cell(fidelity)} |")
    return "\n".join(rows) + "\n"


def replace(readme: str, new_table: str) -> str:
    """README's text with `new_table` between the markers."""
    if BEGIN not in readme or END not in readme:
        raise SystemExit(f"README.md lacks the markers {BEGIN!r} … {END!r}")
    head, rest = readme.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n{new_table}{END}{tail}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--write", action="store_true", help="replace the table in README.md")
    g.add_argument("--check", action="store_true", help="exit 1 when README.md's table is not current")
    args = ap.parse_args()
    readme_path = ROOT / "README.md"
    t = table()
    if not (args.write or args.check):
        sys.stdout.write(t)
        return
    readme = readme_path.read_text()
    new = replace(readme, t)
    if args.check:
        if new != readme:
            raise SystemExit("README.md's environment table is not current: python3 scripts/docs/readme_table.py --write")
        return
    if new != readme:
        readme_path.write_text(new)
        print("README.md: environment table updated")


if __name__ == "__main__":
    main()
