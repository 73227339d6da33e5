"""carl-bench's `carl.envs.dmc.dmc_tasks.fish`: pending (issue 27; see `carl_spec.compat._pending`)."""

from ...._pending import pending_function

get_model_and_assets = pending_function("get_model_and_assets", "dmc_fish", 27, __name__)
upright_context = pending_function("upright_context", "dmc_fish", 27, __name__)
swim_context = pending_function("swim_context", "dmc_fish", 27, __name__)

__all__ = ["get_model_and_assets", "upright_context", "swim_context"]
