//! The widened evaluation of the diagnosis (issue 46;
//! `tests/diagnose/wide/`): sets of four arms in every form the world
//! sends, each withholding one library effect (or none) at a size from zero
//! to four times the noise, diagnosed as a user would, and the confusion
//! table by class and by size relative to the detection limit.
//!
//!     cargo run --release --example diagnose_eval -- --sets 100 --seed 46000
//!
//! Options: `--sets N` per class (default 10), `--seed S` (default 46000;
//! set i of class c has seed S + 1000·c + i), `--classes 0,2` (places in
//! the class list: nothing, expansion-scale, thermal-lag, arm-bending,
//! joint-offset-drift, mount-drift, gravity-sag), `--from K` (skip the first
//! K sets of the run's order: a stopped run taken up on the same seeds),
//! `--quiet` (no line per set), `--dump DIR` (write each set's CSV as
//! `DIR/SEED.csv`, to run `rapidtherm diagnose` on it by hand),
//! `--check-saved BIN` (instead of the tables: every set diagnosed through
//! the library's job, its model saved, and the report's "after" checked
//! against `BIN gap --model` of the saved files to 1 %,
//! `wide/saved_check.rs`; BIN is a built `rapidtherm`). Every set's line, with its seed and form,
//! goes to stderr as it is done; the tables to stdout at the end.

#[path = "../tests/diagnose/wide/mod.rs"]
mod wide;

use std::process::ExitCode;
use wide::run::{evaluate, specs};
use wide::world::Class;

fn main() -> ExitCode {
    let mut sets = 10usize;
    let mut seed = 46_000u64;
    let mut classes: Vec<Class> = Class::ALL.to_vec();
    let mut from = 0usize;
    let mut quiet = false;
    let mut dump: Option<std::path::PathBuf> = None;
    let mut check_saved: Option<std::path::PathBuf> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |name: &str| args.next().ok_or_else(|| format!("{name} needs a value"));
        let parsed = match a.as_str() {
            "--sets" => value("--sets").and_then(|v| {
                v.parse()
                    .map_err(|e| format!("--sets: {e}"))
                    .map(|v| sets = v)
            }),
            "--seed" => value("--seed").and_then(|v| {
                v.parse()
                    .map_err(|e| format!("--seed: {e}"))
                    .map(|v| seed = v)
            }),
            "--from" => value("--from").and_then(|v| {
                v.parse()
                    .map_err(|e| format!("--from: {e}"))
                    .map(|v| from = v)
            }),
            "--classes" => value("--classes").and_then(|v| {
                v.split(',')
                    .map(|c| {
                        c.trim()
                            .parse::<usize>()
                            .ok()
                            .and_then(|i| Class::ALL.get(i).copied())
                            .ok_or_else(|| {
                                format!("--classes: `{c}` is not 0-{}", Class::ALL.len() - 1)
                            })
                    })
                    .collect::<Result<Vec<_>, _>>()
                    .map(|v| classes = v)
            }),
            "--dump" => value("--dump").map(|v| dump = Some(v.into())),
            "--check-saved" => value("--check-saved").map(|v| check_saved = Some(v.into())),
            "--quiet" => {
                quiet = true;
                Ok(())
            }
            other => Err(format!("unknown argument `{other}`")),
        };
        if let Err(e) = parsed {
            eprintln!("diagnose_eval: {e}");
            return ExitCode::from(2);
        }
    }
    let all = specs(sets, seed, &classes);
    let todo = &all[from.min(all.len())..];
    eprintln!(
        "{} sets ({sets} per class of {}), seeds {seed} + 1000 x class + i, from set {from}",
        todo.len(),
        classes.len()
    );
    if let Some(dir) = &dump {
        for spec in todo {
            let set = wide::world::generate(spec);
            let path = dir.join(format!("{}.csv", spec.seed));
            if let Err(e) = std::fs::write(&path, &set.csv) {
                eprintln!("diagnose_eval: {}: {e}", path.display());
                return ExitCode::from(2);
            }
            eprintln!(
                "{} [{}] withheld {}",
                path.display(),
                spec.form.label(),
                set.truth
                    .effect
                    .as_ref()
                    .map_or("nothing".into(), |e| format!(
                        "{} {:?}",
                        e.kind.name(),
                        e.params
                    ))
            );
        }
        return ExitCode::SUCCESS;
    }
    if let Some(bin) = &check_saved {
        return saved_everywhere(bin, todo, quiet);
    }
    let out = evaluate(todo, |r| {
        if !quiet || !r.right {
            eprintln!("{}", r.line());
        }
    });
    println!("{}", out.table());
    println!("seeds: {seed} + 1000 x class + i (classes in the order of the table), sets per class {sets}, from set {from}");
    ExitCode::SUCCESS
}

/// `--check-saved`: every set's "after" against `bin gap --model` of its
/// saved files; exit 1 if any differs.
fn saved_everywhere(bin: &std::path::Path, todo: &[wide::world::Spec], quiet: bool) -> ExitCode {
    let Ok(dir) = tempfile::tempdir() else {
        eprintln!("diagnose_eval: no temporary folder");
        return ExitCode::from(2);
    };
    let mut bad = 0usize;
    for spec in todo {
        let name = format!("s{}", spec.seed);
        let data = dir.path().join(format!("{name}.csv"));
        if let Err(e) = std::fs::write(&data, wide::world::generate(spec).csv) {
            eprintln!("diagnose_eval: {}: {e}", data.display());
            return ExitCode::from(2);
        }
        let checked = wide::saved_check::check(
            bin,
            &name,
            &data,
            spec.form.arm.urdf(),
            !spec.form.registered,
            dir.path(),
        );
        match checked {
            Ok((_, c)) if !quiet => eprintln!(
                "ok   seed {} [{}] after {:.4} / {:.4} mm held out, {:.4} / {:.4} mm all rows (report / saved files)",
                spec.seed,
                spec.form.label(),
                c.report_held_out_mm,
                c.file_held_out_mm,
                c.report_all_mm,
                c.file_all_mm
            ),
            Ok(_) => {}
            Err(e) => {
                bad += 1;
                eprintln!("DIFF seed {} [{}] {e}", spec.seed, spec.form.label());
            }
        }
    }
    println!(
        "{} of {} sets: the report's after is the saved model's to 1 %",
        todo.len() - bad,
        todo.len()
    );
    if bad == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
