//! Why the fast lane left a statement to the grammar after it began to
//! read it (a motion instruction it knows, a robtarget or jointtarget
//! declaration): a typed reason, counted per run (`LaneTally`) and said
//! with `-v`, so that a program that reads slowly says why. A statement
//! the lane does not cover at all (an IF, an assignment, a MoveAbsJ) is
//! no decline: it is the grammar's from the start.

use std::collections::BTreeMap;
use std::fmt;

/// The part of a statement the lane was reading when it stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Part {
    /// Between the instruction and its first argument.
    Instruction,
    /// A move's target (a literal or a name).
    Target,
    Speed,
    Zone,
    Tool,
    /// An optional argument (`\WObj:=`, or another).
    OptionalArgument,
    /// The work object named by `\WObj:=`.
    WorkObject,
    /// The `;` that ends the statement.
    End,
    /// A declaration's name.
    Name,
    /// An array declaration's size.
    ArraySize,
    /// A declaration's value.
    Value,
}

/// What the lane found where it stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum StoppedAt {
    /// A `!` comment inside the statement.
    Comment,
    /// A string literal.
    Text,
    /// A line break inside a statement that is not an array's value.
    LineBreak,
    /// A byte above 0x7F (Latin-1 or UTF-8 text).
    NonAscii,
    /// A reserved word where a name goes.
    ReservedWord,
    /// A name where a number goes (a named constant).
    Name,
    /// A number whose form or size the lane does not read (more than 60
    /// digits, a long exponent, a value beyond `f64`).
    Number,
    /// A character the lane does not read there (an operator, a bracket
    /// of an index or a call, another optional argument's `\`).
    Char(u8),
    /// The end of the file.
    EndOfText,
}

/// Why the lane left a statement it began to the grammar.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Decline {
    /// It found something it does not read in a part of the statement.
    At(Part, StoppedAt),
    /// An optional argument other than `\WObj`.
    OtherOptional,
    /// An array of jointtargets (the lane reads robtarget arrays only).
    JointtargetArray,
    /// A statement longer than a run's offsets hold (64 KiB).
    TooLong,
    /// More distinct speed, zone, tool and work object names than a run's
    /// table holds (65,535).
    TooManyNames,
    /// A file larger than a run's offsets hold (4 GiB).
    FileTooLarge,
}

impl fmt::Display for Part {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Part::Instruction => "after the instruction",
            Part::Target => "in the target",
            Part::Speed => "in the speed",
            Part::Zone => "in the zone",
            Part::Tool => "in the tool",
            Part::OptionalArgument => "in an optional argument",
            Part::WorkObject => "in the work object",
            Part::End => "before the end",
            Part::Name => "in the name",
            Part::ArraySize => "in the array's size",
            Part::Value => "in the value",
        })
    }
}

impl fmt::Display for StoppedAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StoppedAt::Comment => f.write_str("a comment"),
            StoppedAt::Text => f.write_str("a string"),
            StoppedAt::LineBreak => f.write_str("a line break"),
            StoppedAt::NonAscii => f.write_str("a byte above 0x7F"),
            StoppedAt::ReservedWord => f.write_str("a reserved word"),
            StoppedAt::Name => f.write_str("a name"),
            StoppedAt::Number => f.write_str("a number of a form or size it does not read"),
            StoppedAt::Char(c) if c.is_ascii_graphic() => write!(f, "`{}`", char::from(*c)),
            StoppedAt::Char(c) => write!(f, "`{}`", char::from(*c).escape_default()),
            StoppedAt::EndOfText => f.write_str("the end of the file"),
        }
    }
}

impl fmt::Display for Decline {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Decline::At(part, found) => write!(f, "{found} {part}"),
            Decline::OtherOptional => f.write_str("an optional argument other than \\WObj"),
            Decline::JointtargetArray => f.write_str("an array of jointtargets"),
            Decline::TooLong => f.write_str("a statement longer than 64 KiB"),
            Decline::TooManyNames => {
                f.write_str("more than 65,535 names of speeds, zones, tools and work objects")
            }
            Decline::FileTooLarge => f.write_str("a file larger than 4 GiB"),
        }
    }
}

/// What the lane left to the grammar for one reason: how many statements,
/// and where the first was (a file's index in the run, its line).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Declined {
    pub count: usize,
    pub file: usize,
    pub line: u32,
}

/// What the lane did in one run: how many statements it read (and how
/// many of those it read ahead of the parse, on every core), and those it
/// began and left to the grammar, by reason.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LaneTally {
    pub read: usize,
    pub ahead: usize,
    pub declined: BTreeMap<Decline, Declined>,
}

impl LaneTally {
    /// A statement declined for `why` at `line` of file `file`.
    pub fn decline(&mut self, why: Decline, file: usize, line: u32) {
        self.declined
            .entry(why)
            .or_insert(Declined {
                count: 0,
                file,
                line,
            })
            .count += 1;
    }

    /// How many statements it declined, for every reason.
    pub fn declined_count(&self) -> usize {
        self.declined.values().map(|d| d.count).sum()
    }
}
