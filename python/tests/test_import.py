"""What `import carl_spec` loads: only what `cs.make` needs; everything else on first use.

Each check runs in a fresh interpreter (this test process has imported everything already).
"""

from __future__ import annotations

import json
import subprocess
import sys
from typing import Any


def fresh(code: str) -> Any:
    """Run `code` in a new interpreter; it prints one JSON value, returned here."""
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


# Never imported by `import carl_spec; cs.make(...)`: the training frameworks, carl_spec's
# integrations, and its modules that `make` does not use (loaded by the names that need them).
DEFERRED = [
    "torch",
    "stable_baselines3",
    "ray",
    "carl_spec.sb3",
    "carl_spec.rllib",
    "carl_spec.compat",
    "carl_spec._audit",
    "carl_spec._wrap",
    "carl_spec.specs",
    "carl_spec.vector",
]


def test_import_and_make_load_nothing_deferred() -> None:
    loaded = fresh(
        "import json, sys, carl_spec as cs\n"
        "env = cs.make('cartpole'); env.reset(seed=0); env.step(0)\n"
        f"print(json.dumps([m for m in {DEFERRED!r} if m in sys.modules]))"
    )
    assert loaded == []


def test_gymnasium_registration_without_touching_deferred_names() -> None:
    out = fresh(
        "import json, gymnasium, carl_spec\n"
        "env = gymnasium.make('carl_spec/cartpole-v0'); env.reset(seed=0)\n"
        "venv = gymnasium.make_vec('carl_spec/cartpole-v0', 3, vectorization_mode='vector_entry_point')\n"
        "obs, _ = venv.reset(seed=0)\n"
        "print(json.dumps([type(env.unwrapped).__name__, type(venv).__name__, list(obs.shape)]))"
    )
    assert out == ["CarlEnv", "CarlVectorEnv", [3, 4]]


def test_every_public_name_resolves_in_a_fresh_process() -> None:
    out = fresh(
        "import json, carl_spec as cs\n"
        "missing = [n for n in cs.__all__ if getattr(cs, n, None) is None]\n"
        "print(json.dumps([missing, sorted(set(cs.__all__) - set(dir(cs)))]))"
    )
    assert out == [[], []]


def test_wrap_and_audit_are_functions_and_the_package_a_plain_module() -> None:
    # `cs.wrap` / `cs.audit` live in the private modules `_wrap` / `_audit`: importing those
    # first must leave the functions in place, and the package stays a plain module (cloudpickle
    # ships plain modules by reference; a module subclass does not pickle, issue 31 item 4).
    out = fresh(
        "import json, types, carl_spec._audit, carl_spec._wrap\n"
        "import carl_spec as cs\n"
        "from carl_spec import audit, wrap, AuditReport, ContextualWrapper\n"
        "print(json.dumps([cs.wrap is wrap, cs.audit is audit, type(cs.wrap).__name__, type(cs.audit).__name__,"
        " AuditReport.__name__, ContextualWrapper.__name__, type(cs) is types.ModuleType]))"
    )
    assert out == [True, True, "function", "function", "AuditReport", "ContextualWrapper", True]


def test_unknown_attribute_is_an_attribute_error() -> None:
    out = fresh(
        "import json, carl_spec as cs\n"
        "try:\n    cs.no_such_name\nexcept AttributeError as e:\n    print(json.dumps(str(e)))"
    )
    assert "no_such_name" in out
