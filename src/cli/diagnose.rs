//! `simulate`, `diagnose` and `gap`: argument parsing and printing only.

use super::diagnose_args::{parameter_table, DiagnoseArgs};
use super::messages::{info, note, outcome, status, warning};
use super::Format;
use super::{read_input, write_output, write_stdout, Status};
use rapidtherm::csv_table::CsvTable;
use rapidtherm::diagnose::arm::Arm;
use rapidtherm::diagnose::job::{self, DiagnoseEvent, DiagnoseHost, Diagnosed, OwnGeometry};
use rapidtherm::diagnose::plan::{DiagnosePlan, Refused, RobotChoice, Which};
use rapidtherm::diagnose::prose::{self, Remedies};
use rapidtherm::diagnose::simulate::{
    iso_cube_poses, program_poses, random_poses, simulate_arm, SimSpec,
};
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::unidentified::Unidentified;
use rapidtherm::diagnose::{self, Diagnosis, RegisterFailure, ScoredIn};
use rapidtherm::error::{Error, ErrorKind, Result};
use rapidtherm::model::effects::Effect;
use rapidtherm::model::Model;
use rapidtherm::report::{render_csv, render_table, Align};
use rapidtherm::writes::{Checked, Made, Plan, Role};
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TempsSource {
    /// Write t1_c..t6_c columns.
    Measured,
    /// Leave temperatures to the reader's heating profile.
    Profile,
}

#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Poses: `random:N` (uniform within the joint limits), `joints:FILE.csv`
    /// (columns j1_deg..j6_deg, optional pose), `iso-cube` or `program:FILE`.
    #[arg(long, default_value = "random:12")]
    poses: String,
    /// Minutes since the cold start: START:END:STEP or a comma list.
    #[arg(long, default_value = "0:180:6")]
    times: String,
    /// An effect to add, `NAME[:param=value,...]` (repeatable).
    #[arg(long = "effect", value_name = "NAME[:P=V,...]")]
    effects: Vec<String>,
    /// Tracker noise, mm per axis.
    #[arg(long, default_value_t = 0.01)]
    noise: f64,
    /// Also write the measured orientation (qw, qx, qy, qz).
    #[arg(long)]
    orientation: bool,
    /// Write motor temperatures, or leave them to the heating profile.
    #[arg(long, value_enum, default_value_t = TempsSource::Profile)]
    temps: TempsSource,
    /// Random seed (poses and noise).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The model the "real" robot departs from (default: nominal IRB 140).
    #[arg(long)]
    model: Option<PathBuf>,
    /// An arm with an offset shoulder and a spherical wrist, by name
    /// (`rapidtherm arms`) or URDF file; its lengths replace the model's
    /// geometry.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    robot: Option<PathBuf>,
    /// Output CSV (`-`: standard output).
    #[arg(short = 'o', long = "output", default_value = "-")]
    output: PathBuf,
}

#[derive(clap::Args)]
pub struct GapArgs {
    /// Measurements CSV (`-`: standard input).
    data: PathBuf,
    #[arg(long)]
    model: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
    /// First fit the rigid transform from the instrument's frame to the robot base.
    #[arg(long)]
    register: bool,
    /// The arm, by name (`rapidtherm arms`) or URDF file.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    robot: Option<PathBuf>,
    /// Exit with status 1 when the RMS gap exceeds this many mm (a gate for scripts).
    #[arg(long, value_name = "MM")]
    fail_above: Option<f64>,
    /// Data without temperature columns: assume the session starts cold at its first row and follows this warm-up (`irb140`); without it every row is held at the reference temperature, as the diagnosis holds them
    #[arg(long, value_name = "PROFILE", value_parser = super::diagnose_args::cold_start)]
    assume_cold_start: Option<ColdStart>,
}

fn load_model(path: &Option<PathBuf>) -> Result<Model> {
    match path {
        Some(p) => super::correct::load_model(Some(p)),
        None => Ok(Model::default()),
    }
}

/// The host of a diagnosis job: its events as this command line's
/// messages.
struct Messages;

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
fn robot_choice(arg: &Option<PathBuf>) -> Result<Option<RobotChoice>> {
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
fn refused(r: Refused, robot: Option<&Path>) -> Error {
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

fn read_poses(spec: &str, seed: u64, setup: &job::Setup) -> Result<Vec<(String, [f64; 6])>> {
    let limits = &setup.arm.limits_deg;
    if let Some(n) = spec.strip_prefix("random:") {
        let n: usize = n
            .parse()
            .ok()
            .filter(|&n| n > 0 && n <= 100_000)
            .ok_or_else(|| Error::usage(format!("--poses {spec}: N must be 1..100000")))?;
        return Ok(random_poses(n, limits, seed));
    }
    if let Some(file) = spec.strip_prefix("joints:") {
        let (name, bytes) = read_input(Path::new(file))?;
        let table = CsvTable::parse(&name, &bytes)?;
        let cols: Vec<usize> = (1..=6)
            .map(|i| table.require(&format!("j{i}_deg")))
            .collect::<Result<_>>()?;
        let label = table.column("pose");
        let mut out = Vec::new();
        for (k, row) in table.rows.iter().enumerate() {
            let mut q = [0.0; 6];
            for i in 0..6 {
                let v = table.number(row, cols[i])?;
                let (lo, hi) = limits[i];
                if v < lo || v > hi {
                    return Err(Error::input(format!(
                        "axis {} at {v}° is outside {lo}..{hi}°",
                        i + 1
                    ))
                    .at(table.field_location(row, cols[i])));
                }
                q[i] = v.to_radians();
            }
            let name = match label {
                Some(c) => table.text(row, c)?.to_string(),
                None => format!("P{}", k + 1),
            };
            out.push((name, q));
        }
        if out.is_empty() {
            return Err(Error::input(format!("{name}: no poses")));
        }
        return Ok(out);
    }
    if spec == "iso-cube" {
        return iso_cube_poses(&setup.robot, &setup.arm.iso_cube()?);
    }
    if let Some(file) = spec.strip_prefix("program:") {
        let (name, bytes) = read_input(Path::new(file))?;
        let program = rapidtherm::rapid::parse(&name, &bytes)?;
        return program_poses(&program, &setup.robot);
    }
    Err(Error::usage(format!(
        "--poses `{spec}`: expected random:N, joints:FILE.csv, iso-cube or program:FILE"
    )))
}

/// Parse `--times`: `START:END:STEP` (inclusive) or a comma list of
/// minutes.
fn parse_times(text: &str) -> Result<Vec<f64>> {
    let bad = || {
        Error::usage(format!(
            "--times `{text}`: expected START:END:STEP or a comma list of minutes"
        ))
    };
    let num = |s: &str| -> Result<f64> {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(bad)
    };
    let parts: Vec<&str> = text.split(':').collect();
    let times: Vec<f64> = match parts.as_slice() {
        [a, b, c] => {
            let (start, end, step) = (num(a)?, num(b)?, num(c)?);
            if step <= 0.0 || end < start {
                return Err(bad());
            }
            let n = ((end - start) / step + 1e-9).floor() as usize;
            if n > 1_000_000 {
                return Err(Error::usage("--times: too many times"));
            }
            (0..=n).map(|i| start + i as f64 * step).collect()
        }
        [list] => list.split(',').map(num).collect::<Result<_>>()?,
        _ => return Err(bad()),
    };
    if times.is_empty() || times.iter().any(|&t| t < 0.0) || times.windows(2).any(|w| w[1] < w[0]) {
        return Err(Error::usage(format!(
            "--times `{text}`: minutes must be >= 0 and increasing"
        )));
    }
    Ok(times)
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

pub fn run_simulate(args: SimulateArgs) -> Result<Status> {
    if !(args.noise.is_finite() && args.noise >= 0.0) {
        return Err(Error::usage("--noise must be a finite number >= 0"));
    }
    // Every output checked before anything is read or written.
    let poses_file = ["joints:", "program:"]
        .iter()
        .find_map(|p| args.poses.strip_prefix(p))
        .map(Path::new);
    let inputs: Vec<&Path> = poses_file
        .into_iter()
        .chain(args.model.as_deref())
        .chain(args.robot.as_deref())
        .collect();
    super::output::check_file("-o", &args.output)?;
    diagnose::simulate::check_noise(args.noise)?;
    let mut writes = Plan::new(false);
    for f in inputs {
        writes.input(f);
    }
    writes.output("-o", &args.output, Role::Named);
    let checked = super::output::check(&writes)?;
    let model = load_model(&args.model)?;
    let mut effects = model.effects()?;
    for spec in &args.effects {
        effects.push(Effect::parse_spec(spec)?);
    }
    let setup = job::setup(
        robot_choice(&args.robot)?.as_ref(),
        &model,
        args.model.is_some(),
        &mut Messages,
    )?;
    let spec = SimSpec {
        base: setup.arm.base(&model),
        poses: read_poses(&args.poses, args.seed, &setup)?,
        times: parse_times(&args.times)?,
        effects,
        noise_mm: args.noise,
        orientation: args.orientation,
        measured_temps: args.temps == TempsSource::Measured,
        seed: args.seed,
    };
    let profile = model.profile()?;
    let meas = simulate_arm(&spec, &setup.arm.map, profile.as_ref())?;
    write_output(&checked, &args.output, meas.to_csv().as_bytes())?;
    Ok(Status::Success)
}

pub fn run_gap(args: GapArgs) -> Result<Status> {
    // A usage error before any file is read.
    if let Some(limit) = args.fail_above {
        if !(limit.is_finite() && limit >= 0.0) {
            return Err(Error::usage("--fail-above must be a number of mm >= 0"));
        }
    }
    let robot = robot_choice(&args.robot)?;
    let model = load_model(&args.model)?;
    let setup = job::setup(robot.as_ref(), &model, args.model.is_some(), &mut Messages)?;
    let prepared = job::gap_of(
        &args.data,
        &model,
        &setup,
        args.register,
        args.assume_cold_start,
        &mut Messages,
    )
    .map_err(|r| refused(r, args.robot.as_deref()))?;
    let g = diagnose::gap(&prepared);
    let text = match args.format {
        Format::Json => {
            let mut v = serde_json::json!({"rms_mm": g.rms_mm, "max_mm": g.max_mm, "n": g.n});
            if let Some((rms, max)) = diagnose::orientation_gap(&prepared) {
                v["rot_rms_mrad"] = rms.into();
                v["rot_max_mrad"] = max.into();
            }
            if let Some(r) = &prepared.registration {
                v["registration"] = serde_json::to_value(r).unwrap_or_default();
            }
            format!("{v}\n")
        }
        Format::Csv => render_csv(
            &["rms_mm", "max_mm", "n"],
            &[vec![
                format!("{:.5}", g.rms_mm),
                format!("{:.5}", g.max_mm),
                g.n.to_string(),
            ]],
        ),
        Format::Table => {
            let mut s = String::new();
            if let Some(r) = &prepared.registration {
                s.push_str(&registration_words(r));
            }
            s.push_str(&format!(
                "gap: {:.4} mm RMS, {:.4} mm max over {} rows\n",
                g.rms_mm, g.max_mm, g.n
            ));
            if let Some((rms, max)) = diagnose::orientation_gap(&prepared) {
                s.push_str(&format!(
                    "orientation gap: {rms:.4} mrad RMS, {max:.4} mrad max\n"
                ));
            }
            s
        }
    };
    write_stdout(text.as_bytes())?;
    match args.fail_above {
        // A gap that is not a number never passes the gate: nothing was
        // shown to be within it.
        Some(limit) if g.rms_mm.is_nan() => {
            outcome!("gap is not a number: it is not within {limit} mm");
            Ok(Status::Changes)
        }
        Some(limit) if g.rms_mm > limit => {
            outcome!("gap {:.4} mm RMS is above {limit} mm", g.rms_mm);
            Ok(Status::Changes)
        }
        _ => Ok(Status::Success),
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

fn registration_words(r: &diagnose::Registration) -> String {
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
fn plan(args: &DiagnoseArgs) -> Result<DiagnosePlan> {
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
struct DiagnoseCommand {
    plan: DiagnosePlan,
    /// The outputs, checked against the inputs before any is read.
    checked: Checked,
    /// `--robot` as given, for the words of a refusal.
    robot: Option<PathBuf>,
    format: Format,
    plot: Option<PathBuf>,
    save_model: Option<PathBuf>,
}

fn command(args: DiagnoseArgs) -> Result<DiagnoseCommand> {
    let plan = plan(&args)?;
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

pub fn run_diagnose(args: DiagnoseArgs) -> Result<Status> {
    // The arguments are spent here: what follows reads the plan alone.
    let cmd = command(args)?;
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
            status!("wrote {}", path.display());
        }
    }
    if let (Some(path), Some(text)) = (&cmd.save_model, &run.model_toml) {
        super::output::write_atomic(checked, path, text.as_bytes(), None)?;
        status!("wrote {}", path.display());
    }
    let own = run.setup.own_geometry.map(OwnGeometry::name);
    let arm = &run.setup.arm;
    let text = match cmd.format {
        Format::Json => {
            let json_err = |e: serde_json::Error| {
                Error::new(ErrorKind::Input, format!("cannot write JSON: {e}"))
            };
            let v = if let Some(from) = own {
                // Flattened so the diagnosis keeps its field order.
                #[derive(serde::Serialize)]
                struct WithRobot<'a> {
                    robot: serde_json::Value,
                    #[serde(flatten)]
                    diagnosis: WithWords<'a>,
                }
                serde_json::to_string_pretty(&WithRobot {
                    robot: robot_json(arm, from),
                    diagnosis: WithWords::of(d),
                })
                .map_err(json_err)?
            } else {
                serde_json::to_string_pretty(&WithWords::of(d)).map_err(json_err)?
            };
            format!("{v}\n")
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
    fn times_parse() {
        assert_eq!(parse_times("0:12:6").unwrap(), vec![0.0, 6.0, 12.0]);
        assert_eq!(parse_times("0,5,7.5").unwrap(), vec![0.0, 5.0, 7.5]);
        assert!(parse_times("0:10:-1").is_err());
        assert!(parse_times("5,1").is_err());
    }

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
