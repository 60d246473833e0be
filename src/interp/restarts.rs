//! What the controller keeps when it starts again, besides a program
//! restart (PP to Main, [`Interp::restart`]): a restart after a power
//! failure, and a module loaded again from its file.

use super::load::index;
use super::state::Interp;
use crate::error::{Error, Result};
use crate::rapid;
use std::rc::Rc;

impl Interp {
    /// The controller off for `minutes` and on again (a power failure, a
    /// warm start): every datum kept, VAR and PERS alike, the program
    /// displacement too (the RAPID reference, PDispOff: off only at a cold
    /// start, a new program, a start from the beginning); the wall clock
    /// (battery-backed) moved on by `minutes`.
    ///
    /// The manual does not say what a running `clock` counts across a
    /// power failure; the interpreter takes the controller's time as
    /// stopped while it is off: a running clock keeps its count and runs
    /// on, the time off not counted (a program that wants the time off
    /// reads the wall clock).
    pub fn power_fail(&mut self, minutes: f64) {
        self.frames.clear();
        self.raised = None;
        self.clock.advance(minutes);
    }

    /// Module `name` loaded again from `bytes` (its file as it now reads):
    /// its data as the file declares them, PERS ones too, VAR ones reset;
    /// its routines the file's; every other module's data kept.
    pub fn reload_module(&mut self, name: &str, bytes: &[u8]) -> Result<()> {
        let m = self
            .program
            .modules
            .iter()
            .position(|x| x.name.eq_ignore_ascii_case(name))
            .ok_or_else(|| Error::input(format!("no module `{name}` loaded")))?;
        let file = self.program.modules[m].file;
        let mut files = self.files.clone();
        let f = files
            .get_mut(file)
            .ok_or_else(|| Error::input(format!("module `{name}` has no file")))?;
        f.1 = bytes.to_vec();
        let refs: Vec<(&str, &[u8])> = files
            .iter()
            .map(|(n, b)| (n.as_str(), b.as_slice()))
            .collect();
        let program = rapid::parse_files(&refs)?;
        let same = program.modules.len() == self.program.modules.len()
            && program
                .modules
                .get(m)
                .is_some_and(|x| x.name.eq_ignore_ascii_case(name));
        if !same {
            return Err(Error::input(format!(
                "the file of module `{name}` no longer holds that module alone"
            )));
        }
        let (types, routines) = index(&program);
        self.program = Rc::new(program);
        self.types = types;
        self.types.add_alias("errnum", "num");
        self.routines = routines;
        self.files = files;
        self.frames.clear();
        for slots in self.globals.values_mut() {
            slots.retain(|g| g.module != m);
        }
        self.globals.retain(|_, slots| !slots.is_empty());
        self.init_modules(true, Some(m))
    }
}
