//! Fit results as text: the paper-like per-axis table, CSV and JSON. Every
//! coefficient is printed so that it reads back to the same f64 (shortest
//! round-trip form); the 6-decimal equation is only for reading.

use super::fit::{AxisFit, Curve, Metrics};
use crate::report::{render_csv, render_table, Align};
use serde_json::{json, Value};

/// A number printed so that parsing it gives back the same f64.
pub fn exact(v: f64) -> String {
    if v != 0.0 && v.abs() < 1e-3 {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

fn opt(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "n/a".to_string(), |v| format!("{v:.decimals$}"))
}

/// The equation the way the paper prints it (6 decimals), for reading.
pub fn equation(curve: &Curve) -> String {
    match curve {
        Curve::Poly(p) => {
            let c = p.coefficients();
            let mut out = String::from("y =");
            for (k, v) in c.iter().enumerate().rev() {
                let sign = if v < &0.0 { '-' } else { '+' };
                let first = k + 1 == c.len();
                let mag = format!("{:.6}", v.abs());
                match (first, sign) {
                    (true, '-') => out.push_str(&format!(" -{mag}")),
                    (true, _) => out.push_str(&format!(" {mag}")),
                    _ => out.push_str(&format!(" {sign} {mag}")),
                }
                match k {
                    0 => {}
                    1 => out.push('x'),
                    _ => out.push_str(&format!("x^{k}")),
                }
            }
            out
        }
        Curve::Saturating(s) => {
            let mut out = format!("T = {:.4}", s.t0);
            for term in &s.terms {
                let sign = if term.delta < 0.0 { '-' } else { '+' };
                out.push_str(&format!(
                    " {sign} {:.4}(1-e^(-t/{:.3}))",
                    term.delta.abs(),
                    term.tau
                ));
            }
            out
        }
    }
}

/// Named parameters at full precision: (name, value).
pub fn parameters(curve: &Curve) -> Vec<(String, f64)> {
    match curve {
        Curve::Poly(p) => {
            let mut out: Vec<(String, f64)> = p
                .coefficients()
                .iter()
                .enumerate()
                .rev()
                .map(|(k, v)| (format!("x^{k}"), *v))
                .collect();
            out.extend(
                p.scaled_coefficients()
                    .iter()
                    .enumerate()
                    .rev()
                    .map(|(k, v)| (format!("s^{k}"), *v)),
            );
            out.push(("t_lo".to_string(), p.t_lo));
            out.push(("t_hi".to_string(), p.t_hi));
            out
        }
        Curve::Saturating(s) => {
            let mut out = vec![("T0".to_string(), s.t0)];
            for (j, term) in s.terms.iter().enumerate() {
                out.push((format!("dT{}", j + 1), term.delta));
                out.push((format!("tau{}", j + 1), term.tau));
            }
            out
        }
    }
}

const METRIC_HEADER: [&str; 11] = [
    "axis",
    "model",
    "equation",
    "R",
    "R2",
    "A_pct",
    "rmse_c",
    "max_c",
    "holdout_rmse_c",
    "holdout_max_c",
    "parameters",
];

fn metric_cells(f: &AxisFit) -> Vec<String> {
    let m: &Metrics = &f.fit;
    vec![
        f.axis.to_string(),
        f.model_name(),
        equation(&f.curve),
        opt(m.r, 4),
        opt(m.r2, 5),
        opt(m.mean_rel_pct, 4),
        format!("{:.4}", m.rmse),
        format!("{:.3}", m.max_abs),
        opt(f.holdout.map(|h| h.rmse), 4),
        opt(f.holdout.map(|h| h.max_abs), 3),
    ]
}

/// The per-axis table (like the paper's, plus RMSE, max and held-out error),
/// then the parameters at full precision.
pub fn render_fits_table(fits: &[AxisFit]) -> String {
    let rows: Vec<Vec<String>> = fits.iter().map(metric_cells).collect();
    let mut align = vec![Align::Right, Align::Left, Align::Left];
    align.extend([Align::Right; 7]);
    let mut out = render_table(&METRIC_HEADER[..10], &align, &rows);
    out.push('\n');
    let prows: Vec<Vec<String>> = fits
        .iter()
        .flat_map(|f| {
            parameters(&f.curve)
                .into_iter()
                .map(move |(name, v)| vec![f.axis.to_string(), f.model_name(), name, exact(v)])
        })
        .collect();
    out.push_str(&render_table(
        &["axis", "model", "parameter", "value"],
        &[Align::Right, Align::Left, Align::Left, Align::Right],
        &prows,
    ));
    out
}

/// One CSV row per fit; `parameters` holds `name=value` pairs separated by
/// `;` at full precision.
pub fn render_fits_csv(fits: &[AxisFit]) -> String {
    let rows: Vec<Vec<String>> = fits
        .iter()
        .map(|f| {
            let mut cells = metric_cells(f);
            let params: Vec<String> = parameters(&f.curve)
                .into_iter()
                .map(|(n, v)| format!("{n}={}", exact(v)))
                .collect();
            cells.push(params.join(";"));
            cells
        })
        .collect();
    render_csv(&METRIC_HEADER, &rows)
}

fn metrics_json(m: &Metrics) -> Value {
    json!({
        "n": m.n,
        "r": m.r,
        "r2": m.r2,
        "mean_rel_err_pct": m.mean_rel_pct,
        "rmse_c": m.rmse,
        "max_abs_c": m.max_abs,
    })
}

/// Full results as JSON (`rapidtherm.heating-fit/1`): temperatures to
/// 1e-3 °C, the rest at full precision (`report::json`).
pub fn render_fits_json(file: &str, rows: usize, fits: &[AxisFit]) -> String {
    let fits: Vec<Value> = fits
        .iter()
        .map(|f| {
            let mut v = json!({
                "axis": f.axis,
                "model": f.kind.to_string(),
                "equation": equation(&f.curve),
                "fit": metrics_json(&f.fit),
                "holdout": f.holdout.as_ref().map(metrics_json),
            });
            if !f.chosen_from.is_empty() {
                // How `auto` chose: each candidate's held-out forecast error.
                v["chosen_by"] = json!("auto");
                v["candidates"] = json!(f
                    .chosen_from
                    .iter()
                    .map(|c| json!({
                        "model": c.kind.to_string(),
                        "holdout_rmse_c": c.holdout_rmse,
                        "refused": c.refused,
                    }))
                    .collect::<Vec<_>>());
            }
            match &f.curve {
                Curve::Poly(p) => {
                    v["window_min"] = json!([p.t_lo, p.t_hi]);
                    v["coefficients"] = json!(p.coefficients());
                    v["scaled_coefficients"] = json!(p.scaled_coefficients());
                    v["legendre_coefficients"] = json!(p.legendre);
                }
                Curve::Saturating(s) => {
                    v["t0_c"] = json!(s.t0);
                    v["terms"] = json!(s
                        .terms
                        .iter()
                        .map(|k| json!({"delta_c": k.delta, "tau_min": k.tau}))
                        .collect::<Vec<_>>());
                    v["steady_c"] = json!(s.steady());
                    v["steady_interval_c"] = json!(f.steady_interval.map(|(a, b)| [a, b]));
                }
            }
            v
        })
        .collect();
    let doc = json!({
        "file": file,
        "rows": rows,
        "holdout": "fitted to the first 80 % of the rows, evaluated on the last 20 %",
        "coefficients_order": "constant first, in minutes (x); scaled: s = (2x - t_lo - t_hi)/(t_hi - t_lo)",
        "fits": fits,
    });
    crate::report::json::document("heating-fit", &doc).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thermal::poly::fit_poly;

    #[test]
    fn equation_reads_like_the_paper() {
        let t: Vec<f64> = (0..=100).map(f64::from).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|&x| 0.000005 * x.powi(3) - 0.001969 * x * x + 0.247369 * x + 7.769163)
            .collect();
        let c = Curve::Poly(fit_poly(&t, &y, 3).unwrap());
        assert_eq!(
            equation(&c),
            "y = 0.000005x^3 - 0.001969x^2 + 0.247369x + 7.769163"
        );
    }

    #[test]
    fn exact_numbers_round_trip() {
        for v in [5.338326421134883e-6, 7.769163, -0.001969, 0.1 + 0.2] {
            assert_eq!(exact(v).parse::<f64>().unwrap(), v);
        }
    }
}
