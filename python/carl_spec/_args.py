"""The keyword arguments `make`, `make_vec` and `wrap` share about contexts: checked once here and
handed to the native constructors as one frozen `_core.ContextArgs` (contexts and options as
JSON objects, noise as `(name, kind, std)` triples). Also the checks of sizes and seeds that
`make_vec` shares with the CLI and with `cs.make`."""

from __future__ import annotations

import json
import math
import numbers
from typing import Any, Mapping, Union

from . import _core
from ._errors import UnknownNameError

#: A noise standard deviation: a number (the feature's unit) or a percentage string of the
#: feature's |default| ("10%").
NoiseStd = Union[float, str]

#: Characters of input repeated in a message before it is cut (as the library's `text::quote`).
_MAX_SHOWN = 80
#: Longest name that can name anything (environments, features, sets, distributions).
_MAX_NAME = 200


def _shown(c: str) -> str:
    if c in '"\\':
        return "\\" + c
    return c if c.isprintable() else c.encode("unicode_escape").decode("ascii")


def quote(text: str) -> str:
    """`text` in double quotes, control characters escaped and long input cut (as the library's
    `carl_spec::text::quote`)."""
    shown = "".join(_shown(c) for c in text[:_MAX_SHOWN])
    if len(text) > _MAX_SHOWN:
        return f'"{shown}…" ({len(text.encode("utf-8", "replace"))} bytes)'
    return f'"{shown}"'


def check_name(what: str, name: Any) -> str:
    """A name given by the caller: a string that could name something (no control characters, not
    megabytes long), else an unknown name, quoted escaped and cut."""
    if not isinstance(name, str):
        raise ValueError(f"{what} must be a string, got {type(name).__name__} {quote(repr(name))}")
    if len(name) > _MAX_NAME or not name.isprintable():
        raise UnknownNameError(f"{what}: no such name {quote(name)}")
    return name


def check_int(what: str, value: Any, low: int = 0, high: int | None = None) -> int:
    """An int argument in `low..high` (inclusive), else a ValueError naming it (never NumPy's or
    PyO3's OverflowError)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{what} must be an int, got {type(value).__name__} {quote(repr(value))}")
    n = int(value)
    if n < low or (high is not None and n > high):
        shown = quote(str(n))[1:-1]
        if high is None:
            raise ValueError(f"{what}={shown} is below {low}")
        raise ValueError(f"{what}={shown} is outside {low}..={high}")
    return n


def check_seed(seed: Any, what: str = "seed") -> int | None:
    """Gymnasium's seed rule (`gymnasium.utils.seeding.np_random`: None or a non-negative Python
    int), bounded by the engines' 64-bit seeds: `0 <= seed < 2**64`."""
    if seed is None:
        return None
    if not isinstance(seed, int):
        raise ValueError(f"{what} must be None or a non-negative int below 2**64, got {type(seed).__name__} {quote(repr(seed))}")
    return check_int(what, seed, 0, 2**64 - 1)


def noise_triples(noise: Mapping[str, NoiseStd] | None) -> list[tuple[str, str, float]] | None:
    if noise is None:
        return None
    if not isinstance(noise, Mapping):
        raise ValueError(
            f"context_noise must map feature names to a std (a number, or a percentage such as '10%'), got {quote(repr(noise))}"
        )
    out = []
    for name, std in noise.items():
        name = check_name("context_noise", name)
        where = f"context_noise[{quote(name)}]"
        if isinstance(std, bool):
            raise ValueError(f"{where}: a std is a number or a percentage string, got {std!r}")
        if isinstance(std, str):
            text = std.strip()
            try:
                if not text.endswith("%"):
                    raise ValueError
                value = float(text[:-1]) / 100.0
            except ValueError:
                raise ValueError(f"{where}: {quote(std)} is neither a number nor a percentage such as '10%'") from None
            out.append((name, "relative", _finite(where, value)))
        elif isinstance(std, numbers.Real):
            out.append((name, "absolute", _finite(where, std)))
        else:
            raise ValueError(f"{where}: a std is a number or a percentage string, got {quote(repr(std))}")
    return out


def _finite(where: str, value: Any) -> float:
    try:
        x = float(value)
    except OverflowError:
        x = math.inf
    if not math.isfinite(x):
        raise ValueError(f"{where}: {quote(repr(value))} is not a finite number")
    return x


def _value(where: str, value: Any) -> Any:
    """One context or option value as JSON takes it: a bool, a string, a finite number or a list."""
    if isinstance(value, (bool, str)):
        return value
    if hasattr(value, "tolist") and not isinstance(value, (list, tuple)):
        value = value.tolist()  # NumPy scalars and arrays
        if isinstance(value, (bool, str)):
            return value
    if isinstance(value, numbers.Integral):
        return int(value) if abs(int(value)) < 2**63 else _finite(where, value)
    if isinstance(value, numbers.Real):
        return _finite(where, value)
    if isinstance(value, (list, tuple)):
        return [_value(where, v) for v in value]
    raise ValueError(f"{where}: expected a number, bool, string or list of numbers, got {type(value).__name__} {quote(repr(value))}")


def _json_object(what: str, value: Mapping[str, Any] | None) -> str | None:
    if value is None:
        return None
    if not isinstance(value, Mapping):
        raise ValueError(f"{what} must be a dict of name -> value, got {type(value).__name__}")
    plain = {}
    for k, v in value.items():
        k = check_name(what, k)
        plain[k] = _value(f"{what}[{quote(k)}]", v)
    return json.dumps(plain, allow_nan=False)


def json_object(what: str, value: Mapping[str, Any]) -> str:
    """A dict of name -> value (e.g. a curriculum's context) as JSON, each value checked."""
    if value is None:
        raise ValueError(f"{what} must be a dict of name -> value, got None")
    return _json_object(what, value)  # type: ignore[return-value]


def context_args(
    *,
    context: Mapping[str, Any] | None = None,
    instances: str | None = None,
    distribution: str | None = None,
    selection: str = "round_robin",
    instance: int | None = None,
    obs_context: list[str] | tuple[str, ...] | bool | None = None,
    context_noise: Mapping[str, NoiseStd] | None = None,
    context_noise_redraw: str = "episode",
    options: Mapping[str, Any] | None = None,
    allow_out_of_bounds: bool = False,
    schedules: Mapping[str, Mapping[str, Any]] | None = None,
    curriculum: bool = False,
) -> _core.ContextArgs:
    """The context source of `make`, `make_vec` and `wrap`, checked, as the native constructors
    take it."""
    if not isinstance(allow_out_of_bounds, bool):
        raise ValueError(f"allow_out_of_bounds must be True or False, got {quote(repr(allow_out_of_bounds))}")
    if obs_context is not None and not isinstance(obs_context, (bool, list, tuple)):
        raise ValueError(f"obs_context must be a list of feature names or True, got {quote(repr(obs_context))}")
    if isinstance(obs_context, (list, tuple)):
        obs_context = [check_name("obs_context", n) for n in obs_context]
    return _core.ContextArgs(
        context=_json_object("context", context),
        instances=None if instances is None else check_name("instances", instances),
        distribution=None if distribution is None else check_name("distribution", distribution),
        selection=check_name("selection", selection),
        instance=None if instance is None else check_int("instance", instance),
        obs_context=obs_context,
        context_noise=noise_triples(context_noise),
        context_noise_redraw=check_name("context_noise_redraw", context_noise_redraw),
        options=_json_object("options", options),
        allow_out_of_bounds=allow_out_of_bounds,
        schedules=_schedules_json(schedules),
        curriculum=curriculum,
    )


def _schedules_json(schedules: Mapping[str, Mapping[str, Any]] | None) -> str | None:
    """`schedules={feature: {"kind": ..., ...}}` as the native constructors take it (JSON)."""
    if schedules is None:
        return None
    if not isinstance(schedules, Mapping):
        raise ValueError(f"schedules must be a dict of feature -> schedule, got {type(schedules).__name__}")
    plain = {}
    for name, schedule in schedules.items():
        name = check_name("schedules", name)
        if not isinstance(schedule, Mapping):
            raise ValueError(
                f"schedules[{quote(name)}] must be a dict such as {{'kind': 'sine', 'amplitude': 2, 'period': 100}}, "
                f"got {quote(repr(schedule))}"
            )
        plain[name] = {check_name(f"schedules[{quote(name)}]", k): _value(f"schedules[{quote(name)}][{quote(k)}]", v) for k, v in schedule.items()}
    return json.dumps(plain, allow_nan=False)
