//! Generator of `samples/heating_irb140_60pct.csv`, the synthesised reference
//! heating recording (the paper's own data are not published).
//!
//!     cargo run --example synth_heating -- samples/heating_irb140_60pct.csv
//!
//! Deterministic: same seed, same bytes. Prints a per-axis fit summary on
//! stderr. How each axis is made is written into the file's header.

use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rapidtherm::thermal::fit::{fit_points, ModelKind};
use rapidtherm::thermal::poly::fit_poly;
use rapidtherm::thermal::TABLE1_TMAX;
use std::fmt::Write as _;

const SEED: u64 = 20_190_140;
const ROWS: usize = 2017;
const STEP_MIN: f64 = 5.0 / 60.0;
const COLD_C: f64 = 7.0;
const NOISE_C: f64 = 0.05;
/// The paper's printed cubic for axis 1, [d, c, b, a]: y = a·x³ + b·x² + c·x + d.
const PAPER_CUBIC: [f64; 4] = [7.769163, 0.247369, -0.001969, 0.000005];
/// How close the cubic fit of the rounded data must come to the intended
/// cubic: half a unit of each printed digit, and for the leading coefficient
/// close enough that the linear and quadratic projections keep their
/// printed 4 decimals too (their constants move by ~1 per 1e-6 of a).
const PRINTED_HALF_ULP: [f64; 4] = [5e-7, 5e-7, 5e-7, 1e-11];

/// Axes 2..6: (fraction of the rise in the fast term, τ fast, τ slow), in
/// minutes. The upper-arm motors (4, 5, 6) are enclosed and rise faster at
/// first; axis 6 is the steepest (the paper: worst cubic Ā ≈ 2.03 %).
const SHAPES: [(f64, f64, f64); 5] = [
    (0.25, 14.0, 80.0),
    (0.22, 14.0, 80.0),
    (0.30, 14.0, 75.0),
    (0.30, 13.0, 70.0),
    (0.32, 12.0, 65.0),
];

fn main() {
    let out = std::env::args().nth(1);
    // Times as the file will hold them (6 decimals), so that the fits made
    // here see exactly what a reader of the file sees.
    let times: Vec<f64> = (0..ROWS)
        .map(|i| {
            format!("{:.6}", i as f64 * STEP_MIN)
                .parse::<f64>()
                .unwrap_or(0.0)
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let noise = Normal::new(0.0, NOISE_C).expect("valid normal");

    let mut header = String::new();
    let mut columns: Vec<Vec<i64>> = Vec::new();

    // Axis 1: a two-time-constant curve from 7.0 °C whose cubic least-squares
    // fit over these times is as close as possible to the paper's cubic,
    // plus the (cubic) remainder, so that its cubic fit IS the paper's cubic.
    let (cubic1, shape1, base1) = axis1_base(&times);
    let mut n1: Vec<f64> = (0..ROWS).map(|_| noise.sample(&mut rng)).collect();
    let proj = project_cubic(&times, &n1);
    for (v, p) in n1.iter_mut().zip(&proj) {
        *v -= p;
    }
    let y1: Vec<f64> = base1.iter().zip(&n1).map(|(b, n)| b + n).collect();
    let q1 = quantise_keeping_cubic(&times, &y1, &cubic1);
    columns.push(q1);
    let _ = writeln!(
        header,
        "# axis 1: 7.0 + {:.4}*(1-exp(-t/{:.3})) + {:.4}*(1-exp(-t/{:.3})), chosen so that its cubic least-squares fit over",
        shape1[0], shape1[1], shape1[2], shape1[3]
    );
    let _ = writeln!(
        header,
        "#   these times is y = {:e}x^3 {:+e}x^2 {:+}x {:+}:",
        cubic1[3], cubic1[2], cubic1[1], cubic1[0]
    );
    let _ = writeln!(
        header,
        "#   the cubic whose digits round to the paper's printed cubic and whose linear and quadratic least-squares"
    );
    let _ = writeln!(
        header,
        "#   projections round to the paper's printed linear and quadratic fits; plus the small cubic remainder,"
    );
    let _ = writeln!(
        header,
        "#   plus N(0, {NOISE_C}) noise made orthogonal to cubics, rounded to 0.01 with rounding directions chosen to keep that cubic"
    );

    // Axes 2..6: two time constants from 7.0 °C, reaching the table-1
    // maximum at the end of the recording (168 min).
    let t_end = times[ROWS - 1];
    for (k, &(w, tau1, tau2)) in SHAPES.iter().enumerate() {
        let axis = k + 2;
        let shape = |t: f64| w * -(-t / tau1).exp_m1() + (1.0 - w) * -(-t / tau2).exp_m1();
        let rise = (TABLE1_TMAX[axis - 1] - COLD_C) / shape(t_end);
        let col: Vec<i64> = times
            .iter()
            .map(|&t| hundredths(COLD_C + rise * shape(t) + noise.sample(&mut rng)))
            .collect();
        columns.push(col);
        let _ = writeln!(
            header,
            "# axis {axis}: 7.0 + {:.4}*(1-exp(-t/{tau1})) + {:.4}*(1-exp(-t/{tau2})) + N(0, {NOISE_C}), rounded to 0.01",
            rise * w,
            rise * (1.0 - w)
        );
    }

    let mut csv = String::new();
    csv.push_str("# SYNTHESISED reference heating recording for rapidtherm, NOT measured data.\n");
    csv.push_str("# It imitates the recording of Cristoiu and Ivan (IRB 140, 60 % of maximum speed, cold lab at about 7 C):\n");
    csv.push_str("# 2017 rows at 5 s (0 to 168 min), motor temperatures of axes 1..6 in C, 0.01 C resolution.\n");
    let _ = writeln!(
        csv,
        "# Generator: cargo run --example synth_heating -- samples/heating_irb140_60pct.csv (ChaCha8 seed {SEED})."
    );
    csv.push_str("# Axes 2..6 reach the table-1 maxima of Cristoiu et al. 2020 (the FEA paper) at 168 min. Model per axis (t in min):\n");
    csv.push_str(&header);
    csv.push_str("time_min,t1_c,t2_c,t3_c,t4_c,t5_c,t6_c\n");
    for (i, t) in times.iter().enumerate() {
        let _ = write!(csv, "{t:.6}");
        for col in &columns {
            let _ = write!(csv, ",{:.2}", col[i] as f64 / 100.0);
        }
        csv.push('\n');
    }

    summary(&times, &columns);
    match out {
        Some(path) => std::fs::write(&path, csv).expect("write the sample"),
        None => print!("{csv}"),
    }
}

fn hundredths(v: f64) -> i64 {
    (v * 100.0).round() as i64
}

/// Least-squares projection of `y` on cubics in t (values at the times).
fn project_cubic(t: &[f64], y: &[f64]) -> Vec<f64> {
    let c = fit_poly(t, y, 3).expect("cubic fit");
    t.iter().map(|&x| c.eval(x)).collect()
}

/// The printed linear and quadratic fits of axis 1, [constant, x, x²].
const PAPER_LINEAR: [f64; 2] = [11.9655, 0.0522];
const PAPER_QUADRATIC: [f64; 3] = [9.0328, 0.1570, -0.0006];

/// The cubic of axis 1 at full precision: the paper printed it, and the
/// linear and quadratic fits of the same data, rounded. Least-squares fits of
/// one data set are projections of each other, so the full-precision cubic
/// is the one whose own digits and whose linear and quadratic projections
/// over these times all round to the printed numbers: found by weighted
/// least squares over those nine printed numbers (each weighted by its
/// printed half-unit), then checked.
fn paper_cubic(t: &[f64]) -> [f64; 4] {
    // Projection of each monomial x^j on polynomials of degree `deg`.
    let project = |deg: usize, j: usize| -> Vec<f64> {
        let y: Vec<f64> = t.iter().map(|&x| x.powi(j as i32)).collect();
        fit_poly(t, &y, deg).expect("projection").coefficients()
    };
    // Rows: (coefficient of the printed number as a function of the cubic's
    // [d, c, b, a], printed value, half-unit).
    let mut rows: Vec<([f64; 4], f64, f64)> = Vec::new();
    for k in 0..4 {
        let mut unit = [0.0; 4];
        unit[k] = 1.0;
        rows.push((unit, PAPER_CUBIC[k], 5e-7));
    }
    for (deg, printed) in [(1, &PAPER_LINEAR[..]), (2, &PAPER_QUADRATIC[..])] {
        let proj: Vec<Vec<f64>> = (0..4).map(|j| project(deg, j)).collect();
        for (k, &value) in printed.iter().enumerate() {
            rows.push((std::array::from_fn(|j| proj[j][k]), value, 5e-5));
        }
    }
    // Unknowns scaled by 168^k so the system is well conditioned.
    let s = t[t.len() - 1];
    let a = DMatrix::from_fn(rows.len(), 4, |r, j| {
        rows[r].0[j] * s.powi(-(j as i32)) / rows[r].2
    });
    let b = DVector::from_iterator(rows.len(), rows.iter().map(|r| r.1 / r.2));
    let x = a.svd(true, true).solve(&b, 1e-12).expect("weighted fit");
    let cubic: [f64; 4] = std::array::from_fn(|j| x[j] * s.powi(-(j as i32)));
    for (coef, value, half) in &rows {
        let v: f64 = coef.iter().zip(&cubic).map(|(c, k)| c * k).sum();
        eprintln!(
            "printed {value:>10} reproduced {v:.9} ({:+.2} of the rounding half-width)",
            (v - value) / half
        );
    }
    cubic
}

/// The cubic of axis 1 ([d, c, b, a]), the two-time-constant curve from
/// 7.0 °C (ΔT1, τ1, ΔT2, τ2) whose cubic projection over these times is
/// closest to it, and that curve plus the remaining cubic difference (whose
/// cubic projection is then exactly the cubic).
fn axis1_base(t: &[f64]) -> ([f64; 4], [f64; 4], Vec<f64>) {
    let cubic = paper_cubic(t);
    let target_fn: Vec<f64> = t.iter().map(|&x| eval_power(&cubic, x)).collect();
    let b = DVector::from_iterator(t.len(), target_fn.iter().map(|v| v - COLD_C));
    let proj_e = |tau: f64| -> Vec<f64> {
        let e: Vec<f64> = t.iter().map(|&x| -(-x / tau).exp_m1()).collect();
        project_cubic(t, &e)
    };
    // For fixed τ the ΔT are linear: minimise ‖P3(g) − cubic‖ over a grid of
    // (ln τ1, ln τ2), then zoom in around the best point.
    let solve = |l1: f64, l2: f64| -> Option<(f64, [f64; 4])> {
        let (p1, p2) = (proj_e(l1.exp()), proj_e(l2.exp()));
        let a = DMatrix::from_fn(t.len(), 2, |r, c| if c == 0 { p1[r] } else { p2[r] });
        let x = a.clone().svd(true, true).solve(&b, 1e-12).ok()?;
        let sse = (a * &x - &b).norm_squared();
        (x[0] > 0.0 && x[1] > 0.0).then_some((sse, [x[0], l1.exp(), x[1], l2.exp()]))
    };
    let (mut c1, mut c2, mut width) = (2.5f64, 4.0f64, 2.0f64);
    let mut best: Option<(f64, [f64; 4])> = None;
    for _ in 0..6 {
        for i in 0..=12 {
            for j in 0..=12 {
                let l1 = c1 + width * (i as f64 / 6.0 - 1.0);
                let l2 = c2 + width * (j as f64 / 6.0 - 1.0);
                if l1 >= l2 {
                    continue;
                }
                if let Some(s) = solve(l1, l2) {
                    if best.is_none_or(|(b, _)| s.0 < b) {
                        best = Some(s);
                    }
                }
            }
        }
        if let Some((_, p)) = best {
            (c1, c2) = (p[1].ln(), p[3].ln());
        }
        width /= 4.0;
    }
    let (_, p) = best.expect("a two-time-constant curve");
    let g: Vec<f64> = t
        .iter()
        .map(|&x| COLD_C + p[0] * -(-x / p[1]).exp_m1() + p[2] * -(-x / p[3]).exp_m1())
        .collect();
    let gp = project_cubic(t, &g);
    let rem = (0..t.len())
        .map(|i| (target_fn[i] - gp[i]).abs())
        .fold(0.0, f64::max);
    eprintln!("axis 1: cubic {cubic:?}, curve {p:?}, largest cubic remainder {rem:.2e} C");
    let base = (0..t.len()).map(|i| g[i] + target_fn[i] - gp[i]).collect();
    (cubic, p, base)
}

fn eval_power(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, k| acc * x + k)
}

/// Round to 0.01 °C, then move single values to their other 0.01 neighbour
/// (never further than 0.01 from the unrounded value) until the cubic fit
/// of the rounded data reproduces the paper's printed coefficients.
fn quantise_keeping_cubic(t: &[f64], y: &[f64], cubic: &[f64; 4]) -> Vec<i64> {
    let n = t.len();
    let scale = t[n - 1];
    // Coefficient k (of t^k) = Σ_i m[k][i]·q_i, via the pseudo-inverse of the
    // design in t/scale (well conditioned), rescaled by scale^-k.
    let xs = DMatrix::from_fn(n, 4, |i, k| (t[i] / scale).powi(k as i32));
    let pinv = xs.pseudo_inverse(1e-14).expect("pseudo-inverse");
    let m: Vec<[f64; 4]> = (0..n)
        .map(|i| std::array::from_fn(|k| pinv[(k, i)] / scale.powi(k as i32) / PRINTED_HALF_ULP[k]))
        .collect();
    let mut q: Vec<i64> = y.iter().map(|&v| hundredths(v)).collect();
    let coef = |q: &[i64]| -> [f64; 4] {
        std::array::from_fn(|k| {
            (0..n).map(|i| m[i][k] * q[i] as f64 / 100.0).sum::<f64>()
                - cubic[k] / PRINTED_HALF_ULP[k]
        })
    };
    let mut err = coef(&q);
    let norm = |e: &[f64; 4]| e.iter().map(|v| v * v).sum::<f64>();
    let step_of = |q: &[i64], i: usize| if (q[i] as f64) / 100.0 > y[i] { -1 } else { 1 };
    for _ in 0..20_000 {
        if err.iter().all(|e| e.abs() < 0.2) {
            break;
        }
        let moved = |e: &[f64; 4], i: usize, step: i64| -> [f64; 4] {
            std::array::from_fn(|k| e[k] + m[i][k] * step as f64 / 100.0)
        };
        // Best single move; when none helps, best pair of moves.
        let mut best = (norm(&err), Vec::new(), err);
        for i in 0..n {
            let e = moved(&err, i, step_of(&q, i));
            if norm(&e) < best.0 {
                best = (norm(&e), vec![i], e);
            }
        }
        if best.1.is_empty() {
            for i in 0..n {
                let ei = moved(&err, i, step_of(&q, i));
                for j in i + 1..n {
                    let e = moved(&ei, j, step_of(&q, j));
                    if norm(&e) < best.0 {
                        best = (norm(&e), vec![i, j], e);
                    }
                }
            }
        }
        if best.1.is_empty() {
            break;
        }
        for &i in &best.1 {
            q[i] += step_of(&q, i);
        }
        err = best.2;
    }
    let err = coef(&q);
    eprintln!("axis 1 cubic after rounding, error / tolerance: {err:?}");
    assert!(
        err.iter().all(|e| e.abs() < 0.5),
        "could not keep the printed cubic"
    );
    q
}

fn summary(t: &[f64], columns: &[Vec<i64>]) {
    for (a, col) in columns.iter().enumerate() {
        let y: Vec<f64> = col.iter().map(|&v| v as f64 / 100.0).collect();
        for kind in [ModelKind::Poly(3), ModelKind::FirstOrder, ModelKind::TwoTau] {
            match fit_points(a + 1, t, &y, kind, None) {
                Ok(f) => eprintln!(
                    "axis {} {:<12} R2 {:.5} A {:.4} % rmse {:.4} max {:.3} holdout rmse {:.4} | end {:.2}",
                    a + 1,
                    kind.to_string(),
                    f.fit.r2.unwrap_or(f64::NAN),
                    f.fit.mean_rel_pct.unwrap_or(f64::NAN),
                    f.fit.rmse,
                    f.fit.max_abs,
                    f.holdout.map_or(f64::NAN, |h| h.rmse),
                    y[y.len() - 1]
                ),
                Err(e) => eprintln!("axis {} {kind}: {e}", a + 1),
            }
        }
    }
}
