//! `BACKINFO/backinfo.txt` of a controller backup: which folder holds which
//! task, and the modules each task loads, in the order it loads them.
//!
//! ```text
//! >>TASK1: (T_ROB1,KrakerTrailers,)
//! SYSMOD/user.sys @ user.sys
//! PROGMOD/MainModule.mod @ mainmodule.mod
//! SYSMOD/LINKEDM.sys @ HIDDEN
//! ```
//! The header names the backup folder (`TASK1`), the task (`T_ROB1`) and
//! its program; each module line its path inside the folder, then `@` and
//! what the controller loaded it as.

/// One task of the backup.
#[derive(Debug, Clone, PartialEq)]
pub struct BackTask {
    /// The folder under `RAPID/`: `TASK1`.
    pub folder: String,
    /// The task's name on the controller: `T_ROB1`.
    pub name: String,
    /// Module paths inside the folder (`PROGMOD/x.mod`), in load order.
    pub modules: Vec<String>,
    /// The line of its `>>TASKn:` header (1-based).
    pub line: usize,
}

/// The tasks a backinfo.txt lists, in its order.
pub fn parse(text: &str) -> Vec<BackTask> {
    let mut tasks: Vec<BackTask> = Vec::new();
    let mut in_task = false;
    // Every line end counts (a backup copied through an old Mac keeps
    // `\r` alone).
    for (n, raw) in crate::error::split_lines(text).enumerate() {
        let line = raw.trim();
        if let Some(head) = line.strip_prefix(">>") {
            in_task = false;
            let Some((folder, rest)) = head.split_once(':') else {
                continue;
            };
            if !folder.to_ascii_uppercase().starts_with("TASK") {
                continue;
            }
            let inner = rest.trim().trim_start_matches('(').trim_end_matches(')');
            let name = inner.split(',').next().unwrap_or("").trim();
            tasks.push(BackTask {
                folder: folder.trim().to_string(),
                name: if name.is_empty() {
                    folder.trim().to_string()
                } else {
                    name.to_string()
                },
                modules: Vec::new(),
                line: n + 1,
            });
            in_task = true;
        } else if in_task && !line.is_empty() && !line.starts_with('#') {
            let path = line.split(" @").next().unwrap_or(line).trim();
            if let Some(task) = tasks.last_mut() {
                task.modules.push(path.to_string());
            }
        }
    }
    tasks
}

#[cfg(test)]
mod tests {
    #[test]
    fn tasks_names_and_module_order() {
        let text = "#\n>>SYSTEM_ID:\n66-60711\n\n>>TASK1: (T_ROB1,Kraker,)\nSYSMOD/user.sys @ user.sys\r\nPROGMOD/Main.mod @ main.mod\nSYSMOD/LINKEDM.sys @ HIDDEN\n\n>>TASK2: (PSC_CBC,,)\nSYSMOD/user.sys @ \n\n>>EOF:\n";
        let tasks = super::parse(text);
        assert_eq!(tasks.len(), 2);
        assert_eq!(tasks[0].folder, "TASK1");
        assert_eq!(tasks[0].name, "T_ROB1");
        assert_eq!(
            tasks[0].modules,
            ["SYSMOD/user.sys", "PROGMOD/Main.mod", "SYSMOD/LINKEDM.sys"]
        );
        assert_eq!(tasks[1].name, "PSC_CBC");
        assert_eq!(tasks[1].modules, ["SYSMOD/user.sys"]);
        assert_eq!((tasks[0].line, tasks[1].line), (5, 10));
        // A backup whose lines end in `\r` alone reads the same.
        assert_eq!(
            super::parse(&text.replace("\r\n", "\n").replace('\n', "\r")),
            tasks
        );
    }
}
