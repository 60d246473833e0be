//! The key under which a fit is remembered ([`super::memo`]): the SHA-256
//! of everything the fit's outcome depends on. The memo's idea, not the
//! fit's: a change to what a fit reads must change this key, and the two
//! are reviewed side by side here.

use super::fit_problem::Problem;
use crate::model::EffectKind;
use sha2::{Digest, Sha256};

impl Problem {
    /// The memo's key of a fit of `kinds` to `rows` ([`super::memo`]): the
    /// SHA-256 of everything the fit's outcome depends on.
    pub(crate) fn memo_key(
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
}
