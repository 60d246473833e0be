//! The names the run-time module adds to a task, and whether a task can
//! take them. The module declares five global routines, all named from
//! the module's name N ([`public_names`]); everything else in it is
//! LOCAL. A name RAPID itself gives meaning to (a reserved word, an
//! instruction, a function, a data type, a predefined datum: the embedded
//! `data/rapid/names.toml`, with the manual it is from) cannot be one of
//! them ([`check_module_name`]), and neither can a name the program
//! already declares ([`check_program_names`]): either way the task would
//! not load, or a move would call something else than the module.

use crate::error::{Error, Errors, Result};
use crate::rapid::Program;
use std::collections::HashMap;
use std::sync::OnceLock;

/// The longest RAPID name (RAPID kernel manual, "Identifiers").
const MAX_RAPID_NAME: usize = 32;

/// The longest module name: its longest public name, `NReset`, is a
/// RAPID name too.
pub const MAX_MODULE_NAME: usize = MAX_RAPID_NAME - "Reset".len();

/// The five global routines of the module named `module`, in the order
/// the module declares them: the robtarget and jointtarget functions of
/// the slow path, those of the table, and the operator's reset.
pub fn public_names(module: &str) -> [String; 5] {
    ["", "J", "T", "JT", "Reset"].map(|s| format!("{module}{s}"))
}

/// What RAPID means by a name of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Meaning {
    Reserved,
    Keyword,
    Instruction,
    Function,
    DataType,
    Predefined,
}

impl Meaning {
    fn describe(self) -> &'static str {
        match self {
            Meaning::Reserved => "a RAPID reserved word",
            Meaning::Keyword => "a keyword of RAPID's declarations",
            Meaning::Instruction => "a RAPID instruction",
            Meaning::Function => "a RAPID function",
            Meaning::DataType => "a RAPID data type",
            Meaning::Predefined => "a datum RAPID predefines",
        }
    }
}

#[derive(serde::Deserialize)]
struct NamesFile {
    reserved: Vec<String>,
    keywords: Vec<String>,
    instructions: Vec<String>,
    functions: Vec<String>,
    data_types: Vec<String>,
    predefined: Vec<String>,
}

const NAMES_TOML: &str = include_str!("../../../data/rapid/names.toml");

fn names_file() -> Option<NamesFile> {
    toml::from_str(NAMES_TOML).ok()
}

/// Every name of the file by lower-case name: what it means, and how the
/// manual writes it.
fn table() -> &'static HashMap<String, (Meaning, String)> {
    static TABLE: OnceLock<HashMap<String, (Meaning, String)>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut out = HashMap::new();
        // The file is part of the build, read by the tests below.
        let Some(f) = names_file() else {
            return out;
        };
        for (meaning, list) in [
            (Meaning::Reserved, f.reserved),
            (Meaning::Keyword, f.keywords),
            (Meaning::Instruction, f.instructions),
            (Meaning::Function, f.functions),
            (Meaning::DataType, f.data_types),
            (Meaning::Predefined, f.predefined),
        ] {
            for name in list {
                // A name of two lists keeps the first (a reserved word
                // before an instruction of that name).
                out.entry(name.to_ascii_lowercase())
                    .or_insert((meaning, name));
            }
        }
        out
    })
}

/// What RAPID means by `name` (any case), as the manual writes the name:
/// `None` for a name RAPID leaves to programs.
fn meaning_of(name: &str) -> Option<&'static (Meaning, String)> {
    table().get(&name.to_ascii_lowercase())
}

/// Whether `name` is a RAPID name: a letter, then letters, digits or `_`.
fn is_rapid_name(name: &str) -> bool {
    name.bytes().next().is_some_and(|b| b.is_ascii_alphabetic())
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

/// Whether `name` can name the module: a RAPID name of at most
/// [`MAX_MODULE_NAME`] characters none of whose public names RAPID
/// itself gives meaning to, and not `main`. A usage error naming the word
/// and why otherwise, raised while the plan is made, before anything is
/// read.
pub fn check_module_name(name: &str) -> Result<()> {
    let flag = format!("--runtime-module `{name}`");
    if !is_rapid_name(name) {
        return Err(Error::usage(format!(
            "{flag}: not a RAPID name (a letter, then letters, digits or _)"
        )));
    }
    if name.len() > MAX_MODULE_NAME {
        return Err(Error::usage(format!(
            "{flag}: {} characters, at most {MAX_MODULE_NAME}: the module's routine {name}Reset must be a RAPID name of at most {MAX_RAPID_NAME}",
            name.len()
        )));
    }
    if name.eq_ignore_ascii_case("main") {
        // A task's program starts at its procedure `main` (RAPID
        // overview, "Program structure"); the module's first function
        // would be a global FUNC of that name.
        return Err(Error::usage(format!(
            "{flag}: a program starts at its procedure main, and the module would declare a global function {name}: the task would not load"
        )));
    }
    for public in public_names(name) {
        if let Some((meaning, word)) = meaning_of(&public) {
            let whose = if public == name {
                "the module's correcting function".to_string()
            } else {
                format!("the module's routine {public}")
            };
            return Err(Error::usage(format!(
                "{flag}: {whose} would be named {word}, {}: choose another name",
                meaning.describe()
            )));
        }
    }
    Ok(())
}

/// Whether `m` is a module a former run wrote for `module` (loaded with
/// the task it corrects, as a backup's SYSMOD holds it): its own names
/// are no clash.
pub fn is_written_module(program: &Program, m: &crate::rapid::Module, module: &str) -> bool {
    m.name.eq_ignore_ascii_case(module)
        && std::str::from_utf8(program.source(m.file))
            .is_ok_and(|s| s.contains("! Written by rapidtherm"))
}

/// Refuses a program that already declares a module, routine, datum,
/// parameter or record type named like one of the module's public names:
/// a second global of one name, or a local one hiding the module's from
/// the moves of its module or routine, and the task would not load or
/// would call something else. An input error at each such declaration.
pub fn check_program_names(program: &Program, module: &str) -> Result<()> {
    let public = public_names(module);
    let clash = |name: &str| public.iter().find(|p| p.eq_ignore_ascii_case(name));
    let mut errors = Errors::default();
    let mut refuse = |file: usize, pos: crate::rapid::Pos, what: &str, name: &str, p: &str| {
        errors.push(Error::input_at(
            program.file_name(file),
            pos.line as usize,
            pos.col as usize,
            format!(
                "the program already declares {what} {name}, and --runtime-module {module} adds the global routine {p}: the task would not load; choose another --runtime-module"
            ),
        ));
    };
    for m in &program.modules {
        if is_written_module(program, m, module) {
            continue;
        }
        if let Some(p) = clash(&m.name) {
            refuse(m.file, m.pos, "a module", &m.name, p);
        }
        for d in program.module_data(m) {
            if let Some(p) = clash(&d.name) {
                refuse(m.file, d.pos, "the datum", &d.name, p);
            }
        }
        for r in &m.records {
            if let Some(p) = clash(&r.name) {
                refuse(m.file, r.pos, "the record type", &r.name, p);
            }
        }
        for (_, alias) in &m.aliases {
            if let Some(p) = clash(alias) {
                refuse(m.file, m.pos, "the alias type", alias, p);
            }
        }
        for r in &m.routines {
            if let Some(p) = clash(&r.name) {
                refuse(m.file, r.pos, "the routine", &r.name, p);
            }
            for a in &r.params {
                if let Some(p) = clash(&a.name) {
                    let what = format!("a parameter of {}:", r.name);
                    refuse(m.file, r.pos, &what, &a.name, p);
                }
            }
            for d in &r.data {
                if let Some(p) = clash(&d.name) {
                    let what = format!("in {} the datum", r.name);
                    refuse(m.file, d.pos, &what, &d.name, p);
                }
            }
        }
    }
    match errors.into_error(|n| {
        Error::input(format!(
            "{n} declarations of the program are named like the routines --runtime-module {module} adds; the task would not load"
        ))
    }) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn program(src: &str) -> Program {
        crate::rapid::parse("t.mod", src.as_bytes()).unwrap()
    }

    fn usage(name: &str) -> String {
        let e = check_module_name(name).unwrap_err();
        assert_eq!(e.kind, crate::error::ErrorKind::Usage, "{name}");
        e.message.clone()
    }

    #[test]
    fn the_five_public_names() {
        assert_eq!(
            public_names("ThWarm"),
            ["ThWarm", "ThWarmJ", "ThWarmT", "ThWarmJT", "ThWarmReset"]
        );
    }

    #[test]
    fn the_file_reads_and_holds_the_manuals_names() {
        let f = names_file().expect("data/rapid/names.toml reads");
        let lower =
            |v: &[String]| -> Vec<String> { v.iter().map(|s| s.to_ascii_lowercase()).collect() };
        let has = |v: &[String], n: &str| lower(v).contains(&n.to_ascii_lowercase());
        // Instructions and functions of the reference manual.
        for n in [
            "MoveL", "MoveJ", "MoveAbsJ", "SearchL", "TPWrite", "ErrWrite",
        ] {
            assert!(has(&f.instructions, n), "{n}");
        }
        for n in [
            "CalcJointT",
            "CalcRobT",
            "CRobT",
            "CJointT",
            "Offs",
            "CDate",
        ] {
            assert!(has(&f.functions, n), "{n}");
        }
        for n in ["robtarget", "jointtarget", "tooldata", "num", "pose"] {
            assert!(has(&f.data_types, n), "{n}");
        }
        for n in ["tool0", "wobj0", "load0", "fine", "z50", "v100", "vmax"] {
            assert!(has(&f.predefined, n), "{n}");
        }
        // The program's entry routine is the program's, not RAPID's.
        assert_eq!(meaning_of("main"), None);
        assert_eq!(meaning_of("RtWarm"), None);
        // The kernel manual's reserved words, UNDO among them.
        for n in ["UNDO", "RECORD", "ENDRECORD", "ALIAS", "XOR"] {
            assert!(has(&f.reserved, n), "{n}");
        }
        // Each one a word the grammar will not take as a datum's name.
        for w in &f.reserved {
            let text = format!("MODULE M\n  VAR num {w} := 1;\nENDMODULE\n");
            assert!(
                crate::rapid::parse("t.mod", text.as_bytes()).is_err(),
                "{w}"
            );
        }
    }

    #[test]
    fn every_listed_name_is_a_rapid_name_listed_once() {
        let f = names_file().unwrap();
        let all: Vec<&String> = [
            &f.reserved,
            &f.keywords,
            &f.instructions,
            &f.functions,
            &f.data_types,
            &f.predefined,
        ]
        .into_iter()
        .flatten()
        .collect();
        let mut seen = std::collections::HashSet::new();
        for n in &all {
            assert!(is_rapid_name(n) && n.len() <= MAX_RAPID_NAME, "{n}");
            assert!(seen.insert(n.to_ascii_lowercase()), "{n} is listed twice");
        }
        assert_eq!(table().len(), all.len());
    }

    #[test]
    fn names_rapid_gives_meaning_to_are_refused_any_case() {
        assert!(usage("MoveL").contains("MoveL, a RAPID instruction"));
        assert!(usage("movel").contains("MoveL, a RAPID instruction"));
        assert!(usage("tool0").contains("tool0, a datum RAPID predefines"));
        assert!(usage("CRobT").contains("CRobT, a RAPID function"));
        assert!(usage("robtarget").contains("a RAPID data type"));
        assert!(usage("IF").contains("a RAPID reserved word"));
        assert!(usage("Task").contains("keyword"));
        // Worked by hand: each name is free, but one routine it adds is
        // RAPID's: Move+J = MoveJ, Search+J = SearchJ, Trigg+J = TriggJ,
        // Clk+Reset = ClkReset, Tune+Reset = TuneReset.
        for (n, word) in [
            ("Move", "MoveJ"),
            ("Search", "SearchJ"),
            ("Trigg", "TriggJ"),
            ("Clk", "ClkReset"),
            ("Tune", "TuneReset"),
        ] {
            let m = usage(n);
            assert!(
                m.contains(&format!("routine {word} would be named {word}")),
                "{m}"
            );
        }
    }

    #[test]
    fn form_and_length() {
        assert!(usage("9Warm").contains("not a RAPID name"));
        assert!(usage("Rt-Warm").contains("not a RAPID name"));
        assert!(usage("").contains("not a RAPID name"));
        // 27 characters: RtWarm...Reset is 32, RAPID's longest name.
        let longest = "R".repeat(27);
        assert!(check_module_name(&longest).is_ok());
        assert_eq!(public_names(&longest)[4].len(), 32);
        assert!(usage(&"R".repeat(28)).contains("at most 27"));
        assert!(check_module_name("RtWarm").is_ok());
        assert!(check_module_name("ThWarm").is_ok());
        assert!(check_module_name("Th_Warm2").is_ok());
    }

    #[test]
    fn main_is_the_programs_not_a_module_name() {
        assert!(usage("main").contains("procedure main"));
        assert!(usage("MAIN").contains("procedure main"));
        // A program declaring main is fine under another module name.
        let p = program("MODULE MainModule\nPROC main()\nENDPROC\nENDMODULE\n");
        assert!(check_program_names(&p, "RtWarm").is_ok());
        // Under the name main it clashes with the program's entry.
        let e = check_program_names(&p, "main").unwrap_err();
        assert!(e.message.contains("the routine main"), "{}", e.message);
    }

    #[test]
    fn declarations_named_like_a_public_name_are_refused_where_they_stand() {
        let src = "MODULE Cell\n  PERS num rtwarmt := 0;\n  PROC main()\n    VAR robtarget RtWarmJ;\n  ENDPROC\n  LOCAL FUNC num RTWARMRESET()\n    RETURN 0;\n  ENDFUNC\nENDMODULE\n";
        let e = check_program_names(&program(src), "RtWarm").unwrap_err();
        assert_eq!(e.kind, crate::error::ErrorKind::Input);
        let all: Vec<&Error> = std::iter::once(&e).chain(e.related()).collect();
        let at: Vec<(usize, String)> = all
            .iter()
            .filter_map(|e| e.location.as_ref())
            .map(|l| (l.line, l.file.clone()))
            .collect();
        assert_eq!(
            at,
            [
                (2, "t.mod".into()),
                (4, "t.mod".into()),
                (6, "t.mod".into())
            ]
        );
        let text: String = all.iter().map(|e| e.message.clone()).collect();
        for n in ["rtwarmt", "RtWarmJ", "RTWARMRESET"] {
            assert!(text.contains(n), "{n}: {text}");
        }
    }

    #[test]
    fn a_module_of_the_name_is_refused_unless_a_former_run_wrote_it() {
        let theirs = program("MODULE RtWarm\nENDMODULE\n");
        let e = check_program_names(&theirs, "rtwarm").unwrap_err();
        assert!(e.message.contains("a module RtWarm"), "{}", e.message);
        assert_eq!(e.location.as_ref().map(|l| l.line), Some(1));
        let ours = program(
            "MODULE RtWarm(SYSMODULE,NOSTEPIN)\n  ! Written by rapidtherm 0.1.0 for the IRB 140\n  FUNC robtarget RtWarm(robtarget p)\n    RETURN p;\n  ENDFUNC\nENDMODULE\n",
        );
        assert!(check_program_names(&ours, "RtWarm").is_ok());
        // A module named like another public name is a clash all the same.
        let j = program("MODULE RtWarmJ\nENDMODULE\n");
        assert!(check_program_names(&j, "RtWarm").is_err());
        // Names beside the public ones are free: the module's own are LOCAL.
        let free =
            program("MODULE Cell\n  PERS num rtX := 0;\n  PROC RtWarmUp()\n  ENDPROC\nENDMODULE\n");
        assert!(check_program_names(&free, "RtWarm").is_ok());
    }
}
