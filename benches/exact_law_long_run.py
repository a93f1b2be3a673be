#!/usr/bin/env python3
"""The long-run law without sampling (`stickslip exact-law`) against a long Monte Carlo run.

For each scene: `exact-law` (its values and error estimates, and its time), then `simulate`
of REALIZATIONS realizations over t_a = HORIZON s. The long-run estimates are ratios of
per-realization sums (realizations are independent), each with a 95 % interval from the delta
method: the time stuck and the sticks begun within [BURN, HORIZON] per second; the durations of
the sticks and slips begun within [BURN, HORIZON − TAIL], all of which end before t_a (dropping the
intervals cut at t_a instead would bias the mean slip duration low by ~2e-4 relative: the cut
ones are the long ones). Prints one Markdown table per scene: the exact
value ± its error, the Monte Carlo estimate and interval, and whether the exact value is inside.

usage: python3 benches/exact_law_long_run.py [BINARY] [--realizations N] [--horizon T] [--burn B]
       [--resolution R] [--seed S] [--keep DIR] [--only SCENE ...]
(pinned: polars==2.1.0 and numpy==2.4.6, which polars' to_numpy needs; the binary defaults to target/release/stickslip)
"""
import argparse, math, os, shutil, subprocess, sys, tempfile, time

import polars as pl

SCENES = {
    "paper": [],
    "mu_s = 0.6": ["--set", "model.static_friction_coefficient=0.6"],
    "damped c = 0.5": ["--set", "model.damping=0.5"],
    "asymmetric belt": ["--set", "belt.reverse_speed=0.5", "--set", "belt.reverse_switch_rate=2"],
}

QUANTITIES = ["stick_fraction", "mean_stick_duration", "mean_slip_duration", "var_stick_duration",
              "var_slip_duration", "sticks_per_second", "breakaway_fraction", "mean_cycle"]


def run(cmd):
    t = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t


TAIL = 30.0  # s: a stick lasts at most 2 c_s / v0; a slip longer than 30 s has probability ~e^{-150}


def long_run(d, burn, horizon):
    """Per-realization sums (streaming), then ratio estimates with delta-method standard errors."""
    lf = pl.scan_parquet(f"{d}/*.parquet")
    last = horizon - TAIL
    inside = (pl.col("stick_start") >= burn) & (pl.col("stick_start") < last)
    sticks = (lf.select("realization", "stick_start", "stick_duration", "stick_end")
              .explode(["stick_start", "stick_duration", "stick_end"]).drop_nulls("stick_start")
              .with_columns(end=(pl.col("stick_start") + pl.col("stick_duration")).clip(upper_bound=horizon))
              .group_by("realization").agg(
                  stuck=(pl.col("end") - pl.col("stick_start").clip(lower_bound=burn)).clip(lower_bound=0).sum(),
                  n=(pl.col("stick_start") >= burn).sum(),
                  done=inside.sum(),
                  cut=(inside & (pl.col("stick_end") == "horizon")).sum(),
                  d1=pl.when(inside).then(pl.col("stick_duration")).otherwise(0).sum(),
                  d2=pl.when(inside).then(pl.col("stick_duration") ** 2).otherwise(0).sum(),
                  b=(inside & (pl.col("stick_end") == "breakaway")).sum()))
    slips = (lf.select("realization", "slip_start", "slip_duration")
             .explode(["slip_start", "slip_duration"]).drop_nulls("slip_start")
             .filter((pl.col("slip_start") >= burn) & (pl.col("slip_start") < last))
             .group_by("realization").agg(m=pl.len(), h1=pl.col("slip_duration").sum(), h2=(pl.col("slip_duration") ** 2).sum(),
                                          cut_slip=(pl.col("slip_start") + pl.col("slip_duration") >= horizon).sum()))
    df = (lf.select("realization").join(sticks, on="realization", how="left").join(slips, on="realization", how="left")
          .fill_null(0).collect(engine="streaming"))
    window = horizon - burn
    if df["cut"].sum() or df["cut_slip"].sum():
        raise SystemExit(f"an interval begun before t_a - {TAIL} s was cut at t_a: raise TAIL")

    def ratio(num, den):
        a, b = df[num].cast(pl.Float64).to_numpy() if isinstance(num, str) else num, df[den].cast(pl.Float64).to_numpy() if isinstance(den, str) else den
        r = a.sum() / b.sum()
        return r, math.sqrt(((a - r * b) ** 2).sum()) / b.sum()

    ones = df["realization"].cast(pl.Float64).to_numpy() * 0 + window
    stick_fraction = ratio(df["stuck"].to_numpy(), ones)
    d, d_se = ratio("d1", "done")
    d2, d2_se = ratio("d2", "done")
    h, h_se = ratio("h1", "m")
    h2, h2_se = ratio("h2", "m")
    return {
        "stick_fraction": stick_fraction,
        "mean_stick_duration": (d, d_se),
        "mean_slip_duration": (h, h_se),
        "var_stick_duration": (d2 - d * d, d2_se + 2 * d * d_se),
        "var_slip_duration": (h2 - h * h, h2_se + 2 * h * h_se),
        "sticks_per_second": ratio(df["n"].to_numpy().astype(float), ones),
        "breakaway_fraction": ratio("b", "done"),
        "mean_cycle": (d + h, d_se + h_se),
    }, df["n"].sum()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary", nargs="?", default="target/release/stickslip")
    ap.add_argument("--realizations", type=int, default=100_000)
    ap.add_argument("--horizon", type=float, default=1000.0)
    ap.add_argument("--burn", type=float, default=50.0)
    ap.add_argument("--resolution", type=int, default=160)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--keep", help="keep the outputs in this directory")
    ap.add_argument("--only", action="append", choices=list(SCENES), help="run only this scene (repeatable; default: all)")
    a = ap.parse_args()
    tmp = a.keep or tempfile.mkdtemp(prefix="exact_law_")
    try:
        for name, sets in SCENES.items():
            if a.only and name not in a.only:
                continue
            tag = name.replace(" ", "").replace("=", "").replace(".", "")
            law_dir, data_dir = os.path.join(tmp, f"law_{tag}"), os.path.join(tmp, f"mc_{tag}")
            t_law = run([a.binary, "exact-law", *sets, "--resolution", str(a.resolution), "--out", law_dir, "-q"])
            law = pl.read_parquet(os.path.join(law_dir, "stationary.parquet"))
            t_mc = run([a.binary, "simulate", *sets, "--set", f"run.duration={a.horizon}", "--set", f"run.realizations={a.realizations}", "--set", f"run.seed={a.seed}", "--out", data_dir, "-q"])
            t = time.perf_counter()
            mc, sticks = long_run(data_dir, a.burn, a.horizon)
            t_read = time.perf_counter() - t
            if not a.keep:
                shutil.rmtree(data_dir)
            print(f"\n### {name}: exact-law --resolution {a.resolution} in {t_law:.1f} s; Monte Carlo {a.realizations} realizations x {a.horizon:g} s, seed {a.seed} "
                  f"(after {a.burn:g} s: {sticks} sticks) simulated in {t_mc:.1f} s, read in {t_read:.1f} s\n")
            print("| quantity | exact | error | Monte Carlo | 95 % interval | inside |\n|---|---:|---:|---:|---|:---:|")
            for q in QUANTITIES:
                row = law.filter(pl.col("quantity") == q)
                v, e = row["value"][0], row["error"][0]
                m, se = mc[q]
                lo, hi = m - 1.96 * se, m + 1.96 * se
                print(f"| {q} | {v:.6f} | {e:.1e} | {m:.6f} | [{lo:.6f}, {hi:.6f}] | {'yes' if lo <= v <= hi else 'NO'} |")
    finally:
        if not a.keep:
            shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
