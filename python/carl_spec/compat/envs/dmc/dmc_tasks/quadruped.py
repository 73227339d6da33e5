"""carl-bench's `carl.envs.dmc.dmc_tasks.quadruped`: pending (issue 27; see `carl_spec.compat._pending`)."""

from ...._pending import pending_function

make_model = pending_function("make_model", "dmc_quadruped", 27, __name__)
walk_context = pending_function("walk_context", "dmc_quadruped", 27, __name__)
run_context = pending_function("run_context", "dmc_quadruped", 27, __name__)
escape_context = pending_function("escape_context", "dmc_quadruped", 27, __name__)
fetch_context = pending_function("fetch_context", "dmc_quadruped", 27, __name__)

__all__ = ["make_model", "walk_context", "run_context", "escape_context", "fetch_context"]
