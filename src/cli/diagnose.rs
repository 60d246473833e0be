//! `diagnose`: argument parsing and printing only; what `gap` and
//! `simulate` share with it (the arm, the model, the job's messages).

use super::diagnose_args::{parameter_table, DiagnoseArgs};
use super::messages::{info, note, warning};
use super::Format;
use super::{write_stdout, Status};
use rapidtherm::diagnose::arm::Arm;
use rapidtherm::diagnose::job::{self, DiagnoseEvent, DiagnoseHost, Diagnosed, OwnGeometry};
use rapidtherm::diagnose::plan::{DiagnosePlan, Refused, RobotChoice, Which};
use rapidtherm::diagnose::prose::{self, Remedies};
use rapidtherm::diagnose::unidentified::Unidentified;
use rapidtherm::diagnose::{self, Diagnosis, RegisterFailure, ScoredIn};
use rapidtherm::error::{Error, Result};
use rapidtherm::model::Model;
use rapidtherm::report::{render_csv, render_table, Align};
use rapidtherm::writes::{Checked, Made, Plan, Role};
use std::path::{Path, PathBuf};

pub(super) fn load_model(path: &Option<PathBuf>) -> Result<Model> {
    match path {
        Some(p) => super::correct::load_model(Some(p)),
        None => Ok(Model::default()),
    }
}

/// The host of a diagnosis job: its events as this command line's
/// messages.
pub(super) struct Messages;

impl DiagnoseHost for Messages {
    fn event(&mut self, event: DiagnoseEvent) {
        match event {
            DiagnoseEvent::Arm { robot, choice } => {
                let from = match choice {
                    RobotChoice::Urdf(p) => {
                        format!("from the URDF file {}, chosen by --robot", p.display())
                    }
                    RobotChoice::Catalogue(a) => {
                        format!("from the catalogue, chosen by --robot {}", a.name)
                    }
                };
                info!("arm {} ({from})", robot.name);
            }
            DiagnoseEvent::GeometryReplaced { arm, model } => {
                note!("the geometry of {arm} replaces the model's [robot] geometry ({model})")
            }
            DiagnoseEvent::Warning(w) => warning!("{w}"),
        }
    }
}

/// `--robot` as the plan's arm: a URDF file, or a catalogue arm looked up
/// now (a name it lacks is a usage error before any input is read).
pub(super) fn robot_choice(arg: &Option<PathBuf>) -> Result<Option<RobotChoice>> {
    let Some(p) = arg else {
        return Ok(None);
    };
    if super::arms::is_file(p) {
        return Ok(Some(RobotChoice::Urdf(p.clone())));
    }
    Ok(Some(RobotChoice::Catalogue(super::arms::find_arm(
        &p.display().to_string(),
    )?)))
}

/// A refused job in this command line's words (`robot`: as `--robot`
/// named the arm).
pub(super) fn refused(r: Refused, robot: Option<&Path>) -> Error {
    match r {
        Refused::Error(e) => e,
        Refused::Register(f) => register_error(f),
        Refused::HoldoutOnOpwArm { arm } => Error::usage(format!(
            "--holdout is the general chain's calibration: {} has the OPW form, add --chain",
            robot.map_or(arm, |p| p.display().to_string())
        )),
        Refused::Point { link, error } => {
            Error::usage(format!("--point {link}: {}", error.message))
        }
    }
}

/// The diagnosis's remedies, named by this command line's flags.
fn remedies() -> Remedies {
    Remedies {
        give_noise: "give --noise".into(),
        save_model: "Save the model with --save-model FILE.toml".into(),
    }
}

fn register_error(f: RegisterFailure) -> Error {
    Error::input(format!("--register{}", f.reason()))
}

/// The diagnosis as JSON: its data, then its sentences (`words`).
#[derive(serde::Serialize)]
struct WithWords<'a> {
    #[serde(flatten)]
    diagnosis: &'a Diagnosis,
    words: Vec<String>,
}

impl<'a> WithWords<'a> {
    fn of(d: &'a Diagnosis) -> WithWords<'a> {
        WithWords {
            diagnosis: d,
            words: prose::words(d, &remedies()),
        }
    }
}

/// The outputs of a diagnosis, checked before anything is read or
/// written: a model file or a plot that would replace an input, or a
/// file it did not write, a plot folder that cannot be made.
fn check_diagnose_outputs(args: &DiagnoseArgs) -> Result<Checked> {
    if let Some(dir) = &args.plot {
        super::output::check_folder("--plot", dir)?;
    }
    if let Some(path) = &args.save_model {
        super::output::check_file("--save-model", path)?;
    }
    let mut writes = Plan::new(args.force);
    for f in [Some(args.data.as_path())]
        .into_iter()
        .chain([
            args.model.as_deref(),
            args.robot.as_deref(),
            args.holdout.as_deref(),
        ])
        .flatten()
    {
        writes.input(f);
    }
    if let Some(dir) = &args.plot {
        let flag = format!("--plot {}", dir.display());
        for name in diagnose::plot::FILES {
            writes.output(&flag, &dir.join(name), Role::Made(Made::Picture));
        }
    }
    if let Some(path) = &args.save_model {
        writes.output("--save-model", path, Role::Named);
    }
    super::output::check(&writes)
}

/// The robot's own nominal geometry (a URDF's or a catalogue arm's), which
/// replaces the model's.
fn robot_words(arm: &Arm, from: &str) -> String {
    let from = if from == "urdf" {
        "the URDF"
    } else {
        "the catalogue"
    };
    let Some(o) = arm.nominal.opw() else {
        let [lower, upper] = arm.nominal.arm_lengths();
        return format!(
            "robot: {} ({}); nominal geometry from {from}, not the model: a serial chain without the OPW form, lower arm {lower:.3} mm, upper arm {upper:.3} mm, in the URDF's joint convention\n",
            arm.name, arm.source
        );
    };
    format!(
        "robot: {} ({}); nominal geometry from {from}, not the model: a1 {:.3}, a2 {:.3}, b {:.3}, c1 {:.3}, c2 {:.3}, c3 {:.3}, c4 {:.3} mm\n",
        arm.name, arm.source, o.a1, o.a2, o.b, o.c1, o.c2, o.c3, o.c4
    )
}

fn robot_json(arm: &Arm, from: &str) -> serde_json::Value {
    let opw = arm.nominal.opw().map(|o| {
        serde_json::json!({"a1": o.a1, "a2": o.a2, "b": o.b, "c1": o.c1, "c2": o.c2, "c3": o.c3, "c4": o.c4})
    });
    serde_json::json!({
        "name": arm.name,
        "source": arm.source,
        "nominal_geometry": from,
        "opw_mm": opw,
    })
}

pub(super) fn registration_words(r: &diagnose::Registration) -> String {
    format!(
        "instrument frame: translation ({:.3}, {:.3}, {:.3}) mm, rotation vector ({:.4}, {:.4}, {:.4})°, rigid-fit RMS {:.4} mm over {} rows\n",
        r.translation_mm[0],
        r.translation_mm[1],
        r.translation_mm[2],
        r.rotation_deg[0],
        r.rotation_deg[1],
        r.rotation_deg[2],
        r.rms_mm,
        r.rows_used
    )
}

/// The diagnosis the arguments ask for, every usage error raised before
/// any input is read.
fn diagnose_plan(args: &DiagnoseArgs) -> Result<DiagnosePlan> {
    if let Some(v) = args.noise {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::usage("--noise must be a positive number of mm"));
        }
    }
    if args.robot.is_none() && (args.chain || args.holdout.is_some() || args.point.is_some()) {
        return Err(Error::usage(
            "--chain, --point and --holdout need --robot FILE.urdf",
        ));
    }
    if let (Some(link), Some(p)) = (&args.point, &args.robot) {
        if !super::arms::is_file(p) {
            return Err(Error::usage(format!(
                "--point {link} names a URDF link: give --robot as a URDF file"
            )));
        }
    }
    let effects_asked = [
        (args.model.is_some(), "--model"),
        (args.save_model.is_some(), "--save-model"),
        (args.plot.is_some(), "--plot"),
        (args.noise.is_some(), "--noise"),
        (args.assume_cold_start.is_some(), "--assume-cold-start"),
    ];
    let which = if args.chain || args.holdout.is_some() {
        if let (Some((_, flag)), Some(p)) =
            (effects_asked.iter().find(|(given, _)| *given), &args.robot)
        {
            return Err(Error::usage(format!(
                "{flag} is not available in the general chain's diagnosis (geometric calibration of {}) yet",
                p.display()
            )));
        }
        Which::Chain {
            forced: args.chain,
            holdout: args.holdout.clone(),
        }
    } else if effects_asked.iter().any(|(given, _)| *given) {
        Which::Effects
    } else {
        Which::ByData
    };
    Ok(DiagnosePlan {
        data: args.data.clone(),
        model: args.model.clone(),
        robot: robot_choice(&args.robot)?,
        which,
        noise_mm: args.noise,
        assume_cold_start: args.assume_cold_start,
        register: args.register,
        point: args.point.clone(),
        save_model: args.save_model.is_some(),
        plot: args.plot.is_some(),
    })
}

/// Everything `diagnose` does, read from its arguments once: the
/// library's plan and what the command line does around it. Once it is
/// made, the arguments are not read again.
pub struct DiagnoseCommand {
    plan: DiagnosePlan,
    /// The outputs, checked against the inputs before any is read.
    checked: Checked,
    /// `--robot` as given, for the words of a refusal.
    robot: Option<PathBuf>,
    format: Format,
    plot: Option<PathBuf>,
    save_model: Option<PathBuf>,
}

/// The plan of `diagnose`'s arguments, its outputs checked: every usage
/// error is raised here, before any input is read.
pub fn plan(args: DiagnoseArgs) -> Result<DiagnoseCommand> {
    let plan = diagnose_plan(&args)?;
    let checked = check_diagnose_outputs(&args)?;
    Ok(DiagnoseCommand {
        plan,
        checked,
        robot: args.robot,
        format: args.format,
        plot: args.plot,
        save_model: args.save_model,
    })
}

pub fn run(cmd: DiagnoseCommand) -> Result<Status> {
    let (plan, checked) = (&cmd.plan, &cmd.checked);
    let run = match job::run(plan, &mut Messages).map_err(|r| refused(r, cmd.robot.as_deref()))? {
        Diagnosed::Chain(d) => {
            let text = super::diagnose_chain::render(cmd.format, &d)?;
            write_stdout(text.as_bytes())?;
            return Ok(Status::Success);
        }
        Diagnosed::Effects(run) => run,
    };
    let d = &run.diagnosis;
    if let Some(dir) = &cmd.plot {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, &e))?;
        for (name, svg) in &run.plots {
            let path = dir.join(name);
            super::output::write_atomic(checked, &path, svg.as_bytes(), None)?;
        }
    }
    if let (Some(path), Some(text)) = (&cmd.save_model, &run.model_toml) {
        super::output::write_atomic(checked, path, text.as_bytes(), None)?;
    }
    let own = run.setup.own_geometry.map(OwnGeometry::name);
    let arm = &run.setup.arm;
    let text = match cmd.format {
        Format::Json => {
            use rapidtherm::report::json::document;
            if let Some(from) = own {
                // Flattened so the diagnosis keeps its field order.
                #[derive(serde::Serialize)]
                struct WithRobot<'a> {
                    robot: serde_json::Value,
                    #[serde(flatten)]
                    diagnosis: WithWords<'a>,
                }
                document(
                    "diagnose",
                    &WithRobot {
                        robot: robot_json(arm, from),
                        diagnosis: WithWords::of(d),
                    },
                )?
            } else {
                document("diagnose", &WithWords::of(d))?
            }
        }
        Format::Csv => candidate_csv(d),
        Format::Table => {
            let mut s = String::new();
            if let Some(from) = own {
                s.push_str(&robot_words(arm, from));
            }
            s.push_str(&diagnosis_table(d));
            s
        }
    };
    write_stdout(text.as_bytes())?;
    Ok(Status::Success)
}

fn candidate_rows(d: &Diagnosis, staged: bool) -> Vec<Vec<String>> {
    let mut c = d.candidates.clone();
    // Stage by stage (a stable sort keeps their order), best first.
    c.sort_by(|a, b| a.cv_rms_mm.total_cmp(&b.cv_rms_mm));
    if staged {
        c.sort_by_key(|c| c.part == ScoredIn::Static);
    }
    c.iter()
        .map(|c| {
            let mut row = vec![c.name.clone()];
            if staged {
                row.push(c.part.name().to_string());
            }
            row.extend([
                if c.cv_rms_mm.is_finite() {
                    format!("{:.4}", c.cv_rms_mm)
                } else {
                    "-".into()
                },
                if c.error.is_some() {
                    "-".into()
                } else {
                    format!("{:.0}", 100.0 * c.explained.max(0.0))
                },
                if c.selected {
                    "yes".into()
                } else {
                    String::new()
                },
                c.error.clone().unwrap_or_default(),
            ]);
            row
        })
        .collect()
}

fn candidate_csv(d: &Diagnosis) -> String {
    render_csv(
        &[
            "effect",
            "part",
            "heldout_rms_mm",
            "explained_pct",
            "selected",
            "note",
        ],
        &candidate_rows(d, true),
    )
}

fn diagnosis_table(d: &Diagnosis) -> String {
    let mut s = String::new();
    if let Some(r) = &d.registration {
        s.push_str(&registration_words(r));
    }
    for w in prose::words(d, &remedies()) {
        s.push_str(&w);
        s.push('\n');
    }
    s.push('\n');
    let staged = d.stages.len() > 1;
    if staged {
        let parts: Vec<&str> = d
            .stages
            .iter()
            .map(|st| match st.part {
                ScoredIn::OverTime => {
                    "over time with each pose's own offset fitted (held out by time span)"
                }
                ScoredIn::Absolute => {
                    "absolute on top of the static effects found (held out by pose and time)"
                }
                ScoredIn::Static | ScoredIn::All => {
                    "static with the thermal effects found fitted (held out by pose and time)"
                }
            })
            .collect();
        s.push_str(&format!(
            "Each effect alone, scored on held-out data: {}:\n",
            parts.join("; ")
        ));
    } else {
        s.push_str("Each effect alone, scored on held-out times and poses:\n");
    }
    let mut header = vec!["effect"];
    let mut align = vec![Align::Left];
    if staged {
        header.push("part");
        align.push(Align::Left);
    }
    header.extend(["held-out RMS mm", "explained %", "selected", "note"]);
    align.extend([Align::Right, Align::Right, Align::Left, Align::Left]);
    s.push_str(&render_table(&header, &align, &candidate_rows(d, staged)));
    let selected: Vec<_> = d.candidates.iter().filter(|c| c.selected).collect();
    if !selected.is_empty() {
        s.push_str("\nFitted parameters (± standard error):\n");
        s.push_str(&parameter_table(
            selected
                .iter()
                .flat_map(|c| c.params.iter())
                .map(|p| (p.name.as_str(), p.value, p.stderr, p.unit.as_str())),
        ));
        // A parameter taken beyond what a real arm has, or traded against
        // a few others: its reason, so that its zero is not read as a
        // finding (every held parameter's reason is in the JSON).
        let told: Vec<String> = selected
            .iter()
            .flat_map(|c| c.params.iter())
            .filter_map(|p| {
                let why = p.held.as_ref()?;
                let clear = match why {
                    Unidentified::Implausible { .. } | Unidentified::AtBound { .. } => true,
                    Unidentified::SameAs { same_as, .. } => (1..=3).contains(&same_as.len()),
                    _ => false,
                };
                clear.then(|| {
                    format!(
                        "  {}: held at {:.4} {}: {}\n",
                        p.name,
                        p.value,
                        p.unit,
                        super::diagnose_chain::held_words(why, &p.unit)
                    )
                })
            })
            .collect();
        if !told.is_empty() {
            s.push_str(
                "Not identifiable from these data (held, not fitted, at the value given):\n",
            );
            s.extend(told);
        }
    }
    s.push_str(&format!(
        "\nHeld-out gap: {:.4} mm before, {:.4} mm after ({:.0} % smaller).\n",
        d.gap_before_mm,
        d.gap_after_mm,
        100.0 * (1.0 - d.gap_after_mm / d.gap_before_mm.max(1e-300))
    ));
    s
}

/// Fitted parameters as a table: name, value, standard error ("not
/// identifiable" where the data could not pin it), unit.
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn register_failures_name_the_flag() {
        assert_eq!(
            register_error(RegisterFailure::TooFewPoses).message,
            "--register needs at least 3 measured poses"
        );
        assert_eq!(
            register_error(RegisterFailure::NoFrame).message,
            "--register: the measured points do not fix a frame"
        );
        assert_eq!(
            register_error(RegisterFailure::NotSpread).message,
            "--register needs poses spread in 3-D (these lie on a line or a plane)"
        );
    }
}
