"""carl-bench's `carl.envs.dmc.loader`: pending (issue 27; see `carl_spec.compat._pending`)."""

from ..._pending import pending_function

load_dmc_env = pending_function("load_dmc_env", "dm_control family", 27, __name__)

__all__ = ["load_dmc_env"]
