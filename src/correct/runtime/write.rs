//! Where `correct --runtime` puts what it made: the rewritten programs
//! where the plan says, and each task's module beside them (one module
//! per folder: two tasks of one folder that need different modules are
//! refused). Every output is made before any is kept.

use super::job::RewrittenTask;
use crate::correct::job::Sink;
use crate::correct::plan::Destination;
use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Where the module of a run whose program is `program` goes.
pub fn module_path(program: &Path, file: &str) -> PathBuf {
    RewrittenTask::module_dir(program).join(file)
}

/// Every module file a run on `tasks` (those that move a robot) will
/// write to `dest` for the module named `module`: beside the output, or
/// beside each task's first file. Known before any task is read.
pub fn module_paths(
    dest: &Destination,
    tasks: &[&crate::rapid::task::Task],
    module: &str,
) -> Vec<PathBuf> {
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
    for (path, bytes) in &modules {
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
