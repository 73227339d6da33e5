"""carl-bench's `carl.envs.rna`."""

from .carl_rna import CARLRnaDesignEnv

__all__ = ["CARLRnaDesignEnv"]
