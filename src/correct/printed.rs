//! The writer a corrected file goes through: it reads the numbers of
//! what it writes, for the fingerprint the file's marker seals.

use crate::rapid::numprint::NumberPrint;
use std::io::Write;

/// A writer that reads the numbers of what it writes: what is written
/// (a number's new text, the bytes between two) is read a piece of
/// [`PRINT_PIECE`] at a time, so that few tokens are cut between pieces.
pub(super) struct Printed<'w> {
    pub out: &'w mut (dyn Write + Send),
    pub print: NumberPrint,
    pub held: Vec<u8>,
}

/// How much the fingerprint reads at a time.
pub(super) const PRINT_PIECE: usize = 1 << 16;

impl Printed<'_> {
    /// A chunk's bytes, whose tokens were read on its core where given:
    /// whether they were taken (else the bytes were read here).
    pub fn chunk(&mut self, bytes: &[u8], tokens: Option<&[u8]>) -> std::io::Result<bool> {
        self.out.write_all(bytes)?;
        self.print.feed(&self.held);
        self.held.clear();
        let taken = tokens.is_some_and(|t| self.print.absorb(t));
        if !taken {
            self.print.feed(bytes);
        }
        Ok(taken)
    }
}

impl Write for Printed<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.out.write(buf)?;
        self.held.extend_from_slice(&buf[..n]);
        if self.held.len() >= PRINT_PIECE {
            self.print.feed(&self.held);
            self.held.clear();
        }
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}
