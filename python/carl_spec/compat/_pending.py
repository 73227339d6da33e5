"""carl-bench 1.1.1 environments carl-spec does not have yet, in one place.

Their twin modules exist (so carl-bench code imports unchanged), but building one of these
classes, or calling one of the dm_control helpers, raises `PendingEnvironmentError` naming the
missing environment and the issue that adds it. carl-bench's test suite skips their tests with
the same message (python/tests/carl_bench_suite/conftest.py reads `PENDING`).
"""

from __future__ import annotations

from typing import Any, Callable, NoReturn

#: issue number -> what it adds
ISSUES = {
    27: "the dm_control family",
}

#: carl-bench class -> (the carl-spec environment it needs, the issue adding it)
PENDING: dict[str, tuple[str, int]] = {
}

#: carl-bench classes of the pending families that are not environments of their own
HELPERS: dict[str, tuple[str, int]] = {
    "CARLDmcEnv": ("dm_control family", 27),
    "MujocoToGymWrapper": ("dm_control family", 27),
}

class PendingEnvironmentError(NotImplementedError):
    """A carl-bench environment (or helper) carl-spec does not have yet."""


def message(what: str, env: str, issue: int) -> str:
    return (
        f"{what}: carl-spec does not have the {env} environment yet (pending issue {issue}: {ISSUES[issue]}); "
        "see docs/guides/migration.md"
    )


def reason(cls_name: str) -> str:
    env, issue = PENDING.get(cls_name) or HELPERS[cls_name]
    return message(cls_name, env, issue)


def pending_class(cls_name: str, module: str) -> type:
    """A stand-in for carl-bench's class `cls_name`: importable, refusing to be built."""

    def refuse(*_: Any, **__: Any) -> NoReturn:
        raise PendingEnvironmentError(reason(cls_name))

    def init(self: Any, *args: Any, **kwargs: Any) -> None:
        refuse()

    ns: dict[str, Any] = {
        "__init__": init,
        "__module__": module,
        "__doc__": f"carl-bench's {cls_name}; pending: {reason(cls_name)}.",
        "get_context_features": classmethod(refuse),
        "get_context_space": classmethod(refuse),
        "get_default_context": classmethod(refuse),
    }
    return type(cls_name, (), ns)


def pending_function(name: str, env: str, issue: int, module: str) -> Callable[..., NoReturn]:
    """A stand-in for a carl-bench helper of a pending environment."""

    def refuse(*_: Any, **__: Any) -> NoReturn:
        raise PendingEnvironmentError(message(f"{module}.{name}", env, issue))

    refuse.__name__ = refuse.__qualname__ = name
    refuse.__module__ = module
    refuse.__doc__ = f"carl-bench's {name}; pending: {message(name, env, issue)}."
    return refuse
