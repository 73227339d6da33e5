"""carl-bench's `carl.envs.rna.carl_rna`."""

from .._classes import CARLRnaDesignEnv

__all__ = ["CARLRnaDesignEnv"]
