//! A whole run read: its files' bytes, modules, and the robot data and
//! targets collected from them.

use super::lane::LaneTally;
use super::runs::Runs;
use super::source::Source;
use super::syntax::{Module, Routine};
use super::targets::{Segment, TargetIndex, Targets};
use super::values::{
    JointTarget, Origin, SpeedData, Target, ToolData, Warning, WobjData, ZoneData,
};
use crate::error::Location;

/// A whole run: one or several files, each with one or several modules.
#[derive(Debug, Clone, Default)]
pub struct Program {
    /// File names as given to the parser.
    pub files: Vec<String>,
    /// Each file's bytes as read (see [`Program::source`]): every span of
    /// the program points into these.
    pub(crate) sources: Vec<Source>,
    pub modules: Vec<Module>,
    /// The targets held one by one (see [`Program::targets`]: with the
    /// runs', every target of the program).
    pub(crate) targets: Vec<Target>,
    /// What the fast lane read, held compactly.
    pub(crate) runs: Runs,
    /// Where each stretch of the targets' numbering is held: one by one,
    /// or in a run (empty: every target is held one by one).
    pub(crate) segments: Vec<Segment>,
    pub(crate) jointtargets: Vec<JointTarget>,
    pub(crate) tools: Vec<ToolData>,
    pub(crate) wobjs: Vec<WobjData>,
    pub(crate) speeds: Vec<SpeedData>,
    pub(crate) zones: Vec<ZoneData>,
    /// What the reader could not fully account for (not errors): for
    /// example robtargets inside a RECORD type no file of the run defines.
    pub warnings: Vec<Warning>,
    /// What the fast lane read, and what it began and left to the
    /// grammar, by reason.
    pub lane: LaneTally,
}

impl Program {
    /// The bytes file `file` (an index into [`Program::files`], as in
    /// [`Origin::file`]) was parsed from, kept so that spans can be read
    /// and rewritten without the caller holding them; empty for an index
    /// out of range.
    pub fn source(&self, file: usize) -> &[u8] {
        self.sources.get(file).map_or(&[], |s| s.bytes())
    }

    /// The name file `file` was given to the parser with; empty for an
    /// index out of range.
    pub fn file_name(&self, file: usize) -> &str {
        self.files.get(file).map_or("", String::as_str)
    }

    pub fn jointtargets(&self) -> &[JointTarget] {
        &self.jointtargets
    }
    /// Each jointtarget written as data (declared, an array's element;
    /// not an inline literal), by its identifier in lower case (names are
    /// case-insensitive), with its index in [`Program::jointtargets`]: what
    /// a move naming one finds.
    pub fn jointtargets_by_id(&self) -> impl Iterator<Item = (String, usize)> + '_ {
        self.jointtargets
            .iter()
            .enumerate()
            .filter(|(_, j)| j.kind != super::values::TargetKind::Inline)
            .map(|(i, j)| (j.id.to_ascii_lowercase(), i))
    }
    pub fn tools(&self) -> &[ToolData] {
        &self.tools
    }
    pub fn wobjs(&self) -> &[WobjData] {
        &self.wobjs
    }
    pub fn speeds(&self) -> &[SpeedData] {
        &self.speeds
    }
    pub fn zones(&self) -> &[ZoneData] {
        &self.zones
    }

    /// The target with this identifier (names compared without regard to
    /// case, as RAPID does).
    pub fn target(&self, id: &str) -> Option<Target> {
        self.targets()
            .iter()
            .find(|t| t.id.eq_ignore_ascii_case(id))
            .map(std::borrow::Cow::into_owned)
    }

    /// The routine with this name (first module that has it).
    pub fn routine(&self, name: &str) -> Option<(&Module, &Routine)> {
        self.modules.iter().find_map(|m| {
            m.routines
                .iter()
                .find(|r| r.name.eq_ignore_ascii_case(name))
                .map(|r| (m, r))
        })
    }

    /// A value's place as an error [`Location`] (without the line text).
    pub fn location(&self, origin: &Origin) -> Location {
        Location {
            file: self.files.get(origin.file).cloned().unwrap_or_default(),
            line: origin.pos.line as usize,
            col: origin.pos.col as usize,
            line_text: Box::default(),
        }
    }

    /// Every robtarget, in file and source order: those the fast lane
    /// read into runs too, made when asked for.
    pub fn targets(&self) -> Targets<'_> {
        Targets {
            one_by_one: &self.targets,
            runs: &self.runs,
            segments: &self.segments,
            sources: &self.sources,
        }
    }

    /// The program's targets by identifier (compared without regard to
    /// case): those held one by one that `keep` keeps, and every declared
    /// target and array element of the runs.
    pub fn target_index(&self, keep: impl Fn(&Target) -> bool) -> TargetIndex<'_> {
        TargetIndex::new(self.targets(), keep)
    }
}
