//! Expressions: primaries, postfix (index, component), operator
//! precedence climbing, numbers and their text.

use super::*;

/// Binary operators in one expression beyond this are refused (the tree
/// is as deep as the chain is long).
const MAX_OPERATORS: usize = 1000;

impl FileParser<'_, '_> {
    /// A name as an interned string (the same few names recur millions of
    /// times in a CAM program).
    pub(super) fn name(&mut self, pair: &Pair<'_, Rule>, base: usize) -> Arc<str> {
        let s = pair.as_span();
        let raw = &self.src[base + s.start()..base + s.end()];
        match std::str::from_utf8(raw) {
            Ok(t) => self.b.intern(t),
            Err(_) => self.b.intern(&decode_lossless(raw)),
        }
    }

    pub(super) fn text(&self, pair: &Pair<'_, Rule>, base: usize) -> String {
        let s = pair.as_span();
        decode_lossless(&self.src[base + s.start()..base + s.end()])
    }

    pub(super) fn variable(&mut self, v: Pair<'_, Rule>, base: usize) -> Result<Expr> {
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

    pub(super) fn postfix(&mut self, e: Expr, post: Pair<'_, Rule>, base: usize) -> Result<Expr> {
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

    pub(super) fn expr(&mut self, pair: Pair<'_, Rule>, base: usize) -> Result<Expr> {
        let start = base + pair.as_span().start();
        let mut operands: Vec<Expr> = Vec::new();
        let mut ops: Vec<BinaryOp> = Vec::new();
        let mut prefixes: Vec<(UnaryOp, usize)> = Vec::new();
        let mut pending: Vec<(UnaryOp, usize)> = Vec::new();
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
                    operands.push(signed(e, &mut pending, &mut last_prefix_end));
                    if ops.len() >= MAX_OPERATORS {
                        return Err(self.err(
                            start,
                            format!("more than {MAX_OPERATORS} operators in one expression"),
                        ));
                    }
                    ops.push(binary_op(c.as_str()));
                }
                _ => {
                    // The signs and NOTs before an operand apply to it with
                    // its indexes and components (`NOT t.robhold`, `-x{2}`):
                    // they are applied when the operand ends.
                    pending = std::mem::take(&mut prefixes);
                    current = Some(self.primary(c, base)?);
                }
            }
        }
        let Some(last) = current else {
            return Err(self.err(start, "expected an expression"));
        };
        operands.push(signed(last, &mut pending, &mut last_prefix_end));
        Ok(climb(operands, ops))
    }

    pub(super) fn primary(&mut self, c: Pair<'_, Rule>, base: usize) -> Result<Expr> {
        let span = base + c.as_span().start()..base + c.as_span().end();
        Ok(match c.as_rule() {
            Rule::num_literal => {
                let t = c.as_str();
                let v = parse_num(t).ok_or_else(|| {
                    self.err(
                        span.start,
                        format!("number {} out of range", crate::error::quoted(t)),
                    )
                })?;
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
                aggregate_of(items, span)
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

pub(super) fn binary_op(text: &str) -> BinaryOp {
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
pub(super) fn precedence(op: BinaryOp) -> u8 {
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
pub(super) fn climb(operands: Vec<Expr>, ops: Vec<BinaryOp>) -> Expr {
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

pub(super) fn parse_num(t: &str) -> Option<f64> {
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

pub(super) fn expr_text(e: &Expr) -> String {
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

pub(super) fn format_num(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

/// An operand with the signs and NOTs written before it, innermost last;
/// a sign written against a number is folded into the literal, so that
/// its span covers the sign.
fn signed(mut e: Expr, prefixes: &mut Vec<(UnaryOp, usize)>, last_prefix_end: &mut usize) -> Expr {
    while let Some((op, at)) = prefixes.pop() {
        e = match (op, e) {
            (UnaryOp::Neg, Expr::Num(n)) if n.span().start == *last_prefix_end => {
                Expr::Num(Number::new(-n.value, at..n.span().end))
            }
            (UnaryOp::Plus, Expr::Num(n)) if n.span().start == *last_prefix_end => {
                Expr::Num(Number::new(n.value, at..n.span().end))
            }
            (op, e) => Expr::Unary(op, Box::new(e)),
        };
        *last_prefix_end = usize::MAX;
    }
    e
}
