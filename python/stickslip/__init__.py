"""stickslip — stick-slip statistics of a dry-friction oscillator on a randomly reversing belt.

A thin layer over the Rust library (the same code as the ``stickslip`` command line):

- :func:`simulate` runs realizations and returns the dataset as an Arrow table (``polars.from_arrow``,
  ``pyarrow.table`` and pandas take it without a copy), or writes a dataset directory (``out=``);
- :func:`analyze` analyses a dataset directory and returns its tidy tables and summary;
- :func:`tradeoff`, :func:`sensitivity` run those stages into a directory and return their tables;
- :func:`exact_law` computes the long-run law and Table 1 without sampling, :func:`predict` the next
  stick from a given state (exact, and by conditional Monte Carlo futures);
- :func:`scenes` lists the shipped scenarios.

Units are SI throughout: seconds, metres, kilograms, newtons. Bad input raises ``ValueError`` with
the command line's one-line message (naming the key, value or file); a failure while running raises
``RuntimeError``; Ctrl-C during :func:`simulate` raises ``KeyboardInterrupt``.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from . import _stickslip
from ._stickslip import Table

__all__ = ["Table", "Analysis", "simulate", "analyze", "tradeoff", "sensitivity", "exact_law", "predict", "scenes", "__version__"]
__version__: str = _stickslip.__version__

Scenario = Union[str, "os.PathLike[str]", Mapping[str, Any], None]


def _run_stage(argv: list, progress: bool = False) -> None:
    """Run a stage that writes files (``argv[0]`` is the program name) in a child process running
    the command line's own code, so that Ctrl-C ends it cleanly wherever it is: the child removes
    its temporaries (as the CLI does on SIGINT) and ``KeyboardInterrupt`` is raised here. Its
    one-line error becomes ``ValueError`` (exit code 2: the input is to blame) or ``RuntimeError``.
    With ``progress`` the child writes to this terminal (its progress bar, and its error)."""
    child = subprocess.Popen([sys.executable, "-m", "stickslip._cli", *argv[1:]], stderr=None if progress else subprocess.PIPE, text=True)
    try:
        _, err = child.communicate()
    except KeyboardInterrupt:
        child.send_signal(signal.SIGINT)
        child.wait()
        raise
    if child.returncode == 0:
        if err:
            sys.stderr.write(err)
        return
    message = err.strip().splitlines()[-1] if err and err.strip() else f"stickslip exited with code {child.returncode} (its message is above)"
    message = message.removeprefix("stickslip: error: ") if hasattr(message, "removeprefix") else message
    raise (ValueError if child.returncode == 2 else RuntimeError)(message)


def _scenario_args(scenario: Scenario) -> Dict[str, Optional[str]]:
    """The extension's two ways to take a scenario: a path, or TOML text (a dict is written as TOML)."""
    if scenario is None:
        return {}
    if isinstance(scenario, Mapping):
        return {"toml_text": _stickslip_toml(scenario)}
    text = os.fspath(scenario)
    if "\n" in text or "=" in text or "[" in text:
        return {"toml_text": text}
    return {"path": text}


def _sets(set: Optional[Mapping[str, Any]]) -> List[str]:
    """Dotted keys and values as the CLI's ``--set KEY=VALUE`` arguments (TOML values)."""
    return [f"{key}={_toml_literal(value)}" for key, value in (set or {}).items()]


def _cli_scenario_args(scenario: Scenario, set: Optional[Mapping[str, Any]], tmp: str) -> list:
    """A scenario and overrides as command-line arguments (TOML text goes through a file)."""
    args: list = []
    a = _scenario_args(scenario)
    if "path" in a:
        args.append(a["path"])
    elif a:
        p = os.path.join(tmp, "scenario.toml")
        with open(p, "w", encoding="utf-8") as f:
            f.write(a["toml_text"] or "")
        args.append(p)
    for s in _sets(set):
        args += ["--set", s]
    return args


def _toml_literal(v: Any) -> str:
    """A Python value as a TOML literal (numbers, strings, booleans, lists, dicts)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v) if not isinstance(v, float) or v == v else "nan"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{k} = {_toml_literal(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_literal(x) for x in v) + "]"
    raise ValueError(f"set: {v!r} is not a scenario value")


def _stickslip_toml(d: Mapping[str, Any]) -> str:
    lines = []
    for section, keys in d.items():
        if not isinstance(keys, Mapping):
            raise ValueError(f"scenario: section {section!r} must be a dict of keys")
        lines.append(f"[{section}]")
        lines += [f"{k} = {_toml_literal(v)}" for k, v in keys.items()]
    return "\n".join(lines) + "\n"


def simulate(
    scenario: Scenario = None,
    *,
    realizations: Optional[int] = None,
    seed: Optional[int] = None,
    set: Optional[Mapping[str, Any]] = None,
    threads: Optional[int] = None,
    out: Union[str, "os.PathLike[str]", None] = None,
    progress: bool = False,
) -> Optional[Table]:
    """Simulate realizations of a scene.

    ``scenario``: a path to a TOML file, TOML text, or a dict of sections (``{"belt": {"switch_rate": 1.0}}``);
    keys it omits keep the paper's values (m = 1 kg, k = 4 N/m, n = 9.8 N, mu = 0.51, v0 = 1 m/s,
    lambda = 5 /s, t_a = 10 s, 18,000 realizations). ``set``: dotted keys as the CLI's ``--set``
    (``{"model.damping": 0.5}``; a list is a sweep, which only ``out=`` can write). ``realizations``,
    ``seed`` override ``run.realizations`` and ``run.seed``. ``threads``: worker threads (default: all
    cores; the rows do not depend on it).

    Returns the dataset (one row per realization; columns as the CLI's Parquet files, provenance
    in the schema metadata) as an Arrow table, or, with ``out=``, writes the dataset directory
    exactly as ``stickslip simulate --out`` does and returns None (``progress``: the CLI's progress
    bar and summary line on a terminal; into memory nothing is shown).
    """
    if out is not None:
        with tempfile.TemporaryDirectory() as tmp:
            argv = ["stickslip", *([] if progress else ["--quiet"]), "simulate", *_cli_scenario_args(scenario, set, tmp), "--out", os.fspath(out)]
            if realizations is not None:
                argv += ["--realizations", str(realizations)]
            if seed is not None:
                argv += ["--seed", str(seed)]
            if threads is not None:
                argv += ["--threads", str(threads)]
            _run_stage(argv, progress)
        return None
    return _stickslip.simulate_table(
        **_scenario_args(scenario), sets=_sets(set), realizations=realizations, seed=seed, threads=threads
    )


class Analysis:
    """The tables of an analysis (Arrow tables, by name: ``moments``, ``histograms``,
    ``joint_histograms``, ``growth``, ``convergence``, ``independence``, ``survival``, ``tails``, …,
    as the CLI's ``ADIR/*.parquet``) and its summary (``summary.json`` as a dict)."""

    def __init__(self, directory: Path):
        self.directory = directory
        self.tables: Dict[str, Table] = {
            p.stem: _stickslip.read_parquet(str(p)) for p in sorted(directory.glob("*.parquet"))
        }
        with open(directory / "summary.json", encoding="utf-8") as f:
            self.summary: Dict[str, Any] = json.load(f)

    def __getattr__(self, name: str) -> Table:
        tables = self.__dict__.get("tables", {})
        if name in tables:
            return tables[name]
        raise AttributeError(f"no table {name!r}; the tables are {', '.join(tables)}")

    def __repr__(self) -> str:
        return f"stickslip.Analysis({', '.join(self.tables)})"


def analyze(
    dataset: Union[str, "os.PathLike[str]", Table], *, out: Union[str, "os.PathLike[str]", None] = None, args: tuple = (), progress: bool = False
) -> Analysis:
    """Analyse a dataset (``stickslip analyze``): moments with intervals, histograms, joint
    histograms, independence tests, growth regressions, counts, tails. ``dataset``: a dataset
    directory, or a table from :func:`simulate` (written to a temporary dataset first, exactly as
    ``simulate --out`` writes it). ``out``: where the tables go (default: a temporary directory, read
    back and removed). ``args``: further CLI flags, e.g. ``("--max-index", "4")``. ``progress``: show
    the CLI's progress bar on a terminal."""
    if isinstance(dataset, Table):
        with tempfile.TemporaryDirectory() as tmp:
            _stickslip.write_table(dataset, os.path.join(tmp, "dataset"))
            return analyze(os.path.join(tmp, "dataset"), out=out, args=args, progress=progress)
    quiet = [] if progress else ["--quiet"]
    if out is not None:
        _run_stage(["stickslip", *quiet, "analyze", os.fspath(dataset), "--out", os.fspath(out), *args], progress)
        return Analysis(Path(out))
    with tempfile.TemporaryDirectory() as tmp:
        adir = Path(tmp) / "analysis"
        _run_stage(["stickslip", *quiet, "analyze", os.fspath(dataset), "--out", str(adir), *args], progress)
        return Analysis(adir)


def _stage_table(stage: str, table: str, scenario: Scenario, out: Union[str, "os.PathLike[str]"], realizations: int, set: Optional[Mapping[str, Any]], progress: bool) -> Table:
    """Run ``stickslip STAGE`` into ``out`` and read back its table."""
    with tempfile.TemporaryDirectory() as tmp:
        quiet = [] if progress else ["--quiet"]
        _run_stage(["stickslip", *quiet, stage, *_cli_scenario_args(scenario, set, tmp), "--out", os.fspath(out), "--realizations", str(realizations)], progress)
    return _stickslip.read_parquet(os.path.join(os.fspath(out), table))


def tradeoff(
    scenario: Scenario = None, *, out: Union[str, "os.PathLike[str]"], realizations: int = 100, set: Optional[Mapping[str, Any]] = None, progress: bool = False
) -> Table:
    """The speed/accuracy trade (``stickslip tradeoff``) written into ``out``; returns ``tradeoff.parquet``."""
    return _stage_table("tradeoff", "tradeoff.parquet", scenario, out, realizations, set, progress)


def sensitivity(
    scenario: Scenario = None, *, out: Union[str, "os.PathLike[str]"], realizations: int = 1000, set: Optional[Mapping[str, Any]] = None, progress: bool = False
) -> Table:
    """Sobol indices (``stickslip sensitivity``) written into ``out``; returns ``sobol.parquet``."""
    return _stage_table("sensitivity", "sobol.parquet", scenario, out, realizations, set, progress)


def exact_law(
    scenario: Scenario = None,
    *,
    out: Union[str, "os.PathLike[str]"],
    resolution: int = 80,
    tail_times: Optional[Sequence[float]] = None,
    counts: Optional[int] = None,
    densities: Optional[int] = None,
    set: Optional[Mapping[str, Any]] = None,
    progress: bool = False,
) -> Dict[str, Table]:
    """The law without sampling (``stickslip exact-law``) written into ``out``; returns its tables
    by name: ``stationary`` (the long run), ``moments`` (Table 1's means and variances of T_k,
    L_k, D_k, H_k), ``survival`` (the law of D_k: P(D_k > t) and its density, on a grid with
    ``tail_times`` added; default reproduce's), ``convergence``, ``density``, ``stick_survival``;
    with ``counts`` = N (a resolution, 8 to 320; minutes), also ``counts`` (P(S_T = n) and
    P(S_L = n)) and the S_T, S_L rows of ``moments``; with ``densities`` = N (a resolution, 8 to
    320; minutes and gigabytes), also ``densities`` (the densities of T_k, L_k, H_k averaged over
    100 cells of [0, t_a])."""
    times = [] if tail_times is None else ["--tail-times", ",".join(repr(float(t)) for t in tail_times)]
    if counts is not None:
        times += ["--counts", str(int(counts))]
    if densities is not None:
        times += ["--densities", str(int(densities))]
    with tempfile.TemporaryDirectory() as tmp:
        quiet = [] if progress else ["--quiet"]
        _run_stage(
            ["stickslip", *quiet, "exact-law", *_cli_scenario_args(scenario, set, tmp), "--out", os.fspath(out), "--resolution", str(resolution), *times], progress
        )
    return {p.stem: _stickslip.read_parquet(str(p)) for p in sorted(Path(out).glob("*.parquet"))}


def predict(
    state: "tuple[float, float, float]",
    scenario: Scenario = None,
    *,
    stuck: bool = False,
    futures: Optional[int] = None,
    horizon: Optional[float] = None,
    resolution: int = 40,
    seed: Optional[int] = None,
    set: Optional[Mapping[str, Any]] = None,
) -> Table:
    """The next stick from ``state`` = (x [m], mass velocity [m/s], belt velocity [m/s])
    (``stickslip predict``): the mean and variance of the time to its start, its duration, the
    slip after it and whether it ends by breakaway (with ``stuck``: first the current stick's
    remaining time) — exact where the scene allows, and from ``futures`` conditional Monte Carlo
    futures. Returns ``prediction.parquet`` (``variable``, ``method``, ``mean``, ``variance``,
    ``error``, ``futures``)."""
    x, v, belt = (float(s) for s in state)
    with tempfile.TemporaryDirectory() as tmp:
        args = ["stickslip", "--quiet", "predict", *_cli_scenario_args(scenario, set, tmp), f"--state={x!r},{v!r},{belt!r}", "--resolution", str(resolution), "--out", os.path.join(tmp, "p")]
        args += ["--stuck"] if stuck else []
        args += ["--futures", str(futures)] if futures is not None else []
        args += ["--horizon", repr(float(horizon))] if horizon is not None else []
        args += ["--seed", str(seed)] if seed is not None else []
        _run_stage(args)
        return _stickslip.read_parquet(os.path.join(tmp, "p", "prediction.parquet"))


def scenes() -> Dict[str, str]:
    """The shipped scenario files by name (the paper scenario first), as TOML text."""
    return dict(_stickslip.scenes())
