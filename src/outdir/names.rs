//! The hidden names the tool gives its temporaries, locks and staging directories beside an
//! output, and the one rule by which stale ones are removed: only names of exactly the tool's
//! form (and, for a directory, holding its staging tag or marker) — never by prefix.

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use super::marker::*;

/// A unique token for temporary names: process id, a per-process counter and the clock's
/// nanoseconds (`PID-N-HEX`, at most 40 bytes).
pub(super) fn unique() -> String {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.subsec_nanos());
    format!("{}-{}-{nanos:x}", std::process::id(), NEXT.fetch_add(1, Ordering::Relaxed))
}

/// Whether `s` is a token [`unique`] makes: decimal, decimal and hexadecimal fields.
fn is_token(s: &str) -> bool {
    let f: Vec<&str> = s.split('-').collect();
    let digits = |x: &str, hex: bool| {
        !x.is_empty() && x.len() <= 20 && x.chars().all(|c| if hex { c.is_ascii_hexdigit() && !c.is_ascii_uppercase() } else { c.is_ascii_digit() })
    };
    f.len() == 3 && digits(f[0], false) && digits(f[1], false) && digits(f[2], true)
}

/// The longest file name the file systems we write to accept (NAME_MAX on Linux and macOS).
const NAME_MAX: usize = 255;

/// The part of our hidden names that stands for an output named `name`: the name itself, or,
/// when a hidden name built on it would exceed [`NAME_MAX`], a prefix of it and a 64-bit
/// FNV-1a hash of the whole name (distinct outputs keep distinct locks).
fn hidden_base(name: &str) -> String {
    // room for ".", "." and the longest suffix: "stickslip-tmp-" + a token
    const ROOM: usize = NAME_MAX - 2 - 14 - 40;
    if name.len() <= ROOM {
        return name.to_string();
    }
    let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3));
    let mut cut = ROOM - 17;
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    format!("{}~{hash:016x}", &name[..cut])
}

/// The hidden name `.BASE.stickslip-SUFFIX` beside the output `name` (within [`NAME_MAX`]).
pub(super) fn hidden(name: &str, suffix: &str) -> String {
    format!(".{}.stickslip-{suffix}", hidden_base(name))
}

/// The file a staging directory holds from its creation until it is committed: with the
/// directory's exact name it proves the directory is ours (see [`remove_stale`]).
pub(super) const STAGING: &str = ".stickslip-staging";

/// Remove what a killed writer of the output `name` left in `dir`: call only while holding
/// `name`'s lock (a live writer would hold it). Only entries the tool can prove it wrote go: a
/// Whether `dir` holds our marker and the marker lists every entry in it.
fn all_listed(dir: &Path) -> bool {
    match (read_marker(dir), files_below(dir)) {
        (Some(marker), Ok(present)) => present.iter().all(|f| marker.files.contains(f)),
        _ => false,
    }
}

/// name of exactly the form `.BASE.stickslip-tmp-TOKEN` or `.BASE.stickslip-old-TOKEN`
/// ([`hidden`], [`unique`]), and, for a directory, holding our staging tag ([`STAGING`]) or our
/// marker. Anything else — a user's `.NAME.old` or `.NAME.tmp-notes` — is left alone.
pub(super) fn remove_stale(dir: &Path, name: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let (tmp, old) = (hidden(name, "tmp-"), hidden(name, "old-"));
    for entry in entries.flatten() {
        let n = entry.file_name().to_string_lossy().into_owned();
        let Some(token) = n.strip_prefix(&tmp).or_else(|| n.strip_prefix(&old)) else { continue };
        if !is_token(token) {
            continue;
        }
        let p = entry.path();
        match entry.file_type() {
            // a staging directory, or a swapped-out output whose marker lists everything in it
            // (a directory of that name holding a marker and files it does not list is not ours)
            Ok(t) if t.is_dir() && (p.join(STAGING).is_file() || all_listed(&p)) => {
                let _ = std::fs::remove_dir_all(&p);
            }
            Ok(t) if t.is_file() => {
                let _ = std::fs::remove_file(&p);
            }
            _ => {}
        }
    }
}
