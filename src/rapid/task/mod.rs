//! A task: the modules a controller loads together, read as one program.
//!
//! RAPID programs live in tasks. A task's program modules (PROGMOD) and
//! system modules (SYSMOD, where `user.sys` usually declares the tools and
//! work objects) see each other's global data, so a target can only be
//! resolved with the whole task in view. [`discover`] turns what a user
//! names on the command line into tasks:
//!
//! - files one by one: one task of exactly those files (as before);
//! - a program file (`.pgf`): the modules it lists;
//! - a task folder (`RAPID/TASK1`, or any folder with `PROGMOD`/`SYSMOD`);
//! - a whole controller backup (a folder with `RAPID/`), or its `RAPID`
//!   folder: every `TASKn` folder. The backup's `BACKINFO/backinfo.txt`
//!   gives each folder's task name and load order, `SYSPAR/SYS.cfg` which
//!   tasks move a robot and through which mechanical unit group,
//!   `SYSPAR/MOC.cfg` which robot type that group's robot is. A folder is
//!   a backup only when it holds `BACKINFO/` or `SYSPAR/`: a repository
//!   that keeps just `RAPID/TASK1` (as cell engineers version their
//!   programs) has no configuration to miss, and its task folders are read
//!   as folders of modules ([`Task::not_a_backup`] says where);
//! - any other folder: the RAPID modules in it (or the program file, if it
//!   holds exactly one).
//!
//! Reads the file system but never writes. Knows no robot: the robot type
//! is the controller's string (`ROB1_140_0.81_6`); which arm that is, is
//! for the layers that know arms.

pub mod backinfo;
pub mod backinfo_entry;
pub mod cfg;
pub mod contradiction;
pub mod pgf;
pub mod placement;

use crate::error::{Error, Result};
use backinfo::BackTask;
use cfg::{Cfg, Instance};
use placement::{BackupPart, Gap, GapKind, Placement};
use std::path::{Path, PathBuf};

/// One task to read as one program.
#[derive(Debug, Clone, PartialEq)]
pub struct Task {
    /// The controller's name for it (`T_ROB1`) where a backup says, else
    /// the folder's or program file's name; `None` for files named one by
    /// one.
    pub name: Option<String>,
    /// The folder or program file it was found in.
    pub origin: Option<PathBuf>,
    /// Its module files, in load order (`-` is standard input).
    pub modules: Vec<PathBuf>,
    /// Whether the task moves a robot, where the backup's SYS.cfg says.
    pub motion: Option<bool>,
    /// The robot type of the mechanical unit group the task moves, as
    /// MOC.cfg writes it (`ROB1_140_0.81_6`), where the backup says.
    pub robot_type: Option<String>,
    /// Where that robot stands in the world, as MOC.cfg places it: its
    /// base frame (mm, quaternion w x y z). `None`: at the world origin.
    pub base_frame: Option<([f64; 3], [f64; 4])>,
    /// The mechanical unit the base frame moves with (a track), when
    /// MOC.cfg coordinates it.
    pub base_moved_by: Option<String>,
    /// What the reader noticed on the way (a module listed but missing).
    pub notes: Vec<String>,
    /// What a backup's configuration should have said of this task's robot
    /// and did not (empty for tasks not read from a backup).
    pub gaps: Vec<Gap>,
    /// The folder that would be this task's controller backup (it holds
    /// `RAPID/`) but holds neither `BACKINFO/` nor `SYSPAR/`: the task was
    /// read as a folder of modules, and no configuration says which robot
    /// it moves or where that robot stands. `None` for a task of a backup
    /// and for folders no backup was looked for in.
    pub not_a_backup: Option<PathBuf>,
}

impl Task {
    fn of_files(name: Option<String>, origin: Option<PathBuf>, modules: Vec<PathBuf>) -> Task {
        Task {
            name,
            origin,
            modules,
            motion: None,
            robot_type: None,
            base_frame: None,
            base_moved_by: None,
            notes: Vec::new(),
            gaps: Vec::new(),
            not_a_backup: None,
        }
    }

    /// How messages name the task: its name, else where it was found.
    pub fn label(&self) -> String {
        match (&self.name, &self.origin) {
            (Some(n), _) => n.clone(),
            (None, Some(o)) => o.display().to_string(),
            (None, None) => "program".to_string(),
        }
    }
}

/// True for the file names RAPID modules have: `.mod`, `.modx`, `.sys`,
/// `.sysx`, and the S4 controllers' `.prg`.
pub fn is_rapid_file(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        ["mod", "modx", "sys", "sysx", "prg"]
            .iter()
            .any(|x| e.eq_ignore_ascii_case(x))
    })
}

fn is_pgf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("pgf"))
}

/// The tasks that the paths a user named stand for. Files named one by one
/// (no folder, no program file) are one task, in the order given. Files
/// beside folders or program files join the one task those give, and are
/// an error if they give several.
pub fn discover(paths: &[PathBuf]) -> Result<Vec<Task>> {
    if !paths.iter().any(|p| p.is_dir() || is_pgf(p)) {
        return Ok(vec![Task::of_files(None, None, paths.to_vec())]);
    }
    let mut tasks = Vec::new();
    let mut loose = Vec::new();
    for p in paths {
        if p == Path::new("-") {
            return Err(Error::usage(
                "standard input cannot be read beside task folders or program files",
            ));
        } else if p.is_dir() {
            tasks.extend(tasks_in_folder(p)?);
        } else if is_pgf(p) {
            tasks.push(program_file(p)?);
        } else {
            loose.push(p.clone());
        }
    }
    if !loose.is_empty() {
        match tasks.as_mut_slice() {
            [one] => one.modules.extend(loose),
            _ => {
                return Err(Error::usage(format!(
                    "{} is named beside {} tasks: say which task it belongs to by naming that task's folder or program file alone",
                    loose[0].display(),
                    tasks.len()
                )))
            }
        }
    }
    Ok(tasks)
}

/// The modules of a program file, found beside it.
fn program_file(path: &Path) -> Result<Task> {
    let bytes = crate::input::read_path(path)?;
    let listed = pgf::modules(&path.display().to_string(), &bytes)?;
    // A bare name (`Cell.pgf`, as RobotStudio users name a saved program)
    // has the empty path as its parent: its modules lie in the current
    // folder.
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut modules = Vec::new();
    for m in &listed {
        match find_listed(dir, m, path)? {
            Some(found) => modules.push(found),
            None => {
                return Err(Error::input(format!(
                    "{}: module {m} is listed but not found in {}",
                    path.display(),
                    dir.display()
                )))
            }
        }
    }
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    Ok(Task::of_files(name, Some(path.to_path_buf()), modules))
}

/// What a backup says about its tasks, read once per backup, and which of
/// its parts it lacks.
#[derive(Default)]
struct Backup {
    root: PathBuf,
    /// `root` holds `RAPID/` but neither `BACKINFO/` nor `SYSPAR/`: not a
    /// backup, and nothing of one is missing.
    plain: bool,
    tasks: Option<Vec<BackTask>>,
    sys: Option<Cfg>,
    moc: Option<Cfg>,
    /// The parts missing or unreadable: gaps of every task.
    gaps: Vec<Gap>,
}

impl Backup {
    /// The backup whose root is `root` (a folder holding `RAPID/`). A part
    /// it lacks is a gap of every task, not an error: a backup copied by
    /// hand still lists its targets; what needs the placement refuses.
    ///
    /// A folder with neither `BACKINFO/` nor `SYSPAR/` is no backup (a
    /// repository of programs keeps `RAPID/TASK1` alone): read plain, with
    /// no gaps. A backup needs only one of the two to keep the rules, so
    /// one cut short still has its gaps named.
    fn read(root: &Path) -> Result<Backup> {
        let mut backup = Backup {
            root: root.to_path_buf(),
            ..Backup::default()
        };
        let is_dir = |part: &str| find_ci(root, part).is_some_and(|p| p.is_dir());
        if !is_dir("BACKINFO") && !is_dir("SYSPAR") {
            backup.plain = true;
            return Ok(backup);
        }
        let mut text = |part: BackupPart| -> Result<Option<(PathBuf, String)>> {
            match find_ci(root, part.path()) {
                Some(p) if p.is_file() => {
                    let bytes = crate::input::read_path(&p)?;
                    crate::input::refuse_unread_encoding(
                        &p.display().to_string(),
                        &bytes,
                        "UTF-8 or ISO-8859-1 (Latin-1), as the controller writes its backups",
                    )?;
                    Ok(Some((p, crate::error::decode_lossless(&bytes))))
                }
                _ => {
                    backup.gaps.push(Gap {
                        kind: GapKind::Missing(part),
                        file: root.join(part.path()),
                        location: None,
                    });
                    Ok(None)
                }
            }
        };
        let backinfo = text(BackupPart::BackInfo)?;
        let sys = text(BackupPart::Sys)?;
        let moc = text(BackupPart::Moc)?;
        if let Some((path, text)) = &backinfo {
            let tasks = backinfo::parse(text);
            refuse_folder_listed_twice(path, &tasks)?;
            backup.tasks = Some(tasks);
        }
        for (part, read, slot) in [
            (BackupPart::Sys, sys, &mut backup.sys),
            (BackupPart::Moc, moc, &mut backup.moc),
        ] {
            let Some((path, text)) = read else { continue };
            match Cfg::parse(&path.display().to_string(), &text) {
                Ok(cfg) => {
                    // What the backup says twice, differently, is refused
                    // here, before any task of it is read.
                    contradiction::refuse(&cfg)?;
                    *slot = Some(cfg);
                }
                Err(e) => backup.gaps.push(Gap {
                    kind: GapKind::Unreadable(part),
                    file: path,
                    location: e.location.map(|l| *l),
                }),
            }
        }
        Ok(backup)
    }

    fn backinfo_path(&self, task_dir: &Path) -> PathBuf {
        if self.root.as_os_str().is_empty() {
            task_dir.to_path_buf()
        } else {
            self.root.join(BackupPart::BackInfo.path())
        }
    }

    fn task_of_folder(&self, folder: &str) -> Option<&BackTask> {
        self.tasks
            .as_deref()?
            .iter()
            .find(|t| t.folder.eq_ignore_ascii_case(folder))
    }

    /// A gap in `cfg` at an instance's attribute (or the instance).
    fn gap_at(cfg: &Cfg, inst: &Instance, key: Option<&str>, kind: GapKind) -> Gap {
        let (line, col) = key.and_then(|k| inst.place(k)).unwrap_or((inst.line, 1));
        Gap {
            kind,
            file: PathBuf::from(&cfg.file),
            location: Some(cfg.location(line, col)),
        }
    }

    /// What SYS.cfg and MOC.cfg say of a task: whether it moves a robot,
    /// that robot's type and placement, and what they fail to say.
    fn robot_of(&self, task: &str) -> Placement {
        let mut out = Placement {
            gaps: self.gaps.clone(),
            ..Placement::default()
        };
        let Some(sys) = &self.sys else {
            return out;
        };
        let Some(entry) = sys
            .section("CAB_TASKS")
            .iter()
            .find(|t| t.get("Name").is_some_and(|n| n.eq_ignore_ascii_case(task)))
        else {
            out.gaps.push(Gap {
                kind: GapKind::TaskNotInSys {
                    task: task.to_string(),
                },
                file: PathBuf::from(&sys.file),
                location: None,
            });
            return out;
        };
        if !entry.has("MotionTask") {
            // A task that moves nothing needs no robot: nothing missing
            // matters to it.
            return Placement {
                motion: Some(false),
                ..Placement::default()
            };
        }
        out.motion = Some(true);
        let robot = match entry.get("UseMechanicalUnitGroup") {
            Some(group) => {
                let robot = sys
                    .section("MECHANICAL_UNIT_GROUP")
                    .iter()
                    .find(|g| g.get("Name").is_some_and(|n| n.eq_ignore_ascii_case(group)))
                    .and_then(|g| g.get("Robot"))
                    .map(str::to_string);
                if robot.is_none() {
                    out.gaps.push(Self::gap_at(
                        sys,
                        entry,
                        Some("UseMechanicalUnitGroup"),
                        GapKind::GroupWithoutRobot {
                            group: group.to_string(),
                        },
                    ));
                    return out;
                }
                robot
            }
            None => None,
        };
        let Some(moc) = &self.moc else {
            return out;
        };
        let robots = moc.section("ROBOT");
        let entry = match &robot {
            Some(name) => robots
                .iter()
                .find(|r| r.get("name").is_some_and(|n| n.eq_ignore_ascii_case(name))),
            // A single-robot system names no group: its one robot.
            None if robots.len() == 1 => robots.first(),
            None => None,
        };
        let Some(entry) = entry else {
            out.gaps.push(Gap {
                kind: GapKind::RobotNotInMoc { robot },
                file: PathBuf::from(&moc.file),
                location: None,
            });
            return out;
        };
        out.robot_type = entry.get("use_robot_type").map(str::to_string);
        if out.robot_type.is_none() {
            out.gaps.push(Self::gap_at(
                moc,
                entry,
                None,
                GapKind::NoRobotType {
                    robot: entry.get("name").unwrap_or("?").to_string(),
                },
            ));
        }
        let mut num = |k: &str, default: f64| match entry.get(k) {
            None => default,
            Some(v) => match v.parse::<f64>() {
                Ok(x) if x.is_finite() => x,
                _ => {
                    out.gaps.push(Self::gap_at(
                        moc,
                        entry,
                        Some(k),
                        GapKind::BadNumber {
                            key: k.to_string(),
                            value: v.to_string(),
                        },
                    ));
                    default
                }
            },
        };
        // MOC.cfg places the base in metres.
        let pos = ["x", "y", "z"].map(|a| num(&format!("base_frame_pos_{a}"), 0.0) * 1000.0);
        let orient = [
            num("base_frame_orient_u0", 1.0),
            num("base_frame_orient_u1", 0.0),
            num("base_frame_orient_u2", 0.0),
            num("base_frame_orient_u3", 0.0),
        ];
        let norm = orient.iter().map(|v| v * v).sum::<f64>().sqrt();
        // The controller stores the quaternion to about six digits.
        if (norm - 1.0).abs() > 1e-4 {
            out.gaps.push(Self::gap_at(
                moc,
                entry,
                Some("base_frame_orient_u0"),
                GapKind::BadOrientation { norm },
            ));
        }
        let at_origin = pos == [0.0; 3] && orient == [1.0, 0.0, 0.0, 0.0];
        out.base_frame = (!at_origin).then_some((pos, orient));
        out.base_moved_by = entry.get("base_frame_coordinated").map(str::to_string);
        out
    }
}

/// backinfo.txt listing one task folder twice, differently: which name
/// and load order are the folder's cannot be told.
fn refuse_folder_listed_twice(path: &Path, tasks: &[BackTask]) -> Result<()> {
    for (k, t) in tasks.iter().enumerate() {
        let twice = tasks[..k].iter().find(|f| {
            f.folder.eq_ignore_ascii_case(&t.folder) && (f.name != t.name || f.modules != t.modules)
        });
        if let Some(first) = twice {
            let file = path.display();
            return Err(Error::input(format!(
                "the task folder {} is listed twice, differently (at {file}:{}:1 and at {file}:{}:1): which name and modules are its cannot be told",
                t.folder, first.line, t.line
            ))
            .at(crate::error::Location {
                file: file.to_string(),
                line: t.line,
                col: 1,
                line_text: Box::default(),
            }));
        }
    }
    Ok(())
}

/// The tasks a folder stands for (see the module documentation).
fn tasks_in_folder(dir: &Path) -> Result<Vec<Task>> {
    if let Some(rapid) = find_ci(dir, "RAPID").filter(|p| p.is_dir()) {
        return task_folders(&rapid, &Backup::read(dir)?);
    }
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if name.eq_ignore_ascii_case("RAPID") {
        let backup = match dir.parent() {
            Some(root) => Backup::read(root)?,
            None => Backup::default(),
        };
        return task_folders(dir, &backup);
    }
    let has_task_parts = ["PROGMOD", "SYSMOD"]
        .iter()
        .any(|s| find_ci(dir, s).is_some_and(|p| p.is_dir()));
    if has_task_parts || is_task_folder_name(&name) {
        let backup = match dir.parent().zip(dir.parent().and_then(Path::parent)) {
            Some((rapid, root))
                if rapid
                    .file_name()
                    .is_some_and(|n| n.eq_ignore_ascii_case("RAPID")) =>
            {
                Backup::read(root)?
            }
            _ => Backup::default(),
        };
        return Ok(vec![task_folder(dir, &backup)?]);
    }
    let entries = sorted_entries(dir)?;
    let task_dirs: Vec<&PathBuf> = entries
        .iter()
        .filter(|p| {
            p.is_dir()
                && p.file_name()
                    .is_some_and(|n| is_task_folder_name(&n.to_string_lossy()))
        })
        .collect();
    if !task_dirs.is_empty() {
        return task_folders(dir, &Backup::default());
    }
    let pgfs: Vec<&PathBuf> = entries.iter().filter(|p| is_pgf(p)).collect();
    if let [one] = pgfs.as_slice() {
        return Ok(vec![program_file(one)?]);
    }
    let modules: Vec<PathBuf> = entries
        .iter()
        .filter(|p| p.is_file() && is_rapid_file(p))
        .cloned()
        .collect();
    if modules.is_empty() {
        return Err(Error::input(format!(
            "{}: no RAPID modules here (.mod, .modx, .sys, .sysx, .prg), no task folders and no program file",
            dir.display()
        )));
    }
    Ok(vec![Task::of_files(
        Some(name),
        Some(dir.to_path_buf()),
        modules,
    )])
}

/// `TASKn`, any case. Compared on bytes: a folder name is anything the
/// file system allows (`Menü`), and its fourth byte need not end a
/// character.
fn is_task_folder_name(name: &str) -> bool {
    task_number(name).is_some()
}

/// The `n` of a `TASKn` folder name.
fn task_number(name: &str) -> Option<u32> {
    let b = name.as_bytes();
    if b.len() > 4 && b[..4].eq_ignore_ascii_case(b"TASK") && b[4..].iter().all(u8::is_ascii_digit)
    {
        name[4..].parse().ok()
    } else {
        None
    }
}

/// Every `TASKn` folder of a backup's `RAPID` folder, in task order.
fn task_folders(rapid: &Path, backup: &Backup) -> Result<Vec<Task>> {
    let mut folders: Vec<PathBuf> = sorted_entries(rapid)?
        .into_iter()
        .filter(|p| {
            p.is_dir()
                && p.file_name()
                    .is_some_and(|n| is_task_folder_name(&n.to_string_lossy()))
        })
        .collect();
    // TASK2 before TASK10.
    folders.sort_by_key(|p| {
        p.file_name()
            .and_then(|n| task_number(&n.to_string_lossy()))
            .unwrap_or(u32::MAX)
    });
    if folders.is_empty() {
        return Err(Error::input(format!(
            "{}: no TASKn folders in this backup",
            rapid.display()
        )));
    }
    let tasks: Vec<Task> = folders
        .iter()
        .map(|f| task_folder(f, backup))
        .collect::<Result<_>>()?;
    refuse_one_name_twice(&tasks, backup)?;
    Ok(tasks)
}

/// Two task folders of one task name (folders whose names differ only in
/// case, or that backinfo.txt gives one name): which is the task the
/// controller runs, and which SYS.cfg's entry is of, cannot be told.
fn refuse_one_name_twice(tasks: &[Task], backup: &Backup) -> Result<()> {
    for (k, t) in tasks.iter().enumerate() {
        let Some(first) = tasks[..k].iter().find(|f| {
            f.name
                .as_deref()
                .zip(t.name.as_deref())
                .is_some_and(|(a, b)| a.eq_ignore_ascii_case(b))
        }) else {
            continue;
        };
        let folder = |t: &Task| {
            t.origin
                .as_deref()
                .map_or_else(String::new, |o| o.display().to_string())
        };
        let listed = |t: &Task| {
            let name = t
                .origin
                .as_deref()?
                .file_name()?
                .to_string_lossy()
                .into_owned();
            let line = backup.task_of_folder(&name)?.line;
            Some(format!(
                " (listed at {}:{line}:1)",
                backup.backinfo_path(Path::new("")).display()
            ))
        };
        return Err(Error::input(format!(
            "two task folders are task {}: {}{} and {}{}; which one the controller runs cannot be told, so the backup is not read",
            t.label(),
            folder(first),
            listed(first).unwrap_or_default(),
            folder(t),
            listed(t).unwrap_or_default(),
        )));
    }
    Ok(())
}

/// One task folder: its modules in the backup's load order where the
/// backup lists it, else system modules then program modules by name.
fn task_folder(dir: &Path, backup: &Backup) -> Result<Task> {
    let folder = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let listed = backup.task_of_folder(&folder);
    let name = listed.map_or(folder.clone(), |t| t.name.clone());
    let mut notes = Vec::new();
    let mut placed = backup.robot_of(&name);
    if listed.is_none() && backup.tasks.is_some() && placed.motion != Some(false) {
        placed.gaps.push(Gap {
            kind: GapKind::FolderNotListed {
                folder: folder.clone(),
            },
            file: backup.backinfo_path(dir),
            location: None,
        });
    }
    let mut modules: Vec<PathBuf> = Vec::new();
    if let Some(t) = listed {
        for rel in &t.modules {
            match find_listed(dir, rel, &backup.backinfo_path(dir))? {
                Some(p) => modules.push(p),
                None => notes.push(format!(
                    "task {name}: backinfo.txt lists {rel}, which is not in {}",
                    dir.display()
                )),
            }
        }
    }
    let mut on_disk = Vec::new();
    for sub in ["SYSMOD", "PROGMOD"] {
        if let Some(d) = find_ci(dir, sub).filter(|p| p.is_dir()) {
            on_disk.extend(sorted_entries(&d)?);
        }
    }
    on_disk.extend(sorted_entries(dir)?);
    for p in on_disk {
        if p.is_file() && is_rapid_file(&p) && !modules.contains(&p) {
            modules.push(p);
        }
    }
    Ok(Task {
        name: Some(name),
        origin: Some(dir.to_path_buf()),
        modules,
        motion: placed.motion,
        robot_type: placed.robot_type,
        base_frame: placed.base_frame,
        base_moved_by: placed.base_moved_by,
        notes,
        gaps: placed.gaps,
        not_a_backup: backup.plain.then(|| {
            if backup.root.as_os_str().is_empty() {
                PathBuf::from(".")
            } else {
                backup.root.clone()
            }
        }),
    })
}

/// A folder's entries sorted by lower-case name, so that runs are
/// repeatable whatever order the file system lists them in.
fn sorted_entries(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, &e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort_by_key(|p| {
        p.file_name()
            .map(|n| n.to_string_lossy().to_lowercase())
            .unwrap_or_default()
    });
    Ok(entries)
}

/// `rel` (with `/` separators) under `dir`, each part matched without
/// regard to case: backups copied through Windows change the case of
/// names, the controller does not care.
fn find_ci(dir: &Path, rel: &str) -> Option<PathBuf> {
    let mut here = dir.to_path_buf();
    for part in rel.split(['/', '\\']).filter(|s| !s.is_empty()) {
        let exact = here.join(part);
        if exact.exists() {
            here = exact;
            continue;
        }
        // The empty path (the parent of a relative `RAPID`) is the
        // current folder, which `read_dir` does not take by that name.
        let listed = if here.as_os_str().is_empty() {
            Path::new(".")
        } else {
            here.as_path()
        };
        let found = std::fs::read_dir(listed).ok()?.find_map(|e| {
            let e = e.ok()?;
            e.file_name()
                .to_string_lossy()
                .eq_ignore_ascii_case(part)
                .then(|| e.path())
        })?;
        here = found;
    }
    Some(here)
}

/// A path a file of the backup or program lists (`listed_in` names that
/// file), found under `dir` as [`find_ci`] finds it, and refused when it
/// would lead out of `dir`: an absolute path, a drive, a `..`, or a link
/// to elsewhere. A run then writes only inside what the user named.
fn find_listed(dir: &Path, rel: &str, listed_in: &Path) -> Result<Option<PathBuf>> {
    let escapes = rel.starts_with(['/', '\\'])
        || rel
            .split(['/', '\\'])
            .any(|part| part == ".." || part.contains(':'));
    let outside = || {
        Error::input(format!(
            "{}: lists {rel}, which lies outside {}: a backup or program file may only name files inside its own folder",
            listed_in.display(),
            dir.display()
        ))
    };
    if escapes {
        return Err(outside());
    }
    let Some(found) = find_ci(dir, rel) else {
        return Ok(None);
    };
    let real = |p: &Path| std::fs::canonicalize(p).map_err(|e| Error::io(p, &e));
    if !real(&found)?.starts_with(real(dir)?) {
        return Err(outside());
    }
    Ok(Some(found))
}
