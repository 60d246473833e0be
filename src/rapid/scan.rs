//! The cheap lexical pass: cuts a RAPID file into pieces (one declaration,
//! statement, routine head or block keyword each) without building any tree,
//! respecting strings and comments, so that the pest parser only ever holds
//! one piece and memory stays bounded on files of hundreds of MB.

/// What a piece starts with, as far as the cut needs to know.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PieceKind {
    /// `%%% ... %%%`
    Header,
    Module,
    EndModule,
    Record,
    EndRecord,
    /// `PROC`/`FUNC`/`TRAP` head, possibly `LOCAL`.
    Routine,
    /// `ENDPROC`, `ENDFUNC`, `ENDTRAP`.
    EndRoutine,
    Error,
    Backward,
    Undo,
    IfHead,
    CompactIf,
    ElseIf,
    Else,
    EndIf,
    For,
    EndFor,
    While,
    EndWhile,
    Test,
    Case,
    Default,
    EndTest,
    Label,
    /// `<SMT>`-style placeholder standing for a statement or declaration.
    Placeholder,
    /// Anything else: a declaration or a simple statement ending with `;`.
    Simple,
}

#[derive(Debug, Clone, Copy)]
pub struct Piece {
    pub kind: PieceKind,
    pub start: usize,
    pub end: usize,
    /// Byte range of the first word (empty when the piece starts with a
    /// symbol).
    pub first: (usize, usize),
}

/// A lexical problem: too deep nesting (the parser recurses on brackets).
#[derive(Debug)]
pub struct ScanError {
    pub offset: usize,
    pub message: String,
}

/// Brackets deeper than this are refused before the (recursive) parser sees
/// them: no real program comes near, and it keeps the stack safe.
pub const MAX_NESTING: usize = 48;
/// Consecutive sign or NOT operators refused beyond this count.
const MAX_PREFIX_RUN: usize = 16;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tok {
    Word,
    Number,
    Str,
    Sym(u8),
    /// `:=`
    Assign,
    Eof,
}

pub struct Scanner<'a> {
    src: &'a [u8],
    pos: usize,
    /// The first word met longer than a RAPID name may be (its start and
    /// end): every word of a file passes [`Scanner::token`], which cannot
    /// fail, so the piece it is met in reports it.
    too_long: std::cell::Cell<Option<(usize, usize)>>,
}

/// The most characters of a RAPID name: "The maximum length of an
/// identifier is 32 characters" (ABB, Technical reference manual, RAPID
/// kernel, 2.3 Identifiers). The controller refuses a longer one, so the
/// reader does too, in every context (a data name, a routine, a label).
pub const MAX_NAME_CHARS: usize = 32;

/// How many characters a word of `MAX_NAME_CHARS` or more bytes has:
/// UTF-8 characters where it is UTF-8, else each byte one (Latin-1).
fn word_chars(word: &[u8]) -> usize {
    match std::str::from_utf8(word) {
        Ok(s) => s.chars().count(),
        Err(_) => word.len(),
    }
}

fn is_word_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_' || b >= 0x80
}

fn is_word_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80
}

impl<'a> Scanner<'a> {
    pub fn new(src: &'a [u8]) -> Scanner<'a> {
        Scanner {
            src,
            pos: 0,
            too_long: std::cell::Cell::new(None),
        }
    }

    /// Start scanning at `pos` (after a byte-order mark).
    pub fn skip_to(&mut self, pos: usize) {
        self.pos = pos.min(self.src.len());
    }

    /// Where the next piece starts (after blanks and comments).
    pub fn next_start(&self) -> usize {
        self.skip_trivia(self.pos)
    }

    /// Offset of the first byte that is not blank or comment from `p`.
    fn skip_trivia(&self, mut p: usize) -> usize {
        let s = self.src;
        while p < s.len() {
            match s[p] {
                b' ' | b'\t' | b'\r' | b'\n' | 0x0C => p += 1,
                b'!' => {
                    while p < s.len() && s[p] != b'\n' && s[p] != b'\r' {
                        p += 1;
                    }
                }
                _ => break,
            }
        }
        p
    }

    /// The token at `p` (after trivia): kind, start, end.
    fn token(&self, p: usize) -> (Tok, usize, usize) {
        let s = self.src;
        let p = self.skip_trivia(p);
        if p >= s.len() {
            return (Tok::Eof, s.len(), s.len());
        }
        let b = s[p];
        if is_word_start(b) {
            let mut e = p + 1;
            while e < s.len() && is_word_char(s[e]) {
                e += 1;
            }
            if e - p > MAX_NAME_CHARS
                && self.too_long.get().is_none()
                && word_chars(&s[p..e]) > MAX_NAME_CHARS
            {
                self.too_long.set(Some((p, e)));
            }
            (Tok::Word, p, e)
        } else if b.is_ascii_digit() || (b == b'.' && s.get(p + 1).is_some_and(u8::is_ascii_digit))
        {
            let mut e = p + 1;
            while e < s.len() {
                let c = s[e];
                let exponent_sign = (c == b'+' || c == b'-') && matches!(s[e - 1], b'e' | b'E');
                if c.is_ascii_alphanumeric() || c == b'.' || c == b'_' || exponent_sign {
                    e += 1;
                } else {
                    break;
                }
            }
            // `1THEN`: a keyword written against a number (vendor modules
            // that controllers load) ends the number.
            if let Some(k) = (p + 1..e).find(|&k| {
                s[k].is_ascii_alphabetic()
                    && !matches!(
                        s[k - 1],
                        b'e' | b'E' | b'x' | b'X' | b'o' | b'O' | b'b' | b'B'
                    )
                    && !s[p..k].iter().any(|c| matches!(c, b'x' | b'X' | b'_'))
                    && is_keyword_after_number(&s[k..e])
            }) {
                e = k;
            }
            (Tok::Number, p, e)
        } else if b == b'"' {
            let mut e = p + 1;
            loop {
                match s.get(e) {
                    None | Some(b'\n') | Some(b'\r') => break,
                    Some(b'"') if s.get(e + 1) == Some(&b'"') => e += 2,
                    Some(b'"') => {
                        e += 1;
                        break;
                    }
                    Some(_) => e += 1,
                }
            }
            (Tok::Str, p, e)
        } else if b == b':' && s.get(p + 1) == Some(&b'=') {
            (Tok::Assign, p, p + 2)
        } else {
            (Tok::Sym(b), p, p + 1)
        }
    }

    /// Byte ranges of the words (names and keywords) that start in
    /// `start..end`; strings and comments are skipped.
    pub fn words(&self, start: usize, end: usize) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        let mut p = start;
        loop {
            let (t, s, e) = self.token(p);
            if t == Tok::Eof || s >= end {
                return out;
            }
            if t == Tok::Word {
                out.push((s, e));
            }
            p = e;
        }
    }

    fn word_is(&self, start: usize, end: usize, kw: &str) -> bool {
        self.src[start..end].eq_ignore_ascii_case(kw.as_bytes())
    }

    /// The next piece, or `None` at the end of the text.
    pub fn next_piece(&mut self) -> Result<Option<Piece>, ScanError> {
        let (tok, start, first_end) = self.token(self.pos);
        if tok == Tok::Eof {
            self.pos = self.src.len();
            return Ok(None);
        }
        let first = if tok == Tok::Word {
            (start, first_end)
        } else {
            (start, start)
        };
        let upper = if tok == Tok::Word && first_end - start <= 12 {
            let mut w = [0u8; 12];
            for (d, s) in w.iter_mut().zip(&self.src[start..first_end]) {
                *d = s.to_ascii_uppercase();
            }
            w
        } else {
            [0u8; 12]
        };
        let word = std::str::from_utf8(&upper[..(first_end - start).min(12)]).unwrap_or("");
        let word = if tok == Tok::Word { word } else { "" };
        use PieceKind as K;
        let (kind, end) = match (tok, word) {
            (Tok::Sym(b'%'), _) if self.src[start..].starts_with(b"%%%") => {
                let after = start + 3;
                let end =
                    find(&self.src[after..], b"%%%").map_or(self.src.len(), |p| after + p + 3);
                (K::Header, end)
            }
            (Tok::Sym(b'<'), _) if self.placeholder_end(start).is_some() => {
                let mut end = self.placeholder_end(start).unwrap_or(start + 1);
                let (t, _, e) = self.token(end);
                if t == Tok::Sym(b';') {
                    end = e;
                }
                (K::Placeholder, end)
            }
            (Tok::Word, "MODULE") => {
                let (t, _, mut end) = self.token(first_end);
                // `MODULE 1_T_ROB2` (controller backups): a name may start
                // with a digit, which scans as a number.
                if t != Tok::Word && t != Tok::Number {
                    end = first_end;
                }
                let (t, _, _) = self.token(end);
                if t == Tok::Sym(b'(') {
                    end = self.until_close(end)?;
                }
                (K::Module, end)
            }
            (Tok::Word, "ENDMODULE") => (K::EndModule, first_end),
            (Tok::Word, "ENDRECORD") => (K::EndRecord, first_end),
            (Tok::Word, "ENDPROC" | "ENDFUNC" | "ENDTRAP") => (K::EndRoutine, first_end),
            (Tok::Word, "ENDIF") => (K::EndIf, first_end),
            (Tok::Word, "ELSE") => (K::Else, first_end),
            (Tok::Word, "ENDFOR") => (K::EndFor, first_end),
            (Tok::Word, "ENDWHILE") => (K::EndWhile, first_end),
            (Tok::Word, "ENDTEST") => (K::EndTest, first_end),
            (Tok::Word, "BACKWARD") => (K::Backward, first_end),
            (Tok::Word, "UNDO") => (K::Undo, first_end),
            (Tok::Word, "ERROR") => {
                let (t, _, _) = self.token(first_end);
                let end = if t == Tok::Sym(b'(') {
                    self.until_close(first_end)?
                } else {
                    first_end
                };
                (K::Error, end)
            }
            (Tok::Word, "RECORD") => (K::Record, self.words_after(first_end, 1)),
            (Tok::Word, "PROC" | "FUNC") => (K::Routine, self.routine_end(first_end)?),
            (Tok::Word, "TRAP") => (K::Routine, self.words_after(first_end, 1)),
            (Tok::Word, "LOCAL") => {
                let (t, s2, e2) = self.token(first_end);
                if t == Tok::Word && self.word_is(s2, e2, "RECORD") {
                    (K::Record, self.words_after(e2, 1))
                } else if t == Tok::Word && self.word_is(s2, e2, "TRAP") {
                    (K::Routine, self.words_after(e2, 1))
                } else if t == Tok::Word
                    && (self.word_is(s2, e2, "PROC") || self.word_is(s2, e2, "FUNC"))
                {
                    (K::Routine, self.routine_end(e2)?)
                } else {
                    (K::Simple, self.until(first_end, &[], true)?.1)
                }
            }
            (Tok::Word, "IF") => match self.until(first_end, &["THEN"], true)? {
                (true, end) => (K::IfHead, end),
                (false, end) => (K::CompactIf, end),
            },
            (Tok::Word, "ELSEIF") => (K::ElseIf, self.until(first_end, &["THEN"], true)?.1),
            (Tok::Word, "FOR") => (K::For, self.until(first_end, &["DO"], true)?.1),
            (Tok::Word, "WHILE") => (K::While, self.until(first_end, &["DO"], true)?.1),
            (Tok::Word, "TEST") => (
                K::Test,
                self.until(first_end, &["CASE", "DEFAULT", "ENDTEST"], false)?
                    .1,
            ),
            (Tok::Word, "CASE") => (K::Case, self.until_colon(first_end)?),
            (Tok::Word, "DEFAULT") => (K::Default, self.until_colon(first_end)?),
            (Tok::Word, _) => {
                let (t, _, e) = self.token(first_end);
                if t == Tok::Sym(b':') {
                    (K::Label, e)
                } else {
                    (K::Simple, self.until(first_end, &[], true)?.1)
                }
            }
            _ => (K::Simple, self.until(start, &[], true)?.1),
        };
        if let Some((s, e)) = self.too_long.take() {
            let word = crate::error::decode_lossless(&self.src[s..e]);
            return Err(ScanError {
                offset: s,
                message: format!(
                    "the name {} is {} characters long: a RAPID name has at most {MAX_NAME_CHARS} (the controller refuses a longer one)",
                    crate::error::quoted(&word),
                    word_chars(&self.src[s..e])
                ),
            });
        }
        let end = end.max(first_end).min(self.src.len());
        self.pos = end;
        Ok(Some(Piece {
            kind,
            start,
            end,
            first,
        }))
    }

    fn placeholder_end(&self, p: usize) -> Option<usize> {
        let s = self.src;
        let mut e = p + 1;
        while e < s.len() && s[e].is_ascii_uppercase() {
            e += 1;
        }
        (e > p + 1 && s.get(e) == Some(&b'>')).then_some(e + 1)
    }

    /// End of the `n` words after `p` (a RECORD or TRAP name).
    fn words_after(&self, p: usize, n: usize) -> usize {
        let mut end = p;
        for _ in 0..n {
            let (t, _, e) = self.token(end);
            if t != Tok::Word {
                break;
            }
            end = e;
        }
        end
    }

    /// A PROC/FUNC head ends at the `)` closing its parameter list.
    fn routine_end(&self, p: usize) -> Result<usize, ScanError> {
        let mut q = p;
        loop {
            let (t, s, e) = self.token(q);
            match t {
                Tok::Eof => return Ok(e),
                Tok::Sym(b'(') => return self.until_close(s),
                Tok::Sym(b';') => return Ok(e),
                _ => q = e,
            }
        }
    }

    /// From the `(` at `p` to just after its matching `)`.
    fn until_close(&self, p: usize) -> Result<usize, ScanError> {
        let mut depth = 0usize;
        let mut q = p;
        loop {
            let (t, s, e) = self.token(q);
            match t {
                Tok::Eof => return Ok(e),
                Tok::Sym(b'(' | b'[' | b'{') => {
                    depth += 1;
                    if depth > MAX_NESTING {
                        return Err(too_deep(s));
                    }
                }
                Tok::Sym(b')' | b']' | b'}') => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        return Ok(e);
                    }
                }
                Tok::Sym(b';') => return Ok(s),
                _ => {}
            }
            q = e;
        }
    }

    /// Scan to the first of `stops` (words, at bracket depth 0) or `;`.
    /// Returns whether a stop word was found, and the end: after the word
    /// when `include`, before it otherwise; after the `;`.
    fn until(&self, p: usize, stops: &[&str], include: bool) -> Result<(bool, usize), ScanError> {
        let mut depth = 0usize;
        let mut prefix_run = 0usize;
        let mut q = p;
        loop {
            let (t, s, e) = self.token(q);
            match t {
                Tok::Eof => return Ok((false, e)),
                Tok::Sym(b';') => return Ok((false, e)),
                Tok::Sym(b'(' | b'[' | b'{') => {
                    depth += 1;
                    if depth > MAX_NESTING {
                        return Err(too_deep(s));
                    }
                }
                Tok::Sym(b')' | b']' | b'}') => depth = depth.saturating_sub(1),
                Tok::Word if depth == 0 && stops.iter().any(|w| self.word_is(s, e, w)) => {
                    return Ok((true, if include { e } else { s }));
                }
                _ => {}
            }
            let is_prefix =
                matches!(t, Tok::Sym(b'-' | b'+')) || (t == Tok::Word && self.word_is(s, e, "NOT"));
            prefix_run = if is_prefix { prefix_run + 1 } else { 0 };
            if prefix_run > MAX_PREFIX_RUN {
                return Err(ScanError {
                    offset: s,
                    message: format!("more than {MAX_PREFIX_RUN} signs or NOT in a row"),
                });
            }
            q = e;
        }
    }

    /// A CASE/DEFAULT head ends at its `:` (not `:=`).
    fn until_colon(&self, p: usize) -> Result<usize, ScanError> {
        let mut q = p;
        let mut depth = 0usize;
        loop {
            let (t, s, e) = self.token(q);
            match t {
                Tok::Eof => return Ok(e),
                Tok::Sym(b':') | Tok::Sym(b';') => return Ok(e),
                Tok::Sym(b'(' | b'[' | b'{') => {
                    depth += 1;
                    if depth > MAX_NESTING {
                        return Err(too_deep(s));
                    }
                }
                Tok::Sym(b')' | b']' | b'}') => depth = depth.saturating_sub(1),
                _ => {}
            }
            q = e;
        }
    }
}

fn too_deep(offset: usize) -> ScanError {
    ScanError {
        offset,
        message: format!("brackets nested deeper than {MAX_NESTING} levels"),
    }
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Words that may follow a number without a space: what an expression
/// can be followed by (`1THEN`, `10DO`, `5TO`, `2STEP`, `1AND`, `3MOD`).
fn is_keyword_after_number(word: &[u8]) -> bool {
    const WORDS: [&str; 9] = ["THEN", "DO", "TO", "STEP", "AND", "OR", "XOR", "MOD", "DIV"];
    WORDS
        .iter()
        .any(|w| w.as_bytes().eq_ignore_ascii_case(word))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(src: &str) -> Vec<(PieceKind, String)> {
        let mut s = Scanner::new(src.as_bytes());
        let mut out = Vec::new();
        while let Some(p) = s.next_piece().unwrap() {
            out.push((p.kind, src[p.start..p.end].to_string()));
        }
        out
    }

    #[test]
    fn cuts_at_statement_ends_not_inside_strings_or_comments() {
        let k = kinds(
            "MODULE m (SYSMODULE)\n VAR string s := \"a;\"\"b\"; ! c; d\n PROC main(num a)\n IF a THEN\n x:=1;\n ENDIF\n lab:\n ENDPROC\nENDMODULE",
        );
        let got: Vec<_> = k.iter().map(|(k, t)| (*k, t.as_str())).collect();
        assert_eq!(
            got,
            vec![
                (PieceKind::Module, "MODULE m (SYSMODULE)"),
                (PieceKind::Simple, "VAR string s := \"a;\"\"b\";"),
                (PieceKind::Routine, "PROC main(num a)"),
                (PieceKind::IfHead, "IF a THEN"),
                (PieceKind::Simple, "x:=1;"),
                (PieceKind::EndIf, "ENDIF"),
                (PieceKind::Label, "lab:"),
                (PieceKind::EndRoutine, "ENDPROC"),
                (PieceKind::EndModule, "ENDMODULE"),
            ]
        );
    }

    #[test]
    fn refuses_deep_nesting() {
        let src = format!("x := {}1;", "(".repeat(100));
        let mut s = Scanner::new(src.as_bytes());
        assert!(s.next_piece().is_err());
    }
}
