"""carl-bench's `carl.envs.dmc.dmc_tasks.finger`: pending (issue 27; see `carl_spec.compat._pending`)."""

from ...._pending import pending_function

check_constraints = pending_function("check_constraints", "dmc_finger", 27, __name__)
get_finger_xml_string = pending_function("get_finger_xml_string", "dmc_finger", 27, __name__)
get_model_and_assets = pending_function("get_model_and_assets", "dmc_finger", 27, __name__)
spin_context = pending_function("spin_context", "dmc_finger", 27, __name__)
turn_easy_context = pending_function("turn_easy_context", "dmc_finger", 27, __name__)
turn_hard_context = pending_function("turn_hard_context", "dmc_finger", 27, __name__)

__all__ = ["check_constraints", "get_finger_xml_string", "get_model_and_assets", "spin_context", "turn_easy_context", "turn_hard_context"]
