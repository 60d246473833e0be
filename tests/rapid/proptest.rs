//! Generated modules (declarations, arrays, inline moves, Latin-1 comments
//! and names, CRLF/LF mixes, every number spelling): each round-trips
//! byte for byte, every robtarget is found under the identifier docs/formats.md
//! gives it with the numbers written, and editing one number changes only
//! that number's bytes.

use proptest::prelude::*;
use rapidtherm::rapid::{self, rewrite};

/// A number as written, and its value.
fn number() -> impl Strategy<Value = (String, f64)> {
    let plain = prop_oneof![
        (-800i32..800).prop_map(|i| i.to_string()),
        (-800_000i32..800_000, 1usize..5).prop_map(|(i, d)| format!("{:.*}", d, i as f64 / 1000.0)),
        (1u32..999).prop_map(|d| format!(".{d}")),
        (1u32..999).prop_map(|d| format!("-.{d}")),
        (0u32..999).prop_map(|i| format!("{i}.")),
        (
            1u32..99,
            1u32..99999,
            -9i32..10,
            any::<bool>(),
            any::<bool>()
        )
            .prop_map(|(m, f, e, upper, plus)| {
                let sign = if e >= 0 && plus { "+" } else { "" };
                let l = if upper { "E" } else { "e" };
                format!("{m}.{f:05}{l}{sign}{e:02}")
            }),
        (-245i32..245, -3i32..3).prop_map(|(m, e)| format!("{m}E{e}")),
    ];
    plain.prop_map(|s| {
        let v: f64 = s.parse().unwrap();
        (s, v)
    })
}

fn extax() -> impl Strategy<Value = String> {
    prop::sample::select(vec!["9E+09", "9E9", "9e9", "9E+9", "9e+09", "9.0E+09"])
        .prop_map(str::to_string)
}

#[derive(Debug, Clone)]
struct Rt {
    nums: Vec<(String, f64)>,
    text: String,
}

fn robtarget() -> impl Strategy<Value = Rt> {
    (
        prop::collection::vec(number(), 11),
        prop::collection::vec(extax(), 6),
        prop::sample::select(vec![",", ", ", " , "]),
    )
        .prop_map(|(mut nums, ext, sep)| {
            let t =
                |v: &[(String, f64)]| v.iter().map(|n| n.0.clone()).collect::<Vec<_>>().join(sep);
            let text = format!(
                "[[{}]{sep}[{}]{sep}[{}]{sep}[{}]]",
                t(&nums[0..3]),
                t(&nums[3..7]),
                t(&nums[7..11]),
                ext.join(sep)
            );
            nums.extend(ext.iter().map(|e| (e.clone(), e.parse().unwrap())));
            Rt { nums, text }
        })
}

#[derive(Debug, Clone)]
enum Item {
    Decl {
        latin1: bool,
        storage: &'static str,
        rt: Rt,
    },
    Array(Vec<Rt>),
    Comment(Vec<u8>),
    Text(Vec<u8>),
}

#[derive(Debug, Clone)]
enum Stmt {
    Move {
        instr: &'static str,
        comma: bool,
        rt: Rt,
    },
    Wait,
    If(Vec<Rt>),
    Comment(Vec<u8>),
}

fn latin1_text() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(
        prop_oneof![
            Just(b'a'),
            Just(b' '),
            Just(b';'),
            Just(b'['),
            0xA0u8..=0xFF
        ],
        0..20,
    )
}

fn item() -> impl Strategy<Value = Item> {
    prop_oneof![
        (
            any::<bool>(),
            prop::sample::select(vec![
                "CONST",
                "PERS",
                "VAR",
                "TASK PERS",
                "LOCAL CONST",
                "const"
            ]),
            robtarget()
        )
            .prop_map(|(latin1, storage, rt)| Item::Decl {
                latin1,
                storage,
                rt
            }),
        prop::collection::vec(robtarget(), 1..4).prop_map(Item::Array),
        latin1_text().prop_map(Item::Comment),
        latin1_text().prop_map(Item::Text),
    ]
}

fn stmt() -> impl Strategy<Value = Stmt> {
    prop_oneof![
        (
            prop::sample::select(vec!["MoveL", "MoveJ", "movel", "MOVEL"]),
            any::<bool>(),
            robtarget()
        )
            .prop_map(|(instr, comma, rt)| Stmt::Move { instr, comma, rt }),
        Just(Stmt::Wait),
        prop::collection::vec(robtarget(), 0..3).prop_map(Stmt::If),
        latin1_text().prop_map(Stmt::Comment),
    ]
}

/// Expected targets: identifier, and each number's text and value.
type Expected = Vec<(String, Vec<(String, f64)>)>;

/// The module text, and the expected targets in source order.
fn module(items: &[Item], stmts: &[Stmt], eols: &[bool]) -> (Vec<u8>, Expected) {
    let mut lines: Vec<Vec<u8>> = vec![b"MODULE Gen".to_vec()];
    let mut expect = Vec::new();
    for (i, it) in items.iter().enumerate() {
        match it {
            Item::Decl {
                latin1,
                storage,
                rt,
            } => {
                let (name_bytes, name) = if *latin1 {
                    (format!("p\u{0}{i}").into_bytes(), format!("p\u{e9}{i}"))
                } else {
                    (format!("p{i}").into_bytes(), format!("p{i}"))
                };
                let name_bytes: Vec<u8> = name_bytes
                    .into_iter()
                    .map(|b| if b == 0 { 0xE9 } else { b })
                    .collect();
                let mut l = format!("  {storage} robtarget ").into_bytes();
                l.extend(name_bytes);
                l.extend(format!(" := {};", rt.text).into_bytes());
                lines.push(l);
                expect.push((name, rt.nums.clone()));
            }
            Item::Array(rts) => {
                let body: Vec<String> = rts.iter().map(|r| r.text.clone()).collect();
                lines.push(
                    format!(
                        "  VAR robtarget arr{i}{{{}}} := [{}];",
                        rts.len(),
                        body.join(",\n    ")
                    )
                    .into_bytes(),
                );
                for (k, r) in rts.iter().enumerate() {
                    expect.push((format!("arr{i}{{{}}}", k + 1), r.nums.clone()));
                }
            }
            Item::Comment(c) => {
                let mut l = b"  ! ".to_vec();
                l.extend(c);
                lines.push(l);
            }
            Item::Text(c) => {
                let mut l = format!("  VAR string s{i} := \"").into_bytes();
                for &b in c {
                    if b == b'"' {
                        l.extend(b"\"\"");
                    } else {
                        l.push(b);
                    }
                }
                l.extend(b"\"\"x\";");
                lines.push(l);
            }
        }
    }
    lines.push(b"  PROC main()".to_vec());
    let mut k = 0;
    let mut mv = |rt: &Rt, instr: &str, comma: bool, lines: &mut Vec<Vec<u8>>| {
        k += 1;
        let sep = if comma { ", " } else { "" };
        lines.push(
            format!(
                "    {instr} {}, v100, z10, tool0{sep}\\WObj:=wobj0;",
                rt.text
            )
            .into_bytes(),
        );
        expect.push((format!("main#{k}"), rt.nums.clone()));
    };
    for s in stmts {
        match s {
            Stmt::Move { instr, comma, rt } => mv(rt, instr, *comma, &mut lines),
            Stmt::Wait => lines.push(b"    WaitTime 0.5;".to_vec()),
            Stmt::If(rts) => {
                lines.push(b"    IF reg1 > 0 THEN".to_vec());
                for r in rts {
                    mv(r, "MoveL", false, &mut lines);
                }
                lines.push(b"    endif".to_vec());
            }
            Stmt::Comment(c) => {
                let mut l = b"    ! ".to_vec();
                l.extend(c);
                lines.push(l);
            }
        }
    }
    lines.push(b"  ENDPROC".to_vec());
    lines.push(b"ENDMODULE".to_vec());
    let mut out = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        out.extend(l);
        out.extend(
            if eols.get(i % eols.len().max(1)).copied().unwrap_or(false) {
                &b"\r\n"[..]
            } else {
                &b"\n"[..]
            },
        );
    }
    (out, expect)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn generated_modules_round_trip_and_targets_are_found(
        items in prop::collection::vec(item(), 0..8),
        stmts in prop::collection::vec(stmt(), 0..8),
        eols in prop::collection::vec(any::<bool>(), 1..5),
        pick in any::<prop::sample::Index>(),
        new_value in -900.0f64..900.0,
    ) {
        let (src, expect) = module(&items, &stmts, &eols);
        let prog = rapid::parse("gen.mod", &src).map_err(|e| TestCaseError::fail(format!("{e}\n{}", String::from_utf8_lossy(&src))))?;
        prop_assert_eq!(rewrite::apply_edits("gen.mod", &src, &[]).unwrap(), src.clone());
        let got: Vec<String> = prog.targets().iter().map(|t| t.id.clone()).collect();
        let want: Vec<&str> = expect.iter().map(|e| e.0.as_str()).collect();
        prop_assert_eq!(got, want);
        for (t, (_, nums)) in prog.targets().iter().zip(&expect) {
            let v = t.value.as_ref().unwrap();
            for (n, (text, value)) in v.numbers().zip(nums) {
                prop_assert_eq!(n.text(&src), text.as_str());
                prop_assert_eq!(n.value, *value);
            }
        }
        if !expect.is_empty() {
            // Edit one number of one target: only its bytes change.
            let ti = pick.index(expect.len());
            let num = prog.targets().at(ti).value.as_ref().unwrap().trans[pick.index(3)].clone();
            if let Some(edit) = rewrite::number_edit(&src, &num, new_value, rewrite::POSITION_RESOLUTION) {
                let out = rewrite::apply_edits("gen.mod", &src, std::slice::from_ref(&edit)).unwrap();
                prop_assert_eq!(&out[..num.span().start], &src[..num.span().start]);
                prop_assert_eq!(&out[num.span().start + edit.new.len()..], &src[num.span().end..]);
                let prog2 = rapid::parse("gen.mod", &out).unwrap();
                let n2 = prog2.targets().at(ti).value.as_ref().unwrap().numbers()
                    .find(|n| n.span().start == num.span().start).unwrap().value;
                prop_assert!((n2 - new_value).abs() <= 0.0005 + 1e-9, "{} -> {}", new_value, n2);
            }
        }
    }
}
