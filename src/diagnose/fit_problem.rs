//! What a fit of effects to the gap is fitted to: the rows (joints,
//! temperatures, measured poses), the model's fixed part and the
//! temperature history; the residuals of any set of effects on any rows,
//! each pose's offset taken out where asked, and the Jacobians at zero
//! parameters that every fit starting there shares.

use super::fit_steps::identifiable;
use super::fitted::Fit;
use super::plausible;
use crate::model::effects::GEOMETRY_ORIGINS_FROM;
use crate::model::{Base, Effect, EffectKind, LinkLags, RowFree, RowState};
use crate::robot::Joints;
use crate::thermal::MotorTemps;
use crate::thermal::TempHistory;
use nalgebra::{DMatrix, DVector, UnitQuaternion, Vector3};
use std::collections::BTreeMap;
use std::sync::Arc;

/// Rows below which a pass over them stays on one core: a flange pose is
/// about a microsecond, a hand-off between threads some tens.
const PARALLEL_ROWS: usize = 512;

/// One row ready for fitting: joints, resolved motor temperatures, measured
/// pose (already in the robot base frame).
#[derive(Debug, Clone)]
pub struct Row {
    pub time_min: f64,
    pub q: Joints,
    pub temps: MotorTemps,
    pub position: Vector3<f64>,
    pub orientation: Option<UnitQuaternion<f64>>,
    /// Pose identity (label or identical joints), 0-based.
    pub pose: usize,
}

/// Everything a fit needs: the data, the model's fixed part, and the
/// temperature history for the thermal lag.
#[derive(Debug, Clone)]
pub struct Problem {
    pub base: Base,
    /// Effects already in the user's model (held fixed).
    pub fixed: Vec<Effect>,
    pub rows: Vec<Row>,
    pub history: TempHistory,
    /// Weight of orientation residuals, mm per mrad (position noise over
    /// orientation noise); 0 ignores orientation.
    pub w_ori: f64,
    /// Measurement noise per residual, mm: parameter directions that move
    /// the data less than this are not identifiable.
    pub noise_mm: f64,
    /// Jacobian columns of each effect at zero parameters over all rows
    /// (see [`Problem::with_zero_jacobians`]): reused by every fit that
    /// starts there, instead of recomputed per fold and per step.
    pub zero_jacobians: Option<Arc<BTreeMap<EffectKind, DMatrix<f64>>>>,
    /// Give every pose its own constant offset (eliminated: residuals are
    /// taken about each pose's mean over the rows fitted). Whatever is the
    /// same at every visit of a pose (the arm's geometric error, the
    /// reflector, a frame, sag) is then absorbed whatever its form, and
    /// only what changes with time is left to the effects.
    pub centre_poses: bool,
    /// Fit the joint-origin part of geometry-offset (a full kinematic
    /// calibration): only where the poses are enough for it, else it would
    /// fit each pose's own error and predict no other.
    pub origins: bool,
    /// Fits already made on this problem or one derived from it, by what
    /// they were fitted to ([`super::memo`]).
    pub memo: super::memo::Memo<Fit>,
}

impl Problem {
    /// Precompute, for every effect except the lag (whose fits start at a
    /// nonzero τ), its Jacobian at zero parameters over all rows. At zero
    /// an effect's columns do not depend on the other effects in the set.
    pub fn with_zero_jacobians(self) -> Problem {
        self.with_zero_jacobians_of(&EffectKind::ALL)
    }

    /// [`Problem::with_zero_jacobians`] for `kinds` only (a problem that
    /// will fit only those).
    pub fn with_zero_jacobians_of(mut self, kinds: &[EffectKind]) -> Problem {
        let all: Vec<usize> = (0..self.rows.len()).collect();
        let r0 = self.residuals(&[], &all);
        let mut cache = BTreeMap::new();
        for &kind in kinds {
            if kind == EffectKind::ThermalLag {
                continue;
            }
            let n = kind.params().len();
            let mut j = DMatrix::zeros(r0.len(), n);
            for p in 0..n {
                let mut e = Effect::zero(kind);
                let h = kind.step(p, 0.0);
                e.params[p] = h;
                let r1 = self.residuals(&[e], &all);
                j.set_column(p, &((&r0 - r1) / h));
            }
            cache.insert(kind, j);
        }
        self.zero_jacobians = Some(Arc::new(cache));
        self
    }

    /// The cached Jacobian at zero for `kinds` on `rows`, if every kind is
    /// cached.
    pub(crate) fn cached_jacobian(
        &self,
        kinds: &[EffectKind],
        rows: &[usize],
    ) -> Option<DMatrix<f64>> {
        let cache = self.zero_jacobians.as_ref()?;
        let blocks: Vec<&DMatrix<f64>> =
            kinds.iter().map(|k| cache.get(k)).collect::<Option<_>>()?;
        let w = self.width();
        let cols: usize = blocks.iter().map(|b| b.ncols()).sum();
        let mut j = DMatrix::zeros(rows.len() * w, cols);
        let mut c0 = 0;
        for b in blocks {
            for (k, &i) in rows.iter().enumerate() {
                if (i + 1) * w > b.nrows() {
                    return None;
                }
                j.view_mut((k * w, c0), (w, b.ncols()))
                    .copy_from(&b.view((i * w, 0), (w, b.ncols())));
            }
            c0 += b.ncols();
        }
        if self.centre_poses {
            self.centre(&mut j, rows);
        }
        Some(j)
    }

    /// Subtract from each residual component its pose's mean over `rows`
    /// (rows of `m` are `rows`' residuals, `width()` per row), column by
    /// column.
    fn centre(&self, m: &mut DMatrix<f64>, rows: &[usize]) {
        let w = self.width();
        let groups = self.pose_groups(rows);
        for c in 0..m.ncols() {
            for ks in &groups {
                for d in 0..w {
                    let mean = ks.iter().map(|&k| m[(k * w + d, c)]).sum::<f64>() / ks.len() as f64;
                    for &k in ks {
                        m[(k * w + d, c)] -= mean;
                    }
                }
            }
        }
    }

    /// Subtract from each entry of every column of `m` (`width()` rows per
    /// data row of `rows`) its pose's mean.
    pub(crate) fn centre_columns(&self, m: &mut DMatrix<f64>, rows: &[usize]) {
        self.centre(m, rows);
    }

    /// Positions in `rows` grouped by pose (every pose's rows together).
    pub fn pose_groups(&self, rows: &[usize]) -> Vec<Vec<usize>> {
        let mut groups: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for (k, &i) in rows.iter().enumerate() {
            if let Some(r) = self.rows.get(i) {
                groups.entry(r.pose).or_default().push(k);
            }
        }
        groups.into_values().collect()
    }
}

impl Problem {
    /// Whether orientation enters the residuals.
    pub fn uses_orientation(&self) -> bool {
        self.w_ori > 0.0 && self.rows.iter().all(|r| r.orientation.is_some())
    }

    /// Residual rows per data row.
    pub fn width(&self) -> usize {
        if self.uses_orientation() {
            6
        } else {
            3
        }
    }

    /// Predicted flange poses of `rows` with the fixed effects plus `extra`.
    pub fn predict_rows(&self, extra: &[Effect], rows: &[usize]) -> Vec<nalgebra::Isometry3<f64>> {
        let all = self.with_fixed(extra);
        let lagged = self.lagged_states(&all, rows);
        self.predict_with(&all, rows, lagged.as_deref())
    }

    /// The fixed effects followed by `extra`.
    pub(super) fn with_fixed(&self, extra: &[Effect]) -> Vec<Effect> {
        let mut all = self.fixed.clone();
        all.extend_from_slice(extra);
        all
    }

    /// Per row of `rows`, the motor temperatures through each link's lag
    /// for the time constants of `all` (`None` without a lag). A fit
    /// computes them once per set of time constants: every column of a
    /// Jacobian but the time constants' own shares them.
    pub(super) fn lagged_states(
        &self,
        all: &[Effect],
        rows: &[usize],
    ) -> Option<Vec<[MotorTemps; 4]>> {
        let lag = LinkLags::new(&self.history, all)?;
        Some(
            rows.iter()
                .filter_map(|&i| self.rows.get(i))
                .map(|r| lag.at(r.time_min))
                .collect(),
        )
    }

    /// [`Problem::predict_rows`] for all the effects `all` (fixed ones
    /// included), with their lagged temperatures given.
    fn predict_with(
        &self,
        all: &[Effect],
        rows: &[usize],
        lagged: Option<&[[MotorTemps; 4]]>,
    ) -> Vec<nalgebra::Isometry3<f64>> {
        use rayon::prelude::*;
        let free = RowFree::new(all);
        let present: Vec<&Row> = rows.iter().filter_map(|&i| self.rows.get(i)).collect();
        let one = |k: usize, r: &Row| {
            let state = RowState {
                q: r.q,
                temps: r.temps,
                lagged: lagged.and_then(|l| l.get(k).copied()),
            };
            crate::model::predict_with(&self.base, all, &free, &state)
        };
        // Every residual of every fit passes here (a finite-difference
        // Jacobian is one pass per parameter): the rows are independent, so
        // they are spread over the cores, in blocks large enough that the
        // hand-off costs nothing beside the chains, and gathered in order
        // (the numbers are the serial ones, bit for bit).
        if present.len() < PARALLEL_ROWS {
            return present.iter().enumerate().map(|(k, r)| one(k, r)).collect();
        }
        present
            .par_iter()
            .enumerate()
            .with_min_len(PARALLEL_ROWS / 2)
            .map(|(k, r)| one(k, r))
            .collect()
    }

    /// Position gaps (measured − predicted) of `rows`, mm.
    pub fn position_gaps(&self, extra: &[Effect], rows: &[usize]) -> Vec<Vector3<f64>> {
        self.predict_rows(extra, rows)
            .iter()
            .zip(rows)
            .filter_map(|(p, &i)| self.rows.get(i).map(|r| r.position - p.translation.vector))
            .collect()
    }

    /// The stacked residual vector (positions in mm, orientations in mrad
    /// times `w_ori`).
    pub fn residuals(&self, extra: &[Effect], rows: &[usize]) -> DVector<f64> {
        let all = self.with_fixed(extra);
        let lagged = self.lagged_states(&all, rows);
        self.residuals_with(&all, rows, lagged.as_deref())
    }

    /// [`Problem::residuals`] for all the effects `all` (fixed ones
    /// included), with their lagged temperatures given.
    pub(super) fn residuals_with(
        &self,
        all: &[Effect],
        rows: &[usize],
        lagged: Option<&[[MotorTemps; 4]]>,
    ) -> DVector<f64> {
        let w = self.width();
        let mut out = DVector::zeros(rows.len() * w);
        for (k, (pose, &i)) in self
            .predict_with(all, rows, lagged)
            .iter()
            .zip(rows)
            .enumerate()
        {
            let Some(r) = self.rows.get(i) else { continue };
            let d = r.position - pose.translation.vector;
            out.fixed_rows_mut::<3>(k * w).copy_from(&d);
            if w == 6 {
                if let Some(m) = &r.orientation {
                    let g =
                        crate::model::chain::rotation_gap(&pose.rotation, m) * (1e3 * self.w_ori);
                    out.fixed_rows_mut::<3>(k * w + 3).copy_from(&g);
                }
            }
        }
        if self.centre_poses {
            let mut m = DMatrix::from_column_slice(out.len(), 1, out.as_slice());
            self.centre(&mut m, rows);
            out = DVector::from_column_slice(m.as_slice());
        }
        out
    }
}

impl Problem {
    /// The parameters of `layout` (effect, index) the fit may free: those
    /// with a place on the arm, and the joint origins only where asked for.
    pub(super) fn allowed(&self, layout: &[(EffectKind, usize)]) -> Vec<usize> {
        (0..layout.len())
            .filter(|&p| {
                let (kind, idx) = layout[p];
                (kind != EffectKind::GeometryOffset || idx < GEOMETRY_ORIGINS_FROM || self.origins)
                    && self.base.nominal.has_param(kind, idx)
            })
            .collect()
    }

    /// How many parameters of `kinds` (none of them the lag) the rows `rows`
    /// identify against the noise: the rank of what a fit of them could
    /// take up.
    pub fn identifiable_rank(&self, kinds: &[EffectKind], rows: &[usize]) -> usize {
        let layout: Vec<(EffectKind, usize)> = kinds
            .iter()
            .flat_map(|&k| (0..k.params().len()).map(move |i| (k, i)))
            .collect();
        let Some(j) = self.cached_jacobian(kinds, rows) else {
            return 0;
        };
        let allowed = self.allowed(&layout);
        let typ: Vec<f64> = allowed
            .iter()
            .map(|&p| {
                let (k, i) = layout[p];
                k.params().get(i).map_or(1.0, |p| p.default.abs().max(1e-6))
            })
            .collect();
        let bounds: Vec<(EffectKind, f64)> = allowed
            .iter()
            .map(|&p| (layout[p].0, plausible::bound(layout[p].0, layout[p].1)))
            .collect();
        identifiable(
            &j.select_columns(allowed.iter()),
            &typ,
            &bounds,
            self.noise_mm,
        )
        .0
        .len()
    }
}
