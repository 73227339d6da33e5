"""carl-bench's `carl.context.search_space_encoding`: hydra / JSON search spaces as ConfigSpace
`ConfigurationSpace`s (the route CARL experiment code takes with hydra).

ConfigSpace and omegaconf are optional (`pip install "carl-spec[compat]"`); importing this
module works without them, calling `search_space_to_config_space` then says what to install.
"""

from __future__ import annotations

import io
import json
from typing import Any

_INSTALL = 'search spaces need ConfigSpace and omegaconf: pip install "carl-spec[compat]" (or ConfigSpace omegaconf)'


def _deps() -> tuple[Any, Any, Any]:
    try:
        from ConfigSpace import ConfigurationSpace  # type: ignore[import-not-found, import-untyped, unused-ignore]
        from omegaconf import DictConfig, ListConfig  # type: ignore[import-not-found, import-untyped, unused-ignore]
    except ImportError as e:
        raise ImportError(f"{_INSTALL} ({e})") from e
    return ConfigurationSpace, DictConfig, ListConfig


def _read(text: str) -> Any:
    """A ConfigurationSpace from ConfigSpace's JSON format (its current reader, which also reads
    the older format versions carl-bench's examples use)."""
    ConfigurationSpace, _, _ = _deps()
    data = json.loads(text)
    for hp in data.get("hyperparameters", []):
        # ConfigSpace < 1.0's field names (carl-bench's documented format), as ConfigSpace reads them
        # today, without its warning
        if "default" in hp and "default_value" not in hp:
            hp["default_value"] = hp.pop("default")
        for field in ("q", "default_value"):
            if field in hp and hp[field] is None:
                del hp[field]
    return ConfigurationSpace.from_json(io.StringIO(json.dumps(data)))


class JSONCfgEncoder(json.JSONEncoder):
    """JSON encoder turning omegaconf's DictConfig / ListConfig into dicts and lists."""

    def default(self, obj: Any) -> Any:
        _, DictConfig, ListConfig = _deps()
        if isinstance(obj, DictConfig):
            return dict(obj)
        if isinstance(obj, ListConfig):
            return [dict(o) if isinstance(o, DictConfig) else list(o) if isinstance(o, ListConfig) else o for o in obj]
        return json.JSONEncoder.default(self, obj)


def search_space_to_config_space(search_space: Any, seed: int | None = None) -> Any:
    """A ConfigSpace `ConfigurationSpace` from `search_space`: a path to a ConfigSpace JSON file,
    a hydra `DictConfig` (`hyperparameters: {name: {type, lower, upper, ...}}`), a dict in
    ConfigSpace's JSON format, or a `ConfigurationSpace` (returned as is); seeded with `seed` if
    given. carl-bench's semantics, except that a DictConfig is read, not rewritten in place."""
    ConfigurationSpace, DictConfig, _ = _deps()
    if isinstance(search_space, str):
        with open(search_space, encoding="utf-8") as f:
            cs = _read(f.read())
    elif isinstance(search_space, DictConfig):
        hyperparameters = []
        for name, cfg in search_space.hyperparameters.items():
            hp = dict(cfg)
            hp["name"] = name
            if str(hp.get("type", "")).startswith(("uniform", "normal", "beta")):
                hp.setdefault("log", False)  # carl-bench adds it to every type, which fails categoricals
            hyperparameters.append(hp)
        encoded = {
            **{k: v for k, v in search_space.items() if k != "hyperparameters"},
            "hyperparameters": hyperparameters,
        }
        encoded.setdefault("conditions", [])
        encoded.setdefault("forbiddens", [])
        cs = _read(json.dumps(encoded, cls=JSONCfgEncoder))
    elif isinstance(search_space, ConfigurationSpace):
        cs = search_space
    elif isinstance(search_space, dict):
        cs = _read(json.dumps(search_space))
    else:
        raise ValueError(
            f"search_space must be a path, a DictConfig, a dict or a ConfigurationSpace. Got {type(search_space)}."
        )
    if seed is not None:
        cs.seed(seed)
    return cs


__all__ = ["JSONCfgEncoder", "search_space_to_config_space"]
