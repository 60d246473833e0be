//! The pass over the whole run, once every file is read: targets inside
//! RECORD values, derived targets, identifiers made unique across
//! modules, source order.

use super::*;
use crate::rapid::build::{in_routine, qualified};
use crate::rapid::targets::{Held, Segment};

/// What the run declares itself, lower-case: its RECORD types (name:
/// components), its tooldata names, and the functions that return a
/// robtarget (built-in and its own).
struct RunKinds {
    records: HashMap<String, Vec<(String, String)>>,
    tools: HashSet<String>,
    rt_funcs: HashSet<String>,
}

impl Builder {
    pub(super) fn finish(&mut self, inputs: &[(&str, &[u8])], lines: &[Vec<usize>]) -> Result<()> {
        let kinds = self.declared_kinds();
        let mut modules = std::mem::take(&mut self.prog.modules);
        self.record_targets(&modules, &kinds.records, inputs, lines);
        self.derived_targets(&mut modules, &kinds, inputs, lines);
        self.keep_declared_bases(&modules);
        // A routine's own data shadows a name declared elsewhere: its
        // targets' identifiers carry the routine (`r1/pA`), so that each
        // identifier stays one target's.
        self.scope_routine_data();
        self.unique_ids(&modules);
        self.source_order(&mut modules);
        self.prog.modules = modules;
        self.number_targets();
        Ok(())
    }

    /// The kinds of data the run declares itself.
    fn declared_kinds(&self) -> RunKinds {
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
        let mut rt_funcs: HashSet<String> = super::builtins::ROBTARGET_FUNCTIONS
            .iter()
            .map(|s| s.to_string())
            .collect();
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
        RunKinds {
            records,
            tools,
            rt_funcs,
        }
    }

    fn record_targets(
        &mut self,
        modules: &[Module],
        records: &HashMap<String, Vec<(String, String)>>,
        inputs: &[(&str, &[u8])],
        lines: &[Vec<usize>],
    ) {
        // Robtargets (and jointtargets) inside declared RECORD values.
        for m in modules {
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
                    records,
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
    }

    fn derived_targets(
        &mut self,
        modules: &mut [Module],
        kinds: &RunKinds,
        inputs: &[(&str, &[u8])],
        lines: &[Vec<usize>],
    ) {
        // Derived targets written in routines, in source order.
        for m in modules.iter_mut() {
            let src = inputs.get(m.file).map(|x| x.1).unwrap_or(&[]);
            let ls = lines.get(m.file).map(Vec::as_slice).unwrap_or(&[]);
            let mut d = DerivedWalk {
                b: self,
                rt_funcs: &kinds.rt_funcs,
                tools: &kinds.tools,
                src,
                lines: ls,
                file: m.file,
                module: m.name.clone(),
                routine: Arc::from(""),
                k: 0,
            };
            d.visit_module_mut(m);
        }
    }

    fn keep_declared_bases(&mut self, modules: &[Module]) {
        // Bases of derived targets: only what names a robtarget of the run
        // (the runs' names among them, looked at only where a derived
        // target has a base to keep).
        if self
            .prog
            .targets
            .iter()
            .any(|t| t.derived.as_ref().is_some_and(|d| !d.bases.is_empty()))
        {
            let runs = &self.prog.runs;
            let sources = &self.prog.sources;
            let run_names = runs
                .decls
                .iter()
                .flat_map(|r| {
                    let src = sources.get(r.file).map_or(&[][..], |s| s.bytes());
                    r.items
                        .iter()
                        .filter_map(move |i| r.name_of(src, i).map(str::to_lowercase))
                })
                .chain(runs.arrays.iter().map(|a| a.name.to_lowercase()));
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
                .chain(run_names)
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
        }
    }

    fn unique_ids(&mut self, modules: &[Module]) {
        // Identifiers unique across modules, the runs' among them (their
        // name spaces counted only where the run has several modules).
        let extra = if modules.len() > 1 {
            self.run_name_spaces()
        } else {
            Vec::new()
        };
        let spaces = qualify(
            &mut self.prog.targets,
            |t| (&t.origin.module, &mut t.id),
            &extra,
        );
        qualify(
            &mut self.prog.jointtargets,
            |t| (&t.origin.module, &mut t.id),
            &[],
        );
        if !spaces.is_empty() {
            self.qualify_runs(&spaces);
        }
    }

    fn source_order(&mut self, modules: &mut [Module]) {
        // Source order, and the AST's indices follow.
        let tmap = sort_by_origin(&mut self.prog.targets, |t| &t.origin);
        let jmap = sort_by_origin(&mut self.prog.jointtargets, |t| &t.origin);
        // Already in order (a program without records or derived targets
        // written out of order): the tree's indices stand, and the walk
        // through every statement is saved.
        let identity = |map: &[usize]| map.iter().enumerate().all(|(i, &n)| i == n);
        if !identity(&tmap) || !identity(&jmap) {
            let mut remap = Remap { t: &tmap, j: &jmap };
            for m in modules.iter_mut() {
                remap.visit_module_mut(m);
            }
        }
    }
    fn scope_routine_data(&mut self) {
        let local = |origin: &Origin, kind: TargetKind| {
            origin.routine.is_some()
                && matches!(
                    kind,
                    TargetKind::Declared | TargetKind::ArrayElement | TargetKind::RecordField
                )
        };
        if !self.prog.targets.iter().any(|t| local(&t.origin, t.kind))
            && !self
                .prog
                .jointtargets
                .iter()
                .any(|t| local(&t.origin, t.kind))
        {
            return;
        }
        // Declared names, lower case, with how many declarations
        // (module and routine data alike) have each.
        // A declaration is told by its scope: duplicates in one scope are
        // refused before this, and an array's elements or a record's
        // fields are one declaration.
        type Scope = (Arc<str>, Option<Arc<str>>);
        let mut count: HashMap<String, HashSet<Scope>> = HashMap::new();
        let mut note = |name: &str, at: Scope| {
            count.entry(name.to_lowercase()).or_default().insert(at);
        };
        for t in &self.prog.targets {
            if let (
                Some(n),
                TargetKind::Declared | TargetKind::ArrayElement | TargetKind::RecordField,
            ) = (&t.name, t.kind)
            {
                note(n, (t.origin.module.clone(), t.origin.routine.clone()));
            }
        }
        for t in &self.prog.jointtargets {
            if let (Some(n), TargetKind::Declared | TargetKind::ArrayElement) = (&t.name, t.kind) {
                note(n, (t.origin.module.clone(), t.origin.routine.clone()));
            }
        }
        let runs = &self.prog.runs;
        for r in &runs.decls {
            let src = self.prog.sources.get(r.file).map_or(&[][..], |s| s.bytes());
            for item in &r.items {
                if let Some(n) = r.name_of(src, item) {
                    note(n, (r.module.clone(), None));
                }
            }
        }
        for a in &runs.arrays {
            note(&a.name, (a.module.clone(), a.routine.clone()));
        }
        let shadows = |name: &Option<String>| {
            name.as_ref()
                .is_some_and(|n| count.get(&n.to_lowercase()).is_some_and(|s| s.len() > 1))
        };
        for t in &mut self.prog.targets {
            if local(&t.origin, t.kind) && shadows(&t.name) {
                if let Some(r) = &t.origin.routine {
                    t.id = in_routine(r, &t.id);
                }
            }
        }
        for t in &mut self.prog.jointtargets {
            if local(&t.origin, t.kind) && shadows(&t.name) {
                if let Some(r) = &t.origin.routine {
                    t.id = in_routine(r, &t.id);
                }
            }
        }
        for a in &mut self.prog.runs.arrays {
            if let Some(r) = &a.routine {
                if shadows(&Some(a.name.to_string())) {
                    a.prefix = Arc::from(in_routine(r, &a.name));
                }
            }
        }
    }

    /// The name spaces of the runs' targets, with their modules: each
    /// routine with a run of literals, each array's name, each declared
    /// name.
    fn run_name_spaces(&self) -> Vec<(Arc<str>, String)> {
        let runs = &self.prog.runs;
        let mut out: Vec<(Arc<str>, String)> = Vec::new();
        for r in runs.moves.iter().filter(|r| r.literals > 0) {
            out.push((r.module.clone(), r.routine.to_string()));
        }
        for a in &runs.arrays {
            out.push((a.module.clone(), a.name.to_string()));
        }
        for r in &runs.decls {
            let src = self.prog.sources.get(r.file).map_or(&[][..], |s| s.bytes());
            for item in &r.items {
                if let Some(name) = r.name_of(src, item) {
                    out.push((r.module.clone(), name.to_string()));
                }
            }
        }
        out
    }

    /// The runs' identifiers qualified with their modules where their
    /// name spaces (lower case) are among `spaces`.
    fn qualify_runs(&mut self, spaces: &HashSet<String>) {
        let runs = &mut self.prog.runs;
        for r in &mut runs.moves {
            if spaces.contains(&r.routine.to_lowercase()) {
                r.prefix = Arc::from(qualified(&r.module, &r.routine));
            }
        }
        for a in &mut runs.arrays {
            if spaces.contains(&a.name.to_lowercase()) {
                a.prefix = Arc::from(qualified(&a.module, &a.name));
            }
        }
        for r in &mut runs.decls {
            let src = self.prog.sources.get(r.file).map_or(&[][..], |s| s.bytes());
            for k in 0..r.items.len() {
                let q = r
                    .name_of(src, &r.items[k])
                    .is_some_and(|n| spaces.contains(&n.to_lowercase()));
                r.items[k].qualified = q;
            }
        }
    }

    /// Every target numbered in file order, those of the runs among them:
    /// each run's targets a stretch of the numbering, the targets held one
    /// by one the stretches between, and the tree's indices renumbered.
    fn number_targets(&mut self) {
        let runs = &mut self.prog.runs;
        let mut blocks: Vec<(usize, usize, usize, Held)> = Vec::new();
        for (i, r) in runs.moves.iter().enumerate() {
            if let Some(first) = r.items.first().filter(|_| r.literals > 0) {
                let at = first.at as usize + usize::from(first.parts[0]);
                blocks.push((r.file, at, r.targets(), Held::Moves(i)));
            }
        }
        for (i, r) in runs.decls.iter().enumerate() {
            if let Some(first) = r.items.first() {
                let at = first.at as usize + usize::from(first.literal);
                blocks.push((r.file, at, r.items.len(), Held::Decls(i)));
            }
        }
        for (i, a) in runs.arrays.iter().enumerate() {
            if let Some(&first) = a.elements.first() {
                blocks.push((a.file, first as usize, a.elements.len(), Held::Array(i)));
            }
        }
        if blocks.is_empty() {
            return;
        }
        blocks.sort_by_key(|b| (b.0, b.1));
        let loose = &self.prog.targets;
        let mut segments = Vec::with_capacity(2 * blocks.len() + 1);
        let mut map = vec![0; loose.len()];
        let (mut next, mut li) = (0, 0);
        // The targets held one by one before `upto` (all that are left for
        // none): a stretch of the numbering.
        let one_by_one = |upto: Option<(usize, usize)>,
                          (next, li): (&mut usize, &mut usize),
                          segments: &mut Vec<Segment>,
                          map: &mut Vec<usize>| {
            let from = *li;
            while *li < loose.len()
                && upto.is_none_or(|u| (loose[*li].origin.file, loose[*li].origin.pos.offset) < u)
            {
                map[*li] = *next + (*li - from);
                *li += 1;
            }
            if *li > from {
                segments.push(Segment {
                    start: *next,
                    len: *li - from,
                    held: Held::OneByOne(from),
                });
                *next += *li - from;
            }
        };
        let mut bases = Vec::with_capacity(blocks.len());
        for &(file, at, len, held) in &blocks {
            one_by_one(
                Some((file, at)),
                (&mut next, &mut li),
                &mut segments,
                &mut map,
            );
            bases.push((held, next));
            segments.push(Segment {
                start: next,
                len,
                held,
            });
            next += len;
        }
        one_by_one(None, (&mut next, &mut li), &mut segments, &mut map);
        for (held, base) in bases {
            match held {
                Held::Moves(r) => runs.moves[r].base = base,
                Held::Decls(r) => runs.decls[r].base = base,
                Held::Array(r) => runs.arrays[r].base = base,
                Held::OneByOne(_) => {}
            }
        }
        self.prog.segments = segments;
        let identity = map.iter().enumerate().all(|(i, &n)| i == n);
        if !identity {
            let mut remap = Remap { t: &map, j: &[] };
            for m in &mut self.prog.modules {
                remap.visit_module_mut(m);
            }
        }
    }
}

/// The name space an identifier is unique in (lower case): the routine
/// for `main#3` / `main@2`, else the declared name (`arr` for `arr{2}`,
/// `w` for `w{3}.pos`).
pub(in crate::rapid) fn name_space(id: &str) -> String {
    name_space_as_written(id).to_lowercase()
}

/// [`name_space`] as the identifier writes it.
fn name_space_as_written(id: &str) -> &str {
    id.split(['#', '@', '{', '.']).next().unwrap_or("")
}

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

/// Qualify with the module every identifier whose name space occurs in
/// more than one module of the run, counting the name spaces of `extra`
/// (module, routine) too; the name spaces qualified, in lower case.
fn qualify<T>(
    items: &mut [T],
    f: impl Fn(&mut T) -> (&Arc<str>, &mut String),
    extra: &[(Arc<str>, String)],
) -> HashSet<String> {
    let mut modules_of: HashMap<String, HashSet<String>> = HashMap::new();
    for (m, r) in extra {
        modules_of
            .entry(r.to_lowercase())
            .or_default()
            .insert(m.to_lowercase());
    }
    // Identifiers in a row mostly share their name space and module (a
    // routine's literals, a million in a CAM program): each pair is
    // entered once, not copied twice per identifier.
    let mut last: Option<(Arc<str>, String)> = None;
    for it in items.iter_mut() {
        let (m, id) = f(it);
        let space = name_space_as_written(id);
        if last
            .as_ref()
            .is_some_and(|(lm, ls)| Arc::ptr_eq(lm, m) && ls == space)
        {
            continue;
        }
        modules_of
            .entry(space.to_lowercase())
            .or_default()
            .insert(m.to_lowercase());
        last = Some((m.clone(), space.to_string()));
    }
    if modules_of.values().all(|s| s.len() < 2) {
        return HashSet::new();
    }
    for it in items.iter_mut() {
        let (m, id) = f(it);
        if modules_of.get(&name_space(id)).is_some_and(|s| s.len() > 1) {
            *id = qualified(m, id);
        }
    }
    modules_of
        .into_iter()
        .filter(|(_, m)| m.len() > 1)
        .map(|(space, _)| space)
        .collect()
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

/// Old target indices to new ones, in the tree and in each call's lists.
struct Remap<'a> {
    t: &'a [usize],
    j: &'a [usize],
}

impl VisitMut for Remap<'_> {
    fn visit_call_mut(&mut self, c: &mut Call) {
        walk_call_mut(self, c);
        let (t, j) = (self.t, self.j);
        c.targets
            .iter_mut()
            .for_each(|i| *i = t.get(*i).copied().unwrap_or(*i));
        c.jointtargets
            .iter_mut()
            .for_each(|i| *i = j.get(*i).copied().unwrap_or(*i));
    }

    fn visit_expr_mut(&mut self, e: &mut Expr) {
        match e {
            Expr::Target(i) => *i = self.t.get(*i).copied().unwrap_or(*i),
            Expr::JointTarget(i) => *i = self.j.get(*i).copied().unwrap_or(*i),
            _ => walk_expr_mut(self, e),
        }
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
}

/// Statements only: derived targets are the robtarget calls a statement
/// passes, assigns or returns, not those nested in other expressions.
impl VisitMut for DerivedWalk<'_> {
    fn visit_routine_mut(&mut self, r: &mut Routine) {
        self.routine = r.name.clone();
        self.k = 0;
        walk_routine_mut(self, r);
    }

    fn visit_statement_mut(&mut self, s: &mut Statement) {
        match &mut s.kind {
            StatementKind::Assign { target, value } if self.is_rt_call(value) => {
                self.derived(value, Some(expr_text(target)), None);
            }
            StatementKind::Return(Some(e)) if self.is_rt_call(e) => {
                self.derived(e, None, None);
            }
            _ => walk_statement_mut(self, s),
        }
    }

    fn visit_call_mut(&mut self, c: &mut Call) {
        // Literals whose instruction's tool is only known now (most know
        // it: a CAM program's million moves are not asked again).
        let targets = &self.b.prog.targets;
        let untooled = c
            .targets
            .iter()
            .any(|&i| targets.get(i).is_some_and(|x| x.tool.is_none()));
        let t = match untooled {
            true => call_tool_wobj(&c.name, &c.args, self.tools).0,
            false => None,
        };
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

    fn visit_expr_mut(&mut self, _: &mut Expr) {}
}
