#!/usr/bin/env python3
"""The densities of T_k, L_k and H_k without sampling (`stickslip exact-law --densities N`:
densities.parquet) against a Monte Carlo dataset of the same scene.

In each cell [t_lo, t_hi) of the law (its density averaged over the cell), the dataset's density
is its share of values in the cell over the cell's width, with the binomial standard error (the
law's side: the density plus the cell's point mass over its width);
z = (exact − MC) / sqrt(SE² + error²). The law is the process' without the window: H_k counts
only the slips that end before t_a (stick k + 1 started), every share is of all realizations.
Prints per variable and k the integral of the exact density over [0, t_a], the L1 distance
∫|exact − MC|, how many |z| exceed 1.96 and the largest |z|; then the totals, and each point
mass beside the share of the most frequent value (to 1 µs) in its cell, with its binomial
standard error.

usage: python3 benches/exact_densities.py LAWDIR DATASET_DIR   (LAWDIR: exact-law's or predict's --out)
(pinned: polars==2.1.0, numpy==2.4.6)
"""
import sys

import numpy as np
import polars as pl

law, data = sys.argv[1], sys.argv[2].rstrip("/")
dens = pl.read_parquet(f"{law}/densities.parquet")
df = pl.scan_parquet(f"{data}/**/part-*.parquet").select("stick_start", "slip_start", "slip_duration").collect()
n = df.height
print(f"{n} realizations\n")
print("| variable | k | ∫ exact | L1 distance | beyond 1.96 | largest abs z |\n|---|---:|---:|---:|---:|---:|")
total, beyond, largest, masses = 0, 0, 0.0, []
# predict's densities (--densities of `predict --out DIR`) are T_1 and H_1 of a dataset simulated
# from the same point (initial_conditions.position = [x, x], velocity = [v, v], the belt's sign)
ALIAS = {"time_to_stick": "T", "slip_duration": "H"}
dens = dens.with_columns(pl.col("variable").replace(ALIAS))
for (v, k), rows in sorted(dens.group_by("variable", "index"), key=lambda g: ({"T": 0, "L": 1, "H": 2}[g[0][0]], g[0][1])):
    rows = rows.sort("t_lo")
    lo, hi, e = rows["t_lo"].to_numpy(), rows["t_hi"].to_numpy(), rows["error"].to_numpy()
    # a cell's probability over its width: the density's average plus its point masses (H_k of a
    # scene whose breakaway slip sticks again without a flip)
    point = rows["point_mass"].to_numpy() if "point_mass" in rows.columns else 0.0
    f = rows["density"].to_numpy() + point / (hi - lo)
    if v == "T":
        x = df.select(pl.col("stick_start").list.get(k - 1, null_on_oob=True))
    elif v == "L":
        x = df.select(pl.col("slip_start").list.get(k - 1, null_on_oob=True))
    else:
        # a slip that ends before t_a: stick k + 1 started
        x = df.select(pl.when(pl.col("stick_start").list.len() > k).then(pl.col("slip_duration").list.get(k - 1, null_on_oob=True)))
    x = x.to_series().drop_nulls().to_numpy()
    edges = np.concatenate([lo, hi[-1:]])
    counts, _ = np.histogram(x, bins=edges)
    width = np.diff(edges)
    p = counts / n
    mc = p / width
    se = np.sqrt(np.maximum(p, 1 / n) * (1 - p) / n) / width
    z = (f - mc) / np.sqrt(se**2 + e**2)
    integral = float(np.sum(f * width))
    l1 = float(np.sum(np.abs(f - mc) * width))
    b = int(np.sum(np.abs(z) > 1.96))
    total, beyond, largest = total + len(z), beyond + b, max(largest, float(np.max(np.abs(z))))
    print(f"| {v} | {k} | {integral:.5f} | {l1:.4f} | {b} of {len(z)} | {np.max(np.abs(z)):.2f} |")
    # a point mass (the slip the belt's flips leave unchanged) against the share of the most
    # frequent value in its cell (rounded to 1 µs)
    for c in np.nonzero(np.atleast_1d(point) > 0)[0] if "point_mass" in rows.columns else []:
        inside = np.round(x[(x >= lo[c]) & (x < hi[c])], 6)
        values, counts_at = np.unique(inside, return_counts=True)
        share = counts_at.max() / n if len(values) else 0.0
        masses.append(f"{v}_{k}: point mass {point[c]:.6f} at {values[counts_at.argmax()] if len(values) else float('nan'):.4f} s, share {share:.6f} ± {np.sqrt(share * (1 - share) / n):.5f}")
print(f"\n{beyond} of {total} cells beyond 1.96; largest |z|: {largest:.2f}")
for m in masses:
    print(m)
