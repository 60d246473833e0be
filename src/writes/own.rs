//! The files a run names itself, by kind, and how one of rapidtherm's own
//! earlier making is known: such a file is the run's to replace (a second
//! `--plot` run, the module of a second `--runtime` run); any other is the
//! user's.

/// A kind of file a run makes under a name of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Made {
    /// A picture (SVG) in a `--plot` folder.
    Picture,
    /// The `--runtime` system module.
    RuntimeModule,
    /// A man page (roff) in a `man --out-dir` folder.
    ManPage,
}

/// How much of an existing file is looked at.
pub const LOOKED_AT: usize = 4096;

impl Made {
    /// What the kind is called in a refusal.
    pub fn words(self) -> &'static str {
        match self {
            Made::Picture => "an SVG picture",
            Made::RuntimeModule => "a module rapidtherm wrote",
            Made::ManPage => "a man page",
        }
    }

    /// Whether `head`, the first [`LOOKED_AT`] bytes of an existing file,
    /// are those of a file of this kind as rapidtherm writes it: an SVG
    /// document; the module's header comment (`! Written by rapidtherm`,
    /// `correct::runtime::module`); roff as clap_mangen starts it.
    pub fn is_own(self, head: &[u8]) -> bool {
        let text = String::from_utf8_lossy(head);
        let start = text.trim_start_matches('\u{feff}').trim_start();
        match self {
            Made::Picture => start.starts_with("<svg") || start.starts_with("<?xml"),
            Made::RuntimeModule => {
                start.starts_with("MODULE ") && text.contains("! Written by rapidtherm ")
            }
            Made::ManPage => start.starts_with(".ie \\n(.g") || start.starts_with(".TH "),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Made;

    #[test]
    fn own_files_are_told_from_the_users() {
        assert!(Made::Picture.is_own(b"<svg width=\"800\" height=\"600\""));
        assert!(!Made::Picture.is_own(b"MODULE top\nENDMODULE\n"));
        assert!(Made::RuntimeModule.is_own(
            b"MODULE RtWarm(SYSMODULE,NOSTEPIN)\r\n  ! Written by rapidtherm 0.1.0 for the IRB 140"
        ));
        // A cell's own system module (its tools and work objects).
        assert!(!Made::RuntimeModule.is_own(b"MODULE user(SYSMODULE)\n  PERS tooldata tGun:=[TRUE,[[0,0,100],[1,0,0,0]],[1,[0,0,1],[1,0,0,0],0,0,0]];\nENDMODULE\n"));
        assert!(Made::ManPage.is_own(b".ie \\n(.g .ds Aq \\(aq\n.el .ds Aq '\n.TH rapidtherm 1"));
        assert!(!Made::ManPage.is_own(b"time_min,t1_c\n0,20\n"));
    }
}
