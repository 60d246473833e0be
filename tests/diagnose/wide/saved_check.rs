//! Every number after the diagnosis is the saved model's, checked through
//! the binary a user runs: the report's gap after on all rows is what `gap
//! --model` gives with the saved file on those rows, and its held-out gap
//! after is what `gap --model` gives with each fold's file (the saved
//! model's effects fitted without the fold's rows, written as
//! `--save-model` writes) on the fold's held-out rows, pooled; both to
//! 1 %. Used by `saved.rs` (the seeded sets, the real UR5) and by the
//! evaluation runner on every set (`--check-saved`).

use rapidtherm::diagnose::job::{self, DiagnoseEvent, DiagnoseHost, Diagnosed};
use rapidtherm::diagnose::plan::{DiagnosePlan, RobotChoice, Which};
use std::path::{Path, PathBuf};
use std::process::Command;

struct Quiet;

impl DiagnoseHost for Quiet {
    fn event(&mut self, _: DiagnoseEvent) {}
}

fn plan(data: &Path, robot: Option<PathBuf>, register: bool) -> DiagnosePlan {
    DiagnosePlan {
        data: data.to_path_buf(),
        model: None,
        robot: robot.map(RobotChoice::Urdf),
        which: Which::Effects,
        noise_mm: None,
        assume_cold_start: None,
        register,
        point: None,
        save_model: true,
        plot: false,
    }
}

/// `BIN gap DATA --model MODEL --format json [ARGS]`: its RMS and rows.
pub fn gap_cli(
    bin: &Path,
    model: &Path,
    data: &Path,
    args: &[&str],
) -> Result<(f64, usize), String> {
    let out = Command::new(bin)
        .arg("gap")
        .arg(data)
        .arg("--model")
        .arg(model)
        .args(["--format", "json"])
        .args(args)
        .output()
        .map_err(|e| format!("{}: {e}", bin.display()))?;
    if !out.status.success() {
        return Err(format!("gap: {}", String::from_utf8_lossy(&out.stderr)));
    }
    let v: serde_json::Value =
        serde_json::from_slice(&out.stdout).map_err(|e| format!("gap's JSON: {e}"))?;
    match (v["rms_mm"].as_f64(), v["n"].as_u64()) {
        (Some(rms), Some(n)) => Ok((rms, n as usize)),
        _ => Err(format!("gap's JSON lacks rms_mm or n: {v}")),
    }
}

/// Within 1 % of `b`.
pub fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 0.01 * b.abs().max(1e-12)
}

/// What the check found: the report's two "after" numbers and the saved
/// files' own.
#[derive(Debug, Clone, Copy)]
pub struct Checked {
    pub report_all_mm: f64,
    pub file_all_mm: f64,
    pub report_held_out_mm: f64,
    pub file_held_out_mm: f64,
}

/// Diagnose `data` through the job, save its model in `dir`, and check
/// both "after" numbers against `bin gap --model` of the written files.
/// Returns the saved model's path and the numbers, or what differed.
pub fn check(
    bin: &Path,
    name: &str,
    data: &Path,
    robot: Option<PathBuf>,
    register: bool,
    dir: &Path,
) -> Result<(PathBuf, Checked), String> {
    let Diagnosed::Effects(run) = job::run(&plan(data, robot, register), &mut Quiet)
        .map_err(|_| format!("{name}: the job failed"))?
    else {
        return Err(format!("{name}: not the effect diagnosis"));
    };
    let d = &run.diagnosis;
    let io = |e: std::io::Error| format!("{name}: {e}");
    let saved = dir.join(format!("{name}.toml"));
    let toml = run
        .model_toml
        .as_ref()
        .ok_or_else(|| format!("{name}: no model to save"))?;
    std::fs::write(&saved, toml).map_err(io)?;
    // The saved file alone: no --robot, no --register.
    let (all, n) = gap_cli(bin, &saved, data, &[])?;
    if n != d.gap.n {
        return Err(format!("{name}: gap read {n} rows, the report {}", d.gap.n));
    }
    if !close(d.gap_after.rms_mm, all) {
        return Err(format!(
            "{name}: report {:.5} mm after, the saved file {all:.5} mm",
            d.gap_after.rms_mm
        ));
    }
    let text = std::fs::read_to_string(data).map_err(io)?;
    let lines: Vec<&str> = text.lines().collect();
    let s = d
        .saved
        .as_ref()
        .ok_or_else(|| format!("{name}: the report has no saved model"))?;
    let (mut sum, mut count) = (0.0, 0usize);
    for (k, fold) in s.folds.iter().enumerate() {
        let model = dir.join(format!("{name}_fold{k}.toml"));
        let toml = fold
            .model
            .to_toml()
            .map_err(|e| format!("{name} fold {k}: {}", e.message))?;
        std::fs::write(&model, toml).map_err(io)?;
        let csv = dir.join(format!("{name}_fold{k}.csv"));
        let mut held = vec![lines[0].to_string()];
        held.extend(fold.lines.iter().map(|&l| lines[l - 1].to_string()));
        std::fs::write(&csv, held.join("\n") + "\n").map_err(io)?;
        let (rms, n) = gap_cli(bin, &model, &csv, &[])?;
        if n != fold.lines.len() {
            return Err(format!(
                "{name} fold {k}: gap read {n} rows of {}",
                fold.lines.len()
            ));
        }
        sum += rms * rms * n as f64;
        count += n;
    }
    let pooled = (sum / count.max(1) as f64).sqrt();
    if !close(d.gap_after_mm, pooled) {
        return Err(format!(
            "{name}: report {:.5} mm held out after, the folds' files {pooled:.5} mm",
            d.gap_after_mm
        ));
    }
    Ok((
        saved,
        Checked {
            report_all_mm: d.gap_after.rms_mm,
            file_all_mm: all,
            report_held_out_mm: d.gap_after_mm,
            file_held_out_mm: pooled,
        },
    ))
}
