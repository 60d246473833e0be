//! Modules, RECORD types, routines and their parameters: the outer
//! blocks of a file, assembled piece by piece.

use super::*;

impl FileParser<'_, '_> {
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
                    Rule::module_name => name = s.text(&c, head.start),
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
            decl_runs: Vec::new(),
            routines: Vec::new(),
            pos: self.pos(head.start),
        };
        self.open_decls = None;
        loop {
            // The fast lane reads the declarations it knows (`lane`);
            // anything else ends the run of declarations it was making.
            if self.lane_decl(&mut m)? {
                continue;
            }
            self.open_decls = None;
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
                body: Block::default(),
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
                            format!(
                                "expected {}, found {}",
                                end_word(r.kind),
                                crate::error::quoted(&w)
                            ),
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
}
