//! The streamed main job (`correct::stream`, `rapid::fastmove`) against
//! the whole-program path: on generated programs (inline moves the fast
//! recogniser reads, and declared, derived, array and record targets,
//! several modules, moves it leaves to the grammar) it writes the same
//! bytes and the same summary, or declines; the recogniser reads the
//! same numbers the grammar does; and `targets` lists the same targets
//! (`rapid::fastlist`) and prints the same bytes in every format.

use proptest::prelude::*;
use rapidtherm::correct::stream::correct_streamed;
use rapidtherm::correct::{correct, CutTimes, Options, When};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid::fastlist::{Entry, Listing};
use rapidtherm::rapid::fastmove::{recognise, skeleton, Skeleton};
use rapidtherm::rapid::{self, TargetKind};
use rapidtherm::robot::Robot;
use std::sync::OnceLock;

pub(super) fn warm() -> &'static WarmRobot {
    static WARM: OnceLock<WarmRobot> = OnceLock::new();
    WARM.get_or_init(|| WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).unwrap())
}

fn options() -> Options {
    Options::new(When::At(Moment::Minute(120.0)))
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
fn program(bodies: &[Vec<Stmt>], eol: &str, latin1: bool) -> Vec<u8> {
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

/// Whether the streamed path wrote what the whole path writes and said
/// the same summary; `false` when it declined.
fn same_as_whole(src: &[u8]) -> bool {
    let whole =
        rapid::parse("p.mod", src).and_then(|p| correct(&p, warm(), &options(), &mut |_, _| {}));
    let skel = skeleton(src);
    let Ok(program) = rapid::parse("p.mod", &skel.bytes) else {
        assert!(
            whole.is_err(),
            "the skeleton of a program that parses must parse"
        );
        return false;
    };
    streamed_as_whole(src, (&skel, &program), (&options(), None), whole)
}

/// Whether `correct_streamed` of `src` (read as `skel`, whose kept bytes
/// parsed as `program`) for `options` (and the schedule's `times`)
/// writes the bytes and says the summary of `whole`, the whole path's
/// outcome; `false` when it declined. It never corrects what the whole
/// path refuses.
pub(super) fn streamed_as_whole(
    src: &[u8],
    (skel, program): (&Skeleton, &rapid::Program),
    (options, times): (&Options, Option<&CutTimes>),
    whole: rapidtherm::error::Result<rapidtherm::correct::Outcome>,
) -> bool {
    let mut written = Vec::new();
    let streamed = correct_streamed(program, skel, src, warm(), (options, times), &mut written)
        .expect("writes to memory");
    let Some(streamed) = streamed else {
        return false;
    };
    let whole = whole.expect("the fast path corrected a program the whole path refuses");
    let bytes = if streamed.changed { &written[..] } else { src };
    assert!(
        bytes == whole.outputs[0].as_slice(),
        "streamed bytes differ:\n{}",
        String::from_utf8_lossy(bytes)
    );
    let said = |o: &rapidtherm::correct::Outcome| {
        serde_json::to_string(&(&o.summary, &o.left_alone, &o.shared, &o.splits, &o.notes)).unwrap()
    };
    assert_eq!(said(&streamed.outcome), said(&whole));
    true
}

#[test]
fn a_cam_program_streams_with_the_same_bytes() {
    let body: Vec<Stmt> = (0..300)
        .map(|i| Stmt::Inline("MoveL", i, (i % 4) as u8, i % 3 == 0, ""))
        .chain([Stmt::Named(0), Stmt::Named(3)])
        .collect();
    for eol in ["\n", "\r\n"] {
        let src = program(
            &[body.clone(), vec![Stmt::Named(1), Stmt::Named(2)]],
            eol,
            true,
        );
        assert_eq!(skeleton(&src).cuts.len(), 300);
        assert!(same_as_whole(&src), "the fast path declined a CAM program");
    }
}

#[test]
fn a_refused_program_is_declined_and_left_to_the_whole_path() {
    let body = vec![
        Stmt::Inline("MoveL", 1, 0, false, ""),
        Stmt::Unreachable,
        Stmt::Inline("MoveL", 2, 0, false, ""),
    ];
    assert!(!same_as_whole(&program(&[body], "\n", false)));
}

#[test]
fn a_declaration_after_a_cut_move_is_left_to_the_whole_path() {
    // The grammar refuses a routine's data after its first statement; cut
    // out, the move leaves the skeleton a routine the grammar takes.
    let src = b"MODULE m\nPROC main()\n  MoveL [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],v100,z1,tool0;\n  VAR num k;\n  WaitTime 1;\nENDPROC\nENDMODULE\n";
    assert!(rapid::parse("p.mod", src).is_err());
    let skel = skeleton(src);
    assert_eq!(skel.cuts.len(), 1);
    assert!(rapid::parse("p.mod", &skel.bytes).is_ok());
    assert!(!same_as_whole(src));
    assert!(!listed_as_whole(src));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn streamed_and_whole_write_the_same_bytes(
        bodies in prop::collection::vec(prop::collection::vec(stmt(), 0..40), 1..3),
        crlf in any::<bool>(),
        latin1 in any::<bool>(),
    ) {
        let src = program(&bodies, if crlf { "\r\n" } else { "\n" }, latin1);
        same_as_whole(&src);
    }

    #[test]
    fn the_recogniser_reads_what_the_grammar_reads(
        body in prop::collection::vec(stmt(), 1..30),
    ) {
        let src = program(&[body], "\n", false);
        let program = rapid::parse("p.mod", &src).unwrap();
        let skel = skeleton(&src);
        let read: Vec<_> = skel
            .cuts
            .iter()
            .flat_map(|c| recognise(&src, c.start).unwrap().targets)
            .collect();
        let inline: Vec<_> = program
            .targets()
            .iter()
            .filter(|t| t.kind == TargetKind::Inline && read.iter().any(|(at, _)| *at == t.origin.pos.offset))
            .map(|t| (t.origin.pos.offset, t.value.clone().unwrap()))
            .collect();
        prop_assert_eq!(read, inline);
    }
}

/// What `targets` prints of a target, field by field (the numbers as
/// written and as read).
fn listed(t: &rapid::Target, src: &[u8]) -> String {
    let numbers: Vec<(String, u64)> = t
        .value
        .iter()
        .flat_map(|v| v.numbers())
        .map(|n| (n.text(src).to_string(), n.value.to_bits()))
        .collect();
    format!(
        "{} {} {}:{} {} {:?} {:?} {:?} {:?} {:?} {:?} {numbers:?}",
        t.id,
        t.kind.as_str(),
        t.origin.pos.line,
        t.origin.pos.col,
        t.origin.module,
        t.origin.routine,
        t.instruction,
        t.tool,
        t.wobj,
        t.name,
        t.derived,
    )
}

/// Whether the fast listing of `src` (`rapid::fastlist`) lists the targets
/// the whole parse lists; `false` when it declined.
fn listed_as_whole(src: &[u8]) -> bool {
    let whole = rapid::parse("p.mod", src);
    let skel = skeleton(src);
    let Ok(program) = rapid::parse("p.mod", &skel.bytes) else {
        assert!(
            whole.is_err(),
            "the skeleton of a program that parses must parse"
        );
        return false;
    };
    let Some(listing) = Listing::new(&program, &skel, src) else {
        return false;
    };
    let whole = whole.expect("the skeleton parses where the whole file does not");
    let mut got = Vec::new();
    let mut reader = listing.reader();
    for e in listing.entries() {
        match *e {
            Entry::Kept(i) => got.push(listed(listing.kept(i), &skel.bytes)),
            Entry::Cut(k) => reader
                .read(k, &mut |t| got.push(listed(t, src)))
                .expect("a cut move reads again"),
        }
    }
    let want: Vec<String> = whole.targets().iter().map(|t| listed(t, src)).collect();
    assert_eq!(got, want);
    true
}

/// `rapidtherm targets` of the file `src` in `format`, read by name (the
/// fast path where it applies) and from standard input (always the whole
/// path; its file is named `<stdin>`, put back to the name).
fn targets_both_ways(src: &[u8], format: &str) -> (String, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.mod");
    std::fs::write(&path, src).unwrap();
    let run = |stdin: bool| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_rapidtherm"));
        cmd.args(["targets", "--format", format]);
        if stdin {
            cmd.arg("-").stdin(std::fs::File::open(&path).unwrap());
        } else {
            cmd.arg(&path);
        }
        let out = cmd.output().unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (code, by_name, said) = run(false);
    let (whole_code, whole, whole_said) = run(true);
    assert_eq!(code, whole_code, "{said}\n{whole_said}");
    let name = path.display().to_string();
    (by_name, whole.replace("<stdin>", &name))
}

#[test]
fn a_cam_program_lists_the_same_targets() {
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
    for one_name in [false, true] {
        // The second module's one literal is cut: only the whole file
        // has `main#` in two modules when the routines share a name.
        let second = vec![
            Stmt::Named(1),
            Stmt::Inline("MoveL", 5, 0, false, ""),
            Stmt::Named(2),
        ];
        let src = program_with(&[body.clone(), second], "\r\n", true, one_name);
        assert!(
            listed_as_whole(&src),
            "the fast listing declined a CAM program"
        );
        let text = String::from_utf8_lossy(&src).into_owned();
        let qualified = rapid::parse("p.mod", &src)
            .unwrap()
            .targets()
            .iter()
            .any(|t| t.id.starts_with("M1:main#"));
        assert_eq!(qualified, one_name, "{text}");
        for format in ["table", "csv", "json"] {
            let (fast, whole) = targets_both_ways(&src, format);
            assert_eq!(fast, whole, "{format}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn fast_and_whole_list_the_same_targets(
        bodies in prop::collection::vec(prop::collection::vec(stmt(), 0..40), 1..3),
        crlf in any::<bool>(),
        latin1 in any::<bool>(),
        one_name in any::<bool>(),
    ) {
        let src = program_with(&bodies, if crlf { "\r\n" } else { "\n" }, latin1, one_name);
        listed_as_whole(&src);
    }
}

proptest! {
    // Each case runs the binary six times.
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn targets_prints_the_same_bytes_either_way(
        bodies in prop::collection::vec(prop::collection::vec(stmt(), 0..25), 1..3),
        crlf in any::<bool>(),
        latin1 in any::<bool>(),
        one_name in any::<bool>(),
    ) {
        let src = program_with(&bodies, if crlf { "\r\n" } else { "\n" }, latin1, one_name);
        for format in ["table", "csv", "json"] {
            let (fast, whole) = targets_both_ways(&src, format);
            prop_assert_eq!(fast, whole, "{}", format);
        }
    }
}
