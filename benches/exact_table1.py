#!/usr/bin/env python3
"""The paper's Table 1 without sampling (`stickslip exact-law`, moments.parquet) against Monte Carlo.

Runs `exact-law` on the paper scenario (or the scene `--set` makes of it; timed) and `simulate` of REALIZATIONS realizations of it
(timed), then compares every mean and variance of T_k, L_k, D_k, H_k (k = 1..6): Monte Carlo over
the realizations that reached the k-th stick (a duration only if it ended before t_a), its
standard error (the variance's from the fourth central moment), and z = (exact − MC) /
sqrt(SE² + error²). Prints a Markdown table and the largest |z|; then the same for D_k's law
(survival.parquet): P(D_k > t) at reproduce's tail times against the share of the k-th sticks
(ended before t_a) that last longer, with its binomial standard error. Last, the cost at matched
precision: per statistic the relative error the exact run certifies and the realizations Monte
Carlo needs for a standard error that small, N·(SE/error)², timed at the simulate run's rate (its
cost is linear in N: the book's Benchmarks, "Whole processes"); and the same for 1e-4 relative.

usage: python3 benches/exact_table1.py [BINARY] [--realizations N] [--seed S] [--resolution R] [--keep DIR]
       [--law LAWDIR] [--set KEY=VALUE ...]
(--law: compare an existing `exact-law --out LAWDIR` of the same scene instead of running it,
e.g. a second seed against one long exact run; its time is then not measured)
(pinned: polars==2.1.0; the binary defaults to target/release/stickslip)
"""
import argparse, math, resource, subprocess, sys, tempfile, time

import polars as pl

p = argparse.ArgumentParser()
p.add_argument("binary", nargs="?", default="target/release/stickslip")
p.add_argument("--realizations", type=int, default=10_000_000)
p.add_argument("--seed", type=int, default=1)
p.add_argument("--resolution", type=int, default=80)
p.add_argument("--keep", help="keep the exact-law output and the dataset in this new directory")
p.add_argument("--law", help="an existing exact-law output directory of the same scene (not run, not timed)")
p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="a scenario key for both runs (repeatable), e.g. model.damping=0.5")
a = p.parse_args()
sets = [x for kv in a.set for x in ("--set", kv)]

with tempfile.TemporaryDirectory() as scratch:
    tmp = a.keep or scratch
    law = a.law or f"{tmp}/law"
    t_exact, rss_exact = float("nan"), float("nan")
    if not a.law:
        t0 = time.time()
        subprocess.run([a.binary, "exact-law", *sets, "--out", law, "--resolution", str(a.resolution), "-q"], check=True)
        t_exact = time.time() - t0
        rss_exact = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 2**20  # KiB -> GiB: the only child so far
    t0 = time.time()
    subprocess.run([a.binary, "simulate", *sets, "--out", f"{tmp}/mc", "--realizations", str(a.realizations), "--seed", str(a.seed), "-q"], check=True)
    t_mc = time.time() - t0
    ex = pl.read_parquet(f"{law}/moments.parquet")
    df = pl.scan_parquet(f"{tmp}/mc/*.parquet")
    cols = {"T": "stick_start", "L": "slip_start", "D": "stick_duration", "H": "slip_duration"}
    made = f"exact-law --resolution {a.resolution}: {t_exact:.1f} s, peak RSS {rss_exact:.1f} GiB" if not a.law else f"exact-law output {a.law} (given)"
    print(f"{' '.join(a.set) or 'the paper scenario'}: {made}; simulate {a.realizations} realizations (seed {a.seed}): {t_mc:.1f} s\n")
    print("| variable | mean, exact | Monte Carlo | z | variance, exact | Monte Carlo | z |\n|---|---:|---:|---:|---:|---:|---:|")
    worst, need = 0.0, []
    for v, c in cols.items():
        for k in range(1, 7):
            x = pl.col(c).list.get(k - 1, null_on_oob=True)
            q = df.select(x.alias("x"), pl.col("n_stick" if v == "D" else "n_slip").alias("n"), pl.col("n_stick").alias("s"), pl.col("last_truncated").alias("cut"))
            if v == "D":  # the k-th stick ended before t_a
                q = q.filter(~((pl.col("n") == k) & pl.col("cut")))
            if v == "H":  # the k-th slip ended in stick k + 1
                q = q.filter(pl.col("s") > k)
            n, m, var, m4 = q.select(pl.col("x").drop_nulls()).select(
                pl.len().alias("n"), pl.col("x").mean().alias("m"), pl.col("x").var().alias("v"),
                ((pl.col("x") - pl.col("x").mean()) ** 4).mean().alias("m4")).collect().row(0)
            se_m, se_v = math.sqrt(var / n), math.sqrt(max(m4 - var * var, 0.0) / n)
            e = ex.filter((pl.col("variable") == v) & (pl.col("index") == k)).row(0, named=True)
            zm = (e["mean"] - m) / math.hypot(se_m, e["error"])
            zv = (e["variance"] - var) / math.hypot(se_v, e["variance_error"])
            worst = max(worst, abs(zm), abs(zv))
            need += [(f"mean {v}_{k}", e["mean"], e["error"], se_m), (f"variance {v}_{k}", e["variance"], e["variance_error"], se_v)]
            print(f"| {v}_{k} | {e['mean']:.6f} ± {e['error']:.1e} | {m:.6f} ± {se_m:.1e} | {zm:+.2f} | {e['variance']:.6f} ± {e['variance_error']:.1e} | {var:.6f} ± {se_v:.1e} | {zv:+.2f} |")
    print(f"\nlargest |z|: {worst:.2f}")

    sv = pl.read_parquet(f"{law}/survival.parquet")
    times = [0.5, 1.0, 1.5, 2.0, 2.4]
    print("\n| P(D_k > t) | " + " | ".join(f"t = {t} s: exact | Monte Carlo | z" for t in times) + " |")
    print("|---|" + "---:|---:|---:|" * len(times))
    worst = 0.0
    for k in range(1, 7):
        d = (df.select(pl.col("stick_duration").list.get(k - 1, null_on_oob=True).alias("d"), pl.col("n_stick").alias("n"), pl.col("last_truncated").alias("cut"))
             .filter(~((pl.col("n") == k) & pl.col("cut"))).select(pl.col("d").drop_nulls()))
        counts = d.select(pl.len().alias("n"), *[(pl.col("d") > t).sum().alias(str(t)) for t in times]).collect().row(0, named=True)
        cells = []
        for t in times:
            e = sv.filter((pl.col("index") == k) & (pl.col("t") == t)).row(0, named=True)
            share = counts[str(t)] / counts["n"]
            se = math.sqrt(max(share, 1.0 / counts["n"]) * (1.0 - share) / counts["n"])
            z = (e["survival"] - share) / math.hypot(se, e["error"])
            worst = max(worst, abs(z))
            cells.append(f"{e['survival']:.3e} ± {e['error']:.0e} | {share:.3e} ± {se:.0e} | {z:+.2f}")
        print(f"| D_{k} | " + " | ".join(cells) + " |")
    print(f"\nlargest |z|: {worst:.2f}")

    # Cost at matched precision: Monte Carlo's standard error falls as 1/sqrt(N), so a standard
    # error equal to the exact run's error needs N (SE / error)^2 realizations; its time is the
    # simulate run's, scaled by the realizations.
    rate = a.realizations / t_mc
    def cost(se, target):  # (realizations, seconds)
        n = a.realizations * (se / target) ** 2
        return n, n / rate
    print("\n| statistic | exact: error (relative) | Monte Carlo, same SE: realizations | time | Monte Carlo, 1e-4 relative: realizations | time |\n|---|---:|---:|---:|---:|---:|")
    worst_rel, worst_same, worst_e4, worst_e4_means = 0.0, ((0.0, 0.0), ""), ((0.0, 0.0), ""), ((0.0, 0.0), "")
    for name, value, error, se in need:
        rel = error / abs(value)
        same, e4 = cost(se, error), cost(se, 1e-4 * abs(value))
        worst_rel = max(worst_rel, rel)
        worst_same, worst_e4 = max(worst_same, (same, name)), max(worst_e4, (e4, name))
        if name.startswith("mean"):
            worst_e4_means = max(worst_e4_means, (e4, name))
        print(f"| {name} | {error:.1e} ({rel:.1e}) | {same[0]:.2e} | {same[1]:.3g} s | {e4[0]:.2e} | {e4[1]:.3g} s |")
    print(f"\n{made}: every error at most {worst_rel:.1e} relative; "
          f"Monte Carlo to the same standard error on every statistic: {worst_same[0][0]:.2e} realizations ({worst_same[1]}), {worst_same[0][1]:.0f} s; "
          f"to 1e-4 relative on every mean: {worst_e4_means[0][0]:.2e} ({worst_e4_means[1]}), {worst_e4_means[0][1]:.0f} s; "
          f"on every statistic: {worst_e4[0][0]:.2e} ({worst_e4[1]}), {worst_e4[0][1]:.0f} s (at {rate:.0f} realizations/s)")
