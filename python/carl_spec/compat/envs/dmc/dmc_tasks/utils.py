"""carl-bench's `carl.envs.dmc.dmc_tasks.utils`: pending (issue 27; see `carl_spec.compat._pending`)."""

from ...._pending import pending_function

adapt_context = pending_function("adapt_context", "dm_control family", 27, __name__)

__all__ = ["adapt_context"]
