//! The fast lane against the grammar: a program read every way the reader
//! reads (`tests/common/ways.rs`: the lane reading ahead, the lane at the
//! parse's place, the moves, robtarget declarations and array literals
//! it knows held in runs) is the program the grammar reads statement by
//! statement: the same targets, field by field, the same
//! uses, and corrected (in memory, and streamed into writers with the
//! summary alone kept) into the same bytes with the same report, on
//! generated programs (inline moves in several number styles, declared,
//! derived, array and record targets, several modules, Latin-1 comments,
//! CRLF). Each comparison counts the cases where the lane read targets
//! and fails unless it did on most of them.

use crate::ways::{self, Ways};
use proptest::prelude::*;
use rapidtherm::correct::{correct, correct_into, Options, Outcome, ReportRows, When, Writers};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid::{self, Program};
use rapidtherm::resolve::usages;
use rapidtherm::robot::Robot;
use std::sync::OnceLock;

pub(super) fn warm() -> &'static WarmRobot {
    static WARM: OnceLock<WarmRobot> = OnceLock::new();
    WARM.get_or_init(|| WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).unwrap())
}

/// One statement of a generated routine body.
#[derive(Debug, Clone)]
pub(super) enum Stmt {
    /// An inline move: instruction, point index, number style, work
    /// object, what follows on the line.
    Inline(&'static str, u32, u8, bool, &'static str),
    /// A move to a declared target, an array element, a record field or
    /// a derived pose of the first declared target.
    Named(u8),
    ConfOff,
    /// A literal assigned to a variable (numbered with the inline ones).
    Assigned(u32),
    /// A target no arm reaches: the run refuses the program.
    Unreachable,
}

/// A reachable point of the CAM field (the benchmark's zigzag).
fn point(i: u32) -> (f64, f64, f64, i32) {
    let u = f64::from(i % 37) / 37.0;
    let v = f64::from(i % 23) / 23.0;
    let y = -150.0 + 300.0 * v;
    (
        420.0 + 80.0 * u,
        y,
        250.0 + 20.0 * (u * 7.0).sin(),
        if y >= 0.0 { 0 } else { -1 },
    )
}

/// A robtarget literal in one of a few number styles.
fn literal(i: u32, style: u8) -> String {
    let (x, y, z, cf) = point(i);
    match style % 4 {
        0 => format!("[[{x:.3},{y:.3},{z:.3}],[0,0,1,0],[{cf},0,{cf},0],[9E9,9E9,9E9,9E9,9E9,9E9]]"),
        1 => format!(
            "[ [ {x:.1} , {y:.2} , {z:.4} ] , [ 0.0 , 0. , 1 , .0 ] , [ {cf} , 0 , {cf} , 0 ] , [ 9E+09 , 9e9 , 9E9 , 9E9 , 9E9 , 9E9 ] ]"
        ),
        2 => format!("[[+{x:.2},{y:.0},{z:.5}],[0,0,1,0],[{cf},0,{cf},0],[9E9,9E9,9E9,9E9,9E9,9E9]]"),
        _ => format!("[[{x:.3}E0,{y:.3},{z:.3}],[0,0,1,0],[{cf},0,{cf},0],[9E9,9E9,9E9,9E9,9E9,9E9]]"),
    }
}

pub(super) fn stmt() -> impl Strategy<Value = Stmt> {
    prop_oneof![
        8 => (
            prop::sample::select(vec!["MoveL", "MoveJ", "movel", "MoveC"]),
            0u32..1000,
            0u8..4,
            any::<bool>(),
            prop::sample::select(vec!["", " ! pass", "\tWaitTime 0;", " ! caf\u{e9}"]),
        )
            .prop_map(|(i, p, s, w, after)| Stmt::Inline(i, p, s, w, after)),
        2 => (0u8..4).prop_map(Stmt::Named),
        1 => Just(Stmt::ConfOff),
        1 => (0u32..1000).prop_map(Stmt::Assigned),
        1 => prop::bool::weighted(0.15).prop_map(|b| if b { Stmt::Unreachable } else { Stmt::ConfOff }),
    ]
}

/// A program of one or two modules, every line ended with `eol`, the
/// comments Latin-1 where `latin1`.
pub(super) fn program(bodies: &[Vec<Stmt>], eol: &str, latin1: bool) -> Vec<u8> {
    program_with(bodies, eol, latin1, false)
}

/// [`program`], the routines of every module named `main` where
/// `one_name` (their inline targets' identifiers then name the module:
/// `M0:main#3`).
pub(super) fn program_with(
    bodies: &[Vec<Stmt>],
    eol: &str,
    latin1: bool,
    one_name: bool,
) -> Vec<u8> {
    let mut s = String::new();
    for (m, body) in bodies.iter().enumerate() {
        let routine = if one_name {
            "main".to_string()
        } else {
            format!("main{m}")
        };
        s += &format!("MODULE M{m}{eol}");
        s += &format!("  PERS tooldata tSpindle{m}:=[TRUE,[[0,0,150],[1,0,0,0]],[2,[0,0,60],[1,0,0,0],0,0,0]];{eol}");
        s += &format!("  PERS wobjdata wPlate{m}:=[FALSE,TRUE,\"\",[[0,0,20],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];{eol}");
        s += &format!("  CONST robtarget pD{m}:={};{eol}", literal(5, 0));
        s += &format!(
            "  CONST robtarget aD{m}{{2}}:=[{},{}];{eol}",
            literal(7, 0),
            literal(8, 0)
        );
        s += &format!(
            "  RECORD path{m}{eol}    robtarget start;{eol}    num n;{eol}  ENDRECORD{eol}"
        );
        s += &format!("  CONST path{m} rD{m}:=[{},1];{eol}", literal(9, 0));
        s += &format!("  VAR robtarget pV{m};{eol}");
        s += &format!("  PROC {routine}(){eol}");
        for st in body {
            let line = match st {
                Stmt::Inline(ins, p, style, w, after) => {
                    let wobj = if *w {
                        format!("\\WObj:=wPlate{m}")
                    } else {
                        String::new()
                    };
                    let points = if ins.eq_ignore_ascii_case("MoveC") {
                        format!("{}, {}", literal(*p, *style), literal(p + 1, *style))
                    } else {
                        literal(*p, *style)
                    };
                    format!("    {ins} {points},v200,z1,tSpindle{m}{wobj};{after}")
                }
                Stmt::Named(k) => {
                    let t = match k {
                        0 => format!("pD{m}"),
                        1 => format!("aD{m}{{2}}"),
                        2 => format!("rD{m}.start"),
                        _ => format!("Offs(pD{m},0,0,5)"),
                    };
                    format!("    MoveL {t},v200,z1,tSpindle{m}\\WObj:=wPlate{m};")
                }
                Stmt::ConfOff => "    ConfL \\Off;".to_string(),
                Stmt::Assigned(p) => format!("    pV{m} := {};", literal(*p, 0)),
                Stmt::Unreachable => format!(
                    "    MoveL [[3000,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],v200,z1,tSpindle{m};"
                ),
            };
            s += &line;
            s += eol;
        }
        s += &format!("  ENDPROC{eol}ENDMODULE{eol}");
    }
    if latin1 {
        s.chars()
            .map(|c| u8::try_from(u32::from(c)).unwrap_or(b'?'))
            .collect()
    } else {
        s.into_bytes()
    }
}

/// What a program says of its targets, field by field (the numbers as
/// written and as read), its jointtargets', and every target's uses.
pub(super) fn listing(p: &Program) -> Vec<String> {
    let src = p.source(0);
    let uses = usages(p);
    let targets = p.targets();
    (0..targets.len())
        .map(|i| {
            let t = targets.at(i);
            format!("{} {:?}", listed(&t, src), uses.get(&i))
        })
        .chain(p.jointtargets().iter().map(|j| {
            let numbers: Vec<(String, u64)> = j
                .robax
                .iter()
                .chain(&j.extax)
                .map(|n| (n.text(src).to_string(), n.value.to_bits()))
                .collect();
            format!("{j:?} {numbers:?}")
        }))
        .collect()
}

/// The lane's listing is the grammar's: the first line that differs.
pub(super) fn same_listing(lane: &[String], grammar: &[String]) -> Result<(), TestCaseError> {
    // The first characters that differ, with a few before.
    let around = |x: &str, at: usize| -> String { x.chars().skip(at).take(300).collect() };
    for (i, (l, g)) in lane.iter().zip(grammar).enumerate() {
        let at = l.chars().zip(g.chars()).take_while(|(a, b)| a == b).count();
        let from = at.saturating_sub(40);
        prop_assert!(
            l == g,
            "line {} of the listings differs after {:?}:\n lane {:?}\n grammar {:?}",
            i,
            l.chars().take(at.min(60)).collect::<String>(),
            around(l, from),
            around(g, from)
        );
    }
    prop_assert_eq!(lane.len(), grammar.len(), "the listings' lengths differ");
    Ok(())
}

/// A target, field by field.
fn listed(t: &rapid::Target, src: &[u8]) -> String {
    let numbers: Vec<(String, u64)> = t
        .value
        .iter()
        .flat_map(|v| v.numbers())
        .map(|n| (n.text(src).to_string(), n.value.to_bits()))
        .collect();
    format!("{t:?} {numbers:?}")
}

/// What a run said, less its outputs.
pub(super) fn said(o: &Outcome) -> String {
    serde_json::to_string(o).unwrap()
}

/// Read every way, `src` is one program: listed alike, corrected alike
/// (in memory every way, and streamed every way the lane reads) for
/// `options`, or refused alike. How many move literals the lane read
/// (held in runs).
pub(super) fn same_both_ways(src: &[u8], options: &Options) -> Result<usize, TestCaseError> {
    let Some(ways) = ways::read_every_way(src)? else {
        return Ok(0);
    };
    let grammar = ways.grammar();
    let want = listing(grammar);
    for (_, p) in ways.others() {
        same_listing(&listing(p), &want)?;
    }
    let whole = correct(grammar, warm(), options, &mut |_, _| {});
    for (way, lane) in ways.others() {
        corrected_alike(src, &whole, lane, options)
            .map_err(|e| TestCaseError::fail(format!("read {way:?}: {e}")))?;
    }
    Ok(held(&ways))
}

/// How many move literals the lane read (held in runs).
pub(super) fn held(ways: &Ways) -> usize {
    ways.lane().targets().moves_in_runs()
}

/// `lane` corrected in memory and streamed as the grammar's program was
/// (`whole`).
fn corrected_alike(
    src: &[u8],
    whole: &rapidtherm::error::Result<Outcome>,
    lane: &Program,
    options: &Options,
) -> Result<(), TestCaseError> {
    let with_lane = correct(lane, warm(), options, &mut |_, _| {});
    let mut written = Vec::new();
    let streamed = {
        let mut outs: Vec<&mut (dyn std::io::Write + Send)> = vec![&mut written];
        correct_into(
            lane,
            warm(),
            options,
            Writers::new(&mut outs, ReportRows::SummaryOnly),
            &mut |_, _| {},
        )
    };
    match (whole, with_lane, streamed) {
        (Ok(whole), Ok(with_lane), Ok(streamed)) => {
            prop_assert!(
                with_lane.outputs == whole.outputs,
                "the lane's program corrects otherwise"
            );
            prop_assert_eq!(said(&with_lane), said(whole));
            let bytes = if streamed.changed[0] {
                &written[..]
            } else {
                src
            };
            prop_assert!(
                bytes == whole.outputs[0].as_slice(),
                "streamed bytes differ:\n{}",
                String::from_utf8_lossy(bytes)
            );
            // Streamed, the run keeps the summary (its count of moves by
            // fate among it) and what is said about targets, not every
            // target's or move's row.
            let mut whole = whole.clone();
            whole.moves.clear();
            whole.corrections.clear();
            whole.derived.clear();
            whole.residuals.clear();
            let mut streamed = streamed.outcome;
            streamed.moves.clear();
            streamed.corrections.clear();
            streamed.derived.clear();
            streamed.residuals.clear();
            prop_assert_eq!(said(&streamed), said(&whole));
        }
        (Err(whole), Err(with_lane), Err(streamed)) => {
            prop_assert_eq!(with_lane.to_string(), whole.to_string());
            prop_assert_eq!(streamed.to_string(), whole.to_string());
        }
        (w, l, s) => {
            return Err(TestCaseError::fail(format!(
                "the ways disagree on refusing: whole {:?}, lane {:?}, streamed {:?}",
                w.as_ref().err().map(|e| e.to_string()),
                l.err().map(|e| e.to_string()),
                s.err().map(|e| e.to_string())
            )))
        }
    }
    Ok(())
}

fn at_120() -> Options {
    Options::new(When::At(Moment::Minute(120.0)))
}

#[test]
fn a_cam_program_reads_and_corrects_the_same_both_ways() {
    let body: Vec<Stmt> = (0..300)
        .map(|i| {
            Stmt::Inline(
                ["MoveL", "MoveC"][(i % 7 == 0) as usize],
                i,
                (i % 4) as u8,
                i % 3 == 0,
                "",
            )
        })
        .chain([Stmt::Named(0), Stmt::Named(3), Stmt::Assigned(4)])
        .collect();
    for (eol, one_name) in [("\n", false), ("\r\n", true)] {
        let second = vec![
            Stmt::Named(1),
            Stmt::Inline("MoveL", 5, 0, false, ""),
            Stmt::Named(2),
        ];
        let src = program_with(&[body.clone(), second], eol, true, one_name);
        let read = same_both_ways(&src, &at_120()).unwrap();
        // Every move literal (a MoveC has two).
        assert_eq!(read, 300 + 43 + 1, "the lane read {read} move literals");
        let qualified = rapid::parse("p.mod", &src)
            .unwrap()
            .targets()
            .iter()
            .any(|t| t.id.starts_with("M1:main#"));
        assert_eq!(qualified, one_name);
    }
}

#[test]
fn a_refused_program_is_refused_alike() {
    let body = vec![
        Stmt::Inline("MoveL", 1, 0, false, ""),
        Stmt::Unreachable,
        Stmt::Inline("MoveL", 2, 0, false, ""),
    ];
    same_both_ways(&program(&[body], "\n", false), &at_120()).unwrap();
}

#[test]
fn a_declaration_after_a_move_is_refused_alike() {
    // The grammar refuses a routine's data after its first statement;
    // the lane's move is a statement as the grammar's is.
    let src = b"MODULE m\nPROC main()\n  MoveL [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],v100,z1,tool0;\n  VAR num k;\n  WaitTime 1;\nENDPROC\nENDMODULE\n";
    let read = ways::read_every_way(src).unwrap();
    assert!(read.is_none(), "every way refuses it alike");
}

#[test]
fn generated_programs_read_and_correct_the_same_both_ways() {
    ways::counted(
        "read and corrected at minute 120",
        32,
        9,
        (
            prop::collection::vec(prop::collection::vec(stmt(), 0..40), 1..3),
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
        ),
        |(bodies, crlf, latin1, one_name)| {
            let src = program_with(&bodies, if crlf { "\r\n" } else { "\n" }, latin1, one_name);
            same_both_ways(&src, &at_120())
        },
    );
}
