//! Program structure: modules, RECORD types, routines, statement blocks,
//! simple statements, procedure calls and their arguments.

use super::*;

impl<'a, 'b> FileParser<'a, 'b> {
    pub(super) fn run(mut self) -> Result<()> {
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

    pub(super) fn module_(&mut self, head: &Piece) -> Result<()> {
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

    pub(super) fn second_word_is(&self, p: &Piece, w: &str) -> bool {
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

    pub(super) fn record(&mut self, head: &Piece) -> Result<RecordType> {
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

    pub(super) fn routine_(&mut self, head: &Piece) -> Result<Routine> {
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

    pub(super) fn params(&mut self, list: Pair<'_, Rule>, base: usize) -> Vec<Param> {
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

    pub(super) fn statements(&mut self, depth: usize) -> Result<Vec<Statement>> {
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
}
