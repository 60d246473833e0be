//! The instruction table: which argument of a call is the tool, the work
//! object or a target, and which functions derive robtargets.

use super::*;

/// Tool and work object an instruction names: `\Tool:=`/`\WObj:=`, the
/// tool position of a known motion instruction, else the first argument
/// naming a declared tooldata (or `tool0`).
pub(super) fn call_tool_wobj(
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
pub(super) const ROBTARGET_FUNCTIONS: [&str; 6] =
    ["offs", "reltool", "crobt", "calcrobt", "mirpos", "orobt"];

pub(super) fn derivation(src: &[u8], e: &Expr, span: Range<usize>) -> Derivation {
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
pub(super) fn collect_names(e: &Expr, out: &mut Vec<String>) {
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
