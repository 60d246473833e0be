//! Data declarations: their targets and typed values (tooldata, wobjdata,
//! speeddata, zonedata), and robtarget/jointtarget literals taken out of
//! expressions into the program's lists.

use super::*;

impl FileParser<'_, '_> {
    pub(super) fn data_decl(&mut self, p: &Piece) -> Result<DataDecl> {
        let mut d = self.with_pair(Rule::data_declaration, p, |s, pair| {
            let Some(decl) = pair.into_inner().next() else {
                return Err(s.err(p.start, "expected a data declaration"));
            };
            let (mut type_name, mut name) = (String::new(), String::new());
            let mut d = DeclParts {
                scope: None,
                // The grammar's storage and scope are of the keywords
                // only; what else it matched is the last keyword's.
                storage: storage(STORAGE_WORDS.len() - 1),
                type_name: "",
                name: "",
                dims: Vec::new(),
                init: None,
                pos: s.pos(p.start),
                elements: None,
            };
            for c in decl.into_inner() {
                match c.as_rule() {
                    Rule::scope => {
                        let k = keyword_number(&SCOPE_WORDS, c.as_str());
                        d.scope = Some(scope(k.unwrap_or(SCOPE_WORDS.len() - 1)));
                    }
                    Rule::storage => {
                        let k = keyword_number(&STORAGE_WORDS, c.as_str());
                        d.storage = storage(k.unwrap_or(STORAGE_WORDS.len() - 1));
                    }
                    Rule::type_name => type_name = s.text(&c, p.start),
                    Rule::identifier => name = s.text(&c, p.start),
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
            Ok(declaration(DeclParts {
                type_name: &type_name,
                name: &name,
                ..d
            }))
        })?;
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

    /// Where what the parse reads now is: its file, module and routine.
    pub(super) fn place(&self) -> Place<'_> {
        Place {
            file: self.file,
            module: &self.module,
            routine: self.routine.as_ref(),
        }
    }

    /// The target of declaration `d` (an element of its value: `element`)
    /// whose value starts at `offset`.
    pub(super) fn declared_parts<'s>(
        &'s self,
        d: &'s DataDecl,
        offset: usize,
        element: bool,
    ) -> TargetParts<'s> {
        let pos = self.pos(offset);
        TargetParts::declared(self.place(), pos, &d.name, d.storage, element)
    }

    pub(super) fn decl_id(name: &str, index: &[usize]) -> String {
        let mut id = String::new();
        declared_id(name, index, &mut id);
        id
    }

    /// The elements of a declared array value of `dims` dimensions, each
    /// handed to `element` with its 1-based index path (`arr{2,1}`); a
    /// value that is not an aggregate where one is expected stays as
    /// written.
    fn declared_elements(
        &mut self,
        d: &DataDecl,
        e: Expr,
        dims: usize,
        index: &mut Vec<usize>,
        element: fn(&mut Self, &DataDecl, Expr, &[usize]) -> Result<Expr>,
    ) -> Result<Expr> {
        if dims == 0 {
            return element(self, d, e, index);
        }
        let Expr::Aggregate(mut a) = e else {
            return Ok(e);
        };
        let items = std::mem::take(&mut a.items);
        let mut out = Vec::with_capacity(items.len());
        for (i, it) in items.into_iter().enumerate() {
            index.push(i + 1);
            out.push(self.declared_elements(d, it, dims - 1, index, element)?);
            index.pop();
        }
        a.items = out;
        Ok(Expr::Aggregate(a))
    }

    pub(super) fn declared_robtargets(
        &mut self,
        d: &DataDecl,
        e: Expr,
        dims: usize,
        index: &mut Vec<usize>,
    ) -> Result<Expr> {
        self.declared_elements(d, e, dims, index, Self::declared_robtarget)
    }

    /// One robtarget of a declaration (the whole value, or an element).
    fn declared_robtarget(&mut self, d: &DataDecl, e: Expr, index: &[usize]) -> Result<Expr> {
        let id = Self::decl_id(&d.name, index);
        match &e {
            Expr::Aggregate(a) => match robtarget_shape(&a.items) {
                Err(why) => Err(self
                    .err(a.span.start, format!("robtarget {id} is malformed: {why}"))
                    .with_note(ROBTARGET_FORM)),
                Ok(Some(value)) => {
                    let element = !index.is_empty();
                    let parts = self.declared_parts(d, a.span.start, element);
                    let t = parts.target(id, Some(value));
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

    pub(super) fn declared_derived(
        &mut self,
        d: &DataDecl,
        id: String,
        e: &Expr,
        span: Range<usize>,
    ) {
        let parts = TargetParts {
            kind: TargetKind::Derived,
            ..self.declared_parts(d, span.start, false)
        };
        let t = Target {
            derived: Some(Box::new(derivation(self.src, e, span.clone()))),
            ..parts.target(id, None)
        };
        self.push_target(t);
    }

    pub(super) fn push_target(&mut self, t: Target) -> usize {
        self.b.prog.targets.push(t);
        self.b.prog.targets.len() - 1
    }

    pub(super) fn declared_joints(
        &mut self,
        d: &DataDecl,
        e: Expr,
        dims: usize,
        index: &mut Vec<usize>,
    ) -> Result<Expr> {
        self.declared_elements(d, e, dims, index, Self::declared_joint)
    }

    /// One jointtarget of a declaration (the whole value, or an element).
    fn declared_joint(&mut self, d: &DataDecl, e: Expr, index: &[usize]) -> Result<Expr> {
        let Expr::Aggregate(a) = e else {
            return Ok(e);
        };
        let id = Self::decl_id(&d.name, index);
        match jointtarget_shape(&a.items) {
            Err(why) => Err(self
                .err(
                    a.span.start,
                    format!("jointtarget {id} is malformed: {why}"),
                )
                .with_note(JOINTTARGET_FORM)),
            Ok(Some(numbers)) => {
                let element = !index.is_empty();
                let parts = self.declared_parts(d, a.span.start, element);
                let j = parts.jointtarget(id, numbers);
                self.b.prog.jointtargets.push(j);
                Ok(Expr::JointTarget(self.b.prog.jointtargets.len() - 1))
            }
            Ok(None) => Ok(Expr::Aggregate(a)),
        }
    }

    /// tooldata, wobjdata, speeddata, zonedata of the expected shape (other
    /// shapes are left alone: harmless to this tool).
    pub(super) fn typed_data(&mut self, ty: &str, d: &DataDecl, e: &Expr, pos: Pos) {
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
    pub(super) fn take_literals(&mut self, mut e: Expr, ctx: &InlineCtx) -> Expr {
        Literals { p: self, ctx }.visit_expr_mut(&mut e);
        e
    }
}

/// Robtarget and jointtarget literals of an expression moved into the
/// program's lists, each replaced by its index.
struct Literals<'p, 'a, 'b> {
    p: &'p mut FileParser<'a, 'b>,
    ctx: &'p InlineCtx,
}

impl Literals<'_, '_, '_> {
    /// The identifier of the routine's literal number `n`.
    fn inline_id(&self, n: usize) -> String {
        let mut id = String::new();
        inline_id(self.p.routine.as_deref().unwrap_or(""), n, &mut id);
        id
    }

    /// The literal whose value starts at `offset`, held by the context's
    /// instruction (or assigned to its variable).
    fn parts(&self, offset: usize) -> TargetParts<'_> {
        let held = HeldBy {
            instruction: self.ctx.instruction.as_ref(),
            tool: self.ctx.tool.as_ref(),
            wobj: self.ctx.wobj.as_ref(),
        };
        let assigned = self.ctx.assigned_to.as_deref();
        TargetParts::inline(self.p.place(), self.p.pos(offset), held, assigned)
    }
}

impl VisitMut for Literals<'_, '_, '_> {
    fn visit_expr_mut(&mut self, e: &mut Expr) {
        match e {
            Expr::Aggregate(a) => {
                if let Ok(Some(value)) = robtarget_shape(&a.items) {
                    self.p.inline_k += 1;
                    let id = self.inline_id(self.p.inline_k);
                    let t = self.parts(a.span.start).target(id, Some(value));
                    let i = self.p.push_target(t);
                    self.p.call_targets.push(i);
                    *e = Expr::Target(i);
                    return;
                }
                if let Ok(Some(numbers)) = jointtarget_shape(&a.items) {
                    self.p.joint_k += 1;
                    let id = self.inline_id(self.p.joint_k);
                    let j = self.parts(a.span.start).jointtarget(id, numbers);
                    self.p.b.prog.jointtargets.push(j);
                    let i = self.p.b.prog.jointtargets.len() - 1;
                    self.p.call_joints.push(i);
                    *e = Expr::JointTarget(i);
                    return;
                }
                walk_expr_mut(self, e);
            }
            // An index selects an element: a literal there is no target.
            Expr::Index(_) => {}
            _ => walk_expr_mut(self, e),
        }
    }
}
