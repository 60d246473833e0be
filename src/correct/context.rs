//! What every target of a run shares: the program's frames, usages and
//! constants, the warm robot's states, the options; built once per run.

use super::derived::calls_by_offset;
use super::expressions::Expressions;
use super::names::Names;
use super::options::{Options, When};
use crate::error::Result;
use crate::model::{States, WarmRobot};
use crate::rapid::constants::{Constants, Site};
use crate::rapid::{Expr, FunctionCall, Program, Target};
use crate::resolve::dataflow::{runtime_writes, Write};
use crate::resolve::{uses, Frames, Uses};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// What every target of a run shares: the program's frames and usages, the
/// warm robot's states, the options.
pub(super) struct Run<'a> {
    pub program: &'a Program,
    pub warm: &'a WarmRobot,
    pub states: States<'a>,
    pub options: &'a Options,
    pub frames: Frames,
    pub uses: Uses<'a>,
    pub conf_off: bool,
    /// Robtarget and jointtarget variables the run writes, by lower-case
    /// name.
    pub writes: HashMap<String, Write>,
    pub constants: Constants<'a>,
    /// Every function call of the program by where it starts.
    pub calls: HashMap<usize, &'a FunctionCall>,
    pub expressions: Expressions<'a>,
    /// Choices made on the way that the user should know about, each with
    /// the place of the target it was made for (the targets are solved
    /// on every core: said in the program's order).
    pub notes: Mutex<Vec<((usize, usize), String)>>,
    /// Where names are declared and read, for splitting targets (built
    /// when first needed).
    pub names: OnceLock<Names>,
}

impl<'a> Run<'a> {
    pub fn new(program: &'a Program, warm: &'a WarmRobot, options: &'a Options) -> Result<Run<'a>> {
        let mut states = warm.states();
        // Every target at one moment: its state worked out once. (An
        // error is said where a target asks for it, as before.)
        if let When::At(m) = options.when {
            let _ = states.remember(m);
        }
        Ok(Run {
            program,
            warm,
            states,
            options,
            frames: match &options.base_frame {
                Some(base) => Frames::of_program(program)?.placed(base),
                None => Frames::of_program(program)?,
            },
            uses: uses(program),
            conf_off: configuration_monitoring_off(program),
            writes: runtime_writes(program),
            constants: Constants::of(program),
            calls: calls_by_offset(program),
            expressions: Expressions::of(program),
            notes: Mutex::new(Vec::new()),
            names: OnceLock::new(),
        })
    }

    /// A choice made for the target at `place` (file, byte offset) that
    /// the user should know about; said once.
    pub fn note(&self, place: (usize, usize), text: String) {
        if let Ok(mut notes) = self.notes.lock() {
            if !notes.iter().any(|(_, n)| *n == text) {
                notes.push((place, text));
            }
        }
    }

    /// The notes, in the program's order.
    pub fn notes(&self) -> Vec<String> {
        let mut notes = match self.notes.lock() {
            Ok(n) => n.clone(),
            Err(_) => Vec::new(),
        };
        notes.sort_by_key(|n| n.0);
        notes.into_iter().map(|(_, n)| n).collect()
    }

    /// The value of a number in the program as written at `target`
    /// (literals and constants).
    pub fn eval(&self, target: &Target, e: &Expr) -> Option<f64> {
        let site = Site {
            module: &target.origin.module,
            routine: target.origin.routine.as_deref(),
        };
        self.constants.num(e, site)
    }
}

/// Whether the program switches configuration monitoring off
/// (`ConfL \Off`, `ConfJ \Off`): then the controller does not hold targets
/// to their robconf.
pub(super) fn configuration_monitoring_off(program: &Program) -> bool {
    let mut off = false;
    for module in &program.modules {
        for routine in &module.routines {
            crate::resolve::walk_calls(&routine.body, &mut |call, _| {
                let name = call.name.as_ref();
                if (name.eq_ignore_ascii_case("ConfL") || name.eq_ignore_ascii_case("ConfJ"))
                    && call.optional("Off").is_some()
                {
                    off = true;
                }
            });
        }
    }
    off
}
