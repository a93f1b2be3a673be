#!/usr/bin/env python3
"""Coverage of analyze's 95 % intervals (delete-a-group jackknife): RUNS independent datasets of N
paper realizations (seeds 1..RUNS) against a 200,000-realization reference (seed 999999).

    python3 benches/coverage.py [--bin target/release/stickslip] [--runs 200] [--n 1000]

For T_1, T_2, D_1, H_1, L_1, S_T and the stick time, and each statistic kind (mean, variance,
mode, skewness, kurtosis): the fraction of intervals that contain the reference's value.
"""
import argparse
import os
import subprocess
import tempfile

import polars as pl

SERIES = [("T", 1), ("T", 2), ("D", 1), ("H", 1), ("L", 1), ("S_T", 0), ("stick_time", 0)]
KINDS = ["mean", "variance", "mode", "skewness", "kurtosis"]


def analysed(binary, out, seed, n):
    subprocess.run([binary, "simulate", "--out", out, "--realizations", str(n), "--seed", str(seed), "-q"], check=True)
    subprocess.run([binary, "analyze", out, "--out", out + "-a", "-q"], check=True)
    return pl.read_parquet(out + "-a/moments.parquet").with_columns(pl.col("index").fill_null(0))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="target/release/stickslip")
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--n", type=int, default=1000)
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    ref = analysed(a.bin, os.path.join(tmp, "ref"), 999999, 200000)
    row = lambda df, v, i: df.filter((pl.col("variable") == v) & (pl.col("index") == i)).row(0, named=True)
    hits = {k: 0 for k in KINDS}
    total = {k: 0 for k in KINDS}
    for r in range(a.runs):
        out = os.path.join(tmp, f"r{r}")
        m = analysed(a.bin, out, r + 1, a.n)
        for v, i in SERIES:
            ours, truth = row(m, v, i), row(ref, v, i)
            for k in KINDS:
                lo, hi = ours[k + "_lo"], ours[k + "_hi"]
                if lo is None or hi is None or truth[k] is None:
                    continue
                total[k] += 1
                hits[k] += lo <= truth[k] <= hi
        subprocess.run(["rm", "-rf", out, out + "-a"], check=True)
    print(f"{a.runs} datasets of {a.n} paper realizations; reference: 200,000 realizations")
    print("| statistic | intervals | coverage (nominal 0.95) |\n|---|---|---|")
    for k in KINDS:
        print(f"| {k} | {total[k]} | {hits[k] / max(total[k], 1):.3f} |")


if __name__ == "__main__":
    main()
