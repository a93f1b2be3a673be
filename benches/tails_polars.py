"""The yardstick of `analyze`'s tails (the book's Benchmarks, "The tails"): the same counts as
`src/analysis/tail_counts.rs`, written as one Python polars query over a dataset directory — the
stick and slip durations exploded with their index k and censoring flag, counted per
(k, time cell, flag) on the fine cells ρ = t_a 2^-16 split at the tail times (groups pooled)
and per (jackknife group, k, coarse cell, flag) on cells 32ρ wide; the stick entries counted
per (group, k, holding-time cell, belt state); per group the realizations, sticks and the
exceedances of the longest stick and the severity. Usage:

    python3 benches/tails_polars.py DATASET_DIR [--times 0.5,1,1.5,2,2.4] [--check ANALYSIS_DIR]

It prints the rows each count table has and the query's wall time. With --check it also takes
the pooled Kaplan–Meier curves P(D > t), P(H > t) at the tail times from its own counts and
compares them with `analyze --tail-times …`'s survival.parquet in ANALYSIS_DIR (an independent
computation of the same estimate: it exits 1 if one differs by more than 1e-12).

Time it as a whole process (`/usr/bin/time`, runs interleaved) beside `stickslip analyze DIR` and `stickslip analyze DIR --no-tails`: the
difference of those two is the tails' cost in stickslip, this script the same work in polars'
own Python front end.
"""
import glob
import sys
import time
import tomllib

import numpy as np
import polars as pl
import pyarrow.parquet as pq

args = sys.argv[1:]
root = args[0].rstrip("/")
times = [0.5, 1.0, 1.5, 2.0, 2.4]
check = None
for flag, value in zip(args[1::2], args[2::2]):
    if flag == "--times":
        times = sorted({float(t) for t in value.split(",")})
    elif flag == "--check":
        check = value
    else:
        sys.exit(f"unknown option {flag}")

files = sorted(glob.glob(f"{root}/**/part-*.parquet", recursive=True))
if not files:
    sys.exit(f"no part files under {root}")
scenario = tomllib.loads(pq.read_metadata(files[0]).metadata[b"stickslip.scenario"].decode())
t_a = scenario["run"]["duration"]
model = scenario["model"]
# the breakaway position of the paper's scene (no dashpot, μ_s = μ_k): c_s = μ N / k
x_b = model["friction_coefficient"] * model["normal_force"] / model["stiffness"]
GROUPS, K, COARSE = 20, 8, 32  # k ≤ 6 per index, 7 = every later index (the pooled curve)
rho = t_a / 65536.0

lf = pl.scan_parquet(files)


def cell(x, width):
    """φ(d) = ⌊d/width⌋ + #{τ ≤ d}: every tail time is a cell edge."""
    u = (x / width).cast(pl.Int64)
    for t in times:
        u = u + (x >= t).cast(pl.Int64)
    return u


def plans(stick):
    lst, n = ("stick_duration", "n_stick") if stick else ("slip_duration", "n_slip")
    # the one censoring rule: the last interval, cut at t_a, is a final stick when S_T > S_L and
    # a final slip when S_T = S_L
    cut = pl.col("last_truncated") & ((pl.col("n_stick") > pl.col("n_slip")) if stick else (pl.col("n_stick") == pl.col("n_slip")))
    entries = ["stick_entry_position", "stick_entry_velocity"] if stick else []
    base = lf.select(
        (pl.col("realization") % GROUPS).alias("g"), cut.alias("cut"), pl.col(n), pl.col(lst), *entries,
        pl.int_ranges(1, pl.col(lst).list.len() + 1).alias("k"),
    ).explode([lst, "k", *entries])
    base = base.select(
        "g", pl.col(lst).alias("d"), pl.col("k").clip(0, K - 1),
        (pl.col("cut") & (pl.col("k") == pl.col(n))).cast(pl.Int64).alias("f"), *entries,
    )
    fine = (cell(pl.col("d"), rho) * K + pl.col("k")) * 2 + pl.col("f")
    coarse = ((cell(pl.col("d"), rho * COARSE) * K + pl.col("k")) * 2 + pl.col("f")) * GROUPS + pl.col("g")
    out = [base.select(fine.alias("key")).group_by("key").len(), base.select(coarse.alias("key")).group_by("key").len()]
    if stick:
        x, v = pl.col("stick_entry_position"), pl.col("stick_entry_velocity")
        hold = (x_b - x * v.sign()) / v.abs()
        out.append(base.select((((cell(hold, hold_width) * K + pl.col("k")) * 2 + (v > 0).cast(pl.Int64)) * GROUPS + pl.col("g")).alias("key")).group_by("key").len())
    return out


extremes = lf.select((pl.col("realization") % GROUPS).alias("g"), "n_stick", "longest_stick", "severity").group_by("g").agg(
    pl.len(), pl.col("n_stick").sum(), *[(pl.col("longest_stick") > t).sum().alias(f"l{i}") for i, t in enumerate(times)], (pl.col("severity") > 1.0).sum().alias("s")
)
# the entries are binned on the D curve's 200 evaluation points up to the longest stick (as
# analyze does, after the same first query)
start = time.perf_counter()
hold_width = lf.select(pl.col("longest_stick").max()).collect(engine="streaming").item() / 200.0
queries = plans(True) + plans(False) + [extremes]
frames = pl.collect_all(queries, engine="streaming")
elapsed = time.perf_counter() - start
print("rows per count table:", [f.height for f in frames], f"in {elapsed:.2f} s")

if check:
    survival = pl.read_parquet(f"{check}/survival.parquet").filter(pl.col("index").is_null() & (pl.col("method") == "kaplan_meier"))
    worst = 0.0
    for name, fine in (("D", frames[0]), ("H", frames[3])):
        key = fine["key"].to_numpy()
        n = fine["len"].to_numpy().astype(np.float64)
        flag, c = key % 2, key // 2 // K
        cells = np.unique(c)
        events = np.bincount(np.searchsorted(cells, c[flag == 0]), weights=n[flag == 0], minlength=len(cells))
        every = np.bincount(np.searchsorted(cells, c), weights=n, minlength=len(cells))
        at_risk = every[::-1].cumsum()[::-1]  # intervals in this cell or later
        factor = 1.0 - events / at_risk
        for j, t in enumerate(times):
            edge = int(t / rho) + j + 1  # φ(τ_j): the cells below it hold exactly the durations < τ_j
            km = float(np.prod(factor[cells < edge]))
            row = survival.filter((pl.col("variable") == name) & ((pl.col("t") - t).abs() < 1e-12))
            if row.height != 1:
                sys.exit(f"{check}/survival.parquet has no pooled Kaplan-Meier row of {name} at t = {t} (run analyze with --tail-times)")
            ours = row["survival"][0]
            diff = abs(km - ours) / max(km, 1e-300)
            worst = max(worst, diff)
            print(f"P({name} > {t}) = {km:.10e} here, {ours:.10e} from analyze (relative difference {diff:.1e})")
    sys.exit(0 if worst <= 1e-12 else 1)
