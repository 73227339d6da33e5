#!/usr/bin/env python3
"""MFE fold time of carl-rna beside ViennaRNA's RNA.fold, measured in the same run on the same
sequences (uniform random ACGU, fixed seed), single thread.

    pip install viennarna==2.8.0
    cargo build --release -p carl-rna --example fold
    python3 scripts/rna_bench.py [--lengths 100,200,500,800] [--per-length 5] [--reps 3]

carl-rna's time is measured inside the process around `carl_rna::fold` (no process start-up);
ViennaRNA's is `RNA.fold(seq)` (fold-compound creation included, as in gen_fixtures.py bench).
The two calls alternate, so background load hits both alike. Every structure is also compared.
"""
import argparse
import os
import random
import statistics
import subprocess
import sys
import time

import RNA

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "target", "release", "examples", "fold")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lengths", default="100,200,500,800")
    ap.add_argument("--per-length", type=int, default=5)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    if not os.path.exists(BIN):
        sys.exit(f"{BIN} missing: cargo build --release -p carl-rna --example fold")
    rng = random.Random(args.seed)
    print(f"ViennaRNA {RNA.__version__}; {args.per_length} sequences x {args.reps} reps per length; medians in ms")
    print(f"{'length':>6} {'carl-rna':>10} {'ViennaRNA':>10} {'speed-up':>9}")
    for length in [int(x) for x in args.lengths.split(",")]:
        seqs = ["".join(rng.choice("ACGU") for _ in range(length)) for _ in range(args.per_length)]
        ours, theirs = [], []
        for _ in range(args.reps):
            for s in seqs:
                out = subprocess.run([BIN, s], capture_output=True, text=True, check=True).stdout.split()
                ours.append(float(out[2]))
                t = time.perf_counter()
                structure, _ = RNA.fold(s)
                theirs.append(time.perf_counter() - t)
                if structure != out[0]:
                    sys.exit(f"structure differs for {s}")
        a, b = statistics.median(ours) * 1000, statistics.median(theirs) * 1000
        print(f"{length:>6} {a:>10.1f} {b:>10.1f} {b / a:>8.2f}x", flush=True)


if __name__ == "__main__":
    main()
