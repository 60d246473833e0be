//! Helpers shared by the integration tests of the correction.

use nalgebra::Isometry3;
use rapidtherm::rapid::Program;
use rapidtherm::resolve::{frames_of, target_pose, usages, Frames, Usage};
use rapidtherm::robot::frames::{ToolFrame, WobjFrames};
use rapidtherm::robot::RobConf;
use std::collections::HashMap;

/// A robtarget as the program means it: pose in its work object, robconf,
/// and the tool and work object the program moves to it with.
pub struct Meant {
    pub pose: Isometry3<f64>,
    pub conf: RobConf,
    pub tool: ToolFrame,
    pub wobj: WobjFrames,
}

/// What a program means by its targets, looked up independently of the
/// correction's own bookkeeping.
pub struct Meanings<'a> {
    program: &'a Program,
    frames: Frames,
    uses: HashMap<usize, Vec<Usage>>,
}

impl<'a> Meanings<'a> {
    pub fn new(program: &'a Program) -> Meanings<'a> {
        Meanings {
            program,
            frames: Frames::of_program(program).unwrap(),
            uses: usages(program),
        }
    }

    /// What the program means by target `id`.
    pub fn of(&self, id: &str) -> Meant {
        let (index, target) = self
            .program
            .targets()
            .iter()
            .enumerate()
            .find(|(_, t)| t.id == id)
            .unwrap();
        let (pose, conf) = target_pose(self.program, &target).unwrap().unwrap();
        let (tool, wobj, _, _) =
            frames_of(self.program, &self.frames, index, self.uses.get(&index)).unwrap();
        Meant {
            pose,
            conf,
            tool,
            wobj,
        }
    }
}

/// `from` copied into `to`, folders and files (a backup to change in a
/// temporary folder).
// The diagnosis's tests, which share this file, copy no backup.
#[allow(dead_code)]
pub fn copy_tree(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_tree(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}
