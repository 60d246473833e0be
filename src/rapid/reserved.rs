//! RAPID's reserved words: no name can be one.

/// The reserved words of RAPID (the grammar's `reserved_word`).
pub(crate) const RESERVED: [&str; 57] = [
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

pub(crate) fn is_reserved(word: &str) -> bool {
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
