//! A lock on a file a run will replace, taken before the run reads it and
//! held until the new file is in place (the lock's owner drops it then).
//! A second run on the same file finds it locked and is refused, never
//! waits: two runs each locking several files in other orders could wait
//! on each other for ever. The lock is the system's advisory file lock
//! (`flock`), on the file's inode: a run that finds the path naming
//! another inode once it holds the lock (the first run renamed its new
//! file over it in between) takes the lock on the new one.

use crate::error::{Error, ErrorKind, Result};
use std::path::Path;

/// A file locked for this run (unlocked when dropped).
#[derive(Debug)]
pub struct Lock(#[allow(dead_code)] std::fs::File);

/// How often a path that keeps naming another inode is tried.
const TRIES: usize = 100;

impl Lock {
    /// The lock on the existing regular file `path`.
    pub fn take(path: &Path) -> Result<Lock> {
        for _ in 0..TRIES {
            let file = std::fs::File::open(path).map_err(|e| Error::io(path, &e))?;
            let got =
                fs4::fs_std::FileExt::try_lock_exclusive(&file).map_err(|e| Error::io(path, &e))?;
            if !got {
                return Err(Error::new(
                    ErrorKind::Io,
                    format!(
                        "{}: another run is writing this file (a rapidtherm run, or a program holding a lock on it); nothing was done: run again once it has finished",
                        path.display()
                    ),
                ));
            }
            if same_inode(&file, path) {
                return Ok(Lock(file));
            }
        }
        Err(Error::new(
            ErrorKind::Io,
            format!(
                "{}: the file keeps being replaced while this run tries to lock it; nothing was done",
                path.display()
            ),
        ))
    }
}

/// Whether `path` still names the file `file` has open.
#[cfg(unix)]
fn same_inode(file: &std::fs::File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_inode(_file: &std::fs::File, _path: &Path) -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_locked_file_is_refused_until_the_lock_is_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.mod");
        std::fs::write(&p, "x").unwrap();
        let first = Lock::take(&p).unwrap();
        let e = Lock::take(&p).unwrap_err();
        assert!(
            e.message.contains("another run is writing this file"),
            "{e}"
        );
        drop(first);
        assert!(Lock::take(&p).is_ok());
    }
}
