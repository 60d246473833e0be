//! Fits remembered by what they were fitted to. A diagnosis fits the same
//! model to the same rows many times over: the forward pass, the backward
//! elimination, the tests of near-equal candidates, the absolute pass and
//! each fold of every held-out score ask again for fits made before. The
//! memo keys a fit by the SHA-256 of everything its outcome depends on
//! (the arm, the fixed effects, the rows' data, the temperature history,
//! the weights, the effects fitted, where the fit starts and whether only
//! plausible values are reported; `fit_key.rs`), so problems derived from
//! one another may share it safely: two fits with one key are the same
//! computation.

use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Entries kept before the memo starts again (a fit is a few hundred
/// bytes; a diagnosis makes a few thousand).
const CAPACITY: usize = 20_000;

/// The memo shared by a problem and those derived from it: values by the
/// SHA-256 of what they were computed from (the key is the caller's:
/// `Problem::memo_key` for a fit).
pub struct Memo<T>(Arc<Inner<T>>);

struct Inner<T> {
    fits: Mutex<HashMap<[u8; 32], T>>,
    hits: AtomicUsize,
}

impl<T> Clone for Memo<T> {
    fn clone(&self) -> Self {
        Memo(self.0.clone())
    }
}

impl<T> Default for Memo<T> {
    fn default() -> Self {
        Memo(Arc::new(Inner {
            fits: Mutex::new(HashMap::new()),
            hits: AtomicUsize::new(0),
        }))
    }
}

impl<T> std::fmt::Debug for Memo<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Memo({} hits)", self.0.hits.load(Ordering::Relaxed))
    }
}

impl<T: Clone> Memo<T> {
    /// How many fits were answered from the memo.
    pub fn hits(&self) -> usize {
        self.0.hits.load(Ordering::Relaxed)
    }

    pub(crate) fn get(&self, key: &[u8; 32]) -> Option<T> {
        let found = self.0.fits.lock().ok()?.get(key).cloned();
        if found.is_some() {
            self.0.hits.fetch_add(1, Ordering::Relaxed);
        }
        found
    }

    pub(crate) fn put(&self, key: [u8; 32], fit: &T) {
        if let Ok(mut m) = self.0.fits.lock() {
            if m.len() >= CAPACITY {
                m.clear();
            }
            m.insert(key, fit.clone());
        }
    }
}
