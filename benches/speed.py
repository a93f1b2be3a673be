"""The book's speed table (docs/src/benchmarks.md), measured in one interleaved run (rounds of A B C ..., medians, and the
median of the per-round ratios; `benches/interleaved.py`). Usage:

    python3 benches/speed.py --bin target/release/stickslip [--vs OLD_BINARY] [--rounds N]
                             [--large | --simulate-only]

1. `simulate` of 10^6 paper realizations (`--threads` all cores, to Parquet): wall, CPU, peak RSS,
   realizations per second; with `--vs`, the other binary's `simulate` in the same rounds.
2. `analyze` of that dataset with the tails (the default) and with `--no-tails`, beside the
   yardsticks of `benches/analyze_vs.py` (DuckDB and polars-Python: Table 1 moments and one joint
   histogram; `read`: every value read, nothing computed), if duckdb and polars are installed; with
   `--vs`, the other binary's `analyze` too.
3. With `--large` (about 6 minutes and 15 GB of disk): `simulate` of 10^7 realizations against ten
   runs of 10^6 one after the other, and `analyze` of the 10^7 dataset against the 10^6 one (peak
   RSS ratio).
`--simulate-only` stops after section 1 (for a change to the solver or the writer).

Every run writes into a temporary directory; what a command wrote is removed (untimed) before that
command runs again, and the whole directory when the bench ends or is interrupted.
"""
import argparse
import importlib.util
import os
import shlex
import shutil
import signal
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from interleaved import measure, medians, ratio  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
GIB = 1048576  # KiB


def table(title, labels, results, rounds, per=None, lead=1):
    """Print one section: per command its medians (and realizations/s if `per` gives N), then the
    ratio of each of the first `lead` commands to every later one."""
    print(f"\n## {title} ({rounds} rounds, medians)")
    for n, (label, rows) in enumerate(zip(labels, results)):
        wall, cpu, rss = medians(rows)
        rate = f"  {per[n] / wall:10,.0f} realizations/s" if per and per[n] else ""
        print(f"  {label:<44} {wall:7.2f} s wall {cpu:7.2f} CPU-s {rss / GIB:6.2f} GiB{rate}")
    for i in range(lead):
        for j in range(i + 1, len(labels)):
            w, c = ratio(results, i, j)
            print(f"  {labels[i]} / {labels[j]}: wall {w:.3f}, CPU {c:.3f} (median of per-round ratios)")


def clean(*paths):
    for p in paths:
        shutil.rmtree(p, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", required=True, help="the stickslip binary to measure")
    ap.add_argument("--vs", help="another stickslip binary, measured in the same rounds")
    ap.add_argument("--rounds", type=int, default=7, help="rounds of every command (default 7)")
    ap.add_argument("--large", action="store_true", help="also 10^7 realizations (minutes, GBs)")
    ap.add_argument("--simulate-only", action="store_true", help="only section 1 (a change to the solver or the writer)")
    a = ap.parse_args()
    if a.rounds < 1:
        ap.error("--rounds must be at least 1")
    q = shlex.quote
    bins = [("stickslip", q(os.path.abspath(a.bin)))] + ([("--vs binary", q(os.path.abspath(a.vs)))] if a.vs else [])
    tmp = tempfile.mkdtemp(prefix="stickslip-speed-")
    # (a kill runs the `finally` below too: the datasets are GBs)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    try:
        # 1. simulate 10^6
        outs = [os.path.join(tmp, f"sim{i}") for i in range(len(bins))]
        cmds = [f"{b} simulate -q --realizations 1000000 --out {q(o)}" for (_, b), o in zip(bins, outs)]
        res = measure(cmds, a.rounds, before=lambda i: clean(outs[i]))
        table("simulate, 10^6 paper realizations, to Parquet", [f"{n} simulate" for n, _ in bins], res, a.rounds, per=[1e6] * len(bins))
        data = outs[0]
        clean(*outs[1:])
        size = sum(os.path.getsize(os.path.join(r, f)) for r, _, fs in os.walk(data) for f in fs if f.endswith(".parquet"))
        print(f"  dataset: {size / 2**20:,.0f} MiB")
        if a.simulate_only:
            return

        # 2. analyze 10^6 beside the yardsticks
        ana = os.path.join(tmp, "analysis")
        labels, cmds = [], []
        for n, b in bins:
            labels += [f"{n} analyze", f"{n} analyze --no-tails"]
            cmds += [f"{b} analyze {q(data)} -q --out {q(ana)}", f"{b} analyze {q(data)} -q --no-tails --out {q(ana)}"]
        for engine, module in [("duckdb", "duckdb"), ("polars", "polars"), ("read", "polars")]:
            if importlib.util.find_spec(module):
                labels.append(f"analyze_vs.py {engine}")
                cmds.append(f"{q(sys.executable)} {q(os.path.join(HERE, 'analyze_vs.py'))} {engine} {q(data)}")
        res = measure(cmds, a.rounds, before=lambda i: clean(ana))
        table("analyze, the 10^6 dataset", labels, res, a.rounds, lead=len(labels) - 1)

        if a.large:
            b = bins[0][1]
            big = os.path.join(tmp, "big")
            ten = " && ".join(f"{b} simulate -q --realizations 1000000 --out {q(os.path.join(tmp, 'ten', str(i)))}" for i in range(10))
            rounds = min(a.rounds, 3)
            res = measure([f"{b} simulate -q --realizations 10000000 --out {q(big)}", f"sh -c {q(ten)}"], rounds, before=lambda i: clean([big, os.path.join(tmp, "ten")][i]))
            table("simulate, 10^7 realizations against ten runs of 10^6", ["10^7 at once", "ten of 10^6"], res, rounds, per=[1e7, 1e7])
            clean(os.path.join(tmp, "ten"))
            res = measure([f"{b} analyze {q(big)} -q --out {q(ana)}", f"{b} analyze {q(data)} -q --out {q(ana)}"], rounds, before=lambda i: clean(ana))
            table("analyze, 10^7 against 10^6 (the peak RSS ratio is the medians')", ["analyze 10^7", "analyze 10^6"], res, rounds)
            print(f"  peak RSS 10^7 / 10^6: {medians(res[0])[2] / medians(res[1])[2]:.2f}")
    finally:
        clean(tmp)


if __name__ == "__main__":
    main()
