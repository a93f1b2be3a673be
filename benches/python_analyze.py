"""`stickslip.analyze(DATASET)` from Python: the median wall time of the call over ROUNDS calls
in one process (the package imported once, the first call not counted).

    python benches/python_analyze.py DATASET [ROUNDS]

Run it under two installs of the package, alternating (A B A B …), to compare them paired:
the issue's figure is 18,000 paper realizations (`stickslip simulate --seed 1 --out DATASET`).
"""

import statistics
import sys
import time

import stickslip

dataset = sys.argv[1]
rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 7
stickslip.analyze(dataset)
times = []
for _ in range(rounds):
    t = time.perf_counter()
    stickslip.analyze(dataset)
    times.append(time.perf_counter() - t)
print(f"{statistics.median(times):.4f}")
