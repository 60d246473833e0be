//! Writes a large RAPID program of one of the three shapes large programs
//! come in, with `n` targets, CRLF line ends, a tool and a work object
//! (`cargo bench --bench correct` writes each of them for a million
//! targets; the tests write small ones):
//!
//! - `cam`: a CAM post-processor's inline moves, `MoveL [[...]],v200,z1,
//!   tSpindle\WObj:=wPlate;`, one after another in `main`;
//! - `declared`: RobotStudio's path export, `CONST robtarget
//!   Target_10:=[...];` declarations, then procedures of 1,000 moves by
//!   name (`MoveL Target_10,v1000,z1,tGlue\WObj:=wTable;`) that `main`
//!   calls in turn;
//! - `array`: a generator's one array of every target (`CONST robtarget
//!   pScan{n}:=[[...],...];`, an element a line) walked by a FOR loop.
//!
//! `cargo run --release --example gen_shapes SHAPE N > FILE`.
//!
//! Every target is reachable on the IRB 140 with the robconf written, a
//! deterministic zigzag over a 300 x 300 mm field.

use std::io::Write;

fn main() {
    let mut args = std::env::args().skip(1);
    let shape = args.next().unwrap_or_else(|| "cam".to_string());
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let out = std::io::stdout().lock();
    let mut w = std::io::BufWriter::new(out);
    let written = match Shape::named(&shape) {
        Some(s) => s.write(&mut w, n),
        None => {
            eprintln!("gen_shapes: SHAPE is cam, declared or array");
            std::process::exit(2);
        }
    };
    if written.and_then(|_| w.flush()).is_err() {
        std::process::exit(1);
    }
}

/// The three shapes of large programs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    Cam,
    Declared,
    Array,
}

impl Shape {
    pub const ALL: [Shape; 3] = [Shape::Cam, Shape::Declared, Shape::Array];

    pub fn named(name: &str) -> Option<Shape> {
        match name {
            "cam" => Some(Shape::Cam),
            "declared" => Some(Shape::Declared),
            "array" => Some(Shape::Array),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Shape::Cam => "cam",
            Shape::Declared => "declared",
            Shape::Array => "array",
        }
    }

    /// The program of this shape with `n` targets.
    pub fn write(self, w: &mut dyn Write, n: usize) -> std::io::Result<()> {
        match self {
            Shape::Cam => cam(w, n),
            Shape::Declared => declared(w, n),
            Shape::Array => array(w, n),
        }
    }
}

/// Target `i`'s position (mm) and robconf's cf1 and cf6.
fn point(i: usize) -> ([f64; 3], i32) {
    let u = (i % 1000) as f64 / 1000.0;
    let v = (i / 1000 % 1000) as f64 / 1000.0;
    let p = [
        420.0 + 80.0 * u,
        -150.0 + 300.0 * v,
        250.0 + 20.0 * (u * 7.0).sin(),
    ];
    (p, if p[1] >= 0.0 { 0 } else { -1 })
}

/// Target `i` as a robtarget literal.
fn literal(i: usize) -> String {
    let ([x, y, z], cf) = point(i);
    format!("[[{x:.3},{y:.3},{z:.3}],[0,0,1,0],[{cf},0,{cf},0],[9E9,9E9,9E9,9E9,9E9,9E9]]")
}

fn cam(w: &mut dyn Write, n: usize) -> std::io::Result<()> {
    write!(w, "MODULE Big\r\n")?;
    write!(
        w,
        "  PERS tooldata tSpindle:=[TRUE,[[0,0,150],[1,0,0,0]],[2,[0,0,60],[1,0,0,0],0,0,0]];\r\n"
    )?;
    write!(
        w,
        "  PERS wobjdata wPlate:=[FALSE,TRUE,\"\",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];\r\n"
    )?;
    write!(w, "  PROC main()\r\n")?;
    for i in 0..n {
        write!(
            w,
            "    MoveL {},v200,z1,tSpindle\\WObj:=wPlate;\r\n",
            literal(i)
        )?;
    }
    write!(w, "  ENDPROC\r\nENDMODULE\r\n")
}

/// Moves per procedure of the RobotStudio shape.
const PER_PATH: usize = 1000;

fn declared(w: &mut dyn Write, n: usize) -> std::io::Result<()> {
    write!(w, "MODULE Module1\r\n")?;
    write!(
        w,
        "    PERS tooldata tGlue:=[TRUE,[[0,0,150],[1,0,0,0]],[2,[0,0,60],[1,0,0,0],0,0,0]];\r\n"
    )?;
    write!(
        w,
        "    TASK PERS wobjdata wTable:=[FALSE,TRUE,\"\",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];\r\n"
    )?;
    for i in 0..n {
        let ([x, y, z], cf) = point(i);
        write!(
            w,
            "    CONST robtarget Target_{}:=[[{x:.3},{y:.3},{z:.3}],[0,0,1,0],[{cf},0,{cf},0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];\r\n",
            10 * (i + 1)
        )?;
    }
    let paths = n.div_ceil(PER_PATH);
    for p in 0..paths {
        write!(w, "    PROC Path_{}()\r\n", 10 * (p + 1))?;
        for i in p * PER_PATH..((p + 1) * PER_PATH).min(n) {
            write!(
                w,
                "        MoveL Target_{},v1000,z1,tGlue\\WObj:=wTable;\r\n",
                10 * (i + 1)
            )?;
        }
        write!(w, "    ENDPROC\r\n")?;
    }
    write!(w, "    PROC main()\r\n")?;
    for p in 0..paths {
        write!(w, "        Path_{};\r\n", 10 * (p + 1))?;
    }
    write!(w, "    ENDPROC\r\nENDMODULE\r\n")
}

fn array(w: &mut dyn Write, n: usize) -> std::io::Result<()> {
    write!(w, "MODULE Scan\r\n")?;
    write!(
        w,
        "  PERS tooldata tProbe:=[TRUE,[[0,0,150],[1,0,0,0]],[2,[0,0,60],[1,0,0,0],0,0,0]];\r\n"
    )?;
    write!(
        w,
        "  PERS wobjdata wPart:=[FALSE,TRUE,\"\",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];\r\n"
    )?;
    write!(w, "  CONST robtarget pScan{{{n}}}:=[\r\n")?;
    for i in 0..n {
        let sep = if i + 1 < n { "," } else { "];" };
        write!(w, "    {}{sep}\r\n", literal(i))?;
    }
    write!(w, "  PROC main()\r\n")?;
    write!(w, "    FOR i FROM 1 TO {n} DO\r\n")?;
    write!(w, "      MoveL pScan{{i}},v200,z1,tProbe\\WObj:=wPart;\r\n")?;
    write!(w, "    ENDFOR\r\n  ENDPROC\r\nENDMODULE\r\n")
}
