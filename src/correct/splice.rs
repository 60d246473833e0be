//! A file's bytes with edits spliced in, written as they come: every
//! edit in file order, each checked against the bytes it replaces (as
//! [`apply_edits`](crate::rapid::rewrite::apply_edits) checks them).

use crate::error::{Error, ErrorKind, Result};
use crate::rapid::rewrite::Edit;
use std::io::Write;
use std::ops::Range;

pub(super) struct Splice<'a> {
    pub src: &'a [u8],
    /// Where the file is written up to.
    pub at: usize,
    pub out: &'a mut dyn Write,
}

impl Splice<'_> {
    /// An edit, after the bytes before it.
    pub fn edit(&mut self, e: &Edit) -> Result<()> {
        let old = self.src.get(e.span.clone());
        if e.span.start < self.at || old != Some(e.expected_old.as_slice()) {
            return Err(internal(e.span.start));
        }
        self.write(e.span.start)?;
        self.out.write_all(&e.new).map_err(write_error)?;
        self.at = e.span.end;
        Ok(())
    }

    /// A number's new text over `span` of the file, after the edits of
    /// `fixed` that come before it.
    pub fn put_after<'e>(
        &mut self,
        fixed: &mut std::iter::Peekable<impl Iterator<Item = &'e Edit>>,
        span: Range<usize>,
        new: &[u8],
    ) -> Result<()> {
        while let Some(x) = fixed.next_if(|x| x.span.start < span.start) {
            self.edit(x)?;
        }
        if span.start < self.at || span.end > self.src.len() {
            return Err(internal(span.start));
        }
        self.write(span.start)?;
        self.out.write_all(new).map_err(write_error)?;
        self.at = span.end;
        Ok(())
    }

    /// Every edit of `fixed` before `to`, and the bytes up to it.
    pub fn finish_at<'e>(
        &mut self,
        fixed: &mut std::iter::Peekable<impl Iterator<Item = &'e Edit>>,
        to: usize,
    ) -> Result<()> {
        while let Some(x) = fixed.next_if(|x| x.span.start < to) {
            self.edit(x)?;
        }
        self.write(to)
    }

    fn write(&mut self, to: usize) -> Result<()> {
        if to < self.at {
            return Err(internal(to));
        }
        self.out
            .write_all(&self.src[self.at..to])
            .map_err(write_error)?;
        self.at = to;
        Ok(())
    }
}

fn internal(at: usize) -> Error {
    Error::input(format!(
        "internal: an edit at byte {at} does not fit the file"
    ))
}

pub(super) fn write_error(e: std::io::Error) -> Error {
    Error::new(ErrorKind::Io, format!("writing the corrected program: {e}"))
}
