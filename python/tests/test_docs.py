"""The README and the documentation site: every code block runs, nothing dated or machine-specific.

* Every fenced block of README.md, docs/**/*.md, the environments' pages in their family crates
  (crates/carl-envs-*/docs/*.md) and the pages generated from the specs
  (scripts/docs/gen_pages.py) is executed: ```sh / ```console blocks by bash in a fresh temporary
  directory with the built `carl-spec` first on PATH (CARL_SPEC_BIN, default
  target/release/carl-spec; a ```console block's `$ ` commands one by one, each printing exactly the
  output shown after it), ```python blocks in a fresh interpreter (this one), ```json blocks are
  parsed. Rust blocks are not compiled here: each carries a skip marker naming what compiles it. A block that cannot run here is marked on the line right before its fence with
  `<!-- docs-test: skip (reason) -->`; each shows as a skipped test with its reason (pytest -ra).
* Committed text files (README, CHANGELOG, docs/, scripts/, python/, mkdocs.yml, crates/*/docs/) hold no dated
  timestamps of runs and no absolute paths of one machine.
* README.md stays a front door: at most 150 lines, links that resolve inside the repository, and an
  environment table that is what scripts/docs/readme_table.py generates from the specs.
* Gymnasium ids are `carl_spec/<id>-v<version>`, as the docs say.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import pytest

from conftest import ROOT, cli_json, cli_path

sys.path.insert(0, str(ROOT / "scripts" / "docs"))
import gen_pages  # noqa: E402
import readme_table  # noqa: E402

RUN_LANGS = {"sh", "bash", "console", "python", "json"}
# Languages shown, never run: program output, Rust (compiled by the crates' doctests and tests),
# configuration fragments.
SHOWN_LANGS = {"text", "rust", "yaml", "toml", "diff", "bibtex"}
SKIP = re.compile(r"<!--\s*docs-test:\s*skip\s*\((?P<reason>[^)]*(?:\([^)]*\)[^)]*)*)\)\s*-->")
FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>`{3,}|~{3,})[ \t]*(?P<lang>[\w+-]*)(?P<attrs>[^`]*)$")
BLOCK_TIMEOUT = 600  # a hang guard, generous: CI runs this beside the other test jobs on two cores


@dataclass
class Block:
    source: str  # file (and line) it comes from
    lang: str
    code: str
    skip: str | None  # the reason, when marked skip

    @property
    def id(self) -> str:
        return self.source


def blocks_of(text: str, name: str) -> list[Block]:
    """The fenced code blocks of a Markdown text, with the skip marker before each (if any)."""
    lines = text.splitlines()
    out: list[Block] = []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence, lang = m["indent"], m["fence"], m["lang"].lower()
        start = i
        body: list[str] = []
        i += 1
        while i < len(lines) and not (lines[i].strip().startswith(fence) and lines[i].strip().strip(fence[0]) == ""):
            line = lines[i]
            body.append(line[len(indent):] if line.startswith(indent) else line.lstrip())
            i += 1
        i += 1
        j = start - 1
        while j >= 0 and not lines[j].strip():
            j -= 1
        marker = SKIP.search(lines[j]) if j >= 0 else None
        out.append(Block(f"{name}:{start + 1}", lang, "\n".join(body) + "\n", marker["reason"] if marker else None))
    return out


def doc_sources() -> dict[str, str]:
    """README.md, every Markdown file under docs/, the environments' hand-written pages in their
    family crates (crates/carl-envs-*/docs/), and the generated pages (by their site path)."""
    texts = {"README.md": (ROOT / "README.md").read_text()}
    for p in sorted((ROOT / "docs").rglob("*.md")) + sorted((ROOT / "crates").glob("carl-envs-*/docs/*.md")):
        texts[str(p.relative_to(ROOT))] = p.read_text()
    for path, text in gen_pages.generate(cli_path(), ROOT).items():
        texts.setdefault(f"docs/{path} (generated)", text)
    return texts


def all_blocks() -> list[Block]:
    """Every block once: a generated page repeats the blocks of its hand-written source."""
    seen: set[tuple[str, str]] = set()
    out = []
    for name, text in doc_sources().items():
        for b in blocks_of(text, name):
            if (b.lang, b.code) not in seen:
                seen.add((b.lang, b.code))
                out.append(b)
    return out


def console_steps(code: str) -> list[tuple[str, list[str]]]:
    """A console block's commands (after `$ `, continued by a trailing backslash or a here-document),
    each with the output lines shown after it."""
    steps: list[tuple[str, list[str]]] = []
    cont = False
    heredoc: str | None = None
    for line in code.splitlines():
        if cont or heredoc is not None:
            steps[-1] = (steps[-1][0] + "\n" + line, steps[-1][1])
            if heredoc is not None and line == heredoc:
                heredoc = None
            cont = cont and line.endswith("\\")
            continue
        if line.startswith("$ "):
            steps.append((line[2:], []))
            cont = line.endswith("\\")
            m = re.search(r"<<-?\s*'?(\w+)'?\s*$", line)
            if m:  # a here-document: its lines up to the terminator belong to the command
                heredoc = m[1]
        elif steps:
            steps[-1][1].append(line)
    return steps


def run_block(block: Block, tmp: Path) -> None:
    env = dict(os.environ)
    bindir = tmp / ".bin"
    bindir.mkdir()
    (bindir / "carl-spec").symlink_to(cli_path().resolve())
    (bindir / "python").symlink_to(sys.executable)
    (bindir / "python3").symlink_to(sys.executable)
    env["PATH"] = f"{bindir}{os.pathsep}{env.get('PATH', '')}"
    env["CARL_SPEC_REPO"] = str(ROOT)
    env.setdefault("MPLBACKEND", "Agg")
    work = tmp / "work"
    work.mkdir()
    if block.lang == "console":
        # Each command runs in turn; the output shown after it must be what it prints (stdout and
        # stderr together, trailing spaces ignored).
        for command, shown in console_steps(block.code):
            r = subprocess.run(["bash", "-o", "pipefail", "-c", command], cwd=work, env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=BLOCK_TIMEOUT)
            assert r.returncode == 0, f"{block.source}: `{command}` exited {r.returncode}:\n{r.stdout[-3000:]}"
            if shown:
                got = [line.rstrip() for line in r.stdout.rstrip("\n").splitlines()]
                want = [line.rstrip() for line in shown]
                assert got == want, f"{block.source}: `{command}` printed\n" + "\n".join(got) + "\ninstead of\n" + "\n".join(want)
        return
    if block.lang in ("sh", "bash"):
        cmd = ["bash", "-euo", "pipefail", "-c", block.code]
    elif block.lang == "python":
        cmd = [sys.executable, "-W", "error", "-c", block.code]
    else:  # json
        json.loads(block.code)
        return
    r = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True, timeout=BLOCK_TIMEOUT)
    assert r.returncode == 0, (
        f"{block.source}: the {block.lang} block exited {r.returncode}\n--- block\n{block.code}"
        f"--- stdout (tail)\n{r.stdout[-3000:]}\n--- stderr (tail)\n{r.stderr[-3000:]}"
    )


BLOCKS = all_blocks()


@pytest.mark.parametrize("block", [b for b in BLOCKS if b.lang in RUN_LANGS or b.skip is not None], ids=lambda b: b.id)
def test_code_block_runs(block: Block, tmp_path: Path) -> None:
    if block.skip is not None:  # listed with its reason in pytest's summary (-ra)
        pytest.skip(f"{block.source}: not run: {block.skip}")
    run_block(block, tmp_path)


def test_every_block_has_a_known_language() -> None:
    unknown = [f"{b.source}: ```{b.lang}" for b in BLOCKS if b.lang not in RUN_LANGS | SHOWN_LANGS]
    unknown += [f"{b.source}: a rust block needs a skip marker naming what compiles it" for b in BLOCKS
                if b.lang == "rust" and b.skip is None]
    assert not unknown, "fences need a language (sh, console, python, json; or text, rust, yaml, toml, diff, bibtex):\n" + "\n".join(unknown)


def test_skipped_blocks_are_few_and_listed() -> None:
    skipped = [b for b in BLOCKS if b.skip is not None]
    for b in skipped:
        assert b.skip.strip(), f"{b.source}: a skip needs a reason"
    print("\ncode blocks not run (docs-test: skip):")
    for b in skipped:
        print(f"  {b.source} [{b.lang}]: {b.skip}")
    runnable = [b for b in BLOCKS if b.lang in RUN_LANGS]
    assert len(skipped) <= max(12, len(runnable) // 5), f"{len(skipped)} of {len(runnable)} blocks skipped: too many"


# --- nothing dated, nothing of one machine -------------------------------------------------------

DATE = re.compile(r"(?<![\w.])(19|20)\d\d-(0[1-9]|1[0-2])-(0[1-9]|[12]\d|3[01])(?![\w.])")
TIME = re.compile(r"(?<![\w.:\[])([01]\d|2[0-3]):[0-5]\d(:[0-5]\d)?(?![\w:\]])")
MACHINE_PATH = re.compile(
    r"(?<![\w.~/:-])/(?:tmp|work|home|root|Users|mnt|opt|srv|var|scratch|media|private|nix|data)/[\w.~+-]"
    r"|\b[A-Za-z]:\\\\?(?:Users|Program Files)"
)
# Absolute paths that are the same on every machine.
ALLOWED_PATHS = ("/dev/null", "/usr/bin/env", "/proc/self", "/bin/sh", "/bin/bash")
SCANNED = ("README.md", "CHANGELOG.md", "mkdocs.yml", "docs", "scripts", "python", ":(glob)crates/*/docs/**")
TEXT_SUFFIXES = {".md", ".py", ".pyi", ".sh", ".txt", ".json", ".yml", ".yaml", ".toml", ".cfg", ".ini", ".svg", ""}
# The test of these rules spells the patterns it looks for.
NOT_SCANNED = {"python/tests/test_docs.py"}


def committed_text_files() -> list[Path]:
    r = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard", "--", *SCANNED],
                       cwd=ROOT, capture_output=True, text=True)
    if r.returncode == 0:
        names = sorted(set(r.stdout.split("\n")) - {""})
    else:  # not a git checkout: every file below the scanned paths
        def below(s: str) -> list[Path]:
            if s.startswith(":(glob)"):
                return list(ROOT.glob(s[len(":(glob)"):]))
            return [ROOT / s] if (ROOT / s).is_file() else list((ROOT / s).rglob("*"))

        names = sorted(str(p.relative_to(ROOT)) for s in SCANNED for p in below(s) if p.is_file())
    out = []
    for n in names:
        p = ROOT / n
        if n in NOT_SCANNED or not p.is_file() or p.suffix not in TEXT_SUFFIXES:
            continue
        if p.suffix == "" and not p.read_bytes()[:2] == b"#!":
            continue
        out.append(p)
    return out


def test_no_timestamps_or_machine_paths_in_committed_text() -> None:
    problems = []
    files = committed_text_files()
    assert any(p.name == "README.md" for p in files)
    for p in files:
        try:
            text = p.read_text()
        except UnicodeDecodeError:
            continue
        for no, line in enumerate(text.splitlines(), 1):
            where = f"{p.relative_to(ROOT)}:{no}"
            for m in DATE.finditer(line):
                problems.append(f"{where}: a date ({m.group(0)}): history belongs in git, current facts undated")
            for m in TIME.finditer(line):
                problems.append(f"{where}: a time of day ({m.group(0)})")
            for m in MACHINE_PATH.finditer(line):
                rest = line[m.start():]
                if not rest.startswith(ALLOWED_PATHS):
                    problems.append(f"{where}: an absolute path of one machine ({rest[:60]})")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("text,bad", [
    ("measured 2026-11-24 at 22:47", True),
    # The machine paths are put together here, so this file names none itself.
    ("run " + "/".join(["", "work", "venvs", "peers", "bin", "python"]) + " x.py", True),
    ("python3 -m venv " + "/".join(["", "tmp", "mjvenv"]), True),
    ("cat " + "/".join(["", "home", "me", "data"]), True),
    ("cmd > /dev/null; #!/usr/bin/env bash", False),
    ("x[10:20], ratio 3:1, see https://example.org/home/x and v1.2.3", False),
])
def test_the_scan_finds_what_it_should(text: str, bad: bool) -> None:
    found = bool(DATE.search(text) or TIME.search(text) or
                 any(not text[m.start():].startswith(ALLOWED_PATHS) for m in MACHINE_PATH.finditer(text)))
    assert found == bad


# --- README ---------------------------------------------------------------------------------------

README = (ROOT / "README.md").read_text()
LINK = re.compile(r"\[[^\]]*\]\((?P<target>[^)\s]+)(?:\s+\"[^\"]*\")?\)")


def test_readme_is_short() -> None:
    n = len(README.splitlines())
    assert n <= 150, f"README.md has {n} lines (at most 150: details belong on the documentation site)"


def test_readme_links_stay_inside_the_repository() -> None:
    for m in LINK.finditer(README):
        t = m["target"]
        if re.match(r"[a-z]+:", t) or t.startswith("#"):
            continue
        path = (ROOT / t.split("#")[0]).resolve()
        assert path.is_relative_to(ROOT), f"README links outside the repository: {t}"
        assert path.exists(), f"README links to a missing file: {t}"


def test_readme_environment_table_is_current() -> None:
    """The table between the markers is what scripts/docs/readme_table.py prints from the specs
    (versioned id, family, features, engine, fidelity): adding an environment or bumping a version
    needs `python3 scripts/docs/readme_table.py --write`, no hand edit."""
    assert README.count(readme_table.BEGIN) == 1 and README.count(readme_table.END) == 1, "README.md lacks the table's markers"
    want = readme_table.replace(README, readme_table.table(cli_path(), ROOT))
    assert README == want, "README.md's environment table is not current: python3 scripts/docs/readme_table.py --write"
    rows = [line for line in README.split(readme_table.BEGIN)[1].split(readme_table.END)[0].splitlines() if line.startswith("| [`")]
    assert len(rows) == len(cli_json("list", "--format", "json"))


def test_gymnasium_ids_are_versioned() -> None:
    """Every runtime is registered with Gymnasium as `carl_spec/<id>-v<version>`, the id the docs show."""
    gymnasium = pytest.importorskip("gymnasium")
    import carl_spec  # noqa: F401  (registers the ids)

    registered = {k for k in gymnasium.registry if k.startswith("carl_spec/")}
    want = {f"carl_spec/{e['id']}-v{e.get('version', 0)}" for e in cli_json("list", "--format", "json")}
    runtimes = {k.rsplit("-v", 1)[0] for k in registered}
    want = {w for w in want if w.rsplit("-v", 1)[0] in runtimes}
    assert registered == want, f"registered {sorted(registered ^ want)} differ from carl_spec/<id>-v<version>"


# --- paths named in the docs ----------------------------------------------------------------------

PATH_TOKEN = re.compile(r"`((?:src|tests|benches|crates|examples|scripts|python|specs|schema|robots|data|vendor|docs)/[^`\s]*)`")


def test_repository_paths_named_in_the_docs_exist() -> None:
    """A file or folder of this repository named in backticks (`tests/parity.rs`) exists, so a
    moved file shows up here; names with placeholders (`<id>`, `ENV/SET`, `*`, `{a,b}`) are left."""
    missing = []
    for name, text in doc_sources().items():
        for m in PATH_TOKEN.finditer(text):
            path = m[1].rstrip(".,;:)")
            if re.search(r"[<>*{}…]|\b[A-Z]{2,}\b|\.\.\.", path):
                continue
            if not (ROOT / path).exists():
                missing.append(f"{name}: `{path}`")
    assert not missing, "paths named in the docs that do not exist:\n" + "\n".join(sorted(set(missing)))
