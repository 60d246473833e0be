//! Sets diagnosed as a user would (the file read, `--robot` the arm's
//! URDF, `--register` where the frame is unknown, no `--noise`), scored,
//! and the confusion table: by class and by the withheld effect's size
//! relative to its detection limit, and by each dimension of the form.

use super::limit;
use super::score::{right, Expected};
use super::world::{generate, Class, Form, Spec};
use rapidtherm::diagnose::measurements::Measurements;
use rapidtherm::diagnose::{diagnose, prepare_arm, DiagnoseOptions, Diagnosis, ScoredIn};
use rapidtherm::model::{Effect, EffectKind, Model};
use std::collections::BTreeMap;
use std::time::Instant;

/// The sets of an evaluation of `per_class` sets per class: set `i` of
/// class `c` has seed `seed0 + 1000·c + i` and form `(37·i + 11·c) mod 64`
/// (every form once in 64 sets of a class, the classes on different
/// forms), ordered set by set across the classes so that a run stopped
/// early has measured every class about as often.
pub fn specs(per_class: usize, seed0: u64, classes: &[Class]) -> Vec<Spec> {
    let mut out = Vec::new();
    for i in 0..per_class {
        for (c, class) in Class::ALL.into_iter().enumerate() {
            if classes.contains(&class) {
                out.push(Spec {
                    class,
                    form: Form::of_index(37 * i + 11 * c),
                    seed: seed0 + 1000 * c as u64 + i as u64,
                });
            }
        }
    }
    out
}

/// One set's result.
#[derive(Debug, Clone)]
pub struct Record {
    pub spec: Spec,
    /// The withheld effect's size over its detection limit.
    pub rho: f64,
    /// Without temperature columns, the session's drift in time over its
    /// detection limit (0 with them).
    pub rho_drift: f64,
    /// The size over the limit the report itself gives for the withheld
    /// effect (`detection_limits`), where it gives one (a check of
    /// `limit.rs`; not for the lag, whose size is not a scale of its
    /// defaults).
    pub rho_report: Option<f64>,
    pub size_mm: f64,
    pub noise_mm: f64,
    pub rows: usize,
    pub expected: Expected,
    /// The verdict's labels (or the error the diagnosis ended in).
    pub labels: Vec<String>,
    pub right: bool,
    /// Held-out shrink of the gap above the noise where the withheld
    /// effect lives.
    pub shrink: Option<f64>,
    pub secs: f64,
}

/// Held-out shrink of the gap above the noise in the stage where an effect
/// of this kind lives (over time for thermal ones, the static stage
/// otherwise; the one stage where there is one), `None` where the gap
/// there is at the noise.
fn shrink_of(d: &Diagnosis, thermal: bool) -> Option<f64> {
    let n2 = d.noise.rms_mm.powi(2);
    let wanted = |p: ScoredIn| match p {
        ScoredIn::OverTime | ScoredIn::Absolute => thermal,
        ScoredIn::Static => !thermal,
        ScoredIn::All => true,
    };
    let stage = d.stages.iter().find(|s| wanted(s.part))?;
    let above = stage.gap_before_mm.powi(2) - n2;
    (above > 0.0).then(|| 1.0 - (stage.gap_after_mm.powi(2) - n2).max(0.0) / above)
}

/// Make, diagnose and score one set.
pub fn run_one(spec: &Spec) -> Record {
    let start = Instant::now();
    let set = generate(spec);
    let rho = limit::ratio(&set);
    let rho_drift = limit::drift_ratio(&set);
    let expected = Expected::of(spec.class, spec.form, rho, rho_drift);
    let result = Measurements::parse("wide.csv", set.csv.as_bytes(), &set.arm.limits_deg)
        .and_then(|m| prepare_arm(&m, &Model::default(), &set.arm, !spec.form.registered))
        .and_then(|p| diagnose(&p, &DiagnoseOptions::default()));
    let (labels, ok, shrink, rho_report) = match result {
        Ok(d) => {
            let labels = d.verdict.labels();
            let ok = right(expected, &labels, &d.ambiguous);
            let thermal = set
                .truth
                .effect
                .as_ref()
                .is_some_and(|e| e.kind.is_thermal());
            let reported = set.truth.effect.as_ref().and_then(|e| {
                let limit = d.detection_limits.iter().find(|l| l.effect == e.kind)?;
                let default = Effect::with_defaults(e.kind);
                // The withheld effect is its defaults times m.
                let (v, d0) = e
                    .params
                    .iter()
                    .zip(&default.params)
                    .find(|(_, d)| **d != 0.0)?;
                (e.kind != EffectKind::ThermalLag && limit.of_default > 0.0)
                    .then(|| (v / d0) / limit.of_default)
            });
            (labels, ok, shrink_of(&d, thermal), reported)
        }
        Err(e) => (vec![format!("error: {}", e.message)], false, None, None),
    };
    Record {
        spec: *spec,
        rho,
        rho_drift,
        rho_report,
        size_mm: set.truth.size_mm,
        noise_mm: set.truth.noise_mm,
        rows: set.truth.rows.len(),
        expected,
        labels,
        right: ok,
        shrink,
        secs: start.elapsed().as_secs_f64(),
    }
}

impl Record {
    /// One line: right or not, the class, seed, form, size, verdict.
    pub fn line(&self) -> String {
        format!(
            "{} {} seed {} [{}] {} rows, noise {:.3} mm, size {:.4} mm = {:.2} x limit ({} by the report's), drift {:.2} x limit, expected {}, verdict {}, shrink {}, {:.1} s",
            if self.right { "ok  " } else { "MISS" },
            self.spec.class.name(),
            self.spec.seed,
            self.spec.form.label(),
            self.rows,
            self.noise_mm,
            self.size_mm,
            self.rho,
            self.rho_report.map_or("-".into(), |r| format!("{r:.2}")),
            self.rho_drift,
            self.expected.words(),
            self.labels.join(" + "),
            self.shrink.map_or("-".into(), |s| format!("{s:.3}")),
            self.secs
        )
    }

    /// Whether the right verdict names the withheld effect: the sets whose
    /// shrink the acceptance counts.
    pub fn nameable(&self) -> bool {
        self.expected.named.is_some()
    }
}

/// The size bins relative to the detection limit.
const BINS: [(f64, f64, &str); 5] = [
    (0.0, 0.5, "<0.5"),
    (0.5, 1.0, "0.5-1"),
    (1.0, 2.0, "1-2"),
    (2.0, 4.0, "2-4"),
    (4.0, f64::INFINITY, ">=4"),
];

fn bin(r: &Record) -> &'static str {
    if r.spec.class == Class::Nothing {
        return "none";
    }
    BINS.iter()
        .find(|(lo, hi, _)| r.rho >= *lo && r.rho < *hi)
        .map_or(">=4", |b| b.2)
}

fn cell((r, n): (usize, usize)) -> String {
    if n == 0 {
        "".into()
    } else {
        format!("{r}/{n}")
    }
}

/// A dimension of the form: its name and each set's value of it.
type Dimension<'a> = (&'a str, &'a dyn Fn(&Form) -> String);

/// Every set's record, and the tables.
pub struct Outcome {
    pub records: Vec<Record>,
}

impl Outcome {
    pub fn total(&self) -> (usize, usize) {
        (
            self.records.iter().filter(|r| r.right).count(),
            self.records.len(),
        )
    }

    /// The median shrink over the sets whose right verdict names the
    /// withheld effect (`None` where there are none).
    pub fn median_shrink(&self) -> Option<f64> {
        let mut s: Vec<f64> = self
            .records
            .iter()
            .filter(|r| r.nameable())
            .filter_map(|r| r.shrink)
            .collect();
        s.sort_by(f64::total_cmp);
        s.get(s.len() / 2).copied()
    }

    /// The confusion tables, as Markdown.
    pub fn table(&self) -> String {
        let mut out = String::new();
        // By class and size relative to the detection limit.
        let cols: Vec<&str> = std::iter::once("none")
            .chain(BINS.iter().map(|b| b.2))
            .collect();
        out.push_str("| class | right | ");
        out.push_str(
            &cols
                .iter()
                .map(|c| format!("size/limit {c}"))
                .collect::<Vec<_>>()
                .join(" | "),
        );
        out.push_str(" |\n|---|---:|");
        out.push_str(&"---:|".repeat(cols.len()));
        out.push('\n');
        for class in Class::ALL {
            let of: Vec<&Record> = self
                .records
                .iter()
                .filter(|r| r.spec.class == class)
                .collect();
            if of.is_empty() {
                continue;
            }
            let count = |f: &dyn Fn(&Record) -> bool| {
                let n = of.iter().filter(|r| f(r)).count();
                let k = of.iter().filter(|r| f(r) && r.right).count();
                (k, n)
            };
            out.push_str(&format!(
                "| {} | {} |",
                class.name(),
                cell(count(&|_: &Record| true))
            ));
            for c in &cols {
                out.push_str(&format!(" {} |", cell(count(&|r: &Record| bin(r) == *c))));
            }
            out.push('\n');
        }
        // By each dimension of the form.
        out.push_str("\n| form | right |\n|---|---:|\n");
        let yes_no = |b: bool, yes: &str, no: &str| (if b { yes } else { no }).to_string();
        let dims: [Dimension; 5] = [
            ("arm", &|f: &Form| f.arm.name().to_string()),
            ("temperatures", &|f: &Form| {
                yes_no(f.temps, "logged", "no columns")
            }),
            ("poses", &|f: &Form| {
                yes_no(f.repeats, "repeated", "each once")
            }),
            ("time", &|f: &Form| yes_no(f.clock, "clock", "order only")),
            ("frame", &|f: &Form| {
                yes_no(f.registered, "known", "registered (--register)")
            }),
        ];
        for (name, key) in dims {
            let mut by: BTreeMap<String, (usize, usize)> = BTreeMap::new();
            for r in &self.records {
                let e = by.entry(key(&r.spec.form)).or_default();
                e.0 += usize::from(r.right);
                e.1 += 1;
            }
            for (k, v) in by {
                out.push_str(&format!("| {name}: {k} | {} |\n", cell(v)));
            }
        }
        // The verdicts per class and what was expected.
        out.push_str(
            "\n| class | expected | verdicts (how often; misses marked) |\n|---|---|---|\n",
        );
        for class in Class::ALL {
            let mut by: BTreeMap<String, BTreeMap<String, (usize, bool)>> = BTreeMap::new();
            for r in self.records.iter().filter(|r| r.spec.class == class) {
                let e = by
                    .entry(r.expected.words())
                    .or_default()
                    .entry(r.labels.join(" + "))
                    .or_insert((0, r.right));
                e.0 += 1;
            }
            for (expected, verdicts) in by {
                let v: Vec<String> = verdicts
                    .iter()
                    .map(|(l, (n, ok))| format!("{}{l} ({n})", if *ok { "" } else { "MISS " }))
                    .collect();
                out.push_str(&format!(
                    "| {} | {expected} | {} |\n",
                    class.name(),
                    v.join("; ")
                ));
            }
        }
        // Near the limit the right answer is nearly a coin's: an effect at
        // the limit is found by its test in 90 % of sets, at half of it in
        // about a quarter, and a size fitted to a few tenths of the limit
        // falls on either side of it.
        let near = |r: &Record| r.spec.class != Class::Nothing && (0.5..2.0).contains(&r.rho);
        let split = |f: &dyn Fn(&Record) -> bool| {
            let of: Vec<&Record> = self.records.iter().filter(|r| f(r)).collect();
            (of.iter().filter(|r| r.right).count(), of.len())
        };
        let (rn, nn) = split(&|r: &Record| near(r));
        let (ra, na) = split(&|r: &Record| !near(r));
        out.push_str(&format!(
            "\naway from the detection limit (nothing withheld, or size/limit < 0.5 or >= 2): {ra}/{na}; near it (0.5-2): {rn}/{nn}\n"
        ));
        let (r, n) = self.total();
        let secs: f64 = self.records.iter().map(|r| r.secs).sum();
        let nameable = self.records.iter().filter(|r| r.nameable()).count();
        out.push_str(&format!(
            "\nright {r}/{n} ({:.1} %); median held-out shrink of the gap above noise {} over the {} sets whose right verdict names the effect; {:.1} s per set ({:.0} s in all)\n",
            100.0 * r as f64 / n.max(1) as f64,
            self.median_shrink().map_or("-".into(), |s| format!("{s:.3}")),
            nameable,
            secs / n.max(1) as f64,
            secs
        ));
        out
    }
}

/// Evaluate `specs`, each set's line given to `each` as it is done.
pub fn evaluate(specs: &[Spec], mut each: impl FnMut(&Record)) -> Outcome {
    let mut records = Vec::with_capacity(specs.len());
    for s in specs {
        let r = run_one(s);
        each(&r);
        records.push(r);
    }
    Outcome { records }
}
