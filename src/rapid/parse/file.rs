//! The state of one file's parse: the scanner's pieces, where the parse
//! is, and the glue to pest ([`FileParser::with_pair`]: a piece parsed
//! with the rule its context calls for).

use super::*;

pub(super) struct FileParser<'a, 'b> {
    pub file: usize,
    pub name: &'a str,
    pub src: &'a [u8],
    pub lines: &'a [usize],
    pub scanner: Scanner<'a>,
    pub peeked: Option<Piece>,
    pub b: &'b mut Builder,
    pub module: Arc<str>,
    pub routine: Option<Arc<str>>,
    /// Robtarget and jointtarget literals of the current routine so far.
    pub inline_k: usize,
    pub joint_k: usize,
    pub call_targets: Vec<usize>,
    pub call_joints: Vec<usize>,
    /// What the fast lane has looked up already.
    pub seen: Seen<'a>,
    /// The declaration run the next declaration the lane reads joins,
    /// while nothing else came between.
    pub open_decls: Option<usize>,
    /// What the fast lane read ahead of the parse, on every core.
    pub ahead: Ahead,
}

/// Pest's view of a piece: ASCII as is, every other byte as U+007F, so
/// that offsets are unchanged.
pub(super) fn piece_text(raw: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(raw) {
        Ok(s) if raw.is_ascii() => std::borrow::Cow::Borrowed(s),
        _ => std::borrow::Cow::Owned(
            raw.iter()
                .map(|&b| if b >= 0x80 { '\u{7F}' } else { b as char })
                .collect(),
        ),
    }
}

pub(super) fn upper_word(src: &[u8], p: &Piece) -> String {
    String::from_utf8_lossy(&src[p.first.0..p.first.1]).to_ascii_uppercase()
}

impl<'a, 'b> FileParser<'a, 'b> {
    pub fn new(
        file: usize,
        name: &'a str,
        src: &'a [u8],
        lines: &'a [usize],
        b: &'b mut Builder,
    ) -> Self {
        let mut scanner = Scanner::new(src);
        if src.starts_with(&[0xEF, 0xBB, 0xBF]) {
            scanner.skip_to(3);
        }
        FileParser {
            file,
            name,
            src,
            lines,
            scanner,
            peeked: None,
            b,
            module: Arc::from(""),
            routine: None,
            inline_k: 0,
            joint_k: 0,
            call_targets: Vec::new(),
            call_joints: Vec::new(),
            seen: Seen::default(),
            open_decls: None,
            ahead: Ahead::default(),
        }
    }

    pub fn err(&self, offset: usize, msg: impl Into<String>) -> Error {
        Error::new(ErrorKind::Syntax, msg).at(Location::from_offset(self.name, self.src, offset))
    }

    pub fn peek(&mut self) -> Result<Option<Piece>> {
        if self.peeked.is_none() {
            self.peeked = self
                .scanner
                .next_piece()
                .map_err(|e| self.err(e.offset, e.message))?;
        }
        Ok(self.peeked)
    }

    pub fn next(&mut self) -> Result<Option<Piece>> {
        self.peek()?;
        Ok(self.peeked.take())
    }

    pub fn pos(&self, offset: usize) -> Pos {
        pos_of(self.src, self.lines, offset)
    }

    pub fn found(&self, p: &Piece) -> String {
        if p.first.1 > p.first.0 {
            crate::error::quoted(&decode_lossless(&self.src[p.first.0..p.first.1]))
        } else {
            let end = (p.start + 12).min(p.end);
            crate::error::quoted(decode_lossless(&self.src[p.start..end]).trim())
        }
    }

    /// Parse a piece with `rule`; `f` builds from the rule's pair.
    pub fn with_pair<T>(
        &mut self,
        rule: Rule,
        piece: &Piece,
        f: impl FnOnce(&mut Self, Pair<'_, Rule>) -> Result<T>,
    ) -> Result<T> {
        let raw = &self.src[piece.start..piece.end];
        let text = piece_text(raw);
        let mut pairs = match grammar::read(rule, &text) {
            Ok(p) => p,
            Err(e) => return Err(self.pest_error(&e, &text, piece.start, rule)),
        };
        let Some(pair) = pairs.next() else {
            return Err(self.err(piece.start, "internal: empty parse"));
        };
        if let Some(id) = pair
            .clone()
            .into_inner()
            .flatten()
            .find(|p| p.as_rule() == Rule::identifier && is_reserved(p.as_str()))
        {
            return Err(self.err(
                piece.start + id.as_span().start(),
                format!(
                    "expected a name, found {}, a reserved word of RAPID",
                    crate::error::quoted(id.as_str())
                ),
            ));
        }
        f(self, pair)
    }
}
