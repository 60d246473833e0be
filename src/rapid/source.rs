//! The bytes a file of a program was read from, kept as they were read:
//! every span of the program points into them. A file mapped into
//! memory is held as it is, not copied (a program of 200 MB would
//! otherwise be in memory twice).

use std::sync::Arc;

/// A file's bytes, shared (cloning a program does not copy them).
#[derive(Clone)]
pub struct Source(Arc<dyn AsRef<[u8]> + Send + Sync>);

impl Source {
    /// The bytes of `held` (a vector, a memory map, ...), held as they are.
    pub fn new(held: impl AsRef<[u8]> + Send + Sync + 'static) -> Source {
        Source(Arc::new(held))
    }

    /// A copy of `bytes`.
    pub fn copied(bytes: &[u8]) -> Source {
        Source::new(bytes.to_vec())
    }

    pub fn bytes(&self) -> &[u8] {
        (*self.0).as_ref()
    }
}

impl std::fmt::Debug for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Source({} bytes)", self.bytes().len())
    }
}
