//! The scenario files shipped inside the binary: the paper scenario (the default of every key)
//! and the example scenes, so that a user of an installed `stickslip` (no clone, no
//! `pipelines/`) can list them and write one out to edit (`stickslip scenes`).

use crate::scenario::PAPER_TOML;

/// A shipped scenario file: its name and its text.
#[derive(Debug, Clone, Copy)]
pub struct Shipped {
    /// what `stickslip scenes NAME` calls it
    pub name: &'static str,
    /// the file's text, as in `pipelines/`
    pub text: &'static str,
    /// files the scene reads, written beside it: (file name, text)
    pub companions: &'static [(&'static str, &'static str)],
}

/// A scenario file of `pipelines/`, embedded.
macro_rules! shipped {
    ($name:literal, $file:literal) => {
        Shipped { name: $name, text: include_str!(concat!("../pipelines/", $file)), companions: &[] }
    };
}

impl Shipped {
    /// What the scene is: the first sentence of its opening comment.
    pub fn summary(&self) -> String {
        let comment: Vec<&str> = self.text.lines().take_while(|l| l.starts_with('#')).map(|l| l.trim_start_matches('#').trim()).collect();
        let text = comment.join(" ");
        let end = text.find(". ").map_or(text.len(), |i| i + 1);
        text[..end].trim().to_string()
    }
}

/// Every shipped scenario, the paper's first.
pub const SHIPPED: [Shipped; 12] = [
    Shipped { name: "paper", text: PAPER_TOML, companions: &[] },
    shipped!("stribeck", "stribeck.toml"),
    shipped!("damped", "scenes/damped.toml"),
    shipped!("static_friction", "scenes/static_friction.toml"),
    shipped!("asymmetric_belt", "scenes/asymmetric_belt.toml"),
    shipped!("uncertain_friction", "scenes/uncertain_friction.toml"),
    shipped!("stribeck_damped", "scenes/stribeck_damped.toml"),
    shipped!("viscous", "scenes/viscous.toml"),
    shipped!("markov_belt", "scenes/markov_belt.toml"),
    shipped!("chain_paper", "scenes/chain_paper.toml"),
    shipped!("drillstring", "scenes/drillstring.toml"),
    // (its velocity log is written beside it: `belt.file` is relative to the scenario's directory)
    Shipped {
        name: "recorded_belt",
        text: include_str!("../pipelines/scenes/recorded_belt.toml"),
        companions: &[("rotary_log.csv", include_str!("../pipelines/scenes/rotary_log.csv"))],
    },
];

/// The shipped scenario called `name`.
pub fn find(name: &str) -> Option<&'static Shipped> {
    SHIPPED.iter().find(|s| s.name == name)
}
