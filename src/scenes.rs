//! The scenario files shipped inside the binary: the paper scenario (the default of every key)
//! and the example scenes, so that a user of an installed `stickslip` (no clone, no
//! `pipelines/`) can list them and write one out to edit (`stickslip scenes`).

use crate::scenario::PAPER_TOML;

/// A shipped scenario file: its name, where it lives in the repository, its text.
#[derive(Debug, Clone, Copy)]
pub struct Shipped {
    pub name: &'static str,
    pub path: &'static str,
    pub text: &'static str,
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
pub const SHIPPED: [Shipped; 9] = [
    Shipped { name: "paper", path: "pipelines/paper.toml", text: PAPER_TOML },
    Shipped { name: "stribeck", path: "pipelines/stribeck.toml", text: include_str!("../pipelines/stribeck.toml") },
    Shipped { name: "damped", path: "pipelines/scenes/damped.toml", text: include_str!("../pipelines/scenes/damped.toml") },
    Shipped { name: "static_friction", path: "pipelines/scenes/static_friction.toml", text: include_str!("../pipelines/scenes/static_friction.toml") },
    Shipped { name: "asymmetric_belt", path: "pipelines/scenes/asymmetric_belt.toml", text: include_str!("../pipelines/scenes/asymmetric_belt.toml") },
    Shipped { name: "uncertain_friction", path: "pipelines/scenes/uncertain_friction.toml", text: include_str!("../pipelines/scenes/uncertain_friction.toml") },
    Shipped { name: "stribeck_damped", path: "pipelines/scenes/stribeck_damped.toml", text: include_str!("../pipelines/scenes/stribeck_damped.toml") },
    Shipped { name: "viscous", path: "pipelines/scenes/viscous.toml", text: include_str!("../pipelines/scenes/viscous.toml") },
    // (the recorded-belt example is not shipped: it needs its log file, pipelines/scenes/rotary_log.csv)
    Shipped { name: "markov_belt", path: "pipelines/scenes/markov_belt.toml", text: include_str!("../pipelines/scenes/markov_belt.toml") },
];

/// The shipped scenario called `name`.
pub fn find(name: &str) -> Option<&'static Shipped> {
    SHIPPED.iter().find(|s| s.name == name)
}
