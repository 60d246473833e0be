//! Fingerprints of what a run read, as a corrected file's marker records
//! them: `sha256:` and the first 16 hex digits of the SHA-256 of bytes (a
//! file as read), or of a value's byte encoding written field by field
//! through an [`Encoder`] (each encoding documented and versioned where
//! its value is defined, never a type's `Debug` text, which a changed
//! derive would change).
//!
//! A foundation: imports nothing of the library.

use sha2::{Digest, Sha256};

/// `sha256:` and the first 16 hex digits of the bytes' SHA-256: enough to
/// tell files apart, short enough to read.
pub fn fingerprint(bytes: &[u8]) -> String {
    hex_of(&Sha256::digest(bytes))
}

fn hex_of(digest: &[u8]) -> String {
    let hex: String = digest.iter().take(8).map(|b| format!("{b:02x}")).collect();
    format!("sha256:{hex}")
}

/// A value's byte encoding, hashed as it is written (a schedule of a
/// million visits is tens of megabytes). Integers and floats are written
/// little-endian, a float as its IEEE 754 bits, text as its length (u32)
/// then its UTF-8 bytes.
pub struct Encoder {
    sha: Sha256,
    buf: Vec<u8>,
}

/// Bytes gathered before they are hashed (many small fields a page at a
/// time).
const PAGE: usize = 8192;

impl Encoder {
    /// A new encoding, starting with its `tag` (the encoding's name and
    /// version, e.g. `rapidtherm schedule 1`) and a zero byte.
    pub fn new(tag: &str) -> Encoder {
        let mut e = Encoder {
            sha: Sha256::new(),
            buf: Vec::with_capacity(PAGE + 64),
        };
        e.bytes(tag.as_bytes());
        e.u8(0);
        e
    }

    fn bytes(&mut self, b: &[u8]) {
        if self.buf.len() + b.len() > PAGE {
            self.sha.update(&self.buf);
            self.buf.clear();
        }
        if b.len() > PAGE {
            self.sha.update(b);
        } else {
            self.buf.extend_from_slice(b);
        }
    }

    pub fn u8(&mut self, v: u8) {
        self.bytes(&[v]);
    }

    pub fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }

    pub fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }

    /// A float by its bits: `-0.0` and `0.0` differ, every NaN is its own.
    pub fn f64(&mut self, v: f64) {
        self.bytes(&v.to_bits().to_le_bytes());
    }

    /// Text: its length in bytes (u32), then its bytes.
    pub fn text(&mut self, s: &str) {
        self.u32(u32::try_from(s.len()).unwrap_or(u32::MAX));
        self.bytes(s.as_bytes());
    }

    /// The fingerprint of everything written.
    pub fn finish(mut self) -> String {
        self.sha.update(&self.buf);
        hex_of(&self.sha.finalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_fingerprint_is_the_first_16_hex_digits_of_sha256() {
        // SHA-256("abc") = ba7816bf8f01cfea414140de5dae2223...
        assert_eq!(fingerprint(b"abc"), "sha256:ba7816bf8f01cfea");
    }

    #[test]
    fn an_encoding_is_its_fields_bytes_whatever_the_pages() {
        let mut e = Encoder::new("t 1");
        e.text("ab");
        e.u32(7);
        e.f64(1.5);
        let mut bytes = b"t 1\0".to_vec();
        bytes.extend_from_slice(&2u32.to_le_bytes());
        bytes.extend_from_slice(b"ab");
        bytes.extend_from_slice(&7u32.to_le_bytes());
        bytes.extend_from_slice(&1.5f64.to_bits().to_le_bytes());
        assert_eq!(e.finish(), fingerprint(&bytes));
        // Many fields across pages, and one field larger than a page.
        let mut e = Encoder::new("t 1");
        let mut bytes = b"t 1\0".to_vec();
        for i in 0..5000u32 {
            e.u32(i);
            bytes.extend_from_slice(&i.to_le_bytes());
        }
        let big = "x".repeat(3 * PAGE);
        e.text(&big);
        bytes.extend_from_slice(&(big.len() as u32).to_le_bytes());
        bytes.extend_from_slice(big.as_bytes());
        assert_eq!(e.finish(), fingerprint(&bytes));
    }
}
