"""Time whole commands side by side: rounds of A B (C ...) in turn, so that a slower or busier
moment of the machine falls on every command alike. Usage:

    python3 benches/interleaved.py [--rounds N] -- 'COMMAND A' 'COMMAND B' ...

Each command runs through the shell, its output discarded. Printed per command: the median wall
time, CPU time (user + system) and peak RSS of its process tree's largest process; then, for
every pair of commands, the median of their per-round ratios (wall and CPU), #2 / #1 and so on.
"""
import os
import statistics
import subprocess
import sys
import time


def run(command):
    """Wall seconds, CPU seconds and peak RSS (KiB) of one run of `command`."""
    start = time.perf_counter()
    proc = subprocess.Popen(["/bin/sh", "-c", f"exec {command}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"failed (exit {os.waitstatus_to_exitcode(status)}): {command}")
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss


def measure(commands, rounds, before=None):
    """Per command, one (wall, CPU, peak RSS) per round: each round runs every command once, in
    the order given; `before(i)`, if given, runs untimed before command i (e.g. to remove what the
    previous run wrote)."""
    results = [[] for _ in commands]
    for _ in range(rounds):
        for i, command in enumerate(commands):
            if before:
                before(i)
            results[i].append(run(command))
    return results


def medians(rows):
    """Median wall, CPU and peak RSS (KiB) of one command's rounds."""
    return tuple(statistics.median(r[j] for r in rows) for j in range(3))


def ratio(results, j, i):
    """Median of the per-round ratios command j / command i: (wall, CPU); NaN where a divisor was
    0 in every round (a command that used no measurable CPU)."""
    return tuple(statistics.median([a[k] / b[k] for a, b in zip(results[j], results[i]) if b[k]] or [float("nan")]) for k in range(2))


def main(argv):
    rounds = 7
    if argv[:1] == ["--rounds"]:
        rounds, argv = int(argv[1]), argv[2:]
    if argv[:1] == ["--"]:
        argv = argv[1:]
    if len(argv) < 2:
        sys.exit(__doc__)
    results = measure(argv, rounds)
    for n, (command, rows) in enumerate(zip(argv, results), 1):
        wall, cpu, rss = medians(rows)
        print(f"#{n} {wall:7.2f} s wall {cpu:7.2f} CPU-s {rss / 1048576:6.2f} GiB  {command}")
    for i in range(len(argv)):
        for j in range(i + 1, len(argv)):
            walls, cpus = ratio(results, j, i)
            print(f"#{j + 1} / #{i + 1} (median of {rounds} per-round ratios): wall {walls:.3f}, CPU {cpus:.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
