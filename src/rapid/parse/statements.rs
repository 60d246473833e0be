//! Statements and the blocks they nest (IF, FOR, WHILE, TEST), procedure
//! calls and their arguments.

use super::*;

/// Blocks (IF, FOR, ...) nested deeper than this are refused: the
/// assembler recurses on them.
const MAX_BLOCK_DEPTH: usize = 64;

impl FileParser<'_, '_> {
    pub(super) fn statements(&mut self, depth: usize) -> Result<Block> {
        let mut out = Block::default();
        loop {
            // The fast lane reads the moves it knows, into runs (`lane`).
            if self.lane_move(&mut out)? {
                continue;
            }
            let next = self.peek()?;
            let Some(p) = next else {
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
                    let s = self.statement(&p, depth)?;
                    out.stmts.push(s);
                }
                _ => return Ok(out),
            }
        }
    }

    pub(super) fn block_end(&mut self, want: PieceKind, word: &str) -> Result<()> {
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

    pub(super) fn statement(&mut self, p: &Piece, depth: usize) -> Result<Statement> {
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
            K::CompactIf => self.compact_if(p)?,
            K::IfHead => self.if_statement(p, depth)?,
            K::For => self.for_statement(p, depth)?,
            K::While => {
                let cond = self.head_exprs(Rule::while_head, p)?.remove(0);
                let body = self.statements(depth + 1)?;
                self.block_end(K::EndWhile, "ENDWHILE")?;
                StatementKind::While { cond, body }
            }
            K::Test => self.test_statement(p, depth)?,
            _ => {
                let f = self.found(p);
                return Err(self.err(p.start, format!("expected a statement, found {f}")));
            }
        };
        Ok(Statement { pos, kind })
    }

    /// `IF cond stmt;` on one line.
    fn compact_if(&mut self, p: &Piece) -> Result<StatementKind> {
        self.with_pair(Rule::compact_if, p, |s, pair| {
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
        })
    }

    /// `IF ... ELSEIF ... ELSE ... ENDIF`, its head at `p`.
    fn if_statement(&mut self, p: &Piece, depth: usize) -> Result<StatementKind> {
        use PieceKind as K;
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
                None => return Err(self.err(self.src.len(), "expected ENDIF, found end of file")),
            }
        }
        Ok(StatementKind::If {
            branches,
            otherwise,
        })
    }

    /// `FOR var FROM a TO b [STEP c] DO ... ENDFOR`, its head at `p`.
    fn for_statement(&mut self, p: &Piece, depth: usize) -> Result<StatementKind> {
        use PieceKind as K;
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
        Ok(StatementKind::For {
            var,
            from,
            to,
            step,
            body,
        })
    }

    /// `TEST value CASE ... DEFAULT ... ENDTEST`, its head at `p`.
    fn test_statement(&mut self, p: &Piece, depth: usize) -> Result<StatementKind> {
        use PieceKind as K;
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
                None => return Err(self.err(self.src.len(), "expected ENDTEST, found end of file")),
            }
        }
        Ok(StatementKind::Test {
            value,
            cases,
            default,
        })
    }

    /// The expressions of a block head (at least one).
    pub(super) fn head_exprs(&mut self, rule: Rule, p: &Piece) -> Result<Vec<Expr>> {
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

    pub(super) fn simple(&mut self, st: Pair<'_, Rule>, base: usize) -> Result<StatementKind> {
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

    pub(super) fn call<'i>(
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
            .map(|a| {
                arg(
                    a.optional,
                    a.name,
                    a.value.map(|v| self.take_literals(v, &ctx)),
                )
            })
            .collect();
        let call = Call {
            name,
            late_bound,
            args,
            targets: std::mem::take(&mut self.call_targets),
            jointtargets: std::mem::take(&mut self.call_joints),
        };
        // A move the lane covers is made by the one constructor of moves,
        // the lane's too.
        Ok(StatementKind::Call(match MoveParts::of_call(&call) {
            Some(parts) => parts.call(),
            None => call,
        }))
    }

    pub(super) fn args(&mut self, list: Pair<'_, Rule>, base: usize) -> Result<Vec<Arg>> {
        let mut out = Vec::new();
        for a in list.into_inner() {
            let optional = a.as_rule() == Rule::optional_argument;
            let mut name = None;
            let mut value = None;
            for c in a.into_inner() {
                match c.as_rule() {
                    Rule::identifier => name = Some(self.name(&c, base)),
                    Rule::expression => value = Some(self.expr(c, base)?),
                    // `\WObj?WObj`: the value is the routine's parameter.
                    Rule::conditional_value => {
                        if let Some(param) = c.into_inner().next() {
                            value = Some(Expr::Name(self.name(&param, base)));
                        }
                    }
                    _ => {}
                }
            }
            out.push(arg(optional, name, value));
        }
        Ok(out)
    }
}
