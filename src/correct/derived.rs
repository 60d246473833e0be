//! Derived targets (`Offs(p10, 0, 0, 50)`, `RelTool(p10, 0, 0, -20 \Rz:=45)`)
//! are left as written: they move with their corrected base. What remains
//! is their residual drift: where the warm robot puts the derived pose of
//! the corrected base, against the derived pose the cold program meant.

use super::Correction;
use crate::model::{Moment, States, WarmRobot};
use crate::rapid::targets::TargetIndex;
use crate::rapid::{builtins, Block, Expr, FunctionCall, Program, StatementKind, UnaryOp};
use crate::resolve::{
    frames_for, frames_named, target_pose, walk_statements, Frames, Through, Uses,
};
use crate::robot::frames::{flange_of_target, target_of_flange};
use nalgebra::Isometry3;
use std::collections::HashMap;

/// Every function call of the program (data initialisers and statement
/// arguments), by the byte offset where it starts.
pub fn calls_by_offset(program: &Program) -> HashMap<usize, &FunctionCall> {
    let mut out = HashMap::new();
    for module in &program.modules {
        for d in &module.data {
            add(&mut out, d.init.as_ref());
        }
        for routine in &module.routines {
            for d in &routine.data {
                add(&mut out, d.init.as_ref());
            }
            visit(&routine.body, &mut out);
        }
    }
    out
}

fn add<'a>(out: &mut HashMap<usize, &'a FunctionCall>, e: Option<&'a Expr>) {
    if let Some(Expr::Call(c)) = e {
        out.insert(c.span.start, c.as_ref());
    }
}

/// Call arguments, assigned values and RETURNs, nested ones included.
fn visit<'a>(statements: &'a Block, out: &mut HashMap<usize, &'a FunctionCall>) {
    walk_statements(statements, &mut |s| match &s.kind {
        StatementKind::Call(call) => {
            for a in &call.args {
                add(out, a.value.as_ref());
            }
        }
        StatementKind::Assign { value, .. } => add(out, Some(value)),
        StatementKind::Return(e) => add(out, e.as_ref()),
        _ => {}
    });
}

fn literal(e: &Expr) -> Option<f64> {
    match e {
        Expr::Num(n) => Some(n.value),
        Expr::Unary(UnaryOp::Neg, inner) => literal(inner).map(|v| -v),
        Expr::Unary(UnaryOp::Plus, inner) => literal(inner),
        _ => None,
    }
}

/// The pose `call` computes from `base`, when its arguments are literals:
/// Offs adds a displacement in the work object, RelTool displaces and turns
/// in the tool frame (\Rx, \Ry, \Rz in degrees, applied in that order).
pub fn apply(call: &FunctionCall, base: &Isometry3<f64>) -> Option<Isometry3<f64>> {
    apply_with(call, base, &literal)
}

/// [`apply`] with arguments valued by `eval` (literals and the program's
/// constants: `Offs(p, 0, 0, nLift)`).
pub fn apply_with(
    call: &FunctionCall,
    base: &Isometry3<f64>,
    eval: &dyn Fn(&Expr) -> Option<f64>,
) -> Option<Isometry3<f64>> {
    let (name, d, turn) = offsets(call, eval)?;
    Some(match name {
        Function::Offs => builtins::offs(base, d),
        Function::RelTool => builtins::reltool(base, d, turn),
    })
}

/// The base whose [`apply_with`] is `pose`: the inverse of the offset.
pub fn unapply_with(
    call: &FunctionCall,
    pose: &Isometry3<f64>,
    eval: &dyn Fn(&Expr) -> Option<f64>,
) -> Option<Isometry3<f64>> {
    let (name, d, turn) = offsets(call, eval)?;
    Some(match name {
        Function::Offs => builtins::offs(pose, d.map(|x| -x)),
        Function::RelTool => pose * builtins::reltool(&Isometry3::identity(), d, turn).inverse(),
    })
}

enum Function {
    Offs,
    RelTool,
}

/// The function, displacement and (RelTool) turn of a call whose
/// arguments `eval` values.
fn offsets(
    call: &FunctionCall,
    eval: &dyn Fn(&Expr) -> Option<f64>,
) -> Option<(Function, [f64; 3], [f64; 3])> {
    let literal = eval;
    let positional: Vec<&Expr> = call.positional().collect();
    if positional.len() != 4 {
        return None;
    }
    let d = [
        literal(positional[1])?,
        literal(positional[2])?,
        literal(positional[3])?,
    ];
    let name = call.name.to_ascii_lowercase();
    match name.as_str() {
        "offs" => Some((Function::Offs, d, [0.0; 3])),
        "reltool" => {
            let angle = |n: &str| -> Option<f64> {
                match call.args.iter().find(|a| {
                    a.optional && a.name.as_deref().is_some_and(|x| x.eq_ignore_ascii_case(n))
                }) {
                    Some(a) => a.value.as_ref().and_then(literal),
                    None => Some(0.0),
                }
            };
            Some((
                Function::RelTool,
                d,
                [angle("Rx")?, angle("Ry")?, angle("Rz")?],
            ))
        }
        _ => None,
    }
}

#[allow(clippy::too_many_arguments)]
/// Residual drift (mm) of the derived target `index` after its base's
/// correction, in the tool and work object of the first move to it, or
/// `None` where it cannot be evaluated statically (CRobT, a FUNC, a
/// computed offset, a base that was not corrected).
pub fn residual(
    program: &Program,
    index: usize,
    calls: &HashMap<usize, &FunctionCall>,
    (frames, uses, index_of): &(&Frames, &Uses, &TargetIndex),
    corrections: &[Correction],
    warm: &WarmRobot,
    states: &States,
    eval: &dyn Fn(&Expr) -> Option<f64>,
) -> Option<f64> {
    let target = program.targets().get(index)?;
    let call = calls.get(&target.origin.pos.offset)?;
    let base_id = target.derived.as_ref()?.bases.first()?;
    let correction = corrections
        .iter()
        .find(|c| c.id.eq_ignore_ascii_case(base_id))?;
    let base_index = index_of.get(base_id)?;
    let base = program.targets().get(base_index)?;
    let (original, conf) = target_pose(program, &base).ok()??;
    // This expression's own move: its tool and work object may be other
    // than the ones the base is corrected for (its first use's).
    let (tool, wobj) = match uses
        .of(base_index)
        .find(|u| u.through() == Through::Derived(index))
    {
        Some(u) => frames_named(program, frames, &base, u.tool(), u.wobj()).ok()?,
        None => {
            let first = uses.first(base_index).map(|f| (f.tool(), f.wobj()));
            let (tool, wobj, _, _) = frames_for(program, frames, &base, first).ok()?;
            (tool, wobj)
        }
    };
    let meant = apply_with(call, &original, eval)?;
    let sent = apply_with(call, &correction.exact?, eval)?;
    let q = warm
        .nominal
        .ik_conf(&flange_of_target(&sent, &tool, &wobj).ok()?, &conf)
        .ok()?;
    let moment = correction.time_min.map_or(Moment::Steady, Moment::Minute);
    let state = states.at(moment).ok()?;
    let landed = target_of_flange(&warm.flange(&q, &state), &tool, &wobj).ok()?;
    Some((landed.translation.vector - meant.translation.vector).norm())
}
