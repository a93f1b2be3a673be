"""The extension's functions (``stickslip._stickslip``); the package's public API wraps them."""

from typing import Any, Callable, Dict, List, Optional, Tuple

__version__: str

class UsageError(ValueError): ...
class ScenarioError(ValueError): ...
class DatasetError(ValueError): ...
class OutputError(ValueError): ...
class RunError(RuntimeError): ...

Progress = Optional[Callable[..., None]]

class Table:
    """An Arrow table held in Rust memory, exported without a copy (``__arrow_c_stream__``)."""
    @property
    def num_rows(self) -> int: ...
    @property
    def metadata(self) -> Dict[str, str]: ...
    def __arrow_c_stream__(self, requested_schema: Optional[object] = None) -> object: ...
    def __len__(self) -> int: ...

def simulate_table(
    kind: str, value: Optional[str], sets: List[str], realizations: Optional[int] = None, seed: Optional[int] = None, threads: Optional[int] = None, progress: Progress = None
) -> Table: ...
def simulate_to(
    kind: str,
    value: Optional[str],
    sets: List[str],
    out: str,
    realizations: Optional[int] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    target_se: List[str] = ...,
    progress: Progress = None,
) -> List[Tuple[str, int, float, int, Optional[bool]]]: ...
def analyze(
    dataset: str,
    out: Optional[str] = None,
    max_index: Optional[int] = None,
    bins: Optional[int] = None,
    pairs: Optional[List[str]] = None,
    permutations: Optional[int] = None,
    allow_partial: bool = False,
    tails: bool = True,
    tail_times: Optional[List[float]] = None,
    severity: Optional[List[float]] = None,
    progress: Progress = None,
) -> Tuple[List[Tuple[str, List[Tuple[str, Table]], str]], Optional[Table]]: ...
def tradeoff(
    kind: str, value: Optional[str], sets: List[str], out: str, realizations: Optional[int] = None, bias_fraction: Optional[float] = None, progress: Progress = None
) -> List[Tuple[str, Table]]: ...
def sensitivity(
    kind: str, value: Optional[str], sets: List[str], out: str, realizations: Optional[int] = None, seed: Optional[int] = None, progress: Progress = None
) -> List[Tuple[str, Table]]: ...
def exact_law(
    kind: str,
    value: Optional[str],
    sets: List[str],
    out: str,
    resolution: Optional[int] = None,
    tail_times: Optional[List[float]] = None,
    counts: Optional[int] = None,
    densities: Optional[int] = None,
    progress: Progress = None,
) -> List[Tuple[str, Table]]: ...
def predict(
    kind: str,
    value: Optional[str],
    sets: List[str],
    state: Tuple[float, float, float],
    out: Optional[str] = None,
    stuck: bool = False,
    futures: Optional[int] = None,
    horizon: Optional[float] = None,
    resolution: Optional[int] = None,
    seed: Optional[int] = None,
    densities: Optional[int] = None,
    progress: Progress = None,
) -> List[Tuple[str, Table]]: ...
def run_cli(argv: List[str]) -> int: ...
def write_table(table: Table, out: str) -> str: ...
def scenes() -> List[Tuple[str, str]]: ...
