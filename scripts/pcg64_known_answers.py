#!/usr/bin/env python3
"""Known-answer vectors for carl-spec's PCG64 (crates/carl-spec-core/src/sampling/pcg64.rs), produced by NumPy itself.

1. Raw states: set np.random.PCG64's state dict to a chosen (state, inc) and print random_raw().
2. Seeding: re-implement Pcg64::new(seed, stream) (SplitMix64 expansion + PCG srandom) here in
   pure Python, hand the resulting raw state to NumPy and print its outputs and random() doubles.

Usage: python3 scripts/pcg64_known_answers.py   (needs numpy; run it in a venv of its own)
"""
import numpy as np

M64 = (1 << 64) - 1
M128 = (1 << 128) - 1
MULT = 0x2360ED051FC65DA44385DF649FCCF645


def splitmix64(x):
    x = (x + 0x9E3779B97F4A7C15) & M64
    z = x
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & M64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & M64
    return x, z ^ (z >> 31)


def carl_spec_seed(seed, stream):
    """Raw (state, inc) of carl-spec's Pcg64::new(seed, stream)."""
    s, s0 = splitmix64(seed)
    s, s1 = splitmix64(s)
    t, t0 = splitmix64(stream)
    t, t1 = splitmix64(t)
    t, t2 = splitmix64(t)
    t, t3 = splitmix64(t)
    initstate = ((s0 << 64) | s1) ^ ((t2 << 64) | t3)
    initseq = (t0 << 64) | t1
    inc = ((initseq << 1) | 1) & M128
    state = 0
    state = (state * MULT + inc) & M128
    state = (state + initstate) & M128
    state = (state * MULT + inc) & M128
    return state, inc


def numpy_pcg64(state, inc):
    bg = np.random.PCG64()
    bg.state = {
        "bit_generator": "PCG64",
        "state": {"state": state, "inc": inc},
        "has_uint32": 0,
        "uinteger": 0,
    }
    return bg


RAW_CASES = [
    (0, 1),
    (0x0123456789ABCDEF_FEDCBA9876543210, 0xDEADBEEFCAFEBABE_0123456789ABCDEF | 1),
    (M128, M128),
]
SEED_CASES = [(0, 0), (42, 7), (2**64 - 1, 0xCBF29CE484222325)]

if __name__ == "__main__":
    print(f"# numpy {np.__version__}")
    for state, inc in RAW_CASES:
        bg = numpy_pcg64(state, inc)
        outs = bg.random_raw(6)
        print(f"raw state={state:#034x} inc={inc:#034x}")
        print("  random_raw:", ", ".join(f"{int(v):#018x}" for v in outs))
    for seed, stream in SEED_CASES:
        state, inc = carl_spec_seed(seed, stream)
        bg = numpy_pcg64(state, inc)
        outs = bg.random_raw(4)
        print(f"new(seed={seed}, stream={stream:#x}) -> state={state:#034x} inc={inc:#034x}")
        print("  random_raw:", ", ".join(f"{int(v):#018x}" for v in outs))
        gen = np.random.Generator(numpy_pcg64(state, inc))
        doubles = gen.random(3)
        print("  random() bits:", ", ".join(f"{float(d).hex()} ({np.float64(d).view(np.uint64):#018x})" for d in doubles))
