"""mkdocs hooks (mkdocs.yml `hooks:`): the pages made from the specs and the schema.

At every build, `gen_pages.generate()` runs the built `carl-spec` (CARL_SPEC_BIN, default
target/release/carl-spec) and its pages replace or join the files under docs/: among them every
environment's page, whose hand-written half lives in its family's crate
(crates/carl-envs-<family>/docs/<id>.md), so docs/ holds no per-environment file. The Environments
section of the navigation lists every environment it found.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from mkdocs.structure.files import File, Files

sys.path.insert(0, str(Path(__file__).resolve().parent))
import gen_pages  # noqa: E402

_pages: dict[str, str] = {}


def on_config(config: Any) -> Any:
    _pages.clear()
    _pages.update(gen_pages.generate())
    envs = [p for p in _pages if p.startswith("envs/") and p != "envs/index.md"]
    section = ["envs/index.md"] + [{Path(p).stem: p} for p in envs]
    nav = config["nav"]
    for i, item in enumerate(nav):
        if isinstance(item, dict) and "Environments" in item:
            nav[i] = {"Environments": section}
    return config


def on_files(files: Files, config: Any) -> Files:
    for path, content in _pages.items():
        existing = files.get_file_from_path(path)
        if existing is not None:
            files.remove(existing)
        files.append(File.generated(config, path, content=content))
    return files
