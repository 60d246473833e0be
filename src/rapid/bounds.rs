//! An array indexed by a number outside its declared size (`pA{5}` of a
//! `CONST robtarget pA{2}`): RAPID stops there with ERR_OUTOFBND ("array
//! index out of bounds"), so the program cannot mean it. Where both the
//! index and the size are written as numbers, the reader refuses it at
//! the index, rather than letting it pass as a target "the run fills".
//! An index computed at run time is the run's to check.

use super::syntax::{DataDecl, Expr, Module, Routine, Statement};
use super::visit::{walk_expr, walk_module, walk_routine, walk_statement, Visit};
use super::Program;
use crate::error::{Error, Location, Result};

/// The declared sizes of an array, where each is written as a number.
fn sizes(d: &DataDecl) -> Option<Vec<u64>> {
    if d.dims.is_empty() {
        return None;
    }
    d.dims.iter().map(literal_index).collect()
}

/// A number written as a whole number (an index or a size).
fn literal_index(e: &Expr) -> Option<u64> {
    let v = e.as_num()?;
    if !(v.is_finite() && v.fract() == 0.0 && v.abs() < 1e15) {
        return None;
    }
    // A negative index is outside every array: counted as 0.
    Some(if v < 0.0 { 0 } else { v as u64 })
}

/// An array's declared sizes, and where it is declared (file, line)
/// where the program's data say.
type Declared = (Vec<u64>, Option<(usize, u32)>);

struct Bounds<'p> {
    program: &'p Program,
    module: Option<&'p Module>,
    routine: Option<&'p Routine>,
    statement: Option<&'p Statement>,
    /// The lane's arrays of robtarget literals, by lower-case name: their
    /// size (made only when an index names no declaration here).
    lane: Option<std::collections::HashMap<String, u64>>,
    errors: Vec<Error>,
}

impl<'p> Bounds<'p> {
    /// The declared sizes of `name` as the place being read sees it: the
    /// routine's data, then the module's, then any module's.
    fn declared(&mut self, name: &str) -> Option<Declared> {
        let same = |d: &&DataDecl| d.name.eq_ignore_ascii_case(name);
        let here = self.module.map_or(0, |m| m.file);
        let found = self
            .routine
            .and_then(|r| r.data.iter().find(same))
            .or_else(|| self.module.and_then(|m| m.data.iter().find(same)))
            .map(|d| (d, here))
            .or_else(|| {
                let mut all = (self.program.modules.iter())
                    .flat_map(|m| m.data.iter().filter(same).map(|d| (d, m.file)));
                let one = all.next()?;
                // LOCAL data of two modules: which one is read is the
                // module's question, not guessed here.
                all.next().is_none().then_some(one)
            });
        if let Some((d, file)) = found {
            return sizes(d).map(|s| (s, Some((file, d.pos.line))));
        }
        let lane = self.lane.get_or_insert_with(|| {
            let index = self.program.target_index(|_| true);
            let mut out = std::collections::HashMap::new();
            for t in self.program.targets().iter() {
                if let Some((prefix, _)) = t.id.split_once('{') {
                    let key = prefix.to_ascii_lowercase();
                    if let std::collections::hash_map::Entry::Vacant(slot) = out.entry(key) {
                        if let Some((_, len)) = index.array(slot.key()) {
                            slot.insert(len as u64);
                        }
                    }
                }
            }
            out
        });
        lane.get(&name.to_ascii_lowercase())
            .map(|&n| (vec![n], None))
    }

    fn check(&mut self, name: &str, indices: &[Expr]) {
        let Some(idx) = indices
            .iter()
            .map(literal_index)
            .collect::<Option<Vec<u64>>>()
        else {
            return;
        };
        let Some((sizes, line)) = self.declared(name) else {
            return;
        };
        if sizes.len() != idx.len() {
            return;
        }
        let Some(k) = (0..idx.len()).find(|&k| idx[k] == 0 || idx[k] > sizes[k]) else {
            return;
        };
        let (Some(m), Some(s)) = (self.module, self.statement) else {
            return;
        };
        let src = self.program.source(m.file);
        let file = self.program.file_name(m.file);
        let at = index_place(src, s.pos.offset, name).unwrap_or(s.pos.offset);
        let written: Vec<String> = idx.iter().map(u64::to_string).collect();
        let size: Vec<String> = sizes.iter().map(u64::to_string).collect();
        let declared = match line {
            None => String::new(),
            Some((f, l)) => format!(" at {}:{l}", self.program.file_name(f)),
        };
        self.errors.push(
            Error::input(format!(
                "{name}{{{}}} is out of bounds: {name} is declared {name}{{{}}}{declared}, and index {} of {} is {} (RAPID stops here: ERR_OUTOFBND)",
                written.join(","),
                size.join(","),
                k + 1,
                idx.len(),
                idx[k]
            ))
            .at(Location::from_offset(file, src, at)),
        );
    }
}

/// Where `name{` stands in the statement starting at `from` (its first
/// such place), for the message's column.
fn index_place(src: &[u8], from: usize, name: &str) -> Option<usize> {
    let end = (from + (1 << 16)).min(src.len());
    let hay = &src[from.min(end)..end];
    let n = name.len();
    (0..hay.len().saturating_sub(n)).find_map(|i| {
        let word = hay.get(i..i + n)?;
        let before_ok = i == 0 || !(hay[i - 1].is_ascii_alphanumeric() || hay[i - 1] == b'_');
        let rest = hay[i + n..].iter().position(|b| !b" \t".contains(b))?;
        (before_ok && word.eq_ignore_ascii_case(name.as_bytes()) && hay[i + n + rest] == b'{')
            .then_some(from + i)
    })
}

impl<'p> Visit<'p> for Bounds<'p> {
    fn program(&self) -> Option<&'p Program> {
        Some(self.program)
    }
    fn visit_module(&mut self, m: &'p Module) {
        self.module = Some(m);
        self.routine = None;
        walk_module(self, m);
    }
    fn visit_routine(&mut self, r: &'p Routine) {
        self.routine = Some(r);
        walk_routine(self, r);
        self.routine = None;
    }
    fn visit_data_decl(&mut self, _: &'p DataDecl) {}
    fn visit_statement(&mut self, s: &'p Statement) {
        let outer = self.statement.replace(s);
        walk_statement(self, s);
        self.statement = outer;
    }
    fn visit_expr(&mut self, e: &'p Expr) {
        if let Expr::Index(b) = e {
            if let Expr::Name(n) = &b.0 {
                self.check(n, &b.1);
            }
        }
        walk_expr(self, e);
    }
}

/// Every index of a declared array that lies outside it, as one error.
pub(crate) fn refuse_out_of_bounds(program: &Program) -> Result<()> {
    let mut b = Bounds {
        program,
        module: None,
        routine: None,
        statement: None,
        lane: None,
        errors: Vec::new(),
    };
    b.visit_program(program);
    match Error::many(b.errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
