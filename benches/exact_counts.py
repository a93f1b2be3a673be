#!/usr/bin/env python3
"""The laws of the counts without sampling (`stickslip exact-law --counts N`: counts.parquet and
the S_T, S_L rows of moments.parquet) against a Monte Carlo dataset of the same scene.

For S_T (sticks started in [0, t_a]) and S_L (slips started there): every P(S = n) the law gives
above 1e-6 beside the dataset's share with its binomial standard error, and z = (exact − MC) /
sqrt(SE² + error²); then the means and variances (the variance's standard error from the fourth
central moment). Prints Markdown tables, how many |z| exceed 1.96 and the largest |z|.

usage: python3 benches/exact_counts.py LAWDIR DATASET_DIR
(pinned: polars==2.1.0)
"""
import math
import sys

import polars as pl

law, data = sys.argv[1], sys.argv[2].rstrip("/")
counts = pl.read_parquet(f"{law}/counts.parquet")
moments = pl.read_parquet(f"{law}/moments.parquet").filter(pl.col("index").is_null())
df = pl.scan_parquet(f"{data}/**/part-*.parquet").select("n_stick", "n_slip").collect()
n = df.height
zs = []
print(f"{n} realizations\n")
print("| n | P(S_T = n): exact | Monte Carlo | z | P(S_L = n): exact | Monte Carlo | z |\n|---:|---:|---:|---:|---:|---:|---:|")
shares = {v: df[c].value_counts().rows() for v, c in (("S_T", "n_stick"), ("S_L", "n_slip"))}
cells = {}
for v in ("S_T", "S_L"):
    seen = dict(shares[v])
    for value, p, e in counts.filter(pl.col("variable") == v).select("value", "probability", "error").rows():
        share = seen.get(value, 0) / n
        se = math.sqrt(max(p, 1 / n) * (1 - p) / n)
        z = (p - share) / math.sqrt(se**2 + e**2)
        cells[(v, value)] = (p, e, share, se, z)
for value in sorted({k[1] for k in cells}):
    row = [cells.get((v, value)) for v in ("S_T", "S_L")]
    if all(c is None or c[0] < 1e-6 for c in row):
        continue
    text = []
    for c in row:
        if c is None:
            text.append(" | | ")
            continue
        p, e, share, se, z = c
        zs.append(z)
        text.append(f"{p:.4e} ± {e:.0e} | {share:.4e} ± {se:.0e} | {z:+.2f}")
    print(f"| {value} | {' | '.join(text)} |")
print("\n| variable | mean, exact | Monte Carlo | z | variance, exact | Monte Carlo | z |\n|---|---:|---:|---:|---:|---:|---:|")
for v, c in (("S_T", "n_stick"), ("S_L", "n_slip")):
    x = df[c].cast(pl.Float64)
    mean, m2 = x.mean(), ((x - x.mean()) ** 2).mean()
    m4 = ((x - mean) ** 4).mean()
    se, se_var = math.sqrt(m2 / n), math.sqrt((m4 - m2 * m2) / n)
    row = moments.filter(pl.col("variable") == v).row(0, named=True)
    z1 = (row["mean"] - mean) / math.sqrt(se**2 + row["error"] ** 2)
    z2 = (row["variance"] - m2) / math.sqrt(se_var**2 + row["variance_error"] ** 2)
    zs += [z1, z2]
    print(f"| {v} | {row['mean']:.6f} ± {row['error']:.1e} | {mean:.6f} ± {se:.1e} | {z1:+.2f} | {row['variance']:.6f} ± {row['variance_error']:.1e} | {m2:.6f} ± {se_var:.1e} | {z2:+.2f} |")
print(f"\n{sum(abs(z) > 1.96 for z in zs)} of {len(zs)} beyond 1.96; largest |z|: {max(abs(z) for z in zs):.2f}")
