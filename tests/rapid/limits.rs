//! RAPID's own limits, checked as the controller checks them, on the fast
//! lane and on the grammar alike: names of at most 32 characters (ABB,
//! Technical reference manual, RAPID kernel, 2.3 Identifiers), array
//! indexes written as numbers inside the declared size, the encodings
//! read (UTF-8 with or without its mark, Latin-1) and those refused by
//! name, every line end (LF, CRLF, a lone CR) with offsets kept exact,
//! and messages that quote at most a bounded excerpt of the input.

use proptest::prelude::*;
use rapidtherm::rapid::{parse_read, Program, Reading, Source};

const RT: &str = "[[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]";

/// `src` read every way the reader reads (the fast lane reading ahead or
/// at the parse's place, the grammar alone): all give the same answer,
/// which is returned.
fn read(name: &str, src: &[u8]) -> Result<Program, String> {
    let answers =
        Reading::ALL.map(|way| parse_read(vec![(name.to_string(), Source::copied(src))], way));
    let ids = |p: &Program| {
        p.targets()
            .iter()
            .map(|t| (t.id.clone(), t.origin.pos.line, t.origin.pos.col))
            .collect::<Vec<_>>()
    };
    let [.., grammar] = &answers;
    for (way, answer) in Reading::ALL.iter().zip(&answers) {
        match (answer, grammar) {
            (Ok(a), Ok(b)) => assert_eq!(ids(a), ids(b), "{way:?} and the grammar differ"),
            (Err(a), Err(b)) => {
                assert_eq!(
                    a.to_string(),
                    b.to_string(),
                    "{way:?} and the grammar differ"
                )
            }
            (a, b) => panic!(
                "{way:?} and the grammar differ: {:?} / {:?}",
                a.is_ok(),
                b.is_ok()
            ),
        }
    }
    let [lane, ..] = answers;
    lane.map_err(|e| e.to_string())
}

fn module(body: &str) -> String {
    format!("MODULE m\n{body}\nENDMODULE\n")
}

#[test]
fn a_name_of_33_characters_is_refused_where_it_stands_and_32_is_read() {
    let n32 = format!("p{}", "a".repeat(31));
    let n33 = format!("p{}", "a".repeat(32));
    let ok = module(&format!(
        "CONST robtarget {n32} := {RT};\nPROC main()\n  MoveL {n32}, v100, fine, tool0;\nENDPROC"
    ));
    let p = read("m.mod", ok.as_bytes()).unwrap();
    assert_eq!(p.targets().at(0).id, n32);
    // In a declaration (line 2, after `CONST robtarget `: column 17), a
    // move (line 4, column 9), a routine (line 3, column 6), a label.
    let cases = [
        (
            format!("CONST robtarget {n33} := {RT};\nPROC main()\n  MoveL {n33}, v100, fine, tool0;\nENDPROC"),
            (2, 17),
        ),
        (
            format!("CONST robtarget p := {RT};\nPROC main()\n  MoveL {n33}, v100, fine, tool0;\nENDPROC"),
            (4, 9),
        ),
        (format!("CONST num x := 1;\nPROC {n33}()\nENDPROC"), (3, 6)),
        (format!("PROC main()\n  {n33}:\nENDPROC"), (3, 3)),
    ];
    for (body, (line, col)) in cases {
        let e = read("m.mod", module(&body).as_bytes()).unwrap_err();
        assert!(
            e.starts_with(&format!("m.mod:{line}:{col}: error: the name `{n33}` is 33 characters long: a RAPID name has at most 32")),
            "{e}"
        );
    }
    // Characters, not bytes: 32 Latin-1 letters are 32 (64 bytes in UTF-8).
    let latin = format!("p{}", "é".repeat(31));
    let ok = module(&format!("CONST num {latin} := 1;"));
    read("m.mod", ok.as_bytes()).unwrap();
    let latin1: Vec<u8> = format!(
        "MODULE m\nCONST num p{} := 1;\nENDMODULE\n",
        "\u{e9}".repeat(32)
    )
    .chars()
    .map(|c| c as u32 as u8)
    .collect();
    let e = read("m.mod", &latin1).unwrap_err();
    assert!(e.contains("is 33 characters long"), "{e}");
}

#[test]
fn an_index_written_outside_the_declared_size_is_refused_at_the_index() {
    let two = format!("CONST robtarget pA{{2}} := [{RT},{RT}];");
    let e = read(
        "m.mod",
        module(&format!(
            "{two}\nPROC main()\n  MoveL pA{{5}}, v100, fine, tool0;\nENDPROC"
        ))
        .as_bytes(),
    )
    .unwrap_err();
    assert!(
        e.starts_with("m.mod:4:9: error: pA{5} is out of bounds: pA is declared pA{2} at m.mod:2"),
        "{e}"
    );
    let e = read(
        "m.mod",
        module(&format!(
            "VAR robtarget pB{{1}} := [{RT}];\nPROC main()\n  MoveJ pB{{1000000000}}, v100, fine, tool0;\nENDPROC"
        ))
        .as_bytes(),
    )
    .unwrap_err();
    assert!(
        e.starts_with("m.mod:4:9: error: pB{1000000000} is out of bounds"),
        "{e}"
    );
    // Two dimensions, an index 0, and in an expression.
    let e = read(
        "m.mod",
        module("CONST num n{2,3} := [[1,2,3],[4,5,6]];\nVAR num x;\nPROC main()\n  x := n{2,4} + n{0,1};\nENDPROC").as_bytes(),
    )
    .unwrap_err();
    assert!(
        e.starts_with("m.mod:5:8: error: n{2,4} is out of bounds"),
        "{e}"
    );
    // Inside the size, or an index the run computes: read.
    for body in [
        format!("{two}\nPROC main()\n  MoveL pA{{2}}, v100, fine, tool0;\nENDPROC"),
        format!(
            "{two}\nVAR num i := 7;\nPROC main()\n  MoveL pA{{i}}, v100, fine, tool0;\nENDPROC"
        ),
    ] {
        read("m.mod", module(&body).as_bytes()).unwrap();
    }
}

#[test]
fn utf16_is_named_and_refused_and_a_utf8_mark_is_read() {
    let text = module(&format!("CONST robtarget p := {RT};"));
    for (bytes, name) in [
        (
            std::iter::once(0xFEFF)
                .chain(text.encode_utf16())
                .flat_map(u16::to_le_bytes)
                .collect::<Vec<u8>>(),
            "UTF-16 (little-endian)",
        ),
        (
            text.encode_utf16().flat_map(u16::to_be_bytes).collect(),
            "UTF-16 (big-endian)",
        ),
    ] {
        let e = read("w.mod", &bytes).unwrap_err();
        assert_eq!(
            e,
            format!("w.mod:1:1: error: {name} is not read; save the file as UTF-8 or ISO-8859-1 (Latin-1), as RobotStudio and the controller write RAPID")
        );
    }
    // A UTF-8 mark: the same targets, each 3 bytes later, on the same line
    // and column.
    let plain = read("a.mod", text.as_bytes()).unwrap();
    let marked: Vec<u8> = [&[0xEF, 0xBB, 0xBF][..], text.as_bytes()].concat();
    let p = read("a.mod", &marked).unwrap();
    let (a, b) = (plain.targets().at(0), p.targets().at(0));
    assert_eq!(b.origin.pos.offset, a.origin.pos.offset + 3);
    assert_eq!(
        (b.origin.pos.line, b.origin.pos.col),
        (a.origin.pos.line, a.origin.pos.col)
    );
}

#[test]
fn a_ten_megabyte_number_is_quoted_by_an_excerpt() {
    let big = "1".repeat(10 << 20);
    let e = read(
        "m.mod",
        module(&format!("CONST num n := {big};")).as_bytes(),
    )
    .unwrap_err();
    assert!(e.len() < 1000, "{} bytes of message", e.len());
    assert!(
        e.starts_with(&format!(
            "m.mod:2:16: error: number `{}…` (10485760 characters) out of range",
            "1".repeat(40)
        )),
        "{e}"
    );
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20)
}

/// A module of declarations and moves, its lines ending in `eols` (one
/// drawn per line, cycled).
fn program_with(eols: &[&str]) -> Vec<u8> {
    let lines = [
        "MODULE m".to_string(),
        "  ! a comment, then a declaration the lane reads".to_string(),
        format!("  CONST robtarget p10 := {RT};"),
        format!("  PERS robtarget pArr{{2}} := [{RT},"),
        format!("    {RT}];"),
        "  PROC main()".to_string(),
        "    MoveL p10, v100, fine, tool0;".to_string(),
        format!("    MoveJ {RT}, v100, z1, tool0;"),
        "    IF TRUE MoveL pArr{2}, v100, fine, tool0;".to_string(),
        "  ENDPROC".to_string(),
        "ENDMODULE".to_string(),
    ];
    let mut out = Vec::new();
    for (k, l) in lines.iter().enumerate() {
        out.extend_from_slice(l.as_bytes());
        out.extend_from_slice(eols[k % eols.len()].as_bytes());
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    /// A name is read up to 32 characters and refused beyond, at its
    /// line and column, on both paths, wherever it stands.
    #[test]
    fn a_name_is_read_up_to_32_characters(
        len in 1usize..70,
        context in 0usize..3,
        indent in 0usize..6,
    ) {
        let name = format!("p{}", "x".repeat(len - 1));
        let pad = " ".repeat(indent);
        let (body, line, col) = match context {
            0 => (format!("{pad}CONST robtarget {name} := {RT};"), 2, indent + 17),
            1 => (format!("{pad}VAR num {name};"), 2, indent + 9),
            _ => (format!("PROC main()\n{pad}MoveL {name}, v100, fine, tool0;\nENDPROC"), 3, indent + 7),
        };
        let found = read("m.mod", module(&body).as_bytes());
        if len <= 32 {
            // A move to an undeclared name is read all the same.
            prop_assert!(found.is_ok(), "{:?}", found.err());
        } else {
            let e = found.unwrap_err();
            let head = format!("m.mod:{line}:{col}: error: the name ");
            prop_assert!(e.starts_with(&head), "{}", e);
            let says = format!("is {len} characters long");
            prop_assert!(e.contains(&says), "{}", e);
            // The echo is bounded.
            prop_assert!(e.lines().next().unwrap().len() < 200, "{}", e);
        }
    }

    /// Every line end, mixed as it likes: the same targets on the same
    /// lines and columns as with LF, at the same offsets less the bytes
    /// the line ends take, and every byte kept.
    #[test]
    fn every_line_end_reads_alike(
        eols in prop::collection::vec(prop::sample::select(vec!["\n", "\r\n", "\r"]), 1..5),
    ) {
        let lf = read("m.mod", &program_with(&["\n"])).unwrap();
        let src = program_with(&eols);
        let p = read("m.mod", &src).unwrap();
        prop_assert_eq!(p.source(0), &src[..]);
        prop_assert_eq!(p.targets().len(), lf.targets().len());
        for (a, b) in lf.targets().iter().zip(p.targets().iter()) {
            prop_assert_eq!(&a.id, &b.id);
            prop_assert_eq!((a.origin.pos.line, a.origin.pos.col), (b.origin.pos.line, b.origin.pos.col));
            // The offset in this file: LF's, plus one for each CRLF before it.
            let line = b.origin.pos.line as usize;
            let extra = (0..line - 1).filter(|k| eols[k % eols.len()] == "\r\n").count();
            prop_assert_eq!(b.origin.pos.offset, a.origin.pos.offset + extra);
            let loc = rapidtherm::error::Location::from_offset("m.mod", &src, b.origin.pos.offset);
            prop_assert_eq!((loc.line, loc.col), (line, b.origin.pos.col as usize));
        }
    }
}
