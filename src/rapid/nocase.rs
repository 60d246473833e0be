//! A name as RAPID compares names: without regard to ASCII case. Used as
//! a hash key borrowed from the source, so that a table of a million
//! declared names is built without allocating a lower-case copy of each.

use std::hash::{Hash, Hasher};

/// A name compared without regard to case, as RAPID compares names.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NoCase<'a>(pub(crate) &'a [u8]);

impl Hash for NoCase<'_> {
    fn hash<H: Hasher>(&self, state: &mut H) {
        // FNV-1a over the lower-case bytes, handed on as one number.
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for &b in self.0 {
            h = (h ^ u64::from(b.to_ascii_lowercase())).wrapping_mul(0x100_0000_01b3);
        }
        state.write_u64(h);
    }
}

impl PartialEq for NoCase<'_> {
    fn eq(&self, other: &Self) -> bool {
        self.0.eq_ignore_ascii_case(other.0)
    }
}

impl Eq for NoCase<'_> {}
