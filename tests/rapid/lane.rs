//! The fast lane against the grammar: a program read every way the reader
//! reads (`tests/common/ways.rs`: the lane reading ahead on every core or
//! at the parse's place), made into what the grammar makes of it
//! (`Program::expanded`), is the program the grammar reads statement by
//! statement: the same modules,
//! data, routines and statements, the same targets and jointtargets field
//! by field, the same warnings; or both refuse it with the same error. On
//! the samples, on the three shapes of large programs (inline moves,
//! declared targets moved to by name, an array walked by a FOR loop) and
//! on generated modules of robtarget and jointtarget declarations (every
//! scope, storage and spacing, arrays of one and two dimensions written
//! over several lines, comments between) with moves to them. The
//! generated comparison counts the programs whose declarations the lane
//! read and fails unless most were.

#[path = "../../examples/gen_shapes.rs"]
#[allow(dead_code)]
mod gen_shapes;

use crate::ways;
use proptest::prelude::*;
use rapidtherm::rapid::{self, Program, Reading};

fn read(src: &[u8]) -> rapidtherm::error::Result<Program> {
    ways::read(src, Reading::Lane)
}

/// What a program is, as text, part by part.
fn parts(p: &Program) -> Vec<String> {
    p.modules
        .iter()
        .map(|m| format!("{m:?}"))
        .chain(p.targets().iter().map(|t| format!("{t:?}")))
        .chain(p.jointtargets().iter().map(|j| format!("{j:?}")))
        .chain(p.warnings.iter().map(|w| format!("{w:?}")))
        .chain([format!("{:?} {:?}", p.tools(), p.wobjs())])
        .collect()
}

/// How many targets the lane held: (move literals, the rest).
fn same_both_ways(src: &[u8]) -> Result<(usize, usize), TestCaseError> {
    let Some(ways) = ways::read_every_way(src)? else {
        return Ok((0, 0));
    };
    let grammar = ways.grammar();
    let want = parts(grammar);
    for (way, lane) in ways.others() {
        let got = parts(&lane.expanded());
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            prop_assert!(
                g == w,
                "part {} differs:\n {:?} {}\n grammar {}",
                i,
                way,
                g,
                w
            );
        }
        prop_assert_eq!(got.len(), want.len());
        let t = lane.targets();
        // A target's pose numbers read alone (as the walk reads them, the
        // external axes left out) are those of the target the grammar
        // makes, wherever it has numbers.
        for (i, g) in grammar.targets().iter().enumerate() {
            let want = g.value.as_ref().map(rapid::PoseNumbers::from);
            prop_assert_eq!(t.pose(i), want, "{:?}: target {}", way, i);
        }
    }
    let t = ways.lane().targets();
    Ok((t.moves_in_runs(), t.in_runs() - t.moves_in_runs()))
}

#[test]
fn the_samples_read_the_same_with_the_lane() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/samples");
    let mut read_by_lane = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if !rapid::task::is_rapid_file(&path) {
            continue;
        }
        let src = std::fs::read(&path).unwrap();
        let (moves, rest) = same_both_ways(&src).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        read_by_lane += moves + rest;
    }
    eprintln!("the lane read {read_by_lane} targets of the samples");
    assert!(read_by_lane > 0);
}

#[test]
fn the_three_shapes_read_the_same_with_the_lane() {
    for shape in gen_shapes::Shape::ALL {
        let mut src = Vec::new();
        shape.write(&mut src, 2500).unwrap();
        let (moves, rest) = same_both_ways(&src).unwrap();
        // Every target: the CAM shape's move literals, the others'
        // declarations and elements.
        let want = match shape {
            gen_shapes::Shape::Cam => (2500, 0),
            _ => (0, 2500),
        };
        assert_eq!((moves, rest), want, "{}", shape.name());
    }
}

#[test]
fn large_programs_are_read_ahead_on_every_core_the_same() {
    // Large enough that the lane reads stretches of them ahead of the
    // parse, cut into pieces on every core (from 256 kB on).
    for shape in [gen_shapes::Shape::Cam, gen_shapes::Shape::Declared] {
        let mut src = Vec::new();
        shape.write(&mut src, 20_000).unwrap();
        let (moves, rest) = same_both_ways(&src).unwrap();
        assert_eq!(moves + rest, 20_000, "{}", shape.name());
        let lane = read(&src).unwrap();
        let tally = &lane.lane;
        eprintln!(
            "{}: the lane read {} statements, {} of them ahead of the parse",
            shape.name(),
            tally.read,
            tally.ahead
        );
        // The parse reads a statement itself where a stretch read ahead
        // ends: a few dozen of 20,000 (the declared shape's 20,000 moves
        // by name too).
        assert!(
            tally.ahead * 100 >= tally.read * 99,
            "{}: {} of {} read ahead",
            shape.name(),
            tally.ahead,
            tally.read
        );
        assert!(tally.declined.is_empty(), "{:?}", tally.declined);
    }
}

/// A robtarget literal of target `i`, in one of a few number styles.
fn literal(i: u32, style: u8) -> String {
    let x = 400.0 + f64::from(i % 97);
    let y = -100.0 + f64::from(i % 41) * 3.5;
    match style % 4 {
        0 => format!("[[{x:.3},{y:.3},300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]"),
        // Over two lines: the lane reads an array's so, the grammar a
        // scalar's.
        1 => format!(
            "[ [ {x:.1} , {y} , 3E2 ] ,\n      [ 0.0 , 0. , 1 , .0 ] , [ 0 , 0 , 0 , 0 ] , [ 9E+09 , 9e9 , 9E9 , 9E9 , 9E9 , 9E9 ] ]"
        ),
        2 => format!("[[+{x},{y:.2},300.0],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]]"),
        _ => format!("[ [{x}, {y}, 3.0e2], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9] ]"),
    }
}

/// One piece of a module's data.
#[derive(Debug, Clone)]
enum Data {
    /// Scope, storage, style, whether it has a value.
    Scalar(u8, u8, u8, bool),
    Joint(u8),
    /// Elements, and whether two-dimensional.
    Array(u8, bool, u8),
    Num,
    Comment,
}

fn data() -> impl Strategy<Value = Data> {
    prop_oneof![
        6 => (0u8..3, 0u8..3, 0u8..4, prop::bool::weighted(0.9))
            .prop_map(|(a, b, c, d)| Data::Scalar(a, b, c, d)),
        1 => (0u8..3).prop_map(Data::Joint),
        2 => (1u8..6, any::<bool>(), 0u8..4).prop_map(|(n, two, s)| Data::Array(n, two, s)),
        1 => Just(Data::Num),
        1 => Just(Data::Comment),
    ]
}

/// A module of `items`, each robtarget named `p{k}` (arrays `a{k}`), and
/// a routine that moves to each by name (to an array's elements by a
/// literal index and in a FOR loop).
fn module(items: &[Data]) -> String {
    let mut s = String::from("MODULE Gen\n  PERS tooldata tG:=[TRUE,[[0,0,100],[1,0,0,0]],[1,[0,0,1],[1,0,0,0],0,0,0]];\n");
    let mut moves = Vec::new();
    for (k, d) in items.iter().enumerate() {
        let k = k as u32;
        match d {
            Data::Scalar(scope, storage, style, valued) => {
                let scope = ["", "LOCAL ", "TASK "][usize::from(*scope)];
                let storage = ["CONST", "PERS", "VAR"][usize::from(*storage)];
                let (storage, valued) = match (storage, valued) {
                    // A constant has a value.
                    ("CONST", false) => ("VAR", false),
                    (s, v) => (s, *v),
                };
                let scope = if scope == "TASK " && storage != "PERS" {
                    ""
                } else {
                    scope
                };
                if valued {
                    let note = if *style == 2 { " ! a note" } else { "" };
                    s += &format!(
                        "  {scope}{storage} robtarget p{k} := {};{note}\n",
                        literal(k, *style)
                    );
                } else {
                    s += &format!("  {scope}{storage} robtarget p{k};\n");
                }
                moves.push(format!("    MoveL p{k}, v100, z1, tG;"));
            }
            Data::Joint(style) => {
                let sp = if *style == 1 { " " } else { "" };
                s += &format!(
                    "  CONST jointtarget j{k}:={sp}[[0,{k},0,0,{sp}30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
                );
                moves.push(format!("    MoveAbsJ j{k}, v100, z1, tG;"));
            }
            Data::Array(n, two, style) => {
                let n = u32::from(*n);
                let lits: Vec<String> = (0..n * if *two { 2 } else { 1 })
                    .map(|i| literal(k * 10 + i, *style))
                    .collect();
                if *two {
                    let rows: Vec<String> = lits
                        .chunks(n as usize)
                        .map(|r| format!("[{}]", r.join(",\n    ")))
                        .collect();
                    s += &format!(
                        "  CONST robtarget a{k}{{2,{n}}} := [\n    {}];\n",
                        rows.join(",\n    ")
                    );
                    moves.push(format!("    MoveL a{k}{{2,1}}, v100, z1, tG;"));
                } else {
                    s += &format!(
                        "  CONST robtarget a{k}{{{n}}}:=[\n    {}\n  ];\n",
                        lits.join(",\n    ")
                    );
                    moves.push(format!(
                        "    FOR i FROM 1 TO {n} DO\n      MoveL a{k}{{i}}, v100, z1, tG;\n    ENDFOR"
                    ));
                    moves.push(format!("    MoveJ a{k}{{1}}, v100, z1, tG;"));
                }
            }
            Data::Num => s += &format!("  CONST num n{k} := {k};\n"),
            Data::Comment => s += "  ! a comment between declarations\n\n",
        }
    }
    s += "  PROC main()\n";
    for m in moves {
        s += &m;
        s += "\n";
    }
    s += "  ENDPROC\nENDMODULE\n";
    s
}

#[test]
fn generated_declarations_read_the_same_with_the_lane() {
    ways::counted(
        "declarations",
        64,
        8,
        prop::collection::vec(data(), 2..12),
        |items| Ok(same_both_ways(module(&items).as_bytes())?.1),
    );
}

/// A statement the lane began and left to the grammar is counted with its
/// typed reason and place (what `-v` says), and read as the grammar reads
/// it; a statement it reads, or never began (an assignment, a MoveAbsJ),
/// is no decline.
#[test]
fn a_declined_statement_is_counted_with_its_reason() {
    use rapidtherm::rapid::{Decline, Part, StoppedAt};
    let lit = "[[400,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]";
    let cases: Vec<(String, Option<Decline>)> = vec![
        (format!("MoveL {lit}, v100, z1, tG;"), None),
        ("MoveL p1, v100, z1, tG\\WObj:=wT;".into(), None),
        ("x := 1;".into(), None),
        ("MoveAbsJ j1, v100, z1, tG;".into(), None),
        (
            "MoveL [[400+10,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z1, tG;"
                .into(),
            Some(Decline::At(Part::Target, StoppedAt::Char(b'+'))),
        ),
        (
            "MoveL [[nX,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z1, tG;"
                .into(),
            Some(Decline::At(Part::Target, StoppedAt::Name)),
        ),
        (
            "MoveL Offs(p1,0,0,10), v100, z1, tG;".into(),
            Some(Decline::At(Part::Target, StoppedAt::Char(b'('))),
        ),
        (
            "MoveL p1,\n      v100, z1, tG;".into(),
            Some(Decline::At(Part::Speed, StoppedAt::LineBreak)),
        ),
        (
            "MoveL p1, v100, z1, tG\\TLoad:=load0;".into(),
            Some(Decline::OtherOptional),
        ),
        (
            "MoveL p1, v100, z1, tG\\WObj:=wT\\TLoad:=load0;".into(),
            Some(Decline::At(Part::End, StoppedAt::Char(b'\\'))),
        ),
        (
            "MoveL\\Conc, p1, v100, z1, tG;".into(),
            Some(Decline::At(Part::Instruction, StoppedAt::Char(b'\\'))),
        ),
    ];
    for (statement, want) in cases {
        let src = format!(
            "MODULE m\n  CONST robtarget p1 := {lit};\n  CONST jointtarget j1 := [[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  CONST num nX := 400;\n  VAR num x := 0;\n  PROC main()\n    MoveJ p1, v100, z1, tG;\n    {statement}\n  ENDPROC\nENDMODULE\n"
        );
        same_both_ways(src.as_bytes()).unwrap_or_else(|e| panic!("{statement}: {e}"));
        let p = read(src.as_bytes()).unwrap_or_else(|e| panic!("{statement}: {e}"));
        let declined = declines(&p);
        let want: Vec<(Decline, usize, u32)> = want.into_iter().map(|w| (w, 1, 8)).collect();
        assert_eq!(declined, want, "{statement}");
        // The declarations and the first move, and the statement where read.
        let read_here = usize::from(p.lane.declined.is_empty() && statement.starts_with("MoveL"));
        assert_eq!(p.lane.read, 3 + read_here, "{statement}");
    }
    // Declarations.
    for (decl, want) in [
        (
            "CONST jointtarget jj{2} := [[[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]]];",
            Decline::JointtargetArray,
        ),
        (
            "CONST robtarget pp{2,1} := [[[[400,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]],[[[400,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]]];",
            Decline::At(Part::ArraySize, StoppedAt::Char(b',')),
        ),
        (
            "CONST robtarget pq := [[400,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]] ! why\n ;",
            Decline::At(Part::End, StoppedAt::Comment),
        ),
    ] {
        let src = format!("MODULE m\n  {decl}\n  PROC main()\n  ENDPROC\nENDMODULE\n");
        same_both_ways(src.as_bytes()).unwrap_or_else(|e| panic!("{decl}: {e}"));
        let p = read(src.as_bytes()).unwrap();
        let declined = declines(&p);
        assert_eq!(declined, vec![(want, 1, 2)], "{decl}");
    }
}

/// What a program's lane declined: each reason, how many, its first
/// line.
fn declines(p: &Program) -> Vec<(rapidtherm::rapid::Decline, usize, u32)> {
    p.lane
        .declined
        .iter()
        .map(|(why, d)| (*why, d.count, d.line))
        .collect()
}
