//! Writing results safely: a file is either complete or untouched. Every
//! output goes to a temporary file in the destination folder and is renamed
//! into place only once fully written, keeping the old file's permissions.
//! Only a path of the run's checked plan of writes
//! ([`rapidtherm::writes`]) is written; a temporary file is removed on
//! SIGINT, SIGTERM and SIGHUP ([`remove_temporaries_on_signals`]).
//! Each file put in place is announced on standard error as `wrote PATH`
//! (a summary line, hidden by `-q`), once it is there: a run that fails
//! before announces nothing (docs/conventions.md).

use rapidtherm::error::{Error, ErrorKind, Result};
use rapidtherm::writes::{Checked, Plan};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// Write `bytes` to `path` atomically, a path of the checked plan. With
/// `backup`, the existing file is first copied to `path` + suffix.
pub fn write_atomic(
    checked: &Checked,
    path: &Path,
    bytes: &[u8],
    backup: Option<&str>,
) -> Result<()> {
    // A device or pipe (`-o /dev/null`, a FIFO) is written as it is:
    // renaming a file over it would replace the device itself.
    if planned_stream(checked, path)? {
        let mut d = Device::open(path)?;
        return d.write_all(bytes).map_err(|e| Error::io(path, &e));
    }
    let mut f = AtomicFile::create(path, backup)?;
    f.write_all(bytes).map_err(|e| Error::io(path, &e))?;
    f.commit()?;
    announce(path);
    Ok(())
}

/// `wrote PATH` on standard error, for a file just put in place. Only a
/// file is announced: standard output and a device or pipe named as an
/// output are no file the run leaves behind.
fn announce(path: &Path) {
    super::messages::status!("wrote {}", path.display());
}

/// Whether `path`, which must be in the checked plan, is a device or pipe
/// written as it is. A path the plan does not have is a fault of this
/// program, refused rather than written unchecked.
fn planned_stream(checked: &Checked, path: &Path) -> Result<bool> {
    match checked.find(path) {
        Some(p) => Ok(p.stream),
        None => Err(Error::new(
            ErrorKind::Io,
            format!(
                "{}: not among the files this run planned to write (an internal error); nothing more is written",
                path.display()
            ),
        )),
    }
}

/// The run's plan of writes checked (see [`rapidtherm::writes`]), before
/// any input is read.
pub fn check(plan: &Plan) -> Result<Checked> {
    plan.check()
}

/// Temporary files being written, removed by the signal handler.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn temporaries() -> MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner)
}

/// On SIGINT, SIGTERM or SIGHUP, every temporary file being written is
/// removed and the process ends as the signal would have ended it. A file
/// already renamed into place stays (it is complete); one not yet renamed
/// is gone with its temporary file, the old one kept.
#[cfg(unix)]
pub fn remove_temporaries_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            // Held to the end: no temporary file is made or renamed after.
            let held = temporaries();
            for path in held.iter() {
                let _ = std::fs::remove_file(path);
            }
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            std::process::exit(128 + signal);
        }
    });
}

#[cfg(not(unix))]
pub fn remove_temporaries_on_signals() {}

/// A device or pipe named as an output (`/dev/null`, a FIFO), opened to
/// be written as it is (the plan found it one).
struct Device(std::fs::File);

impl Device {
    fn open(path: &Path) -> Result<Device> {
        std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map(Device)
            .map_err(|e| Error::io(path, &e))
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
    /// The path as the run named it (a symbolic link stays one), which
    /// the `wrote` line names.
    named: std::path::PathBuf,
    /// `None` once renamed into place.
    tmp: Option<tempfile::NamedTempFile>,
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
        let named = path;
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
        // Made and listed at once: a signal finds every temporary file.
        let tmp = {
            let mut held = temporaries();
            let tmp = builder
                .tempfile_in(&dir)
                .map_err(|e| Error::io(&dir, &without_temporary_name(&e)))?;
            held.push(tmp.path().to_path_buf());
            tmp
        };
        Ok(AtomicFile {
            path,
            named: named.to_path_buf(),
            tmp: Some(tmp),
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

    /// The temporary file (there until the commit takes it).
    fn tmp(&mut self) -> std::io::Result<&mut tempfile::NamedTempFile> {
        self.tmp
            .as_mut()
            .ok_or_else(|| std::io::Error::other("the file is in place already"))
    }

    /// Throw away what was written.
    pub fn restart(&mut self) -> std::io::Result<()> {
        use std::io::Seek;
        self.join()?;
        let f = self.tmp()?.as_file_mut();
        f.set_len(0)?;
        f.rewind()?;
        self.unsynced = 0;
        Ok(())
    }

    /// Put the new file in place (the old one copied to its backup first).
    pub fn commit(mut self) -> Result<()> {
        self.join().map_err(|e| Error::io(&self.path, &e))?;
        let path = self.path.clone();
        let tmp = self.tmp().map_err(|e| Error::io(&path, &e))?;
        tmp.as_file()
            .sync_all()
            .map_err(|e| Error::io(tmp.path(), &e))?;
        if let Some(name) = &self.backup {
            std::fs::copy(&self.path, name).map_err(|e| Error::io(name, &e))?;
        }
        if let Some(meta) = &self.existing {
            let tmp = self.tmp.as_ref().map(|t| (t.as_file(), t.path()));
            if let Some((file, at)) = tmp {
                keep_owner(file, &self.path, meta)?;
                std::fs::set_permissions(at, meta.permissions())
                    .map_err(|e| Error::io(&self.path, &e))?;
            }
        }
        let Some(tmp) = self.tmp.take() else {
            return Ok(());
        };
        // Renamed and struck off the list at once: a signal between would
        // remove the file just put in place, or leave the temporary one.
        let mut held = temporaries();
        let at = tmp.path().to_path_buf();
        let kept = tmp.persist(&path);
        held.retain(|p| *p != at);
        kept.map_err(|e| Error::new(ErrorKind::Io, format!("{}: {}", path.display(), e.error)))?;
        Ok(())
    }
}

/// A file dropped unfinished: its temporary file removed and struck off
/// the list, under the list's lock.
impl Drop for AtomicFile {
    fn drop(&mut self) {
        if let Some(tmp) = self.tmp.take() {
            let mut held = temporaries();
            let at = tmp.path().to_path_buf();
            drop(tmp);
            held.retain(|p| *p != at);
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.tmp()?.as_file_mut().write(buf)?;
        self.unsynced += n;
        if self.unsynced >= WRITEBACK_BYTES
            && self
                .syncing
                .as_ref()
                .is_none_or(std::thread::JoinHandle::is_finished)
        {
            self.join()?;
            let file = self.tmp()?.as_file().try_clone()?;
            self.syncing = Some(std::thread::spawn(move || file.sync_data()));
            self.unsynced = 0;
        }
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.tmp()?.as_file_mut().flush()?;
        self.join()
    }
}

/// Where `correct` writes its corrected files: each through an
/// [`AtomicFile`] (standard output for `-`, a device as it is), all of
/// them put in place by [`FileSink::commit`] once the run is done, so
/// that a run that fails (or whose pictures cannot be drawn) leaves every
/// file as it was.
pub struct FileSink<'a> {
    backup: Option<String>,
    /// The run's checked plan: the only files it writes.
    checked: &'a Checked,
    ready: std::sync::Arc<std::sync::Mutex<Vec<AtomicFile>>>,
}

impl FileSink<'_> {
    pub fn new(backup: Option<String>, checked: &Checked) -> FileSink<'_> {
        FileSink {
            backup,
            checked,
            ready: Default::default(),
        }
    }

    /// Put every finished file in place, in the order of their names (the
    /// tasks finish in any order), each announced once it is there.
    pub fn commit(self) -> Result<()> {
        let mut ready = match self.ready.lock() {
            Ok(mut r) => std::mem::take(&mut *r),
            Err(_) => return Err(Error::new(ErrorKind::Io, "a file being written was lost")),
        };
        ready.sort_by(|a, b| a.named.cmp(&b.named));
        for f in ready {
            let named = f.named.clone();
            f.commit()?;
            announce(&named);
        }
        Ok(())
    }
}

impl rapidtherm::correct::job::Sink for FileSink<'_> {
    fn create(&mut self, name: &str) -> Result<Box<dyn rapidtherm::correct::job::OutputFile>> {
        let path = Path::new(name);
        if path == Path::new("-") {
            return Ok(Box::new(Stdout(Vec::new())));
        }
        if planned_stream(self.checked, path)? {
            return Ok(Box::new(DeviceOutput {
                device: Device::open(path)?,
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

impl rapidtherm::correct::job::OutputFile for Pending {
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

impl rapidtherm::correct::job::OutputFile for DeviceOutput {
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

impl rapidtherm::correct::job::OutputFile for Stdout {
    fn restart(&mut self) -> std::io::Result<()> {
        self.0.clear();
        Ok(())
    }
    fn finish(self: Box<Self>, _: bool) -> Result<()> {
        super::write_stdout(&self.0)
    }
}

/// Write to a file atomically (a path of the checked plan), or to
/// standard output for `-`.
pub fn write_output(checked: &Checked, path: &Path, bytes: &[u8]) -> Result<()> {
    if path == Path::new("-") {
        super::write_stdout(bytes)
    } else {
        write_atomic(checked, path, bytes, None)
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

/// The reason a temporary file could not be made, without its name: the
/// name (`.rapidtherm-FePMJu`) is no file of the user's, and the message
/// already names the folder.
fn without_temporary_name(e: &std::io::Error) -> std::io::Error {
    match e.raw_os_error() {
        Some(code) => std::io::Error::from_raw_os_error(code),
        None => std::io::Error::from(e.kind()),
    }
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
    use rapidtherm::writes::Role;

    /// `path` written by `-o`, as a checked plan.
    fn named(path: &Path) -> Result<Checked> {
        let mut plan = Plan::new(false);
        plan.output("-o", path, Role::Named);
        plan.check()
    }

    /// [`write_atomic`] of a planned `-o path`.
    fn write_named(path: &Path, bytes: &[u8], backup: Option<&str>) -> Result<()> {
        let checked = named(path)?;
        write_atomic(&checked, path, bytes, backup)
    }

    #[test]
    fn a_path_not_planned_is_not_written() {
        let dir = tempfile::tempdir().unwrap();
        let checked = named(&dir.path().join("a.mod")).unwrap();
        let other = dir.path().join("b.mod");
        assert!(write_atomic(&checked, &other, b"x", None).is_err());
        assert!(!other.exists());
    }

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
        write_named(&p, b"new", Some(".bak")).unwrap();
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
        write_named(&p, b"x", None).unwrap();
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        // Whatever the umask, more than the owner may read (the usual
        // umasks 022 and 002 both leave 0o044).
        assert_ne!(mode, 0o600, "mode {mode:o}");
    }

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_not_replaced_and_a_link_is_kept() {
        use std::os::unix::fs::FileTypeExt;
        write_named(Path::new("/dev/null"), b"nothing", None).unwrap();
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
        write_named(&link, b"new", None).unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        assert!(
            write_named(dir.path(), b"x", None).is_err(),
            "a folder is refused"
        );
    }

    #[test]
    fn missing_folder_is_an_error_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("no/such/dir/out.mod");
        assert!(write_named(&p, b"x", None).is_err());
        assert!(!p.exists());
    }
}
