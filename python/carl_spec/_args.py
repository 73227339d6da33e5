"""The keyword arguments `make` and `make_vec` share: checked once here, passed to the native
module in its own form (JSON for contexts and options, `(name, kind, std)` triples for noise)."""

from __future__ import annotations

import json
import os
from typing import Any, Mapping, Union

#: A noise standard deviation: a number (the feature's unit) or a percentage string of the
#: feature's |default| ("10%").
NoiseStd = Union[float, str]


def noise_triples(noise: Mapping[str, NoiseStd] | None) -> list[tuple[str, str, float]] | None:
    if noise is None:
        return None
    if not isinstance(noise, Mapping):
        raise ValueError(
            f"context_noise must map feature names to a std (a number, or a percentage such as '10%'), got {noise!r}"
        )
    out = []
    for name, std in noise.items():
        if isinstance(std, bool):
            raise ValueError(f"context_noise[{name!r}]: a std is a number or a percentage string, got {std!r}")
        if isinstance(std, str):
            text = std.strip()
            try:
                if not text.endswith("%"):
                    raise ValueError
                out.append((str(name), "relative", float(text[:-1]) / 100.0))
            except ValueError:
                raise ValueError(
                    f"context_noise[{name!r}]: {std!r} is neither a number nor a percentage such as '10%'"
                ) from None
        elif isinstance(std, (int, float)):
            out.append((str(name), "absolute", float(std)))
        else:
            raise ValueError(f"context_noise[{name!r}]: a std is a number or a percentage string, got {std!r}")
    return out


def _json_object(what: str, value: Mapping[str, Any] | None) -> str | None:
    if value is None:
        return None
    if not isinstance(value, Mapping):
        raise ValueError(f"{what} must be a dict of name -> value, got {type(value).__name__}")
    try:
        return json.dumps(dict(value), default=_plain)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{what}: {e}") from None


def _plain(x: Any) -> Any:
    """NumPy scalars and arrays as JSON numbers and lists."""
    if hasattr(x, "tolist"):
        return x.tolist()
    raise TypeError(f"{x!r} is not a number, bool, string or list of numbers")


def core_kwargs(
    *,
    context: Mapping[str, Any] | None,
    instances: str | None,
    distribution: str | None,
    selection: str,
    instance: int | None,
    obs_context: list[str] | tuple[str, ...] | bool | None,
    context_noise: Mapping[str, NoiseStd] | None,
    context_noise_redraw: str,
    options: Mapping[str, Any] | None,
    allow_out_of_bounds: bool,
    specs_dir: str | os.PathLike[str] | None,
) -> dict[str, Any]:
    """The native constructors' keyword arguments (both `_core.Env` and `_core.VecEnv`)."""
    if not isinstance(allow_out_of_bounds, bool):
        raise ValueError(f"allow_out_of_bounds must be True or False, got {allow_out_of_bounds!r}")
    if obs_context is not None and not isinstance(obs_context, (bool, list, tuple)):
        raise ValueError(f"obs_context must be a list of feature names or True, got {obs_context!r}")
    return {
        "context_json": _json_object("context", context),
        "instances": instances,
        "distribution": distribution,
        "selection": selection,
        "instance": instance,
        "obs_context": list(obs_context) if isinstance(obs_context, (list, tuple)) else obs_context,
        "options_json": _json_object("options", options),
        "noise": noise_triples(context_noise),
        "noise_redraw": context_noise_redraw,
        "allow_out_of_bounds": allow_out_of_bounds,
        "specs_dir": None if specs_dir is None else os.fspath(specs_dir),
    }
