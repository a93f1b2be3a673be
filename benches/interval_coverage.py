#!/usr/bin/env python3
"""Coverage of analyze's 95 % intervals (delete-a-group jackknife): RUNS independent datasets of N
realizations (seeds 1..RUNS) of a scene against a 200,000-realization reference (seed 999999).

    python3 benches/interval_coverage.py [--bin target/release/stickslip] [--runs 200] [--n 1500]
                                [--scenario FILE] [--set KEY=VALUE ...]

For T_1, L_1, D_1, H_1, S_T and the stick fraction, and each statistic kind (mean, variance,
mode, skewness, kurtosis): the fraction of intervals that contain the reference's value, pooled
and per series.
"""
import argparse
import os
import subprocess
import tempfile

import polars as pl

SERIES = [("T", 1), ("L", 1), ("D", 1), ("H", 1), ("S_T", 0), ("stick_fraction", 0)]
KINDS = ["mean", "variance", "mode", "skewness", "kurtosis"]


def analysed(a, out, seed, n):
    scene = ([a.scenario] if a.scenario else []) + sum((["--set", s] for s in a.set), [])
    subprocess.run([a.bin, "simulate", *scene, "--out", out, "--realizations", str(n), "--seed", str(seed), "-q"], check=True)
    subprocess.run([a.bin, "analyze", out, "--out", out + "-a", "-q", "--no-tails"], check=True)
    return pl.read_parquet(out + "-a/moments.parquet").with_columns(pl.col("index").fill_null(0))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="target/release/stickslip")
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--n", type=int, default=1500)
    ap.add_argument("--scenario", default=None)
    ap.add_argument("--set", action="append", default=[])
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    ref = analysed(a, os.path.join(tmp, "ref"), 999999, 200000)
    row = lambda df, v, i: df.filter((pl.col("variable") == v) & (pl.col("index") == i)).row(0, named=True)
    hits, total = {}, {}
    for r in range(a.runs):
        out = os.path.join(tmp, f"r{r}")
        m = analysed(a, out, r + 1, a.n)
        for v, i in SERIES:
            ours, truth = row(m, v, i), row(ref, v, i)
            for k in KINDS:
                lo, hi = ours[k + "_lo"], ours[k + "_hi"]
                if lo is None or hi is None or truth[k] is None:
                    continue
                for key in [(k, None), (k, f"{v}_{i}" if i else v)]:
                    total[key] = total.get(key, 0) + 1
                    hits[key] = hits.get(key, 0) + (lo <= truth[k] <= hi)
        subprocess.run(["rm", "-rf", out, out + "-a"], check=True)
    scene = a.scenario or "the paper scene"
    print(f"{a.runs} datasets of {a.n} realizations of {scene} {' '.join(a.set)}; reference: 200,000 realizations")
    names = [f"{v}_{i}" if i else v for v, i in SERIES]
    print("| statistic | all | " + " | ".join(names) + " |\n|---|---|" + "---|" * len(names))
    for k in KINDS:
        cells = [f"{hits.get((k, s), 0) / total[(k, s)]:.3f}" if total.get((k, s)) else "–" for s in [None] + names]
        print(f"| {k} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
