//! Every RAPID sample reads, rewrites losslessly, and a one-target edit
//! changes exactly that target's number bytes.

use rapidtherm::rapid::{self, rewrite, Program, TargetKind};
use std::path::{Path, PathBuf};

fn samples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("samples"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| {
                matches!(
                    p.extension().and_then(|e| e.to_str()),
                    Some("mod" | "modx" | "prg" | "sys")
                )
            })
            .collect();
    v.sort();
    v
}

fn load(name: &str) -> (Vec<u8>, Program) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("samples")
        .join(name);
    let bytes = std::fs::read(&path).unwrap();
    let prog = rapid::parse(name, &bytes).unwrap_or_else(|e| panic!("{e}"));
    (bytes, prog)
}

#[test]
fn at_least_eight_samples_all_parse_and_round_trip() {
    let files = samples();
    assert!(files.len() >= 8, "{} samples", files.len());
    for f in files {
        let bytes = std::fs::read(&f).unwrap();
        let name = f.display().to_string();
        let prog = rapid::parse(&name, &bytes).unwrap_or_else(|e| panic!("{e}"));
        assert!(!prog.modules.is_empty(), "{name}");
        let same = rewrite::apply_edits(&name, &bytes, &[]).unwrap();
        assert_eq!(same, bytes, "{name}");
        // Every number span holds the text of its value.
        for t in prog.targets() {
            if let Some(v) = &t.value {
                for n in v.numbers() {
                    let text = n.text(&bytes);
                    let parsed: f64 = text
                        .trim()
                        .parse()
                        .unwrap_or_else(|_| panic!("{name}: `{text}`"));
                    assert_eq!(parsed, n.value, "{name} {}", t.id);
                }
            }
        }
    }
}

#[test]
fn editing_one_target_changes_only_its_number_bytes() {
    for f in samples() {
        let bytes = std::fs::read(&f).unwrap();
        let name = f.display().to_string();
        let prog = rapid::parse(&name, &bytes).unwrap();
        let literal: Vec<_> = prog
            .targets()
            .iter()
            .filter(|t| t.value.is_some())
            .collect();
        if literal.is_empty() {
            continue;
        }
        let t = &literal[literal.len() / 2];
        let v = t.value.as_ref().unwrap();
        let new = [
            v.trans[0].value + 0.25,
            v.trans[1].value - 1.0,
            v.trans[2].value + 0.0004,
        ];
        let edits: Vec<_> = v
            .trans
            .iter()
            .zip(new)
            .filter_map(|(n, x)| rewrite::number_edit(&bytes, n, x, rewrite::POSITION_RESOLUTION))
            .collect();
        assert!(edits.len() >= 2, "{name}: {}", t.id);
        let out = rewrite::apply_edits(&name, &bytes, &edits).unwrap();
        // Outside the edited spans, the bytes are the original ones.
        let first = edits.iter().map(|e| e.span.start).min().unwrap();
        let last = edits.iter().map(|e| e.span.end).max().unwrap();
        let grow = out.len() as isize - bytes.len() as isize;
        assert_eq!(&out[..first], &bytes[..first], "{name}");
        assert_eq!(
            &out[(last as isize + grow) as usize..],
            &bytes[last..],
            "{name}"
        );
        // Between the edited numbers (commas, spaces) nothing changed.
        let mut sorted = edits.clone();
        sorted.sort_by_key(|e| e.span.start);
        let mut at_out = first;
        for w in sorted.windows(2) {
            at_out += w[0].new.len();
            let gap = &bytes[w[0].span.end..w[1].span.start];
            assert_eq!(&out[at_out..at_out + gap.len()], gap);
            at_out += gap.len();
        }
        // Read back: this target moved, every other one is unchanged.
        let prog2 = rapid::parse(&name, &out).unwrap();
        assert_eq!(prog2.targets().len(), prog.targets().len());
        for (a, b) in prog.targets().iter().zip(prog2.targets()) {
            assert_eq!(a.id, b.id);
            let (Some(va), Some(vb)) = (&a.value, &b.value) else {
                continue;
            };
            if a.id == t.id {
                for (n, want) in vb.trans.iter().zip(new) {
                    assert!((n.value - want).abs() <= 0.0005 + 1e-9, "{name} {}", a.id);
                }
                assert_eq!(va.rot_values(), vb.rot_values());
            } else {
                assert_eq!(va.trans_values(), vb.trans_values(), "{name} {}", a.id);
            }
        }
    }
}

#[test]
fn cam_sample_has_thousands_of_inline_movel_targets() {
    let (_, prog) = load("cam_contour.mod");
    let movel = prog
        .targets()
        .iter()
        .filter(|t| t.kind == TargetKind::Inline && t.instruction.as_deref() == Some("MoveL"))
        .count();
    assert!(movel >= 5000, "{movel}");
    let t = prog.target("main#1").unwrap();
    assert_eq!(
        t.value.as_ref().unwrap().trans_values(),
        [370.0, 20.0, 120.0]
    );
    assert_eq!(t.tool.as_deref(), Some("tSpindle"));
    assert_eq!(t.wobj.as_deref(), Some("wPlate"));
    // The CAM generator is deterministic and the committed file is its output.
    assert!(prog.target(&format!("main#{movel}")).is_some());
}

#[test]
fn latin1_crlf_sample_keeps_its_bytes_and_names() {
    let (bytes, prog) = load("weld_cell_latin1.mod");
    assert!(bytes.windows(2).any(|w| w == b"\r\n"));
    assert!(
        std::str::from_utf8(&bytes).is_err(),
        "must be Latin-1, not UTF-8"
    );
    let t = prog.target("p\u{dc}ber").expect("Latin-1 identifier");
    assert_eq!(
        t.value.as_ref().unwrap().trans_values(),
        [470.0, -60.0, 205.0]
    );
    // Line 10, after 4 spaces and `CONST robtarget pÜber := `.
    assert_eq!((t.origin.pos.line, t.origin.pos.col), (10, 30));
    let d = prog.target("Naht1@1").unwrap();
    assert_eq!(
        d.derived.as_ref().unwrap().bases,
        vec!["pNahtEnde".to_string()]
    );
    assert_eq!(d.wobj.as_deref(), Some("wTr\u{e4}ger"));
}

#[test]
fn two_modules_qualify_shared_names() {
    let (_, prog) = load("two_modules.mod");
    assert_eq!(prog.modules.len(), 2);
    let ids: Vec<String> = prog.targets().iter().map(|t| t.id.clone()).collect();
    assert_eq!(
        ids,
        [
            "MainModule:p10",
            "p20",
            "MainModule:main#1",
            "Station2:p10",
            "pPlace",
            "Station2:main#1"
        ]
    );
}

#[test]
fn fixtures_arrays_records_tools_wobjs() {
    let (_, prog) = load("fixtures.mod");
    let g = prog.target("pGrid{2,1}").unwrap();
    assert_eq!(g.kind, TargetKind::ArrayElement);
    assert_eq!(
        g.value.as_ref().unwrap().trans_values(),
        [520.0, 70.0, 105.0]
    );
    let r = prog.target("sCell{2}.path.finish").unwrap();
    assert_eq!(r.kind, TargetKind::RecordField);
    assert_eq!(
        r.value.as_ref().unwrap().trans_values(),
        [540.0, 140.0, 102.0]
    );
    assert!(prog.target("gBead.start").is_some());
    assert_eq!(
        prog.jointtargets()
            .iter()
            .filter(|j| j.id.starts_with("sCell"))
            .count(),
        2
    );
    let tool = &prog.tools()[0];
    assert_eq!(tool.name, "tGlue");
    assert_eq!(
        tool.tframe_trans.each_ref().map(|n| n.value),
        [0.0, 0.0, 145.2]
    );
    assert_eq!(tool.mass.value, 1.8);
    assert_eq!(prog.wobjs().len(), 2);
    assert_eq!(
        prog.wobjs()[1].oframe_trans.each_ref().map(|n| n.value),
        [10.0, 5.0, 0.0]
    );
    assert_eq!(prog.speeds()[0].v_tcp.value, 80.0);
    // zGlue is a zonedata; zOdd (six fields) is harmless and not listed.
    assert_eq!(prog.zones().len(), 1);
    assert_eq!(prog.zones()[0].values[0].value, 0.5);
}

#[test]
fn pendant_program_with_header_lowercase_movec_and_arc() {
    let (_, prog) = load("arc_pendant.mod");
    let by_instr = |i: &str| {
        prog.targets()
            .iter()
            .filter(|t| {
                t.instruction
                    .as_deref()
                    .is_some_and(|x| x.eq_ignore_ascii_case(i))
            })
            .count()
    };
    assert_eq!(by_instr("movec"), 2);
    assert_eq!(by_instr("arcc"), 2);
    assert_eq!(by_instr("arcl"), 1);
    let (_, r) = prog.routine("rweldcircle").unwrap();
    assert!(r
        .body
        .iter()
        .any(|s| matches!(&s.kind, rapid::StatementKind::Placeholder(p) if p == "<SMT>")));
    assert_eq!(
        prog.target("rWeldCircle#3")
            .unwrap()
            .value
            .as_ref()
            .unwrap()
            .trans_values(),
        [500.0, 200.0, 152.0]
    );
}

#[test]
fn control_flow_statements_and_derived_targets() {
    let (_, prog) = load("control_flow.mod");
    let (_, main) = prog.routine("main").unwrap();
    use rapid::StatementKind as S;
    let kinds: Vec<&S> = main.body.iter().map(|s| &s.kind).collect();
    assert!(kinds.iter().any(
        |k| matches!(k, S::For { body, .. } if matches!(body[0].kind, S::For { step: Some(_), .. }))
    ));
    assert!(kinds.iter().any(|k| matches!(k, S::While { .. })));
    assert!(kinds.iter().any(|k| matches!(k, S::Test { cases, default: Some(_), .. } if cases.len() == 2 && cases[1].0.len() == 3)));
    assert!(kinds
        .iter()
        .any(|k| matches!(k, S::Label(l) if l == "lblDone")));
    assert!(main.error.is_some());
    let (_, pick) = prog.routine("PickPart").unwrap();
    assert!(pick.backward.is_some() && pick.undo.is_some());
    let rot = prog.target("pRot").unwrap();
    assert_eq!(rot.kind, TargetKind::Derived);
    assert_eq!(rot.derived.as_ref().unwrap().function, "RelTool");
    assert_eq!(
        rot.derived.as_ref().unwrap().bases,
        vec!["pPick".to_string()]
    );
    // FUNC returning robtarget: the call is a derived target, the literal
    // it returns is an inline target of the FUNC.
    assert_eq!(
        prog.target("main@1")
            .unwrap()
            .derived
            .as_ref()
            .unwrap()
            .function,
        "Home"
    );
    assert!(prog.target("Home#1").is_some());
    // Optional argument after a comma and without one.
    let p = prog.target("PlacePart#1").unwrap();
    assert_eq!(p.wobj.as_deref(), Some("wPallet"));
    // 9E9 in every spelling is the same placeholder value.
    let pick_t = prog.target("pPick").unwrap();
    assert!(pick_t
        .value
        .as_ref()
        .unwrap()
        .extax_values()
        .iter()
        .all(|&e| e == 9e9));
    // The schedule estimator's view of a move.
    let S::Call(c) = &pick.body[0].kind else {
        panic!()
    };
    assert_eq!(&*c.name, "MoveJ");
    assert_eq!(
        c.positional().nth(1).and_then(|e| e.as_name()),
        Some("vFast")
    );
    assert_eq!(c.targets.len(), 1);
    assert_eq!(prog.targets().at(c.targets[0]).id, "PickPart@1");
}

#[test]
fn jointtargets_for_moveabsj() {
    let (bytes, prog) = load("service_positions.mod");
    let ids: Vec<&str> = prog.jointtargets().iter().map(|j| j.id.as_str()).collect();
    assert_eq!(
        ids,
        [
            "jHome",
            "jService",
            "jCalib{1}",
            "jCalib{2}",
            "jCalib{3}",
            "rCalibrate#1"
        ]
    );
    let j = &prog.jointtargets()[2];
    assert_eq!(
        j.robax.each_ref().map(|n| n.value),
        [30.0, 20.0, -40.0, 50.0, 60.0, 70.0]
    );
    assert_eq!(j.robax[2].text(&bytes), "-40");
}

#[test]
fn bom_utf8_and_mixed_line_endings() {
    let (bytes, prog) = load("inspection_bom.prg");
    assert!(bytes.starts_with(&[0xEF, 0xBB, 0xBF]));
    let t = prog.target("pMe\u{df}punkt1").unwrap();
    assert_eq!(t.value.as_ref().unwrap().trans[2].text(&bytes), "300.125");
    let (bytes, prog) = load("deburr_mixed_eol.modx");
    assert!(bytes.windows(2).any(|w| w == b"\r\n"));
    assert!(bytes.windows(2).any(|w| w[0] != b'\r' && w[1] == b'\n'));
    assert_eq!(prog.targets().len(), 3);
    assert_eq!(
        prog.target("main#1").unwrap().instruction.as_deref(),
        Some("SearchL")
    );
}

#[test]
fn motion_parts_for_a_schedule_estimator() {
    use rapid::{Expr, MotionKind, StatementKind as S};
    // The tree as the grammar makes it (the lane holds moves in runs).
    let prog = load("arc_pendant.mod").1.expanded();
    let (_, r) = prog.routine("rWeldCircle").unwrap();
    let motions: Vec<_> = r
        .body
        .iter()
        .filter_map(|s| match &s.kind {
            S::Call(c) => c.motion().map(|m| (c.name.to_string(), m)),
            _ => None,
        })
        .collect();
    let names: Vec<&str> = motions.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "movej",
            "movel",
            "movec",
            "ArcLStart",
            "arcl",
            "arcc",
            "ArcLEnd",
            "movel"
        ]
    );
    let (_, arcl) = &motions[4];
    assert_eq!(arcl.signature.kind, MotionKind::Linear);
    assert_eq!(arcl.speed.and_then(Expr::as_name), Some("v20"));
    assert_eq!(arcl.zone.and_then(Expr::as_name), Some("z1"));
    assert_eq!(arcl.tool.and_then(Expr::as_name), Some("tWeldGun"));
    assert_eq!(arcl.wobj.and_then(Expr::as_name), Some("wJig"));
    let Some(Expr::Target(i)) = arcl.to else {
        panic!("{:?}", arcl.to)
    };
    assert_eq!(prog.targets().at(*i).id, "rWeldCircle#5");
    let (_, movec) = &motions[2];
    assert_eq!(movec.signature.kind, MotionKind::Circular);
    let (Some(Expr::Target(via)), Some(Expr::Target(to))) = (movec.via, movec.to) else {
        panic!()
    };
    assert_eq!(
        (
            prog.targets().at(*via).id.as_str(),
            prog.targets().at(*to).id.as_str()
        ),
        ("rWeldCircle#2", "rWeldCircle#3")
    );
    let (_, start) = &motions[3];
    assert_eq!(start.zone.and_then(Expr::as_name), Some("fine"));

    let prog = load("service_positions.mod").1.expanded();
    let (_, r) = prog.routine("rCalibrate").unwrap();
    let S::Call(c) = &r.body[2].kind else {
        panic!()
    };
    let m = c.motion().unwrap();
    assert_eq!(m.signature.kind, MotionKind::AbsJoint);
    assert!(matches!(m.to, Some(Expr::JointTarget(_))));
    assert_eq!(m.zone.and_then(Expr::as_name), Some("z50"));

    let (_, prog) = load("control_flow.mod");
    let (_, r) = prog.routine("PickPart").unwrap();
    // Every statement in source order, a move the lane holds too.
    let body: Vec<_> = (prog.statements(&r.body))
        .map(|s| s.statement().unwrap().into_owned())
        .collect();
    let S::Call(c) = &body[0].kind else { panic!() };
    let m = c.motion().unwrap();
    assert!(matches!(m.to, Some(Expr::Call(f)) if &*f.name == "Offs"));
    assert_eq!(m.speed.and_then(Expr::as_name), Some("vFast"));
    let S::Call(wait) = &body[3].kind else {
        panic!()
    };
    assert_eq!(&*wait.name, "WaitTime");
    assert!(wait.motion().is_none());
    assert_eq!(wait.positional().next().and_then(Expr::as_num), Some(0.3));
}

#[test]
fn deep_nesting_is_refused_not_overflowed() {
    // 60 nested blocks parse (on a test thread's small stack, debug build);
    // beyond the limit, a located error rather than a stack overflow.
    let nest = |n: usize| {
        let mut s = String::from("MODULE m\nPROC main()\n");
        for _ in 0..n {
            s.push_str("IF reg1 > 0 THEN\n");
        }
        s.push_str("MoveL [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n");
        for _ in 0..n {
            s.push_str("ENDIF\n");
        }
        s.push_str("ENDPROC\nENDMODULE\n");
        s
    };
    let p = rapid::parse("deep.mod", nest(60).as_bytes()).unwrap();
    assert_eq!(p.targets().at(0).id, "main#1");
    let e = rapid::parse("deep.mod", nest(500).as_bytes()).unwrap_err();
    assert!(e.to_string().contains("nested deeper than 64"), "{e}");
    let brackets = format!(
        "MODULE m\nVAR num x := {}1{};\nENDMODULE\n",
        "(".repeat(1000),
        ")".repeat(1000)
    );
    let e = rapid::parse("deep.mod", brackets.as_bytes()).unwrap_err();
    assert_eq!(e.location.as_ref().map(|l| l.line), Some(2));
    let signs = format!("MODULE m\nVAR num x := {}1;\nENDMODULE\n", "-".repeat(5000));
    assert!(rapid::parse("deep.mod", signs.as_bytes()).is_err());
    let long = format!(
        "MODULE m\nVAR num x := 1{};\nENDMODULE\n",
        "+1".repeat(5000)
    );
    assert!(rapid::parse("deep.mod", long.as_bytes()).is_err());
}

#[test]
fn nested_indexes_do_not_backtrack_exponentially() {
    // Found by fuzzing: names with 40 nested, unclosed `{` indexes took
    // seconds and a GB of memory when a name's index could be read two
    // ways. Now one way: an error, at once.
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/malformed/fuzz_nested_index.mod"
    ))
    .unwrap();
    let e = rapid::parse("fuzz.mod", &bytes).unwrap_err();
    assert_eq!(e.location.as_ref().map(|l| l.line), Some(3));
    let deep = format!(
        "MODULE m\nPROC main()\nx := a{}1{};\nENDPROC\nENDMODULE\n",
        "{b".repeat(40),
        "}".repeat(39)
    );
    assert!(rapid::parse("deep.mod", deep.as_bytes()).is_err());
}

#[test]
fn a_robtarget_array_of_20000_elements_parses() {
    // A CAM path as one array literal: nothing in the parser may bound a
    // piece's size (pest's cumulative call limit once did).
    let n = 20_000;
    let items: Vec<String> = (0..n)
        .map(|i| format!("[[{i},0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]"))
        .collect();
    let src = format!(
        "MODULE m\nCONST robtarget path{{{n}}} := [{}];\nENDMODULE\n",
        items.join(",\n")
    );
    let program = rapid::parse("path.mod", src.as_bytes()).unwrap();
    let targets = program.targets();
    assert_eq!(targets.len(), n);
    assert_eq!(targets.at(0).id, "path{1}");
    assert_eq!(targets.at(n - 1).id, format!("path{{{n}}}"));
    assert_eq!(
        targets.at(n - 1).value.as_ref().unwrap().trans_values(),
        [(n - 1) as f64, 0.0, 400.0]
    );
    assert_eq!(program.source(0), src.as_bytes());
}
