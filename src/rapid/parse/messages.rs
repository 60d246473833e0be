//! Syntax errors: pest's error turned into a message in the words of
//! RAPID, pointing where a compiler would.

use super::*;

impl FileParser<'_, '_> {
    pub(super) fn pest_error(
        &self,
        e: &pest::error::Error<Rule>,
        text: &str,
        base: usize,
        rule: Rule,
    ) -> Error {
        let at = error_offset(e);
        let mut expected: Vec<String> = Vec::new();
        let mut push = |s: String| {
            if !expected.contains(&s) {
                expected.push(s);
            }
        };
        for t in expected_punctuation(rule, text, at) {
            if let Some(s) = describe_token(t) {
                push(s);
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
}

fn error_offset(e: &pest::error::Error<Rule>) -> usize {
    match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((s, _)) => s,
    }
}

/// Separators and closing marks the grammar writes as literal strings, in
/// the order a message lists them.
const PUNCTUATION: [&str; 8] = [",", ";", "]", ")", "}", ":=", "|", "%"];

/// Which of [`PUNCTUATION`] would let the parse of `text` go on at `at`.
/// Pest's error names only rules; the literal strings it tried are
/// recorded only under its process-wide `set_error_detail`, which a
/// library should not switch. So each mark is tried in place instead
/// (on the error path only): it was expected if the parse then gets past
/// it.
fn expected_punctuation(rule: Rule, text: &str, at: usize) -> Vec<&'static str> {
    let Some((before, after)) = text.split_at_checked(at) else {
        return Vec::new();
    };
    PUNCTUATION
        .into_iter()
        .filter(|t| {
            let probe = format!("{before}{t} {after}");
            match grammar::read(rule, &probe) {
                Ok(_) => true,
                Err(e) => error_offset(&e) >= at + t.len(),
            }
        })
        .collect()
}

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
        crossed |= crate::error::ends_line(src, p - 1);
        p -= 1;
    }
    if !crossed {
        return offset;
    }
    // The line ending at `p`: cut a comment (a `!` outside strings).
    let start = crate::error::line_start(src, p);
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
    // A UTF-16 file reads as `ÿþM\0O\0…` byte by byte: name what it is.
    if offset == 0 && (rest.starts_with(&[0xFF, 0xFE]) || rest.starts_with(&[0xFE, 0xFF])) {
        return "a UTF-16 byte-order mark (RAPID files are UTF-8 or Latin-1: save the file as one of them)".into();
    }
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
    crate::error::quoted(&decode_lossless(&rest[..len.min(24)]))
}
