//! The rule every write of a run goes through: every path the run will
//! write is planned before it reads anything ([`Plan`]), then checked at
//! once ([`Plan::check`]): against every input and every other output by
//! the file's identity (device and inode, through links and any spelling
//! of the path); a file the user did not name as an output (a picture in a
//! `--plot` folder, the `--runtime` module, a man page) replaced only where
//! it is one of rapidtherm's own making, or with `force`; in place only
//! regular files of one name (no FIFO, device, folder or hard-linked
//! file); every file to be replaced locked, so that a second run on it is
//! refused instead of one being lost. The [`Checked`] plan holds the locks
//! until it is dropped, after the files are in place; the binary writes
//! only paths it lists.

mod check;
mod identity;
mod lock;
mod own;
mod plan;

pub use check::{Checked, Planned};
pub use identity::{key, Key};
pub use own::Made;
pub use plan::{Output, Plan, Role};
