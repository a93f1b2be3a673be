//! Write-behind for the part files: the pages of a file written front to back are handed to the
//! disk as each window fills, so dirty pages do not pile up in the page cache.
//!
//! Without it, a run that writes gigabytes leaves them dirty in the page cache until the kernel's
//! thresholds (`vm.dirty_background_ratio`, `vm.dirty_ratio`) force writeback all at once: the
//! flusher threads and the throttled writer then compete with the solver threads for the cores,
//! and the final `fsync` waits for whatever is left. Measured before this (10^7 paper
//! realizations, 2 cores): 1.19–1.37× ten times the 10^6 run, system time 13 s against 0.5 s.
//!
//! The cure is the classic one for streaming writers on Linux (`sync_file_range(2)`): when a
//! window of [`WINDOW`] bytes has been written, start its writeback (`SYNC_FILE_RANGE_WRITE`,
//! asynchronous) and wait for the window before it, which has had a whole window's time to
//! reach the disk. At most two windows are dirty at once. The written pages stay in the page
//! cache, clean (a following `analyze` still reads them from memory), up to [`KEEP`] bytes of
//! the file; windows past it are dropped from the cache once on the disk
//! (`posix_fadvise(DONTNEED)`), so a long run does not grow the page cache into memory it has
//! not touched yet (13 s of system time at 10^7 on this VM). Elsewhere than on Linux the writer is
//! a plain file.
//!
//! **Errors.** Waiting for a window's writeback consumes the file's pending write-back error
//! (the kernel reports it once, to the first caller that waits): so the wait's error is the
//! write's error, returned from the next `write` — never swallowed, since the `fsync` before the
//! part is renamed into place ([`crate::outdir`]) would no longer see it. A file system without
//! `sync_file_range` (EINVAL, ENOSYS, ESPIPE) turns write-behind off for the file; the advice to
//! drop pages is only advice.

use std::fs::File;
use std::io::Write;

/// Bytes per write-behind window.
const WINDOW: u64 = 32 << 20;

/// Bytes of a part kept in the page cache once written; windows past them are dropped from it.
const KEEP: u64 = 1 << 30;

/// A file written front to back with write-behind (module docs).
pub(crate) struct WriteBehind {
    file: File,
    /// bytes written so far
    written: u64,
    /// bytes whose writeback has been started ([0, started))
    started: u64,
    /// bytes known to be on their way or on the disk ([0, waited))
    waited: u64,
    /// write-behind is on (off after the file system refused it)
    on: bool,
}

impl WriteBehind {
    pub(crate) fn new(file: File) -> WriteBehind {
        WriteBehind { file, written: 0, started: 0, waited: 0, on: cfg!(target_os = "linux") }
    }

    /// Start the writeback of the bytes written since the last window, and wait for the window
    /// before it; the wait's error is the file's write error (module docs).
    fn behind(&mut self) -> std::io::Result<()> {
        #[cfg(target_os = "linux")]
        {
            use std::os::fd::AsRawFd;
            let fd = self.file.as_raw_fd();
            let range = |from: u64, to: u64| (from as libc::off64_t, (to - from) as libc::off64_t);
            let refused = |e: &std::io::Error| matches!(e.raw_os_error(), Some(libc::EINVAL | libc::ENOSYS | libc::ESPIPE));
            let (at, len) = range(self.started, self.written);
            // SAFETY: a system call on a file descriptor this value owns; it reads no memory of ours.
            if unsafe { libc::sync_file_range(fd, at, len, libc::SYNC_FILE_RANGE_WRITE) } != 0 {
                let e = std::io::Error::last_os_error();
                if refused(&e) {
                    self.on = false;
                    return Ok(());
                }
                return Err(e);
            }
            if self.waited < self.started {
                let (at, len) = range(self.waited, self.started);
                let flags = libc::SYNC_FILE_RANGE_WAIT_BEFORE | libc::SYNC_FILE_RANGE_WRITE | libc::SYNC_FILE_RANGE_WAIT_AFTER;
                // SAFETY: as above
                if unsafe { libc::sync_file_range(fd, at, len, flags) } != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                // the part of the window past the first KEEP bytes leaves the cache
                let from = self.waited.max(KEEP);
                if from < self.started {
                    let (at, len) = range(from, self.started);
                    // SAFETY: as above; advice only, its result does not matter
                    unsafe { libc::posix_fadvise64(fd, at, len, libc::POSIX_FADV_DONTNEED) };
                }
            }
        }
        self.waited = self.started;
        self.started = self.written;
        Ok(())
    }
}

impl Write for WriteBehind {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.written += n as u64;
        if self.on && self.written - self.started >= WINDOW {
            self.behind()?;
        }
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    /// What goes through the writer is what the file holds, across several windows and a
    /// partial last one.
    #[test]
    fn bytes_pass_through_unchanged() {
        let dir = std::env::temp_dir().join(format!("stickslip-writeback-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("f");
        let bytes: Vec<u8> = (0..(2 * WINDOW + 12_345)).map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8).collect();
        let mut w = WriteBehind::new(File::create(&path).unwrap());
        for chunk in bytes.chunks(1 << 20) {
            w.write_all(chunk).unwrap();
        }
        w.flush().unwrap();
        let (started, waited) = (w.started, w.waited);
        drop(w);
        let mut back = Vec::new();
        File::open(&path).unwrap().read_to_end(&mut back).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(back == bytes, "the file differs from what was written");
        // two windows filled: the second's writeback started, the first's waited for
        assert_eq!((started, waited), (2 * WINDOW, WINDOW));
    }
}
