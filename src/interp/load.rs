//! A program loaded: its record types and routines by name, RAPID's
//! predefined data, and every datum initialised from its declaration
//! (again at a restart, `PERS` data kept).

use super::bounds;
use super::clock::Clock;
use super::kin::{self, Kinematics};
use super::state::{Frame, Global, Interp, Ops, Precision};
use super::value::{Types, Value};
use crate::error::{Error, Result};
use crate::rapid::{self, DataDecl, Program, Storage};
use std::collections::HashMap;
use std::rc::Rc;

impl Interp {
    /// Reads `files` with the project's grammar and loads their modules:
    /// every datum initialised, the clock at 2000-01-01.
    pub fn load(files: &[(&str, &[u8])], kin: Kinematics) -> Result<Interp> {
        let program = rapid::parse_files(files)?;
        let (types, routines) = index(&program);
        let mut interp = Interp {
            program: Rc::new(program),
            types,
            globals: HashMap::new(),
            routines,
            frames: Vec::new(),
            kin,
            clock: Clock::at(2000, 1, 1, 0, 0, 0),
            precision: Precision::Double,
            ops: Ops::default(),
            call_began: 0,
            step_budget: bounds::STEP_BUDGET,
            moves: Vec::new(),
            at: None,
            raised: None,
            uptime: 0.0,
            commanded: None,
            messages: Vec::new(),
            files: files
                .iter()
                .map(|(n, b)| (n.to_string(), b.to_vec()))
                .collect(),
        };
        interp.predefined()?;
        interp.init_data(true)?;
        Ok(interp)
    }

    /// RAPID's predefined data the module and programs name.
    pub(super) fn predefined(&mut self) -> Result<()> {
        let tool0 = self.types.coerce_to(
            kin::tool_value(&crate::robot::ToolFrame::tool0()),
            "tooldata",
        )?;
        let tool0 = match tool0 {
            Value::Rec(t, mut f) => {
                // tload: a mass of 0.001 kg, as the controller's tool0.
                if let Some(Value::Rec(_, load)) = f.get_mut(2) {
                    load[0] = Value::Num(0.001);
                }
                Value::Rec(t, f)
            }
            v => v,
        };
        let wobj0 = kin::wobj_value(&crate::robot::WobjFrames::wobj0());
        let wobj0 = self.types.coerce_to(wobj0, "wobjdata")?;
        let load0 = self.types.default_of("loaddata")?;
        self.predefined_errors();
        self.predefined_progdisp();
        for (name, value) in [("tool0", tool0), ("wobj0", wobj0), ("load0", load0)] {
            self.globals.insert(
                name.into(),
                vec![Global {
                    module: usize::MAX,
                    local: false,
                    storage: Storage::Pers,
                    value,
                }],
            );
        }
        Ok(())
    }

    /// Initialises the modules' data from their declarations: every datum
    /// at a load, all but `PERS` ones at a program restart.
    pub(super) fn init_data(&mut self, with_pers: bool) -> Result<()> {
        self.init_modules(with_pers, None)
    }

    /// [`Interp::init_data`] of module `only` where given.
    pub(super) fn init_modules(&mut self, with_pers: bool, only: Option<usize>) -> Result<()> {
        let program = self.program.clone();
        for (m, module) in program.modules.iter().enumerate() {
            if only.is_some_and(|o| o != m) {
                continue;
            }
            // Every declaration in source order, those the fast lane
            // holds together too.
            for d in program.module_data(module) {
                if d.storage == Storage::Pers && !with_pers {
                    continue;
                }
                self.at = Some((module.file, d.pos));
                self.frames.push(Frame {
                    module: m,
                    routine: None,
                    vars: HashMap::new(),
                    handling: None,
                });
                let value = self.declared_value(&d);
                self.frames.pop();
                let value = value.map_err(|e| self.locate(e))?;
                let key = d.name.to_ascii_lowercase();
                let local = d.scope == Some(rapid::Scope::Local);
                let slots = self.globals.entry(key).or_default();
                match slots.iter_mut().find(|g| g.module == m) {
                    Some(g) => g.value = value,
                    None => slots.push(Global {
                        module: m,
                        local,
                        storage: d.storage,
                        value,
                    }),
                }
            }
        }
        self.at = None;
        Ok(())
    }

    /// The value a declaration gives its datum (in the current frame).
    pub(super) fn declared_value(&mut self, d: &DataDecl) -> Result<Value> {
        let mut dims = Vec::with_capacity(d.dims.len());
        for e in &d.dims {
            let n = self
                .eval(e)?
                .num()
                .ok_or_else(|| Error::input("an array size that is not a num"))?;
            if n < 1.0 || n.fract() != 0.0 || n > 1e7 {
                return Err(Error::input(format!("array size {n}")));
            }
            dims.push(n as usize);
        }
        let like = self.types.default_array(&d.type_name, &dims)?;
        let program = self.program.clone();
        let value = match program.value_of(d) {
            Some(e) => {
                let v = self.eval(&e)?;
                self.types.coerce(v, &like)?
            }
            None => like,
        };
        Ok(self.stored(value))
    }

    /// A program restart (PP to Main): every `VAR` and `CONST` datum set
    /// from its declaration again, `PERS` data kept, nothing running, the
    /// program displacement off (the RAPID reference, PDispOff: off when
    /// a program starts from the beginning).
    pub fn restart(&mut self) -> Result<()> {
        self.frames.clear();
        self.progdisp_off();
        self.init_data(false)
    }
}

/// The record types, aliases and routines (by lower-case name) of a
/// program.
pub(super) fn index(program: &Program) -> (Types, HashMap<String, Vec<(usize, usize)>>) {
    let mut types = Types::default();
    let mut routines: HashMap<String, Vec<(usize, usize)>> = HashMap::new();
    for (m, module) in program.modules.iter().enumerate() {
        for r in &module.records {
            types.add_record(
                &r.name,
                r.components
                    .iter()
                    .map(|(t, n)| (n.clone(), t.clone()))
                    .collect(),
            );
        }
        for (a, of) in &module.aliases {
            types.add_alias(a, of);
        }
        for (k, r) in module.routines.iter().enumerate() {
            routines
                .entry(r.name.to_ascii_lowercase())
                .or_default()
                .push((m, k));
        }
    }
    (types, routines)
}
