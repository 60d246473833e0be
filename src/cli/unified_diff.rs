//! The unified diff `correct --diff` prints.

/// A unified diff of two versions of a file, in the file's own bytes: a
/// Latin-1 file's diff is Latin-1, so that `patch` applies it to the
/// original.
pub fn unified_diff(name: &str, before: &[u8], after: &[u8]) -> Vec<u8> {
    if before == after {
        return Vec::new();
    }
    let utf8 = std::str::from_utf8(before).is_ok() && std::str::from_utf8(after).is_ok();
    // Latin-1: each byte one char, and back.
    let text = |b: &[u8]| -> String {
        if utf8 {
            String::from_utf8_lossy(b).into_owned()
        } else {
            b.iter().map(|&c| char::from(c)).collect()
        }
    };
    let (a, b) = (text(before), text(after));
    let body = similar::TextDiff::from_lines(&a, &b)
        .unified_diff()
        .context_radius(1)
        .to_string();
    let mut out = format!("--- a/{name}\n+++ b/{name}\n").into_bytes();
    if utf8 {
        out.extend(body.into_bytes());
    } else {
        out.extend(
            body.chars()
                .map(|c| u8::try_from(u32::from(c)).unwrap_or(b'?')),
        );
    }
    out
}
