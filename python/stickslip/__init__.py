"""stickslip — stick-slip statistics of a dry-friction oscillator on a randomly reversing belt.

The stages of the Rust library (the same code as the ``stickslip`` command line), run in this
process with the GIL released, their tables returned as ``polars.DataFrame``:

- :func:`simulate` runs realizations and returns the dataset (one row per realization;
  :func:`provenance` gives its recorded scenario), or writes a dataset directory (``out=``);
- :func:`analyze` analyses a dataset and returns its tables and typed summary (:class:`Analysis`);
- :func:`tradeoff`, :func:`sensitivity` measure the solvers and the Sobol indices;
- :func:`exact_law` computes the long-run law and Table 1 without sampling, :func:`predict` the
  next stick from a given state;
- :func:`scenes` lists the shipped scenarios.

A scenario is a path (a ``str`` or ``os.PathLike``: always a file, ``=`` or ``[`` in its name
included), a dict of sections (``{"belt": {"switch_rate": 1.0}}``) or TOML text wrapped as
:class:`Toml`. Units are SI throughout: seconds, metres, kilograms, newtons.

Errors: bad input raises a subclass of ``ValueError`` naming the culprit, with the command line's
one-line message — :class:`UsageError` (an argument), :class:`ScenarioError` (a key, value or
scenario file), :class:`DatasetError` (a dataset or other input file), :class:`OutputError` (the
output directory); a failure while running raises :class:`RunError` (a ``RuntimeError``); Ctrl-C
ends a stage between chunks of work with ``KeyboardInterrupt``, leaving nothing it staged.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import os
import tempfile
import typing
import weakref
from pathlib import Path
from typing import Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple, Union

import polars as pl

from . import _args, _stickslip, _summary
from ._args import Scenario, Toml
from ._progress import Bar
from ._stickslip import DatasetError, OutputError, RunError, ScenarioError, UsageError
from ._summary import Summary

__all__ = [
    "Toml",
    "Analysis",
    "Tables",
    "Summary",
    "Written",
    "UsageError",
    "ScenarioError",
    "DatasetError",
    "OutputError",
    "RunError",
    "simulate",
    "provenance",
    "analyze",
    "tradeoff",
    "sensitivity",
    "exact_law",
    "predict",
    "scenes",
    "__version__",
]
__version__: str = _stickslip.__version__

PathArg = Union[str, "os.PathLike[str]"]

# the Rust table behind each frame `simulate` returned, by the frame's id (dropped with the frame)
_TABLES: Dict[int, Any] = {}


def _frame(table: Any) -> pl.DataFrame:
    """A polars frame over a table of the extension (Arrow C stream), remembered for
    :func:`provenance` and :func:`analyze`."""
    df = pl.DataFrame(table)
    _TABLES[id(df)] = table
    weakref.finalize(df, _TABLES.pop, id(df), None)
    return df


def _progress(show: bool) -> Optional[Bar]:
    return Bar() if show else None


@dataclasses.dataclass(frozen=True)
class Written:
    """A part file :func:`simulate` wrote (one per sweep cell)."""

    #: the part file
    path: Path
    #: realizations written (fewer than asked when ``target_se`` stopped the run)
    realizations: int
    #: wall-clock time [s]
    seconds: float
    #: Σ S_T over the realizations written
    total_sticks: int
    #: with ``target_se``: whether every target was met (else the cap was reached)
    targets_met: Optional[bool]


def simulate(
    scenario: Scenario = None,
    *,
    realizations: Optional[int] = None,
    seed: Optional[int] = None,
    set: Optional[Mapping[str, Any]] = None,
    threads: Optional[int] = None,
    out: Optional[PathArg] = None,
    target_se: Optional[Sequence[str]] = None,
    progress: bool = False,
) -> Union[pl.DataFrame, List[Written]]:
    """Simulate realizations of a scene (``stickslip simulate``).

    Parameters
    ----------
    scenario : str, os.PathLike, dict, Toml or None
        A ``str`` or ``os.PathLike`` is always the path of a TOML file; a dict is sections of keys
        (``{"belt": {"switch_rate": 1.0}}``); TOML text is given as ``stickslip.Toml(text)``. Keys
        it omits keep the paper's values (m = 1 kg, k = 4 N/m, n = 9.8 N, mu = 0.51, v0 = 1 m/s,
        lambda = 5 /s, t_a = 10 s, 18,000 realizations). None: the paper scenario.
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
        Write the dataset directory exactly as ``stickslip simulate --out`` does.
    target_se : sequence of str, optional
        With ``out``: stop once every standard error is reached (``["S_T=0.01"]``, the CLI's
        ``--target-se``); ``realizations`` is the cap.
    progress : bool
        Draw a progress bar on stderr (tqdm's when installed).

    Returns
    -------
    polars.DataFrame or list of Written
        The dataset (one row per realization; the columns of the CLI's Parquet files;
        :func:`provenance` gives its metadata); with ``out``, the part files written.

    Raises
    ------
    UsageError, ScenarioError, OutputError
        Bad input, named: an argument, a scenario key or value, a file, the output directory.

    Examples
    --------
    >>> import stickslip
    >>> df = stickslip.simulate(realizations=100, seed=1)
    >>> df.height
    100
    """
    realizations = _args.optional_integer("realizations", realizations)
    seed = _args.optional_integer("seed", seed, 0)
    threads = _args.optional_integer("threads", threads)
    kind, value = _args.scenario(scenario)
    sets = _args.sets(set)
    if out is None:
        if target_se is not None:
            raise UsageError("target_se: needs out=DIR (the run stops at a chunk boundary of the written dataset)")
        return _frame(_stickslip.simulate_table(kind, value, sets, realizations, seed, threads, _progress(progress)))
    targets = _args.strings("target_se", target_se) or []
    written = _stickslip.simulate_to(kind, value, sets, os.fspath(out), realizations, seed, threads, targets, _progress(progress))
    return [Written(Path(p), n, s, t, met) for p, n, s, t, met in written]


def provenance(df: pl.DataFrame) -> Dict[str, str]:
    """The provenance of a frame :func:`simulate` returned: the ``stickslip.*`` metadata the CLI
    writes into each part file's footer (``stickslip.scenario``: the resolved scenario as TOML,
    ``stickslip.seed``, ``stickslip.schema_version``, …).

    A frame derived from it (filtered, selected) is a new frame and has none: read the dataset's
    footers with ``pyarrow.parquet.read_schema(path).metadata`` for written files.

    Raises
    ------
    DatasetError
        ``df`` is not a frame :func:`simulate` returned.
    """
    table = _TABLES.get(id(df))
    if table is None:
        raise DatasetError("provenance: not a frame stickslip.simulate returned (a frame derived from one is a new frame; keep the original)")
    return dict(table.metadata)


@functools.lru_cache(maxsize=None)
def _fields(tp: Any) -> Tuple[Tuple[str, Any], ...]:
    """A summary dataclass' fields with their evaluated annotations (evaluated once per class)."""
    hints = typing.get_type_hints(tp, vars(_summary))
    return tuple((f.name, hints[f.name]) for f in dataclasses.fields(tp))


def _summary_value(tp: Any, value: Any) -> Any:
    """``value`` (parsed JSON) as the annotation ``tp`` of :mod:`stickslip._summary` says."""
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if value is None:
        return None
    if dataclasses.is_dataclass(tp):
        return tp(**{name: _summary_value(hint, value.get(name)) for name, hint in _fields(tp)})
    if origin is Union:
        inner = [a for a in args if a is not type(None)]
        return _summary_value(inner[0], value) if len(inner) == 1 else value
    if origin in (list, List):
        return [_summary_value(args[0], v) for v in value]
    if origin in (dict, Dict):
        return {k: _summary_value(args[1], v) for k, v in value.items()}
    if origin is tuple:
        return tuple(_summary_value(a, v) for a, v in zip(args, value))
    return value


class Tables(Mapping[str, pl.DataFrame]):
    """Tables by name (``t["moments"]`` or ``t.moments``), as the CLI's ``DIR/NAME.parquet``."""

    def __init__(self, tables: Mapping[str, pl.DataFrame], directory: Optional[Path] = None):
        self.tables: Dict[str, pl.DataFrame] = dict(tables)
        #: where the files were written (None: only in memory)
        self.directory = directory

    def __getitem__(self, name: str) -> pl.DataFrame:
        if name not in self.tables:
            raise KeyError(f"no table {name!r}; the tables are {', '.join(self.tables)}")
        return self.tables[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self.tables)

    def __len__(self) -> int:
        return len(self.tables)

    def __getattr__(self, name: str) -> pl.DataFrame:
        tables = self.__dict__.get("tables", {})
        if name in tables:
            return tables[name]
        raise AttributeError(f"no table {name!r}; the tables are {', '.join(tables)}")

    def __repr__(self) -> str:
        return f"stickslip.{type(self).__name__}({', '.join(self.tables)})"


class Analysis(Tables):
    """An analysis: its tables by name (``moments``, ``histograms``, ``joint_histograms``,
    ``independence``, ``growth``, ``convergence``, ``survival``, ``tails``) as polars frames, its
    typed :class:`Summary` (``summary.json``); for a sweep, the ``sweep`` table and each cell's
    :class:`Analysis` in ``cells`` (by hive path) with no summary of its own."""

    def __init__(self, tables: Mapping[str, pl.DataFrame], summary: Optional[Summary], cells: Mapping[str, "Analysis"], directory: Optional[Path]):
        super().__init__(tables, directory)
        #: the typed ``summary.json`` (None for a sweep's top level)
        self.summary = summary
        #: a sweep's cells by hive path (empty for a plain dataset)
        self.cells: Dict[str, Analysis] = dict(cells)


def analyze(
    dataset: Union[PathArg, pl.DataFrame],
    *,
    out: Optional[PathArg] = None,
    max_index: Optional[int] = None,
    bins: Optional[int] = None,
    pairs: Optional[Sequence[str]] = None,
    permutations: Optional[int] = None,
    allow_partial: bool = False,
    tails: bool = True,
    tail_times: Optional[Sequence[float]] = None,
    severity: Optional[Sequence[float]] = None,
    progress: bool = False,
) -> Analysis:
    """Analyse a dataset (``stickslip analyze``): moments with intervals, histograms, joint
    histograms, independence tests, growth regressions, counts, tails.

    Parameters
    ----------
    dataset : str, os.PathLike or polars.DataFrame
        A dataset directory (a sweep's too), or a frame :func:`simulate` returned (written to a
        temporary dataset first, exactly as ``simulate --out`` writes it).
    out : str or os.PathLike, optional
        Also write the CLI's files there (replaced when complete).
    max_index, bins, pairs, permutations, allow_partial, tails, tail_times, severity
        As the CLI's ``--max-index`` (default 6), ``--bins`` (default: Scott's rule), ``--pair``
        (``["T1,T2"]``), ``--permutations``, ``--allow-partial``, ``--no-tails`` (``tails=False``),
        ``--tail-times``, ``--severity``.
    progress : bool
        Draw a progress bar on stderr.

    Returns
    -------
    Analysis
        The tables as polars frames and the typed summary.

    Raises
    ------
    DatasetError, UsageError, OutputError
        A dataset that cannot be analysed, an option out of range, a refused output directory.

    Examples
    --------
    >>> import stickslip
    >>> a = stickslip.analyze(stickslip.simulate(realizations=500, seed=1))
    >>> a.summary.dataset.realizations
    500
    """
    if isinstance(dataset, pl.DataFrame):
        table = _TABLES.get(id(dataset))
        if table is None:
            raise DatasetError("dataset: a frame stickslip.simulate returned, or a dataset directory (a frame derived from one is a new frame: write it with simulate(out=...))")
        with tempfile.TemporaryDirectory() as tmp:
            _stickslip.write_table(table, os.path.join(tmp, "dataset"))
            return _analyze(os.path.join(tmp, "dataset"), out, max_index, bins, pairs, permutations, allow_partial, tails, tail_times, severity, progress)
    if not isinstance(dataset, (str, os.PathLike)):
        raise UsageError(f"dataset: a dataset directory or a frame stickslip.simulate returned, not {type(dataset).__name__}")
    return _analyze(os.fspath(dataset), out, max_index, bins, pairs, permutations, allow_partial, tails, tail_times, severity, progress)


def _analyze(dataset: str, out: Optional[PathArg], max_index: Any, bins: Any, pairs: Any, permutations: Any, allow_partial: bool, tails: bool, tail_times: Any, severity: Any, progress: bool) -> Analysis:
    cells, sweep = _stickslip.analyze(
        dataset,
        None if out is None else os.fspath(out),
        _args.optional_integer("max_index", max_index, 1, _args.MAX_U32),
        _args.optional_integer("bins", bins),
        _args.strings("pairs", pairs),
        _args.optional_integer("permutations", permutations, 0, _args.MAX_U32),
        bool(allow_partial),
        bool(tails),
        _args.times("tail_times", tail_times),
        _args.times("severity", severity),
        _progress(progress),
    )
    directory = None if out is None else Path(out)
    analyses = {
        path: Analysis({name: pl.DataFrame(t) for name, t in tables}, _summary_value(Summary, json.loads(text)), {}, directory and directory / path)
        for path, tables, text in cells
    }
    if sweep is None:
        return analyses[""]
    return Analysis({"sweep": pl.DataFrame(sweep)}, None, analyses, directory)


def _frames(tables: Sequence[Tuple[str, Any]]) -> Dict[str, pl.DataFrame]:
    """A stage's tables (name, Arrow stream) as polars frames, without a copy."""
    return {name: pl.DataFrame(t) for name, t in tables}


def tradeoff(scenario: Scenario = None, *, out: PathArg, realizations: Optional[int] = None, set: Optional[Mapping[str, Any]] = None, progress: bool = False) -> pl.DataFrame:
    """The speed/accuracy trade of the solvers on the same realizations (``stickslip tradeoff``),
    written into ``out``.

    Parameters
    ----------
    scenario, set
        As for :func:`simulate`.
    out : str or os.PathLike
        The output directory (replaced when complete).
    realizations : int, optional
        Realizations per setting (at least 1; default 100).
    progress : bool
        Notes on stderr.

    Returns
    -------
    polars.DataFrame
        ``tradeoff.parquet``: one row per setting.
    """
    realizations = _args.optional_integer("realizations", realizations)
    tables = _stickslip.tradeoff(*_args.scenario(scenario), _args.sets(set), os.fspath(out), realizations, None, _progress(progress))
    return _frames(tables)["tradeoff"]


def sensitivity(
    scenario: Scenario = None, *, out: PathArg, realizations: Optional[int] = None, seed: Optional[int] = None, set: Optional[Mapping[str, Any]] = None, progress: bool = False
) -> pl.DataFrame:
    """First-order and total Sobol indices with bootstrap intervals (``stickslip sensitivity``),
    written into ``out``.

    Parameters
    ----------
    scenario, set
        As for :func:`simulate`; some key must be random (a distribution).
    out : str or os.PathLike
        The output directory (replaced when complete).
    realizations : int, optional
        Pick-freeze samples N (2 to 10**8; default 2000; the run simulates N·(d+3) realizations
        for d random keys).
    seed : int, optional
        Overrides ``run.seed``.
    progress : bool
        Notes on stderr.

    Returns
    -------
    polars.DataFrame
        ``sobol.parquet``: one row per (output, input).
    """
    realizations = _args.optional_integer("realizations", realizations)
    seed = _args.optional_integer("seed", seed, 0)
    tables = _stickslip.sensitivity(*_args.scenario(scenario), _args.sets(set), os.fspath(out), realizations, seed, _progress(progress))
    return _frames(tables)["sobol"]


def exact_law(
    scenario: Scenario = None,
    *,
    out: PathArg,
    resolution: Optional[int] = None,
    tail_times: Optional[Sequence[float]] = None,
    counts: Optional[int] = None,
    densities: Optional[int] = None,
    set: Optional[Mapping[str, Any]] = None,
    progress: bool = False,
) -> Tables:
    """The law without sampling (``stickslip exact-law``), written into ``out``.

    Parameters
    ----------
    scenario, set
        As for :func:`simulate`.
    out : str or os.PathLike
        The output directory (replaced when complete).
    resolution : int, optional
        The finest resolution N (8 to 320; default 80; the solve runs at N/4, N/2 and N).
    tail_times : sequence of float, optional
        Times t [s] (finite, >= 0) at which P(D_k > t) is also evaluated; default reproduce's.
    counts : int, optional
        A resolution (8 to 320; minutes): also the laws of the counts S_T and S_L.
    densities : int, optional
        A resolution (8 to 320; minutes and gigabytes): also the densities of T_k, L_k, H_k.
    progress : bool
        Each resolution's line, and the live iteration, on stderr.

    Returns
    -------
    Tables
        By name: ``stationary``, ``moments``, ``survival``, ``convergence``, ``density``,
        ``stick_survival``; with ``counts`` also ``counts``; with ``densities`` also
        ``densities`` and ``characteristic``.
    """
    resolution = _args.optional_integer("resolution", resolution, 1, _args.MAX_U32)
    counts = _args.optional_integer("counts", counts, 1, _args.MAX_U32)
    densities = _args.optional_integer("densities", densities, 1, _args.MAX_U32)
    kind, value = _args.scenario(scenario)
    tables = _stickslip.exact_law(kind, value, _args.sets(set), os.fspath(out), resolution, _args.times("tail_times", tail_times), counts, densities, _progress(progress))
    return Tables(_frames(tables), Path(out))


def predict(
    state: Any,
    scenario: Scenario = None,
    *,
    stuck: bool = False,
    futures: Optional[int] = None,
    horizon: Optional[float] = None,
    resolution: Optional[int] = None,
    seed: Optional[int] = None,
    set: Optional[Mapping[str, Any]] = None,
    progress: bool = False,
) -> pl.DataFrame:
    """The next stick from a state (``stickslip predict``): the mean and variance of the time to
    its start, its duration, the slip after it and whether it ends by breakaway — exact where the
    scene allows, and from conditional Monte Carlo futures.

    Parameters
    ----------
    state : tuple of three float
        (x [m], mass velocity [m/s], belt velocity [m/s]), finite; the belt velocity one of the
        belt's states.
    scenario, set
        As for :func:`simulate`.
    stuck : bool
        The mass is stuck now: first the current stick's remaining time.
    futures : int, optional
        Monte Carlo futures (at least 1).
    horizon : float, optional
        The futures' horizon [s] (finite, > 0).
    resolution : int, optional
        The exact method's finest resolution (8 to 320; default 40).
    seed : int, optional
        Seed of the futures (0 to 2**63 - 1).
    progress : bool
        Notes on stderr.

    Returns
    -------
    polars.DataFrame
        ``prediction.parquet`` (``variable``, ``method``, ``mean``, ``variance``, ``error``,
        ``variance_error``, ``futures``).

    Examples
    --------
    >>> import stickslip
    >>> p = stickslip.predict((0.5, 0.0, 1.0), resolution=16)
    >>> sorted(set(p["method"]))
    ['exact']
    """
    x = _args.state(state)
    futures = _args.optional_integer("futures", futures)
    h = None
    if horizon is not None:
        h = _args.real("horizon", horizon)
        if h <= 0:
            raise UsageError(f"horizon = {h!r}: must be a positive number of seconds")
    resolution = _args.optional_integer("resolution", resolution, 1, _args.MAX_U32)
    seed = _args.optional_integer("seed", seed, 0)
    kind, value = _args.scenario(scenario)
    tables = _stickslip.predict(kind, value, _args.sets(set), x, None, bool(stuck), futures, h, resolution, seed, None, _progress(progress))
    return _frames(tables)["prediction"]


def scenes() -> Dict[str, str]:
    """The shipped scenario files by name (the paper scenario first), as TOML text."""
    return dict(_stickslip.scenes())
