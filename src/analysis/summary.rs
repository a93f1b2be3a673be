//! `summary.json`, typed: what `analyze` writes and `figures` and `report` read — one struct
//! (serde) on both sides of the stage boundary, so that a renamed or missing field is a
//! compile error or a clear read error, never a silently empty cell. A number that is not
//! finite is written as `null` (`None`).

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

/// The whole file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub stickslip_version: String,
    pub dataset: DatasetSummary,
    pub options: OptionsSummary,
    pub policies: Policies,
    /// S_T, S_L, Q by name
    pub counts: BTreeMap<String, CountSummary>,
    pub growth: Vec<GrowthSummary>,
    pub renewal_check: Option<RenewalSummary>,
    pub independence: Vec<TestSummary>,
}

/// The dataset analysed (its recorded scenario and how complete it is).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DatasetSummary {
    pub files: Vec<String>,
    pub realizations: u64,
    pub seed: u64,
    pub solver: String,
    /// the resolved scenario (TOML), as the parts record it
    pub scenario: String,
    pub complete: bool,
    pub realizations_of_the_run: u64,
    pub missing_ranges: Vec<String>,
}

/// The analysis options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OptionsSummary {
    pub max_index: u32,
    pub bins: Bins,
    pub permutations: u32,
}

/// Histogram bins: Scott's rule, or a fixed number.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Bins {
    /// `"scott"`
    Rule(String),
    Fixed(usize),
}

/// How each statistic is defined, in words.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Policies {
    pub truncated_intervals: String,
    pub moments: String,
    pub intervals: String,
    pub mode: String,
    pub bins: String,
    pub independence: String,
}

/// One count (S_T, S_L, Q) and the paper's values for the paper's scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CountSummary {
    pub n: u64,
    pub mean: Option<f64>,
    pub variance: Option<f64>,
    pub mean_se: Option<f64>,
    pub variance_se: Option<f64>,
    pub mode: Option<f64>,
    pub paper_mean: Option<f64>,
    pub paper_variance: Option<f64>,
}

/// One regression of a statistic of T_k or L_k on k.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GrowthSummary {
    pub variable: String,
    pub statistic: String,
    pub slope: Option<f64>,
    pub intercept: Option<f64>,
    pub r2: Option<f64>,
    pub slope_se: Option<f64>,
    /// the slope's 95 % interval
    pub slope_95: Option<[Option<f64>; 2]>,
}

/// The renewal prediction of the counts from the growth slopes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RenewalSummary {
    #[serde(rename = "predicted_mean_S_T")]
    pub predicted_mean: Option<f64>,
    #[serde(rename = "measured_mean_S_T")]
    pub measured_mean: Option<f64>,
    #[serde(rename = "predicted_variance_S_T")]
    pub predicted_variance: Option<f64>,
    #[serde(rename = "measured_variance_S_T")]
    pub measured_variance: Option<f64>,
    #[serde(rename = "predicted_mean_S_T_95")]
    pub predicted_mean_95: Option<[Option<f64>; 2]>,
    #[serde(rename = "predicted_variance_S_T_95")]
    pub predicted_variance_95: Option<[Option<f64>; 2]>,
    pub formula: String,
}

/// One independence test of a pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TestSummary {
    pub x: String,
    pub y: String,
    pub n: u64,
    /// rows and columns of the merged contingency table
    pub table: [usize; 2],
    pub chi2: Option<f64>,
    pub df: f64,
    pub chi2_p_value: Option<f64>,
    pub g: Option<f64>,
    pub g_p_value: Option<f64>,
    pub mutual_information: Option<f64>,
    pub mi_null_mean: Option<f64>,
    pub mi_p_value: Option<f64>,
    pub permutations: u32,
    pub alpha: f64,
    pub verdict: String,
}

impl Summary {
    /// Read `summary.json` at `path`; the message says what is wrong with it.
    pub fn read(path: &Path) -> Result<Summary, String> {
        let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
        serde_json::from_str(&text).map_err(|e| format!("not a stickslip summary: {e}"))
    }

    /// Only the recorded scenario of the summary at `path` (what `figures` needs; a summary
    /// with just `dataset.scenario` is enough).
    pub fn read_scenario(path: &Path) -> Result<String, String> {
        #[derive(Deserialize)]
        struct Only {
            dataset: Of,
        }
        #[derive(Deserialize)]
        struct Of {
            scenario: String,
        }
        let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
        serde_json::from_str::<Only>(&text).map(|o| o.dataset.scenario).map_err(|e| format!("not a stickslip summary: {e}"))
    }

    /// The file's text.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a summary serializes") + "\n"
    }
}
