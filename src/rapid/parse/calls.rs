//! The instruction table: tool and work object of a call, and what a
//! derived target is computed from.

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
fn collect_names(e: &Expr, out: &mut Vec<String>) {
    struct Names<'o>(&'o mut Vec<String>);
    impl<'a> Visit<'a> for Names<'_> {
        // An expression's walk: no list of statements in it.
        fn program(&self) -> Option<&'a crate::rapid::Program> {
            None
        }
        fn visit_expr(&mut self, e: &'a Expr) {
            match e {
                Expr::Name(n) => self.0.push(n.to_string()),
                Expr::Index(b)
                    if matches!(b.0, Expr::Name(_)) && b.1.iter().all(|i| i.as_num().is_some()) =>
                {
                    let ix: Vec<String> = b.1.iter().map(expr_text).collect();
                    self.0
                        .push(format!("{}{{{}}}", expr_text(&b.0), ix.join(",")));
                }
                _ => walk_expr(self, e),
            }
        }
    }
    Names(out).visit_expr(e);
}
