//! Where `correct --runtime` puts what it made: the rewritten programs
//! where the plan says, and each task's module beside them (one module
//! per folder: two tasks of one folder that need different modules are
//! refused). Every output is made before any is kept.

use super::job::RewrittenTask;
use crate::correct::job::Sink;
use crate::correct::plan::Destination;
use crate::error::{Error, Result};
use crate::rapid::task::backinfo_entry::{backinfo_of, with_module};
use crate::rapid::task::Task;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Where the module of a run whose program is `program` goes.
pub fn module_path(program: &Path, file: &str) -> PathBuf {
    RewrittenTask::module_dir(program).join(file)
}

/// Every module file a run on `tasks` (those that move a robot) will
/// write to `dest` for the module named `module`: beside the output, or
/// beside each task's first file. Known before any task is read.
pub fn module_paths(dest: &Destination, tasks: &[&Task], module: &str) -> Vec<PathBuf> {
    let file = super::module::module_file(module);
    let mut paths: Vec<PathBuf> = Vec::new();
    for task in tasks {
        let beside = match dest {
            Destination::File(out) => out.clone(),
            _ => match task.modules.first() {
                Some(first) => first.clone(),
                None => continue,
            },
        };
        let path = module_path(&beside, &file);
        if !paths.contains(&path) {
            paths.push(path);
        }
    }
    paths
}

/// Where the module of `task` goes in a backup (its first file's
/// folder, `module_path`), as the backup's `backinfo.txt` lists a task's
/// modules: that file, the task's folder there (`TASK1`) and the module's
/// path inside it (`SYSMOD/RtWarm.sys`). `None` for a task of no backup,
/// or a module put outside the task's folder.
fn backinfo_entry(task: &Task, module_path: &Path) -> Option<(PathBuf, String, String)> {
    let dir = task.origin.as_deref()?;
    let (file, folder) = backinfo_of(dir)?;
    let inside = module_path.strip_prefix(dir).ok()?;
    let parts: Vec<String> = inside
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    Some((file, folder, parts.join("/")))
}

/// Every `backinfo.txt` a run on `tasks` (those that move a robot)
/// rewrites for the module named `module`: in place only, where the
/// module goes into a task folder of a backup. Known before any task is
/// read; whether the file changes, only once it is.
pub fn backinfo_paths(dest: &Destination, tasks: &[&Task], module: &str) -> Vec<PathBuf> {
    if !matches!(dest, Destination::InPlace { .. }) {
        return Vec::new();
    }
    let file = super::module::module_file(module);
    let mut paths: Vec<PathBuf> = Vec::new();
    for task in tasks {
        let Some(first) = task.modules.first() else {
            continue;
        };
        if let Some((path, _, _)) = backinfo_entry(task, &module_path(first, &file)) {
            if !paths.contains(&path) {
                paths.push(path);
            }
        }
    }
    paths
}

/// A `backinfo.txt` the runs' modules change.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BackinfoChange {
    pub path: PathBuf,
    /// As it is, and as it becomes.
    pub before: Vec<u8>,
    pub after: Vec<u8>,
}

/// Each `backinfo.txt` the runs' modules change: every run's module
/// listed in its task's section (once; a file that lists each already is
/// not among them).
pub fn backinfo_rewrites(runs: &[RewrittenTask]) -> Result<Vec<BackinfoChange>> {
    let mut files: Vec<BackinfoChange> = Vec::new();
    for r in runs {
        let Some(first) = r.task.modules.first() else {
            continue;
        };
        let Some((path, folder, entry)) = backinfo_entry(&r.task, &module_path(first, &r.module.0))
        else {
            continue;
        };
        let k = match files.iter().position(|f| f.path == path) {
            Some(k) => k,
            None => {
                let bytes = std::fs::read(&path).map_err(|e| Error::io(&path, &e))?;
                files.push(BackinfoChange {
                    path,
                    before: bytes.clone(),
                    after: bytes,
                });
                files.len() - 1
            }
        };
        if let Some(changed) = with_module(&files[k].after, &folder, &entry) {
            files[k].after = changed;
        }
    }
    files.retain(|f| f.before != f.after);
    Ok(files)
}

/// The runs' programs written to `dest` through `sink`, and each task's
/// module beside them. A module as it already is on disk stays untouched
/// (and gets no backup).
pub fn write(dest: &Destination, runs: &[RewrittenTask], sink: &mut dyn Sink) -> Result<()> {
    let mut modules: Vec<(PathBuf, &[u8])> = Vec::new();
    for r in runs {
        let beside = match dest {
            Destination::File(out) => out.clone(),
            _ => r.task.modules[0].clone(),
        };
        let path = module_path(&beside, &r.module.0);
        if let Some((_, other)) = modules.iter().find(|(p, _)| *p == path) {
            if *other != r.module.1.as_slice() {
                return Err(Error::usage(format!(
                    "{}: two tasks of one folder need different modules (different arms); rewrite one task at a time",
                    path.display()
                )));
            }
            continue;
        }
        modules.push((path, &r.module.1));
    }
    let mut outputs = Vec::new();
    match dest {
        Destination::File(out) => {
            outputs.push(put_file(sink, &out.display().to_string(), &runs[0], 0)?);
        }
        Destination::Stdout => {
            return Err(Error::usage("--runtime cannot write to standard output"))
        }
        Destination::InPlace { .. } => {
            for r in runs {
                for (f, (name, _)) in r.inputs.iter().enumerate() {
                    if r.file_changed(f) {
                        outputs.push(put_file(sink, name, r, f)?);
                    }
                }
            }
        }
    }
    let mut backinfo = Vec::new();
    if matches!(dest, Destination::InPlace { .. }) {
        // A restore loads what backinfo.txt lists: the module with them.
        backinfo = backinfo_rewrites(runs)?;
    }
    let made = (modules.iter().map(|(p, b)| (p.as_path(), *b))).chain(
        backinfo
            .iter()
            .map(|f| (f.path.as_path(), f.after.as_slice())),
    );
    for (path, bytes) in made {
        if std::fs::read(path).is_ok_and(|b| b == *bytes) {
            continue;
        }
        let name = path.display().to_string();
        let mut o = sink.create(&name)?;
        o.write_all(bytes)
            .map_err(|e| Error::io(Path::new(&name), &e))?;
        outputs.push(o);
    }
    for o in outputs {
        o.finish(true)?;
    }
    Ok(())
}

/// Program file `f` of run `r` written to `name` as the rewrite makes
/// it, through a buffer.
fn put_file(
    sink: &mut dyn Sink,
    name: &str,
    r: &RewrittenTask,
    f: usize,
) -> Result<Box<dyn crate::correct::job::OutputFile>> {
    let mut o = sink.create(name)?;
    let mut buffered = std::io::BufWriter::with_capacity(1 << 20, &mut o);
    r.write_file(f, &mut buffered)
        .and_then(|_| buffered.flush())
        .map_err(|e| Error::io(Path::new(name), &e))?;
    drop(buffered);
    Ok(o)
}
