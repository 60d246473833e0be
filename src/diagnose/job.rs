//! The diagnosis job: a planned diagnosis ([`DiagnosePlan`]) run on its
//! inputs. It reads each input once (the measurements, the model, the
//! URDF, a held-out file), chooses which diagnosis runs (the effect
//! diagnosis, or the general chain's geometric calibration), runs it, and
//! produces what the caller writes: the report's data, the model to save
//! (as its file's text) and the plots. What happens on the way is told to
//! the caller's [`DiagnoseHost`]; the caller renders and writes.

use super::arm::Arm;
use super::chain_calib::Sample;
use super::chain_diagnose::{diagnose_chain, ChainData, ChainDiagnosis, ChainOptions, ChainSetup};
use super::measurements::Measurements;
use super::pipeline::{diagnose, DiagnoseOptions};
use super::plan::{DiagnosePlan, Refused, RobotChoice, Which};
use super::prepare::{place_in_base, problem_of, Prepared};
use super::temps::{as_said, ColdStart, TempOrigin, TempSource};
use super::verdict::Diagnosis;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::robot::{urdf, Robot};
use std::path::Path;

/// What the job tells its caller as it goes.
#[derive(Debug)]
pub enum DiagnoseEvent<'a> {
    /// The arm `--robot` named was read.
    Arm {
        robot: &'a Robot,
        choice: &'a RobotChoice,
    },
    /// The arm's own nominal geometry replaces the model file's.
    GeometryReplaced { arm: &'a str, model: &'a str },
    /// Something the user should know about an input.
    Warning(&'a str),
}

/// The caller's side of a job.
pub trait DiagnoseHost {
    fn event(&mut self, event: DiagnoseEvent);
}

/// Where the nominal geometry comes from when it is not the model's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OwnGeometry {
    Urdf,
    Catalogue,
}

impl OwnGeometry {
    pub fn name(self) -> &'static str {
        match self {
            OwnGeometry::Urdf => "urdf",
            OwnGeometry::Catalogue => "catalogue",
        }
    }
}

/// The arm a command works on: its robot (poses, IK), the diagnosis's
/// arm, and where its nominal geometry comes from.
#[derive(Debug, Clone)]
pub struct Setup {
    pub robot: Robot,
    pub arm: Arm,
    /// `None`: the model's own geometry.
    pub own_geometry: Option<OwnGeometry>,
    /// The URDF's text, where the arm came from a URDF file.
    pub urdf_text: Option<(String, String)>,
}

/// The arm of `choice` (read once), or the model's without one.
pub fn setup(
    choice: Option<&RobotChoice>,
    model: &Model,
    model_file: bool,
    host: &mut dyn DiagnoseHost,
) -> Result<Setup> {
    let Some(choice) = choice else {
        // A model fitted on another arm names it: that arm (read once),
        // not the IRB 140.
        let arm = Arm::of_model(model)?;
        let robot = match model.arm()? {
            Some(named) => named.robot,
            None => Robot::irb140(),
        };
        return Ok(Setup {
            robot,
            arm,
            own_geometry: None,
            urdf_text: None,
        });
    };
    let (robot, arm, own, text) = match choice {
        RobotChoice::Urdf(p) => {
            let name = p.display().to_string();
            let bytes = crate::input::read_path(p)?;
            let text = String::from_utf8(bytes)
                .map_err(|_| Error::input(format!("{name}: a URDF file must be UTF-8")))?;
            let robot = Robot::from_urdf_str(&name, &text)?;
            let arm = Arm::of_urdf_text(&name, &text)?;
            (robot, arm, OwnGeometry::Urdf, Some((name, text)))
        }
        RobotChoice::Catalogue(a) => (
            a.robot(),
            Arm::of_catalogue(a)?,
            OwnGeometry::Catalogue,
            None,
        ),
    };
    host.event(DiagnoseEvent::Arm {
        robot: &robot,
        choice,
    });
    let names_arm = model.robot.urdf.is_some()
        || model.robot.urdf_text.is_some()
        || model.robot.catalogue.is_some();
    // A model naming an arm is replaced whole: its chain is not compared.
    if model_file && (model.robot.opw.as_ref() != arm.nominal.opw() || names_arm) {
        host.event(DiagnoseEvent::GeometryReplaced {
            arm: &arm.source,
            model: &model.robot.name,
        });
    }
    Ok(Setup {
        robot,
        arm,
        own_geometry: Some(own),
        urdf_text: text,
    })
}

/// What a diagnosis job produced.
#[derive(Debug)]
pub enum Diagnosed {
    Effects(Box<EffectRun>),
    Chain(Box<ChainDiagnosis>),
}

/// The effect diagnosis, with what the caller writes.
#[derive(Debug)]
pub struct EffectRun {
    pub diagnosis: Diagnosis,
    pub setup: Setup,
    /// The saved model's file text, where the plan asked for it.
    pub model_toml: Option<String>,
    /// Plots as (file name, SVG text), where the plan asked for them.
    pub plots: Vec<(&'static str, String)>,
}

/// Read a named input whole (`-`: standard input), once.
fn read(path: &Path) -> Result<(String, Vec<u8>)> {
    if path == Path::new("-") {
        Ok(("<stdin>".to_string(), crate::input::read_stdin()?))
    } else {
        Ok((path.display().to_string(), crate::input::read_path(path)?))
    }
}

/// Run `plan`.
pub fn run(
    plan: &DiagnosePlan,
    host: &mut dyn DiagnoseHost,
) -> std::result::Result<Diagnosed, Refused> {
    keep_buffers();
    let mut model = match &plan.model {
        Some(p) => Model::load(p)?,
        None => Model::default(),
    };
    let setup = setup(plan.robot.as_ref(), &model, plan.model.is_some(), host)?;
    // What the arm alone refuses, before the data are read.
    if let Which::Chain { forced: false, .. } = plan.which {
        if setup.robot.opw.is_ok() {
            return Err(Refused::HoldoutOnOpwArm {
                arm: setup.arm.source.clone(),
            });
        }
    }
    let point = measured_point(plan, &setup)?;
    let (name, bytes) = read(&plan.data)?;
    let meas = Measurements::parse(&name, &bytes, &setup.arm.limits_deg)?;
    for w in &meas.warnings {
        host.event(DiagnoseEvent::Warning(w));
    }
    let chain = match &plan.which {
        Which::Effects => false,
        Which::Chain { .. } => true,
        // Temperatures to explain: the effect diagnosis, which runs on
        // any serial chain; without them, on an arm without the OPW form,
        // the geometric calibration (time is then only an order).
        Which::ByData => setup.robot.opw.is_err() && !meas.has_temps(),
    };
    if chain {
        let holdout = match &plan.which {
            Which::Chain {
                holdout: Some(p), ..
            } => {
                let (name, bytes) = read(p)?;
                let h = Measurements::parse(&name, &bytes, &setup.arm.limits_deg)?;
                for w in &h.warnings {
                    host.event(DiagnoseEvent::Warning(w));
                }
                Some(chain_data(&h))
            }
            _ => None,
        };
        let (point, point_name) =
            point.unwrap_or_else(|| (nalgebra::Vector3::zeros(), "tool0".into()));
        let chain_setup = ChainSetup {
            robot: setup.robot.name.clone(),
            chain: setup.robot.chain.clone(),
            point,
            point_name,
        };
        let d = diagnose_chain(
            &chain_setup,
            &chain_data(&meas),
            holdout.as_ref(),
            &ChainOptions::default(),
        )?;
        return Ok(Diagnosed::Chain(Box::new(d)));
    }
    if let Some((point, _)) = point {
        // Where the instrument measured: the diagnosis starts from it, and
        // a saved model keeps it.
        model.robot.point_mm = Some(point.into());
    }
    let mut prepared = problem_of(&meas, &model, &setup.arm)?;
    place_in_base(&mut prepared, &model, plan.register).map_err(Refused::Register)?;
    let opts = DiagnoseOptions {
        noise_mm: plan.noise_mm,
        assume_cold_start: plan.assume_cold_start,
        ..DiagnoseOptions::default()
    };
    let d = diagnose(&prepared, &opts)?;
    let plots = if plan.plot {
        super::plot::plots(&prepared, &d)?
    } else {
        Vec::new()
    };
    let model_toml = match (plan.save_model, &d.saved) {
        (true, Some(s)) => Some(s.model.to_toml()?),
        (true, None) => Some(super::pipeline::diagnosed_model(&model, &d).to_toml()?),
        (false, _) => None,
    };
    Ok(Diagnosed::Effects(Box::new(EffectRun {
        diagnosis: d,
        setup,
        model_toml,
        plots,
    })))
}

/// The measured point the plan names (a URDF link hung on the flange), in
/// tool0 (mm), with its name: from the URDF already read.
fn measured_point(
    plan: &DiagnosePlan,
    setup: &Setup,
) -> std::result::Result<Option<(nalgebra::Vector3<f64>, String)>, Refused> {
    let Some(link) = &plan.point else {
        return Ok(None);
    };
    let Some((name, text)) = &setup.urdf_text else {
        return Err(Refused::Point {
            link: link.clone(),
            error: Error::usage("names a URDF link: give the arm as a URDF file"),
        });
    };
    let arm = urdf::parse(name, text)?;
    let iso = urdf::link_in_tip(name, text, &arm, link).map_err(|error| Refused::Point {
        link: link.clone(),
        error,
    })?;
    // To the nanometre: metres composed through the URDF's joints leave
    // binary dust (0.0899999999999892) that a model file would keep.
    let point = iso.translation.vector.map(|v| (v * 1e6).round() / 1e6);
    Ok(Some((point, link.clone())))
}

/// The measurements as the general chain's calibration takes them.
fn chain_data(meas: &Measurements) -> ChainData {
    ChainData {
        samples: meas
            .rows
            .iter()
            .map(|r| Sample {
                q: r.joints,
                position: r.position,
            })
            .collect(),
        times_min: meas.rows.iter().map(|r| r.time_min).collect(),
        poses: meas
            .rows
            .iter()
            .enumerate()
            .map(|(i, r)| r.pose.clone().unwrap_or_else(|| format!("#{}", i + 1)))
            .collect(),
        has_temps: meas.has_temps(),
    }
}

/// `gap`: the measurements prepared under a model and its arm, placed in
/// the base frame (registered anew, or by the model's instrument frame),
/// as the diagnosis scores its saved model.
pub fn gap_of(
    data: &Path,
    model: &Model,
    setup: &Setup,
    register: bool,
    cold_start: Option<ColdStart>,
    host: &mut dyn DiagnoseHost,
) -> std::result::Result<Prepared, Refused> {
    let (name, bytes) = read(data)?;
    let meas = Measurements::parse(&name, &bytes, &setup.arm.limits_deg)?;
    for w in &meas.warnings {
        host.event(DiagnoseEvent::Warning(w));
    }
    let mut prepared = problem_of(&meas, model, &setup.arm)?;
    // The diagnosis's rule (`temps::as_said`): a warm-up the file does not
    // show is assumed only where the caller says so, and either way it is
    // said. So the gap of a saved model is the diagnosis's "after".
    let source = as_said(&mut prepared.problem, &prepared.temps, cold_start)?;
    if let TempOrigin::Profile(_) = &prepared.temps {
        host.event(DiagnoseEvent::Warning(&match source {
            TempSource::AssumedColdStart { profile } => format!(
                "{name}: no temperature columns; assumed, as asked: the session starts cold at its first row and follows the `{profile}` warm-up"
            ),
            _ => format!(
                "{name}: no temperature columns; every row is held at the reference temperature, no warm-up assumed (`--assume-cold-start irb140` assumes the IRB 140's from a cold start at the first row)"
            ),
        }));
    }
    place_in_base(&mut prepared, model, register).map_err(Refused::Register)?;
    Ok(prepared)
}

/// A diagnosis makes and drops millions of buffers of a few hundred kB
/// (a residual or a Jacobian column of 10,000 rows is 240 kB): with the
/// process's threshold of 128 kB (`src/main.rs`, for the correction's
/// peak) each was mapped afresh, faulted in page by page and unmapped, a
/// third of the diagnosis's CPU time spent in the kernel. Buffers below
/// 16 MB are kept in the heap and reused instead; the diagnosis's peak is
/// its data's, a few times the CSV.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_buffers() {
    // SAFETY: mallopt sets tunables of glibc's allocator under its own
    // lock; it takes no pointers.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 16 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 16 << 20);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_buffers() {}
