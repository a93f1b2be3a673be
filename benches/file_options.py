"""How the dataset's Parquet layout affects reading it (issue 47, "files that read fast"): rewrite
the part files of a dataset with pyarrow under several writer options, then time, side by side in
rounds (A B C … A B C …), the polars read floor (`analyze_vs.py read`), DuckDB on the same core
tables (`duckdb_same_tables.py`) and `stickslip analyze` on each copy. Usage:

    python3 benches/file_options.py DATASET_DIR WORK_DIR [--bin target/release/stickslip] [--rounds 3]

Every copy holds the same rows and the same footer metadata; only the layout differs. `analyze`
refuses a copy whose layout its reader does not accept, and the table says so. Prints one row per
variant: size on disk, then the median wall time of each command and its ratio to the copy as
written (medians of per-round ratios).
"""
import argparse
import glob
import os
import shutil
import statistics
import subprocess
import sys
import time

import pyarrow.parquet as pq

HERE = os.path.dirname(os.path.abspath(__file__))
FLOAT_LISTS = ["stick_start", "stick_duration", "slip_start", "slip_duration", "stick_entry_position"]


def variants(schema):
    """Writer options per variant: name → keyword arguments of `pq.write_table` (beyond the
    compression, which keeps the original's per-column choice unless a variant says otherwise)."""
    floats = [f"{c}.list.element" for c in FLOAT_LISTS if c in schema.names]
    return {
        "as written": None,
        "data page v2": dict(data_page_version="2.0"),
        "pages 64 KiB": dict(data_page_size=64 << 10),
        "pages 8 MiB": dict(data_page_size=8 << 20),
        "float lists byte-stream-split + zstd": dict(use_byte_stream_split=floats, compression_override={c: "zstd" for c in floats}),
        "row groups of 31,250": dict(row_group_size=31_250),
        "one row group": dict(row_group_size=1 << 30),
    }


def layout(path):
    """The original's codec and dictionary use per column path (pyarrow matches nested columns by
    their path, e.g. `stick_start.list.element`)."""
    rg = pq.ParquetFile(path).metadata.row_group(0)
    codec, dictionary = {}, []
    for i in range(rg.num_columns):
        c = rg.column(i)
        codec[c.path_in_schema] = {"uncompressed": "none"}.get(c.compression.lower(), c.compression.lower())
        if any("DICTIONARY" in e for e in c.encodings):
            dictionary.append(c.path_in_schema)
    return codec, dictionary


def rewrite(src_dir, dst_dir, options):
    os.makedirs(dst_dir)
    for path in sorted(glob.glob(os.path.join(src_dir, "**", "part-*.parquet"), recursive=True)):
        rel = os.path.relpath(path, src_dir)
        dst = os.path.join(dst_dir, rel)
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        if options is None:
            shutil.copyfile(path, dst)
            continue
        f = pq.ParquetFile(path)
        table = f.read()
        rows_per_group = f.metadata.row_group(0).num_rows
        kw = dict(options)
        compression, dictionary = layout(path)
        compression.update(kw.pop("compression_override", {}))
        kw.setdefault("row_group_size", rows_per_group)
        pq.write_table(table, dst, compression=compression, use_dictionary=dictionary, **kw)
    # the dataset's other files (scenario, manifest) as they are
    for path in glob.glob(os.path.join(src_dir, "**", "*"), recursive=True):
        if os.path.isfile(path) and not os.path.basename(path).startswith("part-"):
            dst = os.path.join(dst_dir, os.path.relpath(path, src_dir))
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            shutil.copyfile(path, dst)


def du(path):
    return sum(os.path.getsize(p) for p in glob.glob(os.path.join(path, "**", "*"), recursive=True) if os.path.isfile(p))


def timed(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return time.perf_counter() - t, r.returncode, r.stderr.strip().splitlines()[-1:] if r.returncode else []


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset")
    ap.add_argument("work")
    ap.add_argument("--bin", default="target/release/stickslip")
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()
    first = sorted(glob.glob(os.path.join(a.dataset, "**", "part-*.parquet"), recursive=True))[0]
    plan = variants(pq.ParquetFile(first).schema_arrow)
    dirs = {}
    for i, (name, options) in enumerate(plan.items()):
        d = os.path.join(a.work, f"v{i}")
        if os.path.exists(d):
            shutil.rmtree(d)
        rewrite(a.dataset, d, options)
        dirs[name] = d
    commands = {
        "polars read": lambda d: [sys.executable, os.path.join(HERE, "analyze_vs.py"), "read", d],
        "duckdb tables": lambda d: [sys.executable, os.path.abspath(os.path.join(HERE, "..", "..", "shared", "tools", "duckdb_same_tables.py")), d],
        "analyze": lambda d: [a.bin, "analyze", d, "--out", d + ".analysis", "-q"],
    }
    times = {(v, c): [] for v in dirs for c in commands}
    errors = {}
    for _ in range(a.rounds):
        for c, cmd in commands.items():
            for v, d in dirs.items():
                shutil.rmtree(d + ".analysis", ignore_errors=True)
                t, rc, err = timed(cmd(d))
                if rc:
                    errors[(v, c)] = err[0] if err else f"exit {rc}"
                times[(v, c)].append(t)
    base = "as written"
    print(f"{'variant':40s} {'size MB':>8s} " + " ".join(f"{c:>22s}" for c in commands))
    for v, d in dirs.items():
        cells = []
        for c in commands:
            if (v, c) in errors:
                cells.append(f"{'refused':>22s}")
                continue
            med = statistics.median(times[(v, c)])
            ratio = statistics.median(x / y for x, y in zip(times[(v, c)], times[(base, c)]))
            cells.append(f"{med:8.2f} s ({ratio:5.2f}x)".rjust(22))
        print(f"{v:40s} {du(d) / 1e6:8.0f} " + " ".join(cells))
    for (v, c), e in errors.items():
        print(f"{v} / {c}: {e}")


if __name__ == "__main__":
    main()
