//! One move's use of a target: the tool and work object it moves with,
//! how it reaches the target, and where the instruction is.

/// The tool and work object one motion instruction uses for a target.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Usage {
    /// How the move reaches the target.
    pub through: Through,
    pub tool: Option<String>,
    pub wobj: Option<String>,
    /// The instruction (`MoveL`) and where it is, for messages.
    pub instruction: String,
    pub routine: String,
    pub line: u32,
    /// The file (index into [`Program::files`]) and byte offset where the
    /// instruction starts, for edits of its arguments.
    pub file: usize,
    pub offset: usize,
}

impl Usage {
    /// The tool's name as written (`tool0` when the move names none).
    pub fn tool_name(&self) -> &str {
        self.tool.as_deref().unwrap_or("tool0")
    }

    /// The work object's name as written (`wobj0` when the move names
    /// none).
    pub fn wobj_name(&self) -> &str {
        self.wobj.as_deref().unwrap_or("wobj0")
    }

    /// Whether two uses move with the same tool and work object (by name,
    /// as RAPID compares names: case-insensitively).
    pub fn same_frames(&self, other: &Usage) -> bool {
        self.tool_name().eq_ignore_ascii_case(other.tool_name())
            && self.wobj_name().eq_ignore_ascii_case(other.wobj_name())
    }
}

/// A target's uses grouped by tool and work object, in program order of
/// each pair's first use: the first group is the pair the target is
/// corrected for (see [`frames_of`]).
pub fn uses_by_frames(uses: &[Usage]) -> Vec<Vec<&Usage>> {
    let mut groups: Vec<Vec<&Usage>> = Vec::new();
    for u in uses {
        match groups.iter_mut().find(|g| g[0].same_frames(u)) {
            Some(g) => g.push(u),
            None => groups.push(vec![u]),
        }
    }
    groups
}

/// How a move reaches a target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Through {
    /// The move names it (or is written with it).
    Direct,
    /// Through a derived expression (`Offs(p10, 0, 0, 50)`): the index of
    /// that expression among the program's targets.
    Derived(usize),
    /// Through a variable the run assigns from it (`pAbove := Offs(p10,
    /// ...); MoveL pAbove`): the pose is decided at run time.
    Variable,
}
