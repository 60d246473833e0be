//! Robtarget literals written with named constants or expressions
//! (`[[nX,0,300],...]`, `[[400,0,-300+600],...]`). They are values the
//! controller computes before the run, but not numbers that can be edited
//! one by one: they are reported and left alone, unless the run is asked
//! to write numbers in their place, and then the position (and the
//! orientation, if it turns) is written as a literal of numbers.

use super::outcome::{leave, Kind, LeftAlone, Reason};
use crate::error::Result;
use crate::rapid::constants::{names_read, Constants, Site};
use crate::rapid::rewrite::{format_like, Edit, POSITION_RESOLUTION, QUATERNION_RESOLUTION};
use crate::rapid::visit::{walk_expr, Visit};
use crate::rapid::{Aggregate, Expr, Program, Target};
use crate::resolve::robconf_of;
use crate::robot::conf::RobConf;
use crate::robot::frames::pose_from_rapid;
use nalgebra::Isometry3;
use std::collections::HashMap;
use std::ops::Range;

/// The program's robtarget-shaped aggregates, by where they start.
pub(super) struct Expressions<'p> {
    by_offset: HashMap<usize, &'p Aggregate>,
}

/// A literal with expressions, valued.
pub(super) struct Evaluated {
    pub trans: [f64; 3],
    pub rot: [f64; 4],
    conf: [f64; 4],
    /// Where the position and orientation parts are written.
    position: Range<usize>,
    orientation: Range<usize>,
}

impl<'p> Expressions<'p> {
    pub fn of(program: &'p Program) -> Expressions<'p> {
        struct Found<'p>(HashMap<usize, &'p Aggregate>);
        impl<'a> Visit<'a> for Found<'a> {
            // Expressions alone: the fast lane's runs hold none.
            fn program(&self) -> Option<&'a Program> {
                None
            }
            fn visit_expr(&mut self, e: &'a Expr) {
                if let Expr::Aggregate(a) = e {
                    if a.items.len() == 4 {
                        self.0.insert(a.span.start, a);
                    }
                }
                walk_expr(self, e);
            }
        }
        let mut found = Found(HashMap::new());
        // The walk over every expression is only needed when some literal
        // is written with expressions (CAM programs hold none).
        if program
            .targets()
            .one_by_one_all()
            .any(|(_, t)| t.written_with_expressions())
        {
            found.visit_program(program);
        }
        Expressions { by_offset: found.0 }
    }

    fn parts(&self, target: &Target) -> Option<&'p [Expr]> {
        let a = self.by_offset.get(&target.origin.pos.offset)?;
        Some(&a.items)
    }

    /// The literal's numbers, when every part is an aggregate of numbers
    /// the program fixes before it runs (literals and `CONST num`).
    pub fn evaluate(&self, constants: &Constants, target: &Target) -> Option<Evaluated> {
        let parts = self.parts(target)?;
        let site = Site {
            module: &target.origin.module,
            routine: target.origin.routine.as_deref(),
        };
        let values = |i: usize| -> Option<(Vec<f64>, Range<usize>)> {
            let Expr::Aggregate(a) = &parts[i] else {
                return None;
            };
            let v: Vec<f64> = a
                .items
                .iter()
                .map(|e| constants.num(e, site))
                .collect::<Option<_>>()?;
            Some((v, a.span.clone()))
        };
        let (trans, position) = values(0)?;
        let (rot, orientation) = values(1)?;
        let (conf, _) = values(2)?;
        Some(Evaluated {
            trans: trans.try_into().ok()?,
            rot: rot.try_into().ok()?,
            conf: conf.try_into().ok()?,
            position,
            orientation,
        })
    }

    /// The report for a literal left as written.
    pub fn left_alone(
        &self,
        program: &Program,
        constants: &Constants,
        target: &Target,
    ) -> LeftAlone {
        let names: Vec<String> = self
            .parts(target)
            .map(|p| p.iter().flat_map(names_read).collect())
            .unwrap_or_default();
        let read = if names.is_empty() {
            String::new()
        } else {
            format!(" (reads {})", names.join(", "))
        };
        if self.evaluate(constants, target).is_some() {
            leave(
                program,
                target,
                Reason::Expression,
                format!("written with named constants or expressions{read}: left as written unless numbers may be written in their place"),
            )
        } else {
            leave(
                program,
                target,
                Reason::Runtime,
                format!("written with expressions whose value only the run knows{read}"),
            )
        }
    }
}

impl Evaluated {
    pub fn pose_conf(&self) -> Result<(Isometry3<f64>, RobConf)> {
        let pose = pose_from_rapid(self.trans, self.rot)?;
        let conf = robconf_of(self.conf).map_err(|x| {
            crate::error::Error::input(format!("robconf value {x} is not a whole number"))
        })?;
        Ok((pose, conf))
    }

    /// The position written as numbers, and the orientation when it turns.
    pub fn edits(&self, src: &[u8], trans: [f64; 3], rot: Option<[f64; 4]>) -> Vec<Edit> {
        let literal = |values: &[f64], resolution: f64| {
            let numbers: Vec<String> = values
                .iter()
                .map(|&v| format_like("0", v, resolution))
                .collect();
            format!("[{}]", numbers.join(","))
        };
        let edit = |span: &Range<usize>, new: String| Edit {
            span: span.clone(),
            expected_old: src.get(span.clone()).unwrap_or_default().to_vec(),
            new: new.into_bytes(),
        };
        let mut out = vec![edit(&self.position, literal(&trans, POSITION_RESOLUTION))];
        if let Some(rot) = rot {
            out.push(edit(
                &self.orientation,
                literal(&rot, QUATERNION_RESOLUTION),
            ));
        }
        out
    }
}

/// Jointtargets written with named constants or expressions
/// (`CONST jointtarget jHome := [[0,nA2,0,0,30,0],[9E9,...]]`, or so in a
/// MoveAbsJ): the reader keeps no numbers for them, so they are found here
/// and reported (left alone: their joints are not rewritten).
pub(super) fn jointtarget_expressions(program: &Program) -> Vec<LeftAlone> {
    use crate::error::Location;
    use crate::rapid::{motion_signature, Statement, StatementKind};
    let mut out = Vec::new();
    let mut add = |file: usize, id: String, offset: usize| {
        let loc = Location::from_offset(&program.files[file], program.source(file), offset);
        out.push(LeftAlone {
            id,
            kind: Kind::JointTarget,
            file: loc.file,
            line: loc.line as u32,
            col: loc.col as u32,
            reason: Reason::Expression,
            detail: "written with named constants or expressions: its joints are left as written"
                .to_string(),
            world_mm: None,
        });
    };
    let aggregate = |e: Option<&Expr>| match e {
        Some(Expr::Aggregate(a)) if a.items.len() == 2 => Some(a.span.start),
        _ => None,
    };
    for m in &program.modules {
        let decls = m.data.iter().chain(m.routines.iter().flat_map(|r| &r.data));
        for d in decls {
            if d.type_name.eq_ignore_ascii_case("jointtarget") && d.dims.is_empty() {
                if let Some(at) = aggregate(d.init.as_ref()) {
                    add(m.file, d.name.clone(), at);
                }
            }
        }
        for r in &m.routines {
            let mut k = 0;
            let mut found = Vec::new();
            crate::resolve::walk_statements(&r.body, &mut |s: &Statement| {
                let StatementKind::Call(call) = &s.kind else {
                    return;
                };
                let Some(sig) = motion_signature(&call.name) else {
                    return;
                };
                let positional: Vec<&Expr> = call.positional().collect();
                for &i in sig.jointtargets {
                    if let Some(at) = aggregate(positional.get(i).copied()) {
                        k += 1;
                        found.push((format!("{}#j{k}", r.name), at));
                    }
                }
            });
            for (id, at) in found {
                add(m.file, id, at);
            }
        }
    }
    out
}
