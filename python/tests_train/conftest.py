"""The training tier (torch, Stable-Baselines3, RLlib): its own venv, see scripts/test-all.

Small MLPs train fastest on one intra-op thread (2-core CI machine); Ray runs on loopback only.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import Any

import pytest

# Before Ray is imported anywhere: every Ray socket on 127.0.0.1, no usage report over the network.
os.environ["RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"] = "0"
os.environ["RAY_USAGE_STATS_ENABLED"] = "0"
os.environ.pop("RAY_ADDRESS", None)

import torch  # noqa: E402

torch.set_num_threads(1)

LOOPBACK = "127.0.0.1"


def node_addresses(ray: Any) -> list[str]:
    """Every address the local Ray cluster reports: each node's manager address, the GCS host
    and the driver's node IP."""
    out = [node["NodeManagerAddress"] for node in ray.nodes()]
    ctx = ray.get_runtime_context()
    out.append(ctx.gcs_address.rsplit(":", 1)[0])
    out.append(ray.util.get_node_ip_address())
    return out


@pytest.fixture(scope="session")
def loopback_ray() -> Iterator[Any]:
    """A local Ray bound to 127.0.0.1 (asserted), shut down after the session."""
    import ray

    ray.init(
        address="local",
        _node_ip_address=LOOPBACK,
        include_dashboard=False,
        num_cpus=2,
        log_to_driver=False,
        configure_logging=False,
    )
    try:
        addrs = node_addresses(ray)
        assert addrs and all(a == LOOPBACK for a in addrs), f"Ray is not on loopback only: {addrs}"
        yield ray
    finally:
        ray.shutdown()


@pytest.fixture(autouse=True)
def sb3_logs_in_tmp_path(tmp_path: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    """SB3 makes `$TMPDIR/SB3-<date>` for every model it trains unless SB3_LOGDIR names a folder:
    each test's logs go to its own tmp_path (pytest cleans those), nothing to the system temp."""
    monkeypatch.setenv("SB3_LOGDIR", str(tmp_path / "sb3-logs"))
