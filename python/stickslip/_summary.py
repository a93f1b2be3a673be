"""The typed summary of an analysis (``summary.json``), generated from the Rust ``Summary``
(``src/analysis/summary.rs``) by ``STICKSLIP_BLESS=1 cargo test --release python_summary``;
do not edit: a test regenerates it and fails when it differs. A number that is not finite
is ``None``."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple, Union


@dataclass(frozen=True)
class Summary:
    """The whole file."""

    stickslip_version: str
    dataset: DatasetSummary
    options: OptionsSummary
    policies: Policies
    #: S_T, S_L, Q by name
    counts: Dict[str, CountSummary]
    growth: List[GrowthSummary]
    renewal_check: Optional[RenewalSummary]
    independence: List[TestSummary]


@dataclass(frozen=True)
class DatasetSummary:
    """The dataset analysed (its recorded scenario and how complete it is)."""

    files: List[str]
    realizations: int
    seed: int
    solver: str
    #: the resolved scenario (TOML), as the parts record it
    scenario: str
    complete: bool
    realizations_of_the_run: int
    missing_ranges: List[str]


@dataclass(frozen=True)
class OptionsSummary:
    """The analysis options."""

    max_index: int
    bins: Bins
    permutations: int


#: Histogram bins: Scott's rule, or a fixed number.
Bins = Union[str, int]


@dataclass(frozen=True)
class Policies:
    """How each statistic is defined, in words."""

    truncated_intervals: str
    moments: str
    intervals: str
    mode: str
    bins: str
    independence: str


@dataclass(frozen=True)
class CountSummary:
    """One count (S_T, S_L, Q) and the paper's values for the paper's scene."""

    n: int
    mean: Optional[float]
    variance: Optional[float]
    mean_se: Optional[float]
    variance_se: Optional[float]
    mode: Optional[float]
    paper_mean: Optional[float]
    paper_variance: Optional[float]


@dataclass(frozen=True)
class GrowthSummary:
    """One regression of a statistic of T_k or L_k on k."""

    variable: str
    statistic: str
    slope: Optional[float]
    intercept: Optional[float]
    r2: Optional[float]
    slope_se: Optional[float]
    #: the slope's 95 % interval
    slope_95: Optional[Tuple[Optional[float], Optional[float]]]


@dataclass(frozen=True)
class RenewalSummary:
    """The renewal prediction of the counts from the growth slopes."""

    predicted_mean_S_T: Optional[float]
    measured_mean_S_T: Optional[float]
    predicted_variance_S_T: Optional[float]
    measured_variance_S_T: Optional[float]
    predicted_mean_S_T_95: Optional[Tuple[Optional[float], Optional[float]]]
    predicted_variance_S_T_95: Optional[Tuple[Optional[float], Optional[float]]]
    formula: str


@dataclass(frozen=True)
class TestSummary:
    """One independence test of a pair."""

    x: str
    y: str
    n: int
    #: rows and columns of the merged contingency table
    table: Tuple[int, int]
    chi2: Optional[float]
    df: float
    chi2_p_value: Optional[float]
    g: Optional[float]
    g_p_value: Optional[float]
    mutual_information: Optional[float]
    mi_null_mean: Optional[float]
    mi_p_value: Optional[float]
    permutations: int
    alpha: float
    verdict: str
