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
//! cache, clean (a following `analyze` still reads them from memory); only their writeback is
//! earlier. These calls are hints: their errors are ignored, and the `fsync` before the part
//! is renamed into place ([`crate::outdir`]) still reports any I/O error. Elsewhere than on Linux
//! the writer is a plain file.

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
}

impl WriteBehind {
    pub(crate) fn new(file: File) -> WriteBehind {
        WriteBehind { file, written: 0, started: 0, waited: 0 }
    }

    /// Start the writeback of the bytes written since the last window, and wait for the window
    /// before it.
    fn behind(&mut self) {
        #[cfg(target_os = "linux")]
        {
            use std::os::fd::AsRawFd;
            let fd = self.file.as_raw_fd();
            // SAFETY: plain system calls on a file descriptor this value owns, with ranges inside
            // the file; they read no memory of ours.
            unsafe {
                libc::sync_file_range(fd, self.started as i64, (self.written - self.started) as i64, libc::SYNC_FILE_RANGE_WRITE);
                if self.waited < self.started {
                    let flags = libc::SYNC_FILE_RANGE_WAIT_BEFORE | libc::SYNC_FILE_RANGE_WRITE | libc::SYNC_FILE_RANGE_WAIT_AFTER;
                    libc::sync_file_range(fd, self.waited as i64, (self.started - self.waited) as i64, flags);
                    if self.started > KEEP {
                        libc::posix_fadvise(fd, self.waited as i64, (self.started - self.waited) as i64, libc::POSIX_FADV_DONTNEED);
                    }
                }
            }
        }
        self.waited = self.started;
        self.started = self.written;
    }
}

impl Write for WriteBehind {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.written += n as u64;
        if self.written - self.started >= WINDOW {
            self.behind();
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
        // two windows filled: the second's writeback started, the first's waited for
        assert_eq!((w.started, w.waited), (2 * WINDOW, WINDOW));
        drop(w);
        let mut back = Vec::new();
        File::open(&path).unwrap().read_to_end(&mut back).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(back == bytes, "the file differs from what was written");
    }
}
