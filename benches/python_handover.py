"""10^6 paper realizations simulated into memory, then handed to pyarrow or to polars (each in its
own run: `python benches/python_handover.py pyarrow|polars`, with the package installed).
"""
import sys
import time

import polars as pl
import pyarrow as pa

import stickslip

t0 = time.perf_counter()
table = stickslip.simulate(realizations=10**6)
t1 = time.perf_counter()
n = pa.table(table).num_rows if sys.argv[1] == "pyarrow" else pl.DataFrame(table).height
t2 = time.perf_counter()
assert n == 10**6
print(f"simulate into memory {t1 - t0:.2f} s; to {sys.argv[1]} {1e3 * (t2 - t1):.0f} ms")
