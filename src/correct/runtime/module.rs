//! The RAPID system module that corrects targets on the controller: the
//! arm's numbers as data, the heating state in PERS data, the clock, the
//! update, the drift and the correcting functions. Only instructions and
//! functions of the RAPID reference manual are used (docs/runtime.md
//! lists each).

use super::spec::{RuntimeSpec, MAX_TERMS};
use super::table::TableRows;

/// What the user may choose of the module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModuleOptions {
    /// The module's name (its file is `NAME.sys`).
    pub name: String,
    /// The tool's version, for the header.
    pub version: String,
    /// Where the heating curves came from, for the header.
    pub heating_source: String,
    /// The model's label, for the header (the `--check` gate compares
    /// the whole module with the one this version would write).
    pub model: String,
}

/// A number as the controller keeps it: IEEE single precision (RAPID's
/// `num`), written as the shortest decimal that gives that value back
/// (at most 9 significant digits), small ones with an exponent.
pub fn num(v: f64) -> String {
    let f = v as f32;
    if f == 0.0 {
        return "0".to_string();
    }
    let plain = format!("{f}");
    if plain.len() <= 12 {
        plain
    } else {
        format!("{f:E}")
    }
}

fn list(values: impl IntoIterator<Item = f64>) -> String {
    let parts: Vec<String> = values.into_iter().map(num).collect();
    format!("[{}]", parts.join(","))
}

/// `[[x,y,z],...]` of a row's vectors.
fn vectors(row: &[[f64; 3]]) -> String {
    // Below a nanometre per unit growth a component is the arithmetic's
    // rounding (an axis along another), not a drift: written as 0.
    let clean = |v: f64| if v.abs() < 1e-9 { 0.0 } else { v };
    let parts: Vec<String> = row
        .iter()
        .map(|v| list(v.iter().copied().map(clean)))
        .collect();
    format!("[{}]", parts.join(","))
}

/// A table's rows as a RAPID array's value, one row a line; one row of
/// zeros where there is none (a RAPID array has at least one element).
fn rows_text(rows: &[String], zero: &str) -> (usize, String) {
    if rows.is_empty() {
        return (1, format!("[{zero}]"));
    }
    (rows.len(), format!("[\r\n    {}]", rows.join(",\r\n    ")))
}

/// The whole module, CRLF line ends as RobotStudio writes them: the
/// arm's numbers, the table of the program's targets, the state, and the
/// routines (`super::body`).
pub fn module_text(spec: &RuntimeSpec, table: &TableRows, opts: &ModuleOptions) -> String {
    let g = &spec.geom;
    let terms = |f: &dyn Fn(usize, usize) -> f64| {
        let rows: Vec<String> = (0..6)
            .map(|a| list((0..MAX_TERMS).map(|k| f(a, k))))
            .collect();
        format!("[{}]", rows.join(","))
    };
    let term = |a: usize, k: usize| spec.curves[a].terms.get(k);
    let rises = terms(&|a, k| term(a, k).map_or(0.0, |t| t.delta));
    // A missing term has no time constant: 0 marks it, and the update
    // skips it.
    let taus = terms(&|a, k| term(a, k).map_or(0.0, |t| t.tau));
    let motors: Vec<String> = spec
        .links
        .iter()
        .map(|l| list(l.motors.map(|m| if m { 1.0 } else { 0.0 })))
        .collect();
    let b = spec.base_rotation.quaternion();
    let mut s = String::new();
    let mut line = |text: &str| {
        s.push_str(text);
        s.push_str("\r\n");
    };
    line(&format!("MODULE {}(SYSMODULE,NOSTEPIN)", opts.name));
    for l in [
        format!(
            "  ! Written by rapidtherm {} for the {}: corrects targets for the",
            opts.version, spec.arm
        ),
        "  ! arm's thermal drift when the program reaches them, from a heating".to_string(),
        "  ! state carried through running and stopped spans. Write it again with".to_string(),
        "  ! `rapidtherm correct --runtime`; do not edit. See docs/runtime.md.".to_string(),
        format!("  ! Heating curves: {}.", opts.heating_source),
        format!("  ! Model: {}.", opts.model),
    ] {
        line(&l);
    }
    line("");
    line("  ! The arm's lengths (mm) and joint convention: theta = sign * q + offset (deg).");
    for (n, v) in [
        ("rtA1", g.a1),
        ("rtA2", g.a2),
        ("rtB", g.b),
        ("rtC1", g.c1),
        ("rtC2", g.c2),
        ("rtC3", g.c3),
        ("rtC4", g.c4),
    ] {
        line(&format!("  LOCAL CONST num {n} := {};", num(v)));
    }
    line(&format!(
        "  LOCAL CONST num rtSign{{6}} := {};",
        list(spec.signs)
    ));
    line(&format!(
        "  LOCAL CONST num rtOffset{{6}} := {};",
        list(spec.offsets_deg)
    ));
    line("  ! Each link (base, lower arm, upper arm, wrist) grows by rtGrow (1/degC)");
    line("  ! times its temperature above rtTref, the mean of the motors marked 1.");
    line(&format!(
        "  LOCAL CONST num rtGrow{{4}} := {};",
        list(spec.links.iter().map(|l| l.per_degree))
    ));
    line(&format!(
        "  LOCAL CONST num rtLinkMotor{{4,6}} := [{}];",
        motors.join(",")
    ));
    line(&format!("  LOCAL CONST num rtTref := {};", num(spec.t_ref)));
    line("  ! Motor temperature = rtT0 + the rises of its terms; a rise tends to rtRise");
    line("  ! while the program runs and to 0 while the robot stands, with time");
    line("  ! constant rtTau (min; 0: no such term).");
    line(&format!(
        "  LOCAL CONST num rtT0{{6}} := {};",
        list(spec.curves.iter().map(|c| c.t0))
    ));
    line(&format!(
        "  LOCAL CONST num rtRise{{6,{MAX_TERMS}}} := {rises};"
    ));
    line(&format!(
        "  LOCAL CONST num rtTau{{6,{MAX_TERMS}}} := {taus};"
    ));
    line("  ! Longer than this (min) between two corrections: the robot stood, and cooled.");
    line(&format!(
        "  LOCAL CONST num rtStopGap := {};",
        num(spec.stop_gap_min)
    ));
    line("  ! The state is brought to now at most every rtEvery seconds of running; the");
    line("  ! controller's clock moving rtJump minutes more or less than that: a jump.");
    line(&format!(
        "  LOCAL CONST num rtEvery := {};",
        num(UPDATE_EVERY_S)
    ));
    line(&format!(
        "  LOCAL CONST num rtJump := {};",
        num(CLOCK_JUMP_MIN)
    ));
    line("  ! The robot's base frame in the world (its rotation: a drift is a direction).");
    line(&format!(
        "  LOCAL CONST orient rtBaseRot := [{},{},{},{}];",
        num(b.w),
        num(b.i),
        num(b.j),
        num(b.k)
    ));
    line("");
    line(table_text(table).trim_end_matches("\r\n"));
    line("");
    line("  ! The state, kept through program restarts and power failures (PERS):");
    line("  ! each motion task (each robot of a MultiMove system) keeps its own. Loaded");
    line("  ! again, the module starts from these values: a cold arm, said.");
    line(&format!(
        "  LOCAL PERS num rtX{{6,{MAX_TERMS}}} := {};",
        terms(&|_, _| 0.0)
    ));
    line("  ! Whether a state is kept; the day (since 2000-01-01, negative before) and");
    line("  ! the minute of the day of the last update.");
    line("  LOCAL PERS bool rtKnown := FALSE;");
    line("  LOCAL PERS num rtDay := 0;");
    line("  LOCAL PERS num rtMinute := 0;");
    line("  ! Since loading or a P-start: whether rtClk runs (the time since the last");
    line("  ! update), and each link's growth now.");
    line("  LOCAL VAR bool rtOn := FALSE;");
    line("  LOCAL VAR clock rtClk;");
    for e in ["rtE1", "rtE2", "rtE3", "rtE4"] {
        line(&format!("  LOCAL VAR num {e} := 0;"));
    }
    s.push_str(&super::body::routines(&opts.name));
    s.push_str("ENDMODULE\r\n");
    s
}

/// The table's lines: per target the program names, the drift of its
/// cold joints per unit growth of each link; per jointtarget, the change
/// of its axes.
fn table_text(table: &TableRows) -> String {
    let mut s = String::new();
    let mut line = |text: &str| {
        s.push_str(text);
        s.push_str("\r\n");
    };
    line("  ! The table: per target the program names, the drift (mm, world frame) of its");
    line("  ! cold joints per unit growth of each link; per jointtarget, the change of");
    line("  ! axes 1-3 (rtGa) and 4-6 (rtGb), degrees per unit growth.");
    let zero4 = "[[0,0,0],[0,0,0],[0,0,0],[0,0,0]]";
    let d: Vec<String> = table.robtargets.iter().map(|r| vectors(r)).collect();
    let (n, text) = rows_text(&d, zero4);
    line(&format!("  LOCAL CONST pos rtD{{{n},4}} := {text};"));
    let half = |k: usize| -> Vec<String> {
        table
            .jointtargets
            .iter()
            .map(|r| {
                let v: Vec<[f64; 3]> = r
                    .iter()
                    .map(|g| [g[3 * k], g[3 * k + 1], g[3 * k + 2]])
                    .collect();
                vectors(&v)
            })
            .collect()
    };
    let (m, text) = rows_text(&half(0), zero4);
    line(&format!("  LOCAL CONST pos rtGa{{{m},4}} := {text};"));
    let (_, text) = rows_text(&half(1), zero4);
    line(&format!("  LOCAL CONST pos rtGb{{{m},4}} := {text};"));
    s
}

/// At most this long (s) between two updates of the state while the
/// program runs: the drift changes by far less than a micrometre in it
/// (the fastest heating term, ~20 min, moves 0.1 mm of drift by 0.8 µm
/// in 10 s at its steepest).
pub const UPDATE_EVERY_S: f64 = 10.0;

/// The controller's date and time moving this much (min) more or less
/// than the running clock between two updates: the clock was set (by
/// hand, a summer time, a time sync).
pub const CLOCK_JUMP_MIN: f64 = 1.0;

/// The file the module named `name` is written to.
pub fn module_file(name: &str) -> String {
    format!("{name}.sys")
}
