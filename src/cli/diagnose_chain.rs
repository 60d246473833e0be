//! `diagnose` on a general serial chain (an arm without the OPW form, or
//! any arm with `--chain`): argument checks and printing only; the work is
//! `rapidtherm::diagnose::chain_diagnose`.

use super::diagnose_args::{parameter_table, DiagnoseArgs};
use super::messages::warning;
use super::Format;
use super::{read_input, write_stdout, Status};
use rapidtherm::diagnose::chain_calib::{Dropped, Sample, Unidentified};
use rapidtherm::diagnose::chain_diagnose::{
    diagnose_chain, ChainData, ChainDiagnosis, ChainOptions, ChainSetup,
};
use rapidtherm::diagnose::measurements::Measurements;
use rapidtherm::error::{Error, ErrorKind, Result};
use rapidtherm::report::{render_csv, render_table, Align};
use rapidtherm::robot::{urdf, Robot};
use std::path::Path;

/// The chain setup when this diagnosis is the general chain's geometric
/// calibration: `--chain` or `--holdout` ask for it, or the arm
/// has no OPW form and nothing asks for the effects (no temperatures in
/// the data, no model given or to save). `None`: the effect diagnosis.
pub fn chain_setup(
    args: &DiagnoseArgs,
    name: &str,
    bytes: &[u8],
) -> Result<Option<(ChainSetup, Robot)>> {
    let general_only = args.holdout.is_some();
    let Some(p) = &args.robot else {
        if args.chain || general_only || args.point.is_some() {
            return Err(Error::usage(
                "--chain, --point and --holdout need --robot FILE.urdf",
            ));
        }
        return Ok(None);
    };
    let robot = super::arms::load_robot(Some(p))?;
    if robot.opw.is_ok() && !args.chain {
        if general_only {
            return Err(Error::usage(format!(
                "--holdout is the general chain's calibration: {} has the OPW form, add --chain",
                p.display()
            )));
        }
        return Ok(None);
    }
    let effects_asked = args.model.is_some()
        || args.save_model.is_some()
        || args.plot.is_some()
        || args.noise.is_some()
        || args.assume_cold_start.is_some();
    if !args.chain && !general_only && (effects_asked || has_temps(name, bytes, &robot)?) {
        // Temperatures to explain, or a model to fit: the effect diagnosis,
        // which runs on any serial chain.
        return Ok(None);
    }
    for (given, flag) in [
        (args.model.is_some(), "--model"),
        (args.save_model.is_some(), "--save-model"),
        (args.plot.is_some(), "--plot"),
        (args.noise.is_some(), "--noise"),
    ] {
        if given {
            return Err(Error::usage(format!(
                "{flag} is not available in the general chain's diagnosis (geometric calibration of {}) yet",
                p.display()
            )));
        }
    }
    let (point, point_name) =
        measured_point(args)?.unwrap_or_else(|| (nalgebra::Vector3::zeros(), "tool0".to_string()));
    Ok(Some((
        ChainSetup {
            robot: robot.name.clone(),
            chain: robot.chain.clone(),
            point,
            point_name,
        },
        robot,
    )))
}

/// The URDF link `--point` names, in tool0 (mm), with its name.
pub fn measured_point(args: &DiagnoseArgs) -> Result<Option<(nalgebra::Vector3<f64>, String)>> {
    let Some(link) = &args.point else {
        return Ok(None);
    };
    let p = match &args.robot {
        Some(p) if super::arms::is_file(p) => p,
        _ => {
            return Err(Error::usage(format!(
                "--point {link} names a URDF link: give --robot as a URDF file"
            )))
        }
    };
    let (name, bytes) = read_input(p)?;
    let text = String::from_utf8_lossy(&bytes);
    let arm = urdf::parse(&name, &text)?;
    let iso = urdf::link_in_tip(&name, &text, &arm, link)
        .map_err(|e| Error::usage(format!("--point {link}: {}", e.message)))?;
    // To the nanometre: metres composed through the URDF's joints leave
    // binary dust (0.0899999999999892) that a model file would keep.
    let point = iso.translation.vector.map(|v| (v * 1e6).round() / 1e6);
    Ok(Some((point, link.clone())))
}

fn read_data(path: &Path, robot: &Robot) -> Result<ChainData> {
    let (name, bytes) = read_input(path)?;
    parse_data(&name, &bytes, robot)
}

fn limits_deg(robot: &Robot) -> [(f64, f64); 6] {
    robot
        .limits
        .map(|(lo, hi)| (lo.to_degrees(), hi.to_degrees()))
}

/// Whether the data carry motor temperatures (its warnings are printed by
/// the diagnosis that reads it).
fn has_temps(name: &str, bytes: &[u8], robot: &Robot) -> Result<bool> {
    Ok(Measurements::parse(name, bytes, &limits_deg(robot))?.has_temps())
}

fn parse_data(name: &str, bytes: &[u8], robot: &Robot) -> Result<ChainData> {
    let meas = Measurements::parse(name, bytes, &limits_deg(robot))?;
    for w in &meas.warnings {
        warning!("{w}");
    }
    let poses = meas
        .rows
        .iter()
        .enumerate()
        .map(|(i, r)| r.pose.clone().unwrap_or_else(|| format!("#{}", i + 1)))
        .collect();
    Ok(ChainData {
        samples: meas
            .rows
            .iter()
            .map(|r| Sample {
                q: r.joints,
                position: r.position,
            })
            .collect(),
        times_min: meas.rows.iter().map(|r| r.time_min).collect(),
        poses,
        has_temps: meas.has_temps(),
    })
}

pub fn run(
    args: &DiagnoseArgs,
    setup: ChainSetup,
    robot: &Robot,
    name: &str,
    bytes: &[u8],
) -> Result<Status> {
    let data = parse_data(name, bytes, robot)?;
    let holdout = match &args.holdout {
        Some(p) => Some(read_data(p, robot)?),
        None => None,
    };
    let d = diagnose_chain(&setup, &data, holdout.as_ref(), &ChainOptions::default())?;
    let text = match args.format {
        Format::Json => {
            let v = serde_json::to_string_pretty(&d)
                .map_err(|e| Error::new(ErrorKind::Input, format!("cannot write JSON: {e}")))?;
            format!("{v}\n")
        }
        Format::Csv => render_csv(
            &[
                "stage",
                "parameters",
                "fit_rms_mm",
                "cv_rms_mm",
                "holdout_rms_mm",
                "holdout_max_mm",
            ],
            &stage_rows(&d),
        ),
        Format::Table => table(&d),
    };
    write_stdout(text.as_bytes())?;
    Ok(Status::Success)
}

/// Why a parameter is held at zero, in words.
fn unidentified_words(x: &Dropped) -> String {
    held_words(&x.why, x.unit)
}

/// Why a parameter in `unit` is not identifiable, in words.
pub(crate) fn held_words(why: &Unidentified, unit: &str) -> String {
    match why {
        Unidentified::NoLever { lever_mm } => {
            format!("no lever: it moves the measured point by at most {lever_mm:.2e} mm per {unit}")
        }
        Unidentified::SameAs { same_as, .. } if same_as.is_empty() => {
            "the same effect as the parameters kept before it".into()
        }
        Unidentified::SameAs { same_as, .. } => {
            format!("same effect as {}", same_as.join(" + "))
        }
        Unidentified::Unresolved { stderr, limit } => {
            format!("standard error {stderr:.3} {unit}, above its resolution {limit} {unit}")
        }
        Unidentified::Implausible { value, limit } => {
            format!("fitted to {value:.3} {unit}, beyond a plausible {limit} {unit}")
        }
        Unidentified::AtBound { value } => {
            format!("on a bound of its range, held at {value:.0} {unit}, not fitted")
        }
    }
}

fn opt(v: Option<f64>) -> String {
    v.map(|v| format!("{v:.4}")).unwrap_or_else(|| "-".into())
}

fn stage_rows(d: &ChainDiagnosis) -> Vec<Vec<String>> {
    d.stages
        .iter()
        .map(|s| {
            vec![
                s.name.words().to_string(),
                s.parameters.to_string(),
                format!("{:.4}", s.fit.rms_mm),
                opt(s.cv_rms_mm),
                opt(s.holdout.map(|h| h.rms_mm)),
                opt(s.holdout.map(|h| h.max_mm)),
            ]
        })
        .collect()
}

fn table(d: &ChainDiagnosis) -> String {
    let mut s = String::new();
    for w in &d.words {
        s.push_str(w);
        s.push('\n');
    }
    s.push_str(&format!(
        "\nModels of growing scope ({} rows fitted{}):\n",
        d.rows,
        d.holdout_rows
            .map(|n| format!(", {n} held out"))
            .unwrap_or_default()
    ));
    s.push_str(&render_table(
        &[
            "model",
            "parameters",
            "fit RMS mm",
            "cross-validated mm",
            "held-out RMS mm",
            "held-out max mm",
        ],
        &[
            Align::Left,
            Align::Right,
            Align::Right,
            Align::Right,
            Align::Right,
            Align::Right,
        ],
        &stage_rows(d),
    ));
    s.push_str("\nFitted parameters of the full geometry (± standard error):\n");
    s.push_str(&parameter_table(
        d.parameters
            .iter()
            .map(|p| (p.name.as_str(), p.value, Some(p.stderr), p.unit)),
    ));
    s.push_str(&format!(
        "\nNot identifiable from these positions (held at zero; {} kept, of rank {} and condition {:.0}):\n",
        d.parameters.len(),
        d.rank,
        d.condition
    ));
    for x in &d.dropped {
        s.push_str(&format!("  {} ({})\n", x.name, unidentified_words(x)));
    }
    if let Some(r) = &d.holdout_remainder {
        s.push_str("\nOn the held-out set:\n");
        for w in &r.words() {
            s.push_str(w);
            s.push('\n');
        }
    }
    s
}
