//! The paper scenario's rows, pinned: seed 1, 18,000 realizations, every value of every core
//! column. A redesign of the solvers or of the scene must keep them bit for bit.
//!
//! The pinned hash was taken from the rows that `../shared/tools/paper_fingerprint.py --check`
//! (the fingerprint of the rows before any redesign) accepted on 2026-11-23; this test recomputes
//! it in-process, without Parquet, so it also runs where Python is absent.

use stickslip::scenario::Scenario;

use crate::common::outcomes;

/// FNV-1a, 64 bits.
struct Fnv(u64);

impl Fnv {
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 = (self.0 ^ u64::from(x)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn f64s(&mut self, v: &[f64]) {
        self.bytes(&(v.len() as u64).to_le_bytes());
        for x in v {
            self.bytes(&x.to_bits().to_le_bytes());
        }
    }
}

#[test]
fn paper_rows_are_unchanged() {
    let sc = Scenario::paper();
    assert_eq!((sc.run.seed, sc.run.realizations), (1, 18_000));
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    for (i, o) in outcomes(&sc, sc.run.realizations).iter().enumerate() {
        let r = &o.record;
        h.bytes(&(i as u64).to_le_bytes());
        h.f64s(&[o.x0, o.xdot0]);
        h.bytes(&(o.belt.switch_times.len() as u64).to_le_bytes());
        for list in [&r.stick_start, &r.stick_duration, &r.slip_start, &r.slip_duration] {
            h.f64s(list);
        }
        h.bytes(&[u8::from(r.last_truncated)]);
    }
    assert_eq!(h.0, PAPER_SEED1_18000, "the paper scenario's rows changed: {:#018x}", h.0);
}

const PAPER_SEED1_18000: u64 = 0xb353_0cd4_4ab1_f9fb;
