//! `correct --runtime` run on the tasks the user named: for each task
//! that moves a robot, the module written from its arm and the model, and
//! its files with every move wrapped in the module's function. Every task
//! is tried before anything is written.

use super::from_robot::FromRobot;
use super::rewrite::{move_insertions, write_rewritten, Insertions, MoveTally, Route};
use super::table::Table;
use super::{module_text, ModuleOptions, RuntimeSpec};
use crate::correct::job::{checked_arm, load_model, model_label, moves_a_robot, read_task};
use crate::correct::job::{Event, Host, Inputs};
use crate::correct::marker;
use crate::correct::plan::{ModelSource, RuntimePlan};
use crate::error::{Error, Errors, Result};
use crate::rapid::rewrite::Edit;
use crate::rapid::task::Task;
use crate::rapid::Program;
use crate::resolve::arm::base_frame;
use nalgebra::Isometry3;
use std::path::{Path, PathBuf};

/// The marker's basis of a run-time rewrite: the module's name, so that
/// a static correction of the rewritten program is refused (it would
/// correct twice), and a second `--runtime` run recognises its output.
pub fn basis(module: &str) -> String {
    format!("runtime {module}")
}

/// One task rewritten.
#[derive(Debug)]
pub struct RewrittenTask {
    pub task: Task,
    pub arm: String,
    pub inputs: Inputs,
    /// Each input's rewrite (`None`: it stays as it is), written out by
    /// [`RewrittenTask::write_file`] as it is made.
    rewrites: Vec<Option<FileRewrite>>,
    /// The module's file name (`NAME.sys`) and bytes.
    pub module: (String, Vec<u8>),
    pub tally: MoveTally,
    /// A former `--runtime` run made these files: nothing was changed.
    pub already: bool,
}

/// What a file's rewrite inserts: the moves' calls and the marker.
#[derive(Debug)]
struct FileRewrite {
    calls: Insertions,
    marker: Option<Edit>,
    /// The marker's fields, which the seal covers with the numbers.
    sealed: marker::Marker,
}

impl RewrittenTask {
    /// Whether any of its program files changes.
    pub fn changed(&self) -> bool {
        (0..self.inputs.len()).any(|f| self.file_changed(f))
    }

    /// Whether input `f` changes.
    pub fn file_changed(&self, f: usize) -> bool {
        self.rewrites.get(f).is_some_and(Option::is_some)
    }

    /// Input `f` as the rewrite makes it, written to `out` as it is made
    /// (a program of a million moves is never held whole).
    pub fn write_file(&self, f: usize, out: &mut dyn std::io::Write) -> std::io::Result<()> {
        let Some((_, source)) = self.inputs.get(f) else {
            return Ok(());
        };
        match self.rewrites.get(f).and_then(Option::as_ref) {
            Some(r) => write_rewritten(source.bytes(), &r.calls, r.marker.as_ref(), &r.sealed, out),
            None => out.write_all(source.bytes()),
        }
    }

    /// Input `f` as the rewrite makes it, whole (for a diff).
    pub fn file_bytes(&self, f: usize) -> Vec<u8> {
        let mut out = Vec::new();
        // Writing to a Vec cannot fail.
        let _ = self.write_file(f, &mut out);
        out
    }

    /// The folder the module goes in beside `program`: a task's SYSMOD
    /// where its program sits in PROGMOD (a backup's layout), else the
    /// program's own folder.
    pub fn module_dir(program: &Path) -> PathBuf {
        let dir = program.parent().unwrap_or(Path::new("")).to_path_buf();
        let is_progmod = dir
            .file_name()
            .is_some_and(|n| n.eq_ignore_ascii_case("PROGMOD"));
        match dir.parent().map(|p| p.join("SYSMOD")) {
            Some(sys) if is_progmod && sys.is_dir() => sys,
            _ => dir,
        }
    }
}

/// Rewrite the tasks (those that move no robot are said and left alone)
/// for the plan's module.
pub fn run(
    plan: &RuntimePlan,
    tasks: Vec<Task>,
    host: &mut dyn Host,
) -> Result<Vec<RewrittenTask>> {
    crate::resolve::arm::check_task_specs(&plan.arms.specs, &tasks)?;
    let model = load_model(&plan.arms.model)?;
    let mut runs = Vec::new();
    let mut errors = Errors::default();
    for task in tasks {
        if !moves_a_robot(&task) {
            host.event(Event::NotMotion {
                task: &task.label(),
                moves: 0,
            });
            continue;
        }
        match rewrite_task(plan, &model, task, host) {
            Ok(r) => runs.push(r),
            Err(e) => errors.push(e),
        }
    }
    if let Some(e) = errors.into_error(|n| {
        Error::input(format!(
            "{n} tasks cannot be rewritten for the controller; nothing was written"
        ))
    }) {
        return Err(e);
    }
    Ok(runs)
}

/// What a task's module is made of: its arm, the spec of the module and
/// where the robot stands, the model's label for the marker, the module's
/// options.
pub(super) struct Made {
    arm: crate::robot::Robot,
    spec: RuntimeSpec,
    base: Isometry3<f64>,
    pub(super) label: String,
    opts: ModuleOptions,
}

pub(super) fn made(
    plan: &RuntimePlan,
    model: &crate::model::Model,
    task: &Task,
    host: &mut dyn Host,
) -> Result<Made> {
    let arm = checked_arm(&plan.arms, task, model, host)?;
    let base = base_frame(task)?.unwrap_or_else(Isometry3::identity);
    let spec = RuntimeSpec::new(&arm.robot, model, base.rotation)?;
    let label = model_label(&plan.arms.model, &arm.label)?;
    let opts = ModuleOptions {
        name: plan.module.clone(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        heating_source: match &plan.arms.model {
            ModelSource::File(p) => format!("the model file {}", p.display()),
            ModelSource::Named(n) => format!("the embedded model {n}"),
            ModelSource::Default => "the embedded default (IRB 140, 60 % speed)".to_string(),
        },
        model: label.clone(),
    };
    Ok(Made {
        arm: arm.robot,
        spec,
        base,
        label,
        opts,
    })
}

impl Made {
    /// The insertions that wrap `program`'s moves, the tally, and the
    /// module with the table they number.
    pub(super) fn wrapped(&self, program: &Program) -> (Vec<Insertions>, MoveTally, Vec<u8>) {
        let mut table = Table::new(program, &self.arm, &self.spec, &self.base);
        let from_robot = FromRobot::new(program);
        let (calls, tally) = move_insertions(program, &self.opts.name, &mut |m, k| {
            if let Some(why) = from_robot.why(m, k) {
                return Route::Leave(format!(
                    "a reading of the robot, where the corrected robot already is ({why})"
                ));
            }
            table.row(m, k).unwrap_or(Route::Slow)
        });
        let text = module_text(&self.spec, &table.rows, &self.opts).into_bytes();
        (calls, tally, text)
    }

    /// The module of a program a former run rewrote: the one its cold
    /// original gets (the table numbers the cold program's targets), so
    /// that a second run writes the same module.
    pub(super) fn module_of_rewritten(&self, program: &Program) -> Result<Vec<u8>> {
        let cold = super::unwrap::cold_original(program, &self.opts.name)?;
        let names: Vec<&str> = (0..program.files.len())
            .map(|f| program.file_name(f))
            .collect();
        let files: Vec<(&str, &[u8])> = names
            .iter()
            .zip(&cold)
            .map(|(n, b)| (*n, b.as_slice()))
            .collect();
        let cold = crate::rapid::parse_files(&files)?;
        Ok(self.wrapped(&cold).2)
    }
}

fn rewrite_task(
    plan: &RuntimePlan,
    model: &crate::model::Model,
    task: Task,
    host: &mut dyn Host,
) -> Result<RewrittenTask> {
    let module = plan.module.as_str();
    let made = made(plan, model, &task, host)?;
    let label = &made.label;
    let (inputs, program) = read_task(&task, host)?;
    super::names::check_program_names(&program, module)?;
    let wanted = marker::for_run(&basis(module), label, false, b"");
    if let Some(u) = marker::untrusted(&program) {
        return Err(marker::refuse_untrusted(&program, &u));
    }
    // Any of rapidtherm's lines of a former run, trusted: its marker.
    let found = marker::find(&program);
    if let Some(f) = &found {
        if !f.marker.same_correction(&wanted) {
            return Err(marker::refuse(&program, f, &wanted));
        }
    }
    let (calls, tally, mut text) = made.wrapped(&program);
    if found.is_some() {
        text = made.module_of_rewritten(&program)?;
    }
    let mut rewrites = Vec::with_capacity(program.files.len());
    for (f, calls) in calls.into_iter().enumerate() {
        if calls.is_empty() {
            rewrites.push(None);
            continue;
        }
        if found.is_some() {
            // Moves written after the first rewrite: its marker's
            // fingerprints are of the file as it was then.
            return Err(Error::input(format!(
                "{}: a former --runtime run rewrote this program, and {} target argument(s) of moves were added since; rewrite its cold original",
                program.file_name(f),
                // Two insertions wrap each argument.
                calls.len() / 2
            )));
        }
        // The marker, with the cold file's fingerprint, under the module
        // header; the numbers' fingerprint goes above the last ENDMODULE
        // as the file is written.
        let m = marker::for_run(&basis(module), label, false, program.source(f));
        rewrites.push(Some(FileRewrite {
            calls,
            marker: marker::insert(&program, f, &m),
            sealed: m,
        }));
    }
    let already = found.is_some() && tally.wrapped == 0;
    Ok(RewrittenTask {
        task,
        arm: made.arm.name.clone(),
        inputs,
        rewrites,
        module: (super::module::module_file(module), text),
        tally,
        already,
    })
}
