"""carl-bench's `carl.envs.dmc.dmc_tasks`: pending (issue 27)."""
