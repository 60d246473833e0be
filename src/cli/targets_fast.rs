//! `targets FILE` on a program of millions of moves: the file
//! memory-mapped, its moves cut out by the fast recogniser
//! (`rapid::fastmove`), the rest parsed whole, the rows of the cut moves
//! made on every core (`rapid::fastlist`) by the same code as the whole
//! program's (`targets::Lister`), and written in order. Any other run, and
//! any file the fast path declines, takes the whole-program path, which
//! prints the same bytes (see `docs/streaming.md`).

use super::messages;
use super::stream::{is_plain_file, map_file};
use super::targets::{all_uses, Lister, Sink, TargetsArgs};
use super::{stdout_written, Status};
use rapidtherm::error::Result;
use rapidtherm::rapid::fastlist::{Entry, Listing};
use rapidtherm::rapid::{self, task::Task};
use rayon::prelude::*;
use std::io::Write;

/// Targets one core lists at a time.
const CHUNK: usize = 16_384;

/// List the targets of `tasks` the fast way where it applies; `None`: it
/// does not, and nothing was written or said.
pub fn run(args: &TargetsArgs, tasks: &[Task]) -> Result<Option<Status>> {
    let [task] = tasks else {
        return Ok(None);
    };
    let [path] = task.modules.as_slice() else {
        return Ok(None);
    };
    if args.joints || task.name.is_some() || !is_plain_file(path) {
        return Ok(None);
    }
    let started = std::time::Instant::now();
    let map = map_file(path)?;
    let src: &[u8] = &map;
    let skeleton = rapid::fastmove::skeleton(src);
    if skeleton.cuts.is_empty() {
        return Ok(None);
    }
    // Whatever the skeleton's parse would say (an error, a warning) the
    // whole path says with the whole file's lines.
    let Ok(program) = rapid::parse(&path.display().to_string(), &skeleton.bytes) else {
        return Ok(None);
    };
    if !program.warnings.is_empty() {
        return Ok(None);
    }
    let Some(listing) = Listing::new(&program, &skeleton, src) else {
        return Ok(None);
    };
    let uses = all_uses(&program);
    let lister = Lister {
        prog: &program,
        several: false,
        format: args.format,
    };
    let parts: Option<Vec<Sink>> = listing
        .entries()
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut reader = listing.reader();
            let mut sink = lister.sink();
            for e in chunk {
                match *e {
                    Entry::Kept(i) => {
                        lister.add(&mut sink, listing.kept(i), uses.get(&i), &skeleton.bytes)
                    }
                    Entry::Cut(k) => {
                        reader.read(k, &mut |t| lister.add(&mut sink, t, None, src))?
                    }
                }
            }
            Some(sink)
        })
        .collect();
    let Some(parts) = parts else {
        return Ok(None);
    };
    super::tasks::announce(task);
    messages::took("parsing", started);
    let mut out = std::io::BufWriter::with_capacity(1 << 20, std::io::stdout().lock());
    stdout_written(lister.finish(parts, &mut out).and_then(|_| out.flush()))?;
    Ok(Some(Status::Success))
}
