//! From bytes to [`Program`]: pieces from the scanner, each parsed by pest
//! with the rule its context calls for, assembled into blocks here; then a
//! pass over the whole run for what needs every file (record types, FUNCs
//! returning robtarget, identifiers unique across modules).

use super::motion::{motion_signature, ArgAt};
use super::scan::{Piece, PieceKind, Scanner};
use super::*;
use crate::error::{decode_lossless, Error, ErrorKind, Location};
use pest::iterators::Pair;
use pest::Parser as _;
use std::collections::{HashMap, HashSet};

#[derive(pest_derive::Parser)]
#[grammar = "../grammar/rapid.pest"]
struct RapidParser;

/// Blocks (IF, FOR, ...) nested deeper than this are refused: the
/// assembler recurses on them.
const MAX_BLOCK_DEPTH: usize = 64;
/// Binary operators in one expression beyond this are refused (the tree
/// is as deep as the chain is long).
const MAX_OPERATORS: usize = 1000;

/// Parse one file (one or several modules).
pub fn parse(file_name: &str, bytes: &[u8]) -> Result<Program> {
    parse_files(&[(file_name, bytes)])
}

/// Parse a run of files together: identifiers are made unique across all
/// their modules, and RECORD types and FUNCs of one file apply to all.
pub fn parse_files(inputs: &[(&str, &[u8])]) -> Result<Program> {
    // Each piece is parsed on its own; a generous call limit turns any
    // pathological backtracking into an error rather than a hang.
    pest::set_call_limit(std::num::NonZeroUsize::new(20_000_000));
    let mut b = Builder::default();
    let mut lines = Vec::new();
    for (i, (name, bytes)) in inputs.iter().enumerate() {
        b.prog.files.push(name.to_string());
        let line_starts = line_starts(bytes);
        FileParser::new(i, name, bytes, &line_starts, &mut b).run()?;
        lines.push(line_starts);
    }
    // RAPID loads one module of a name per task; two would also make the
    // identifiers of the run ambiguous.
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (i, m) in b.prog.modules.iter().enumerate() {
        if let Some(&first) = seen.get(&m.name.to_lowercase()) {
            let f = &b.prog.modules[first];
            let name = inputs.get(m.file).map_or("", |x| x.0);
            let src = inputs.get(m.file).map_or(&[][..], |x| x.1);
            return Err(Error::new(
                ErrorKind::Syntax,
                format!(
                    "module {} is defined twice (also at {}:{})",
                    m.name,
                    inputs.get(f.file).map_or("", |x| x.0),
                    f.pos.line
                ),
            )
            .at(Location::from_offset(name, src, m.pos.offset)));
        }
        seen.insert(m.name.to_lowercase(), i);
    }
    b.finish(inputs, &lines)?;
    Ok(b.prog)
}

fn line_starts(src: &[u8]) -> Vec<usize> {
    let mut v = vec![0];
    v.extend(
        src.iter()
            .enumerate()
            .filter(|(_, &b)| b == b'\n')
            .map(|(i, _)| i + 1),
    );
    v
}

fn pos_of(src: &[u8], lines: &[usize], offset: usize) -> Pos {
    let offset = offset.min(src.len());
    let line = lines.partition_point(|&s| s <= offset).max(1);
    let start = lines.get(line - 1).copied().unwrap_or(0);
    let prefix = &src[start..offset];
    let col = 1 + match std::str::from_utf8(prefix) {
        Ok(s) => s.chars().count(),
        Err(_) => prefix.len(),
    };
    Pos {
        offset,
        line: line as u32,
        col: col as u32,
    }
}

// ------------------------------------------------------------- builder

#[derive(Default)]
struct Builder {
    prog: Program,
    names: HashMap<String, Arc<str>>,
    /// Per routine (lower-case "module\0routine"): literals counted so far.
    inline_counts: HashMap<String, usize>,
}

impl Builder {
    fn intern(&mut self, s: &str) -> Arc<str> {
        if let Some(a) = self.names.get(s) {
            return a.clone();
        }
        let a: Arc<str> = Arc::from(s);
        self.names.insert(s.to_string(), a.clone());
        a
    }
}

/// Instruction context of inline literals.
#[derive(Clone, Default)]
struct InlineCtx {
    instruction: Option<Arc<str>>,
    tool: Option<Arc<str>>,
    wobj: Option<Arc<str>>,
    assigned_to: Option<String>,
}

struct FileParser<'a, 'b> {
    file: usize,
    name: &'a str,
    src: &'a [u8],
    lines: &'a [usize],
    scanner: Scanner<'a>,
    peeked: Option<Piece>,
    b: &'b mut Builder,
    module: Arc<str>,
    routine: Option<Arc<str>>,
    /// Robtarget and jointtarget literals of the current routine so far.
    inline_k: usize,
    joint_k: usize,
    call_targets: Vec<usize>,
    call_joints: Vec<usize>,
}

/// Pest's view of a piece: ASCII as is, every other byte as U+007F, so
/// that offsets are unchanged.
fn piece_text(raw: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(raw) {
        Ok(s) if raw.is_ascii() => std::borrow::Cow::Borrowed(s),
        _ => std::borrow::Cow::Owned(
            raw.iter()
                .map(|&b| if b >= 0x80 { '\u{7F}' } else { b as char })
                .collect(),
        ),
    }
}

fn upper_word(src: &[u8], p: &Piece) -> String {
    String::from_utf8_lossy(&src[p.first.0..p.first.1]).to_ascii_uppercase()
}

impl<'a, 'b> FileParser<'a, 'b> {
    fn new(
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
        }
    }

    fn err(&self, offset: usize, msg: impl Into<String>) -> Error {
        Error::new(ErrorKind::Syntax, msg).at(Location::from_offset(self.name, self.src, offset))
    }

    fn peek(&mut self) -> Result<Option<Piece>> {
        if self.peeked.is_none() {
            self.peeked = self
                .scanner
                .next_piece()
                .map_err(|e| self.err(e.offset, e.message))?;
        }
        Ok(self.peeked)
    }

    fn next(&mut self) -> Result<Option<Piece>> {
        self.peek()?;
        Ok(self.peeked.take())
    }

    fn pos(&self, offset: usize) -> Pos {
        pos_of(self.src, self.lines, offset)
    }

    fn found(&self, p: &Piece) -> String {
        if p.first.1 > p.first.0 {
            format!("`{}`", decode_lossless(&self.src[p.first.0..p.first.1]))
        } else {
            let end = (p.start + 12).min(p.end);
            format!("`{}`", decode_lossless(&self.src[p.start..end]).trim())
        }
    }

    /// Parse a piece with `rule`; `f` builds from the rule's pair.
    fn with_pair<T>(
        &mut self,
        rule: Rule,
        piece: &Piece,
        f: impl FnOnce(&mut Self, Pair<'_, Rule>) -> Result<T>,
    ) -> Result<T> {
        let raw = &self.src[piece.start..piece.end];
        let text = piece_text(raw);
        let mut pairs = match RapidParser::parse(rule, &text) {
            Ok(p) => p,
            Err(e) => {
                // Again with the (slower) record of expected tokens, for
                // the message.
                pest::set_error_detail(true);
                let detailed = RapidParser::parse(rule, &text).err();
                pest::set_error_detail(false);
                return Err(self.pest_error(detailed.as_ref().unwrap_or(&e), piece.start, rule));
            }
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
                    "expected a name, found `{}`, a reserved word of RAPID",
                    id.as_str()
                ),
            ));
        }
        f(self, pair)
    }

    fn pest_error(&self, e: &pest::error::Error<Rule>, base: usize, rule: Rule) -> Error {
        let at = match e.location {
            pest::error::InputLocation::Pos(p) => p,
            pest::error::InputLocation::Span((s, _)) => s,
        };
        let mut expected: Vec<String> = Vec::new();
        let mut push = |s: String| {
            if !expected.contains(&s) {
                expected.push(s);
            }
        };
        if let Some(att) = e.parse_attempts() {
            for t in att.expected_tokens() {
                if let Some(s) = describe_token(&t.to_string()) {
                    push(s);
                }
            }
        }
        if let pest::error::ErrorVariant::ParsingError { positives, .. } = &e.variant {
            for r in positives {
                if *r == Rule::EOI && rule == Rule::test_head {
                    for w in ["CASE", "DEFAULT", "ENDTEST"] {
                        push(w.to_string());
                    }
                }
                if let Some(s) = describe_rule(*r) {
                    push(s.to_string());
                }
            }
        }
        if let pest::error::ErrorVariant::CustomError { message } = &e.variant {
            return self.err(base + at, format!("cannot parse: {message}"));
        }
        order_expected(&mut expected);
        let abs = base + at;
        if self.src.get(abs) == Some(&b'"') {
            return self.err(abs, "string not closed on this line");
        }
        let found = found_at(self.src, abs);
        // A missing `;` (or `,`) is noticed on the next line: point at the
        // end of the line where it belongs, as compilers do.
        let abs = if expected.iter().any(|s| s == "`;`" || s == "`,`") {
            end_of_previous_code(self.src, abs, base)
        } else {
            abs
        };
        let msg = if expected.is_empty() {
            format!("unexpected {found}")
        } else {
            format!("expected {}, found {found}", join_or(&expected))
        };
        self.err(abs, msg)
    }

    // ------------------------------------------------------- structure

    fn run(mut self) -> Result<()> {
        let mut modules = 0;
        loop {
            let Some(p) = self.next()? else {
                if modules == 0 {
                    return Err(self.err(self.src.len(), "expected MODULE, found end of file"));
                }
                return Ok(());
            };
            match p.kind {
                PieceKind::Header if modules == 0 => {
                    self.with_pair(Rule::file_header, &p, |_, _| Ok(()))?;
                }
                PieceKind::Module => {
                    self.module_(&p)?;
                    modules += 1;
                }
                _ => {
                    let f = self.found(&p);
                    return Err(self.err(p.start, format!("expected MODULE, found {f}")));
                }
            }
        }
    }

    fn module_(&mut self, head: &Piece) -> Result<()> {
        let (name, attributes) = self.with_pair(Rule::module_head, head, |s, pair| {
            let mut name = String::new();
            let mut attrs = Vec::new();
            for c in pair.into_inner() {
                match c.as_rule() {
                    Rule::identifier => name = s.text(&c, head.start),
                    Rule::module_attributes => {
                        attrs = c.into_inner().map(|a| s.text(&a, head.start)).collect()
                    }
                    _ => {}
                }
            }
            Ok((name, attrs))
        })?;
        self.module = self.b.intern(&name);
        let mut m = Module {
            name: self.module.clone(),
            file: self.file,
            attributes,
            records: Vec::new(),
            aliases: Vec::new(),
            data: Vec::new(),
            routines: Vec::new(),
            pos: self.pos(head.start),
        };
        loop {
            let Some(p) = self.next()? else {
                return Err(self.err(self.src.len(), "expected ENDMODULE, found end of file"));
            };
            match p.kind {
                PieceKind::EndModule => break,
                PieceKind::Record => m.records.push(self.record(&p)?),
                PieceKind::Routine => m.routines.push(self.routine_(&p)?),
                PieceKind::Placeholder => {}
                PieceKind::Simple => {
                    let w = upper_word(self.src, &p);
                    if w == "ALIAS" || self.second_word_is(&p, "ALIAS") {
                        let a = self.with_pair(Rule::alias_definition, &p, |s, pair| {
                            let mut v = pair
                                .into_inner()
                                .filter(|c| {
                                    matches!(c.as_rule(), Rule::type_name | Rule::identifier)
                                })
                                .map(|c| s.text(&c, p.start));
                            Ok((v.next().unwrap_or_default(), v.next().unwrap_or_default()))
                        })?;
                        m.aliases.push(a);
                    } else if is_decl_word(&w) {
                        let d = self.data_decl(&p)?;
                        m.data.push(d);
                    } else {
                        let f = self.found(&p);
                        return Err(self.err(
                            p.start,
                            format!(
                                "expected a data declaration, a routine or ENDMODULE, found {f}"
                            ),
                        ));
                    }
                }
                _ => {
                    let f = self.found(&p);
                    return Err(self.err(
                        p.start,
                        format!("expected a data declaration, a routine or ENDMODULE, found {f}"),
                    ));
                }
            }
        }
        self.b.prog.modules.push(m);
        Ok(())
    }

    fn second_word_is(&self, p: &Piece, w: &str) -> bool {
        let rest = &self.src[p.first.1..p.end];
        let t = rest
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .unwrap_or(rest.len());
        let rest = &rest[t..];
        rest.len() > w.len()
            && rest[..w.len()].eq_ignore_ascii_case(w.as_bytes())
            && !rest[w.len()].is_ascii_alphanumeric()
    }

    fn record(&mut self, head: &Piece) -> Result<RecordType> {
        let (local, name) = self.with_pair(Rule::record_head, head, |s, pair| {
            let mut local = false;
            let mut name = String::new();
            for c in pair.into_inner() {
                match c.as_rule() {
                    Rule::kw_local => local = true,
                    Rule::identifier => name = s.text(&c, head.start),
                    _ => {}
                }
            }
            Ok((local, name))
        })?;
        let mut components = Vec::new();
        loop {
            let Some(p) = self.next()? else {
                return Err(self.err(self.src.len(), "expected ENDRECORD, found end of file"));
            };
            match p.kind {
                PieceKind::EndRecord => break,
                PieceKind::Simple => {
                    let c = self.with_pair(Rule::record_component, &p, |s, pair| {
                        let mut v = pair
                            .into_inner()
                            .filter(|c| matches!(c.as_rule(), Rule::type_name | Rule::identifier))
                            .map(|c| s.text(&c, p.start));
                        Ok((v.next().unwrap_or_default(), v.next().unwrap_or_default()))
                    })?;
                    components.push(c);
                }
                _ => {
                    let f = self.found(&p);
                    return Err(self.err(
                        p.start,
                        format!(
                            "expected a record component (`type name;`) or ENDRECORD, found {f}"
                        ),
                    ));
                }
            }
        }
        Ok(RecordType {
            name,
            local,
            components,
            pos: self.pos(head.start),
        })
    }

    fn routine_(&mut self, head: &Piece) -> Result<Routine> {
        let mut r = self.with_pair(Rule::routine_head, head, |s, pair| {
            let mut r = Routine {
                kind: RoutineKind::Proc,
                local: false,
                name: Arc::from(""),
                return_type: None,
                params: Vec::new(),
                data: Vec::new(),
                body: Vec::new(),
                backward: None,
                error: None,
                undo: None,
                pos: Pos::default(),
            };
            for c in pair.into_inner() {
                match c.as_rule() {
                    Rule::kw_local => r.local = true,
                    Rule::procedure_head | Rule::function_head | Rule::trap_head => {
                        r.kind = match c.as_rule() {
                            Rule::procedure_head => RoutineKind::Proc,
                            Rule::function_head => RoutineKind::Func,
                            _ => RoutineKind::Trap,
                        };
                        for d in c.into_inner() {
                            match d.as_rule() {
                                Rule::identifier => r.name = s.b.intern(&s.text(&d, head.start)),
                                Rule::type_name => r.return_type = Some(s.text(&d, head.start)),
                                Rule::parameter_list => r.params = s.params(d, head.start),
                                _ => {}
                            }
                        }
                    }
                    _ => {}
                }
            }
            Ok(r)
        })?;
        r.pos = self.pos(head.start);
        self.routine = Some(r.name.clone());
        let key = format!("{}\0{}", self.module.to_lowercase(), r.name.to_lowercase());
        let counts = self.b.inline_counts.get(&key).copied().unwrap_or(0);
        self.inline_k = counts & 0xFFFF_FFFF;
        self.joint_k = counts >> 32;
        // Routine data come first.
        while let Some(p) = self.peek()? {
            if p.kind != PieceKind::Simple || !is_decl_word(&upper_word(self.src, &p)) {
                break;
            }
            self.next()?;
            let d = self.data_decl(&p)?;
            r.data.push(d);
        }
        r.body = self.statements(0)?;
        loop {
            let Some(p) = self.next()? else {
                return Err(self.err(
                    self.src.len(),
                    format!("expected {}, found end of file", end_word(r.kind)),
                ));
            };
            match p.kind {
                PieceKind::Backward if r.backward.is_none() && r.error.is_none() => {
                    self.with_pair(Rule::backward_head, &p, |_, _| Ok(()))?;
                    r.backward = Some(self.statements(0)?);
                }
                PieceKind::Error if r.error.is_none() => {
                    let nums = self.with_pair(Rule::error_head, &p, |s, pair| {
                        pair.into_inner()
                            .filter(|c| c.as_rule() == Rule::expression)
                            .map(|c| s.expr(c, p.start))
                            .collect::<Result<Vec<_>>>()
                    })?;
                    let body = self.statements(0)?;
                    r.error = Some((nums, body));
                }
                PieceKind::Undo if r.undo.is_none() => {
                    self.with_pair(Rule::undo_head, &p, |_, _| Ok(()))?;
                    r.undo = Some(self.statements(0)?);
                }
                PieceKind::EndRoutine => {
                    let w = upper_word(self.src, &p);
                    if w != end_word(r.kind) {
                        return Err(self.err(
                            p.start,
                            format!("expected {}, found `{}`", end_word(r.kind), w),
                        ));
                    }
                    break;
                }
                _ => {
                    let f = self.found(&p);
                    let mut e =
                        self.err(p.start, format!("expected {}, found {f}", end_word(r.kind)));
                    if let Some(note) = stray_note(&upper_word(self.src, &p)) {
                        e = e.with_note(note);
                    }
                    return Err(e);
                }
            }
        }
        self.b
            .inline_counts
            .insert(key, self.inline_k | (self.joint_k << 32));
        self.routine = None;
        Ok(r)
    }

    fn params(&mut self, list: Pair<'_, Rule>, base: usize) -> Vec<Param> {
        let mut out = Vec::new();
        for (group, p) in list.into_inner().enumerate() {
            let optional = p.as_rule() == Rule::optional_parameter;
            let decls: Vec<Pair<'_, Rule>> = if optional {
                p.into_inner().collect()
            } else {
                vec![p]
            };
            for d in decls {
                let mut param = Param {
                    optional,
                    group,
                    access: None,
                    type_name: String::new(),
                    name: String::new(),
                    array_dims: 0,
                };
                let switch = d.as_rule() == Rule::switch_declaration;
                if switch {
                    param.type_name = "switch".into();
                }
                for c in d.into_inner() {
                    match c.as_rule() {
                        Rule::access => param.access = Some(self.text(&c, base).to_uppercase()),
                        Rule::type_name => param.type_name = self.text(&c, base),
                        Rule::identifier => param.name = self.text(&c, base),
                        Rule::array_dim => {
                            param.array_dims = c.as_str().matches('*').count();
                        }
                        _ => {}
                    }
                }
                out.push(param);
            }
        }
        out
    }

    fn statements(&mut self, depth: usize) -> Result<Vec<Statement>> {
        let mut out = Vec::new();
        loop {
            let Some(p) = self.peek()? else {
                return Ok(out);
            };
            use PieceKind as K;
            match p.kind {
                K::Simple
                | K::Label
                | K::Placeholder
                | K::IfHead
                | K::CompactIf
                | K::For
                | K::While
                | K::Test => {
                    self.next()?;
                    out.push(self.statement(&p, depth)?);
                }
                _ => return Ok(out),
            }
        }
    }

    fn block_end(&mut self, want: PieceKind, word: &str) -> Result<()> {
        match self.next()? {
            Some(p) if p.kind == want => Ok(()),
            Some(p) => {
                let f = self.found(&p);
                Err(self.err(p.start, format!("expected {word}, found {f}")))
            }
            None => Err(self.err(
                self.src.len(),
                format!("expected {word}, found end of file"),
            )),
        }
    }

    fn statement(&mut self, p: &Piece, depth: usize) -> Result<Statement> {
        if depth > MAX_BLOCK_DEPTH {
            return Err(self.err(
                p.start,
                format!("blocks nested deeper than {MAX_BLOCK_DEPTH} levels"),
            ));
        }
        let pos = self.pos(p.start);
        use PieceKind as K;
        let kind = match p.kind {
            K::Simple => {
                if is_decl_word(&upper_word(self.src, p)) {
                    return Err(self.err(
                        p.start,
                        "data declarations must come before the first statement of a routine",
                    ));
                }
                self.with_pair(Rule::simple_statement_piece, p, |s, pair| {
                    let Some(st) = pair.into_inner().next() else {
                        return Err(s.err(p.start, "expected a statement"));
                    };
                    s.simple(st, p.start)
                })?
            }
            K::Placeholder => StatementKind::Placeholder(
                decode_lossless(&self.src[p.start..p.end])
                    .trim_end_matches(';')
                    .trim()
                    .to_string(),
            ),
            K::Label => self.with_pair(Rule::label_statement, p, |s, pair| {
                let name = pair
                    .into_inner()
                    .next()
                    .map(|c| s.text(&c, p.start))
                    .unwrap_or_default();
                Ok(StatementKind::Label(name))
            })?,
            K::CompactIf => self.with_pair(Rule::compact_if, p, |s, pair| {
                let mut it = pair.into_inner().filter(|c| c.as_rule() != Rule::kw_if);
                let (Some(c), Some(st)) = (it.next(), it.next()) else {
                    return Err(s.err(p.start, "expected a condition and a statement"));
                };
                let cond = s.expr(c, p.start)?;
                let stpos = s.pos(p.start + st.as_span().start());
                let then = s.simple(st, p.start)?;
                Ok(StatementKind::CompactIf {
                    cond,
                    then: Box::new(Statement {
                        pos: stpos,
                        kind: then,
                    }),
                })
            })?,
            K::IfHead => {
                let cond = self.head_exprs(Rule::if_head, p)?.remove(0);
                let mut branches = vec![(cond, self.statements(depth + 1)?)];
                let mut otherwise = None;
                loop {
                    match self.next()? {
                        Some(q) if q.kind == K::ElseIf && otherwise.is_none() => {
                            let c = self.head_exprs(Rule::elseif_head, &q)?.remove(0);
                            branches.push((c, self.statements(depth + 1)?));
                        }
                        Some(q) if q.kind == K::Else && otherwise.is_none() => {
                            self.with_pair(Rule::else_head, &q, |_, _| Ok(()))?;
                            otherwise = Some(self.statements(depth + 1)?);
                        }
                        Some(q) if q.kind == K::EndIf => break,
                        Some(q) => {
                            let f = self.found(&q);
                            let want = if otherwise.is_some() {
                                "ENDIF"
                            } else {
                                "ELSEIF, ELSE or ENDIF"
                            };
                            return Err(self.err(q.start, format!("expected {want}, found {f}")));
                        }
                        None => {
                            return Err(
                                self.err(self.src.len(), "expected ENDIF, found end of file")
                            )
                        }
                    }
                }
                StatementKind::If {
                    branches,
                    otherwise,
                }
            }
            K::For => {
                let (var, mut e) = self.with_pair(Rule::for_head, p, |s, pair| {
                    let mut var: Arc<str> = Arc::from("");
                    let mut es = Vec::new();
                    for c in pair.into_inner() {
                        match c.as_rule() {
                            Rule::identifier => var = s.name(&c, p.start),
                            Rule::expression => es.push(s.expr(c, p.start)?),
                            _ => {}
                        }
                    }
                    Ok((var, es))
                })?;
                let body = self.statements(depth + 1)?;
                self.block_end(K::EndFor, "ENDFOR")?;
                if e.len() < 2 {
                    return Err(self.err(p.start, "expected FROM and TO"));
                }
                let step = if e.len() > 2 {
                    e.pop().map(Box::new)
                } else {
                    None
                };
                let to = e.pop().unwrap_or(Expr::Bool(false));
                let from = e.pop().unwrap_or(Expr::Bool(false));
                StatementKind::For {
                    var,
                    from,
                    to,
                    step,
                    body,
                }
            }
            K::While => {
                let cond = self.head_exprs(Rule::while_head, p)?.remove(0);
                let body = self.statements(depth + 1)?;
                self.block_end(K::EndWhile, "ENDWHILE")?;
                StatementKind::While { cond, body }
            }
            K::Test => {
                let value = self.head_exprs(Rule::test_head, p)?.remove(0);
                let mut cases = Vec::new();
                let mut default = None;
                loop {
                    match self.next()? {
                        Some(q) if q.kind == K::Case && default.is_none() => {
                            let vals = self.head_exprs(Rule::case_head, &q)?;
                            cases.push((vals, self.statements(depth + 1)?));
                        }
                        Some(q) if q.kind == K::Default && default.is_none() => {
                            self.with_pair(Rule::default_head, &q, |_, _| Ok(()))?;
                            default = Some(self.statements(depth + 1)?);
                        }
                        Some(q) if q.kind == K::EndTest => break,
                        Some(q) => {
                            let f = self.found(&q);
                            return Err(self.err(
                                q.start,
                                format!("expected CASE, DEFAULT or ENDTEST, found {f}"),
                            ));
                        }
                        None => {
                            return Err(
                                self.err(self.src.len(), "expected ENDTEST, found end of file")
                            )
                        }
                    }
                }
                StatementKind::Test {
                    value,
                    cases,
                    default,
                }
            }
            _ => {
                let f = self.found(p);
                return Err(self.err(p.start, format!("expected a statement, found {f}")));
            }
        };
        Ok(Statement { pos, kind })
    }

    /// The expressions of a block head (at least one).
    fn head_exprs(&mut self, rule: Rule, p: &Piece) -> Result<Vec<Expr>> {
        let v = self.with_pair(rule, p, |s, pair| {
            pair.into_inner()
                .filter(|c| c.as_rule() == Rule::expression)
                .map(|c| s.expr(c, p.start))
                .collect::<Result<Vec<_>>>()
        })?;
        if v.is_empty() {
            return Err(self.err(p.start, "expected an expression"));
        }
        Ok(v)
    }

    fn simple(&mut self, st: Pair<'_, Rule>, base: usize) -> Result<StatementKind> {
        let start = base + st.as_span().start();
        let rule = st.as_rule();
        let mut inner = st.into_inner().filter(|c| !is_keyword(c.as_rule()));
        Ok(match rule {
            Rule::placeholder_statement => StatementKind::Placeholder(
                inner
                    .next()
                    .map(|c| c.as_str().to_string())
                    .unwrap_or_default(),
            ),
            Rule::goto_statement => StatementKind::Goto(
                inner
                    .next()
                    .map(|c| self.text(&c, base))
                    .unwrap_or_default(),
            ),
            Rule::return_statement | Rule::raise_statement => {
                let e = match inner.next() {
                    Some(c) => {
                        let e = self.expr(c, base)?;
                        Some(self.take_literals(e, &InlineCtx::default()))
                    }
                    None => None,
                };
                if rule == Rule::return_statement {
                    StatementKind::Return(e)
                } else {
                    StatementKind::Raise(e)
                }
            }
            Rule::exit_statement => StatementKind::Exit,
            Rule::retry_statement => StatementKind::Retry,
            Rule::trynext_statement => StatementKind::TryNext,
            Rule::connect_statement => {
                let (Some(v), Some(t)) = (inner.next(), inner.next()) else {
                    return Err(self.err(start, "expected CONNECT interrupt WITH trap"));
                };
                StatementKind::Connect {
                    interrupt: self.variable(v, base)?,
                    trap: self.text(&t, base),
                }
            }
            Rule::assignment_statement => {
                let (Some(v), Some(e)) = (inner.next(), inner.next()) else {
                    return Err(self.err(start, "expected an assignment"));
                };
                let target = self.variable(v, base)?;
                let ctx = InlineCtx {
                    assigned_to: Some(expr_text(&target)),
                    ..InlineCtx::default()
                };
                let value = self.expr(e, base)?;
                let value = self.take_literals(value, &ctx);
                StatementKind::Assign { target, value }
            }
            Rule::procedure_call => self.call(inner, base, start)?,
            _ => return Err(self.err(start, "expected a statement")),
        })
    }

    fn call<'i>(
        &mut self,
        mut inner: impl Iterator<Item = Pair<'i, Rule>>,
        base: usize,
        start: usize,
    ) -> Result<StatementKind> {
        let Some(name_pair) = inner.next() else {
            return Err(self.err(start, "expected a procedure name"));
        };
        let late_bound = name_pair
            .clone()
            .into_inner()
            .next()
            .is_some_and(|c| c.as_rule() == Rule::late_binding);
        let name = self.name(&name_pair, base);
        let args = match inner.next() {
            Some(list) => self.args(list, base)?,
            None => Vec::new(),
        };
        let sig = motion_signature(&name);
        // A literal where the instruction takes a robtarget must be one.
        if let Some(sig) = &sig {
            let positional: Vec<&Expr> = args
                .iter()
                .filter(|a| !a.optional)
                .filter_map(|a| a.value.as_ref())
                .collect();
            for &i in sig.robtargets {
                if let Some(Expr::Aggregate(a)) = positional.get(i) {
                    if let Err(why) = robtarget_shape(&a.items) {
                        return Err(self
                            .err(
                                a.span.start,
                                format!("this robtarget value of {name} is malformed: {why}"),
                            )
                            .with_note(ROBTARGET_FORM));
                    }
                }
            }
            for &i in sig.jointtargets {
                if let Some(Expr::Aggregate(a)) = positional.get(i) {
                    if let Err(why) = jointtarget_shape(&a.items) {
                        return Err(self
                            .err(
                                a.span.start,
                                format!("this jointtarget value of {name} is malformed: {why}"),
                            )
                            .with_note(JOINTTARGET_FORM));
                    }
                }
            }
        }
        let (tool, wobj) = call_tool_wobj(&name, &args, &HashSet::new());
        let ctx = InlineCtx {
            instruction: Some(name.clone()),
            tool: tool.map(|t| self.b.intern(&t)),
            wobj: wobj.map(|w| self.b.intern(&w)),
            assigned_to: None,
        };
        self.call_targets.clear();
        self.call_joints.clear();
        let args = args
            .into_iter()
            .map(|a| Arg {
                value: a.value.map(|v| self.take_literals(v, &ctx)),
                ..a
            })
            .collect();
        Ok(StatementKind::Call(Call {
            name,
            late_bound,
            args,
            targets: std::mem::take(&mut self.call_targets),
            jointtargets: std::mem::take(&mut self.call_joints),
        }))
    }

    fn args(&mut self, list: Pair<'_, Rule>, base: usize) -> Result<Vec<Arg>> {
        let mut out = Vec::new();
        for a in list.into_inner() {
            let optional = a.as_rule() == Rule::optional_argument;
            let mut name = None;
            let mut value = None;
            for c in a.into_inner() {
                match c.as_rule() {
                    Rule::identifier => name = Some(self.name(&c, base)),
                    Rule::expression => value = Some(self.expr(c, base)?),
                    _ => {}
                }
            }
            out.push(Arg {
                optional,
                name,
                value,
            });
        }
        Ok(out)
    }

    // --------------------------------------------------- declarations

    fn data_decl(&mut self, p: &Piece) -> Result<DataDecl> {
        let mut d = self.with_pair(Rule::data_declaration, p, |s, pair| {
            let Some(decl) = pair.into_inner().next() else {
                return Err(s.err(p.start, "expected a data declaration"));
            };
            let mut d = DataDecl {
                scope: None,
                storage: Storage::Var,
                type_name: String::new(),
                name: String::new(),
                dims: Vec::new(),
                init: None,
                pos: Pos::default(),
            };
            for c in decl.into_inner() {
                match c.as_rule() {
                    Rule::scope => {
                        d.scope = Some(if c.as_str().eq_ignore_ascii_case("LOCAL") {
                            Scope::Local
                        } else {
                            Scope::Task
                        })
                    }
                    Rule::storage => {
                        let t = c.as_str().to_ascii_uppercase();
                        d.storage = match t.as_str() {
                            "CONST" => Storage::Const,
                            "PERS" => Storage::Pers,
                            _ => Storage::Var,
                        }
                    }
                    Rule::type_name => d.type_name = s.text(&c, p.start),
                    Rule::identifier => d.name = s.text(&c, p.start),
                    Rule::dim => {
                        for e in c.into_inner() {
                            d.dims.push(s.expr(e, p.start)?);
                        }
                    }
                    Rule::initializer => {
                        if let Some(e) = c.into_inner().next() {
                            d.init = Some(s.expr(e, p.start)?);
                        }
                    }
                    _ => {}
                }
            }
            Ok(d)
        })?;
        d.pos = self.pos(p.start);
        let ty = d.type_name.to_ascii_lowercase();
        if let Some(init) = d.init.take() {
            let origin_pos = d.pos;
            let init = match ty.as_str() {
                "robtarget" => self.declared_robtargets(&d, init, d.dims.len(), &mut Vec::new())?,
                "jointtarget" => self.declared_joints(&d, init, d.dims.len(), &mut Vec::new())?,
                _ => {
                    if d.dims.is_empty() {
                        self.typed_data(&ty, &d, &init, origin_pos);
                    }
                    init
                }
            };
            d.init = Some(init);
        }
        Ok(d)
    }

    fn origin(&self, offset: usize) -> Origin {
        Origin {
            file: self.file,
            module: self.module.clone(),
            routine: self.routine.clone(),
            pos: self.pos(offset),
        }
    }

    fn decl_id(name: &str, index: &[usize]) -> String {
        if index.is_empty() {
            name.to_string()
        } else {
            let ix: Vec<String> = index.iter().map(|i| i.to_string()).collect();
            format!("{name}{{{}}}", ix.join(","))
        }
    }

    fn declared_robtargets(
        &mut self,
        d: &DataDecl,
        e: Expr,
        dims: usize,
        index: &mut Vec<usize>,
    ) -> Result<Expr> {
        if dims > 0 {
            if let Expr::Aggregate(mut a) = e {
                let items = std::mem::take(&mut a.items);
                let mut out = Vec::with_capacity(items.len());
                for (i, it) in items.into_iter().enumerate() {
                    index.push(i + 1);
                    out.push(self.declared_robtargets(d, it, dims - 1, index)?);
                    index.pop();
                }
                a.items = out;
                return Ok(Expr::Aggregate(a));
            }
            return Ok(e);
        }
        let id = Self::decl_id(&d.name, index);
        let kind = if index.is_empty() {
            TargetKind::Declared
        } else {
            TargetKind::ArrayElement
        };
        match &e {
            Expr::Aggregate(a) => match robtarget_shape(&a.items) {
                Err(why) => Err(self
                    .err(a.span.start, format!("robtarget {id} is malformed: {why}"))
                    .with_note(ROBTARGET_FORM)),
                Ok(Some(value)) => {
                    let t = self.new_target(id, kind, a.span.start, Some(value));
                    let t = Target {
                        name: Some(d.name.clone()),
                        storage: Some(d.storage),
                        ..t
                    };
                    Ok(Expr::Target(self.push_target(t)))
                }
                Ok(None) => {
                    let span = a.span.clone();
                    self.declared_derived(d, id, &e, span);
                    Ok(e)
                }
            },
            Expr::Call(c) => {
                let span = c.span.clone();
                self.declared_derived(d, id, &e, span);
                Ok(e)
            }
            _ => Ok(e),
        }
    }

    fn declared_derived(&mut self, d: &DataDecl, id: String, e: &Expr, span: Range<usize>) {
        let t = self.new_target(id, TargetKind::Derived, span.start, None);
        let t = Target {
            name: Some(d.name.clone()),
            storage: Some(d.storage),
            derived: Some(Box::new(derivation(self.src, e, span))),
            ..t
        };
        self.push_target(t);
    }

    fn new_target(
        &mut self,
        id: String,
        kind: TargetKind,
        offset: usize,
        value: Option<RobTargetValue>,
    ) -> Target {
        Target {
            id,
            kind,
            origin: self.origin(offset),
            name: None,
            storage: None,
            value,
            instruction: None,
            tool: None,
            wobj: None,
            derived: None,
        }
    }

    fn push_target(&mut self, t: Target) -> usize {
        self.b.prog.targets.push(t);
        self.b.prog.targets.len() - 1
    }

    fn declared_joints(
        &mut self,
        d: &DataDecl,
        e: Expr,
        dims: usize,
        index: &mut Vec<usize>,
    ) -> Result<Expr> {
        let Expr::Aggregate(mut a) = e else {
            return Ok(e);
        };
        if dims > 0 {
            let items = std::mem::take(&mut a.items);
            let mut out = Vec::with_capacity(items.len());
            for (i, it) in items.into_iter().enumerate() {
                index.push(i + 1);
                out.push(self.declared_joints(d, it, dims - 1, index)?);
                index.pop();
            }
            a.items = out;
            return Ok(Expr::Aggregate(a));
        }
        let id = Self::decl_id(&d.name, index);
        match jointtarget_shape(&a.items) {
            Err(why) => Err(self
                .err(
                    a.span.start,
                    format!("jointtarget {id} is malformed: {why}"),
                )
                .with_note(JOINTTARGET_FORM)),
            Ok(Some((robax, extax))) => {
                let kind = if index.is_empty() {
                    TargetKind::Declared
                } else {
                    TargetKind::ArrayElement
                };
                let j = JointTarget {
                    id,
                    kind,
                    origin: self.origin(a.span.start),
                    name: Some(d.name.clone()),
                    storage: Some(d.storage),
                    robax,
                    extax,
                    instruction: None,
                    tool: None,
                    wobj: None,
                };
                self.b.prog.jointtargets.push(j);
                Ok(Expr::JointTarget(self.b.prog.jointtargets.len() - 1))
            }
            Ok(None) => Ok(Expr::Aggregate(a)),
        }
    }

    /// tooldata, wobjdata, speeddata, zonedata of the expected shape (other
    /// shapes are left alone: harmless to this tool).
    fn typed_data(&mut self, ty: &str, d: &DataDecl, e: &Expr, pos: Pos) {
        let origin = Origin {
            file: self.file,
            module: self.module.clone(),
            routine: self.routine.clone(),
            pos,
        };
        let name = d.name.clone();
        let storage = d.storage;
        match ty {
            "tooldata" => {
                if let Some(t) = tooldata(e, name, origin, storage) {
                    self.b.prog.tools.push(t);
                }
            }
            "wobjdata" => {
                if let Some(w) = wobjdata(e, name, origin, storage) {
                    self.b.prog.wobjs.push(w);
                }
            }
            "speeddata" => {
                if let Some([a, b, c, d]) = nums::<4>(e) {
                    self.b.prog.speeds.push(SpeedData {
                        name,
                        origin,
                        storage,
                        v_tcp: a,
                        v_ori: b,
                        v_leax: c,
                        v_reax: d,
                    });
                }
            }
            "zonedata" => {
                if let Some(items) = aggregate(e, 7) {
                    if let (Some(finep), Some(values)) = (
                        flag(&items[0]),
                        items[1..]
                            .iter()
                            .map(num)
                            .collect::<Option<Vec<_>>>()
                            .and_then(|v| <[Number; 6]>::try_from(v).ok()),
                    ) {
                        self.b.prog.zones.push(ZoneData {
                            name,
                            origin,
                            storage,
                            finep,
                            values,
                        });
                    }
                }
            }
            _ => {}
        }
    }

    /// Replace robtarget- and jointtarget-shaped literals in a routine
    /// expression by references to new inline targets.
    fn take_literals(&mut self, e: Expr, ctx: &InlineCtx) -> Expr {
        match e {
            Expr::Aggregate(mut a) => {
                if let Ok(Some(value)) = robtarget_shape(&a.items) {
                    self.inline_k += 1;
                    let routine = self.routine.clone().unwrap_or_else(|| Arc::from(""));
                    let id = format!("{}#{}", routine, self.inline_k);
                    let kind = if ctx.assigned_to.is_some() {
                        TargetKind::Assigned
                    } else {
                        TargetKind::Inline
                    };
                    let t = self.new_target(id, kind, a.span.start, Some(value));
                    let t = Target {
                        name: ctx.assigned_to.clone(),
                        instruction: ctx.instruction.clone(),
                        tool: ctx.tool.clone(),
                        wobj: ctx.wobj.clone(),
                        ..t
                    };
                    let i = self.push_target(t);
                    self.call_targets.push(i);
                    return Expr::Target(i);
                }
                if let Ok(Some((robax, extax))) = jointtarget_shape(&a.items) {
                    self.joint_k += 1;
                    let routine = self.routine.clone().unwrap_or_else(|| Arc::from(""));
                    let j = JointTarget {
                        id: format!("{}#{}", routine, self.joint_k),
                        kind: if ctx.assigned_to.is_some() {
                            TargetKind::Assigned
                        } else {
                            TargetKind::Inline
                        },
                        origin: self.origin(a.span.start),
                        name: ctx.assigned_to.clone(),
                        storage: None,
                        robax,
                        extax,
                        instruction: ctx.instruction.clone(),
                        tool: ctx.tool.clone(),
                        wobj: ctx.wobj.clone(),
                    };
                    self.b.prog.jointtargets.push(j);
                    let i = self.b.prog.jointtargets.len() - 1;
                    self.call_joints.push(i);
                    return Expr::JointTarget(i);
                }
                let items = std::mem::take(&mut a.items);
                a.items = items
                    .into_iter()
                    .map(|x| self.take_literals(x, ctx))
                    .collect();
                Expr::Aggregate(a)
            }
            Expr::Call(mut c) => {
                let args = std::mem::take(&mut c.args);
                c.args = args
                    .into_iter()
                    .map(|a| Arg {
                        value: a.value.map(|v| self.take_literals(v, ctx)),
                        ..a
                    })
                    .collect();
                Expr::Call(c)
            }
            Expr::Unary(op, x) => Expr::Unary(op, Box::new(self.take_literals(*x, ctx))),
            Expr::Binary(b) => {
                let (op, x, y) = *b;
                let x = self.take_literals(x, ctx);
                let y = self.take_literals(y, ctx);
                Expr::Binary(Box::new((op, x, y)))
            }
            Expr::Component(b) => {
                let (x, f) = *b;
                Expr::Component(Box::new((self.take_literals(x, ctx), f)))
            }
            other => other,
        }
    }

    // ----------------------------------------------------- expressions

    /// A name as an interned string (the same few names recur millions of
    /// times in a CAM program).
    fn name(&mut self, pair: &Pair<'_, Rule>, base: usize) -> Arc<str> {
        let s = pair.as_span();
        let raw = &self.src[base + s.start()..base + s.end()];
        match std::str::from_utf8(raw) {
            Ok(t) => self.b.intern(t),
            Err(_) => self.b.intern(&decode_lossless(raw)),
        }
    }

    fn text(&self, pair: &Pair<'_, Rule>, base: usize) -> String {
        let s = pair.as_span();
        decode_lossless(&self.src[base + s.start()..base + s.end()])
    }

    fn variable(&mut self, v: Pair<'_, Rule>, base: usize) -> Result<Expr> {
        let mut it = v.into_inner();
        let Some(id) = it.next() else {
            return Ok(Expr::Name(Arc::from("")));
        };
        let mut e = Expr::Name(self.name(&id, base));
        for post in it {
            e = self.postfix(e, post, base)?;
        }
        Ok(e)
    }

    fn postfix(&mut self, e: Expr, post: Pair<'_, Rule>, base: usize) -> Result<Expr> {
        Ok(match post.as_rule() {
            Rule::index => {
                let ix = post
                    .into_inner()
                    .map(|x| self.expr(x, base))
                    .collect::<Result<Vec<_>>>()?;
                Expr::Index(Box::new((e, ix)))
            }
            Rule::component => {
                let f = match post.into_inner().next() {
                    Some(c) => self.name(&c, base),
                    None => Arc::from(""),
                };
                Expr::Component(Box::new((e, f)))
            }
            _ => e,
        })
    }

    fn expr(&mut self, pair: Pair<'_, Rule>, base: usize) -> Result<Expr> {
        let start = base + pair.as_span().start();
        let mut operands: Vec<Expr> = Vec::new();
        let mut ops: Vec<BinaryOp> = Vec::new();
        let mut prefixes: Vec<(UnaryOp, usize)> = Vec::new();
        let mut current: Option<Expr> = None;
        let mut last_prefix_end = 0usize;
        for c in pair.into_inner() {
            let r = c.as_rule();
            match r {
                Rule::prefix_operator => {
                    let op = match c.as_str() {
                        "-" => UnaryOp::Neg,
                        "+" => UnaryOp::Plus,
                        _ => UnaryOp::Not,
                    };
                    prefixes.push((op, base + c.as_span().start()));
                    last_prefix_end = base + c.as_span().end();
                    if prefixes.len() > 16 {
                        return Err(self.err(start, "more than 16 signs or NOT in a row"));
                    }
                }
                Rule::index | Rule::component => {
                    let Some(e) = current.take() else {
                        return Err(self.err(start, "expected an expression"));
                    };
                    current = Some(self.postfix(e, c, base)?);
                }
                Rule::binary_operator => {
                    let Some(e) = current.take() else {
                        return Err(self.err(start, "expected an expression"));
                    };
                    operands.push(e);
                    if ops.len() >= MAX_OPERATORS {
                        return Err(self.err(
                            start,
                            format!("more than {MAX_OPERATORS} operators in one expression"),
                        ));
                    }
                    ops.push(binary_op(c.as_str()));
                }
                _ => {
                    let mut e = self.primary(c, base)?;
                    // Fold a sign written against a number into the literal,
                    // so that its span covers the sign.
                    while let Some((op, at)) = prefixes.pop() {
                        e = match (op, e) {
                            (UnaryOp::Neg, Expr::Num(n)) if n.span().start == last_prefix_end => {
                                Expr::Num(Number::new(-n.value, at..n.span().end))
                            }
                            (UnaryOp::Plus, Expr::Num(n)) if n.span().start == last_prefix_end => {
                                Expr::Num(Number::new(n.value, at..n.span().end))
                            }
                            (op, e) => Expr::Unary(op, Box::new(e)),
                        };
                        last_prefix_end = usize::MAX;
                    }
                    current = Some(e);
                }
            }
        }
        let Some(last) = current else {
            return Err(self.err(start, "expected an expression"));
        };
        operands.push(last);
        Ok(climb(operands, ops))
    }

    fn primary(&mut self, c: Pair<'_, Rule>, base: usize) -> Result<Expr> {
        let span = base + c.as_span().start()..base + c.as_span().end();
        Ok(match c.as_rule() {
            Rule::num_literal => {
                let t = c.as_str();
                let v = parse_num(t)
                    .ok_or_else(|| self.err(span.start, format!("number `{t}` out of range")))?;
                Expr::Num(Number::new(v, span))
            }
            Rule::string_literal => {
                let raw = decode_lossless(&self.src[span.clone()]);
                let inner = raw
                    .get(1..raw.len().saturating_sub(1))
                    .unwrap_or("")
                    .replace("\"\"", "\"");
                Expr::Str(inner.into())
            }
            Rule::bool_literal => Expr::Bool(c.as_str().eq_ignore_ascii_case("TRUE")),
            Rule::placeholder => Expr::Placeholder(c.as_str().into()),
            Rule::parenthesised => match c.into_inner().next() {
                Some(e) => self.expr(e, base)?,
                None => return Err(self.err(span.start, "expected an expression")),
            },
            Rule::aggregate => {
                let items = c
                    .into_inner()
                    .map(|x| self.expr(x, base))
                    .collect::<Result<Vec<_>>>()?;
                Expr::Aggregate(Box::new(Aggregate { items, span }))
            }
            Rule::function_call => {
                let mut it = c.into_inner();
                let name = match it.next() {
                    Some(n) => self.name(&n, base),
                    None => Arc::from(""),
                };
                let args = match it.next() {
                    Some(list) => self.args(list, base)?,
                    None => Vec::new(),
                };
                Expr::Call(Box::new(FunctionCall { name, args, span }))
            }
            Rule::variable => self.variable(c, base)?,
            _ => return Err(self.err(span.start, "expected an expression")),
        })
    }
}

/// The reserved words of RAPID (the grammar's `reserved_word`).
const RESERVED: [&str; 57] = [
    "ALIAS",
    "AND",
    "BACKWARD",
    "CASE",
    "CONNECT",
    "CONST",
    "DEFAULT",
    "DIV",
    "DO",
    "ELSE",
    "ELSEIF",
    "ENDFOR",
    "ENDFUNC",
    "ENDIF",
    "ENDMODULE",
    "ENDPROC",
    "ENDRECORD",
    "ENDTEST",
    "ENDTRAP",
    "ENDWHILE",
    "ERROR",
    "EXIT",
    "FALSE",
    "FOR",
    "FROM",
    "FUNC",
    "GOTO",
    "IF",
    "INOUT",
    "LOCAL",
    "MOD",
    "MODULE",
    "NOSTEPIN",
    "NOT",
    "NOVIEW",
    "OR",
    "PERS",
    "PROC",
    "RAISE",
    "READONLY",
    "RECORD",
    "RETRY",
    "RETURN",
    "STEP",
    "SYSMODULE",
    "TEST",
    "THEN",
    "TO",
    "TRAP",
    "TRUE",
    "TRYNEXT",
    "UNDO",
    "VAR",
    "VIEWONLY",
    "WHILE",
    "WITH",
    "XOR",
];

fn is_reserved(word: &str) -> bool {
    word.len() <= 9 && RESERVED.iter().any(|r| r.eq_ignore_ascii_case(word))
}

/// Why a block keyword may appear where it has no block to close.
fn stray_note(word: &str) -> Option<&'static str> {
    Some(match word {
        "ENDIF" | "ELSE" | "ELSEIF" => {
            "no IF ... THEN is open here (is THEN missing? a one-line IF has no ENDIF)"
        }
        "ENDFOR" => "no FOR ... DO is open here (is DO missing?)",
        "ENDWHILE" => "no WHILE ... DO is open here (is DO missing?)",
        "ENDTEST" | "CASE" | "DEFAULT" => "no TEST is open here",
        _ => return None,
    })
}

fn end_word(k: RoutineKind) -> &'static str {
    match k {
        RoutineKind::Proc => "ENDPROC",
        RoutineKind::Func => "ENDFUNC",
        RoutineKind::Trap => "ENDTRAP",
    }
}

fn is_decl_word(w: &str) -> bool {
    matches!(w, "CONST" | "PERS" | "VAR" | "LOCAL" | "TASK")
}

fn is_keyword(r: Rule) -> bool {
    use Rule as R;
    matches!(
        r,
        R::kw_goto
            | R::kw_return
            | R::kw_raise
            | R::kw_exit
            | R::kw_retry
            | R::kw_trynext
            | R::kw_connect
            | R::kw_with
    )
}

fn binary_op(text: &str) -> BinaryOp {
    use BinaryOp as B;
    match text.to_ascii_uppercase().as_str() {
        "+" => B::Add,
        "-" => B::Sub,
        "*" => B::Mul,
        "/" => B::Div,
        "DIV" => B::IntDiv,
        "MOD" => B::Mod,
        "<" => B::Lt,
        "<=" => B::Le,
        "=" => B::Eq,
        "<>" => B::Ne,
        ">=" => B::Ge,
        ">" => B::Gt,
        "AND" => B::And,
        "OR" => B::Or,
        _ => B::Xor,
    }
}

/// RAPID precedence: `* / DIV MOD` over `+ -` over comparisons over `AND`
/// over `OR XOR`; all left-associative.
fn precedence(op: BinaryOp) -> u8 {
    use BinaryOp as B;
    match op {
        B::Mul | B::Div | B::IntDiv | B::Mod => 5,
        B::Add | B::Sub => 4,
        B::Lt | B::Le | B::Eq | B::Ne | B::Ge | B::Gt => 3,
        B::And => 2,
        B::Or | B::Xor => 1,
    }
}

/// Operator-precedence assembly without recursion (shunting-yard).
fn climb(operands: Vec<Expr>, ops: Vec<BinaryOp>) -> Expr {
    let mut out: Vec<Expr> = Vec::new();
    let mut stack: Vec<BinaryOp> = Vec::new();
    let reduce = |out: &mut Vec<Expr>, op: BinaryOp| {
        if let (Some(b), Some(a)) = (out.pop(), out.pop()) {
            out.push(Expr::Binary(Box::new((op, a, b))));
        }
    };
    let mut operands = operands.into_iter();
    if let Some(first) = operands.next() {
        out.push(first);
    }
    for (op, rhs) in ops.into_iter().zip(operands) {
        while let Some(&top) = stack.last() {
            if precedence(top) >= precedence(op) {
                stack.pop();
                reduce(&mut out, top);
            } else {
                break;
            }
        }
        stack.push(op);
        out.push(rhs);
    }
    while let Some(top) = stack.pop() {
        reduce(&mut out, top);
    }
    out.pop().unwrap_or(Expr::Bool(false))
}

fn parse_num(t: &str) -> Option<f64> {
    let lower = t.to_ascii_lowercase();
    let v = if let Some(h) = lower.strip_prefix("0x") {
        u64::from_str_radix(h, 16).ok()? as f64
    } else if let Some(o) = lower.strip_prefix("0o") {
        u64::from_str_radix(o, 8).ok()? as f64
    } else if let Some(b) = lower.strip_prefix("0b") {
        u64::from_str_radix(b, 2).ok()? as f64
    } else {
        t.parse::<f64>().ok()?
    };
    v.is_finite().then_some(v)
}

fn expr_text(e: &Expr) -> String {
    match e {
        Expr::Name(n) => n.to_string(),
        Expr::Component(b) => format!("{}.{}", expr_text(&b.0), b.1),
        Expr::Index(b) => {
            let ix: Vec<String> = b.1.iter().map(expr_text).collect();
            format!("{}{{{}}}", expr_text(&b.0), ix.join(","))
        }
        Expr::Num(n) => format_num(n.value),
        _ => "?".into(),
    }
}

fn format_num(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

// ------------------------------------------------------------- shapes

const ROBTARGET_FORM: &str =
    "a robtarget is [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a,eax_b,eax_c,eax_d,eax_e,eax_f]]";
const JOINTTARGET_FORM: &str =
    "a jointtarget is [[rax_1,rax_2,rax_3,rax_4,rax_5,rax_6],[eax_a,eax_b,eax_c,eax_d,eax_e,eax_f]]";

fn num(e: &Expr) -> Option<Number> {
    match e {
        Expr::Num(n) => Some(n.clone()),
        _ => None,
    }
}

fn nums<const N: usize>(e: &Expr) -> Option<[Number; N]> {
    let items = aggregate(e, N)?;
    let v: Vec<Number> = items.iter().map(num).collect::<Option<_>>()?;
    v.try_into().ok()
}

fn aggregate(e: &Expr, n: usize) -> Option<&[Expr]> {
    match e {
        Expr::Aggregate(a) if a.items.len() == n => Some(&a.items),
        _ => None,
    }
}

fn flag(e: &Expr) -> Option<Flag> {
    match e {
        Expr::Bool(b) => Some(Flag {
            value: *b,
            span: 0..0,
        }),
        _ => None,
    }
}

/// `Ok(Some)` for a literal robtarget, `Ok(None)` for the right shape with
/// components that are expressions, `Err(why)` for a wrong shape.
fn robtarget_shape(items: &[Expr]) -> std::result::Result<Option<RobTargetValue>, String> {
    const SIZES: [usize; 4] = [3, 4, 4, 6];
    const NAMES: [&str; 4] = ["position", "orientation", "robconf", "extax"];
    if items.len() != 4 {
        return Err(format!("{} parts instead of 4", items.len()));
    }
    let mut all_literal = true;
    for (i, it) in items.iter().enumerate() {
        match it {
            Expr::Aggregate(a) => {
                let sub = &a.items;
                if sub.len() != SIZES[i] {
                    return Err(format!(
                        "{} has {} numbers instead of {}",
                        NAMES[i],
                        sub.len(),
                        SIZES[i]
                    ));
                }
                all_literal &= sub.iter().all(|x| matches!(x, Expr::Num(_)));
            }
            _ => all_literal = false,
        }
    }
    if !all_literal {
        // Components given by expressions or whole parts by name: valid
        // RAPID, but not numbers this tool can rewrite.
        let parts_ok = items
            .iter()
            .all(|x| !matches!(x, Expr::Str(_) | Expr::Bool(_)));
        return if parts_ok {
            Ok(None)
        } else {
            Err("a part is not numeric".into())
        };
    }
    Ok(Some(RobTargetValue {
        trans: nums::<3>(&items[0]).ok_or("position")?,
        rot: nums::<4>(&items[1]).ok_or("orientation")?,
        robconf: nums::<4>(&items[2]).ok_or("robconf")?,
        extax: nums::<6>(&items[3]).ok_or("extax")?,
    }))
}

type JointValue = ([Number; 6], [Number; 6]);

fn jointtarget_shape(items: &[Expr]) -> std::result::Result<Option<JointValue>, String> {
    if items.len() != 2 {
        return Err(format!("{} parts instead of 2", items.len()));
    }
    for (i, it) in items.iter().enumerate() {
        if let Expr::Aggregate(a) = it {
            let sub = &a.items;
            if sub.len() != 6 {
                let what = if i == 0 { "robax" } else { "extax" };
                return Err(format!("{what} has {} numbers instead of 6", sub.len()));
            }
        }
    }
    match (nums::<6>(&items[0]), nums::<6>(&items[1])) {
        (Some(a), Some(b)) => Ok(Some((a, b))),
        _ => Ok(None),
    }
}

fn tooldata(e: &Expr, name: String, origin: Origin, storage: Storage) -> Option<ToolData> {
    let items = aggregate(e, 3)?;
    let robhold = flag(&items[0])?;
    let tframe = aggregate(&items[1], 2)?;
    let load = aggregate(&items[2], 6)?;
    let inertia: Vec<Number> = load[3..].iter().map(num).collect::<Option<_>>()?;
    Some(ToolData {
        name,
        origin,
        storage,
        robhold,
        tframe_trans: nums::<3>(&tframe[0])?,
        tframe_rot: nums::<4>(&tframe[1])?,
        mass: num(&load[0])?,
        cog: nums::<3>(&load[1])?,
        aom: nums::<4>(&load[2])?,
        inertia: inertia.try_into().ok()?,
    })
}

fn wobjdata(e: &Expr, name: String, origin: Origin, storage: Storage) -> Option<WobjData> {
    let items = aggregate(e, 5)?;
    let ufmec = match &items[2] {
        Expr::Str(s) => s.to_string(),
        _ => return None,
    };
    let uf = aggregate(&items[3], 2)?;
    let of = aggregate(&items[4], 2)?;
    Some(WobjData {
        name,
        origin,
        storage,
        robhold: flag(&items[0])?,
        ufprog: flag(&items[1])?,
        ufmec,
        uframe_trans: nums::<3>(&uf[0])?,
        uframe_rot: nums::<4>(&uf[1])?,
        oframe_trans: nums::<3>(&of[0])?,
        oframe_rot: nums::<4>(&of[1])?,
    })
}

// -------------------------------------------------- instruction table

/// Tool and work object an instruction names: `\Tool:=`/`\WObj:=`, the
/// tool position of a known motion instruction, else the first argument
/// naming a declared tooldata (or `tool0`).
fn call_tool_wobj(
    name: &str,
    args: &[Arg],
    tools: &HashSet<String>,
) -> (Option<String>, Option<String>) {
    let opt = |n: &str| {
        args.iter()
            .find(|a| a.optional && a.name.as_deref().is_some_and(|x| x.eq_ignore_ascii_case(n)))
            .and_then(|a| a.value.as_ref())
            .map(expr_text)
    };
    let positional: Vec<&Expr> = args
        .iter()
        .filter(|a| !a.optional)
        .filter_map(|a| a.value.as_ref())
        .collect();
    let mut tool = opt("Tool");
    if tool.is_none() {
        let at = motion_signature(name).and_then(|s| s.tool);
        let i = match at {
            Some(ArgAt::Index(i)) => Some(i),
            Some(ArgAt::FromEnd(k)) => positional.len().checked_sub(k),
            None => None,
        };
        tool = i
            .and_then(|i| positional.get(i))
            .and_then(|e| e.as_name())
            .map(str::to_string);
    }
    if tool.is_none() {
        tool = positional
            .iter()
            .filter_map(|e| e.as_name())
            .find(|n| n.eq_ignore_ascii_case("tool0") || tools.contains(&n.to_lowercase()))
            .map(str::to_string);
    }
    (tool, opt("WObj"))
}

/// Functions of RAPID that return a robtarget.
const ROBTARGET_FUNCTIONS: [&str; 6] = ["offs", "reltool", "crobt", "calcrobt", "mirpos", "orobt"];

fn derivation(src: &[u8], e: &Expr, span: Range<usize>) -> Derivation {
    let mut bases = Vec::new();
    collect_names(e, &mut bases);
    let function = match e {
        Expr::Call(c) => c.name.to_string(),
        _ => String::new(),
    };
    Derivation {
        expr: decode_lossless(src.get(span).unwrap_or(&[])),
        function,
        bases,
    }
}

/// Candidate base targets: every variable an expression reads (filtered
/// to robtargets once the whole run is known).
fn collect_names(e: &Expr, out: &mut Vec<String>) {
    match e {
        Expr::Name(n) => out.push(n.to_string()),
        Expr::Index(b) => {
            let (x, ix) = &**b;
            if let (Expr::Name(n), true) = (x, ix.iter().all(|i| i.as_num().is_some())) {
                let ix: Vec<String> = ix.iter().map(expr_text).collect();
                out.push(format!("{n}{{{}}}", ix.join(",")));
            } else {
                collect_names(x, out);
            }
            for i in ix {
                collect_names(i, out);
            }
        }
        Expr::Component(b) => collect_names(&b.0, out),
        Expr::Call(c) => {
            for a in &c.args {
                if let Some(v) = &a.value {
                    collect_names(v, out);
                }
            }
        }
        Expr::Aggregate(a) => a.items.iter().for_each(|x| collect_names(x, out)),
        Expr::Unary(_, x) => collect_names(x, out),
        Expr::Binary(b) => {
            collect_names(&b.1, out);
            collect_names(&b.2, out);
        }
        _ => {}
    }
}

// ------------------------------------------------------ whole-run pass

impl Builder {
    fn finish(&mut self, inputs: &[(&str, &[u8])], lines: &[Vec<usize>]) -> Result<()> {
        let records: HashMap<String, Vec<(String, String)>> = self
            .prog
            .modules
            .iter()
            .flat_map(|m| &m.records)
            .map(|r| (r.name.to_lowercase(), r.components.clone()))
            .collect();
        let tools: HashSet<String> = self
            .prog
            .modules
            .iter()
            .flat_map(|m| m.data.iter().chain(m.routines.iter().flat_map(|r| &r.data)))
            .filter(|d| d.type_name.eq_ignore_ascii_case("tooldata"))
            .map(|d| d.name.to_lowercase())
            .collect();
        let mut rt_funcs: HashSet<String> =
            ROBTARGET_FUNCTIONS.iter().map(|s| s.to_string()).collect();
        for m in &self.prog.modules {
            for r in &m.routines {
                if r.kind == RoutineKind::Func
                    && r.return_type
                        .as_deref()
                        .is_some_and(|t| t.eq_ignore_ascii_case("robtarget"))
                {
                    rt_funcs.insert(r.name.to_lowercase());
                }
            }
        }

        // Robtargets (and jointtargets) inside declared RECORD values.
        let mut modules = std::mem::take(&mut self.prog.modules);
        for m in &modules {
            let src = inputs.get(m.file).map(|x| x.1).unwrap_or(&[]);
            let ls = lines.get(m.file).map(Vec::as_slice).unwrap_or(&[]);
            let decls = m.data.iter().map(|d| (d, None)).chain(
                m.routines
                    .iter()
                    .flat_map(|r| r.data.iter().map(|d| (d, Some(r.name.clone())))),
            );
            for (d, routine) in decls {
                let ty = d.type_name.to_lowercase();
                let Some(init) = &d.init else { continue };
                if !records.contains_key(&ty) {
                    // A value of a type this run does not define, holding
                    // what looks like robtargets: say so rather than
                    // silently leave them out.
                    if ty != "robtarget" && ty != "jointtarget" && holds_robtarget_shape(init, 0) {
                        let at = decl_offset(init).unwrap_or(d.pos.offset);
                        let loc = Location::from_offset(
                            self.prog.files.get(m.file).map_or("", String::as_str),
                            src,
                            at,
                        );
                        self.prog.warnings.push(Warning {
                            location: loc,
                            message: format!(
                                "{} holds robtarget values, but RECORD {} is not defined in the \
                                 files read: they are not listed (read the module that defines it too)",
                                d.name, d.type_name
                            ),
                        });
                    }
                    continue;
                }
                let mut w = RecordWalk {
                    b: self,
                    records: &records,
                    src,
                    lines: ls,
                    file: m.file,
                    module: m.name.clone(),
                    routine,
                    decl: d,
                };
                w.walk(init, &ty, d.dims.len(), d.name.clone(), 0);
            }
        }

        // Derived targets written in routines, in source order.
        for m in &mut modules {
            let src = inputs.get(m.file).map(|x| x.1).unwrap_or(&[]);
            let ls = lines.get(m.file).map(Vec::as_slice).unwrap_or(&[]);
            for r in &mut m.routines {
                let mut d = DerivedWalk {
                    b: self,
                    rt_funcs: &rt_funcs,
                    tools: &tools,
                    src,
                    lines: ls,
                    file: m.file,
                    module: m.name.clone(),
                    routine: r.name.clone(),
                    k: 0,
                };
                d.stmts(&mut r.body);
                if let Some(b) = &mut r.backward {
                    d.stmts(b);
                }
                if let Some((_, b)) = &mut r.error {
                    d.stmts(b);
                }
                if let Some(b) = &mut r.undo {
                    d.stmts(b);
                }
            }
        }

        // Bases of derived targets: only what names a robtarget of the run.
        let declared: HashSet<String> = self
            .prog
            .targets
            .iter()
            .filter(|t| t.kind != TargetKind::Inline && t.kind != TargetKind::Assigned)
            .filter_map(|t| t.name.as_ref().map(|n| n.to_lowercase()))
            .chain(
                modules
                    .iter()
                    .flat_map(|m| m.data.iter().chain(m.routines.iter().flat_map(|r| &r.data)))
                    .filter(|d| d.type_name.eq_ignore_ascii_case("robtarget"))
                    .map(|d| d.name.to_lowercase()),
            )
            .collect();
        for t in &mut self.prog.targets {
            if let Some(d) = &mut t.derived {
                d.bases.retain(|b| {
                    let base = b.split('{').next().unwrap_or("").to_lowercase();
                    declared.contains(&base)
                });
                d.bases.dedup();
            }
        }

        // Identifiers unique across modules.
        qualify(&mut self.prog.targets, |t| (&t.origin.module, &mut t.id));
        qualify(&mut self.prog.jointtargets, |t| {
            (&t.origin.module, &mut t.id)
        });

        // Source order, and the AST's indices follow.
        let tmap = sort_by_origin(&mut self.prog.targets, |t| &t.origin);
        let jmap = sort_by_origin(&mut self.prog.jointtargets, |t| &t.origin);
        for m in &mut modules {
            for d in &mut m.data {
                if let Some(e) = &mut d.init {
                    remap_expr(e, &tmap, &jmap);
                }
            }
            for r in &mut m.routines {
                for d in &mut r.data {
                    if let Some(e) = &mut d.init {
                        remap_expr(e, &tmap, &jmap);
                    }
                }
                remap_stmts(&mut r.body, &tmap, &jmap);
                for b in [&mut r.backward, &mut r.undo].into_iter().flatten() {
                    remap_stmts(b, &tmap, &jmap);
                }
                if let Some((_, b)) = &mut r.error {
                    remap_stmts(b, &tmap, &jmap);
                }
            }
        }
        self.prog.modules = modules;
        Ok(())
    }
}

/// The name space an identifier is unique in (lower case): the routine
/// for `main#3` / `main@2`, else the declared name (`arr` for `arr{2}`,
/// `w` for `w{3}.pos`).
fn name_space(id: &str) -> String {
    id.split(['#', '@', '{', '.'])
        .next()
        .unwrap_or("")
        .to_lowercase()
}

/// Qualify with the module every identifier whose name space occurs in
/// more than one module of the run.
/// Whether an expression contains a robtarget-shaped literal.
fn holds_robtarget_shape(e: &Expr, depth: usize) -> bool {
    match e {
        Expr::Aggregate(a) if depth < 32 => {
            matches!(robtarget_shape(&a.items), Ok(Some(_)))
                || a.items.iter().any(|x| holds_robtarget_shape(x, depth + 1))
        }
        _ => false,
    }
}

fn decl_offset(e: &Expr) -> Option<usize> {
    match e {
        Expr::Aggregate(a) => Some(a.span.start),
        _ => None,
    }
}

fn qualify<T>(items: &mut [T], f: impl Fn(&mut T) -> (&Arc<str>, &mut String)) {
    let mut modules_of: HashMap<String, HashSet<String>> = HashMap::new();
    for it in items.iter_mut() {
        let (m, id) = f(it);
        modules_of
            .entry(name_space(id))
            .or_default()
            .insert(m.to_lowercase());
    }
    for it in items.iter_mut() {
        let (m, id) = f(it);
        if modules_of.get(&name_space(id)).is_some_and(|s| s.len() > 1) {
            *id = format!("{m}:{id}");
        }
    }
}

/// Sort by (file, offset) in place; returns old index -> new index. Most
/// targets are already in order (only record fields and derived targets
/// are appended later), and the permutation is applied by swaps, so that
/// a list of millions of targets is never copied.
fn sort_by_origin<T>(items: &mut [T], key: impl Fn(&T) -> &Origin) -> Vec<usize> {
    let k = |t: &T| {
        let o = key(t);
        (o.file, o.pos.offset)
    };
    if items.windows(2).all(|w| k(&w[0]) <= k(&w[1])) {
        return (0..items.len()).collect();
    }
    // order[new] = old
    let mut order: Vec<usize> = (0..items.len()).collect();
    order.sort_by_key(|&i| k(&items[i]));
    let mut map = vec![0; items.len()];
    for (new, &old) in order.iter().enumerate() {
        map[old] = new;
    }
    // Move each item to its place: follow the cycles of `map`.
    let mut place = map.clone();
    for i in 0..items.len() {
        while place[i] != i {
            let j = place[i];
            items.swap(i, j);
            place.swap(i, j);
        }
    }
    map
}

fn remap_expr(e: &mut Expr, t: &[usize], j: &[usize]) {
    match e {
        Expr::Target(i) => *i = t.get(*i).copied().unwrap_or(*i),
        Expr::JointTarget(i) => *i = j.get(*i).copied().unwrap_or(*i),
        Expr::Aggregate(a) => a.items.iter_mut().for_each(|x| remap_expr(x, t, j)),
        Expr::Call(c) => c
            .args
            .iter_mut()
            .filter_map(|a| a.value.as_mut())
            .for_each(|x| remap_expr(x, t, j)),
        Expr::Unary(_, x) => remap_expr(x, t, j),
        Expr::Component(b) => remap_expr(&mut b.0, t, j),
        Expr::Binary(b) => {
            remap_expr(&mut b.1, t, j);
            remap_expr(&mut b.2, t, j);
        }
        Expr::Index(b) => {
            remap_expr(&mut b.0, t, j);
            b.1.iter_mut().for_each(|x| remap_expr(x, t, j));
        }
        _ => {}
    }
}

fn remap_stmts(stmts: &mut [Statement], t: &[usize], j: &[usize]) {
    for s in stmts {
        for_each_expr_and_block(s, &mut |e| remap_expr(e, t, j), &mut |b| {
            remap_stmts(b, t, j)
        });
        if let StatementKind::Call(c) = &mut s.kind {
            c.targets
                .iter_mut()
                .for_each(|i| *i = t.get(*i).copied().unwrap_or(*i));
            c.jointtargets
                .iter_mut()
                .for_each(|i| *i = j.get(*i).copied().unwrap_or(*i));
        }
    }
}

/// Visit the expressions of a statement and its nested blocks.
fn for_each_expr_and_block(
    s: &mut Statement,
    fe: &mut dyn FnMut(&mut Expr),
    fb: &mut dyn FnMut(&mut Vec<Statement>),
) {
    match &mut s.kind {
        StatementKind::Call(c) => c
            .args
            .iter_mut()
            .filter_map(|a| a.value.as_mut())
            .for_each(fe),
        StatementKind::Assign { target, value } => {
            fe(target);
            fe(value);
        }
        StatementKind::If {
            branches,
            otherwise,
        } => {
            for (c, b) in branches {
                fe(c);
                fb(b);
            }
            if let Some(b) = otherwise {
                fb(b);
            }
        }
        StatementKind::CompactIf { cond, then } => {
            fe(cond);
            for_each_expr_and_block(then, fe, fb);
        }
        StatementKind::For {
            from,
            to,
            step,
            body,
            ..
        } => {
            fe(from);
            fe(to);
            if let Some(s) = step {
                fe(s);
            }
            fb(body);
        }
        StatementKind::While { cond, body } => {
            fe(cond);
            fb(body);
        }
        StatementKind::Test {
            value,
            cases,
            default,
        } => {
            fe(value);
            for (vs, b) in cases {
                vs.iter_mut().for_each(&mut *fe);
                fb(b);
            }
            if let Some(b) = default {
                fb(b);
            }
        }
        StatementKind::Return(Some(e)) | StatementKind::Raise(Some(e)) => fe(e),
        StatementKind::Connect { interrupt, .. } => fe(interrupt),
        _ => {}
    }
}

struct RecordWalk<'a> {
    b: &'a mut Builder,
    records: &'a HashMap<String, Vec<(String, String)>>,
    src: &'a [u8],
    lines: &'a [usize],
    file: usize,
    module: Arc<str>,
    routine: Option<Arc<str>>,
    decl: &'a DataDecl,
}

impl RecordWalk<'_> {
    fn origin(&self, offset: usize) -> Origin {
        Origin {
            file: self.file,
            module: self.module.clone(),
            routine: self.routine.clone(),
            pos: pos_of(self.src, self.lines, offset),
        }
    }

    fn walk(&mut self, e: &Expr, ty: &str, dims: usize, path: String, depth: usize) {
        if depth > 32 {
            return;
        }
        let Expr::Aggregate(a) = e else {
            return;
        };
        let (items, span) = (&a.items, &a.span);
        if dims > 0 {
            // Arrays of records: `w{3}`; 2-D `w{2,4}`.
            let (base, prefix) = match path.strip_suffix('}') {
                Some(p) if path.contains('{') && dims > 0 && self.decl.dims.len() > dims => {
                    (p.to_string(), ",")
                }
                _ => (path.clone(), "{"),
            };
            for (i, it) in items.iter().enumerate() {
                let p = format!("{base}{prefix}{}}}", i + 1);
                self.walk(it, ty, dims - 1, p, depth + 1);
            }
            return;
        }
        match ty {
            "robtarget" => {
                let (value, derived) = match robtarget_shape(items) {
                    Ok(Some(v)) => (Some(v), None),
                    Ok(None) => (None, Some(Box::new(derivation(self.src, e, span.clone())))),
                    Err(_) => return,
                };
                self.b.prog.targets.push(Target {
                    id: path,
                    kind: TargetKind::RecordField,
                    origin: self.origin(span.start),
                    name: Some(self.decl.name.clone()),
                    storage: Some(self.decl.storage),
                    value,
                    instruction: None,
                    tool: None,
                    wobj: None,
                    derived,
                });
            }
            "jointtarget" => {
                if let Ok(Some((robax, extax))) = jointtarget_shape(items) {
                    self.b.prog.jointtargets.push(JointTarget {
                        id: path,
                        kind: TargetKind::RecordField,
                        origin: self.origin(span.start),
                        name: Some(self.decl.name.clone()),
                        storage: Some(self.decl.storage),
                        robax,
                        extax,
                        instruction: None,
                        tool: None,
                        wobj: None,
                    });
                }
            }
            _ => {
                let Some(comps) = self.records.get(ty) else {
                    return;
                };
                if comps.len() != items.len() {
                    return;
                }
                for ((cty, cname), it) in comps.iter().zip(items) {
                    let cty = cty.to_lowercase();
                    if cty == "robtarget" || cty == "jointtarget" || self.records.contains_key(&cty)
                    {
                        self.walk(it, &cty, 0, format!("{path}.{cname}"), depth + 1);
                    }
                }
            }
        }
    }
}

struct DerivedWalk<'a> {
    b: &'a mut Builder,
    rt_funcs: &'a HashSet<String>,
    tools: &'a HashSet<String>,
    src: &'a [u8],
    lines: &'a [usize],
    file: usize,
    module: Arc<str>,
    routine: Arc<str>,
    k: usize,
}

impl DerivedWalk<'_> {
    fn is_rt_call(&self, e: &Expr) -> bool {
        matches!(e, Expr::Call(c) if self.rt_funcs.contains(&c.name.to_lowercase()))
    }

    fn derived(&mut self, e: &Expr, name: Option<String>, call: Option<(&str, &[Arg])>) -> usize {
        let Expr::Call(c) = e else {
            return usize::MAX;
        };
        let span = &c.span;
        self.k += 1;
        let (instruction, tool, wobj) = match call {
            Some((n, args)) => {
                let (t, w) = call_tool_wobj(n, args, self.tools);
                (
                    Some(self.b.intern(n)),
                    t.map(|t| self.b.intern(&t)),
                    w.map(|w| self.b.intern(&w)),
                )
            }
            None => (None, None, None),
        };
        self.b.prog.targets.push(Target {
            id: format!("{}@{}", self.routine, self.k),
            kind: TargetKind::Derived,
            origin: Origin {
                file: self.file,
                module: self.module.clone(),
                routine: Some(self.routine.clone()),
                pos: pos_of(self.src, self.lines, span.start),
            },
            name,
            storage: None,
            value: None,
            instruction,
            tool,
            wobj,
            derived: Some(Box::new(derivation(self.src, e, span.clone()))),
        });
        self.b.prog.targets.len() - 1
    }

    fn stmts(&mut self, stmts: &mut [Statement]) {
        for s in stmts {
            self.stmt(s);
        }
    }

    fn stmt(&mut self, s: &mut Statement) {
        match &mut s.kind {
            StatementKind::Call(c) => {
                let (t, _) = call_tool_wobj(&c.name, &c.args, self.tools);
                // Literals whose instruction's tool is only known now.
                if let Some(t) = t {
                    let t = self.b.intern(&t);
                    for &i in &c.targets {
                        if let Some(x) = self.b.prog.targets.get_mut(i) {
                            if x.tool.is_none() {
                                x.tool = Some(t.clone());
                            }
                        }
                    }
                }
                let mut found = Vec::new();
                for a in &c.args {
                    if let Some(v) = &a.value {
                        if self.is_rt_call(v) {
                            found.push(self.derived(v, None, Some((&c.name, &c.args))));
                        }
                    }
                }
                c.targets.extend(found);
                c.targets.sort_by_key(|&i| {
                    self.b
                        .prog
                        .targets
                        .get(i)
                        .map_or(0, |t| t.origin.pos.offset)
                });
            }
            StatementKind::Assign { target, value } if self.is_rt_call(value) => {
                self.derived(value, Some(expr_text(target)), None);
            }
            StatementKind::Return(Some(e)) if self.is_rt_call(e) => {
                self.derived(e, None, None);
            }
            StatementKind::CompactIf { then, .. } => self.stmt(then),
            StatementKind::If {
                branches,
                otherwise,
            } => {
                for (_, b) in branches {
                    self.stmts(b);
                }
                if let Some(b) = otherwise {
                    self.stmts(b);
                }
            }
            StatementKind::For { body, .. } | StatementKind::While { body, .. } => self.stmts(body),
            StatementKind::Test { cases, default, .. } => {
                for (_, b) in cases {
                    self.stmts(b);
                }
                if let Some(b) = default {
                    self.stmts(b);
                }
            }
            _ => {}
        }
    }
}

// ------------------------------------------------------ error messages

fn describe_rule(r: Rule) -> Option<&'static str> {
    use Rule as R;
    Some(match r {
        R::identifier | R::type_name | R::assignment_target => "a name",
        R::num_literal => "a number",
        R::expression
        | R::string_literal
        | R::bool_literal
        | R::aggregate
        | R::placeholder
        | R::parenthesised
        | R::function_call
        | R::variable
        | R::initializer
        | R::prefix_operator => "an expression",
        R::binary_operator => "an operator",
        R::storage | R::kw_const | R::kw_pers | R::kw_var => "CONST, PERS or VAR",
        R::scope | R::kw_local | R::kw_task => "LOCAL or TASK",
        R::optional_argument => "an optional argument",
        R::required_argument | R::procedure_argument_list | R::function_argument_list => {
            "an argument"
        }
        R::index => "`{`",
        R::component => "`.`",
        R::dim => "`{`",
        R::parameter_list | R::parameter_declaration | R::optional_parameter => "a parameter",
        R::header_entry => "`VERSION:`/`LANGUAGE:`",
        R::kw_then => "THEN",
        R::kw_do => "DO",
        R::kw_from => "FROM",
        R::kw_to => "TO",
        R::kw_step => "STEP",
        R::kw_with => "WITH",
        R::kw_proc => "PROC",
        R::kw_func => "FUNC",
        R::kw_trap => "TRAP",
        R::kw_record => "RECORD",
        R::kw_module => "MODULE",
        R::kw_if => "IF",
        R::procedure_call
        | R::assignment_statement
        | R::goto_statement
        | R::return_statement
        | R::raise_statement
        | R::exit_statement
        | R::retry_statement
        | R::trynext_statement
        | R::connect_statement
        | R::placeholder_statement => "a statement",
        R::EOI => "the end of the statement",
        R::late_binding => "a procedure name",
        R::module_attributes => "`(`",
        R::module_attribute => "SYSMODULE, NOVIEW, NOSTEPIN, VIEWONLY or READONLY",
        R::access => "VAR, PERS or INOUT",
        R::array_dim => "`{*}`",
        _ => return None,
    })
}

fn describe_token(token: &str) -> Option<String> {
    if token == "BUILTIN_RULE"
        || (token.len() > 3 && token.contains(".."))
        || token.is_empty()
        || token == "!"
        || token
            .chars()
            .all(|c| c.is_control() || c.is_whitespace() || c == '_')
        || (token.len() == 1 && token.chars().all(|c| c.is_ascii_alphanumeric()))
    {
        return None;
    }
    {
        {
            Some(match token {
                "+" | "-" | "*" | "/" | "<" | ">" | "<=" | ">=" | "<>" | "=" | "AND" | "OR"
                | "XOR" | "DIV" | "MOD" => "an operator".to_string(),
                "\\" => "an optional argument".to_string(),
                "\"" => "a string".to_string(),
                "0" => return None,
                "." | "E" | "e" | "x" | "o" | "b" => return None,
                t if t.chars().all(|c| c.is_ascii_alphabetic()) => t.to_ascii_uppercase(),
                t => format!("`{t}`"),
            })
        }
    }
}

/// Most useful words first: closing punctuation, keywords, then the
/// general ones; what is possible after almost any name (`(`, `{`, `.`,
/// `:=`) only when little else fits.
fn order_expected(v: &mut Vec<String>) {
    let minor = |s: &str| matches!(s, "`(`" | "`{`" | "`.`" | "`:=`");
    let rank = |s: &str| -> u8 {
        if minor(s) {
            6
        } else if s.starts_with('`') {
            0
        } else if s
            .chars()
            .all(|c| c.is_ascii_uppercase() || c == ',' || c == ' ')
        {
            1
        } else if s == "an expression" || s == "a name" || s == "a statement" {
            2
        } else if s == "an optional argument" {
            3
        } else if s == "an operator" {
            4
        } else {
            5
        }
    };
    v.sort_by_key(|s| rank(s));
    if v.iter().any(|s| s == "an expression") {
        v.retain(|s| s != "a string" && s != "a number" && s != "a name");
    }
    if v.iter().filter(|s| !minor(s)).count() >= 2 {
        v.retain(|s| !minor(s));
    }
    v.retain(|s| s != "the end of the statement");
    v.truncate(5);
}

fn join_or(v: &[String]) -> String {
    match v {
        [] => String::new(),
        [a] => a.clone(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// If only blanks and line breaks separate `offset` from the code before
/// it (not before `floor`), the end of that code (before any comment).
fn end_of_previous_code(src: &[u8], offset: usize, floor: usize) -> usize {
    let mut p = offset.min(src.len());
    let mut crossed = false;
    while p > floor && src[p - 1].is_ascii_whitespace() {
        crossed |= src[p - 1] == b'\n';
        p -= 1;
    }
    if !crossed {
        return offset;
    }
    // The line ending at `p`: cut a comment (a `!` outside strings).
    let start = src[..p]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let mut in_str = false;
    let mut end = p;
    for (i, &b) in src[start..p].iter().enumerate() {
        match b {
            b'"' => in_str = !in_str,
            b'!' if !in_str => {
                end = start + i;
                break;
            }
            _ => {}
        }
    }
    while end > start && src[end - 1].is_ascii_whitespace() {
        end -= 1;
    }
    if end <= floor.max(start) && end == start {
        offset
    } else {
        end
    }
}

/// What is at `offset`, for "found ...".
fn found_at(src: &[u8], offset: usize) -> String {
    let rest = &src[offset.min(src.len())..];
    let Some(&b) = rest.first() else {
        return "end of file".into();
    };
    if b == b'\n' || b == b'\r' {
        return "end of line".into();
    }
    let len = if b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80 || b == b'.' {
        rest.iter()
            .position(|&c| !(c.is_ascii_alphanumeric() || c == b'_' || c >= 0x80 || c == b'.'))
            .unwrap_or(rest.len())
    } else if rest.starts_with(b":=") {
        2
    } else {
        1
    };
    format!("`{}`", decode_lossless(&rest[..len.min(24)]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reserved_list_matches_the_grammar() {
        for w in RESERVED {
            assert!(
                RapidParser::parse(Rule::reserved_word, w).is_ok(),
                "{w} not in the grammar"
            );
        }
    }
}
