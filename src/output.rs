//! Writing results safely: a file is either complete or untouched. Every
//! output goes to a temporary file in the destination folder and is renamed
//! into place only once fully written, keeping the old file's permissions.

use crate::error::{Error, ErrorKind, Result};
use std::io::Write;
use std::path::Path;

/// Write `bytes` to `path` atomically. With `backup`, the existing file is
/// first copied to `path` + suffix.
pub fn write_atomic(path: &Path, bytes: &[u8], backup: Option<&str>) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let existing = std::fs::metadata(path).ok();
    if let (Some(suffix), Some(_)) = (backup, &existing) {
        let mut name = path.as_os_str().to_owned();
        name.push(suffix);
        std::fs::copy(path, &name).map_err(|e| Error::io(Path::new(&name), &e))?;
    }
    let mut builder = tempfile::Builder::new();
    builder.prefix(".rapidtherm-");
    // A new file gets the usual mode (0666 less the umask), not the
    // temporary file's private 0600.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(dir).map_err(|e| Error::io(dir, &e))?;
    tmp.write_all(bytes)
        .and_then(|_| tmp.as_file().sync_all())
        .map_err(|e| Error::io(tmp.path(), &e))?;
    if let Some(meta) = existing {
        std::fs::set_permissions(tmp.path(), meta.permissions())
            .map_err(|e| Error::io(path, &e))?;
    }
    tmp.persist(path)
        .map_err(|e| Error::new(ErrorKind::Io, format!("{}: {}", path.display(), e.error)))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_content_keeps_permissions_and_backs_up() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.mod");
        std::fs::write(&p, b"old").unwrap();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o640)).unwrap();
        }
        write_atomic(&p, b"new", Some(".bak")).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        assert_eq!(std::fs::read(dir.path().join("a.mod.bak")).unwrap(), b"old");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o640);
        }
        // No temporary files left behind.
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 2);
    }

    #[cfg(unix)]
    #[test]
    fn a_new_file_is_readable_by_others_as_the_umask_allows() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("new.toml");
        write_atomic(&p, b"x", None).unwrap();
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        // Whatever the umask, more than the owner may read (the usual
        // umasks 022 and 002 both leave 0o044).
        assert_ne!(mode, 0o600, "mode {mode:o}");
    }

    #[test]
    fn missing_folder_is_an_error_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no/such/dir/out.mod");
        assert!(write_atomic(&p, b"x", None).is_err());
        assert!(!p.exists());
    }
}
