"""The paper's Table 1 and Fig. 12 from Python, and a sweep over the belt's switch rate.

    pip install .  (from a clone; then)  python python/examples/paper.py [OUTDIR]
"""
import sys

import matplotlib
import polars as pl
import stickslip

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "data/python"
stickslip.simulate(seed=1, out=f"{out}/dataset")                 # the paper scenario: 18,000 realizations
a = stickslip.analyze(f"{out}/dataset")
table1 = a.moments.filter(pl.col("index").is_between(1, 6) | pl.col("index").is_null())
with pl.Config(tbl_rows=-1):
    print(table1.select("variable", "index", "mean", "variance", "skewness", "kurtosis"))

d = a.histograms.filter(pl.col("variable") == "D")  # Fig. 12: stick durations D_1..D_6
fig, axes = plt.subplots(2, 3, figsize=(12, 6))
for ax, ((k,), h) in zip(axes.flat, d.sort("index").group_by(["index"], maintain_order=True)):
    ax.bar(h["lo"], h["density"], width=h["hi"] - h["lo"], align="edge")
    ax.set_title(f"D_{k}")
fig.savefig(f"{out}/fig12.png")

sweep = pl.concat(                                                  # a sweep over lambda, one frame
    stickslip.simulate(set={"belt.switch_rate": lam}, realizations=2000).with_columns(switch_rate=pl.lit(lam))
    for lam in (1.0, 2.0, 5.0, 10.0)
)
print(sweep.group_by("switch_rate").agg(pl.col("n_stick").mean().alias("mean S_T")).sort("switch_rate"))
