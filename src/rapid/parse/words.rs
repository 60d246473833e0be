//! RAPID's reserved words and the keyword facts the assembler needs.

use super::*;

pub(super) use crate::rapid::reserved::is_reserved;
#[cfg(test)]
pub(super) use crate::rapid::reserved::RESERVED;

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
