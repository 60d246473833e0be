//! A backup that says two things of one thing: one truth or a refusal.
//!
//! The configuration rapidtherm reads (SYS.cfg's `CAB_TASKS` and
//! `MECHANICAL_UNIT_GROUP`, MOC.cfg's `ROBOT`) decides which robot a task
//! moves, what it is and where it stands. Where it says so twice, and
//! differently, taking either value would be a guess; the backup is
//! refused, naming both places (file:line:column of each). Said twice
//! alike, it is one truth and read.
//!
//! What the controller holds to (ABB, Technical reference manual, System
//! parameters, topic Controller, type Task, and topic Motion): an
//! instance's name is unique in its type; a mechanical unit group is
//! moved by one motion task (the `-MotionTask` of the task that uses it)
//! and a robot belongs to one group.

use super::cfg::{Cfg, Instance};
use crate::error::{Error, Result};

/// The sections read, and the attribute that names their instances.
const NAMED: [(&str, &str); 3] = [
    ("CAB_TASKS", "Name"),
    ("MECHANICAL_UNIT_GROUP", "Name"),
    ("ROBOT", "name"),
];

/// A place of a configuration file, as messages write it.
fn place(cfg: &Cfg, (line, col): (usize, usize)) -> String {
    format!("{}:{line}:{col}", cfg.file)
}

/// Why two different values of one thing are refused.
const TWO_VALUES: &str = "the two differ, and which one the controller takes cannot be told";

/// The refusal of a contradiction: at its later place, naming both, and
/// why they cannot both hold.
fn refusal(cfg: &Cfg, what: String, places: [(usize, usize); 2], why: &str) -> Error {
    let [first, second] = places;
    Error::input(format!(
        "{what} (at {} and at {}): {why}",
        place(cfg, first),
        place(cfg, second)
    ))
    .at(cfg.location(second.0, second.1))
}

/// Whether two instances say the same, attribute by attribute (names
/// compared as the controller does, without regard to case; order and
/// places do not count).
fn same(a: &Instance, b: &Instance) -> bool {
    let key = |i: &Instance| {
        let mut v: Vec<(String, Option<String>)> = i
            .attributes
            .iter()
            .map(|a| (a.name.to_ascii_lowercase(), a.value.clone()))
            .collect();
        v.sort();
        v
    };
    key(a) == key(b)
}

/// Every contradiction of `cfg` in the sections rapidtherm reads, as one
/// error (each its own, related); `Ok` where there is none.
pub fn refuse(cfg: &Cfg) -> Result<()> {
    let mut errors = Vec::new();
    for (section, name_key) in NAMED {
        let instances = cfg.section(section);
        for (k, inst) in instances.iter().enumerate() {
            // One attribute given twice in one instance.
            for (i, a) in inst.attributes.iter().enumerate() {
                if let Some(b) = inst.attributes[i + 1..]
                    .iter()
                    .find(|b| b.name.eq_ignore_ascii_case(&a.name) && b.value != a.value)
                {
                    let whose = inst.get(name_key).unwrap_or("?");
                    errors.push(refusal(
                        cfg,
                        format!("{section} {whose} gives -{} twice", a.name),
                        [(a.line, a.col), (b.line, b.col)],
                        TWO_VALUES,
                    ));
                    break;
                }
            }
            // One instance declared twice.
            let Some(name) = inst.get(name_key) else {
                continue;
            };
            let first = instances[..k].iter().find(|e| {
                e.get(name_key)
                    .is_some_and(|n| n.eq_ignore_ascii_case(name))
            });
            if let Some(first) = first.filter(|f| !same(f, inst)) {
                let at = |i: &Instance| i.place(name_key).unwrap_or((i.line, 1));
                errors.push(refusal(
                    cfg,
                    format!("{section} {name} is declared twice"),
                    [at(first), at(inst)],
                    TWO_VALUES,
                ));
            }
        }
    }
    errors.extend(shared_groups(cfg));
    errors.extend(robot_in_two_groups(cfg));
    match Error::many(errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Two motion tasks that use one mechanical unit group (or, naming none,
/// the system's one robot): each would move the same robot.
fn shared_groups(cfg: &Cfg) -> Vec<Error> {
    let mut errors = Vec::new();
    let mut seen: Vec<(String, &Instance)> = Vec::new();
    for task in cfg.section("CAB_TASKS") {
        if !task.has("MotionTask") {
            continue;
        }
        let group = task
            .get("UseMechanicalUnitGroup")
            .unwrap_or("")
            .to_ascii_lowercase();
        let name = |t: &Instance| t.get("Name").unwrap_or("?").to_string();
        match seen
            .iter()
            .find(|(g, t)| *g == group && !name(t).eq_ignore_ascii_case(&name(task)))
        {
            Some((_, first)) => {
                let at = |t: &Instance| {
                    t.place("UseMechanicalUnitGroup")
                        .or_else(|| t.place("MotionTask"))
                        .unwrap_or((t.line, 1))
                };
                let group = task
                    .get("UseMechanicalUnitGroup")
                    .map_or("the system's one mechanical unit group".to_string(), |g| {
                        format!("mechanical unit group {g}")
                    });
                errors.push(refusal(
                    cfg,
                    format!(
                        "the motion tasks {} and {} both move {group}",
                        name(first),
                        name(task)
                    ),
                    [at(first), at(task)],
                    "one motion task moves a mechanical unit group",
                ));
            }
            None => seen.push((group, task)),
        }
    }
    errors
}

/// One robot in two mechanical unit groups: which task moves it cannot be
/// told.
fn robot_in_two_groups(cfg: &Cfg) -> Vec<Error> {
    let mut errors = Vec::new();
    let groups = cfg.section("MECHANICAL_UNIT_GROUP");
    for (k, g) in groups.iter().enumerate() {
        let Some(robot) = g.get("Robot") else {
            continue;
        };
        let name = |g: &Instance| g.get("Name").unwrap_or("?").to_string();
        let first = groups[..k].iter().find(|f| {
            f.get("Robot")
                .is_some_and(|r| r.eq_ignore_ascii_case(robot))
                && !name(f).eq_ignore_ascii_case(&name(g))
        });
        if let Some(first) = first {
            let at = |g: &Instance| g.place("Robot").unwrap_or((g.line, 1));
            errors.push(refusal(
                cfg,
                format!(
                    "robot {robot} is in two mechanical unit groups, {} and {}",
                    name(first),
                    name(g)
                ),
                [at(first), at(g)],
                "a robot is in one mechanical unit group, which one motion task moves",
            ));
        }
    }
    errors
}

#[cfg(test)]
mod tests {
    use super::*;

    fn refused(text: &str) -> String {
        let cfg = Cfg::parse("SYS.cfg", text).unwrap();
        refuse(&cfg).unwrap_err().to_string()
    }

    const HEAD: &str = "SYS:CFG_1.0:6:0::\n#\n";

    #[test]
    fn a_task_declared_twice_differently_is_refused_at_both_places() {
        let text = format!(
            "{HEAD}CAB_TASKS:\n\n -Name \"T_ROB1\" -MotionTask\n\n -Name \"T_ROB1\" -Type \"STATIC\"\n#\n"
        );
        let e = refused(&text);
        // The names' values: line 5 column 8, line 7 column 8.
        assert!(e.starts_with("SYS.cfg:7:8: error: CAB_TASKS T_ROB1 is declared twice (at SYS.cfg:5:8 and at SYS.cfg:7:8): the two differ"), "{e}");
        // Declared twice alike: one truth.
        let alike = format!(
            "{HEAD}CAB_TASKS:\n -Name \"T_ROB1\" -MotionTask\n -MotionTask -name \"T_ROB1\"\n#\n"
        );
        assert!(refuse(&Cfg::parse("SYS.cfg", &alike).unwrap()).is_ok());
    }

    #[test]
    fn a_key_given_twice_is_refused_unless_alike() {
        let text = "MOC:CFG_1.0:6:0::\n#\nROBOT:\n -name \"ROB_1\" -base_frame_pos_z 1.6 -base_frame_pos_z 0\n";
        let cfg = Cfg::parse("MOC.cfg", text).unwrap();
        let e = refuse(&cfg).unwrap_err().to_string();
        // `1.6` at column 34 of line 4, `0` at column 56.
        assert!(e.starts_with("MOC.cfg:4:56: error: ROBOT ROB_1 gives -base_frame_pos_z twice (at MOC.cfg:4:34 and at MOC.cfg:4:56): the two differ"), "{e}");
        let alike = "MOC:CFG_1.0:6:0::\n#\nROBOT:\n -name \"ROB_1\" -base_frame_pos_z 0 -base_frame_pos_z 0\n";
        assert!(refuse(&Cfg::parse("MOC.cfg", alike).unwrap()).is_ok());
    }

    #[test]
    fn two_motion_tasks_on_one_group_and_one_robot_in_two_groups() {
        let text = format!(
            "{HEAD}CAB_TASKS:\n -Name \"T_A\" -UseMechanicalUnitGroup \"rob1\" -MotionTask\n -Name \"T_B\" -UseMechanicalUnitGroup \"ROB1\" -MotionTask\n -Name \"T_C\" -UseMechanicalUnitGroup \"rob1\"\n#\nMECHANICAL_UNIT_GROUP:\n -Name \"rob1\" -Robot \"ROB_1\"\n -Name \"rob2\" -Robot \"ROB_1\"\n#\n"
        );
        let e = refused(&text);
        assert!(e.contains("SYS.cfg:5:38: error: the motion tasks T_A and T_B both move mechanical unit group ROB1 (at SYS.cfg:4:38 and at SYS.cfg:5:38): one motion task"), "{e}");
        assert!(e.contains("SYS.cfg:10:22: error: robot ROB_1 is in two mechanical unit groups, rob1 and rob2 (at SYS.cfg:9:22 and at SYS.cfg:10:22): a robot is in one"), "{e}");
        // Two motion tasks naming no group: both the one robot's.
        let none = format!(
            "{HEAD}CAB_TASKS:\n -Name \"T_A\" -MotionTask\n -Name \"T_B\" -MotionTask\n#\n"
        );
        assert!(refused(&none).contains("both move the system's one mechanical unit group"));
    }
}
