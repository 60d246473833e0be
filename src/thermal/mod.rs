//! Motor temperatures over time: heating models fitted to recordings and the
//! embedded default profile of the IRB 140 at 60 % speed.
//!
//! - `heating`: [`HeatingProfile`], what every model answers, and
//!   [`MotorTemps`].
//! - [`record`]: heating records (CSV) and [`RecordedProfile`], measured
//!   temperatures interpolated in time.
//! - [`poly`]: polynomial curves (the paper's regression), solved stably.
//! - [`saturating`]: first-order and two-time-constant curves.
//! - [`uncertainty`]: how far a forecast beyond a recording can be trusted.
//! - [`plausible`]: which numbers can be a robot's temperature.
//! - [`select`]: choosing a saturating model by its held-out forecast.
//! - [`fit`]: fitting one axis, a model named or `auto`'s choice.
//! - `kind_fit`: one named model fitted, its curve and metrics (R, R², Ā,
//!   RMSE, max, held-out).
//! - [`profile`]: profiles from fitted curves and [`default_profile`].
//! - [`plot`]: SVG of measured and fitted curves.
//! - [`table`]: fit results as the paper-like table, CSV and JSON.
//! - [`duty`]: warm-up and cool-down over a day of running and stops,
//!   the exact update of saturating curves.
//! - [`lag`]: a structure's temperature behind its motors' (first-order
//!   lag), one discretisation for every job.
//!
//! Owns temperatures over time. May import the shared `error`,
//! `csv_table` and `report`; never `robot`, `model` or anything above.

pub mod duty;
pub mod fit;
mod heating;
mod kind_fit;
pub mod lag;
pub mod plausible;
pub mod plot;
pub mod poly;
pub mod profile;
pub mod record;
pub mod saturating;
pub mod select;
pub mod table;
pub mod uncertainty;

pub use fit::{fit_axis, AxisFit, Curve, Metrics, ModelKind};
pub use heating::{HeatingProfile, MotorTemps, TABLE1_TMAX};
pub use lag::{Lagged, TempHistory, LAG_STEP_MIN};
pub use profile::{
    default_heating, default_profile, DefaultHeating, FittedProfile, SaturatingProfile,
};
pub use record::{HeatingRecord, RecordedProfile};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_profile_starts_at_reference_and_stays_bounded() {
        let p = default_profile();
        assert_eq!(p.temps_at(0.0).unwrap(), [7.0; 6]);
        let late = p.temps_at(10_000.0).unwrap();
        for (i, c) in p.axes.iter().enumerate() {
            assert!((late[i] - c.steady()).abs() < 1e-9);
            assert!(late[i] < 40.0);
        }
        assert!(p.temps_at(-1.0).is_err());
        assert!(p.temps_at(f64::NAN).is_err());
    }
}
