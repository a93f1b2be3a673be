//! The law without sampling: the long-run (stationary) stick-slip quantities computed from the
//! equations of the process, with no Monte Carlo noise and an error estimate from refinement.
//!
//! **The process.** Between belt flips the oscillator moves deterministically in closed form;
//! flips come at the exponential times of a Poisson process of rate λ. It is a piecewise-
//! deterministic Markov process, and the state just after each flip is a Markov chain: walk the
//! flow for an Exp(λ) time, flip. This module computes that chain's stationary measure ν and
//! reads every long-run quantity off the walks from it (renewal–reward: flips come at rate λ in
//! the long run, so a per-flip mean times λ is a per-second rate).
//!
//! **The frame.** With the belt at s·v0 (s = ±1) write X = s x, V = s ẋ: the belt then always
//! moves at +v0, and a flip is the point reflection (X, V) → (−X, −V) (the symmetric belt and
//! Coulomb friction are odd). With ω² = k/m, a_k = μ_k n/m, a_s = μ_s n/m, c_k = a_k/ω²,
//! c_s = a_s/ω², w0 = v0/ω, in the plane (X, W = V/ω):
//!
//! ```text
//!     slip below belt speed (V < v0):  Ẍ = −ω²(X − c_k)   clockwise circles about (+c_k, 0)
//!     slip above belt speed (V > v0):  Ẍ = −ω²(X + c_k)   clockwise circles about (−c_k, 0)
//!     X = C + r sin φ,  W = r cos φ,  φ̇ = ω
//!     arrival at V = v0: rising at X_a = c_k − √(r² − w0²) (below), falling at −c_k + √(r² − w0²)
//!                         (above); −c_s ≤ X_a < c_s → stick, else it passes belt speed
//!     stick: Ẋ = v0 until X = c_s (breakaway after d(X_e) = (c_s − X_e)/v0)
//! ```
//!
//! A circle below the belt line with r < w0 never reaches belt speed (it slips until a flip);
//! after a breakaway the slip leaves (c_s, v0) on the circle of radius √((c_s − c_k)² + w0²)
//! about c_k — for μ_s = μ_k the grazing circle r = w0, which touches the belt line again after
//! 2π/ω and goes on (a touch is not a stick), for μ_s > μ_k a slip back to a stick at 2c_k − c_s:
//! either way the same periodic continuation for every breakaway, summed once in closed form
//! over its repetitions (`chain::continuation`).
//!
//! **The telegraph belt** (forward at v_f, left at rate λ_f; reverse at −v_r, left at λ_r):
//! the two states are no longer one frame by symmetry. Each has its own frame (the belt at +v_s
//! there, flips at λ_s; the reverse frame reflected, X = −x), and a flip, still the point
//! reflection (X, V) → (−X, −V), carries a state into the other state's frame. The chain's
//! post-flip measure then lives on one mesh per state ([`chain::Chain`]): a step walks state s's
//! measure in its frame and deposits what the flips leave into the other state's. Each state is
//! entered once per cycle of the belt, whose mean length is 1/λ_f + 1/λ_r, so the per-cycle sums
//! of the tallies over both states times ρ = 1/(1/λ_f + 1/λ_r) are rates per second (one state:
//! ρ = λ), and each state's measure is renormalised to 1.
//!
//! **The dashpot** (c > 0, γ = c/m): the Coulomb slip is the damped linear oscillator
//! Ẍ = σ a_k − ω² X − γ Ẋ about the same centres, a spiral in the plane instead of a circle, in
//! the closed forms of [`crate::physics::damped`] (whose first return to belt speed is bracketed
//! by the velocity's turning points: it cannot be missed). The point reflection still maps the
//! flow onto itself (the dashpot is odd too). While stuck the holding force per unit mass is
//! ω² X + γ v0, so the stick region is shifted by −γ v0/ω²: −c_s − γv0/ω² ≤ X < x_b = c_s − γv0/ω²
//! ([`flow::Frame::hold_lo`], [`flow::Frame::hold_hi`]), and a stick entered at X_e breaks away
//! after (x_b − X_e)/v0. A spiral below belt speed that does not come back to it never will
//! (the energy only falls), so it has no periodic repetition: it is walked, like every slip,
//! until its weight e^{−λt} is negligible. With μ_s = μ_k the breakaway slip leaves at a
//! velocity maximum and never returns to belt speed; with μ_s > μ_k it may stick again, and
//! that cycle repeats as without the dashpot.
//!
//! **The chain.** ν lives on three supports: the line {(−y, −v0) : −c_s ≤ y ≤ c_s} (a flip during
//! a stick at y; nodes every h/4, linear), the images of the breakaway slip's samples (exact
//! points), and a grid of the plane of spacing h (bilinear): the measure of the post-flip
//! state after a flip at time t of a walk is deposited with weight λ e^{−λt} dt. Each atom
//! also carries its slip's age-mass (mass × the time since the slip began), so that the second
//! moment of the slip duration is a renewal–reward too: ∫ age dt over a slip is H²/2. One
//! step walks every atom's flow in closed form (`flow::Frame::walk`); the stationary ν is the
//! fixed point of the steps, iterated with Anderson mixing and renormalised (mass leaving the
//! grid's box is counted and reported).
//!
//! **The quantities**, per unit mass of ν, with the walk's integrals T_stick = E∫e^{−λt}1{stuck},
//! T_slip, A_slip = E∫e^{−λt}·age·1{slip}, N = E Σ_entries e^{−λ t_e}, B = E Σ_breakaways e^{−λ t_b}:
//!
//! ```text
//!     stick fraction = λ T_stick,   sticks per second = λ N,   breakaway fraction = B / N
//!     E[D] = T_stick / N,   E[D²] = Σ e^{−λt_e} (2/λ²)(1 − e^{−λd}(1 + λd)) / N   (D = min(Exp(λ), d))
//!     E[H] = T_slip / N,    E[H²] = 2 A_slip / N,   mean cycle E[D] + E[H] (the slope of E[T_k])
//! ```
//!
//! **Accuracy.** The walks are exact (closed forms; the times of every sample integrated
//! exactly); the discretisation is where ν is held: a post-flip state is moved to the nodes
//! around it (at most h away). Below and above belt speed the flow differs (the friction
//! reverses), so each side has its own rows of nodes, one on the belt line each, and no
//! interpolation crosses the line (with one shared grid the error was first order). The error
//! is then second order in h (paper scene, sticks per second: the change shrinks by 4.5 from
//! n = 20, 40 to 80 and by 3.3 from n = 80, 160 to 320), and `exact-law` extrapolates
//! (Richardson) from the two finest of three nested resolutions, with the change of that
//! extrapolation from the coarser pair as its error.
//!
//! **Where it holds**: Coulomb friction (μ_s ≥ μ_k), any dashpot c ≥ 0, no viscous friction, k > 0,
//! the symmetric or the telegraph belt, every flip rate > 0, fixed parameters. Anything else
//! is refused with the reason.

mod anderson;
pub(crate) mod chain;
pub(crate) mod characteristic;
pub(crate) mod clock;
pub mod counts;
pub mod defs;
pub mod densities;
pub mod density;
pub(crate) mod flow;
pub(crate) mod kept;
pub(crate) mod passage;
pub(crate) mod richardson;
mod run;
pub(crate) mod stationary;
pub mod sticks;
pub mod tables;
pub(crate) mod window;

pub use richardson::LEVELS;
pub(crate) use richardson::{guarded, Order};
pub use run::{plan, solve, LawError, Options, Plan, Solved, SCENARIO_FILE};
pub use stationary::{cost_note, estimates, stationary, Level, Rung, QUANTITIES};
pub(crate) use stationary::{frames, ladder};
