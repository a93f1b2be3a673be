#!/usr/bin/env python3
"""Coverage of analyze's 95 % intervals, per column: RUNS independent datasets of N realizations
(seeds 1..RUNS) of a scene, each analysed, against a reference of 10^6 realizations (seed 999999)
of the same scene, or a reference analysis you give.

    python3 benches/interval_coverage.py [--bin target/release/stickslip] [--runs 200] [--n 1500]
                                [--scenario FILE] [--set KEY=VALUE ...]
                                [--reference ADIR | --reference-n 1000000]

For every Table 1 variable (T_k, L_k, D_k, H_k for k = 1…6, S_T, S_L) and every moment (mean,
variance, skewness, kurtosis): how many of the RUNS intervals hold the reference's value, the
coverage with its binomial standard error sqrt(p(1 − p)/RUNS), and a mark where the coverage is
below 0.93 (✗; ✗✗ where it is below by more than two standard errors), and ≈ where the analysis
flags the interval approximate (`skewness_approximate`, `kurtosis_approximate`) in most runs. The
reference's own sampling error is about
sqrt(N / 10^6) of a run's (0.04 at N = 1,500, 0.13 at N = 18,000): small beside the intervals'
half-widths, not zero. Rows a run cannot estimate (too few realizations reach T_6, say) count in
neither hits nor runs; the column `runs` says how many did.
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile

import polars as pl

VARIABLES = [(v, k) for v in "TLDH" for k in range(1, 7)] + [("S_T", None), ("S_L", None)]
MOMENTS = ["mean", "variance", "skewness", "kurtosis"]
FLOOR = 0.93


def scene(a):
    return ([a.scenario] if a.scenario else []) + sum((["--set", s] for s in a.set), [])


def analysed(a, out, seed, n):
    """Simulate and analyse one dataset; its moments table (the dataset is removed)."""
    subprocess.run([a.bin, "simulate", *scene(a), "--out", out, "--realizations", str(n), "--seed", str(seed), "-q"], check=True)
    subprocess.run([a.bin, "analyze", out, "--out", out + "-a", "-q", "--no-tails"], check=True)
    m = pl.read_parquet(out + "-a/moments.parquet")
    shutil.rmtree(out)
    shutil.rmtree(out + "-a")
    return m


def values(m):
    """(variable, index) → the row of the moments table."""
    return {(r["variable"], r["index"]): r for r in m.iter_rows(named=True)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default="target/release/stickslip")
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--n", type=int, default=1500)
    ap.add_argument("--scenario", default=None)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--reference", default=None, help="an analysis directory of the same scene (its moments.parquet)")
    ap.add_argument("--reference-n", type=int, default=1_000_000)
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    if a.reference:
        ref = values(pl.read_parquet(os.path.join(a.reference, "moments.parquet")))
        what = a.reference
    else:
        ref = values(analysed(a, os.path.join(tmp, "ref"), 999999, a.reference_n))
        what = f"{a.reference_n:,} realizations, seed 999999"
    hits = {(v, m): 0 for v in VARIABLES for m in MOMENTS}
    runs = dict.fromkeys(hits, 0)
    # runs whose analysis flagged the interval approximate (skewness_approximate, kurtosis_approximate)
    flagged = dict.fromkeys(hits, 0)
    for r in range(a.runs):
        ours = values(analysed(a, os.path.join(tmp, f"r{r}"), r + 1, a.n))
        for v in VARIABLES:
            row, truth = ours.get(v), ref.get(v)
            for m in MOMENTS:
                if row is None or truth is None or None in (row[m + "_lo"], row[m + "_hi"], truth[m]):
                    continue
                runs[(v, m)] += 1
                hits[(v, m)] += row[m + "_lo"] <= truth[m] <= row[m + "_hi"]
                flagged[(v, m)] += row.get(m + "_approximate") == 1
        print(f"\r{r + 1}/{a.runs}", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    shutil.rmtree(tmp)
    name = lambda v: f"{v[0]}_{v[1]}" if v[1] else v[0]
    print(f"{a.runs} datasets of {a.n:,} realizations of {a.scenario or 'the paper scene'} {' '.join(a.set)}; reference: {what}")
    print(f"coverage (binomial SE); ✗: below {FLOOR}; ✗✗: below by more than two SE; ≈: the analysis flags the interval approximate (in most runs)\n")
    print("| variable | " + " | ".join(MOMENTS) + " |\n|---|" + "---|" * len(MOMENTS))
    short, clearly, unflagged = 0, 0, 0
    for v in VARIABLES:
        cells = []
        for m in MOMENTS:
            n = runs[(v, m)]
            if n == 0:
                cells.append("–")
                continue
            p = hits[(v, m)] / n
            se = math.sqrt(p * (1 - p) / n)
            short += p < FLOOR
            clearly += p + 2 * se < FLOOR
            approximate = 2 * flagged[(v, m)] > n
            unflagged += p < FLOOR and not approximate
            mark = " ✗✗" if p + 2 * se < FLOOR else " ✗" if p < FLOOR else ""
            cells.append(f"{p:.3f} ({se:.3f}){mark}" + (" ≈" if approximate else "") + ("" if n == a.runs else f" [{n} runs]"))
        print(f"| {name(v)} | " + " | ".join(cells) + " |")
    print(f"\n{short} of {len(VARIABLES) * len(MOMENTS)} columns below {FLOOR}, {clearly} of them by more than two SE; {unflagged} below {FLOOR} and not flagged approximate")


if __name__ == "__main__":
    main()
