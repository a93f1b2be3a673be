#!/usr/bin/env python3
"""The accurate end of the trade, side by side: stickslip (rk45, dop853) against a compiled DOP853
(numba, `numba_dop853.py`) and scipy's solve_ivp RK45, on the Stribeck scene (pipelines/stribeck.toml:
mu_s = 0.6, mu_k = 0.51, v_s = 0.1, delta = 2), the same realizations, the same event logic, at
matched accuracy, timed in interleaved rounds.

    python3 benches/stribeck_peers.py [--bin target/release/stickslip] [--rounds 3]

Pinned: numba==0.68.1, scipy==1.17.1, numpy==2.4.6, polars==2.1.0.

1. Accuracy: every setting's stick and slip start times on realizations 0..N_ACC (scipy: 0..40)
   against the converged reference stickslip writes (rk45, rtol = atol = 1e-14, max_step = 1e-2, as
   `tradeoff`): the RMS difference over realizations with the same event counts.
2. Cost per realization, CPU seconds (user + system): stickslip the whole process
   (`simulate --threads 1`: one solver thread and the Parquet writer's, N_TIME realizations
   written); numba its compiled loop over the same N_TIME realizations (compilation and input
   loading excluded); scipy its integration of 40. Each round times every setting once, in an
   order shuffled per round (seeded); medians over the rounds.
3. Matched accuracy: for each peer setting (rtol from 1e-3 to 1e-10), stickslip's cost is the
   cheapest of its settings (either solver) at least as accurate on the same realizations (for
   scipy: 0..40); the ratio is taken in each round and its median printed.
"""
import argparse
import importlib.util
import os
import random
import resource
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))

import numpy as np
import polars as pl



def _load(name):
    # by path, whatever the working directory
    spec = importlib.util.spec_from_file_location(name, os.path.join(HERE, name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


nd = _load("numba_dop853")
_scipy = _load("scipy_stribeck")
SCENE, errors, events, realization = _scipy.SCENE, _scipy.errors, _scipy.events, _scipy.realization

TOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
OURS = {"rk45": [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10], "dop853": [1e-3, 1e-5, 1e-7, 1e-9, 1e-10, 1e-11, 1e-12]}
N_ACC, N_TIME, N_SCIPY = 200, 5000, 40


def simulate(binary, out, n, sets):
    args = [binary, "simulate", "--out", out, "--realizations", str(n), "--quiet", "--threads", "1", "--set", "output.switch_times=true"]
    for s in SCENE + sets:
        args += ["--set", s]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(args, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def read(out):
    return pl.read_parquet(os.path.join(out, "*.parquet")).sort("realization")


def ours_sets(solver, tol):
    return [f'run.solver="{solver}"', f"numerics.rtol={tol}", f"numerics.atol={tol}", "numerics.max_step=10"]


def numba_inputs(df):
    sw = df["switch_times"].to_list()
    off = np.zeros(len(sw) + 1, np.int64)
    off[1:] = np.cumsum([len(s) for s in sw])
    flat = np.array([t for s in sw for t in s], dtype=np.float64)
    return (df["x0"].to_numpy().astype(np.float64), df["xdot0"].to_numpy().astype(np.float64),
            df["initial_sign"].to_numpy().astype(np.float64), flat, off)


def numba_run(inp, n, tol):
    x0, xd0, s0, flat, off = inp
    sticks, slips = np.zeros((n, 512)), np.zeros((n, 512))
    counts = np.zeros((n, 2), np.int64)
    start = time.process_time()
    nd.run(x0[:n], xd0[:n], s0[:n], flat, off[: n + 1], tol, sticks, slips, counts)
    elapsed = time.process_time() - start
    return elapsed, [(list(sticks[r, : counts[r, 0]]), list(slips[r, : counts[r, 1]])) for r in range(n)]


def scipy_run(df, tol):
    start = time.process_time()
    out = [realization(r["x0"], r["xdot0"], float(r["initial_sign"]), r["switch_times"], tol) for r in df.head(N_SCIPY).iter_rows(named=True)]
    return time.process_time() - start, out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="target/release/stickslip")
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    simulate(a.bin, os.path.join(tmp, "ref"), N_ACC, ['run.solver="rk45"', "numerics.rtol=1e-14", "numerics.atol=1e-14", "numerics.max_step=1e-2"])
    ref_df = read(os.path.join(tmp, "ref"))
    ref = events(ref_df)
    simulate(a.bin, os.path.join(tmp, "inputs"), N_TIME, ours_sets("rk45", 1e-6))
    inp = numba_inputs(read(os.path.join(tmp, "inputs")))
    numba_run(inp, 2, 1e-6)  # compile

    acc, acc_scipy = {}, {}
    for solver, tols in OURS.items():
        for tol in tols:
            out = os.path.join(tmp, f"{solver}{tol}")
            simulate(a.bin, out, N_ACC, ours_sets(solver, tol))
            ev = events(read(out))
            acc[("stickslip " + solver, tol)] = errors(ref, ev)
            acc_scipy[("stickslip " + solver, tol)] = errors(ref[:N_SCIPY], ev[:N_SCIPY])
    for tol in TOLS:
        acc[("numba DOP853", tol)] = errors(ref, numba_run(inp, N_ACC, tol)[1])
        acc[("scipy RK45", tol)] = errors(ref[:N_SCIPY], scipy_run(ref_df, tol)[1])

    cost = {k: [] for k in acc}
    for r in range(a.rounds):
        jobs = list(acc)
        random.Random(r).shuffle(jobs)
        for name, tol in jobs:
            if name.startswith("stickslip"):
                out = os.path.join(tmp, "timed")
                subprocess.run(["rm", "-rf", out], check=True)
                cost[(name, tol)].append(simulate(a.bin, out, N_TIME, ours_sets(name.split()[1], tol)) / N_TIME)
            elif name.startswith("numba"):
                cost[(name, tol)].append(numba_run(inp, N_TIME, tol)[0] / N_TIME)
            else:
                cost[(name, tol)].append(scipy_run(ref_df, tol)[0] / N_SCIPY)

    print(f"Stribeck scene; accuracy on {N_ACC} realizations (scipy {N_SCIPY}) against stickslip rk45 at 1e-14, max_step 1e-2;")
    print(f"CPU per realization, median of {a.rounds} interleaved rounds (stickslip: whole process, one solver thread, {N_TIME} realizations to Parquet)")
    print(f"{'setting':<22} {'rtol':>7} {'RMS error s':>12} {'mismatched':>10} {'on 0..40':>10} {'cost us':>10}")
    for (name, tol), (err, mism) in sorted(acc.items(), key=lambda kv: (kv[0][0], -kv[0][1])):
        e40 = acc_scipy[(name, tol)][0] if (name, tol) in acc_scipy else (err if name.startswith("scipy") else float("nan"))
        print(f"{name:<22} {tol:>7.0e} {err:>12.3e} {mism:>10d} {e40:>10.3e} {1e6 * np.median(cost[(name, tol)]):>10.2f}")
    print()
    print("matched accuracy: the peer's cost over stickslip's cheapest setting at least as accurate (median of per-round ratios)")
    print(f"{'rtol':>7} {'peer':<14} {'peer error':>11} {'stickslip setting':<26} {'ratio':>8}")
    ours = [k for k in acc if k[0].startswith("stickslip")]
    for tol in TOLS:
        for peer in ["numba DOP853", "scipy RK45"]:
            err, mism = acc[(peer, tol)]
            # stickslip's accuracy on the realizations the peer ran
            mine = acc if peer.startswith("numba") else acc_scipy
            good = [k for k in ours if mine[k][0] <= err and mine[k][1] <= mism]
            if not good:
                print(f"{tol:>7.0e} {peer:<14} {err:>11.3e} {'(none as accurate)':<26}")
                continue
            ratios = [max(cost[(peer, tol)][r] / cost[k][r] for k in good) for r in range(a.rounds)]
            best = min(good, key=lambda k: np.median(cost[k]))
            print(f"{tol:>7.0e} {peer:<14} {err:>11.3e} {best[0] + ' ' + format(best[1], '.0e'):<26} {np.median(ratios):>8.1f}")


if __name__ == "__main__":
    main()
