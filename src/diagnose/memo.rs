//! Fits remembered by what they were fitted to. A diagnosis fits the same
//! model to the same rows many times over: the forward pass, the backward
//! elimination, the tests of near-equal candidates, the absolute pass and
//! each fold of every held-out score ask again for fits made before. The
//! memo keys a fit by the SHA-256 of everything its outcome depends on
//! (the arm, the fixed effects, the rows' data, the temperature history,
//! the weights, the effects fitted, where the fit starts and whether only
//! plausible values are reported), so problems derived from one another may share it safely:
//! two fits with one key are the same computation.

use super::fit::{Fit, Problem};
use crate::model::EffectKind;
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Entries kept before the memo starts again (a fit is a few hundred
/// bytes; a diagnosis makes a few thousand).
const CAPACITY: usize = 20_000;

/// The memo shared by a problem and those derived from it.
#[derive(Clone, Default)]
pub struct FitMemo(Arc<Inner>);

#[derive(Default)]
struct Inner {
    fits: Mutex<HashMap<[u8; 32], Fit>>,
    hits: AtomicUsize,
}

impl std::fmt::Debug for FitMemo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "FitMemo({} hits)", self.hits())
    }
}

impl FitMemo {
    /// How many fits were answered from the memo.
    pub fn hits(&self) -> usize {
        self.0.hits.load(Ordering::Relaxed)
    }

    pub(crate) fn get(&self, key: &[u8; 32]) -> Option<Fit> {
        let found = self.0.fits.lock().ok()?.get(key).cloned();
        if found.is_some() {
            self.0.hits.fetch_add(1, Ordering::Relaxed);
        }
        found
    }

    pub(crate) fn put(&self, key: [u8; 32], fit: &Fit) {
        if let Ok(mut m) = self.0.fits.lock() {
            if m.len() >= CAPACITY {
                m.clear();
            }
            m.insert(key, fit.clone());
        }
    }
}

/// The key of a fit of `kinds` to `rows` of `problem`.
pub(crate) fn key(
    problem: &Problem,
    rows: &[usize],
    kinds: &[EffectKind],
    plausible_only: bool,
    start: Option<&[f64]>,
) -> [u8; 32] {
    let mut h = Sha256::new();
    let f = |h: &mut Sha256, v: f64| h.update(v.to_le_bytes());
    h.update([u8::from(plausible_only)]);
    match start {
        None => h.update(b"cold"),
        Some(t) => {
            h.update(b"from");
            t.iter().for_each(|&v| f(&mut h, v));
        }
    }
    for k in kinds {
        h.update(k.name().as_bytes());
        h.update([0]);
    }
    h.update(b"|");
    // The arm's geometry and thermal model, as one text: it is hashed, never
    // written anywhere.
    h.update(format!("{:?}", problem.base).as_bytes());
    for e in &problem.fixed {
        h.update(e.kind.name().as_bytes());
        for &v in &e.params {
            f(&mut h, v);
        }
    }
    h.update(problem.history.digest());
    f(&mut h, problem.w_ori);
    f(&mut h, problem.noise_mm);
    h.update([
        u8::from(problem.centre_poses),
        u8::from(problem.origins),
        u8::from(problem.zero_jacobians.is_some()),
    ]);
    for &i in rows {
        h.update((i as u64).to_le_bytes());
        let Some(r) = problem.rows.get(i) else {
            continue;
        };
        f(&mut h, r.time_min);
        r.q.iter().for_each(|&v| f(&mut h, v));
        r.temps.iter().for_each(|&v| f(&mut h, v));
        r.position.iter().for_each(|&v| f(&mut h, v));
        if let Some(o) = &r.orientation {
            o.coords.iter().for_each(|&v| f(&mut h, v));
        }
        h.update((r.pose as u64).to_le_bytes());
    }
    h.finalize().into()
}
