"""carl-bench 1.1.1's own tests (vendored, see PROVENANCE.md); a package so its conftest and modules do not clash with python/tests' own."""
