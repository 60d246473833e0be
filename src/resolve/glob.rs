//! Identifiers matched against an access path's pattern, `*` for an
//! index only the run knows.

/// Case-insensitive match of an identifier against a pattern whose `*`
/// stands for one index (an optionally signed whole number).
pub(super) fn glob_match(pattern: &str, id: &str) -> bool {
    let (p, s) = (pattern.as_bytes(), id.as_bytes());
    let (mut i, mut j) = (0, 0);
    while i < p.len() {
        if p[i] == b'*' {
            let start = j;
            if j < s.len() && s[j] == b'-' {
                j += 1;
            }
            while j < s.len() && s[j].is_ascii_digit() {
                j += 1;
            }
            if j == start || (j == start + 1 && s[start] == b'-') {
                return false;
            }
            i += 1;
        } else {
            if j >= s.len() || !p[i].eq_ignore_ascii_case(&s[j]) {
                return false;
            }
            i += 1;
            j += 1;
        }
    }
    j == s.len()
}

#[cfg(test)]
mod tests {
    use super::glob_match;

    #[test]
    fn patterns_match_indices_only() {
        assert!(glob_match("sCell{*}.path.start", "scell{12}.PATH.start"));
        assert!(glob_match("p{*,1}", "p{3,1}"));
        assert!(!glob_match("p{*,1}", "p{3,2}"));
        assert!(!glob_match("p{*}", "p{}"));
        assert!(!glob_match("a.b", "a.bc"));
    }
}
