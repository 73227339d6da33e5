"""carl-bench's `carl.envs.dmc.dmc_tasks.pointmass`: pending (issue 27; see `carl_spec.compat._pending`)."""

from ...._pending import pending_function

check_constraints = pending_function("check_constraints", "dmc_point_mass", 27, __name__)
make_model = pending_function("make_model", "dmc_point_mass", 27, __name__)
easy_pointmass = pending_function("easy_pointmass", "dmc_point_mass", 27, __name__)
hard_pointmass = pending_function("hard_pointmass", "dmc_point_mass", 27, __name__)

__all__ = ["check_constraints", "make_model", "easy_pointmass", "hard_pointmass"]
