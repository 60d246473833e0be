//! One file read by two motion tasks of a run (a task folder named beside
//! its backup, a module hard-linked into two task folders) would be
//! corrected for two robots, and written by whichever came last: its
//! targets cannot be right for both. The run is refused before anything
//! is read, naming the file and both tasks.

use crate::error::{Error, Remedy, Result};
use crate::rapid::task::Task;
use std::collections::HashMap;
use std::path::Path;

/// A file's identity whatever path names it: its device and inode where
/// the system has them, else its canonical path.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum FileId {
    #[cfg(unix)]
    Inode(u64, u64),
    #[cfg(not(unix))]
    Path(std::path::PathBuf),
}

fn file_id(path: &Path) -> Option<FileId> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let m = std::fs::metadata(path).ok()?;
        Some(FileId::Inode(m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        std::fs::canonicalize(path).ok().map(FileId::Path)
    }
}

/// Two tasks, by their places in the run: the earlier, the later.
type TaskPair = (usize, usize);
/// A file as the earlier task reads it, as the later does, and how many
/// files the two share.
type Shared<'a> = (&'a Path, &'a Path, usize);

/// Refuse `tasks` if a file is read by two of them: one error per pair of
/// tasks, naming the first such file. Standard input and a file that
/// cannot be read are left to the read, which says why.
pub fn refuse_files_of_two_tasks(tasks: &[Task]) -> Result<()> {
    if tasks.len() < 2 {
        return Ok(());
    }
    let mut first: HashMap<FileId, (usize, &Path)> = HashMap::new();
    // (earlier task, later task) -> (file as the earlier reads it, as the
    // later does, how many files they share).
    let mut pairs: Vec<(TaskPair, Shared)> = Vec::new();
    for (i, task) in tasks.iter().enumerate() {
        for file in &task.modules {
            if file.as_path() == Path::new("-") {
                continue;
            }
            let Some(id) = file_id(file) else { continue };
            match first.get(&id) {
                Some(&(j, seen)) if j != i => match pairs.iter_mut().find(|(p, _)| *p == (j, i)) {
                    Some((_, (_, _, n))) => *n += 1,
                    None => pairs.push(((j, i), (seen, file, 1))),
                },
                Some(_) => {}
                None => {
                    first.insert(id, (i, file));
                }
            }
        }
    }
    let mut errors: Vec<Error> = pairs
        .into_iter()
        .map(|((j, i), (a, b, n))| {
            let (ta, tb) = (tasks[j].label(), tasks[i].label());
            let more = match n {
                1 => String::new(),
                n => format!(" (and {} more file(s))", n - 1),
            };
            if ta == tb {
                return Error::usage(format!(
                    "task {ta} is named twice in this run (both read {}{more}): name it once",
                    a.display()
                ));
            }
            let what = if a == b {
                format!("{}{more} is read by task {ta} and by task {tb}", a.display())
            } else {
                format!(
                    "{}{more} is read by task {ta} and, as {}, by task {tb}",
                    a.display(),
                    b.display()
                )
            };
            Error::usage(format!(
                "{what}: one file cannot hold the targets of two robots, and would be written twice; name each task once"
            ))
        })
        .collect();
    if let Some(last) = errors.pop() {
        errors.push(last.with_remedy(Remedy::OneTaskAtATime));
    }
    match Error::many(errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
