//! RAPID's reserved words and the keyword facts the assembler needs.

use super::*;

/// The reserved words of RAPID (the grammar's `reserved_word`).
pub(super) const RESERVED: [&str; 57] = [
    "ALIAS",
    "AND",
    "BACKWARD",
    "CASE",
    "CONNECT",
    "CONST",
    "DEFAULT",
    "DIV",
    "DO",
    "ELSE",
    "ELSEIF",
    "ENDFOR",
    "ENDFUNC",
    "ENDIF",
    "ENDMODULE",
    "ENDPROC",
    "ENDRECORD",
    "ENDTEST",
    "ENDTRAP",
    "ENDWHILE",
    "ERROR",
    "EXIT",
    "FALSE",
    "FOR",
    "FROM",
    "FUNC",
    "GOTO",
    "IF",
    "INOUT",
    "LOCAL",
    "MOD",
    "MODULE",
    "NOSTEPIN",
    "NOT",
    "NOVIEW",
    "OR",
    "PERS",
    "PROC",
    "RAISE",
    "READONLY",
    "RECORD",
    "RETRY",
    "RETURN",
    "STEP",
    "SYSMODULE",
    "TEST",
    "THEN",
    "TO",
    "TRAP",
    "TRUE",
    "TRYNEXT",
    "UNDO",
    "VAR",
    "VIEWONLY",
    "WHILE",
    "WITH",
    "XOR",
];

pub(super) fn is_reserved(word: &str) -> bool {
    // Upper-cased on the stack and looked up in the sorted list: the fast
    // move recogniser asks this of every name of a million moves.
    if word.is_empty() || word.len() > 9 || !word.bytes().all(|b| b.is_ascii_alphabetic()) {
        return false;
    }
    let mut upper = [0u8; 9];
    for (u, b) in upper.iter_mut().zip(word.bytes()) {
        *u = b.to_ascii_uppercase();
    }
    let upper = &upper[..word.len()];
    // Most names have no reserved word of their length and first letter.
    static FIRST_LETTERS: std::sync::OnceLock<[u32; 10]> = std::sync::OnceLock::new();
    let first = FIRST_LETTERS.get_or_init(|| {
        let mut by_len = [0u32; 10];
        for r in RESERVED {
            if let (Some(m), Some(c)) = (by_len.get_mut(r.len()), r.bytes().next()) {
                *m |= 1 << (c.to_ascii_uppercase().wrapping_sub(b'A') % 32);
            }
        }
        by_len
    });
    if first[upper.len()] & 1 << (upper[0].wrapping_sub(b'A') % 32) == 0 {
        return false;
    }
    RESERVED
        .binary_search_by(|r| r.as_bytes().cmp(upper))
        .is_ok()
}

/// Why a block keyword may appear where it has no block to close.
pub(super) fn stray_note(word: &str) -> Option<&'static str> {
    Some(match word {
        "ENDIF" | "ELSE" | "ELSEIF" => {
            "no IF ... THEN is open here (is THEN missing? a one-line IF has no ENDIF)"
        }
        "ENDFOR" => "no FOR ... DO is open here (is DO missing?)",
        "ENDWHILE" => "no WHILE ... DO is open here (is DO missing?)",
        "ENDTEST" | "CASE" | "DEFAULT" => "no TEST is open here",
        _ => return None,
    })
}

pub(super) fn end_word(k: RoutineKind) -> &'static str {
    match k {
        RoutineKind::Proc => "ENDPROC",
        RoutineKind::Func => "ENDFUNC",
        RoutineKind::Trap => "ENDTRAP",
    }
}

pub(super) fn is_decl_word(w: &str) -> bool {
    matches!(w, "CONST" | "PERS" | "VAR" | "LOCAL" | "TASK")
}

pub(super) fn is_keyword(r: Rule) -> bool {
    use Rule as R;
    matches!(
        r,
        R::kw_goto
            | R::kw_return
            | R::kw_raise
            | R::kw_exit
            | R::kw_retry
            | R::kw_trynext
            | R::kw_connect
            | R::kw_with
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reserved_words_are_sorted_for_the_lookup() {
        assert!(RESERVED.windows(2).all(|w| w[0] < w[1]));
        assert!(is_reserved("endproc") && is_reserved("XOR") && is_reserved("Alias"));
        assert!(!is_reserved("MoveL") && !is_reserved("tool0") && !is_reserved("VIEWONLYX"));
    }
}
