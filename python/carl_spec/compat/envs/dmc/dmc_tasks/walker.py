"""carl-bench's `carl.envs.dmc.dmc_tasks.walker`: pending (issue 27; see `carl_spec.compat._pending`)."""

from ...._pending import pending_function

get_model_and_assets = pending_function("get_model_and_assets", "dmc_walker", 27, __name__)
stand_context = pending_function("stand_context", "dmc_walker", 27, __name__)
walk_context = pending_function("walk_context", "dmc_walker", 27, __name__)
run_context = pending_function("run_context", "dmc_walker", 27, __name__)

__all__ = ["get_model_and_assets", "stand_context", "walk_context", "run_context"]
