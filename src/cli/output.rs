//! Writing results safely: a file is either complete or untouched. Every
//! output goes to a temporary file in the destination folder and is renamed
//! into place only once fully written, keeping the old file's permissions.

use rapidtherm::error::{Error, ErrorKind, Result};
use std::io::Write;
use std::path::Path;

/// Write `bytes` to `path` atomically. With `backup`, the existing file is
/// first copied to `path` + suffix.
pub fn write_atomic(path: &Path, bytes: &[u8], backup: Option<&str>) -> Result<()> {
    // A device or pipe (`-o /dev/null`, a FIFO) is written as it is:
    // renaming a file over it would replace the device itself.
    if let Ok(meta) = std::fs::metadata(path) {
        if !meta.is_file() {
            if meta.is_dir() {
                return Err(Error::new(
                    ErrorKind::Io,
                    format!("{}: is a folder, not a file", path.display()),
                ));
            }
            return std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .and_then(|mut f| f.write_all(bytes))
                .map_err(|e| Error::io(path, &e));
        }
    }
    write_atomic_with(path, backup, |f| {
        f.write_all(bytes).map_err(|e| Error::io(path, &e))?;
        Ok(Filled::Written(()))
    })
    .map(|_| ())
}

/// What [`write_atomic_with`]'s `fill` made of the temporary file.
pub enum Filled<T> {
    /// The new contents: they replace `path`.
    Written(T),
    /// Nothing to change: `path` stays as it is (and gets no backup).
    Unchanged(T),
    /// Given up: `path` stays as it is, and the caller does otherwise.
    Declined,
}

/// Write the regular file `path` atomically with what `fill` writes into
/// its temporary file; `None`: `fill` declined, and `path` is untouched.
pub fn write_atomic_with<T>(
    path: &Path,
    backup: Option<&str>,
    fill: impl FnOnce(&mut std::fs::File) -> Result<Filled<T>>,
) -> Result<Option<T>> {
    if let Ok(meta) = std::fs::metadata(path) {
        if !meta.is_file() {
            return Err(Error::new(
                ErrorKind::Io,
                format!("{}: not a regular file", path.display()),
            ));
        }
    }
    // Through a symbolic link, the file it points to is replaced, and the
    // link stays.
    let resolved;
    let path = if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        resolved = std::fs::canonicalize(path).map_err(|e| Error::io(path, &e))?;
        resolved.as_path()
    } else {
        path
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let existing = std::fs::metadata(path).ok();
    if let Some(meta) = &existing {
        refuse_read_only(path, meta)?;
    }
    let backup = match (backup, &existing) {
        (Some(suffix), Some(_)) => {
            let name = backup_path(path, suffix);
            check_backup_free(&name)?;
            Some(name)
        }
        _ => None,
    };
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
    let done = match fill(tmp.as_file_mut())? {
        Filled::Written(done) => done,
        Filled::Unchanged(done) => return Ok(Some(done)),
        Filled::Declined => return Ok(None),
    };
    tmp.as_file()
        .sync_all()
        .map_err(|e| Error::io(tmp.path(), &e))?;
    if let Some(name) = backup {
        std::fs::copy(path, &name).map_err(|e| Error::io(Path::new(&name), &e))?;
    }
    if let Some(meta) = existing {
        keep_owner(tmp.as_file(), path, &meta)?;
        std::fs::set_permissions(tmp.path(), meta.permissions())
            .map_err(|e| Error::io(path, &e))?;
    }
    tmp.persist(path)
        .map_err(|e| Error::new(ErrorKind::Io, format!("{}: {}", path.display(), e.error)))?;
    Ok(Some(done))
}

/// An output named by `flag` that is also an input of the same run: the
/// run would destroy what it read. Checked before anything is written;
/// `-` (standard input or output) is never a file here. An output that
/// does not exist yet cannot be an input.
pub fn refuse_inputs_as_outputs(outputs: &[(&str, &Path)], inputs: &[&Path]) -> Result<()> {
    let dash = Path::new("-");
    let mut errors = Vec::new();
    for &(flag, out) in outputs {
        if out == dash {
            continue;
        }
        for &input in inputs {
            if input == dash {
                continue;
            }
            if same_file::is_same_file(out, input).unwrap_or(false) {
                errors.push(Error::usage(format!(
                    "{flag} {}: that is an input of this run ({}); writing it would destroy what was read: name another file",
                    out.display(),
                    input.display()
                )));
                break;
            }
        }
    }
    match Error::many(errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// A folder the run will create (if missing) and write into: its nearest
/// existing ancestor must be a folder. Checked before anything is
/// written, so that a run does not write one output and then fail on
/// another.
pub fn check_folder(flag: &str, dir: &Path) -> Result<()> {
    for ancestor in dir.ancestors() {
        if ancestor.as_os_str().is_empty() {
            break;
        }
        match std::fs::metadata(ancestor) {
            Ok(meta) if meta.is_dir() => return Ok(()),
            Ok(_) => {
                return Err(Error::usage(format!(
                    "{flag} {}: `{}` is a file, not a folder",
                    dir.display(),
                    ancestor.display()
                )))
            }
            Err(_) => continue,
        }
    }
    Ok(())
}

/// A file the run will write: its folder must exist, and the path must
/// not be a folder. Checked before anything is written.
pub fn check_file(flag: &str, path: &Path) -> Result<()> {
    if path == Path::new("-") {
        return Ok(());
    }
    if path.is_dir() {
        return Err(Error::usage(format!(
            "{flag} {}: is a folder, not a file",
            path.display()
        )));
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(Error::usage(format!(
            "{flag} {}: the folder `{}` does not exist",
            path.display(),
            dir.display()
        )));
    }
    Ok(())
}

/// A file nobody may write (no write permission bit), or that this user
/// may not write, is not replaced: renaming over it would only need the
/// folder's permission, and would undo the protection its owner chose.
fn refuse_read_only(path: &Path, meta: &std::fs::Metadata) -> Result<()> {
    let writable = !meta.permissions().readonly()
        && std::fs::OpenOptions::new().write(true).open(path).is_ok();
    if writable {
        return Ok(());
    }
    Err(Error::new(
        ErrorKind::Io,
        format!(
            "{}: the file is read-only, so it is not replaced; make it writable first (chmod u+w) if it should be",
            path.display()
        ),
    ))
}

/// The new file takes the replaced one's owner and group. Where this user
/// may not give them, the file is not replaced: it would change hands.
#[cfg(unix)]
fn keep_owner(tmp: &std::fs::File, path: &Path, meta: &std::fs::Metadata) -> Result<()> {
    use std::os::unix::fs::MetadataExt;
    let now = tmp.metadata().map_err(|e| Error::io(path, &e))?;
    if now.uid() == meta.uid() && now.gid() == meta.gid() {
        return Ok(());
    }
    std::os::unix::fs::fchown(tmp, Some(meta.uid()), Some(meta.gid())).map_err(|e| {
        Error::new(
            ErrorKind::Io,
            format!(
                "{}: belongs to user {} and group {}, which this user cannot give a new file ({e}); it is left as it is: run as its owner, or write elsewhere with -o",
                path.display(),
                meta.uid(),
                meta.gid()
            ),
        )
    })
}

#[cfg(not(unix))]
fn keep_owner(_tmp: &std::fs::File, _path: &Path, _meta: &std::fs::Metadata) -> Result<()> {
    Ok(())
}

/// `path` + `suffix`.
pub fn backup_path(path: &Path, suffix: &str) -> std::path::PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(suffix);
    name.into()
}

/// A backup never replaces an earlier one: that may be the only cold
/// original left.
pub fn check_backup_free(backup: &Path) -> Result<()> {
    if std::fs::symlink_metadata(backup).is_ok() {
        return Err(Error::new(
            ErrorKind::Io,
            format!(
                "{}: a backup of this name exists already (it may be the only cold original); move it away or choose another suffix with --backup",
                backup.display()
            ),
        ));
    }
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

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_not_replaced_and_a_link_is_kept() {
        use std::os::unix::fs::FileTypeExt;
        write_atomic(Path::new("/dev/null"), b"nothing", None).unwrap();
        let meta = std::fs::metadata("/dev/null").unwrap();
        assert!(
            meta.file_type().is_char_device(),
            "/dev/null is still the device"
        );

        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.mod");
        let link = dir.path().join("link.mod");
        std::fs::write(&real, b"old").unwrap();
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_atomic(&link, b"new", None).unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        assert!(
            write_atomic(dir.path(), b"x", None).is_err(),
            "a folder is refused"
        );
    }

    #[test]
    fn missing_folder_is_an_error_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no/such/dir/out.mod");
        assert!(write_atomic(&p, b"x", None).is_err());
        assert!(!p.exists());
    }
}
