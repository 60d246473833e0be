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
//! `--quiet` (no line per set). Every set's line, with its seed and form,
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
    let out = evaluate(todo, |r| {
        if !quiet || !r.right {
            eprintln!("{}", r.line());
        }
    });
    println!("{}", out.table());
    println!("seeds: {seed} + 1000 x class + i (classes in the order of the table), sets per class {sets}, from set {from}");
    ExitCode::SUCCESS
}
