//! Per-realization random streams.
//!
//! Realization `i` of a run with seed `s` draws from ChaCha8 (rand_chacha, a portable,
//! version-stable algorithm) keyed by `s` (little-endian in the first 8 key bytes) and a purpose
//! `p` (little-endian in the next 8; the rest zero) on stream `i`. Purpose 0 is the initial
//! conditions and the belt (the paper's draws); each random scene key has its own purpose
//! ([`crate::simulation::keys`]). The numbers therefore depend only on `(s, p, i)`: any thread count,
//! chunking or shard split reproduces them bit for bit, and the sub-streams never overlap.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The generator's name as recorded in dataset metadata.
pub const GENERATOR: &str = "ChaCha8Rng(key = seed u64 LE, purpose u64 LE, zero-padded; stream = realization index)";

/// The sub-stream of a chain's initial conditions beyond the contact mass's (which draws from
/// the main stream, so that the belt's draws do not depend on the chain).
pub const CHAIN_INITIAL_PURPOSE: u64 = 1 << 32;

/// The sub-stream of the anchor's velocity path.
pub const ANCHOR_PURPOSE: u64 = (1 << 32) + 1;

/// The main random stream of realization `index` in a run seeded with `seed` (purpose 0).
pub fn realization_rng(seed: u64, index: u64) -> ChaCha8Rng {
    substream(seed, index, 0)
}

/// The sub-stream `purpose` of realization `index`.
pub fn substream(seed: u64, index: u64, purpose: u64) -> ChaCha8Rng {
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    key[8..16].copy_from_slice(&purpose.to_le_bytes());
    let mut rng = ChaCha8Rng::from_seed(key);
    rng.set_stream(index);
    rng
}

/// A uniform draw on [0, 1) with 53 random bits: `(next_u64 >> 11) · 2⁻⁵³`.
pub fn unit_f64<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_differ_and_repeat() {
        let a: Vec<u64> = (0..4).map(|_| 0).scan(realization_rng(1, 0), |r, _| Some(r.next_u64())).collect();
        let b: Vec<u64> = (0..4).map(|_| 0).scan(realization_rng(1, 0), |r, _| Some(r.next_u64())).collect();
        let c: Vec<u64> = (0..4).map(|_| 0).scan(realization_rng(1, 1), |r, _| Some(r.next_u64())).collect();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn unit_interval() {
        let mut r = realization_rng(7, 3);
        for _ in 0..10_000 {
            let u = unit_f64(&mut r);
            assert!((0.0..1.0).contains(&u));
        }
    }
}
