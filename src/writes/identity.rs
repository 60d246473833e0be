//! A file's identity whatever path names it: an existing file by its
//! device and inode (through symbolic links, `.`, `..` and any other
//! spelling), a file not made yet by the canonical path of its nearest
//! existing folder and the names below it. Read from the file system's
//! metadata only: opening a FIFO to compare it would block.

use crate::error::{Error, ErrorKind, Result};
use std::path::{Component, Path, PathBuf};

/// A file's identity.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Key {
    /// An existing file: device and inode.
    #[cfg(unix)]
    Inode(u64, u64),
    /// An existing file where the system has no inodes, or one not made
    /// yet: the path it would have, every existing folder canonical.
    Path(PathBuf),
}

/// The identity of `path`; a symbolic link to nothing is an error (the
/// file it would write is not where the path says).
pub fn key(path: &Path) -> Result<Key> {
    match std::fs::metadata(path) {
        Ok(meta) => Ok(existing(path, &meta)),
        Err(_) if std::fs::symlink_metadata(path).is_ok() => Err(Error::new(
            ErrorKind::Usage,
            format!(
                "{}: a symbolic link to a file that does not exist; name the file itself",
                path.display()
            ),
        )),
        Err(_) => Ok(Key::Path(not_yet(path))),
    }
}

#[cfg(unix)]
fn existing(_path: &Path, meta: &std::fs::Metadata) -> Key {
    use std::os::unix::fs::MetadataExt;
    Key::Inode(meta.dev(), meta.ino())
}

#[cfg(not(unix))]
fn existing(path: &Path, _meta: &std::fs::Metadata) -> Key {
    Key::Path(std::fs::canonicalize(path).unwrap_or_else(|_| not_yet(path)))
}

/// The path a file not made yet would have: each existing part made
/// canonical (links followed), a `..` below a folder not made yet taken
/// lexically (such a folder cannot be a link).
fn not_yet(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut resolved = PathBuf::new();
    let mut exists = true;
    for part in absolute.components() {
        match part {
            Component::Prefix(_) | Component::RootDir => resolved.push(part.as_os_str()),
            Component::CurDir => {}
            Component::ParentDir => {
                resolved.pop();
            }
            Component::Normal(name) => {
                resolved.push(name);
                if exists {
                    match std::fs::canonicalize(&resolved) {
                        Ok(c) => resolved = c,
                        Err(_) => exists = false,
                    }
                }
            }
        }
    }
    resolved
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spellings_of_one_file_have_one_key() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("sub")).unwrap();
        std::fs::write(d.join("a.mod"), "x").unwrap();
        let a = key(&d.join("a.mod")).unwrap();
        assert_eq!(key(&d.join("sub/../a.mod")).unwrap(), a);
        assert_eq!(key(&d.join("./././a.mod")).unwrap(), a);
        assert_ne!(key(&d.join("b.mod")).unwrap(), a);
        // Not made yet: one key for the spellings of one path.
        assert_eq!(
            key(&d.join("new/x/../p.svg")).unwrap(),
            key(&d.join("new/./p.svg")).unwrap()
        );
        assert_eq!(
            key(&d.join("sub/../b.mod")).unwrap(),
            key(&d.join("b.mod")).unwrap()
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_link_is_its_file_and_a_link_to_nothing_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("a.mod"), "x").unwrap();
        std::os::unix::fs::symlink(d.join("a.mod"), d.join("link.mod")).unwrap();
        std::os::unix::fs::symlink(d, d.join("here")).unwrap();
        let a = key(&d.join("a.mod")).unwrap();
        assert_eq!(key(&d.join("link.mod")).unwrap(), a);
        assert_eq!(
            key(&d.join("here/new.svg")).unwrap(),
            key(&d.join("new.svg")).unwrap()
        );
        std::os::unix::fs::symlink(d.join("gone"), d.join("dangling")).unwrap();
        assert!(key(&d.join("dangling")).is_err());
    }
}
