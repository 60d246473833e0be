//! Splicing new text into the original bytes of a program: every byte not
//! inside an edit stays as it was (line endings, Latin-1, comments).

use super::{JointTarget, Number, Program, RobTargetValue, Target};
use crate::error::{decode_lossless, Error, ErrorKind, Location, Result};
use std::fmt::Write as _;
use std::ops::Range;

/// Positions: 0.001 mm is what the controller's single-precision `num`
/// can meaningfully hold near 1 m; a written number is within half of it.
pub const POSITION_RESOLUTION: f64 = 0.001;
/// Quaternion components: six decimals keep the orientation within
/// ~1e-4 degrees and renormalisable.
pub const QUATERNION_RESOLUTION: f64 = 0.000_001;

/// Replace the bytes `span` (which must currently be `expected_old`) by
/// `new`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edit {
    pub span: Range<usize>,
    pub expected_old: Vec<u8>,
    pub new: Vec<u8>,
}

/// Apply edits to `src` (the file `file`): they are sorted by position;
/// overlapping edits, spans outside the file and old bytes that are not
/// what the edit expects are errors, and then nothing is changed.
pub fn apply_edits(file: &str, src: &[u8], edits: &[Edit]) -> Result<Vec<u8>> {
    let mut order: Vec<&Edit> = edits.iter().collect();
    order.sort_by_key(|e| (e.span.start, e.span.end));
    let mut prev_end = 0usize;
    let mut prev_start: Option<usize> = None;
    for e in &order {
        if e.span.start > e.span.end || e.span.end > src.len() {
            return Err(Error::new(
                ErrorKind::Input,
                format!(
                    "edit {}..{} lies outside the file ({} bytes)",
                    e.span.start,
                    e.span.end,
                    src.len()
                ),
            ));
        }
        if prev_start.is_some() && (e.span.start < prev_end || prev_start == Some(e.span.start)) {
            return Err(Error::new(
                ErrorKind::Input,
                format!("edits overlap at byte {}", e.span.start),
            )
            .at(Location::from_offset(file, src, e.span.start)));
        }
        let old = &src[e.span.clone()];
        if old != e.expected_old.as_slice() {
            return Err(Error::new(
                ErrorKind::Input,
                format!(
                    "the file changed: expected {} here, found {}",
                    crate::error::quoted(&decode_lossless(&e.expected_old)),
                    crate::error::quoted(&decode_lossless(old))
                ),
            )
            .at(Location::from_offset(file, src, e.span.start)));
        }
        prev_end = e.span.end;
        prev_start = Some(e.span.start);
    }
    let grow: isize = order
        .iter()
        .map(|e| e.new.len() as isize - e.span.len() as isize)
        .sum();
    let mut out = Vec::with_capacity((src.len() as isize + grow).max(0) as usize);
    let mut at = 0;
    for e in order {
        out.extend_from_slice(&src[at..e.span.start]);
        out.extend_from_slice(&e.new);
        at = e.span.end;
    }
    out.extend_from_slice(&src[at..]);
    Ok(out)
}

/// The edit that writes `value` over the literal `num` of `src`, formatted
/// like the old literal and within `resolution`; `None` when the text
/// would not change.
pub fn number_edit(src: &[u8], num: &Number, value: f64, resolution: f64) -> Option<Edit> {
    let old = src.get(num.span())?;
    let old_text = std::str::from_utf8(old).ok()?;
    let new = format_like(old_text, value, resolution);
    (new.as_bytes() != old).then(|| Edit {
        span: num.span(),
        expected_old: old.to_vec(),
        new: new.into_bytes(),
    })
}

/// Joint angles in degrees: 1e-5° moves a point 1 m from the axis by
/// 0.2 µm, below the position resolution, and keeps a corrected jointtarget
/// as exact as the controller's single-precision `num` holds near 100°.
pub const JOINT_RESOLUTION: f64 = 0.000_01;

/// The edit for `num` when `value` differs from it by more than half of
/// `resolution` (see [`changed_text`]).
fn changed_edit(src: &[u8], num: &Number, value: f64, resolution: f64) -> Option<Edit> {
    let mut new = String::new();
    changed_text(src, num, value, resolution, &mut new).then(|| Edit {
        span: num.span(),
        expected_old: src[num.span()].to_vec(),
        new: new.into_bytes(),
    })
}

/// Whether `value` changes the literal `num` of `src`, its new text then
/// in `buf`: it must differ by more than half of `resolution` (a smaller
/// change is below what the written digits mean, and keeping the old text
/// keeps an unchanged number byte-identical), and its text from the old.
fn changed_text(src: &[u8], num: &Number, value: f64, resolution: f64, buf: &mut String) -> bool {
    if (value - num.value).abs() <= resolution / 2.0 {
        return false;
    }
    let Some(old) = src.get(num.span()) else {
        return false;
    };
    // The literal's value is the parser's: no need to read it again.
    format_like_to(buf, old, value, resolution, Some(num.value)).is_some() && buf.as_bytes() != old
}

/// Edits writing a new position, and (optionally) orientation and robconf,
/// over a robtarget literal of `src`; numbers that do not change beyond
/// their resolution are left alone.
pub fn robtarget_edits(
    src: &[u8],
    value: &RobTargetValue,
    trans: [f64; 3],
    rot: Option<[f64; 4]>,
    robconf: Option<[i32; 4]>,
) -> Vec<Edit> {
    let mut out = Vec::new();
    let mut buf = String::new();
    robtarget_changes(
        src,
        value,
        trans,
        rot,
        robconf,
        &mut buf,
        &mut |span, new| {
            out.push(Edit {
                expected_old: src[span.clone()].to_vec(),
                span,
                new: new.to_vec(),
            });
        },
    );
    out
}

/// The changes [`robtarget_edits`] makes, in order, handed to `each` as
/// the span of a number and its new text (formatted in `buf`): a
/// streamed run writes them straight out, without an edit's copies.
pub fn robtarget_changes(
    src: &[u8],
    value: &RobTargetValue,
    trans: [f64; 3],
    rot: Option<[f64; 4]>,
    robconf: Option<[i32; 4]>,
    buf: &mut String,
    each: &mut dyn FnMut(Range<usize>, &[u8]),
) {
    let mut change = |n: &Number, v: f64, resolution: f64| {
        if changed_text(src, n, v, resolution, buf) {
            each(n.span(), buf.as_bytes());
        }
    };
    for (n, v) in value.trans.iter().zip(trans) {
        change(n, v, POSITION_RESOLUTION);
    }
    if let Some(rot) = rot {
        for (n, v) in value.rot.iter().zip(rot) {
            change(n, v, QUATERNION_RESOLUTION);
        }
    }
    if let Some(cf) = robconf {
        for (n, v) in value.robconf.iter().zip(cf) {
            change(n, f64::from(v), 1.0);
        }
    }
}

/// Edits writing new axis angles (degrees) over a jointtarget literal.
pub fn jointtarget_edits(src: &[u8], target: &JointTarget, robax: [f64; 6]) -> Vec<Edit> {
    target
        .robax
        .iter()
        .zip(robax)
        .filter_map(|(n, v)| changed_edit(src, n, v, JOINT_RESOLUTION))
        .collect()
}

/// How a number literal is written.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Style {
    plus: bool,
    /// Digits after the point, and whether a point is written at all.
    decimals: usize,
    point: bool,
    /// `.5` rather than `0.5`.
    bare_point: bool,
    /// Exponent: letter, explicit sign, minimum digits.
    exp: Option<(char, bool, usize)>,
}

fn style_of(old: &str) -> Style {
    let t = old.trim();
    let plus = t.starts_with('+');
    let t = t.trim_start_matches(['+', '-']).trim_start();
    let (mant, exp) = match t.find(['e', 'E']) {
        Some(i) => {
            let letter = t[i..].chars().next().unwrap_or('E');
            let e = &t[i + 1..];
            let signed = e.starts_with(['+', '-']);
            let digits = e.trim_start_matches(['+', '-']).len();
            (&t[..i], Some((letter, signed, digits.max(1))))
        }
        None => (t, None),
    };
    let (int, decimals, point) = match mant.find('.') {
        Some(i) => (&mant[..i], mant.len() - i - 1, true),
        None => (mant, 0, false),
    };
    Style {
        plus,
        decimals,
        point,
        bare_point: point && int.is_empty(),
        exp,
    }
}

/// Format `value` in the style of the literal `old` (decimals, exponent
/// letter and sign, `.5`, `1.`), with more decimals only where needed to
/// stay within `resolution / 2` of `value`. Deterministic: the same inputs
/// give the same text. If `old` already denotes `value` exactly, it is
/// returned unchanged.
pub fn format_like(old: &str, value: f64, resolution: f64) -> String {
    let mut out = String::new();
    format_like_to(&mut out, old.as_bytes(), value, resolution, None);
    out
}

/// [`format_like`] into `out` (cleared first), `was` the old literal's
/// value where the caller has it; `None` for an old text that is no
/// UTF-8 (never a number the parser read).
fn format_like_to(
    out: &mut String,
    old: &[u8],
    value: f64,
    resolution: f64,
    was: Option<f64>,
) -> Option<()> {
    out.clear();
    if !value.is_finite() {
        out.push_str(std::str::from_utf8(old).ok()?);
    } else if format_like_plain_into(out, old, value, resolution, was).is_none() {
        let text = std::str::from_utf8(old).ok()?;
        out.clear();
        out.push_str(&format_like_general(text, value, resolution));
    }
    Some(())
}

/// [`format_like`] for any literal (`value` finite).
fn format_like_general(old: &str, value: f64, resolution: f64) -> String {
    if old.trim().parse::<f64>().ok() == Some(value) {
        return old.to_string();
    }
    let st = style_of(old);
    let tol = if resolution > 0.0 {
        resolution / 2.0
    } else {
        0.0
    };
    let out = match st.exp {
        Some((letter, signed, width)) => {
            let mut d = st.decimals;
            loop {
                let s = format!("{:.*e}", d, value);
                let back: f64 = s.parse().unwrap_or(f64::NAN);
                if (back - value).abs() <= tol || d >= 17 {
                    break render_exp(&s, letter, signed, width, st.point || d > 0, st.bare_point);
                }
                d += 1;
            }
        }
        None => {
            let mut d = st.decimals;
            let mut s = String::new();
            loop {
                s.clear();
                let back = match fixed(&mut s, value, d) {
                    Some(back) => back,
                    None => {
                        s.clear();
                        let _ = write!(s, "{:.*}", d, value);
                        s.parse().unwrap_or(f64::NAN)
                    }
                };
                if (back - value).abs() <= tol || d >= 17 {
                    break render_plain(&s, st.point, st.bare_point);
                }
                d += 1;
            }
        }
    };
    let out = if is_negative_zero(&out) {
        out.trim_start_matches('-').to_string()
    } else {
        out
    };
    if st.plus && !out.starts_with('-') {
        format!("+{out}")
    } else {
        out
    }
}

/// [`format_like`] for what CAM programs write, `-150.000`: digits, a
/// point and decimals, perhaps a minus, nothing else. The same text
/// without the general path's parsing of the old literal by the standard
/// library and its copies; `None` for any other literal or value (the
/// general path then decides).
#[cfg(test)]
fn format_like_plain(old: &[u8], value: f64, resolution: f64) -> Option<String> {
    let mut s = String::new();
    format_like_plain_into(&mut s, old, value, resolution, None).map(|()| s)
}

/// [`format_like_plain`] into `s` (empty); on `None`, `s` holds anything.
/// `was`: the old literal's value where the caller has it (as the parser
/// read it, which is what `str::parse` reads).
fn format_like_plain_into(
    s: &mut String,
    old: &[u8],
    value: f64,
    resolution: f64,
    was: Option<f64>,
) -> Option<()> {
    let digits = old.strip_prefix(b"-").unwrap_or(old);
    let point = digits.iter().position(|&b| b == b'.')?;
    let (int, frac) = (&digits[..point], &digits[point + 1..]);
    let is_digits = |d: &[u8]| !d.is_empty() && d.iter().all(u8::is_ascii_digit);
    if !is_digits(int) || !is_digits(frac) {
        return None;
    }
    // The old literal's value, as `str::parse` reads it.
    let was = match was {
        Some(w) => w,
        None => {
            let w = super::lane::decimal_value(digits)?;
            if digits.len() < old.len() {
                -w
            } else {
                w
            }
        }
    };
    if was == value {
        s.push_str(std::str::from_utf8(old).ok()?);
        return Some(());
    }
    let tol = if resolution > 0.0 {
        resolution / 2.0
    } else {
        0.0
    };
    for d in frac.len()..=17 {
        s.clear();
        let back = fixed(s, value, d)?;
        if (back - value).abs() <= tol || d >= 17 {
            if is_negative_zero(s) {
                s.remove(0);
            }
            return Some(());
        }
    }
    None
}

fn is_negative_zero(s: &str) -> bool {
    s.starts_with('-')
        && s[1..]
            .split(['e', 'E'])
            .next()
            .is_some_and(|m| m.chars().all(|c| c == '0' || c == '.'))
}

/// `{:.d}` of `v` written at the end of `buf`, and the value that text
/// reads back as; `None` (nothing written) outside what it does exactly.
/// A million corrected targets are three million numbers formatted and
/// read back: this does both in integer arithmetic. `v` is `m·2^e`
/// exactly, so `v·10^d` is `m·10^d` shifted, rounded half to even as the
/// standard formatting rounds; the text's value is that integer over
/// `10^d`, one correctly rounded division of exact operands (below 2^53
/// and 10^22), which is what parsing the text gives.
fn fixed(buf: &mut String, v: f64, d: usize) -> Option<f64> {
    const P10: [u64; 18] = [
        1,
        10,
        100,
        1_000,
        10_000,
        100_000,
        1_000_000,
        10_000_000,
        100_000_000,
        1_000_000_000,
        10_000_000_000,
        100_000_000_000,
        1_000_000_000_000,
        10_000_000_000_000,
        100_000_000_000_000,
        1_000_000_000_000_000,
        10_000_000_000_000_000,
        100_000_000_000_000_000,
    ];
    let p = *P10.get(d)?;
    if !v.is_finite() {
        return None;
    }
    let bits = v.to_bits();
    let negative = bits >> 63 == 1;
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1 << 52) - 1);
    let (m, e) = if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | 1 << 52, biased - 1075)
    };
    // Below 2^53 · 10^17 < 2^110.
    let n = u128::from(m) * u128::from(p);
    let q = if e >= 0 {
        if e > 10 {
            return None;
        }
        n << e
    } else {
        let shift = e.unsigned_abs();
        if shift >= 120 {
            return None;
        }
        let q = n >> shift;
        let rest = n - (q << shift);
        let half = 1u128 << (shift - 1);
        if rest > half || (rest == half && q & 1 == 1) {
            q + 1
        } else {
            q
        }
    };
    let q = u64::try_from(q).ok().filter(|q| *q < 1 << 53)?;
    if negative {
        buf.push('-');
    }
    // The digits by hand (the formatting machinery was a tenth of a
    // streamed correction): all of q's, at least d + 1, and the point d
    // from the end, without dividing by 10^d.
    let mut digits = [b'0'; 24];
    let mut i = digits.len();
    let mut n = q;
    while n > 0 || digits.len() - i <= d {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
    }
    let point = digits.len() - d;
    for &c in &digits[i..point] {
        buf.push(char::from(c));
    }
    if d > 0 {
        buf.push('.');
        for &c in &digits[point..] {
            buf.push(char::from(c));
        }
    }
    let back = q as f64 / p as f64;
    Some(if negative { -back } else { back })
}

fn render_plain(s: &str, point: bool, bare_point: bool) -> String {
    let mut s = s.to_string();
    if point && !s.contains('.') {
        s.push('.');
    }
    if bare_point {
        if let Some(rest) = s.strip_prefix("0.") {
            s = format!(".{rest}");
        } else if let Some(rest) = s.strip_prefix("-0.") {
            s = format!("-.{rest}");
        }
    }
    s
}

/// Rust writes `1.5e-7`; RAPID files write `1.5E-07` or `9E+09`.
fn render_exp(
    s: &str,
    letter: char,
    signed: bool,
    width: usize,
    point: bool,
    bare: bool,
) -> String {
    let (mant, exp) = s.split_once('e').unwrap_or((s, "0"));
    let e: i32 = exp.parse().unwrap_or(0);
    let sign = if e < 0 {
        "-"
    } else if signed {
        "+"
    } else {
        ""
    };
    let mant = render_plain(mant, point && mant.contains('.'), bare);
    format!("{mant}{letter}{sign}{:0width$}", e.abs())
}

/// The statement or declaration of `src` that starts at `start` (through
/// its `;`), and the byte ranges of the words written in it, strings and
/// comments skipped: where an edit of a name in it goes (blanks and
/// comments before `start` are skipped). `None` at the end of the text.
pub fn statement_words(src: &[u8], start: usize) -> Option<(Range<usize>, Vec<Range<usize>>)> {
    let mut scanner = super::scan::Scanner::new(src);
    scanner.skip_to(start);
    let piece = scanner.next_piece().ok()??;
    let words = scanner
        .words(piece.start, piece.end)
        .into_iter()
        .map(|(s, e)| s..e)
        .collect();
    Some((piece.start..piece.end, words))
}

/// The same edits with the bytes taken from the program, which keeps each
/// file's source.
impl Program {
    /// [`apply_edits`] to file `file` of the program.
    pub fn apply_edits(&self, file: usize, edits: &[Edit]) -> Result<Vec<u8>> {
        apply_edits(self.file_name(file), self.source(file), edits)
    }

    /// [`robtarget_edits`] for a target of the program (none for a target
    /// without numbers: a derived one).
    pub fn robtarget_edits(
        &self,
        target: &Target,
        trans: [f64; 3],
        rot: Option<[f64; 4]>,
        robconf: Option<[i32; 4]>,
    ) -> Vec<Edit> {
        match &target.value {
            Some(v) => robtarget_edits(self.source(target.origin.file), v, trans, rot, robconf),
            None => Vec::new(),
        }
    }

    /// [`jointtarget_edits`] for a jointtarget of the program.
    pub fn jointtarget_edits(&self, target: &JointTarget, robax: [f64; 6]) -> Vec<Edit> {
        jointtarget_edits(self.source(target.origin.file), target, robax)
    }

    /// The text of a number literal of file `file`, as written.
    pub fn number_text(&self, file: usize, num: &Number) -> &str {
        num.text(self.source(file))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain path writes what the general one writes, to the byte:
    /// literals of every number of decimals, values near them, at their
    /// rounding ties, far from them, negative zeros.
    #[test]
    fn plain_decimals_are_formatted_as_the_general_path_formats_them() {
        let mut state = 5u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut plain = 0;
        for i in 0..200_000 {
            let decimals = i % 8;
            let old_value = (next() - 0.5) * 2000.0;
            let old = format!("{old_value:.decimals$}");
            let value = match i % 5 {
                0 => old.parse::<f64>().unwrap_or(0.0),
                1 => old_value + (next() - 0.5) * 1e-3,
                2 => (old_value * 1000.0).round() / 1000.0 + 0.0005,
                3 => -(next() * 1e-4),
                _ => (next() - 0.5) * 2000.0,
            };
            for resolution in [0.001, 0.000_001, 0.0] {
                let general = format_like_general(&old, value, resolution);
                if let Some(fast) = format_like_plain(old.as_bytes(), value, resolution) {
                    plain += 1;
                    assert_eq!(fast, general, "{old} {value:e} {resolution}");
                }
            }
        }
        for (old, value) in [
            ("-0.000", 0.0),
            ("0.000", -0.0),
            ("-0.000", -1e-9),
            ("1.", 1.5),
        ] {
            let fast = format_like_plain(old.as_bytes(), value, 0.001);
            assert!(fast.is_none_or(|f| f == format_like_general(old, value, 0.001)));
        }
        assert!(plain > 400_000, "{plain}");
    }

    #[test]
    fn fixed_writes_what_the_standard_formatting_writes() {
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let mut values = vec![
            0.25,
            0.125,
            0.375,
            2.5,
            -2.5,
            1.5,
            -0.0,
            0.0,
            -0.0001,
            0.0005,
            420.08,
            -150.0,
            9e9,
            1e-30,
            123456.789,
            4503599627370495.5,
        ];
        for _ in 0..20_000 {
            let r = next();
            // Spread over magnitudes a program writes, and ties: halves
            // of small integers scaled by powers of two.
            values.push(match r % 3 {
                0 => f64::from_bits(r >> 2) % 1e6,
                1 => ((r >> 8) % 2_000_001) as f64 / 1000.0 - 1000.0,
                _ => ((r >> 8) % 4096) as f64 / 64.0 - 32.0,
            });
        }
        let mut checked = 0;
        for v in values {
            for d in 0..=17 {
                let mut s = String::new();
                if let Some(back) = fixed(&mut s, v, d) {
                    let want = format!("{v:.d$}");
                    assert_eq!(s, want, "{v:e} to {d} places");
                    assert_eq!(
                        back.to_bits(),
                        want.parse::<f64>().unwrap().to_bits(),
                        "{want}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 100_000, "{checked}");
    }

    #[test]
    fn program_keeps_its_sources_for_edits() {
        let a = b"MODULE a\nCONST robtarget p := [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\nENDMODULE\n";
        let b = b"MODULE b\r\nENDMODULE\r\n";
        let prog = crate::rapid::parse_files(&[("a.mod", a), ("b.mod", b)]).unwrap();
        assert_eq!(prog.source(0), a);
        assert_eq!(prog.source(1), b);
        assert_eq!(prog.source(2), b"");
        assert_eq!((prog.file_name(1), prog.file_name(2)), ("b.mod", ""));
        let t = prog.target("p").unwrap();
        assert_eq!(
            prog.number_text(0, &t.value.as_ref().unwrap().trans[2]),
            "3"
        );
        let edits = prog.robtarget_edits(&t, [1.0, 2.0, 4.5], Some([1.0, 0.0, 0.0, 0.0]), None);
        let out = prog.apply_edits(0, &edits).unwrap();
        assert_eq!(
            out,
            apply_edits(
                "a.mod",
                a,
                &robtarget_edits(
                    a,
                    t.value.as_ref().unwrap(),
                    [1.0, 2.0, 4.5],
                    Some([1.0, 0.0, 0.0, 0.0]),
                    None
                )
            )
            .unwrap()
        );
        assert!(String::from_utf8(out).unwrap().contains("[[1,2,4.5]"));
    }

    #[test]
    fn keeps_style_and_precision() {
        let r = POSITION_RESOLUTION;
        assert_eq!(format_like("500", 501.0, r), "501");
        assert_eq!(format_like("500", 500.1234, r), "500.123");
        assert_eq!(format_like("500.00", 500.1, r), "500.10");
        assert_eq!(format_like("500.12345", 500.2, r), "500.20000");
        assert_eq!(format_like("-0.345", 0.5, r), "0.500");
        assert_eq!(format_like(".5", 0.25, r), ".25");
        assert_eq!(format_like(".5", -0.25, r), "-.25");
        assert_eq!(format_like("1.", 2.0, r), "2.");
        assert_eq!(format_like("1.", 2.5, r), "2.5");
        assert_eq!(format_like("9E+09", 8e9, r), "8E+09");
        assert_eq!(format_like("9e9", 8e9, r), "8e9");
        assert_eq!(
            format_like("3.75943E-07", 4.1e-7, QUATERNION_RESOLUTION),
            "4.10000E-07"
        );
        assert_eq!(format_like("-245E-2", -2.5, r), "-2.5E+0");
        assert_eq!(
            format_like("0.64279", 0.6427876, QUATERNION_RESOLUTION),
            "0.642788"
        );
        assert_eq!(format_like("12.5", -0.0001, r), "0.0");
        assert_eq!(format_like("12.5", 12.5, r), "12.5");
    }

    #[test]
    fn written_value_is_within_half_resolution() {
        for &(old, v) in &[
            ("1", 123.456789),
            ("1.0", -987.65432),
            ("1E2", 0.00123),
            (".5", 3.3333),
        ] {
            let s = format_like(old, v, POSITION_RESOLUTION);
            let back: f64 = s.parse().unwrap();
            assert!((back - v).abs() <= 0.0005 + 1e-12, "{old} {v} -> {s}");
        }
    }

    #[test]
    fn edits_splice_and_verify() {
        let src = b"a 12 b \xe9 34\r\n";
        let e = vec![
            Edit {
                span: 9..11,
                expected_old: b"34".to_vec(),
                new: b"35.5".to_vec(),
            },
            Edit {
                span: 2..4,
                expected_old: b"12".to_vec(),
                new: b"-1".to_vec(),
            },
        ];
        assert_eq!(
            apply_edits("f", src, &e).unwrap(),
            b"a -1 b \xe9 35.5\r\n".to_vec()
        );
        let bad = vec![Edit {
            span: 2..4,
            expected_old: b"13".to_vec(),
            new: b"0".to_vec(),
        }];
        assert!(apply_edits("f", src, &bad).is_err());
        let overlap = vec![
            Edit {
                span: 2..4,
                expected_old: b"12".to_vec(),
                new: b"0".to_vec(),
            },
            Edit {
                span: 3..4,
                expected_old: b"2".to_vec(),
                new: b"0".to_vec(),
            },
        ];
        assert!(apply_edits("f", src, &overlap).is_err());
        assert_eq!(apply_edits("f", src, &[]).unwrap(), src.to_vec());
    }
}
