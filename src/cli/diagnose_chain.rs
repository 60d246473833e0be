//! `diagnose` on a general serial chain (an arm without the OPW form, or
//! any arm with `--chain`): printing only; the job
//! (`rapidtherm::diagnose::job`) chooses and runs it.

use super::diagnose_args::parameter_table;
use super::Format;
use rapidtherm::diagnose::chain_calib::{Dropped, Unidentified};
use rapidtherm::diagnose::chain_diagnose::ChainDiagnosis;
use rapidtherm::error::Result;
use rapidtherm::report::{render_csv, render_table, Align};

/// The general chain's calibration report, in the format asked for.
pub fn render(format: Format, d: &ChainDiagnosis) -> Result<String> {
    Ok(match format {
        Format::Json => rapidtherm::report::json::document("diagnose-chain", d)?,
        Format::Csv => render_csv(
            &[
                "stage",
                "parameters",
                "fit_rms_mm",
                "cv_rms_mm",
                "holdout_rms_mm",
                "holdout_max_mm",
            ],
            &stage_rows(d),
        ),
        Format::Table => table(d),
    })
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
