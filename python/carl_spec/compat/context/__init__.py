"""carl-bench's `carl.context` namespace (selectors), for `carl_spec.compat`."""
