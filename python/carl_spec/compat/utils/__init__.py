"""carl-bench's `carl.utils` (its type aliases), for `carl_spec.compat`."""
