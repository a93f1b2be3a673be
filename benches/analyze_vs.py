"""The yardsticks of `stickslip analyze` (the book's Benchmarks): the Table 1 moments of T_k, L_k,
D_k, H_k (k <= 6) and of S_T, S_L, plus one joint histogram (T_1, T_2 on a 64 x 64 grid), as one
query over a dataset directory, in DuckDB or in polars (lazy, streaming). Usage:

    python3 benches/analyze_vs.py duckdb|polars|read DATASET_DIR

It prints how many values it summarised (a check that the query ran). `read` is the floor of any
analysis in polars that checks every value, as `analyze` does: one lazy polars query that reads
every value of every column (sums of the lists' values, of the strings' lengths, of the scalars)
and computes nothing else, with polars' column-parallel decoding turned on. `analyze` computes much more
(every value validated, the censoring rule, jackknife intervals, modes, all histograms and tests):
these queries are the floor a general-purpose engine sets for the core of the same work.
"""
import sys

engine, root = sys.argv[1], sys.argv[2].rstrip("/")
families = [("T", "stick_start"), ("L", "slip_start"), ("D", "stick_duration"), ("H", "slip_duration")]

if engine == "duckdb":
    import duckdb

    src = f"read_parquet('{root}/**/part-*.parquet')"
    cols = [f"{col}[{k}] AS {v}{k}" for v, col in families for k in range(1, 7)] + ["n_stick AS ST", "n_slip AS SL"]
    names = [f"{v}{k}" for v, _ in families for k in range(1, 7)] + ["ST", "SL"]
    stats = ", ".join(f"count({n}), avg({n}), var_samp({n}), skewness({n}), kurtosis({n})" for n in names)
    con = duckdb.connect()
    moments = con.sql(f"WITH v AS (SELECT {', '.join(cols)} FROM {src}) SELECT {stats} FROM v").fetchall()
    joint = con.sql(
        f"SELECT floor(stick_start[1] * 6.4)::INT AS a, floor(stick_start[2] * 6.4)::INT AS b, count(*) "
        f"FROM {src} WHERE len(stick_start) >= 2 GROUP BY a, b"
    ).fetchall()
    print(sum(moments[0][0::5]), len(joint))
elif engine == "polars":
    import polars as pl

    lf = pl.scan_parquet(f"{root}/**/part-*.parquet")
    series = [pl.col(col).list.get(k, null_on_oob=True).alias(f"{v}{k + 1}") for v, col in families for k in range(6)]
    series += [pl.col("n_stick").cast(pl.Float64).alias("ST"), pl.col("n_slip").cast(pl.Float64).alias("SL")]
    names = [s.meta.output_name() for s in series]
    aggs = [f(pl.col(n)).alias(f"{n}_{i}") for n in names for i, f in enumerate([pl.Expr.count, pl.Expr.mean, pl.Expr.var, pl.Expr.skew, pl.Expr.kurtosis])]
    moments = lf.select(series).select(aggs)
    joint = (
        lf.select((pl.col("stick_start").list.get(0, null_on_oob=True) * 6.4).floor().alias("a"), (pl.col("stick_start").list.get(1, null_on_oob=True) * 6.4).floor().alias("b"))
        .drop_nulls()
        .group_by("a", "b")
        .len()
    )
    m, j = pl.collect_all([moments, joint], engine="streaming")
    print(sum(m.row(0)[0::5]), j.height)
elif engine == "read":
    import os

    # polars' knob to decode the columns of a row group on several threads (its default decodes
    # this dataset's wide row groups on one): the floor at its lowest
    os.environ.setdefault("POLARS_PARQUET_DECODE_TARGET_VALUES_PER_THREAD", "131072")
    import polars as pl

    lf = pl.scan_parquet(f"{root}/**/part-*.parquet")
    schema = lf.collect_schema()

    def every_value(c):
        dt = schema[c]
        if isinstance(dt, pl.List):
            values = pl.col(c).list.eval(pl.element().str.len_bytes()) if dt.inner == pl.String else pl.col(c)
            return values.list.sum().cast(pl.Float64).sum().alias(c)
        return pl.col(c).cast(pl.Float64).sum().alias(c)

    print(len(lf.select([every_value(c) for c in schema.names()]).collect(engine="streaming").row(0)))
else:
    sys.exit(f"unknown engine {engine!r}: duckdb, polars or read")
