//! A task the backup's SYSPAR/SYS.cfg does not mark as a motion task is
//! left alone; but one that holds moves is a contradiction of the backup
//! (the controller lets only a motion task move a robot), not a task with
//! nothing to do. It is read, and each target its moves reach is reported
//! left alone for [`Reason::NotMotionTask`], which leaves it cold: a check
//! fails on it, naming it, rather than passing a backup whose moving
//! tasks were all skipped.

use super::corrected::{CorrectedTask, Inputs, Streaming};
use super::host::{Event, Host};
use crate::correct::{Kind, LeftAlone, MoveCounts, Outcome, Reason, Summary};
use crate::rapid::task::Task;
use crate::rapid::Program;
use std::collections::HashSet;

/// The name a task without a robot has in the reports' arm column.
pub const NO_ARM: &str = "none (not a motion task)";

/// A task that moves no robot, read (`inputs`, `program`): said, and
/// where it holds moves, a run whose every target reached is left cold.
pub fn still_task(
    task: Task,
    inputs: Inputs,
    program: &Program,
    host: &mut dyn Host,
) -> Option<CorrectedTask> {
    let left = left_cold(program, &task.label());
    host.event(Event::NotMotion {
        task: &task.label(),
        moves: left.moves,
    });
    if left.moves == 0 {
        return None;
    }
    let outputs = inputs.iter().map(|(_, s)| s.bytes().to_vec()).collect();
    let outcome = Outcome {
        moves: Vec::new(),
        corrections: Vec::new(),
        derived: Vec::new(),
        residuals: Vec::new(),
        shared: Vec::new(),
        splits: Vec::new(),
        already_corrected: None,
        notes: Vec::new(),
        summary: Summary {
            corrected: 0,
            rewritten: 0,
            max_mm: 0.0,
            rms_mm: 0.0,
            max_drift_mm: 0.0,
            derived: 0,
            left_alone: left.rows.len(),
            shared: 0,
            split: 0,
            moves: MoveCounts::default(),
        },
        left_alone: left.rows,
        outputs,
    };
    Some(CorrectedTask {
        task,
        arm: NO_ARM.to_string(),
        inputs,
        outcome,
        streaming: Streaming::InMemory,
    })
}

/// What a still task's moves reach: one row per target (or per argument
/// that reaches none), and how many moves there are.
struct Left {
    rows: Vec<LeftAlone>,
    moves: usize,
}

fn left_cold(program: &Program, task: &str) -> Left {
    let detail = format!(
        "task {task} moves to it, but SYSPAR/SYS.cfg does not mark the task as a motion task (-MotionTask): which robot it moves is not known, so nothing of it is corrected"
    );
    let targets = program.targets();
    let joints = program.jointtargets();
    let mut rows = Vec::new();
    let mut seen: HashSet<(bool, usize)> = HashSet::new();
    let mut moves = 0;
    crate::resolve::each_move_instruction(program, &mut |m| {
        moves += 1;
        let mut reached = false;
        for p in &m.points {
            for (range, _) in &p.robtargets {
                for i in range.clone() {
                    reached = true;
                    if !seen.insert((false, i)) {
                        continue;
                    }
                    let t = targets.at(i);
                    rows.push(row(program, &t.id, Kind::of(&t), &t.origin, &detail));
                }
            }
            for &j in &p.jointtargets {
                reached = true;
                if !seen.insert((true, j)) {
                    continue;
                }
                let t = &joints[j];
                rows.push(row(program, &t.id, Kind::JointTarget, &t.origin, &detail));
            }
        }
        if !reached {
            // An argument the files do not settle: the move itself.
            rows.push(LeftAlone {
                id: m.instruction.to_string(),
                kind: Kind::Argument,
                file: program.file_name(m.file).to_string(),
                line: m.line,
                col: m.col,
                reason: Reason::NotMotionTask,
                detail: detail.clone(),
                world_mm: None,
            });
        }
    });
    Left { rows, moves }
}

fn row(
    program: &Program,
    id: &str,
    kind: Kind,
    origin: &crate::rapid::Origin,
    detail: &str,
) -> LeftAlone {
    LeftAlone {
        id: id.to_string(),
        kind,
        file: program.file_name(origin.file).to_string(),
        line: origin.pos.line,
        col: origin.pos.col,
        reason: Reason::NotMotionTask,
        detail: detail.to_string(),
        world_mm: None,
    }
}
