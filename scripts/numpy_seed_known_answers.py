#!/usr/bin/env python3
"""Known answers for crates/carl-env/src/rng.rs from NumPy itself: SeedSequence words, PCG64(seed) raw
outputs and Generator.uniform(-0.05, 0.05, size=4) (Gymnasium CartPole's reset) per seed.

Usage: python3 scripts/numpy_seed_known_answers.py   (needs numpy)
"""
import numpy as np

for s in [0, 1, 42, 2**32 + 7, 2**64 - 1]:
    print(s, "words", [hex(x) for x in np.random.SeedSequence(s).generate_state(8, np.uint32)])
    print(s, "raw", [hex(x) for x in np.random.PCG64(s).random_raw(2)])
    print(s, "uniform", [float(x) for x in np.random.default_rng(s).uniform(-0.05, 0.05, size=4)])
