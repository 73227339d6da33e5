"""carl-bench's `carl.envs.dmc.dmc_tasks`: each domain's XML (dm_control's, shipped with carl-spec),
carl-bench's XML editing (`utils.adapt_context`) and its task functions, which return dm_control
environments and so need dm_control (`pip install dm_control==1.0.50 'mujoco<4'`)."""
