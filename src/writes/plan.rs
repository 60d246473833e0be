//! What a run will write, as planned before it reads: each output with
//! the flag that asks for it and whether the user named the file.

use std::path::{Path, PathBuf};

/// Whether the user named the file an output writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// A file the user named to be written (`-o FILE`, `--save-model
    /// FILE`, `heating fit --plot FILE`): replaced if it exists (a device
    /// or a pipe is written as it is).
    Named,
    /// An input rewritten in place (`--in-place`): a regular file of one
    /// name, read and replaced by the run.
    InPlace,
    /// A file the run names itself, in a folder the user named or beside
    /// an output: replaced only where it is one of rapidtherm's own making
    /// of this kind, or with force.
    Made(crate::writes::own::Made),
}

/// One file a run will write.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// The flag asking for it, with its value where the file is made in a
    /// folder (`--plot plots`): said in every refusal.
    pub flag: String,
    pub path: PathBuf,
    pub role: Role,
}

/// Every input a run reads (besides those it rewrites in place) and every
/// file it writes, known before it reads; `force`: files the user did not
/// name may be replaced whatever they hold.
#[derive(Debug, Clone, Default)]
pub struct Plan {
    pub inputs: Vec<PathBuf>,
    pub outputs: Vec<Output>,
    pub force: bool,
}

impl Plan {
    pub fn new(force: bool) -> Plan {
        Plan {
            force,
            ..Plan::default()
        }
    }

    /// An input read (`-`, standard input, is no file and is left out).
    pub fn input(&mut self, path: &Path) -> &mut Plan {
        if path != Path::new("-") {
            self.inputs.push(path.to_path_buf());
        }
        self
    }

    /// An output (`-`, standard output, is no file and is left out).
    pub fn output(&mut self, flag: &str, path: &Path, role: Role) -> &mut Plan {
        if path != Path::new("-") {
            self.outputs.push(Output {
                flag: flag.to_string(),
                path: path.to_path_buf(),
                role,
            });
        }
        self
    }
}
