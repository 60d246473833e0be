//! `heating fit` and `heating eval`: heating curves fitted to recordings
//! and evaluated. The arguments are read into a [`HeatingCommand`] (every
//! usage error raised there) before any recording is read.

use super::messages::warning;
use super::Format;
use super::{read_input, write_output, write_stdout, Status};
use rapidtherm::error::{Error, ErrorKind, Result};
use rapidtherm::report::{render_csv, render_table, Align};
use rapidtherm::thermal::fit::{fit_axis, AxisFit, ModelKind};
use rapidtherm::thermal::plot::plot_fits;
use rapidtherm::thermal::table::{render_fits_csv, render_fits_json, render_fits_table};
use rapidtherm::thermal::{
    default_profile, FittedProfile, HeatingProfile, HeatingRecord, RecordedProfile,
};
use rapidtherm::writes::{Checked, Plan, Role};
use std::path::PathBuf;

#[derive(clap::Subcommand)]
pub enum HeatingArgs {
    /// Fit heating models to a recording (time_min,t1_c..t6_c): per-axis
    /// coefficients, R, R², mean relative error Ā, RMSE, max error, and the
    /// error on the last 20 % of the rows when fitted to the first 80 %.
    Fit(FitArgs),
    /// Motor temperatures at given minutes: the embedded default profile, a
    /// model fitted to a recording, or a recording interpolated.
    Eval(EvalArgs),
}

#[derive(clap::Args)]
pub struct FitArgs {
    /// Heating record CSV (`-` for standard input).
    pub records: PathBuf,
    /// Models, comma separated: poly1..poly20, first-order, two-tau, or
    /// `all` (poly1, poly2, poly3, first-order, two-tau).
    #[arg(long, value_delimiter = ',', default_value = "poly3")]
    pub model: Vec<String>,
    /// Axes to fit, comma separated (1..6).
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,5,6")]
    pub axes: Vec<usize>,
    /// Fix T(0) of the saturating models to this temperature (°C) instead
    /// of fitting it (the default profile pins 7.0).
    #[arg(long, value_name = "CELSIUS", value_parser = celsius)]
    pub pin_t0: Option<f64>,
    /// Write an SVG plot of measured and fitted curves (`-`: the SVG goes to
    /// standard output instead of the table).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

#[derive(clap::Args)]
pub struct EvalArgs {
    /// Minutes since the cold start, comma separated.
    #[arg(long, value_delimiter = ',', required = true, value_name = "MIN")]
    pub at: Vec<f64>,
    /// Fit this recording instead of using the embedded default profile.
    #[arg(long, value_name = "RECORDS.csv", conflicts_with = "measured")]
    pub records: Option<PathBuf>,
    /// Model fitted to `--records` (a polynomial refuses minutes outside
    /// the recording).
    #[arg(long, default_value = "auto", requires = "records")]
    pub model: String,
    /// Fix T(0) of a saturating model fitted to `--records` (°C).
    #[arg(long, value_name = "CELSIUS", requires = "records", value_parser = celsius)]
    pub pin_t0: Option<f64>,
    /// Use measured temperatures directly, interpolated linearly in time.
    #[arg(long, value_name = "RECORDS.csv")]
    pub measured: Option<PathBuf>,
    /// With `--measured`: hold the first/last row outside the recording
    /// instead of refusing.
    #[arg(long, requires = "measured")]
    pub hold_ends: bool,
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

/// Everything `heating` does, read from its arguments once.
pub enum HeatingCommand {
    Fit(FitCommand),
    Eval(EvalCommand),
}

/// The plan of `heating`'s arguments: every usage error is raised here,
/// before any file is read.
pub fn plan(args: HeatingArgs) -> Result<HeatingCommand> {
    Ok(match args {
        HeatingArgs::Fit(a) => HeatingCommand::Fit(plan_fit(a)?),
        HeatingArgs::Eval(a) => HeatingCommand::Eval(plan_eval(a)?),
    })
}

pub fn run(cmd: HeatingCommand) -> Result<Status> {
    match cmd {
        HeatingCommand::Fit(c) => run_fit(c),
        HeatingCommand::Eval(c) => run_eval(c),
    }
}

/// Where `heating fit --plot` puts its picture.
enum PlotTo {
    /// `-`: standard output, instead of the table.
    Stdout,
    File(PathBuf),
}

/// `heating fit`, read from its arguments once.
pub struct FitCommand {
    records: PathBuf,
    models: Vec<ModelKind>,
    /// Each once, in the order given.
    axes: Vec<usize>,
    pin_t0: Option<f64>,
    plot: Option<PlotTo>,
    format: Format,
    /// The plot's file, checked against the recording.
    checked: Checked,
}

fn plan_fit(a: FitArgs) -> Result<FitCommand> {
    let mut writes = Plan::new(false);
    writes.input(&a.records);
    if let Some(plot) = &a.plot {
        super::output::check_file("--plot", plot)?;
        writes.output("--plot", plot, Role::Named);
    }
    let checked = super::output::check(&writes)?;
    let models = parse_models(&a.model)?;
    let mut axes: Vec<usize> = Vec::new();
    for x in &a.axes {
        if !axes.contains(x) {
            axes.push(*x);
        }
    }
    if let Some(bad) = axes.iter().find(|x| !(1..=6).contains(*x)) {
        return Err(Error::usage(format!(
            "--axes: axis {bad} does not exist (1..6)"
        )));
    }
    Ok(FitCommand {
        records: a.records,
        models,
        axes,
        pin_t0: a.pin_t0,
        plot: a.plot.map(|p| {
            if p.as_os_str() == "-" {
                PlotTo::Stdout
            } else {
                PlotTo::File(p)
            }
        }),
        format: a.format,
        checked,
    })
}

/// Where `heating eval`'s temperatures come from.
enum Temperatures {
    /// The embedded default profile.
    Default,
    /// `--records`: a model of this kind fitted to the recording.
    Fitted {
        records: PathBuf,
        kind: ModelKind,
        pin_t0: Option<f64>,
    },
    /// `--measured`: the recording interpolated.
    Measured { records: PathBuf, hold_ends: bool },
}

/// `heating eval`, read from its arguments once.
pub struct EvalCommand {
    at: Vec<f64>,
    temps: Temperatures,
    format: Format,
}

fn plan_eval(a: EvalArgs) -> Result<EvalCommand> {
    let temps = match (a.records, a.measured) {
        (Some(records), _) => Temperatures::Fitted {
            records,
            kind: a.model.parse()?,
            pin_t0: a.pin_t0,
        },
        (None, Some(records)) => Temperatures::Measured {
            records,
            hold_ends: a.hold_ends,
        },
        (None, None) => Temperatures::Default,
    };
    Ok(EvalCommand {
        at: a.at,
        temps,
        format: a.format,
    })
}

fn parse_models(names: &[String]) -> Result<Vec<ModelKind>> {
    let mut out = Vec::new();
    for name in names {
        let kinds = if name.trim().eq_ignore_ascii_case("all") {
            ModelKind::all()
        } else {
            vec![name.parse::<ModelKind>()?]
        };
        for k in kinds {
            if !out.contains(&k) {
                out.push(k);
            }
        }
    }
    Ok(out)
}

fn read_record(path: &std::path::Path) -> Result<HeatingRecord> {
    let (name, bytes) = read_input(path)?;
    let record = HeatingRecord::parse(&name, &bytes)?;
    for note in &record.reading_notes {
        warning!("{note}");
    }
    for col in &record.ignored_columns {
        warning!("{name}: ignoring unknown column `{col}`");
    }
    Ok(record)
}

/// Width (°C) of the steady-temperature interval above which `heating fit`
/// warns that the recording cannot tell where the warm-up ends: a degree
/// of motor temperature moves the IRB 140's flange by a few micrometres
/// (K0·α·380 mm·1 K ≈ 0.003 mm on the upper arm), less is not worth a word.
const STEADY_WARN_C: f64 = 1.0;

fn run_fit(a: FitCommand) -> Result<Status> {
    let record = read_record(&a.records)?;
    let mut fits: Vec<AxisFit> = Vec::new();
    let mut failed = Vec::new();
    for &axis in &a.axes {
        for &kind in &a.models {
            match fit_axis(&record, axis, kind, a.pin_t0) {
                Ok(f) => fits.push(f),
                // A fit that did not converge, or converged to a degenerate
                // curve, is no result: said, and left out of the table.
                Err(e) if e.kind == ErrorKind::NoConvergence => {
                    failed.push(format!("axis {axis}, {kind}: {}", e.message));
                }
                Err(e) => return Err(e),
            }
        }
    }
    for f in &failed {
        warning!("{f}; not listed");
    }
    let span = record.times.iter().copied().fold(0.0, f64::max);
    for f in &fits {
        if let (Some((lo, hi)), rapidtherm::thermal::fit::Curve::Saturating(c)) =
            (f.steady_interval, &f.curve)
        {
            let longest = c.terms.last().map_or(0.0, |k| k.tau);
            if hi - lo > STEADY_WARN_C && span >= 3.0 * longest {
                // Long enough for its own time constant: what spreads the
                // steady temperature is a heat path this curve lacks.
                warning!(
                    "axis {}, {}: curves with more heat paths fit this recording at least as well and put the steady temperature anywhere between {lo:.1} and {hi:.1} °C (fitted {:.1} °C); compare with two-tau, or let auto choose",
                    f.axis,
                    f.model_name(),
                    c.steady()
                );
            } else if hi - lo > STEADY_WARN_C {
                warning!(
                    "axis {}, {}: a {span:.0}-min recording cannot tell where this warm-up ends: its steady temperature is anywhere between {lo:.1} and {hi:.1} °C (fitted {:.1} °C); record longer, at least as long as the time constant",
                    f.axis,
                    f.model_name(),
                    c.steady()
                );
            }
        }
    }
    if fits.is_empty() {
        return Err(Error::new(
            ErrorKind::NoConvergence,
            "no model could be fitted to this recording",
        )
        .with_note("a recording shorter than its time constants cannot tell them: try first-order, or record longer"));
    }
    let svg = a
        .plot
        .as_ref()
        .map(|_| plot_fits(&record, &fits))
        .transpose()?;
    let text = match a.format {
        Format::Table => render_fits_table(&fits),
        Format::Csv => render_fits_csv(&fits),
        Format::Json => render_fits_json(record.file(), record.len(), &fits),
    };
    match (&a.plot, svg) {
        (Some(PlotTo::Stdout), Some(svg)) => write_stdout(svg.as_bytes())?,
        (Some(PlotTo::File(path)), Some(svg)) => {
            write_output(&a.checked, path, svg.as_bytes())?;
            write_stdout(text.as_bytes())?;
        }
        _ => write_stdout(text.as_bytes())?,
    }
    Ok(Status::Success)
}

/// A forecast beyond the recording whose curves the data cannot tell apart
/// spread over more than [`STEADY_WARN_C`] is said with its range: the
/// number printed is one of many the recording allows.
fn warn_uncertain_forecasts(fitted: &FittedProfile, at: &[f64]) {
    let (_, end) = fitted.window();
    for &t in at.iter().filter(|&&t| t > end) {
        for (axis, range) in fitted.uncertainty_at(t).iter().enumerate() {
            if let Some((lo, hi)) = range.filter(|(lo, hi)| hi - lo > STEADY_WARN_C) {
                warning!(
                    "axis {}, minute {t}: a {end:.0}-min recording cannot tell this forecast better than {lo:.1} to {hi:.1} °C; record longer",
                    axis + 1
                );
            }
        }
    }
}

fn run_eval(a: EvalCommand) -> Result<Status> {
    let profile: Box<dyn HeatingProfile> = match &a.temps {
        Temperatures::Fitted {
            records,
            kind,
            pin_t0,
        } => {
            let record = read_record(records)?;
            let fitted = FittedProfile::fit(&record, *kind, *pin_t0)?;
            warn_uncertain_forecasts(&fitted, &a.at);
            Box::new(fitted)
        }
        Temperatures::Measured { records, hold_ends } => {
            let record = read_record(records)?;
            let p = RecordedProfile::new(&record);
            Box::new(if *hold_ends { p.holding_ends() } else { p })
        }
        Temperatures::Default => Box::new(default_profile()),
    };
    let mut rows = Vec::new();
    for &t in &a.at {
        let temps = profile.temps_at(t)?;
        let mut row = vec![format!("{t}")];
        row.extend(temps.iter().map(|v| format!("{v:.3}")));
        rows.push(row);
    }
    let header = ["time_min", "t1_c", "t2_c", "t3_c", "t4_c", "t5_c", "t6_c"];
    let text = match a.format {
        Format::Table => render_table(&header, &[Align::Right; 7], &rows),
        Format::Csv => render_csv(&header, &rows),
        Format::Json => {
            let mut out = Vec::new();
            for &t in &a.at {
                out.push(serde_json::json!({"time_min": t, "temps_c": profile.temps_at(t)?}));
            }
            rapidtherm::report::json::rows("heating-eval", "rows", &out)?
        }
    };
    write_stdout(text.as_bytes())?;
    Ok(Status::Success)
}

/// A temperature argument: a number a robot's motor can have (the same
/// bounds as every recording's, `data/thermal/plausible.toml`).
fn celsius(text: &str) -> std::result::Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    match rapidtherm::thermal::plausible::implausible(v) {
        None => Ok(v),
        Some(why) => Err(why),
    }
}
