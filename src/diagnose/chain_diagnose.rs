//! The diagnosis of a general serial chain (any URDF arm, no OPW form
//! needed): how far the nominal chain is from the measured points, how much
//! of that a rigid instrument frame and the measured point take, how much
//! more a full geometric calibration ([`super::chain_calib`]) takes, judged
//! on held-out poses (cross-validation, and a separate file when given),
//! and where what is left lies ([`super::chain_residual`]).
//!
//! This is the geometric calibration only. Thermal effects on a general
//! chain are the effect diagnosis's ([`super::pipeline`], on
//! [`crate::model::Geometry::Chain`]); without temperatures in the data
//! (time only an order, not a warm-up) no thermal effect can be named.

use super::chain_calib::{self, ChainParam, Dropped, Group, Nominal, Sample, N_RAW};
use super::chain_finding::{named_words, ChainStage, ChainThermal};
use super::chain_residual::{remainder, Remainder, ResidualRow};
use super::gap::{gap_stats, GapStats};
use super::instrument::default_noise_mm;
use crate::error::{Error, Result};
use crate::model::EffectKind;
use crate::robot::chain::Chain;
use nalgebra::{Isometry3, Vector3};
use serde::Serialize;

/// A measured set for the chain diagnosis.
#[derive(Debug, Clone)]
pub struct ChainData {
    pub samples: Vec<Sample>,
    pub times_min: Vec<f64>,
    /// Pose label per sample (repeated labels are one pose).
    pub poses: Vec<String>,
    /// Whether the set has motor temperatures.
    pub has_temps: bool,
}

/// What is measured: a point in the flange frame.
#[derive(Debug, Clone)]
pub struct ChainSetup {
    pub robot: String,
    pub chain: Chain,
    /// Start value of the measured point in tool0, mm.
    pub point: Vector3<f64>,
    /// Where the point comes from (a URDF link's name or `tool0`).
    pub point_name: String,
}

#[derive(Debug, Clone)]
pub struct ChainOptions {
    pub folds: usize,
}

impl Default for ChainOptions {
    fn default() -> Self {
        ChainOptions { folds: 5 }
    }
}

/// One model of increasing scope, its gap on the fitted set, on held-out
/// folds and on the separate held-out set.
#[derive(Debug, Clone, Serialize)]
pub struct Stage {
    pub name: ChainStage,
    pub parameters: usize,
    pub fit: GapStats,
    pub cv_rms_mm: Option<f64>,
    pub holdout: Option<GapStats>,
}

/// The result.
#[derive(Debug, Clone, Serialize)]
pub struct ChainDiagnosis {
    pub robot: String,
    pub point: String,
    pub rows: usize,
    pub holdout_rows: Option<usize>,
    pub stages: Vec<Stage>,
    /// Effects the held-out evidence names, in the words of the effects
    /// spec (`tracker-frame`, `geometry-offset`).
    pub named: Vec<EffectKind>,
    pub thermal: ChainThermal,
    pub parameters: Vec<ChainParam>,
    pub dropped: Vec<Dropped>,
    /// Rank of the kept parameters' Jacobian columns, each scaled by its
    /// resolution, against the residual noise (counted: equal to their
    /// number), and their condition number.
    pub rank: usize,
    pub condition: f64,
    pub remainder: Remainder,
    pub holdout_remainder: Option<Remainder>,
    pub words: Vec<String>,
}

fn fold_sets(data: &ChainData, folds: usize) -> Vec<(Vec<usize>, Vec<usize>)> {
    let mut ids: Vec<&str> = data.poses.iter().map(String::as_str).collect();
    ids.sort_unstable();
    ids.dedup();
    let k = folds.min(ids.len()).max(2);
    let fold_of = |i: usize| {
        let id = ids.binary_search(&data.poses[i].as_str()).unwrap_or(0);
        id % k
    };
    (0..k)
        .map(|f| {
            let (test, train): (Vec<usize>, Vec<usize>) =
                (0..data.samples.len()).partition(|&i| fold_of(i) == f);
            (train, test)
        })
        .collect()
}

fn pick(samples: &[Sample], idx: &[usize]) -> Vec<Sample> {
    idx.iter().map(|&i| samples[i]).collect()
}

/// The calibration restricted to `allow`: the rank test against the
/// instrument's noise, the fit, and the parameters a metrologist would not
/// sign dropped.
fn calibrate(
    nominal: &Nominal,
    samples: &[Sample],
    allow: &dyn Fn(Group) -> bool,
) -> Result<chain_calib::Calibration> {
    let id = chain_calib::identify(nominal, samples, allow, default_noise_mm()?);
    chain_calib::calibrate(nominal, samples, id)
}

/// Held-out RMS of the model restricted to `allow` (the rank test redone
/// on each training part).
fn cross_validate(
    nominal: &Nominal,
    data: &ChainData,
    allow: &dyn Fn(Group) -> bool,
    folds: usize,
) -> Result<f64> {
    let mut sq = 0.0;
    let mut n = 0usize;
    for (train, test) in fold_sets(data, folds) {
        let tr = pick(&data.samples, &train);
        let f = calibrate(nominal, &tr, allow)?.fit;
        let g = chain_calib::gaps(nominal, &f.x, &pick(&data.samples, &test));
        sq += g.iter().map(|v| v.norm_squared()).sum::<f64>();
        n += g.len();
    }
    Ok((sq / n.max(1) as f64).sqrt())
}

fn residual_rows(
    nominal: &Nominal,
    fit: &chain_calib::ChainFit,
    data: &ChainData,
) -> Vec<ResidualRow> {
    let g = fit.geometry(nominal);
    let frame = nominal.frame.rotation
        * nalgebra::UnitQuaternion::from_scaled_axis(
            Vector3::new(fit.x[3], fit.x[4], fit.x[5]) * 1e-3,
        );
    data.samples
        .iter()
        .enumerate()
        .map(|(i, s)| ResidualRow {
            q: s.q,
            // In the robot base frame's axes: what a user can point at.
            gap: frame.inverse() * (s.position - g.predict(&s.q)),
            at: g.in_base(&s.q),
            time_min: data.times_min[i],
            pose: data.poses[i].clone(),
        })
        .collect()
}

/// Diagnose `data` on the chain of `setup`; `holdout` is a separate set
/// measured in the same instrument frame, judged with the model fitted on
/// `data`.
pub fn diagnose_chain(
    setup: &ChainSetup,
    data: &ChainData,
    holdout: Option<&ChainData>,
    opts: &ChainOptions,
) -> Result<ChainDiagnosis> {
    const MIN_ROWS: usize = 30;
    let n = data.samples.len();
    if n < MIN_ROWS {
        return Err(Error::input(format!(
            "too few measurements for a geometric calibration: {n} rows (at least {MIN_ROWS} poses spread over the workspace)"
        )));
    }
    let frame = chain_calib::start_frame(&setup.chain, setup.point, &data.samples)?;
    let as_measured = Nominal {
        chain: setup.chain.clone(),
        point: setup.point,
        frame: Isometry3::identity(),
    };
    let nominal = Nominal {
        frame,
        ..as_measured.clone()
    };
    let zero = vec![0.0; N_RAW];
    let stats =
        |nom: &Nominal, x: &[f64], d: &ChainData| gap_stats(&chain_calib::gaps(nom, x, &d.samples));
    let mut stages = vec![
        Stage {
            name: ChainStage::AsMeasured,
            parameters: 0,
            fit: stats(&as_measured, &zero, data),
            cv_rms_mm: None,
            holdout: holdout.map(|h| stats(&as_measured, &zero, h)),
        },
        Stage {
            name: ChainStage::RigidFrame,
            parameters: 6,
            fit: stats(&nominal, &zero, data),
            cv_rms_mm: None,
            holdout: holdout.map(|h| stats(&nominal, &zero, h)),
        },
    ];
    let frame_point = |g: Group| matches!(g, Group::Frame | Group::Point);
    let everything = |_: Group| true;
    let scopes: [(ChainStage, &dyn Fn(Group) -> bool); 2] = [
        (ChainStage::FrameAndPoint, &frame_point),
        (ChainStage::FullGeometry, &everything),
    ];
    let mut last = None;
    for (name, allow) in scopes {
        let cal = calibrate(&nominal, &data.samples, allow)?;
        let cv = cross_validate(&nominal, data, allow, opts.folds)?;
        stages.push(Stage {
            name,
            parameters: cal.kept.len(),
            fit: stats(&nominal, &cal.fit.x, data),
            cv_rms_mm: Some(cv),
            holdout: holdout.map(|h| stats(&nominal, &cal.fit.x, h)),
        });
        last = Some(cal);
    }
    let Some(cal) = last else {
        return Err(Error::input("no calibration stage ran"));
    };
    let [raw, rigid, point, geometry] = [0, 1, 2, 3].map(|i| &stages[i]);
    let mut named = Vec::new();
    // The frame is named when the data are not in the robot base frame
    // already: the rigid fit takes a clear part of the gap as measured.
    if rigid.fit.rms_mm < 0.9 * raw.fit.rms_mm {
        named.push(EffectKind::TrackerFrame);
    }
    let (cv_point, cv_geom) = (
        point.cv_rms_mm.unwrap_or(f64::INFINITY),
        geometry.cv_rms_mm.unwrap_or(f64::INFINITY),
    );
    let geometric = cv_point < 0.9 * rigid.fit.rms_mm || cv_geom < 0.9 * cv_point;
    if geometric {
        named.push(EffectKind::GeometryOffset);
    }
    let thermal = if data.has_temps {
        ChainThermal::NotTried
    } else {
        ChainThermal::NoTemperatures
    };
    let full = &cal.fit;
    let rows = residual_rows(&nominal, full, data);
    let remainder_fit = remainder(&rows);
    let holdout_remainder = holdout.map(|h| remainder(&residual_rows(&nominal, full, h)));
    let mut words = vec![format!(
        "Gap of the nominal {} at `{}`: {:.3} mm RMS as measured, {:.3} mm after a rigid instrument frame.",
        setup.robot, setup.point_name, raw.fit.rms_mm, rigid.fit.rms_mm
    )];
    words.push(format!(
        "Instrument frame + measured point: {:.3} mm ({:.3} mm held out); full geometry ({} parameters, {} dropped as not identifiable): {:.3} mm ({:.3} mm held out).",
        point.fit.rms_mm,
        cv_point,
        geometry.parameters,
        cal.dropped.len(),
        geometry.fit.rms_mm,
        cv_geom
    ));
    if let (Some(hp), Some(hg)) = (&point.holdout, &geometry.holdout) {
        words.push(format!(
            "On the separate held-out set ({} rows): {:.3} mm RMS with frame and point, {:.3} mm RMS (max {:.3}) with the full geometry.",
            hg.n, hp.rms_mm, hg.rms_mm, hg.max_mm
        ));
    }
    if named.contains(&EffectKind::TrackerFrame) {
        let f = *full.geometry(&nominal).frame();
        words.push(format!(
            "The measured frame is off the nominal base by {:.3} mm and {:.3} mrad: position data cannot tell an instrument frame from the base mount or joint 1's origin.",
            f.translation.vector.norm(),
            f.rotation.angle() * 1e3
        ));
    }
    words.push(named_words(&named));
    words.push(thermal.words().into());
    words.push(format!(
        "Left over: {:.3} mm RMS on the fitted poses{}.",
        remainder_fit.gap.rms_mm,
        holdout_remainder
            .as_ref()
            .map(|r| format!(", {:.3} mm on the held-out set", r.gap.rms_mm))
            .unwrap_or_default()
    ));
    words.extend(remainder_fit.words());
    Ok(ChainDiagnosis {
        robot: setup.robot.clone(),
        point: setup.point_name.clone(),
        rows: n,
        holdout_rows: holdout.map(|h| h.samples.len()),
        stages,
        named,
        thermal,
        parameters: full.params.clone(),
        dropped: cal.dropped,
        rank: cal.rank,
        condition: cal.condition,
        remainder: remainder_fit,
        holdout_remainder,
        words,
    })
}
