#!/usr/bin/env python3
"""The documentation pages made from the specs and the schema, through the built `carl-spec`.

    python3 scripts/docs/gen_pages.py --out target/docs-generated   # writes them, to read
    python3 scripts/docs/gen_pages.py --pictures   # the environments' pictures to render (render_envs.sh)

mkdocs calls `generate()` from scripts/docs/hooks.py at every build; python/tests/test_docs.py
calls it too, to run the code blocks of the generated pages. Pages (paths below docs/):

* `envs/index.md`: every environment (`carl-spec list`), with its version, family, feature count,
  engine (the spec's) and fidelity (from the front matter of its page) and its picture.
* `envs/<id>.md`: one page per environment from `carl-spec show <id> --format json`: description,
  version and Gymnasium id, spaces, the picture made by `carl-spec render` (committed under
  docs/assets/envs/ by scripts/docs/render_envs.sh), the features with units, bounds, effects and
  aliases, the distributions and instance sets; then the hand-written part, which lives beside the
  environment's code in its family's crate, crates/carl-envs-<family>/docs/<id>.md (front matter
  `fidelity` and optionally `engine_detail`, sections on the engine, fidelity and deviations), if
  there is one. Adding an environment adds its page there; nothing under docs/ changes by hand
  (its picture, asked for by the front matter `picture: FORMAT ARGS…`, is rendered into
  docs/assets/envs/ by scripts/docs/render_envs.sh).
* `reference/spec-language.md`: docs/reference/spec-language.md with the tables of every object of
  the JSON Schema (`carl-spec schema`) in place of its `<!-- generated: schema -->` line.
* `reference/statistics.md`: docs/reference/statistics.md with `carl-spec stats` in place of its
  `<!-- generated: stats -->` line.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
SCHEMA_MARKER = "<!-- generated: schema -->"
STATS_MARKER = "<!-- generated: stats -->"
ENV_PICTURES = ("gif", "png")
# The schema's objects in reading order (the others follow alphabetically).
SCHEMA_ORDER = ("RawEnvSpec", "RawFeature", "Include", "FeaturePatch", "RawFragment", "RawDistribution", "Sampler",
                "AtBounds", "RawInstanceSet", "SampledSet", "ExplicitInstance", "GridSet", "Space", "Upstream")


def binary(root: Path = ROOT) -> Path:
    p = Path(os.environ.get("CARL_SPEC_BIN", root / "target" / "release" / "carl-spec"))
    if not p.exists():
        raise SystemExit(f"{p} not found: build it first (cargo build --release --bin carl-spec), or set CARL_SPEC_BIN")
    return p


def run(bin_: Path, *args: str) -> str:
    r = subprocess.run([str(bin_), *args], capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"carl-spec {' '.join(args)} exited {r.returncode}: {r.stderr}")
    return r.stdout


def front_matter(text: str) -> tuple[dict[str, str], str]:
    """A page's `key: value` front matter (between --- lines) and the rest of the page."""
    m = re.match(r"---\n(.*?)\n---\n", text, re.S)
    if not m:
        return {}, text
    meta = {}
    for line in m[1].splitlines():
        if ":" in line:
            k, v = line.split(":", 1)
            meta[k.strip()] = v.strip().strip('"')
    return meta, text[m.end():]


def family_crate(family: str) -> str:
    """The crate of an environment family: `carl-envs-<family>` (`rna_design` → `carl-envs-rna-design`)."""
    return "carl-envs-" + family.replace("_", "-")


def env_doc(root: Path, spec: dict[str, Any]) -> Path:
    """The hand-written page of an environment, in its family's crate: `crates/carl-envs-<family>/docs/<id>.md`."""
    return root / "crates" / family_crate(spec["family"]) / "docs" / f"{spec['id']}.md"


def env_meta(root: Path, spec: dict[str, Any]) -> dict[str, str]:
    """The facts of an environment beside its spec: the engine (the spec's `engine`, with the page's
    `engine_detail`) and the fidelity to its reference (the page's front matter `fidelity`)."""
    p = env_doc(root, spec)
    meta, _ = front_matter(p.read_text()) if p.exists() else ({}, "")
    engine = f"`{spec['engine']}`" if spec.get("engine") else "–"
    if meta.get("engine_detail"):
        engine += f" ({meta['engine_detail']})"
    return {"engine": engine, "fidelity": meta.get("fidelity", "–")}


def gym_id(spec: dict[str, Any]) -> str:
    """The Gymnasium id of an environment: `carl_spec/<id>-v<version>`."""
    return f"carl_spec/{spec['id']}-v{spec.get('version', 0)}"


def num(x: Any) -> str:
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, float):
        if x == int(x) and abs(x) < 1e15:
            return f"{int(x)}" if abs(x) >= 1 or x == 0 else f"{x:g}"
        return f"{x:.6g}"
    if isinstance(x, list):
        return "[" + ", ".join(num(v) for v in x) + "]"
    return str(x)


def cell(text: Any) -> str:
    """Text safe inside a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def unit(u: str | None) -> str:
    if not u:
        return ""
    return u.replace("^2", "²").replace("^3", "³").replace("^-1", "⁻¹")


def bounds(f: dict[str, Any]) -> str:
    b = f.get("bounds")
    if not b or b == [None, None] and f["type"] in ("bool", "categorical"):
        return "–"
    lo, hi = b
    return f"[{'−∞' if lo is None else num(lo)}, {'+∞' if hi is None else num(hi)}]"


def feature_type(f: dict[str, Any]) -> str:
    if f["type"] == "categorical":
        return f"categorical ({len(f.get('choices') or [])} choices)"
    return f["type"]


def default(f: dict[str, Any]) -> str:
    if "default" in f:
        d = f["default"]
        if f["type"] == "categorical" and f.get("choice_labels") and f.get("choices") and d in f["choices"]:
            return f"{num(d)} ({f['choice_labels'][f['choices'].index(d)]})"
        return num(d)
    return f"computed: {f.get('default_from', '?')}"


def space(s: dict[str, Any]) -> str:
    t = s.get("type")
    if t == "discrete":
        return f"Discrete({s['n']})"
    if t == "box":
        return f"Box(shape {tuple(s.get('shape', []))}, {s.get('dtype', 'float32')})"
    if t == "runtime":
        return "set by the runtime (depends on the options)"
    return json.dumps(s)


def sampler(s: dict[str, Any]) -> str:
    kind = s.get("kind", "?")
    params = ", ".join(f"{k}={num(v)}" for k, v in s.items() if k != "kind")
    return f"{kind}({params})"


def instance_set_source(s: dict[str, Any]) -> str:
    if "sampled" in s:
        x = s["sampled"]
        return f"{x['size']} drawn from `{x['distribution']}` (seed {x['seed']})"
    if "explicit" in s:
        names = [i.get("name") for i in s["explicit"] if i.get("name")]
        listed = ", ".join(names[:8]) + (", …" if len(names) > 8 else "")
        return f"{len(s['explicit'])} listed" + (f": {listed}" if names else "")
    if "grid" in s:
        g = s["grid"]
        return "grid: " + ", ".join(f"{k} {json.dumps(v)}" for k, v in g.items())
    return "–"


def picture(root: Path, env_id: str) -> str | None:
    for ext in ENV_PICTURES:
        if (root / "docs" / "assets" / "envs" / f"{env_id}.{ext}").exists():
            return f"{env_id}.{ext}"
    return None


CARL_BENCH = Path("python/tests/fixtures/carl_bench_1_1_1.json")
# Environments the paper has no appendix table for (their features are the 2021 CARL code's), and
# the features beyond the paper's tables (carl-bench 1.1.1's): both as crates/carl-spec-core/tests/integration/paper_tables.rs has them.
NO_PAPER_TABLE = {"half_cheetah", "ur5e", "mountain_car_continuous"}
BEYOND_PAPER = {"mario": ("noise_seed", "level_width")}


def paper_section(spec: dict[str, Any]) -> list[str]:
    env_id = spec["id"]
    beyond = [f["name"] for f in spec["features"]
              if f["name"].startswith("mass_") or f["name"] in BEYOND_PAPER.get(env_id, ())]
    if env_id in NO_PAPER_TABLE:
        text = ("The paper has no appendix table for this environment: its features are the 2021 CARL "
                "code's definitions, checked by `crates/carl-spec-core/tests/integration/paper_tables.rs`.")
    else:
        text = ("Every feature of the paper's appendix table is here with the same name, default, bounds "
                "and type (`crates/carl-spec-core/tests/integration/paper_tables.rs`; where the table prints a rounded number, the spec "
                "holds the 2021 code's exact value, within 0.005).")
    if beyond:
        text += " Beyond the paper, from carl-bench 1.1.1: " + ", ".join(f"`{n}`" for n in beyond) + "."
    return ["## Against the paper", "", text, ""]


def carl_bench_section(root: Path, spec: dict[str, Any]) -> list[str]:
    """carl-bench 1.1.1's features of this environment (as recorded by scripts/record_carl_bench.py)
    beside the spec's: the same name or an alias, default and bounds, or absent here."""
    p = root / CARL_BENCH
    if not p.exists():
        return []
    classes = json.loads(p.read_text())["classes"]
    cls = next((c for c in spec.get("aliases", []) if c in classes), None)
    if cls is None:
        return []
    by_name = {}
    for f in spec["features"]:
        for n in [f["name"], *f.get("aliases", [])]:
            by_name[n] = f

    def cb_bounds(x: dict[str, Any]) -> str:
        if "lower" not in x:
            return "–"
        lo, hi = x["lower"], x["upper"]
        fmt = lambda v, inf: inf if v in ("inf", "-inf") else num(v)  # noqa: E731
        return f"[{fmt(lo, '−∞')}, {fmt(hi, '+∞')}]"

    out = [f"## Against carl-bench 1.1.1 (`{cls}`)", "",
           "carl-bench's context features as recorded from the package (`scripts/record_carl_bench.py` → "
           f"`{CARL_BENCH.as_posix()}`), beside this spec's:", "",
           "| carl-bench feature | its default | its bounds | here | default here | bounds here |",
           "|---|---|---|---|---|---|"]
    for x in classes[cls].get("features", []):
        f = by_name.get(x["name"])
        here = f"`{f['name']}`" if f else "not a feature here"
        d_here = default(f) if f else "–"
        b_here = bounds(f) if f else "–"
        out.append(f"| `{x['name']}` | {cell(num(x.get('default')))} | {cb_bounds(x)} | {here} | {cell(d_here)} | {b_here} |")
    out.append("")
    return out


def env_page(root: Path, spec: dict[str, Any], body: str, meta: dict[str, str], runtimes: set[str]) -> str:
    env_id = spec["id"]
    up = spec.get("upstream", {})
    out = [f"# `{env_id}`", ""]
    if spec.get("aliases"):
        out += ["CARL's " + " / ".join(f"`{a}`" for a in spec["aliases"]) + ".", ""]
    out += [spec["description"], ""]
    pic = picture(root, env_id)
    if pic:
        out += [f"![{env_id}](../assets/envs/{pic})", ""]
    rows = [
        ("Family", f"`{spec['family']}`"),
        ("Upstream", " ".join(str(up[k]) for k in ("library", "id", "version") if up.get(k))),
        ("Version", f"{spec.get('version', 0)} (`{spec['id']}-v{spec.get('version', 0)}`)"),
        ("Engine", meta["engine"]),
        ("Fidelity", meta["fidelity"]),
        ("Observation space", space(spec["observation_space"])),
        ("Action space", space(spec["action_space"])),
        ("Episode limit", f"{spec['max_episode_steps']} steps" if spec.get("max_episode_steps") else "none"),
    ]
    if env_id in runtimes:
        rows.append(("Gymnasium id", f"`{gym_id(spec)}`"))
    if spec.get("source"):
        rows.append(("Source of the context", spec["source"]))
    out += ["| property | value |", "|---|---|"] + [f"| {k} | {cell(v)} |" for k, v in rows] + [""]
    if env_id in runtimes and env_id != "mario":
        out += ["```sh", f"carl-spec show {env_id}", f"carl-spec rollout {env_id} --seed 0 --steps 3", "```", ""]
    out += [f"## Context features ({len(spec['features'])})", ""]
    if spec["features"]:
        out += ["| feature | default | bounds | unit | affects | description |",
                "|---|---|---|---|---|---|"]
        for f in spec["features"]:
            name = f"`{f['name']}`<br>{feature_type(f)}"
            if f.get("aliases"):
                name += "<br>(" + ", ".join(f"`{a}`" for a in f["aliases"]) + ")"
            if f.get("from_fragment"):
                name += f"<br>from `{f['from_fragment']}`"
            desc = f["description"]
            if f.get("choices") and f.get("choice_labels"):
                desc += " Choices: " + ", ".join(f"{num(c)} {lab}" for c, lab in zip(f["choices"], f["choice_labels"])) + "."
            elif f.get("choices"):
                desc += " Choices: " + ", ".join(num(c) for c in f["choices"]) + "."
            out.append(f"| {name} | {cell(default(f))} | {bounds(f)} | {cell(unit(f.get('unit')))} "
                       f"| {', '.join(f['affects']) or 'nothing'} | {cell(desc)} |")
        out.append("")
    dists = spec.get("distributions") or {}
    if dists:
        out += [f"## Distributions ({len(dists)})", "", "| name | samplers | at the bounds | description |", "|---|---|---|---|"]
        for name, d in dists.items():
            samplers = "<br>".join(f"`{k}` ~ {cell(sampler(s))}" for k, s in d["features"].items())
            out.append(f"| `{name}` | {samplers} | {d.get('at_bounds', '–')} | {cell(d.get('description', ''))} |")
        out.append("")
    sets = spec.get("instance_sets") or {}
    if sets:
        out += [f"## Instance sets ({len(sets)})", "", "| set | role | instances | description |", "|---|---|---|---|"]
        for name, s in sets.items():
            oob = " (out of bounds allowed)" if s.get("allow_out_of_bounds") else ""
            out.append(f"| `{env_id}/{name}` | {s.get('role', '–')} | {cell(instance_set_source(s))}{oob} "
                       f"| {cell(s.get('description', ''))} |")
        out.append("")
    if body.strip():
        out += [body.strip(), ""]
    out += paper_section(spec)
    out += carl_bench_section(root, spec)
    return "\n".join(out)


def env_index(root: Path, specs: list[dict[str, Any]]) -> str:
    out = [
        "# Environments",
        "",
        "The 16 environments of the CARL paper, each described by its spec (`specs/<id>.json`). "
        "Every page is generated from the spec (`carl-spec show ID --format json`); the fidelity to "
        "the reference and the deviations are written by hand beside the environment's code, in its "
        "family's crate (`crates/carl-envs-<family>/docs/<id>.md`). An environment's version is bumped "
        "whenever its dynamics, observation, reward or termination change "
        "([contributing](../contributing.md#versions-and-golden-trajectories)).",
        "",
        "| environment | version | family | features | engine | fidelity | picture |",
        "|---|---|---|---:|---|---|---|",
    ]
    for s in specs:
        meta = env_meta(root, s)
        pic = picture(root, s["id"])
        img = f"![{s['id']}](../assets/envs/{pic}){{ width=\"120\" }}" if pic else ""
        out.append(f"| [`{s['id']}`]({s['id']}.md) | `{s['id']}-v{s.get('version', 0)}` | `{s['family']}` "
                   f"| {len(s['features'])} | {cell(meta['engine'])} "
                   f"| {cell(meta['fidelity'])} | {img} |")
    return "\n".join(out) + "\n"


def schema_ref(v: dict[str, Any]) -> str:
    if "$ref" in v:
        name = v["$ref"].rsplit("/", 1)[-1]
        return f"[{name}](#{anchor(name)})"
    for key in ("oneOf", "anyOf", "allOf"):
        if key in v:
            return " or ".join(schema_ref(x) for x in v[key])
    t = v.get("type")
    if isinstance(t, list):
        t = " or ".join(t)
    if "enum" in v:
        return "one of " + ", ".join(f"`{json.dumps(e)}`" for e in v["enum"])
    if "const" in v:
        return f"`{json.dumps(v['const'])}`"
    if t == "array" and isinstance(v.get("items"), dict):
        return f"array of {schema_ref(v['items'])}"
    if t == "object" and isinstance(v.get("additionalProperties"), dict):
        return f"map to {schema_ref(v['additionalProperties'])}"
    return t or "any"


def anchor(name: str) -> str:
    return re.sub(r"[^a-z0-9_-]", "", name.lower().replace(" ", "-"))


def object_table(v: dict[str, Any]) -> list[str]:
    props = v.get("properties") or {}
    if not props:
        return []
    required = set(v.get("required") or [])
    out = ["| property | type | required | description |", "|---|---|---|---|"]
    for name, p in props.items():
        out.append(f"| `{name}` | {cell(schema_ref(p))} | {'yes' if name in required else ''} | {cell(p.get('description', ''))} |")
    return out


def schema_pages(schema: dict[str, Any]) -> str:
    out = ["### The spec file", ""]
    if schema.get("description"):
        out += [schema["description"], ""]
    out += object_table(schema) + [""]
    variants = schema.get("oneOf") or schema.get("anyOf") or []
    if variants:
        out += ["A file is one of:", ""] + [f"- {schema_ref(v)}" for v in variants] + [""]
    defs = schema.get("$defs") or schema.get("definitions") or {}
    first = [n for n in SCHEMA_ORDER if n in defs]
    for name in first + sorted(set(defs) - set(first)):
        d = defs[name]
        out += [f"### {name}", ""]
        if d.get("description"):
            out += [cell(d["description"]), ""]
        table = object_table(d)
        if table:
            out += table + [""]
        variants = d.get("oneOf") or d.get("anyOf")
        if variants:
            for i, var in enumerate(variants, 1):
                kind = (var.get("properties") or {}).get("kind", {}).get("const")
                label = (f"`{kind}`: " if kind else "") + (var.get("title") or var.get("description") or "")
                t = object_table(var)
                if t:
                    out += [f"Variant {i}{': ' + cell(label) if label else ''}", ""] + t + [""]
                else:
                    out += [f"- variant {i}: {cell(schema_ref(var))}{' — ' + cell(label) if label else ''}"]
            out.append("")
        if not table and not variants:
            out += [f"Type: {cell(schema_ref(d))}.", ""]
    return "\n".join(out)


def generate(bin_: Path | None = None, root: Path = ROOT) -> dict[str, str]:
    """Every generated page, by its path below docs/."""
    bin_ = bin_ or binary(root)
    listing = json.loads(run(bin_, "list", "--format", "json"))
    ids = [e["id"] for e in listing]
    runtimes = {e["id"] for e in listing if e.get("runtime", True)}
    specs = [json.loads(run(bin_, "show", i, "--format", "json")) for i in ids]
    pages = {"envs/index.md": env_index(root, specs)}
    for spec in specs:
        p = env_doc(root, spec)
        meta = env_meta(root, spec)
        _, body = front_matter(p.read_text()) if p.exists() else ({}, "")
        pages[f"envs/{spec['id']}.md"] = env_page(root, spec, body, meta, runtimes)
    src = (root / "docs" / "reference" / "spec-language.md").read_text()
    schema = json.loads(run(bin_, "schema"))
    pages["reference/spec-language.md"] = src.replace(SCHEMA_MARKER, schema_pages(schema))
    stats = (root / "docs" / "reference" / "statistics.md").read_text()
    pages["reference/statistics.md"] = stats.replace(STATS_MARKER, "```text\n" + run(bin_, "stats") + "```")
    return pages


def pictures(bin_: Path | None = None, root: Path = ROOT) -> list[tuple[str, str, list[str]]]:
    """(id, format, `carl-spec render` arguments) of every environment whose page asks for a
    picture: front matter `picture: FORMAT ARGS…` (`gif --seed 0 --policy heuristic --steps 200`,
    `png --seed 0`). scripts/docs/render_envs.sh renders them."""
    bin_ = bin_ or binary(root)
    out = []
    for e in json.loads(run(bin_, "list", "--format", "json")):
        p = env_doc(root, e)
        meta, _ = front_matter(p.read_text()) if p.exists() else ({}, "")
        if meta.get("picture"):
            fmt, *args = meta["picture"].split()
            out.append((e["id"], fmt, args))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--out", help="directory to write the generated pages into")
    g.add_argument("--pictures", action="store_true",
                   help="print `ID FORMAT RENDER-ARGS…` of every environment whose page asks for a picture")
    args = ap.parse_args()
    if args.pictures:
        for env_id, fmt, render_args in pictures():
            print(env_id, fmt, *render_args)
        return
    for path, text in generate().items():
        p = Path(args.out) / path
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
        print(p)


if __name__ == "__main__":
    main()
