//! The listing of a program's targets (`rapidtherm targets`): every
//! robtarget with its place, numbers, RobotStudio's Euler angles and the
//! tools and work objects the moves that reach it use; or every
//! jointtarget. As a table, CSV or JSON; made a chunk of targets at a time
//! on every core.

use super::usage::Usage;
use super::usages::{declared_derived_usages, uses};
use super::uses::UseRef;
use crate::rapid::{Number, Program, Target};
use crate::report::{
    render_csv, render_table, shortest, shortest_of_literal_bytes, shortest_to_4_places,
    write_table, Align, Rows,
};
use crate::robot::euler::euler_zyx_deg;
use crate::robot::frames::pose_from_rapid;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::io::Write;

/// The listing's format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ListFormat {
    Table,
    Csv,
    Json,
}

/// Shortest text that reads back as the same number.
fn n(v: f64) -> String {
    let mut s = String::new();
    shortest(&mut s, v);
    s
}

/// [`n`] of a number of the source `src`, written at the end of `buf`:
/// from its text where that gives the same.
fn num(buf: &mut String, x: &Number, src: &[u8]) {
    let text = src.get(x.span()).unwrap_or_default();
    let same_sign = (text.first() == Some(&b'-')) == x.value.is_sign_negative();
    if !(same_sign && shortest_of_literal_bytes(buf, text)) {
        shortest(buf, x.value);
    }
}

/// One move that reaches a target, as the listing shows it: borrowed
/// from the program's uses, so that a million targets are listed without
/// a copy of each use's names.
#[derive(Clone, Copy)]
pub struct Use<'a> {
    tool: &'a str,
    wobj: &'a str,
    instruction: &'a str,
    routine: &'a str,
    line: u32,
}

impl<'a> From<UseRef<'a>> for Use<'a> {
    fn from(u: UseRef<'a>) -> Use<'a> {
        Use {
            tool: u.tool_name(),
            wobj: u.wobj_name(),
            instruction: u.instruction(),
            routine: u.routine(),
            line: u.line(),
        }
    }
}

impl<'a> From<&'a Usage> for Use<'a> {
    fn from(u: &'a Usage) -> Use<'a> {
        Use {
            tool: u.tool_name(),
            wobj: u.wobj_name(),
            instruction: &u.instruction,
            routine: &u.routine,
            line: u.line,
        }
    }
}

/// The tool/work-object pairs a target is moved to with, grouped as
/// [`super::uses_by_frames`] groups them (names compared as RAPID
/// compares them): in program order of each pair's first use, so the
/// first is the one `correct` corrects it for. Names as written,
/// `tool0`/`wobj0` where the move names none (RAPID's defaults). Empty: no
/// move instruction reaches the target.
fn pairs<'a>(t: &'a Target, uses: &[Use<'a>]) -> Pairs<'a> {
    let mut out = Pairs::new();
    if uses.is_empty() {
        // A derived target written in a move (`MoveL Offs(p10, ...)`):
        // its bases carry the uses, the target the move's own names.
        if t.instruction.is_some() {
            out.push((
                t.tool.as_deref().unwrap_or("tool0"),
                t.wobj.as_deref().unwrap_or("wobj0"),
            ));
        }
        return out;
    }
    for u in uses {
        let same = |p: &&(&str, &str)| {
            p.0.eq_ignore_ascii_case(u.tool) && p.1.eq_ignore_ascii_case(u.wobj)
        };
        if !out.iter().any(|p| same(&p)) {
            out.push((u.tool, u.wobj));
        }
    }
    out
}

/// A target's tool/work-object pairs: nearly always one, held in place
/// (a million rows made a million allocations otherwise).
type Pairs<'a> = smallvec::SmallVec<[(&'a str, &'a str); 2]>;

/// RobotStudio's RX, RY, RZ of a target's quaternion (degrees); `None`
/// without numbers or for a quaternion that is not a rotation.
fn euler(t: &Target) -> Option<[f64; 3]> {
    let v = t.value.as_ref()?;
    let pose = pose_from_rapid(v.trans_values(), v.rot_values()).ok()?;
    Some(euler_zyx_deg(&pose.rotation))
}

/// The listing of one program's robtargets (`several`: read from
/// several files, whose names the table's `at` gives).
pub fn listing(format: ListFormat, several: bool, prog: &Program) -> String {
    let (lister, parts) = listing_parts(format, several, prog);
    let mut out = Vec::new();
    // Writing to a Vec cannot fail.
    let _ = lister.finish(parts, &mut out);
    String::from_utf8(out).unwrap_or_default()
}

/// The listing's rows, a chunk of targets at a time, and the lister that
/// writes them ([`Lister::finish`]): a million targets make 150 MB of
/// text, which a caller writes as it is put together.
pub fn listing_parts(
    format: ListFormat,
    several: bool,
    prog: &Program,
) -> (Lister<'_>, Vec<ListingPart>) {
    let lister = Lister {
        prog,
        several,
        format,
    };
    // The moves that reach each target: those [`resolve::uses`] finds, and
    // the moves naming declared derived targets (`CONST robtarget p20 :=
    // Offs(p10, ...)`), which it gives to no target.
    let uses = uses(prog);
    let derived = declared_derived_usages(prog);
    let all = prog.targets();
    // The rows made a chunk of targets at a time on every core (a
    // program's targets of a run made one at a time), put together in
    // order.
    let chunks = all.len().div_ceil(CHUNK);
    let parts: Vec<ListingPart> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut slot = crate::rapid::targets::blank();
            let mut part = lister.part();
            let mut reach: Vec<Use> = Vec::new();
            for i in c * CHUNK..((c + 1) * CHUNK).min(all.len()) {
                let t: &Target = match all.one_by_one(i) {
                    Some(t) => t,
                    None if all.fill(i, &mut slot) => &slot,
                    None => continue,
                };
                reach.clear();
                reach.extend(uses.of(i).map(Use::from));
                if reach.is_empty() {
                    reach.extend(derived.get(&i).into_iter().flatten().map(Use::from));
                }
                lister.add(&mut part, t, &reach, prog.source(t.origin.file));
            }
            part
        })
        .collect();
    (lister, parts)
}

/// Bytes reserved for a table row's cells (a row of the CAM sample's
/// listing is 129 characters laid out, its cells fewer): a part's text
/// is made without growing.
const ROW_BYTES: usize = 128;

/// Targets one core lists at a time.
const CHUNK: usize = 16_384;

/// Makes the rows of one program's listing, a chunk of targets at a time.
pub struct Lister<'p> {
    pub prog: &'p Program,
    /// Several files: the table's `at` names the file.
    pub several: bool,
    pub format: ListFormat,
}

/// Rows made so far (by one thread), in the format of the listing.
pub enum ListingPart {
    Table {
        rows: Rows,
        several_pairs: bool,
        unused: bool,
    },
    Csv {
        row: Rows,
        out: Box<csv::Writer<Vec<u8>>>,
    },
    /// The items pretty-printed one level in, `,\n` between them.
    Json { out: Vec<u8>, items: usize },
}

const TABLE_HEADER: [&str; 16] = [
    "target", "kind", "at", "x_mm", "y_mm", "z_mm", "q1", "q2", "q3", "q4", "rx_deg", "ry_deg",
    "rz_deg", "robconf", "tool", "wobj",
];

// Scripts read these columns by name or place: new ones are added at the
// end, none renamed.
const CSV_HEADER: [&str; 28] = [
    "target",
    "kind",
    "file",
    "line",
    "col",
    "x",
    "y",
    "z",
    "q1",
    "q2",
    "q3",
    "q4",
    "cf1",
    "cf4",
    "cf6",
    "cfx",
    "tool",
    "wobj",
    "instruction",
    "module",
    "routine",
    "derived_from",
    "expression",
    "rx_deg",
    "ry_deg",
    "rz_deg",
    "frames",
    "moves",
];

impl Lister<'_> {
    pub fn part(&self) -> ListingPart {
        match self.format {
            ListFormat::Table => ListingPart::Table {
                rows: Rows::with_capacity(CHUNK, TABLE_HEADER.len(), CHUNK * ROW_BYTES),
                several_pairs: false,
                unused: false,
            },
            ListFormat::Csv => ListingPart::Csv {
                row: Rows::default(),
                out: Box::new(csv::WriterBuilder::new().from_writer(Vec::new())),
            },
            ListFormat::Json => ListingPart::Json {
                out: Vec::new(),
                items: 0,
            },
        }
    }

    /// The row of target `t`, reached by the moves `uses`, its numbers
    /// written in `src`.
    pub fn add(&self, part: &mut ListingPart, t: &Target, uses: &[Use], src: &[u8]) {
        let prog = self.prog;
        match part {
            ListingPart::Table {
                rows,
                several_pairs,
                unused,
            } => {
                rows.cell(&t.id);
                rows.cell(t.kind.as_str());
                let (line, col) = (t.origin.pos.line, t.origin.pos.col);
                let at = rows.text();
                if self.several {
                    at.push_str(&prog.files[t.origin.file]);
                    at.push(':');
                }
                at.push_str(itoa::Buffer::new().format(line));
                at.push(':');
                at.push_str(itoa::Buffer::new().format(col));
                rows.end_cell();
                match &t.derived {
                    Some(d) if t.value.is_none() => {
                        for _ in 0..10 {
                            rows.cell("");
                        }
                        let _ = write!(rows.text(), "= {}", d.expr);
                        rows.end_cell();
                    }
                    _ => {
                        let v = t.value.as_ref();
                        for x in v.into_iter().flat_map(|v| v.trans.iter().chain(&v.rot)) {
                            num(rows.text(), x, src);
                            rows.end_cell();
                        }
                        if v.is_none() {
                            for _ in 0..7 {
                                rows.cell("");
                            }
                        }
                        eulers(rows, t);
                        rows.text().push('[');
                        for i in 0..4 {
                            if i > 0 {
                                rows.text().push(',');
                            }
                            if let Some(v) = v {
                                num(rows.text(), &v.robconf[i], src);
                            }
                        }
                        rows.text().push(']');
                        rows.end_cell();
                    }
                }
                let p = pairs(t, uses);
                *several_pairs |= p.len() > 1;
                *unused |= p.is_empty();
                if p.is_empty() {
                    rows.cell("-");
                    rows.cell("-");
                } else {
                    join(rows, p.iter().map(|x| x.0), ",");
                    join(rows, p.iter().map(|x| x.1), ",");
                }
                rows.end_row();
            }
            ListingPart::Csv { row, out } => {
                row.clear();
                row.cell(&t.id);
                row.cell(t.kind.as_str());
                row.cell(&prog.files[t.origin.file]);
                let _ = write!(row.text(), "{}", t.origin.pos.line);
                row.end_cell();
                let _ = write!(row.text(), "{}", t.origin.pos.col);
                row.end_cell();
                match &t.value {
                    Some(v) => {
                        for x in v.trans.iter().chain(&v.rot).chain(&v.robconf) {
                            num(row.text(), x, src);
                            row.end_cell();
                        }
                    }
                    None => {
                        for _ in 0..11 {
                            row.cell("");
                        }
                    }
                }
                let p = pairs(t, uses);
                let first = p.first().copied().unwrap_or_default();
                row.cell(first.0);
                row.cell(first.1);
                row.cell(t.instruction.as_deref().unwrap_or(""));
                row.cell(&t.origin.module);
                row.cell(t.origin.routine.as_deref().unwrap_or(""));
                match &t.derived {
                    Some(d) => {
                        join(row, d.bases.iter().map(String::as_str), " ");
                        row.cell(&d.expr);
                    }
                    None => {
                        row.cell("");
                        row.cell("");
                    }
                }
                eulers(row, t);
                for (k, (tool, wobj)) in p.iter().enumerate() {
                    let _ = write!(row.text(), "{}{tool}/{wobj}", if k > 0 { " " } else { "" });
                }
                row.end_cell();
                let _ = write!(row.text(), "{}", moves(t, uses));
                row.end_cell();
                row.end_row();
                // Writing to a Vec cannot fail.
                let _ = out.write_record(row.row(0));
            }
            ListingPart::Json { out, items } => {
                let item = json_item(prog, t, uses);
                let text = crate::report::json::to_string(&item).unwrap_or_default();
                if *items > 0 {
                    out.extend_from_slice(b",\n");
                }
                for (k, line) in text.split('\n').enumerate() {
                    if k > 0 {
                        out.push(b'\n');
                    }
                    out.extend_from_slice(b"    ");
                    out.extend_from_slice(line.as_bytes());
                }
                *items += 1;
            }
        }
    }

    /// Write the listing of the rows of `parts`, in order.
    pub fn finish(&self, parts: Vec<ListingPart>, out: &mut dyn Write) -> std::io::Result<()> {
        match self.format {
            ListFormat::Table => {
                let mut tables = Vec::with_capacity(parts.len());
                let (mut several, mut unused) = (false, false);
                for p in parts {
                    if let ListingPart::Table {
                        rows,
                        several_pairs,
                        unused: u,
                    } = p
                    {
                        several |= several_pairs;
                        unused |= u;
                        tables.push(rows);
                    }
                }
                let mut align = vec![Align::Left, Align::Left, Align::Left];
                align.extend([Align::Right; 10]);
                align.extend([Align::Left; 3]);
                write_table(out, &TABLE_HEADER, &align, &tables)?;
                if tables.iter().any(|t| !t.is_empty()) {
                    out.write_all(LEGEND.as_bytes())?;
                }
                if several {
                    out.write_all(LEGEND_PAIRS.as_bytes())?;
                }
                if unused {
                    out.write_all(LEGEND_UNUSED.as_bytes())?;
                }
            }
            ListFormat::Csv => {
                out.write_all(render_csv(&CSV_HEADER, &[]).as_bytes())?;
                for p in parts {
                    if let ListingPart::Csv { out: w, .. } = p {
                        out.write_all(&(*w).into_inner().unwrap_or_default())?;
                    }
                }
            }
            ListFormat::Json => {
                let mut first = true;
                for p in parts {
                    if let ListingPart::Json { out: text, items } = p {
                        if items == 0 {
                            continue;
                        }
                        if first {
                            let schema = crate::report::json::schema_name("targets");
                            write!(out, "{{\n  \"schema\": \"{schema}\",\n  \"targets\": [\n")?;
                        } else {
                            out.write_all(b",\n")?;
                        }
                        out.write_all(&text)?;
                        first = false;
                    }
                }
                if first {
                    let empty: [u8; 0] = [];
                    let doc = crate::report::json::rows("targets", "targets", &empty[..]);
                    out.write_all(doc.unwrap_or_default().as_bytes())?;
                } else {
                    out.write_all(b"\n  ]\n}\n")?;
                }
            }
        }
        Ok(())
    }
}

/// The RX, RY, RZ cells of a target (empty without numbers).
fn eulers(rows: &mut Rows, t: &Target) {
    match euler(t) {
        Some(e) => {
            for a in e {
                shortest_to_4_places(rows.text(), a);
                rows.end_cell();
            }
        }
        None => {
            for _ in 0..3 {
                rows.cell("");
            }
        }
    }
}

/// One cell of `parts` joined by `sep`.
fn join<'a>(rows: &mut Rows, parts: impl Iterator<Item = &'a str>, sep: &str) {
    for (k, p) in parts.enumerate() {
        if k > 0 {
            rows.text().push_str(sep);
        }
        rows.text().push_str(p);
    }
    rows.end_cell();
}

/// The JSON object of one target.
fn json_item(prog: &Program, t: &Target, uses: &[Use]) -> serde_json::Value {
    let v = t.value.as_ref();
    let p = pairs(t, uses);
    let first = p.first();
    let use_json = |tool: &str, wobj: &str, instruction: &str, routine, line| {
        serde_json::json!({
            "tool": tool,
            "wobj": wobj,
            "instruction": instruction,
            "routine": routine,
            "line": line,
        })
    };
    let mut listed: Vec<serde_json::Value> = uses
        .iter()
        .map(|u| use_json(u.tool, u.wobj, u.instruction, Some(u.routine), u.line))
        .collect();
    // A derived target written in a move: that move.
    if let (true, Some(instruction), Some((tool, wobj))) =
        (listed.is_empty(), t.instruction.as_deref(), first)
    {
        listed.push(use_json(
            tool,
            wobj,
            instruction,
            t.origin.routine.as_deref(),
            t.origin.pos.line,
        ));
    }
    serde_json::json!({
        "target": t.id,
        "kind": t.kind.as_str(),
        "file": prog.files[t.origin.file],
        "line": t.origin.pos.line,
        "col": t.origin.pos.col,
        "module": &*t.origin.module,
        "routine": t.origin.routine.as_deref(),
        "trans": v.map(|v| v.trans_values()),
        "rot": v.map(|v| v.rot_values()),
        "euler_zyx_deg": euler(t).map(|e| e.map(|a| (a * 1e9).round() / 1e9)),
        "robconf": v.map(|v| v.robconf_values()),
        "extax": v.map(|v| v.extax_values()),
        "instruction": t.instruction.as_deref(),
        "tool": first.map(|f| f.0),
        "wobj": first.map(|f| f.1),
        "frames": p.iter().map(|(t, w)| serde_json::json!({"tool": t, "wobj": w})).collect::<Vec<_>>(),
        "uses": listed,
        "derived": t.derived.as_ref().map(|d| serde_json::json!({
            "expression": d.expr,
            "function": d.function,
            "bases": d.bases,
        })),
    })
}

/// How many move instructions reach a target (a derived target written
/// in a move: its own).
fn moves(t: &Target, uses: &[Use]) -> usize {
    match uses.len() {
        0 => usize::from(t.instruction.is_some()),
        n => n,
    }
}

/// What the table's columns mean, under it.
const LEGEND: &str = "frame: x_mm, y_mm, z_mm and q1..q4 are the TCP in the object frame of the row's wobj; rx_deg, ry_deg, rz_deg are q1..q4 as RobotStudio's Euler ZYX (R = Rz·Ry·Rx)\n";
const LEGEND_PAIRS: &str = "several tools or work objects: the pairs in the order the program first uses them, tool and wobj lists matching place by place; `rapidtherm correct` corrects the target for the first\n";
const LEGEND_UNUSED: &str = "-: no move instruction reaches the target\n";

/// The listing of one program's jointtargets.
pub fn joints(prog: &Program, format: ListFormat) -> String {
    let header = [
        "target", "kind", "file", "line", "col", "j1", "j2", "j3", "j4", "j5", "j6", "tool", "wobj",
    ];
    let opt = |s: &Option<std::sync::Arc<str>>| s.as_deref().unwrap_or("").to_string();
    let rows: Vec<Vec<String>> = prog
        .jointtargets()
        .iter()
        .map(|j| {
            let mut r = vec![
                j.id.clone(),
                j.kind.as_str().to_string(),
                prog.files[j.origin.file].clone(),
                j.origin.pos.line.to_string(),
                j.origin.pos.col.to_string(),
            ];
            r.extend(j.robax.iter().map(|x| n(x.value)));
            r.push(opt(&j.tool));
            r.push(opt(&j.wobj));
            r
        })
        .collect();
    match format {
        ListFormat::Table => {
            let mut align = vec![Align::Left; 5];
            align.extend([Align::Right; 6]);
            align.extend([Align::Left; 2]);
            let mut table_header = header;
            table_header[5..11]
                .copy_from_slice(&["j1_deg", "j2_deg", "j3_deg", "j4_deg", "j5_deg", "j6_deg"]);
            render_table(&table_header, &align, &rows)
        }
        ListFormat::Csv => render_csv(&header, &rows),
        ListFormat::Json => {
            let items: Vec<serde_json::Value> = prog
                .jointtargets()
                .iter()
                .map(|j| {
                    serde_json::json!({
                        "target": j.id,
                        "kind": j.kind.as_str(),
                        "file": prog.files[j.origin.file],
                        "line": j.origin.pos.line,
                        "col": j.origin.pos.col,
                        "robax": j.robax.iter().map(|x| x.value).collect::<Vec<_>>(),
                        "extax": j.extax.iter().map(|x| x.value).collect::<Vec<_>>(),
                        "instruction": j.instruction.as_deref(),
                        "tool": j.tool.as_deref(),
                        "wobj": j.wobj.as_deref(),
                    })
                })
                .collect();
            crate::report::json::rows("targets-joints", "jointtargets", &items).unwrap_or_default()
        }
    }
}
