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
    if let Some(device) = Device::open(path)? {
        let mut d = device;
        return d.write_all(bytes).map_err(|e| Error::io(path, &e));
    }
    let mut f = AtomicFile::create(path, backup)?;
    f.write_all(bytes).map_err(|e| Error::io(path, &e))?;
    f.commit()
}

/// A device or pipe named as an output (`/dev/null`, a FIFO), opened to
/// be written as it is; `None` for a regular file or a new name; a folder
/// is an error.
struct Device(std::fs::File);

impl Device {
    fn open(path: &Path) -> Result<Option<Device>> {
        match std::fs::metadata(path) {
            Ok(meta) if meta.is_dir() => Err(Error::new(
                ErrorKind::Io,
                format!("{}: is a folder, not a file", path.display()),
            )),
            Ok(meta) if !meta.is_file() => std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map(|f| Some(Device(f)))
                .map_err(|e| Error::io(path, &e)),
            _ => Ok(None),
        }
    }
}

impl Write for Device {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.0.flush()
    }
}

/// A regular file written atomically: into a temporary file in its folder,
/// renamed over it (its permissions kept, the old one copied to a backup
/// where asked) once [`AtomicFile::commit`]ted; dropped, nothing changes.
/// Its pages go to the disk from another thread as it grows, so that the
/// sync that makes the rename durable finds little left (for a tenth of a
/// gigabyte it took 0.15 s after the last byte); a background sync's
/// error is the next write's or flush's.
pub struct AtomicFile {
    /// The file replaced (a symbolic link's target: the link stays).
    path: std::path::PathBuf,
    tmp: tempfile::NamedTempFile,
    backup: Option<std::path::PathBuf>,
    existing: Option<std::fs::Metadata>,
    unsynced: usize,
    syncing: Option<std::thread::JoinHandle<std::io::Result<()>>>,
}

/// Bytes written between two background syncs.
const WRITEBACK_BYTES: usize = 16 << 20;

impl AtomicFile {
    /// A new version of the regular file `path` (which may not exist yet);
    /// with `backup`, the suffix of the copy the old one is kept as, which
    /// must be free.
    pub fn create(path: &Path, backup: Option<&str>) -> Result<AtomicFile> {
        let f = AtomicFile::unchecked(path, backup)?;
        f.check_backup()?;
        Ok(f)
    }

    /// Whether the backup's name is free (a file that turns out not to
    /// change needs none: [`FileSink`] asks once it knows).
    pub fn check_backup(&self) -> Result<()> {
        match &self.backup {
            Some(name) => check_backup_free(name),
            None => Ok(()),
        }
    }

    /// [`AtomicFile::create`], the backup's name not checked yet.
    fn unchecked(path: &Path, backup: Option<&str>) -> Result<AtomicFile> {
        if let Ok(meta) = std::fs::metadata(path) {
            if !meta.is_file() {
                return Err(Error::new(
                    ErrorKind::Io,
                    format!("{}: not a regular file", path.display()),
                ));
            }
        }
        // Through a symbolic link, the file it points to is replaced, and
        // the link stays.
        let path = if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
            std::fs::canonicalize(path).map_err(|e| Error::io(path, &e))?
        } else {
            path.to_path_buf()
        };
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => Path::new(".").to_path_buf(),
        };
        let existing = std::fs::metadata(&path).ok();
        if let Some(meta) = &existing {
            refuse_read_only(&path, meta)?;
        }
        let backup = match (backup, &existing) {
            (Some(suffix), Some(_)) => Some(backup_path(&path, suffix)),
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
        let tmp = builder.tempfile_in(&dir).map_err(|e| Error::io(&dir, &e))?;
        Ok(AtomicFile {
            path,
            tmp,
            backup,
            existing,
            unsynced: 0,
            syncing: None,
        })
    }

    /// The background sync's outcome, once it has finished.
    fn join(&mut self) -> std::io::Result<()> {
        match self.syncing.take().map(std::thread::JoinHandle::join) {
            Some(Ok(result)) => result,
            Some(Err(_)) => Err(std::io::Error::other("the background sync failed")),
            None => Ok(()),
        }
    }

    /// Throw away what was written.
    pub fn restart(&mut self) -> std::io::Result<()> {
        use std::io::Seek;
        self.join()?;
        let f = self.tmp.as_file_mut();
        f.set_len(0)?;
        f.rewind()?;
        self.unsynced = 0;
        Ok(())
    }

    /// Put the new file in place (the old one copied to its backup first).
    pub fn commit(mut self) -> Result<()> {
        self.join().map_err(|e| Error::io(&self.path, &e))?;
        self.tmp
            .as_file()
            .sync_all()
            .map_err(|e| Error::io(self.tmp.path(), &e))?;
        if let Some(name) = &self.backup {
            std::fs::copy(&self.path, name).map_err(|e| Error::io(name, &e))?;
        }
        if let Some(meta) = &self.existing {
            keep_owner(self.tmp.as_file(), &self.path, meta)?;
            std::fs::set_permissions(self.tmp.path(), meta.permissions())
                .map_err(|e| Error::io(&self.path, &e))?;
        }
        let path = self.path.clone();
        self.tmp
            .persist(&path)
            .map_err(|e| Error::new(ErrorKind::Io, format!("{}: {}", path.display(), e.error)))?;
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.tmp.as_file_mut().write(buf)?;
        self.unsynced += n;
        if self.unsynced >= WRITEBACK_BYTES
            && self
                .syncing
                .as_ref()
                .is_none_or(std::thread::JoinHandle::is_finished)
        {
            self.join()?;
            let file = self.tmp.as_file().try_clone()?;
            self.syncing = Some(std::thread::spawn(move || file.sync_data()));
            self.unsynced = 0;
        }
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.tmp.as_file_mut().flush()?;
        self.join()
    }
}

/// Where `correct` writes its corrected files: each through an
/// [`AtomicFile`] (standard output for `-`, a device as it is), all of
/// them put in place by [`FileSink::commit`] once the run is done, so
/// that a run that fails (or whose pictures cannot be drawn) leaves every
/// file as it was.
pub struct FileSink {
    backup: Option<String>,
    ready: std::sync::Arc<std::sync::Mutex<Vec<AtomicFile>>>,
}

impl FileSink {
    pub fn new(backup: Option<String>) -> FileSink {
        FileSink {
            backup,
            ready: Default::default(),
        }
    }

    /// Put every finished file in place.
    pub fn commit(self) -> Result<()> {
        let ready = match self.ready.lock() {
            Ok(mut r) => std::mem::take(&mut *r),
            Err(_) => return Err(Error::new(ErrorKind::Io, "a file being written was lost")),
        };
        for f in ready {
            f.commit()?;
        }
        Ok(())
    }
}

impl rapidtherm::correct::job::Sink for FileSink {
    fn create(&mut self, name: &str) -> Result<Box<dyn rapidtherm::correct::job::Output>> {
        let path = Path::new(name);
        if path == Path::new("-") {
            return Ok(Box::new(Stdout(Vec::new())));
        }
        if let Some(device) = Device::open(path)? {
            return Ok(Box::new(DeviceOutput {
                device,
                held: Vec::new(),
            }));
        }
        Ok(Box::new(Pending {
            file: AtomicFile::unchecked(path, self.backup.as_deref())?,
            ready: self.ready.clone(),
        }))
    }
}

/// A file finished, waiting for the run's end in its sink.
struct Pending {
    file: AtomicFile,
    ready: std::sync::Arc<std::sync::Mutex<Vec<AtomicFile>>>,
}

impl Write for Pending {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

impl rapidtherm::correct::job::Output for Pending {
    fn restart(&mut self) -> std::io::Result<()> {
        self.file.restart()
    }

    fn finish(self: Box<Self>, changed: bool) -> Result<()> {
        // A file that does not change stays as it is (and gets no backup);
        // one that does is put in place with the run's others, each
        // backup's name checked first.
        if changed {
            self.file.check_backup()?;
            if let Ok(mut r) = self.ready.lock() {
                r.push(self.file);
            }
        }
        Ok(())
    }
}

/// A device's output, held until the run ends: what was streamed may be
/// taken back (a file that does not change is written as it was read),
/// and a device cannot be rewound.
struct DeviceOutput {
    device: Device,
    held: Vec<u8>,
}

impl Write for DeviceOutput {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.held.extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl rapidtherm::correct::job::Output for DeviceOutput {
    fn restart(&mut self) -> std::io::Result<()> {
        self.held.clear();
        Ok(())
    }
    fn finish(mut self: Box<Self>, _: bool) -> Result<()> {
        let held = std::mem::take(&mut self.held);
        self.device
            .write_all(&held)
            .and_then(|_| self.device.flush())
            .map_err(|e| Error::new(ErrorKind::Io, e.to_string()))
    }
}

/// Standard output: written when finished (a run that fails prints
/// nothing).
struct Stdout(Vec<u8>);

impl Write for Stdout {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl rapidtherm::correct::job::Output for Stdout {
    fn restart(&mut self) -> std::io::Result<()> {
        self.0.clear();
        Ok(())
    }
    fn finish(self: Box<Self>, _: bool) -> Result<()> {
        super::write_stdout(&self.0)
    }
}

/// Write to a file atomically, or to standard output for `-`.
pub fn write_output(path: &Path, bytes: &[u8]) -> Result<()> {
    if path == Path::new("-") {
        super::write_stdout(bytes)
    } else {
        write_atomic(path, bytes, None)
    }
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
