//! A run's plan of writes checked before it reads anything: what each
//! output would replace, and which outputs are inputs or each other.

use super::identity::{key, Key};
use super::lock::Lock;
use super::own::{Made, LOOKED_AT};
use super::plan::{Output, Plan, Role};
use crate::error::{Error, ErrorKind, Remedy, Result};
use std::io::Read;
use std::path::{Path, PathBuf};

/// A plan of writes that passed: the outputs the binary may write, and
/// the locks on the files they replace, held until this is dropped.
#[derive(Debug)]
pub struct Checked {
    planned: Vec<Planned>,
    _locks: Vec<Lock>,
}

/// One output that may be written.
#[derive(Debug, Clone)]
pub struct Planned {
    pub output: Output,
    pub key: Key,
    /// A device or pipe named as the output: written as it is, never
    /// replaced.
    pub stream: bool,
}

impl Checked {
    /// The planned output `path` is, by its path as planned or by its
    /// identity; `None` for a path the plan does not have.
    pub fn find(&self, path: &Path) -> Option<&Planned> {
        if let Some(p) = self.planned.iter().find(|p| p.output.path == path) {
            return Some(p);
        }
        let k = key(path).ok()?;
        self.planned.iter().find(|p| p.key == k)
    }

    /// The outputs, in the plan's order.
    pub fn outputs(&self) -> impl Iterator<Item = &Planned> {
        self.planned.iter()
    }
}

impl Plan {
    /// Check every output (see the module's rule); every refusal of the
    /// plan is said at once. Nothing is written; the files to be replaced
    /// are locked.
    pub fn check(&self) -> Result<Checked> {
        let mut errors = Vec::new();
        let mut inputs: Vec<(&Path, Key)> = Vec::new();
        for input in &self.inputs {
            // An input that cannot be read is the reader's to say; one that
            // does not exist (an arm's name) is no file.
            if std::fs::metadata(input).is_err() {
                continue;
            }
            if let Ok(k) = key(input) {
                inputs.push((input, k));
            }
        }
        let mut planned: Vec<Planned> = Vec::new();
        for out in &self.outputs {
            // An input is said as one, whatever else the file is.
            let over = key(&out.path)
                .ok()
                .and_then(|k| inputs.iter().find(|(_, i)| *i == k));
            if let Some((input, _)) = over {
                errors.push(over_input(out, input));
                continue;
            }
            match self.one(out) {
                Ok(p) => planned.push(p),
                Err(e) => errors.push(e),
            }
        }
        for (i, p) in planned.iter().enumerate() {
            if let Some(q) = planned[..i]
                .iter()
                .find(|q| q.key == p.key && !module_read_in_place(q, p))
            {
                errors.push(twice(&q.output, &p.output));
            }
        }
        if let Some(e) = Error::many(errors) {
            return Err(e);
        }
        let mut locks = Vec::new();
        let mut locked: Vec<&Key> = Vec::new();
        for p in &planned {
            // One file planned twice (the module read in place) is locked
            // once: a second lock of this process would find the first.
            if p.stream || locked.contains(&&p.key) || std::fs::metadata(&p.output.path).is_err() {
                continue;
            }
            locks.push(Lock::take(&p.output.path)?);
            locked.push(&p.key);
        }
        Ok(Checked {
            planned,
            _locks: locks,
        })
    }

    /// One output on its own: what it would replace.
    fn one(&self, out: &Output) -> Result<Planned> {
        let path = &out.path;
        let k = key(path).map_err(|e| Error::usage(format!("{}: {}", out.flag, e.message)))?;
        let planned = |stream| Planned {
            output: out.clone(),
            key: k.clone(),
            stream,
        };
        let Ok(meta) = std::fs::metadata(path) else {
            return Ok(planned(false));
        };
        if meta.is_dir() {
            return Err(refusal(out, "is a folder, not a file".into()));
        }
        if !meta.is_file() {
            return match out.role {
                // `-o /dev/null`, a pipe: written as they are.
                Role::Named => Ok(planned(true)),
                Role::InPlace => Err(refusal(
                    out,
                    format!("is not a regular file ({}): a file is rewritten in place only if it is a regular one, and nothing else is read", what(&meta)),
                )),
                Role::Made(_) => Err(refusal(
                    out,
                    format!("is not a regular file ({}); a file this run names itself is written only as a regular file: move it away", what(&meta)),
                )),
            };
        }
        let linked = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
        if let Role::Made(made) = out.role {
            if linked {
                return Err(refusal(
                    out,
                    format!("is a symbolic link (to {}); a file this run names itself is not written through a link, which may lead out of the folder: remove the link", link_target(path)),
                ));
            }
            if !self.force && !made.is_own(&head(path)?) {
                return Err(refusal(
                    out,
                    format!(
                        "exists and is not {}, so this run, which names it itself, does not replace it",
                        made.words()
                    ),
                )
                .with_remedy(Remedy::Force));
            }
        }
        let names = links(&meta);
        if names > 1 {
            return Err(refusal(
                out,
                format!("has {names} names (hard links); replacing it would leave the other names with the old contents, so it is not replaced: copy it to a file of its own first, or write elsewhere"),
            ));
        }
        refuse_read_only(out, &meta)?;
        Ok(planned(false))
    }
}

/// The `--runtime` module over a file of the task rewritten in place: a
/// former run's module, read with the task's other files (a task folder
/// holds it); it passed as the module's own, and has no move to rewrite.
fn module_read_in_place(a: &Planned, b: &Planned) -> bool {
    let module = Role::Made(Made::RuntimeModule);
    matches!(
        (a.output.role, b.output.role),
        (Role::InPlace, r) | (r, Role::InPlace) if r == module
    )
}

/// A refusal of output `out`: its flag, its path, why.
fn refusal(out: &Output, why: String) -> Error {
    match out.role {
        Role::Named => Error::usage(format!("{} {}: {why}", out.flag, out.path.display())),
        Role::InPlace => Error::usage(format!("{}: {why}", out.path.display())),
        Role::Made(_) => Error::usage(format!("{}: {} {why}", out.flag, out.path.display())),
    }
}

fn over_input(out: &Output, input: &Path) -> Error {
    match out.role {
        Role::Made(_) => Error::usage(format!(
            "{}: {} is an input of this run ({}); writing it would destroy what was read: name another folder",
            out.flag,
            out.path.display(),
            input.display()
        )),
        _ => Error::usage(format!(
            "{} {}: that is an input of this run ({}); writing it would destroy what was read: name another file",
            out.flag,
            out.path.display(),
            input.display()
        )),
    }
}

fn twice(first: &Output, then: &Output) -> Error {
    let said = |o: &Output| match o.role {
        Role::InPlace => format!("{} (in place)", o.path.display()),
        Role::Named => format!("{} {}", o.flag, o.path.display()),
        Role::Made(_) => format!("{} ({})", o.path.display(), o.flag),
    };
    Error::usage(format!(
        "{} and {} are one file: the run would write it twice, and keep only the last; name another file",
        said(first),
        said(then)
    ))
}

/// The first bytes of a file (to tell whose it is).
fn head(path: &Path) -> Result<Vec<u8>> {
    let mut bytes = Vec::with_capacity(LOOKED_AT);
    std::fs::File::open(path)
        .and_then(|f| f.take(LOOKED_AT as u64).read_to_end(&mut bytes))
        .map_err(|e| Error::io(path, &e))?;
    Ok(bytes)
}

fn link_target(path: &Path) -> String {
    std::fs::read_link(path)
        .map(|t: PathBuf| t.display().to_string())
        .unwrap_or_else(|_| "?".into())
}

#[cfg(unix)]
fn links(meta: &std::fs::Metadata) -> u64 {
    std::os::unix::fs::MetadataExt::nlink(meta)
}

#[cfg(not(unix))]
fn links(_meta: &std::fs::Metadata) -> u64 {
    1
}

/// What a file that is not a regular one is.
fn what(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    let _ = meta;
    "not a regular file"
}

/// A file nobody may write (no write permission bit), or that this user
/// may not write, is not replaced: renaming over it would only need the
/// folder's permission, and would undo the protection its owner chose.
fn refuse_read_only(out: &Output, meta: &std::fs::Metadata) -> Result<()> {
    let writable = !meta.permissions().readonly()
        && std::fs::OpenOptions::new()
            .write(true)
            .open(&out.path)
            .is_ok();
    if writable {
        return Ok(());
    }
    Err(Error::new(
        ErrorKind::Io,
        format!(
            "{}: the file is read-only, so it is not replaced; make it writable first (chmod u+w) if it should be",
            out.path.display()
        ),
    ))
}
