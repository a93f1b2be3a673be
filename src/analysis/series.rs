//! The analysed quantities and their names: T_k, L_k, D_k, H_k, Y_k, and the counts S_T, S_L, Q.

use std::fmt;
use std::str::FromStr;

/// A family of variables of the paper.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Variable {
    /// T_k, start of the k-th stick
    T,
    /// L_k, start of the k-th slip (counted from the first stick)
    L,
    /// D_k, duration of the k-th stick
    D,
    /// H_k, duration of the k-th slip
    H,
    /// Y_k, k-th belt switch instant
    Y,
    /// S_T, number of sticks
    St,
    /// S_L, number of slips
    Sl,
    /// Q, number of belt switches
    Q,
    /// total time spent stuck in [0, t_a] (Σ D_k, the truncated last stick included)
    StickTime,
}

impl Variable {
    pub const INDEXED: [Variable; 5] = [Variable::T, Variable::L, Variable::D, Variable::H, Variable::Y];
    pub const COUNTS: [Variable; 3] = [Variable::St, Variable::Sl, Variable::Q];

    pub fn name(self) -> &'static str {
        match self {
            Variable::T => "T",
            Variable::L => "L",
            Variable::D => "D",
            Variable::H => "H",
            Variable::Y => "Y",
            Variable::St => "S_T",
            Variable::Sl => "S_L",
            Variable::Q => "Q",
            Variable::StickTime => "stick_time",
        }
    }

    /// The dataset column it is read from.
    pub fn column(self) -> &'static str {
        match self {
            Variable::T => "stick_start",
            Variable::L => "slip_start",
            Variable::D => "stick_duration",
            Variable::H => "slip_duration",
            Variable::Y => "switch_times",
            Variable::St => "n_stick",
            Variable::Sl => "n_slip",
            Variable::Q => "n_switches",
            Variable::StickTime => "stick_duration",
        }
    }

    pub fn is_count(self) -> bool {
        Variable::COUNTS.contains(&self)
    }
}

/// One analysed series: an indexed variable at index k ≥ 1, or a count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Series {
    pub var: Variable,
    pub index: Option<u32>,
}

impl Series {
    pub fn at(var: Variable, k: u32) -> Series {
        Series { var, index: Some(k) }
    }

    pub fn count(var: Variable) -> Series {
        Series { var, index: None }
    }
}

impl fmt::Display for Series {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.index {
            Some(k) => write!(f, "{}_{k}", self.var.name()),
            None => f.write_str(self.var.name()),
        }
    }
}

impl FromStr for Series {
    type Err = String;
    /// `T1`, `T_1`, `D2`, … (indexed variables only).
    fn from_str(s: &str) -> Result<Series, String> {
        let s = s.trim();
        let var = Variable::INDEXED
            .into_iter()
            .find(|v| s.starts_with(v.name()))
            .ok_or_else(|| format!("{s:?}: expected T, L, D, H or Y followed by an index, e.g. D1"))?;
        let k: u32 = s[1..]
            .trim_start_matches('_')
            .parse()
            .ok()
            .filter(|&k| k >= 1)
            .ok_or_else(|| format!("{s:?}: the index must be an integer >= 1"))?;
        Ok(Series::at(var, k))
    }
}

/// A pair of series for a joint histogram, written `A,B` (e.g. `T1,T2`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pair(pub Series, pub Series);

impl FromStr for Pair {
    type Err = String;
    fn from_str(s: &str) -> Result<Pair, String> {
        let (a, b) = s.split_once(',').ok_or_else(|| format!("--pair {s:?}: expected A,B, e.g. D1,D2"))?;
        Ok(Pair(a.parse()?, b.parse()?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        let p: Pair = "T1,T_2".parse().unwrap();
        assert_eq!((p.0.to_string(), p.1.to_string()), ("T_1".into(), "T_2".into()));
        assert!("X1".parse::<Series>().is_err());
        assert!("D0".parse::<Series>().is_err());
    }
}
