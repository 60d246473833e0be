//! The options of a diagnosis: the noise the user gives, the held-out
//! folds, how many effects a selection adds, and the cold start the user
//! says the session follows.

use super::temps::ColdStart;

/// DiagnoseOptions of a diagnosis.
#[derive(Debug, Clone)]
pub struct DiagnoseOptions {
    /// Tracker noise per axis (mm, positive); `None`: estimate, else the
    /// instrument's default.
    pub noise_mm: Option<f64>,
    /// Number of cross-validation folds.
    pub folds: usize,
    /// Most effects forward selection adds.
    pub max_effects: usize,
    /// Where the data carry no temperatures (and the model names no
    /// heating record): the caller says the session starts cold at its
    /// first row and follows this warm-up. `None`: nothing is assumed, no
    /// thermal effect is a candidate ([`super::temps`]).
    pub assume_cold_start: Option<ColdStart>,
}

impl DiagnoseOptions {
    /// These options with the session said to start cold at its first row
    /// and follow `profile` (data without temperature columns).
    pub fn with_cold_start(self, profile: ColdStart) -> DiagnoseOptions {
        DiagnoseOptions {
            assume_cold_start: Some(profile),
            ..self
        }
    }
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        DiagnoseOptions {
            noise_mm: None,
            folds: 4,
            max_effects: 3,
            assume_cold_start: None,
        }
    }
}
