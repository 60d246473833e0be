//! A diagnosis as the user asked for it, every choice read and checked
//! before any input is opened: the files, the arm, which diagnosis, the
//! noise, and what to produce. The command line builds one from its
//! arguments (every usage error is raised there); the job
//! ([`super::job`]) runs it.

use super::prepare::RegisterFailure;
use crate::error::Error;
use crate::robot::abb::AbbArm;
use std::path::PathBuf;

/// A planned diagnosis.
#[derive(Debug, Clone)]
pub struct DiagnosePlan {
    /// The measurements (`-`: standard input).
    pub data: PathBuf,
    /// The current model file (default: the embedded IRB 140 model).
    pub model: Option<PathBuf>,
    /// The arm, where it is not the model's.
    pub robot: Option<RobotChoice>,
    pub which: Which,
    /// The instrument's noise per axis, mm (positive), where given.
    pub noise_mm: Option<f64>,
    /// Fit the instrument's frame before anything else.
    pub register: bool,
    /// The URDF link measured (a reflector on the flange).
    pub point: Option<String>,
    /// Data without temperature columns: the session is assumed to start
    /// cold at its first row and follow this warm-up (said in the report).
    pub assume_cold_start: Option<super::temps::ColdStart>,
    /// Produce the model to save.
    pub save_model: bool,
    /// Produce the plots.
    pub plot: bool,
}

/// The arm a plan names.
#[derive(Debug, Clone)]
pub enum RobotChoice {
    /// A URDF file, read by the job.
    Urdf(PathBuf),
    /// An arm of the catalogue.
    Catalogue(&'static AbbArm),
}

/// Which diagnosis runs.
#[derive(Debug, Clone, PartialEq)]
pub enum Which {
    /// The effect diagnosis (asked for by what only it gives: a model
    /// to start from or to save, plots, a noise level).
    Effects,
    /// The general chain's geometric calibration: asked for (`forced`),
    /// or by a held-out file (which needs an arm without the OPW form).
    Chain {
        forced: bool,
        holdout: Option<PathBuf>,
    },
    /// Decided by the arm and the data: the geometric calibration on an
    /// arm without the OPW form whose data have no temperatures (time is
    /// then only an order), else the effect diagnosis.
    ByData,
}

/// Why a planned diagnosis did not run, typed where the caller words the
/// way it was asked for (a flag) in front of the reason.
#[derive(Debug)]
pub enum Refused {
    Error(Error),
    /// The instrument frame could not be registered.
    Register(RegisterFailure),
    /// A held-out file belongs to the general chain's calibration, and
    /// this arm has the OPW form (asked for without forcing the chain).
    HoldoutOnOpwArm {
        arm: String,
    },
    /// The measured point is no link hung on the flange.
    Point {
        link: String,
        error: Error,
    },
}

impl From<Error> for Refused {
    fn from(e: Error) -> Refused {
        Refused::Error(e)
    }
}
