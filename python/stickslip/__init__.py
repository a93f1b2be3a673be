"""stickslip — stick-slip statistics of a dry-friction oscillator on a randomly reversing belt.

A thin layer over the Rust library (the same code as the ``stickslip`` command line):

- :func:`simulate` runs realizations and returns the dataset as an Arrow table (``polars.from_arrow``,
  ``pyarrow.table`` and pandas take it without a copy), or writes a dataset directory (``out=``);
- :func:`analyze` analyses a dataset directory and returns its tidy tables and summary;
- :func:`tradeoff`, :func:`sensitivity` run those stages into a directory and return their tables;
- :func:`exact_law` computes the long-run law and Table 1 without sampling, :func:`predict` the next
  stick from a given state (exact, and by conditional Monte Carlo futures);
- :func:`scenes` lists the shipped scenarios.

A scenario is a path (a ``str`` or ``os.PathLike``: always a file, ``=`` or ``[`` in its name
included), a dict of sections (``{"belt": {"switch_rate": 1.0}}``) or TOML text wrapped as
:class:`Toml` (``stickslip.Toml("[belt]\\nswitch_rate = 1.0\\n")``).

Units are SI throughout: seconds, metres, kilograms, newtons. Bad input raises ``ValueError`` with
a one-line message naming the argument, key, value or file (the package's own checks of its
arguments, or the command line's message); a failure while running raises ``RuntimeError``;
Ctrl-C during :func:`simulate` raises ``KeyboardInterrupt``.
"""

from __future__ import annotations

import json
import math
import numbers
import operator
import os
import re
import signal
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from . import _stickslip
from ._stickslip import Table

__all__ = ["Table", "Toml", "Analysis", "simulate", "analyze", "tradeoff", "sensitivity", "exact_law", "predict", "scenes", "__version__"]
__version__: str = _stickslip.__version__

_MAX_I64 = 2**63 - 1  # TOML's integers (run.seed, run.realizations) are 64-bit signed
_MAX_U32 = 2**32 - 1  # the CLI's resolutions
_ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")


@dataclass(frozen=True)
class Toml:
    """Scenario TOML text, told apart from a path by its type.

    A ``str`` or ``os.PathLike`` scenario is always a path (sweep cells are named like
    ``hive/mass=1/scene.toml``); TOML text is passed wrapped: ``stickslip.Toml("[belt]\\nswitch_rate = 1.0\\n")``.

    Parameters
    ----------
    text : str
        The scenario as TOML (keys it omits keep the paper's values).
    """

    text: str

    def __post_init__(self) -> None:
        if not isinstance(self.text, str):
            raise ValueError(f"Toml(text): text must be a str of TOML, not {type(self.text).__name__}")


Scenario = Union[str, "os.PathLike[str]", Mapping[str, Any], Toml, None]


def _error_line(err: Optional[str], returncode: int) -> str:
    """The one-line error in a child's stderr: the last line starting with ``stickslip: error:`` or
    clap's ``error:`` (prefix removed); else the last non-empty line that is not clap's ``Usage:``
    / ``For more information`` boilerplate; else a line naming the exit code."""
    # (splitlines also splits at a progress bar's '\r'; colours are dropped)
    lines = [_ANSI.sub("", line).strip() for line in (err or "").splitlines()]
    for line in reversed(lines):
        for prefix in ("stickslip: error:", "error:"):
            if line.startswith(prefix) and line[len(prefix):].strip():
                return line[len(prefix):].strip()
    for line in reversed(lines):
        if line and not line.startswith(("For more information", "Usage:")):
            return line
    return f"stickslip exited with code {returncode}" + (" (its message is above)" if err is None else "")


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
    raise (ValueError if child.returncode == 2 else RuntimeError)(_error_line(err, child.returncode))


def _is_bool(v: Any) -> bool:
    """A Python or numpy boolean (``numpy.bool_``; named ``bool`` from numpy 2)."""
    return isinstance(v, bool) or (type(v).__module__ == "numpy" and type(v).__name__ in ("bool_", "bool"))


def _integer(name: str, value: Any, low: int = 1, high: int = _MAX_I64) -> int:
    """``value`` as an int in [low, high] (a numpy integer too; not a bool or a float), else a
    ``ValueError`` naming ``name`` and the value."""
    n: Any = value
    if not _is_bool(value):
        try:
            n = operator.index(value)
        except TypeError:
            pass
    if not isinstance(n, int) or isinstance(n, bool) or not low <= n <= high:
        raise ValueError(f"{name} = {n!r}: must be an integer between {low} and {high}")
    return n


def _optional_integer(name: str, value: Any, low: int = 1, high: int = _MAX_I64) -> Optional[int]:
    return None if value is None else _integer(name, value, low, high)


def _real(name: str, value: Any) -> float:
    """``value`` as a finite float (any real number, numpy's too; not a bool), else a ``ValueError``."""
    f = float(value) if isinstance(value, numbers.Real) and not _is_bool(value) else None
    if f is None or not math.isfinite(f):
        raise ValueError(f"{name} = {value if f is None else f!r}: must be a finite number")
    return f


def _scenario_args(scenario: Scenario) -> Dict[str, Optional[str]]:
    """The extension's two ways to take a scenario: ``{"path": ...}`` for a str or ``os.PathLike``
    (always a path), ``{"toml_text": ...}`` for :class:`Toml` or a dict of sections (written as TOML)."""
    if scenario is None:
        return {}
    if isinstance(scenario, Toml):
        return {"toml_text": scenario.text}
    if isinstance(scenario, Mapping):
        return {"toml_text": _stickslip_toml(scenario)}
    if isinstance(scenario, str):
        if "\n" in scenario:
            shown = scenario if len(scenario) <= 60 else scenario[:57] + "..."
            raise ValueError(f"scenario {shown!r}: a str is taken as a path, and this one holds a newline; TOML text must be given as stickslip.Toml(text)")
        return {"path": scenario}
    if isinstance(scenario, os.PathLike):
        return {"path": os.fsdecode(scenario)}
    raise ValueError(f"scenario: a path (str or os.PathLike), a dict of sections or stickslip.Toml(text), not {type(scenario).__name__}")


def _sets(set: Optional[Mapping[str, Any]]) -> List[str]:
    """Dotted keys and values as the CLI's ``--set KEY=VALUE`` arguments (TOML values); every
    error names the key."""
    if set is None:
        return []
    if not isinstance(set, Mapping):
        raise ValueError(f"set: a dict of dotted keys and values, e.g. {{'model.damping': 0.5}}, not {type(set).__name__}")
    out = []
    for key, value in set.items():
        if not isinstance(key, str) or not key or "=" in key:
            raise ValueError(f"set: key {key!r}: must be a dotted scenario key such as 'model.damping'")
        out.append(f"{key}={_toml_literal(value, f'set: {key}')}")
    return out


def _cli_scenario_args(scenario: Scenario, set: Optional[Mapping[str, Any]], tmp: str) -> list:
    """A scenario and overrides as command-line arguments (TOML text goes through a file)."""
    args: list = []
    a = _scenario_args(scenario)
    if "path" in a:
        path = a["path"] or ""
        # (a relative path starting with '-' would be read as an option)
        args.append(os.path.join(".", path) if path.startswith("-") else path)
    elif a:
        p = os.path.join(tmp, "scenario.toml")
        with open(p, "w", encoding="utf-8") as f:
            f.write(a["toml_text"] or "")
        args.append(p)
    for s in _sets(set):
        args += ["--set", s]
    return args


def _toml_literal(v: Any, where: str = "set") -> str:
    """A Python value as a TOML literal: booleans (numpy's too), integers (any ``numbers.Integral``),
    finite floats (any ``numbers.Real``), strings, lists and tuples (and numpy arrays, via
    ``.tolist()``), dicts as inline tables. ``where`` (``"set: model.damping"``) names the key in
    the ``ValueError`` for anything else, NaN and infinities included."""
    if _is_bool(v):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        f = float(v)
        if not math.isfinite(f):
            raise ValueError(f"{where} = {f!r}: must be a finite number")
        return repr(f)
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{k} = {_toml_literal(x, where)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_literal(x, where) for x in v) + "]"
    if callable(getattr(v, "tolist", None)):
        return _toml_literal(v.tolist(), where)
    raise ValueError(f"{where} = {v!r}: not a scenario value (a number, string, boolean, list or dict)")


def _stickslip_toml(d: Mapping[str, Any]) -> str:
    lines = []
    for section, keys in d.items():
        if not isinstance(keys, Mapping):
            raise ValueError(f"scenario: section {section!r} must be a dict of keys")
        lines.append(f"[{section}]")
        lines += [f"{k} = {_toml_literal(v, f'scenario: {section}.{k}')}" for k, v in keys.items()]
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

    Parameters
    ----------
    scenario : str, os.PathLike, dict, Toml or None
        A ``str`` or ``os.PathLike`` is always the path of a TOML file (``=`` or ``[`` in it, as in
        the sweep cells' ``hive/mass=1/scene.toml``, change nothing; a ``str`` holding a newline is
        refused with a hint); a dict is sections of keys (``{"belt": {"switch_rate": 1.0}}``);
        TOML text is given as ``stickslip.Toml(text)``. Keys it omits keep the paper's values
        (m = 1 kg, k = 4 N/m, n = 9.8 N, mu = 0.51, v0 = 1 m/s, lambda = 5 /s, t_a = 10 s, 18,000
        realizations). None: the paper scenario.
    realizations : int, optional
        Overrides ``run.realizations`` (at least 1).
    seed : int, optional
        Overrides ``run.seed`` (0 to 2**63 - 1).
    set : dict, optional
        Dotted keys as the CLI's ``--set`` (``{"model.damping": 0.5}``); values are numbers (numpy's
        too; finite), strings, booleans, lists (numpy arrays too) or dicts. A list is a sweep, which
        only ``out=`` can write.
    threads : int, optional
        Worker threads (default: all cores; the rows do not depend on it).
    out : str or os.PathLike, optional
        Write the dataset directory exactly as ``stickslip simulate --out`` does, and return None.
    progress : bool
        With ``out=``: the CLI's progress bar and summary line on a terminal (into memory nothing
        is shown).

    Returns
    -------
    Table or None
        The dataset (one row per realization; columns as the CLI's Parquet files, provenance in the
        schema metadata) as an Arrow table; None with ``out=``.

    Raises
    ------
    ValueError
        Bad input, named: an argument, a scenario key or value, a file.
    """
    realizations = _optional_integer("realizations", realizations)
    seed = _optional_integer("seed", seed, 0)
    threads = _optional_integer("threads", threads)
    if out is not None:
        with tempfile.TemporaryDirectory() as tmp:
            argv = ["stickslip", *([] if progress else ["--quiet"]), "simulate", *_cli_scenario_args(scenario, set, tmp), f"--out={os.fspath(out)}"]
            argv += [] if realizations is None else [f"--realizations={realizations}"]
            argv += [] if seed is None else [f"--seed={seed}"]
            argv += [] if threads is None else [f"--threads={threads}"]
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
        _run_stage(["stickslip", *quiet, "analyze", _positional(os.fspath(dataset)), f"--out={os.fspath(out)}", *args], progress)
        return Analysis(Path(out))
    with tempfile.TemporaryDirectory() as tmp:
        adir = Path(tmp) / "analysis"
        _run_stage(["stickslip", *quiet, "analyze", _positional(os.fspath(dataset)), f"--out={adir}", *args], progress)
        return Analysis(adir)


def _positional(path: str) -> str:
    """A path as a positional argument (a relative one starting with '-' would be read as an option)."""
    return os.path.join(".", path) if path.startswith("-") else path


def _stage_table(stage: str, table: str, scenario: Scenario, out: Union[str, "os.PathLike[str]"], realizations: int, set: Optional[Mapping[str, Any]], progress: bool) -> Table:
    """Run ``stickslip STAGE`` into ``out`` and read back its table."""
    realizations = _integer("realizations", realizations)
    with tempfile.TemporaryDirectory() as tmp:
        quiet = [] if progress else ["--quiet"]
        _run_stage(["stickslip", *quiet, stage, *_cli_scenario_args(scenario, set, tmp), f"--out={os.fspath(out)}", f"--realizations={realizations}"], progress)
    return _stickslip.read_parquet(os.path.join(os.fspath(out), table))


def tradeoff(
    scenario: Scenario = None, *, out: Union[str, "os.PathLike[str]"], realizations: int = 100, set: Optional[Mapping[str, Any]] = None, progress: bool = False
) -> Table:
    """The speed/accuracy trade (``stickslip tradeoff``) written into ``out``.

    Parameters
    ----------
    scenario, set
        As for :func:`simulate` (a path, a dict, or ``stickslip.Toml(text)``; dotted keys).
    out : str or os.PathLike
        The output directory.
    realizations : int
        Realizations per setting (at least 1).
    progress : bool
        The CLI's progress on a terminal.

    Returns
    -------
    Table
        ``tradeoff.parquet``.
    """
    return _stage_table("tradeoff", "tradeoff.parquet", scenario, out, realizations, set, progress)


def sensitivity(
    scenario: Scenario = None, *, out: Union[str, "os.PathLike[str]"], realizations: int = 1000, set: Optional[Mapping[str, Any]] = None, progress: bool = False
) -> Table:
    """Sobol indices (``stickslip sensitivity``) written into ``out``.

    Parameters
    ----------
    scenario, set
        As for :func:`simulate` (a path, a dict, or ``stickslip.Toml(text)``; dotted keys); some key
        must be random (a distribution).
    out : str or os.PathLike
        The output directory.
    realizations : int
        Pick-freeze samples N (at least 1; the run simulates N·(d+3) realizations for d random keys).
    progress : bool
        The CLI's progress on a terminal.

    Returns
    -------
    Table
        ``sobol.parquet``.
    """
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
    """The law without sampling (``stickslip exact-law``) written into ``out``.

    Parameters
    ----------
    scenario, set
        As for :func:`simulate` (a path, a dict, or ``stickslip.Toml(text)``; dotted keys).
    out : str or os.PathLike
        The output directory.
    resolution : int
        The finest resolution N (8 to 320; the solve runs at N/4, N/2 and N).
    tail_times : sequence of float, optional
        Times t [s] (finite, >= 0) at which P(D_k > t) is also evaluated; default reproduce's.
    counts : int, optional
        A resolution (8 to 320; minutes): also the laws of the counts S_T and S_L.
    densities : int, optional
        A resolution (8 to 320; minutes and gigabytes): also the densities of T_k, L_k, H_k.
    progress : bool
        The CLI's progress on a terminal.

    Returns
    -------
    dict of str to Table
        By name: ``stationary`` (the long run), ``moments`` (Table 1's means and variances of T_k,
        L_k, D_k, H_k; with ``counts`` also S_T, S_L), ``survival`` (the law of D_k: P(D_k > t) and
        its density, on a grid with ``tail_times`` added), ``convergence``, ``density``,
        ``stick_survival``; with ``counts`` also ``counts`` (P(S_T = n), P(S_L = n)); with
        ``densities`` also ``densities`` (averaged over 100 cells of [0, t_a]).
    """
    args = [f"--resolution={_integer('resolution', resolution, 1, _MAX_U32)}"]
    if tail_times is not None:
        times = [tail_times] if isinstance(tail_times, numbers.Real) else list(tail_times)
        if not times:
            raise ValueError("tail_times = []: give at least one time, or None for the default")
        checked = [_real("tail_times", t) for t in times]
        if any(t < 0 for t in checked):
            raise ValueError(f"tail_times = {min(checked)!r}: must be a finite time >= 0 s")
        args.append("--tail-times=" + ",".join(repr(t) for t in checked))
    args += [] if counts is None else [f"--counts={_integer('counts', counts, 1, _MAX_U32)}"]
    args += [] if densities is None else [f"--densities={_integer('densities', densities, 1, _MAX_U32)}"]
    with tempfile.TemporaryDirectory() as tmp:
        quiet = [] if progress else ["--quiet"]
        _run_stage(["stickslip", *quiet, "exact-law", *_cli_scenario_args(scenario, set, tmp), f"--out={os.fspath(out)}", *args], progress)
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
    """The next stick from a state (``stickslip predict``): the mean and variance of the time to
    its start, its duration, the slip after it and whether it ends by breakaway — exact where the
    scene allows, and from conditional Monte Carlo futures.

    Parameters
    ----------
    state : tuple of three float
        (x [m], mass velocity [m/s], belt velocity [m/s]), finite; the belt velocity one of the
        belt's states.
    scenario, set
        As for :func:`simulate` (a path, a dict, or ``stickslip.Toml(text)``; dotted keys).
    stuck : bool
        The mass is stuck now: first the current stick's remaining time.
    futures : int, optional
        Monte Carlo futures (at least 1).
    horizon : float, optional
        The futures' horizon [s] (finite, > 0).
    resolution : int
        The exact method's finest resolution (8 to 320).
    seed : int, optional
        Seed of the futures (0 to 2**63 - 1).

    Returns
    -------
    Table
        ``prediction.parquet`` (``variable``, ``method``, ``mean``, ``variance``, ``error``, ``futures``).
    """
    values = state.tolist() if callable(getattr(state, "tolist", None)) else state  # (a numpy array too)
    values = list(values) if isinstance(values, (list, tuple)) else None
    if values is None or len(values) != 3 or not all(isinstance(s, numbers.Real) and not _is_bool(s) and math.isfinite(s) for s in values):
        raise ValueError(f"state = {state!r}: must be three finite numbers (x [m], mass velocity [m/s], belt velocity [m/s])")
    x, v, belt = (float(s) for s in values)
    args = [f"--state={x!r},{v!r},{belt!r}", f"--resolution={_integer('resolution', resolution, 1, _MAX_U32)}"]
    args += ["--stuck"] if stuck else []
    args += [] if futures is None else [f"--futures={_integer('futures', futures)}"]
    if horizon is not None:
        h = _real("horizon", horizon)
        if h <= 0:
            raise ValueError(f"horizon = {h!r}: must be a positive number of seconds")
        args.append(f"--horizon={h!r}")
    args += [] if seed is None else [f"--seed={_integer('seed', seed, 0)}"]
    with tempfile.TemporaryDirectory() as tmp:
        _run_stage(["stickslip", "--quiet", "predict", *_cli_scenario_args(scenario, set, tmp), *args, f"--out={os.path.join(tmp, 'p')}"])
        return _stickslip.read_parquet(os.path.join(tmp, "p", "prediction.parquet"))


def scenes() -> Dict[str, str]:
    """The shipped scenario files by name (the paper scenario first), as TOML text."""
    return dict(_stickslip.scenes())
