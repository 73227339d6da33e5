#!/usr/bin/env python3
"""ViennaRNA oracle fixtures for the Rust RNA-design / MFE-folding port.

Only dependency:  pip install viennarna==2.8.0   (Python >= 3.8, standard library otherwise)

ViennaRNA is used strictly as a black-box oracle: every number in the fixture
files is what the installed wheel returns for the default model (37 C,
Turner 2004, dangles=2, lonely pairs allowed, special hairpins on, no
G-quadruplexes, linear molecule).

Subcommands (run from anywhere; inputs/outputs default to this script's folder):

  all      regenerate vienna_fold_fixtures.jsonl, vienna_eval_fixtures.jsonl and
           vienna_interior_tables.tsv (default seed; reads eterna100_puzzles.tsv
           and rfam_taneda/*.rna from this folder)
  fold     only random (+ optional random adversarial) MFE fixtures, with your
           own seed / length mix / GC range, e.g. for a private hold-out set
  verify   recompute every record of the given fixture files with the installed
           ViennaRNA and report mismatches (cross-version check, CI oracle job)
  bench    median wall time of RNA.fold() at 100/200/500 nt on this machine

Energies are integers in dcal/mol (ViennaRNA's internal unit; 1 kcal/mol = 100).
mfe_dcal = round(mfe_kcal * 100) where mfe_kcal is the float that
fold_compound.mfe() / RNA.fold() returns; the script asserts that it equals the
integer returned by fold_compound.eval_structure_pt() for the same structure.
"""

import argparse
import csv
import glob
import itertools
import json
import math
import os
import platform
import random
import statistics
import sys
import time

import RNA

# carl-spec copy (scripts/rna_gen_fixtures.py, otherwise unchanged from ../shared/data/rna/gen_fixtures.py):
# inputs (eterna100_puzzles.tsv, rfam_taneda/) and default outputs live in the data folder
# ../shared/data/rna beside the repository, or wherever $CARL_RNA_DATA points.
HERE = os.environ.get("CARL_RNA_DATA") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data", "rna")
VERSION = RNA.__version__
DEFAULT_SEED = 20261124
DEFAULT_LENGTHS = "8-19:0.06,20-200:0.70,201-350:0.14,351-500:0.10"
CANONICAL = ("AU", "UA", "GC", "CG", "GU", "UG")
WC = ("AU", "UA", "GC", "CG")
LEARNA_PAIRS = ("GC", "CG", "AU", "UA")  # LEARNA paired-site actions 0..3
TIE_LIST_MAX = 10  # store all co-optimal structures when there are at most this many


# --------------------------------------------------------------------------- model

def default_md():
    md = RNA.md()
    # Guard against a non-default global state: these are ViennaRNA's library defaults.
    assert md.temperature == 37.0 and md.dangles == 2 and md.noLP == 0 and md.noGU == 0
    assert md.noGUclosure == 0 and md.special_hp == 1 and md.gquad == 0 and md.circ == 0
    assert md.max_bp_span == -1 and md.energy_set == 0
    return md


def model_dict():
    md = default_md()
    return {
        "temperature": md.temperature,
        "dangles": md.dangles,
        "noLP": md.noLP,
        "noGU": md.noGU,
        "noGUclosure": md.noGUclosure,
        "special_hp": md.special_hp,
        "gquad": md.gquad,
        "circ": md.circ,
        "max_bp_span": md.max_bp_span,
        "min_loop_size": getattr(md, "min_loop_size", 3),
        "maxloop": getattr(RNA, "MAXLOOP", 30),
        "salt": getattr(md, "salt", 1.021),
        "energy_set": md.energy_set,
        "params": "turner2004 (ViennaRNA compiled-in default)",
    }


MODEL = None  # filled in main()


def eval_fc(seq):
    return RNA.fold_compound(seq, default_md(), RNA.OPTION_EVAL_ONLY)


def pairs_of(pt):
    return [(i, pt[i]) for i in range(1, pt[0] + 1) if pt[i] > i]


def eval_record(seq, db):
    """(total_dcal, loops) with loops = [[0,0,exterior], [i,j,e], ...] (1-based closing pairs)."""
    fc = eval_fc(seq)
    pt = RNA.ptable(db)
    total = fc.eval_structure_pt(pt)
    loops = [[0, 0, fc.eval_loop_pt(0, pt)]]
    for i, j in pairs_of(pt):
        loops.append([i, j, fc.eval_loop_pt(i, pt)])
    s = sum(x[2] for x in loops)
    assert s == total, (seq, db, total, s)
    fl = fc.eval_structure(db)
    assert round(fl * 100) == total, (seq, db, fl, total)
    return total, loops


def fold_record(seq):
    """MFE structure, integer energy and number of co-optimal structures."""
    md = default_md()
    fc = RNA.fold_compound(seq, md)
    st, e = fc.mfe()
    dcal = int(round(e * 100))
    st2, e2 = RNA.fold(seq)  # the call LEARNA makes
    assert st2 == st and int(round(e2 * 100)) == dcal, (seq, st, st2, e, e2)
    ev = eval_fc(seq).eval_structure_pt(RNA.ptable(st))
    assert ev == dcal, (seq, st, ev, dcal)
    md2 = default_md()
    md2.uniq_ML = 1  # required by subopt
    fc2 = RNA.fold_compound(seq, md2)
    tied = []

    def cb(s, en, data):
        if s is not None:
            assert int(round(en * 100)) == dcal
            tied.append(s)

    fc2.subopt_cb(0, cb, None)
    assert st in tied, (seq, st, tied[:5])
    assert len(set(tied)) == len(tied)
    fce = eval_fc(seq)
    for t in tied[:1000]:  # co-optimal structures really are at the MFE
        assert fce.eval_structure_pt(RNA.ptable(t)) == dcal, (seq, t)
    return st, dcal, tied


# --------------------------------------------------------------------------- sequences

def parse_lengths(spec):
    out = []
    for part in spec.split(","):
        rng_part, w = part.split(":")
        lo, hi = (int(x) for x in rng_part.split("-"))
        out.append((lo, hi, float(w)))
    return out


def pick_length(rng, buckets):
    r = rng.random() * sum(b[2] for b in buckets)
    for lo, hi, w in buckets:
        if r < w:
            return rng.randint(lo, hi)
        r -= w
    lo, hi, _ = buckets[-1]
    return rng.randint(lo, hi)


def rand_seq(rng, n, gc, lo=0.0, hi=1.0):
    """Exact composition: round(gc*n) bases from {G,C} (clamped so that the realised GC
    fraction stays inside [lo, hi]), the rest from {A,U}, shuffled."""
    k = min(max(int(round(gc * n)), math.ceil(lo * n - 1e-9)), math.floor(hi * n + 1e-9))
    b = [rng.choice("GC") for _ in range(k)] + [rng.choice("AU") for _ in range(n - k)]
    rng.shuffle(b)
    return "".join(b)


def rand_bases(rng, n, alphabet="ACGU"):
    return "".join(rng.choice(alphabet) for _ in range(n))


def adversarial_fixed():
    """Deterministic adversarial sequences (shared fixture only)."""
    out = []
    for b in "ACGU":
        for n in (5, 10, 30, 100, 300):
            out.append(("homopolymer", b * n))
    for b in "ACGU":
        out.append(("len<5", b))
    for a, b in itertools.product("ACGU", repeat=2):
        out.append(("len<5", a + b))
    for s in ("GAC", "GCC", "AAA", "GGC", "CUG", "UGA", "GCGU", "GGCC", "GCGC", "CCGG", "AUAU",
              "GGGG", "GUGU", "CAUG", "UGCA", "GAAC"):
        out.append(("len<5", s))
    for s in ("GAAAC", "CAAAG", "GUUAC", "CAACG", "GGAAACC", "GCAAAGC", "GGGAAACCC", "CGAAAGG",
              "GGGGAAAACCCC", "GGGCUUCGGCCC"):
        out.append(("tiny_hairpin", s))
    for unit in ("GC", "CG", "GGC", "GCC", "GGCC", "GGGCCC", "GCGCAA", "GGGGCCCC", "CCCGGG", "GGCGCC"):
        for n in (24, 101, 250):
            out.append(("gc_repeat", (unit * (n // len(unit) + 1))[:n]))
    for unit in ("AU", "UA", "AAUU", "AAAUUU"):
        for n in (20, 150):
            out.append(("au_repeat", (unit * (n // len(unit) + 1))[:n]))
    for unit in ("GU", "UG", "GGUU", "GGGUUU", "GUGUU"):
        for n in (30, 120):
            out.append(("gu_repeat", (unit * (n // len(unit) + 1))[:n]))
    for unit, k in (("GGGAAACCC", 4), ("GGGAAACCC", 12), ("GCGAAAGC", 6), ("GGACUUCGGUCC", 5),
                    ("CCCAAAGGG", 8), ("GGGGAAAACCCC", 10), ("ACGUACGU", 6), ("GCAUGC", 20),
                    ("GGGAAAUCC", 7), ("AGGGAAACCCU", 9)):
        out.append(("tandem_hairpins", unit * k))
    # long hairpin loops around the 30-nt table limit (lxc extrapolation)
    for k in (28, 29, 30, 31, 32, 35, 40, 45):
        out.append(("long_hairpin", "GGGGG" + "A" * k + "CCCCC"))
    # interior loops around MAXLOOP = 30 (the MFE may not use interior loops > 30)
    for a, b in ((14, 14), (15, 15), (15, 16), (16, 16), (1, 29), (1, 30), (0, 30), (0, 31), (29, 2), (2, 29),
                 (12, 19), (10, 20), (20, 10), (31, 0)):
        out.append(("interior_maxloop", "GGGGGG" + "A" * a + "GGGGG" + "AAAA" + "CCCCC" + "A" * b + "CCCCCC"))
    # special hairpins with strong stems
    P = RNA.param(default_md())
    specials = P.Tetraloops.split() + P.Triloops.split() + P.Hexaloops.split()
    for sp in specials:
        out.append(("special_hairpin", "GGAC" + sp + "GUCC"))
    for s in ("GGGGGCCCCC", "GGGGGGCCCCCC", "CCCCCGGGGG", "GGGGAAAAAAAAAAAAAAAACCCC", "AAAAAAAAAAAAAAGAAAAAC"):
        out.append(("misc", s))
    return out


def adversarial_random(rng, count, maxlen):
    """Randomised adversarial sequences (used for both the shared set and hold-outs)."""
    out = []
    kinds = ["gu_only", "repeat_unit", "au_rich", "purine_pyrimidine_blocks", "palindrome", "low_gc"]
    for t in range(count):
        kind = kinds[t % len(kinds)]
        n = rng.randint(10, maxlen)
        if kind == "gu_only":
            s = rand_bases(rng, n, "GU")
        elif kind == "repeat_unit":
            u = rand_bases(rng, rng.randint(2, 12))
            s = (u * (n // len(u) + 1))[:n]
        elif kind == "au_rich":
            s = "".join(rng.choice("AAAAAAAAUUUUUUUUGC") for _ in range(n))
        elif kind == "purine_pyrimidine_blocks":
            b = rng.randint(3, 12)
            s = "".join(rand_bases(rng, b, "AG" if (k % 2 == 0) else "CU") for k in range(n // b + 1))[:n]
        elif kind == "palindrome":
            h = rand_bases(rng, n // 2)
            comp = {"A": "U", "U": "A", "G": "C", "C": "G"}
            s = h + rand_bases(rng, rng.randint(0, 6)) + "".join(comp[c] for c in reversed(h))
        else:  # low_gc
            s = rand_seq(rng, n, rng.uniform(0.05, 0.2))
        out.append((kind, s))
    return out


# --------------------------------------------------------------------------- upstream targets

def load_eterna(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f, delimiter="\t"))
    hdr, rows = rows[0], rows[1:]
    col = {h: i for i, h in enumerate(hdr)}
    return hdr, col, rows


def load_taneda(folder):
    files = sorted(glob.glob(os.path.join(folder, "*.rna")), key=lambda p: int(os.path.basename(p)[:-4]))
    return [(int(os.path.basename(p)[:-4]), open(p).read().rstrip()) for p in files]


def pair_table0(db):
    st, pt = [], [-1] * len(db)
    for i, c in enumerate(db):
        if c == "(":
            st.append(i)
        elif c == ")":
            j = st.pop()
            pt[i], pt[j] = j, i
    assert not st
    return pt


def learna_design(rng, target):
    pt = pair_table0(target)
    s = [None] * len(target)
    for i, c in enumerate(target):
        if s[i] is not None:
            continue
        if pt[i] > i:
            p = rng.choice(LEARNA_PAIRS)
            s[i], s[pt[i]] = p[0], p[1]
        else:
            s[i] = rng.choice("GAUC")
    return "".join(s)


def hamming(a, b):
    assert len(a) == len(b)
    return sum(x != y for x, y in zip(a, b))


# --------------------------------------------------------------------------- fold fixtures

def fold_line(rid, kind, seq, extra=None):
    st, dcal, tied = fold_record(seq)
    rec = {"id": rid, "kind": kind, "seq": seq, "structure": st, "mfe_dcal": dcal, "ties": len(tied)}
    if len(tied) > 1 and len(tied) <= TIE_LIST_MAX:
        rec["tied_structures"] = sorted(tied)
    if extra:
        rec.update(extra)
    rec["vienna_version"] = VERSION
    rec["model"] = MODEL
    return rec


def gen_random_fold(rng, n, buckets, gc_lo, gc_hi, prefix):
    recs = []
    for k in range(n):
        L = pick_length(rng, buckets)
        gc = rng.uniform(gc_lo, gc_hi)
        seq = rand_seq(rng, L, gc, gc_lo, gc_hi)
        recs.append(fold_line("%s-%05d" % (prefix, k), "random", seq, {"gc": round((seq.count("G") + seq.count("C")) / L, 4)}))
    return recs


def gen_shared_fold(rng, n_random):
    recs = gen_random_fold(rng, n_random, parse_lengths(DEFAULT_LENGTHS), 0.3, 0.7, "rand")
    for k, (kind, s) in enumerate(adversarial_fixed()):
        recs.append(fold_line("adv-%04d" % k, "adversarial:" + kind, s))
    for k, (kind, s) in enumerate(adversarial_random(rng, 30, 300)):
        recs.append(fold_line("advr-%04d" % k, "adversarial:" + kind, s))
    # LEARNA-style designs (paired sites from GC/CG/AU/UA) for every Eterna100 V1 and Rfam-Taneda target
    hdr, col, rows = load_eterna(os.path.join(HERE, "eterna100_puzzles.tsv"))
    for r in rows:
        pid, tgt = int(r[col["Puzzle #"]]), r[col["Secondary Structure V1"]]
        seq = learna_design(rng, tgt)
        rec = fold_line("design-eterna-v1-%03d" % pid, "learna_design", seq, {"target": tgt, "target_source": "eterna100 V1 #%d" % pid})
        rec_h = hamming(rec["structure"], tgt)
        rec = insert_after(rec, "target_source", "hamming", rec_h)
        recs.append(rec)
    for tid, tgt in load_taneda(os.path.join(HERE, "rfam_taneda")):
        seq = learna_design(rng, tgt)
        rec = fold_line("design-taneda-%02d" % tid, "learna_design", seq, {"target": tgt, "target_source": "rfam_taneda %d.rna" % tid})
        recs.append(insert_after(rec, "target_source", "hamming", hamming(rec["structure"], tgt)))
    # Eterna100 sample solutions designed for ViennaRNA 2 (should fold exactly into their targets)
    for ver, scol in (("V1", "Sample Solution (V1/Vienna2)"), ("V2", "Sample Solution (V2/Vienna2)")):
        for r in rows:
            sol = r[col[scol]]
            if not sol or set(sol) - set("ACGU"):
                continue  # "(unsolved)" / "(undisclosed)"
            pid, tgt = int(r[col["Puzzle #"]]), r[col["Secondary Structure " + ver]]
            rec = fold_line("sol-%s-%03d" % (ver.lower(), pid), "eterna100_solution", sol,
                            {"target": tgt, "target_source": "eterna100 %s/Vienna2 #%d" % (ver, pid)})
            recs.append(insert_after(rec, "target_source", "hamming", hamming(rec["structure"], tgt)))
    return recs


def insert_after(rec, key, newkey, val):
    out = {}
    for k, v in rec.items():
        out[k] = v
        if k == key:
            out[newkey] = val
    return out


# --------------------------------------------------------------------------- eval fixtures

def unp(s):
    return (s, "." * len(s))


def cat(*parts):
    return ("".join(p[0] for p in parts), "".join(p[1] for p in parts))


def wrap(pairs, inner):
    """pairs: outermost first, each a 2-char string like 'GC'."""
    s, d = inner
    for p in reversed(pairs):
        s, d = p[0] + s + p[1], "(" + d + ")"
    return (s, d)


def rpairs(rng, k, alphabet=CANONICAL):
    return [rng.choice(alphabet) for _ in range(k)]


def branch(rng, min_bp=1, max_bp=4, hp_min=3, hp_max=8):
    """A helix closed by a hairpin, random canonical pairs (GU included)."""
    return wrap(rpairs(rng, rng.randint(min_bp, max_bp)), unp(rand_bases(rng, rng.randint(hp_min, hp_max))))


def gap(rng, p0=0.3, hi=5):
    return unp("" if rng.random() < p0 else rand_bases(rng, rng.randint(1, hi)))


def compatible(pt, i, j):
    for k in range(i + 1, j):
        if pt[k] != -1 and (pt[k] < i or pt[k] > j):
            return False
    return True


def random_pt(rng, n, attempts, max_helix, seq=None):
    ok = (lambda a, b: True) if seq is None else (lambda a, b: seq[a] + seq[b] in CANONICAL)
    pt = [-1] * n
    for _ in range(attempts):
        i, j = rng.randrange(n), rng.randrange(n)
        if i > j:
            i, j = j, i
        if j - i - 1 < 3 or pt[i] != -1 or pt[j] != -1 or not ok(i, j) or not compatible(pt, i, j):
            continue
        pt[i], pt[j] = j, i
        a, b = i, j
        for _ in range(rng.randint(1, max_helix) - 1):
            a2, b2 = a + 1, b - 1
            if b2 - a2 - 1 < 3 or pt[a2] != -1 or pt[b2] != -1 or not ok(a2, b2):
                break
            pt[a2], pt[b2] = b2, a2
            a, b = a2, b2
    return pt


def pt_to_db(pt):
    return "".join("." if p == -1 else ("(" if p > i else ")") for i, p in enumerate(pt))


def eval_line(rid, kind, seq, db, info=None):
    total, loops = eval_record(seq, db)
    rec = {"id": rid, "kind": kind, "seq": seq, "structure": db, "energy_dcal": total, "loops": loops}
    if info:
        rec["info"] = info
    rec["vienna_version"] = VERSION
    rec["model"] = MODEL
    return rec


def gen_eval(rng, fold_recs):
    recs = []
    add = lambda kind, sd, info=None: recs.append(eval_line("%s-%04d" % (kind, sum(1 for r in recs if r["kind"] == kind)), kind, sd[0], sd[1], info))
    comp = dict(zip(CANONICAL, CANONICAL))

    # 1. random valid pairings, structure first, then a compatible sequence (GU allowed)
    for _ in range(200):
        n = rng.randint(10, 300)
        pt = random_pt(rng, n, rng.randint(n // 8 + 1, 2 * n), rng.randint(1, 10))
        s = [None] * n
        for i in range(n):
            if pt[i] > i:
                p = rng.choice(("GC", "CG", "GC", "CG", "AU", "UA", "AU", "UA", "GU", "UG"))
                s[i], s[pt[i]] = p[0], p[1]
            elif pt[i] == -1:
                s[i] = rng.choice("ACGU")
        add("random_structure", ("".join(s), pt_to_db(pt)))
    # 2. random sequence, then a random compatible structure on it
    for _ in range(200):
        n = rng.randint(10, 300)
        seq = rand_seq(rng, n, rng.uniform(0.3, 0.7))
        pt = random_pt(rng, n, rng.randint(n // 8 + 1, 3 * n), rng.randint(1, 10), seq)
        add("random_pairing", (seq, pt_to_db(pt)))
    # 3. MFE structures from the fold fixtures (eval must equal mfe_dcal)
    cand = [r for r in fold_recs if r["kind"] == "random"]
    for r in rng.sample(cand, min(200, len(cand))):
        rec = eval_line("mfe-%04d" % sum(1 for x in recs if x["kind"] == "mfe"), "mfe", r["seq"], r["structure"], {"from": r["id"]})
        assert rec["energy_dcal"] == r["mfe_dcal"]
        recs.append(rec)
    # 4. suboptimal structures (random one within delta of the MFE)
    md = default_md()
    md.uniq_ML = 1
    for _ in range(150):
        n = rng.randint(15, 120)
        seq = rand_seq(rng, n, rng.uniform(0.3, 0.7))
        delta = rng.randint(10, 300)
        fc = RNA.fold_compound(seq, md)
        got = []

        def cb(s, en, data):
            if s is not None and len(got) < 5000:
                got.append((s, int(round(en * 100))))

        fc.subopt_cb(delta, cb, None)
        st, en = rng.choice(got)
        rec = eval_line("subopt-%04d" % sum(1 for x in recs if x["kind"] == "subopt"), "subopt", seq, st, {"delta_dcal": delta})
        assert rec["energy_dcal"] == en
        recs.append(rec)
    # 5. targets with LEARNA-style designs (the energy of the target structure itself)
    for r in fold_recs:
        if r["kind"] == "learna_design":
            add("design_on_target", (r["seq"], r["target"]), {"target_source": r["target_source"]})

    # ---- per-loop-type stress cases (each embedded in a small context; "loops" isolates the term)
    def ctx(core, max_flank=3):
        return cat(unp(rand_bases(rng, rng.randint(0, max_flank))), wrap(rpairs(rng, rng.randint(0, 2), WC), core),
                   unp(rand_bases(rng, rng.randint(0, max_flank))))

    # hairpins 3..30 (4 per size, all six closing pairs over the sizes), and > 30
    for size in range(3, 31):
        for k in range(4):
            cp = CANONICAL[(size + k) % 6]
            loop = rand_bases(rng, size)
            add("hairpin", ctx(wrap([cp], unp(loop))), {"size": size, "closing": cp, "loop": loop})
    for size in (31, 32, 33, 35, 40, 50, 64, 100):
        for k in range(2):
            cp = rng.choice(CANONICAL)
            loop = rand_bases(rng, size)
            add("hairpin", ctx(wrap([cp], unp(loop))), {"size": size, "closing": cp, "loop": loop})
    # triloops with every closing pair (terminal AU/GU penalty on size-3 loops)
    for cp in CANONICAL:
        for k in range(4):
            loop = rand_bases(rng, 3)
            add("hairpin", ctx(wrap([cp], unp(loop))), {"size": 3, "closing": cp, "loop": loop})
    # special tri/tetra/hexaloops, as is and two near misses each
    P = RNA.param(default_md())
    for group in ("Triloops", "Tetraloops", "Hexaloops"):
        for sp in getattr(P, group).split():
            loop = sp[1:-1]
            add("special_hairpin", ctx(wrap([sp[0] + sp[-1]], unp(loop))), {"special": sp, "group": group, "variant": "exact"})
            pos = rng.randrange(len(loop))
            mut = loop[:pos] + rng.choice([b for b in "ACGU" if b != loop[pos]]) + loop[pos + 1:]
            add("special_hairpin", ctx(wrap([sp[0] + sp[-1]], unp(mut))), {"special": sp, "group": group, "variant": "loop_mutated"})
            other = rng.choice([p for p in CANONICAL if p != sp[0] + sp[-1]])
            add("special_hairpin", ctx(wrap([other], unp(loop))), {"special": sp, "group": group, "variant": "closing_changed"})
            # the special hairpin inside a multiloop branch
            add("special_hairpin", ctx(wrap(["GC"], cat(gap(rng), wrap(["CG", sp[0] + sp[-1]], unp(loop)), gap(rng), branch(rng), gap(rng)))),
                {"special": sp, "group": group, "variant": "in_multiloop"})
    # poly-C loops and GU closures (NNDB rules that ViennaRNA does NOT apply)
    for size in range(3, 10):
        add("hairpin", ctx(wrap([rng.choice(CANONICAL)], unp("C" * size))), {"size": size, "note": "poly-C loop"})
    for size in (3, 4, 5, 6):
        add("hairpin", cat(unp("A"), wrap(["GC", "GC", "GU"], unp(rand_bases(rng, size))), unp("A")), {"size": size, "note": "GU closure after GG"})
    # stacks: all 6x6 (outer pair, inner pair) combinations
    for p1 in CANONICAL:
        for p2 in CANONICAL:
            add("stack", ctx(wrap([p1, p2, "GC"], unp("GAAA")), 2), {"outer": p1, "inner": p2})
    # bulges 1..30 on either side, plus > 30
    for size in list(range(1, 31)) + [31, 35, 40]:
        for side in ("5p", "3p"):
            for k in range(2 if size <= 30 else 1):
                cpo, cpi = rng.choice(CANONICAL), rng.choice(CANONICAL)
                inner = wrap([cpi] + rpairs(rng, rng.randint(0, 2), WC), unp(rand_bases(rng, rng.randint(3, 6))))
                b = unp(rand_bases(rng, size))
                core = wrap([cpo], cat(b, inner) if side == "5p" else cat(inner, b))
                add("bulge", ctx(core), {"size": size, "side": side, "outer": cpo, "inner": cpi})

    # interior loops
    def interior(l1, l2, kind, extra=None):
        cpo, cpi = rng.choice(CANONICAL), rng.choice(CANONICAL)
        inner = wrap([cpi] + rpairs(rng, rng.randint(0, 2), WC), unp(rand_bases(rng, rng.randint(3, 6))))
        x, y = rand_bases(rng, l1), rand_bases(rng, l2)
        info = {"l1": l1, "l2": l2, "outer": cpo, "inner": cpi, "left": x, "right": y}
        if extra:
            info.update(extra)
        add(kind, ctx(wrap([cpo], cat(unp(x), inner, unp(y)))), info)

    for _ in range(100):
        interior(1, 1, "interior_1x1")
    for k in range(100):
        interior(1, 2, "interior_1x2") if k % 2 == 0 else interior(2, 1, "interior_1x2")
    for _ in range(100):
        interior(2, 2, "interior_2x2")
    for k in range(60):
        interior(2, 3, "interior_2x3") if k % 2 == 0 else interior(3, 2, "interior_2x3")
    for n in range(3, 30):
        interior(1, n, "interior_1xn")
        interior(n, 1, "interior_1xn")
    gen = 0
    while gen < 120:
        l1, l2 = rng.randint(2, 28), rng.randint(2, 28)
        if l1 + l2 > 30 or (l1, l2) in ((2, 2), (2, 3), (3, 2)):
            continue
        interior(l1, l2, "interior_generic")
        gen += 1
    for _ in range(20):
        l1 = rng.randint(1, 40)
        l2 = rng.randint(max(1, 31 - l1), 45)
        interior(l1, l2, "interior_over_maxloop")

    # multiloops with 3..6 branches (closing stem + 2..5 inner stems), gaps 0..5 incl. adjacent stems
    for k in range(150):
        nb = 2 + k % 4
        parts = [gap(rng)]
        for _ in range(nb):
            parts += [branch(rng), gap(rng)]
        cp = rng.choice(CANONICAL)
        add("multiloop", ctx(wrap([cp] + rpairs(rng, rng.randint(0, 2)), cat(*parts))), {"branches": nb + 1, "closing": cp})
    # nested multiloops
    for k in range(20):
        inner_ml = wrap([rng.choice(CANONICAL)], cat(gap(rng), branch(rng), gap(rng), branch(rng), gap(rng)))
        outer = wrap([rng.choice(CANONICAL)], cat(gap(rng), inner_ml, gap(rng), branch(rng), gap(rng), branch(rng), gap(rng)))
        add("multiloop", ctx(outer), {"nested": True})
    # exterior loops: 1..5 stems, with / without unpaired neighbours (dangles on both sides, one side, none)
    for k in range(100):
        m = 1 + k % 5
        parts = [gap(rng, 0.4, 3)]
        for _ in range(m):
            parts += [branch(rng, 1, 5), gap(rng, 0.4, 3)]
        add("exterior", cat(*parts), {"stems": m})
    for n in (1, 4, 10, 57, 200):
        add("exterior", unp(rand_bases(rng, n)), {"stems": 0})
    # lonely pairs in every loop context
    for k in range(30):
        lone = wrap([rng.choice(CANONICAL)], unp(rand_bases(rng, rng.randint(3, 7))))
        where = k % 3
        if where == 0:
            sd = cat(gap(rng), lone, gap(rng), branch(rng), gap(rng))
        elif where == 1:
            sd = wrap(["GC", "CG"], cat(gap(rng), lone, gap(rng), branch(rng), gap(rng)))
        else:
            sd = wrap(["GC", "GC"], cat(unp(rand_bases(rng, rng.randint(1, 4))), lone, unp(rand_bases(rng, rng.randint(1, 4)))))
        add("lonely_pair", sd, {"context": ["exterior", "multiloop", "interior"][where]})
    return recs


def gen_interior_tables(out_path):
    """Every cell of the int11 / int21 (both orientations) / int22 tables, canonical pairs only.
    Sequence: P1[0] x.. P2[0] GAAA P2[1] y.. P1[1]; loop_dcal is the interior-loop term alone."""
    rows = []

    def row(table, p1, p2, x, y):
        seq = p1[0] + x + p2[0] + "GAAA" + p2[1] + y + p1[1]
        db = "(" + "." * len(x) + "(....)" + "." * len(y) + ")"
        fc = eval_fc(seq)
        pt = RNA.ptable(db)
        tot = fc.eval_structure_pt(pt)
        loop = fc.eval_loop_pt(1, pt)
        rows.append((table, p1, p2, x, y, seq, db, tot, loop))

    for p1 in CANONICAL:
        for p2 in CANONICAL:
            for x in "ACGU":
                for y in "ACGU":
                    row("int11", p1, p2, x, y)
            for x in "ACGU":
                for y in itertools.product("ACGU", repeat=2):
                    row("int21", p1, p2, x, "".join(y))
                    row("int12", p1, p2, "".join(y), x)
            for x in itertools.product("ACGU", repeat=2):
                for y in itertools.product("ACGU", repeat=2):
                    row("int22", p1, p2, "".join(x), "".join(y))
    with open(out_path, "w") as f:
        f.write("# ViennaRNA %s eval_structure_pt / eval_loop_pt, default model (37C, turner2004, dangles=2). "
                "outer=(1,n), inner pair closes hairpin GAAA; left/right = unpaired 5'/3' sides of the interior loop\n" % VERSION)
        f.write("table\touter\tinner\tleft\tright\tseq\tstructure\tenergy_dcal\tinterior_loop_dcal\n")
        for r in rows:
            f.write("\t".join(str(x) for x in r) + "\n")
    return len(rows)


# --------------------------------------------------------------------------- verify / bench

def verify(paths):
    bad = n = 0
    for path in paths:
        if path.endswith(".tsv"):
            for line in open(path):
                if line.startswith("#") or line.startswith("table\t"):
                    continue
                t = line.rstrip("\n").split("\t")
                seq, db, tot, loop = t[5], t[6], int(t[7]), int(t[8])
                fc = eval_fc(seq)
                pt = RNA.ptable(db)
                n += 1
                if fc.eval_structure_pt(pt) != tot or fc.eval_loop_pt(1, pt) != loop:
                    bad += 1
                    print("MISMATCH", path, t[:5])
            continue
        for line in open(path):
            r = json.loads(line)
            n += 1
            if "mfe_dcal" in r:
                st, dcal, tied = fold_record(r["seq"])
                ok = st == r["structure"] and dcal == r["mfe_dcal"] and len(tied) == r["ties"]
                if ok and "tied_structures" in r:
                    ok = sorted(tied) == r["tied_structures"]
            else:
                tot, loops = eval_record(r["seq"], r["structure"])
                ok = tot == r["energy_dcal"] and loops == r["loops"]
            if not ok:
                bad += 1
                print("MISMATCH", path, r["id"])
    print("verified %d records with ViennaRNA %s: %d mismatches" % (n, VERSION, bad))
    return bad


def bench(lengths=(100, 200, 500), nseq=5, reps=5, seed=1):
    rng = random.Random(seed)
    res = {}
    for L in lengths:
        ts = []
        for _ in range(nseq):
            s = rand_seq(rng, L, 0.5)
            RNA.fold(s)  # warm-up
            for _ in range(reps):
                t = time.perf_counter()
                RNA.fold(s)
                ts.append(time.perf_counter() - t)
        res[L] = {"median_ms": round(statistics.median(ts) * 1000, 2), "min_ms": round(min(ts) * 1000, 2), "runs": len(ts)}
    return res


# --------------------------------------------------------------------------- main

def write_jsonl(path, recs):
    with open(path, "w") as f:
        for r in recs:
            f.write(json.dumps(r, separators=(",", ":")) + "\n")


def main():
    global MODEL
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    a = sub.add_parser("all")
    a.add_argument("--seed", type=int, default=DEFAULT_SEED)
    a.add_argument("--outdir", default=HERE)
    a.add_argument("--n-random", type=int, default=1600)
    f = sub.add_parser("fold")
    f.add_argument("--seed", type=int, required=True)
    f.add_argument("--n-random", type=int, default=500)
    f.add_argument("--lengths", default=DEFAULT_LENGTHS, help="lo-hi:weight,... (default %(default)s)")
    f.add_argument("--gc", default="0.3,0.7", help="GC-content range, uniform (default %(default)s)")
    f.add_argument("--n-adversarial", type=int, default=0, help="randomised adversarial sequences")
    f.add_argument("--adv-maxlen", type=int, default=300)
    f.add_argument("--prefix", default="rand")
    f.add_argument("--out", required=True)
    v = sub.add_parser("verify")
    v.add_argument("files", nargs="+")
    b = sub.add_parser("bench")
    b.add_argument("--lengths", default="100,200,500")
    b.add_argument("--nseq", type=int, default=5)
    b.add_argument("--reps", type=int, default=5)
    args = ap.parse_args()
    MODEL = model_dict()

    if args.cmd == "all":
        os.makedirs(args.outdir, exist_ok=True)
        rng = random.Random(args.seed)
        t = time.time()
        fold_recs = gen_shared_fold(rng, args.n_random)
        write_jsonl(os.path.join(args.outdir, "vienna_fold_fixtures.jsonl"), fold_recs)
        print("fold: %d records (%.0f s)" % (len(fold_recs), time.time() - t))
        t = time.time()
        eval_recs = gen_eval(rng, fold_recs)
        write_jsonl(os.path.join(args.outdir, "vienna_eval_fixtures.jsonl"), eval_recs)
        print("eval: %d records (%.0f s)" % (len(eval_recs), time.time() - t))
        nt = gen_interior_tables(os.path.join(args.outdir, "vienna_interior_tables.tsv"))
        print("interior tables: %d rows" % nt)
    elif args.cmd == "fold":
        rng = random.Random(args.seed)
        lo, hi = (float(x) for x in args.gc.split(","))
        recs = gen_random_fold(rng, args.n_random, parse_lengths(args.lengths), lo, hi, args.prefix)
        for k, (kind, s) in enumerate(adversarial_random(rng, args.n_adversarial, args.adv_maxlen)):
            recs.append(fold_line("%s-adv-%04d" % (args.prefix, k), "adversarial:" + kind, s))
        write_jsonl(args.out, recs)
        print("fold: %d records" % len(recs))
    elif args.cmd == "verify":
        sys.exit(1 if verify(args.files) else 0)
    elif args.cmd == "bench":
        out = bench(tuple(int(x) for x in args.lengths.split(",")), args.nseq, args.reps)
        print(json.dumps({"vienna_version": VERSION, "python": platform.python_version(), "machine": platform.machine(),
                          "cpus": os.cpu_count(), "load_avg": os.getloadavg(), "rna_fold_ms": out}))


if __name__ == "__main__":
    main()
