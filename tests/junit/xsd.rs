//! A validator for the XML Schema subset that the Apache Ant JUnit schema
//! (`tests/data/ant-junit/JUnit.xsd`) is written in, so that the JUnit reports
//! are checked against the schema file itself with nothing but Rust (no
//! xmllint on the machine, no validator crate in the registry offline).
//!
//! The subset: named and anonymous `simpleType`s restricting `xs:string`,
//! `xs:token`, `xs:int`, `xs:nonNegativeInteger`, `xs:decimal`,
//! `xs:dateTime` or another simple type (with `minLength`, `pattern` and
//! `whiteSpace`), named and anonymous `complexType`s (optionally `mixed`)
//! holding one `sequence` or `choice` of `element`s, a `complexContent`
//! extension of a named complex type or a `simpleContent` extension of a
//! simple type, nested `sequence`/`choice` groups, `minOccurs` and
//! `maxOccurs` (also `unbounded`), and `attribute`s with `use`;
//! `annotation`s are skipped. Any other construct in the schema is an
//! error, so a schema that grows past what this file understands fails the
//! tests instead of being half read. As in XML Schema, an attribute the
//! type does not declare is invalid.

use quick_xml::events::Event;
use quick_xml::Reader;
use std::collections::BTreeMap;

/// A simple type: the built-in it restricts and its length floor.
#[derive(Debug, Clone)]
struct Simple {
    base: String,
    min_length: Option<usize>,
    pattern: Option<String>,
}

/// Anonymous simple types, named `#N` as they are read.
type Anonymous = BTreeMap<String, Simple>;

fn anonymous(node: &Node, anon: &mut Anonymous) -> Result<String, String> {
    let name = format!("#{}", anon.len());
    let simple = read_simple(node)?;
    anon.insert(name.clone(), simple);
    Ok(name)
}

/// A node's children less its annotations.
fn parts(node: &Node) -> Vec<&Node> {
    node.children
        .iter()
        .filter(|c| c.name != "xs:annotation")
        .collect()
}

#[derive(Debug, Clone)]
enum Particle {
    Element {
        name: String,
        ty: TypeRef,
        min: usize,
        max: Option<usize>,
    },
    Group {
        choice: bool,
        items: Vec<Particle>,
        min: usize,
        max: Option<usize>,
    },
}

#[derive(Debug, Clone)]
struct Complex {
    mixed: bool,
    /// A `complexContent` extension: the named type it extends.
    base: Option<String>,
    /// A `simpleContent` extension: the simple type of its text.
    text: Option<String>,
    content: Option<Particle>,
    /// Attribute name → (its simple type, required).
    attributes: BTreeMap<String, (TypeRef, bool)>,
}

#[derive(Debug, Clone)]
enum TypeRef {
    Named(String),
    Anonymous(Box<Complex>),
}

/// A schema in the subset above.
pub struct Schema {
    simple: BTreeMap<String, Simple>,
    complex: BTreeMap<String, Complex>,
    roots: BTreeMap<String, TypeRef>,
}

/// An element of a parsed document.
#[derive(Debug)]
struct Node {
    name: String,
    attributes: Vec<(String, String)>,
    children: Vec<Node>,
    text: String,
}

fn parse_tree(xml: &str) -> Result<Node, String> {
    let mut reader = Reader::from_str(xml);
    let mut stack: Vec<Node> = Vec::new();
    let mut root = None;
    let open = |e: &quick_xml::events::BytesStart| -> Result<Node, String> {
        let mut attributes = Vec::new();
        for a in e.attributes() {
            let a = a.map_err(|e| format!("bad attribute: {e}"))?;
            let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
            let value = a
                .unescape_value()
                .map_err(|e| format!("bad attribute value: {e}"))?
                .into_owned();
            attributes.push((key, value));
        }
        Ok(Node {
            name: String::from_utf8_lossy(e.name().as_ref()).into_owned(),
            attributes,
            children: Vec::new(),
            text: String::new(),
        })
    };
    loop {
        let event = reader.read_event().map_err(|e| {
            format!(
                "not well-formed XML at byte {}: {e}",
                reader.error_position()
            )
        })?;
        match event {
            Event::Start(e) => stack.push(open(&e)?),
            Event::Empty(e) => {
                let node = open(&e)?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(node),
                    None => root = Some(node),
                }
            }
            Event::End(_) => {
                let node = stack.pop().ok_or("an end tag without a start")?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(node),
                    None => root = Some(node),
                }
            }
            Event::Text(t) => {
                if let Some(top) = stack.last_mut() {
                    let text = t.decode().map_err(|e| format!("bad text: {e}"))?;
                    let text =
                        quick_xml::escape::unescape(&text).map_err(|e| format!("bad text: {e}"))?;
                    top.text.push_str(&text);
                }
            }
            Event::CData(t) => {
                if let Some(top) = stack.last_mut() {
                    top.text.push_str(&String::from_utf8_lossy(&t));
                }
            }
            Event::GeneralRef(r) => {
                if let Some(top) = stack.last_mut() {
                    let name = String::from_utf8_lossy(&r).into_owned();
                    let entity = format!("&{name};");
                    let text = quick_xml::escape::unescape(&entity)
                        .map_err(|e| format!("bad entity {entity}: {e}"))?;
                    top.text.push_str(&text);
                }
            }
            Event::Eof => break,
            Event::Decl(_) | Event::Comment(_) | Event::PI(_) | Event::DocType(_) => {}
        }
    }
    if !stack.is_empty() {
        return Err(format!("<{}> is never closed", stack.last().unwrap().name));
    }
    root.ok_or_else(|| "no root element".to_string())
}

fn attr<'a>(node: &'a Node, key: &str) -> Option<&'a str> {
    node.attributes
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

fn occurs(node: &Node) -> Result<(usize, Option<usize>), String> {
    let min = match attr(node, "minOccurs") {
        Some(v) => v.parse().map_err(|_| format!("minOccurs {v:?}"))?,
        None => 1,
    };
    let max = match attr(node, "maxOccurs") {
        Some("unbounded") => None,
        Some(v) => Some(v.parse().map_err(|_| format!("maxOccurs {v:?}"))?),
        None => Some(1),
    };
    Ok((min, max))
}

fn unknown(node: &Node) -> String {
    format!(
        "the schema uses <{}>, which tests/junit/xsd.rs does not read",
        node.name
    )
}

fn read_particle(node: &Node, anon: &mut Anonymous) -> Result<Particle, String> {
    let (min, max) = occurs(node)?;
    match node.name.as_str() {
        "xs:element" => {
            let name = attr(node, "name").ok_or("an element without a name")?;
            let ty = match (attr(node, "type"), parts(node).as_slice()) {
                (Some(t), []) => TypeRef::Named(t.to_string()),
                (None, [c]) if c.name == "xs:complexType" => {
                    TypeRef::Anonymous(Box::new(read_complex(c, anon)?))
                }
                (None, [c]) if c.name == "xs:simpleType" => TypeRef::Named(anonymous(c, anon)?),
                _ => {
                    return Err(format!(
                        "element {name}: a type attribute or one complexType"
                    ))
                }
            };
            Ok(Particle::Element {
                name: name.to_string(),
                ty,
                min,
                max,
            })
        }
        "xs:sequence" | "xs:choice" => Ok(Particle::Group {
            choice: node.name == "xs:choice",
            items: parts(node)
                .into_iter()
                .map(|c| read_particle(c, anon))
                .collect::<Result<_, _>>()?,
            min,
            max,
        }),
        _ => Err(unknown(node)),
    }
}

fn read_complex(node: &Node, anon: &mut Anonymous) -> Result<Complex, String> {
    let mut out = Complex {
        mixed: attr(node, "mixed") == Some("true"),
        base: None,
        text: None,
        content: None,
        attributes: BTreeMap::new(),
    };
    read_complex_parts(node, anon, &mut out)?;
    Ok(out)
}

fn read_complex_parts(node: &Node, anon: &mut Anonymous, out: &mut Complex) -> Result<(), String> {
    for c in parts(node) {
        match c.name.as_str() {
            "xs:complexContent" | "xs:simpleContent" => {
                let inner = parts(c);
                let [ext] = inner.as_slice() else {
                    return Err(format!("<{}> holds one extension", c.name));
                };
                if ext.name != "xs:extension" {
                    return Err(unknown(ext));
                }
                let base = attr(ext, "base").ok_or("an extension without a base")?;
                if c.name == "xs:complexContent" {
                    out.base = Some(base.to_string());
                } else {
                    out.text = Some(base.to_string());
                }
                read_complex_parts(ext, anon, out)?;
            }
            "xs:sequence" | "xs:choice" if out.content.is_none() => {
                out.content = Some(read_particle(c, anon)?)
            }
            "xs:attribute" => {
                let name = attr(c, "name").ok_or("an attribute without a name")?;
                let ty = match (attr(c, "type"), parts(c).as_slice()) {
                    (Some(t), []) => t.to_string(),
                    (None, [t]) if t.name == "xs:simpleType" => anonymous(t, anon)?,
                    _ => return Err(format!("attribute {name}: a type or one simpleType")),
                };
                let required = match attr(c, "use") {
                    None | Some("optional") => false,
                    Some("required") => true,
                    Some(u) => return Err(format!("attribute {name}: use {u:?}")),
                };
                out.attributes
                    .insert(name.to_string(), (TypeRef::Named(ty), required));
            }
            _ => return Err(unknown(c)),
        }
    }
    Ok(())
}

fn read_simple(node: &Node) -> Result<Simple, String> {
    let inner = parts(node);
    let [restriction] = inner.as_slice() else {
        return Err("a simpleType holds one restriction".into());
    };
    if restriction.name != "xs:restriction" {
        return Err(unknown(restriction));
    }
    let base = attr(restriction, "base").ok_or("a restriction without a base")?;
    let mut min_length = None;
    let mut pattern = None;
    for facet in parts(restriction) {
        match facet.name.as_str() {
            "xs:minLength" => {
                let v = attr(facet, "value").ok_or("minLength without a value")?;
                min_length = Some(v.parse().map_err(|_| format!("minLength {v:?}"))?);
            }
            "xs:pattern" => {
                pattern = Some(
                    attr(facet, "value")
                        .ok_or("pattern without a value")?
                        .to_string(),
                );
            }
            // How the text's white space is read; the checks below read
            // xs:token collapsed and the rest as written.
            "xs:whiteSpace" => {}
            _ => return Err(unknown(facet)),
        }
    }
    Ok(Simple {
        base: base.to_string(),
        min_length,
        pattern,
    })
}

impl Schema {
    pub fn parse(xsd: &str) -> Result<Schema, String> {
        let root = parse_tree(xsd)?;
        if root.name != "xs:schema" {
            return Err("the root of a schema is xs:schema".into());
        }
        let mut schema = Schema {
            simple: BTreeMap::new(),
            complex: BTreeMap::new(),
            roots: BTreeMap::new(),
        };
        let mut anon = Anonymous::new();
        for node in parts(&root) {
            match node.name.as_str() {
                "xs:simpleType" => {
                    let name = attr(node, "name").ok_or("a simpleType without a name")?;
                    schema.simple.insert(name.to_string(), read_simple(node)?);
                }
                "xs:complexType" => {
                    let name = attr(node, "name").ok_or("a complexType without a name")?;
                    schema
                        .complex
                        .insert(name.to_string(), read_complex(node, &mut anon)?);
                }
                "xs:element" => {
                    let Particle::Element { name, ty, .. } = read_particle(node, &mut anon)? else {
                        unreachable!()
                    };
                    schema.roots.insert(name, ty);
                }
                _ => return Err(unknown(node)),
            }
        }
        schema.simple.append(&mut anon);
        Ok(schema)
    }

    /// Whether `xml` is valid under the schema; the first fault otherwise.
    pub fn validate(&self, xml: &str) -> Result<(), String> {
        let root = parse_tree(xml)?;
        let ty = self
            .roots
            .get(&root.name)
            .ok_or_else(|| format!("<{}> is not a root element of the schema", root.name))?;
        self.element(&root, ty, &root.name)
    }

    /// A complex type with the type it extends merged in.
    fn resolved(&self, c: &Complex) -> Result<Complex, String> {
        let Some(base) = &c.base else {
            return Ok(c.clone());
        };
        let b = self
            .complex
            .get(base)
            .ok_or_else(|| format!("no complex type {base} to extend"))?;
        let mut out = self.resolved(b)?;
        if c.content.is_some() {
            out.content = c.content.clone();
        }
        out.attributes.extend(c.attributes.clone());
        Ok(out)
    }

    fn element(&self, node: &Node, ty: &TypeRef, path: &str) -> Result<(), String> {
        let complex = match ty {
            TypeRef::Anonymous(c) => c.as_ref(),
            TypeRef::Named(n) => match self.complex.get(n) {
                Some(c) => c,
                None => {
                    // An element of simple type: text only.
                    if let Some(c) = node.children.first() {
                        return Err(format!("{path}: <{}> inside text-only content", c.name));
                    }
                    if let Some((k, _)) = node.attributes.first() {
                        return Err(format!("{path}: attribute {k} on a text-only element"));
                    }
                    return self
                        .value(n, &node.text)
                        .map_err(|e| format!("{path}: {e}"));
                }
            },
        };
        let complex = &self.resolved(complex)?;
        if let Some(text) = &complex.text {
            if let Some(c) = node.children.first() {
                return Err(format!("{path}: <{}> inside text-only content", c.name));
            }
            self.value(text, &node.text)
                .map_err(|e| format!("{path}: {e}"))?;
        }
        for (key, value) in &node.attributes {
            if key.starts_with("xmlns") {
                continue;
            }
            let (aty, _) = complex
                .attributes
                .get(key)
                .ok_or_else(|| format!("{path}: attribute {key} is not declared"))?;
            let TypeRef::Named(aty) = aty else {
                unreachable!()
            };
            self.value(aty, value)
                .map_err(|e| format!("{path}/@{key}: {e}"))?;
        }
        for (key, (_, required)) in &complex.attributes {
            if *required && attr(node, key).is_none() {
                return Err(format!("{path}: required attribute {key} is missing"));
            }
        }
        if !complex.mixed && complex.text.is_none() && !node.text.trim().is_empty() {
            return Err(format!("{path}: text in element-only content"));
        }
        let children: Vec<&Node> = node.children.iter().collect();
        let ends = match &complex.content {
            Some(p) => self.matches(p, &children, 0),
            None => vec![0],
        };
        if !ends.contains(&children.len()) {
            let got: Vec<&str> = children.iter().map(|c| c.name.as_str()).collect();
            return Err(format!(
                "{path}: children {got:?} do not follow the content model"
            ));
        }
        // The content model fits; every child against its declaration.
        for (i, child) in children.iter().enumerate() {
            let ty = self
                .declared(complex.content.as_ref(), &child.name)
                .ok_or_else(|| format!("{path}: <{}> is not declared", child.name))?;
            self.element(child, ty, &format!("{path}/{}[{i}]", child.name))?;
        }
        Ok(())
    }

    /// The type an element name has in a content model (names are unique
    /// per content model in this schema subset).
    fn declared<'a>(&self, p: Option<&'a Particle>, name: &str) -> Option<&'a TypeRef> {
        match p? {
            Particle::Element { name: n, ty, .. } => (n == name).then_some(ty),
            Particle::Group { items, .. } => {
                items.iter().find_map(|i| self.declared(Some(i), name))
            }
        }
    }

    /// Every position the particle can end at when it starts at `at`.
    fn matches(&self, p: &Particle, children: &[&Node], at: usize) -> Vec<usize> {
        let (min, max) = match p {
            Particle::Element { min, max, .. } | Particle::Group { min, max, .. } => (*min, *max),
        };
        let mut reached = vec![at];
        let mut frontier = vec![at];
        let mut ends = if min == 0 { vec![at] } else { Vec::new() };
        let mut count = 0;
        while !frontier.is_empty() && max.is_none_or(|m| count < m) {
            count += 1;
            let mut next = Vec::new();
            for &pos in &frontier {
                for end in self.once(p, children, pos) {
                    // A repetition that consumes nothing cannot help.
                    if end > pos && !reached.contains(&end) {
                        reached.push(end);
                        next.push(end);
                    }
                }
            }
            if count >= min {
                ends.extend(next.iter().copied());
            }
            frontier = next;
        }
        // A particle that can match nothing pads any count up to its
        // minimum with empty matches.
        if Self::nullable(p) {
            ends.extend(reached);
        }
        ends.sort_unstable();
        ends.dedup();
        ends
    }

    /// Whether the particle can match no element at all.
    fn nullable(p: &Particle) -> bool {
        match p {
            Particle::Element { min, .. } => *min == 0,
            Particle::Group {
                choice, items, min, ..
            } => {
                *min == 0
                    || if *choice {
                        items.iter().any(Self::nullable)
                    } else {
                        items.iter().all(Self::nullable)
                    }
            }
        }
    }

    /// One occurrence of the particle from `at`.
    fn once(&self, p: &Particle, children: &[&Node], at: usize) -> Vec<usize> {
        match p {
            Particle::Element { name, .. } => match children.get(at) {
                Some(c) if &c.name == name => vec![at + 1],
                _ => Vec::new(),
            },
            Particle::Group {
                choice: true,
                items,
                ..
            } => {
                let mut out: Vec<usize> = items
                    .iter()
                    .flat_map(|i| self.matches(i, children, at))
                    .collect();
                out.sort_unstable();
                out.dedup();
                out
            }
            Particle::Group { items, .. } => {
                let mut positions = vec![at];
                for item in items {
                    let mut next: Vec<usize> = positions
                        .iter()
                        .flat_map(|&pos| self.matches(item, children, pos))
                        .collect();
                    next.sort_unstable();
                    next.dedup();
                    positions = next;
                }
                positions
            }
        }
    }

    fn value(&self, ty: &str, v: &str) -> Result<(), String> {
        if let Some(s) = self.simple.get(ty) {
            self.value(&s.base, v)?;
            // xs:token's value is the text with its white space collapsed.
            let value = if s.base == "xs:token" {
                v.split_whitespace().collect::<Vec<_>>().join(" ")
            } else {
                v.to_string()
            };
            if let Some(min) = s.min_length {
                if value.chars().count() < min {
                    return Err(format!("{v:?} is shorter than {min} (type {ty})"));
                }
            }
            if let Some(p) = &s.pattern {
                // XML Schema's patterns match the whole value.
                let re = regex::Regex::new(&format!("^(?:{p})$"))
                    .map_err(|e| format!("pattern {p:?}: {e}"))?;
                if !re.is_match(value.trim()) {
                    return Err(format!("{v:?} does not match {p:?} (type {ty})"));
                }
            }
            return Ok(());
        }
        let v = v.trim();
        let ok = match ty {
            "xs:string" | "xs:token" => true,
            "xs:int" => v.parse::<i32>().is_ok(),
            "xs:dateTime" => regex::Regex::new(
                r"^-?[0-9]{4,}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}(\.[0-9]+)?(Z|[+-][0-9]{2}:[0-9]{2})?$",
            )
            .is_ok_and(|re| re.is_match(v)),
            "xs:nonNegativeInteger" => {
                let digits = v.strip_prefix('+').unwrap_or(v);
                !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
            }
            "xs:decimal" => {
                let body = v.strip_prefix(['+', '-']).unwrap_or(v);
                let (int, frac) = body.split_once('.').unwrap_or((body, ""));
                (!int.is_empty() || !frac.is_empty())
                    && int.bytes().all(|b| b.is_ascii_digit())
                    && frac.bytes().all(|b| b.is_ascii_digit())
            }
            _ => return Err(format!("type {ty} is not one tests/junit/xsd.rs reads")),
        };
        if ok {
            Ok(())
        } else {
            Err(format!("{v:?} is not a valid {ty}"))
        }
    }
}
