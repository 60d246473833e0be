//! A diagnosis in sentences: the gap, the verdict, where the gap lies, what
//! each selected effect did, and what to do. The caller names its own ways
//! of acting on the advice ([`Remedies`]): a command line names its flags,
//! the library's default names none.

use super::finding::Finding;
use super::gap::NoiseSource;
use super::joint_signature::JointShape;
use super::verdict::{Advice, Diagnosis, NotNamedWhy, ScoredIn, Verdict};
use serde::Serializer;

/// How the caller lets a user act on the advice, as phrases that fit in
/// the sentences below.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Remedies {
    /// Starts "(<give_noise> or measure poses again to judge it)".
    pub give_noise: String,
    /// Starts "<save_model> and correct programs with it: …".
    pub save_model: String,
}

impl Default for Remedies {
    fn default() -> Self {
        Remedies {
            give_noise: "give the instrument's noise level".into(),
            save_model: "Save the model with the diagnosed effects".into(),
        }
    }
}

/// Where the noise level comes from, in words.
pub fn noise_source(source: &NoiseSource) -> String {
    match source {
        NoiseSource::Given => "given".into(),
        NoiseSource::Estimated { differences } => {
            format!("estimated from {differences} repeated-pose second differences")
        }
        NoiseSource::NotMeasured { dof } => format!(
            "not measured: no repeated poses and none given; the residual the model found leaves, on {dof} degrees of freedom, and each F test divides by its larger model's residual variance"
        ),
    }
}

/// Serialise a noise source as its words (the JSON field `source`).
pub fn serialize_noise_source<S: Serializer>(
    source: &NoiseSource,
    s: S,
) -> Result<S::Ok, S::Error> {
    s.serialize_str(&noise_source(source))
}

/// The diagnosis as lines of text.
pub fn words(d: &Diagnosis, remedies: &Remedies) -> Vec<String> {
    let gap = &d.gap;
    let noise = &d.noise;
    let mut words = Vec::new();
    words.push(format!(
        "Gap of the current model: {:.3} mm RMS (x {:.3}, y {:.3}, z {:.3}), {:.3} mm max over {} rows (noise {:.3} mm RMS, {}).",
        gap.rms_mm,
        gap.axis_rms_mm[0],
        gap.axis_rms_mm[1],
        gap.axis_rms_mm[2],
        gap.max_mm,
        gap.n,
        noise.rms_mm,
        noise_source(&noise.source)
    ));
    // Which source drove the temperatures, where the data carry none.
    if d.temperatures != super::temps::TempSource::Measured {
        words.push(d.temperatures.words());
    }
    verdict_words(d, remedies, &mut words);
    beyond_library_words(d, &mut words);
    words.extend(not_named_words(d));
    words.extend(stability_words(d));
    words.extend(held_words(d));
    words.push(advice(&d.advice, remedies));
    words.extend(detection_words(d));
    if let Some(limits) = joint_limit_words(d) {
        words.push(limits);
    }
    for a in &d.ambiguities {
        let why = match a.correlation {
            Some(c) => format!("correlation {c:.2}"),
            None => "the set scores alike on held-out data with either".to_string(),
        };
        words.push(format!(
            "{} and {} are nearly indistinguishable on these poses ({why}): {}.",
            a.pair[0],
            a.pair[1],
            a.separate_by.words()
        ));
    }
    words
}

/// The verdict, and what the effects it names did, step by step.
fn verdict_words(d: &Diagnosis, remedies: &Remedies, words: &mut Vec<String>) {
    let noise = &d.noise;
    let (cv0, cv) = (d.gap_before_mm, d.gap_after_mm);
    match &d.verdict {
        Verdict::None => match d.advice {
            Advice::NoiseNotMeasured { left_mm } => words.push(format!(
                "Verdict: none. No effect of the library is significant against what is left ({left_mm:.3} mm held-out; {cv0:.3} mm before), but the noise was not measured (no repeated poses): whether that is noise cannot be said ({} or measure poses again to judge it).",
                remedies.give_noise
            )),
            _ => words.push(
                "Verdict: none. The gap is at the measurement noise; nothing to explain.".into(),
            ),
        },
        Verdict::Unexplained { partial } => {
            let partial: Vec<&str> = partial.iter().map(|k| k.name()).collect();
            words.push(format!(
                "Verdict: unexplained. No effect of the library explains the gap (held-out {:.3} mm, {:.3} mm after the best candidates{}).",
                cv0,
                cv,
                if partial.is_empty() {
                    String::new()
                } else {
                    format!(", which explain only part of it: {}", partial.join(", "))
                }
            ));
            let after = !partial.is_empty() && !d.where_after.findings.is_empty();
            if !(after && grows_after(d)) {
                words.extend(d.where_.time_shape.as_ref().and_then(|t| t.words(false)));
            }
            words.extend(whole_words(d, after));
            if after {
                words.push(format!("What {} leaves:", partial.join(" + ")));
                words.extend(after_words(d));
            }
        }
        Verdict::ExplainedBy { remainder, .. } | Verdict::Ambiguous { remainder, .. } => {
            words.push(format!("Verdict: {}.", d.verdict.labels().join(" + ")));
            let thermal = d.verdict.effects().iter().any(|k| k.is_thermal());
            if !(*remainder && grows_after(d)) {
                words.extend(d.where_.time_shape.as_ref().and_then(|t| t.words(thermal)));
            }
            words.extend(whole_words(d, *remainder));
            for s in &d.steps {
                let stage = match s.part {
                    ScoredIn::OverTime => "Over time (each pose's own offset fitted), adding",
                    ScoredIn::Absolute => "Over time (the static effects fitted), adding",
                    ScoredIn::Static => "Static (the thermal effects fitted), adding",
                    ScoredIn::All => "Adding",
                };
                let change = if s.drop_pct >= 0.0 {
                    format!("−{:.0} %", s.drop_pct)
                } else {
                    format!("+{:.0} %: named in-sample, where too few poses are left to hold any out", -s.drop_pct)
                };
                words.push(format!(
                    "{stage} {}: held-out gap {:.3} → {:.3} mm ({change}).",
                    s.added, s.gap_before_mm, s.gap_after_mm
                ));
            }
            if *remainder && d.left_over_time {
                let over_time = d.stages.first().map_or(cv, |s| s.gap_after_mm);
                words.push(format!(
                    "What changes over time and they leave ({over_time:.3} mm held-out with each pose's own offset, noise {:.3} mm) is not explained by the library:",
                    noise.rms_mm
                ));
                words.extend(after_words(d));
            } else if *remainder {
                words.push(format!(
                    "What they leave ({:.3} mm held-out, noise {:.3} mm) is not explained by the library:",
                    cv, noise.rms_mm
                ));
                words.extend(after_words(d));
            }
        }
    }
}

/// What the library's effects do not hold: a drift over time, a growth
/// with the square of the temperature rise, a joint's own shape, a static
/// part left unattributed.
fn beyond_library_words(d: &Diagnosis, words: &mut Vec<String>) {
    let noise = &d.noise;
    if let Some(t) = &d.time_drift {
        words.push(t.words());
    }
    if let Some(q) = &d.quadratic_growth {
        let replaced: Vec<&str> = q.replaces.iter().map(|k| k.name()).collect();
        words.push(format!(
            "What changes over time grows with the square of the links' temperature rise, beyond the library's linear expansion: {:.3} mm RMS (F = {:.1} on {} parameters, p = {:.1e}){}.",
            q.rms_mm,
            q.test.f,
            q.test.df1,
            q.test.p_value,
            match (&q.alike, replaced.is_empty()) {
                (_, true) => String::new(),
                (Some(t), false) => format!(
                    "; {} fit the change about as well with more parameters (F = {:.1} beyond it, p = {:.1e}), and are the other candidate",
                    replaced.join(" + "),
                    t.f,
                    t.p_value
                ),
                (None, false) => format!(
                    "; {} added nothing beyond it and is not named",
                    replaced.join(", ")
                ),
            }
        ));
    }
    if let Some(j) = &d.joint_signature {
        let size = match j.shape {
            JointShape::Cyclic { .. } => format!("amplitude {:.3} mrad", j.amplitude_mrad),
            JointShape::Backlash { lags } => format!(
                "play {:.3} mrad, the axis stopping {} where it was sent",
                j.amplitude_mrad,
                if lags { "short of" } else { "beyond" }
            ),
        };
        words.push(format!(
            "Beyond a full kinematic calibration, the static gap follows {} ({size} from the fit): {:.3} mm RMS (F = {:.1} on {} parameters, p = {:.1e}); no effect of the library has this shape{}.",
            j.follows(),
            j.rms_mm,
            j.test.f,
            j.test.df1,
            j.test.p_value,
            if j.sag_beyond.is_some_and(|t| !t.significant()) {
                "; gravity-sag added nothing beyond it and is not named"
            } else {
                ""
            }
        ));
    }
    // A static part the poses are too few to attribute: said, not judged.
    if let Some(st) = d
        .stages
        .iter()
        .find(|s| s.part == ScoredIn::Static && !s.judged)
        .filter(|s| s.gap_after_mm > 1.5 * noise.rms_mm)
    {
        words.push(format!(
            "Pose-to-pose error of {:.3} mm (held-out, noise {:.3} mm) stays the same over time and is left unattributed: these poses give fewer numbers than a full kinematic calibration takes up, so the arm's own geometry cannot be told from other static causes (measure more poses, spread over the joint ranges).",
            st.gap_after_mm, noise.rms_mm
        ));
    }
}

/// The sizes of the effects these data would have revealed.
fn detection_words(d: &Diagnosis) -> Option<String> {
    if d.detection_limits.is_empty() {
        return None;
    }
    let list: Vec<String> = d
        .detection_limits
        .iter()
        .map(|l| format!("{} above {:.3} mm", l.effect.name(), l.flange_mm))
        .collect();
    let named = !d.verdict.effects().is_empty();
    Some(format!(
        "{} (at {:.0} %, with 90 % power, beyond the rest of what was found; the largest move of the flange at the calibration pose over these times): {}.",
        if named {
            "These poses, times and noise would have revealed"
        } else {
            "No effect named: nothing the data could have seen beyond these sizes"
        },
        100.0 * d.level,
        list.join(", ")
    ))
}

/// The effects the selection took and the verdict does not name, and why.
fn not_named_words(d: &Diagnosis) -> Vec<String> {
    d.not_named
        .iter()
        .map(|n| match &n.why {
            NotNamedWhy::Unpinned => format!(
                "{} is not named: none of its parameters is pinned by these data (each held as not identifiable or on a bound of its range).",
                n.effect.name()
            ),
            NotNamedWhy::BelowLimit { size_mm, limit_mm } => format!(
                "{} is not named: it fits {size_mm:.3} mm, below the {limit_mm:.3} mm these poses, times and noise could reveal along its shape.",
                n.effect.name()
            ),
            NotNamedWhy::Unstable {
                named_in,
                resamples,
            } => format!(
                "{} is a candidate, not a verdict: named again in only {named_in} of {resamples} resampled fits (a quarter of the poses or time blocks left out; a verdict needs 80 %).",
                n.effect.name()
            ),
        })
        .collect()
}

/// How often each effect named is named again over resampled fits.
fn stability_words(d: &Diagnosis) -> Option<String> {
    let named = d.verdict.effects();
    let list: Vec<String> = d
        .stability
        .iter()
        .filter(|st| named.contains(&st.effect))
        .map(|st| format!("{} {} of {}", st.effect.name(), st.named_in, st.resamples))
        .collect();
    (!list.is_empty()).then(|| {
        format!(
            "Named again over resampled fits (a quarter of the poses or time blocks left out, the F test beyond the rest at 1 %): {}.",
            list.join(", ")
        )
    })
}

/// Of each effect named, the parameters held rather than fitted, with the
/// value each is held at; for the geometry and the frame (many of whose
/// parameters no set of poses pins) only how many.
fn held_words(d: &Diagnosis) -> Vec<String> {
    let named = d.verdict.effects();
    let mut out = Vec::new();
    for c in d.candidates.iter().filter(|c| c.selected) {
        let Some(kind) = crate::model::EffectKind::from_name(&c.name) else {
            continue;
        };
        if !named.contains(&kind) {
            continue;
        }
        let held: Vec<&super::verdict::ParamOut> =
            c.params.iter().filter(|p| p.held.is_some()).collect();
        if held.is_empty() {
            continue;
        }
        let short = |p: &super::verdict::ParamOut| {
            p.name
                .strip_prefix(&format!("{}.", c.name))
                .unwrap_or(&p.name)
                .to_string()
        };
        if matches!(
            kind,
            crate::model::EffectKind::GeometryOffset | crate::model::EffectKind::TrackerFrame
        ) {
            out.push(format!(
                "Of {}, {} of {} parameters are held, not fitted (not identifiable from these poses).",
                c.name,
                held.len(),
                c.params.len()
            ));
        } else {
            let list: Vec<String> = held
                .iter()
                .map(|p| {
                    let why = match &p.held {
                        Some(super::unidentified::Unidentified::AtBound { .. }) => {
                            "on a bound of its range"
                        }
                        Some(super::unidentified::Unidentified::Implausible { .. }) => {
                            "its fit was implausible"
                        }
                        _ => "not identifiable",
                    };
                    format!("{} at {:.4} {} ({why})", short(p), p.value, p.unit)
                })
                .collect();
            out.push(format!(
                "Of {}, held, not fitted: {}.",
                c.name,
                list.join(", ")
            ));
        }
    }
    out
}

/// Where the static stage looked for a joint's own error and found none,
/// what it would have seen: per axis, the largest of its signatures'
/// limits (any number of cycles tried, at the worst phase, or backlash).
fn joint_limit_words(d: &Diagnosis) -> Option<String> {
    if d.joint_signature.is_some() || d.joint_limits.is_empty() {
        return None;
    }
    let mut per_axis: Vec<(usize, f64)> = Vec::new();
    for l in &d.joint_limits {
        match per_axis.iter_mut().find(|(a, _)| *a == l.axis) {
            Some((_, m)) => *m = m.max(l.amplitude_mrad),
            None => per_axis.push((l.axis, l.amplitude_mrad)),
        }
    }
    let list: Vec<String> = per_axis
        .iter()
        .map(|(axis, m)| format!("axis {axis} above {m:.3} mrad"))
        .collect();
    Some(format!(
        "Beyond a full kinematic calibration, a cyclic error of a joint angle (1 to 4 cycles per turn, at any phase) or backlash would have been seen (at the level its test is held to, with 90 % power): {}.",
        list.join(", ")
    ))
}

/// Whether what is left is said to change over time ([`after_words`]):
/// then that is the one description of the change over time, and the whole
/// gap's is not said beside it.
fn grows_after(d: &Diagnosis) -> bool {
    d.where_after
        .time_shape
        .as_ref()
        .and_then(|t| t.words(true))
        .is_some()
}

/// Whether the report says `f`: a joint's error is described once, by the
/// joint signature where one was tested beyond a full calibration (the
/// localisation's harmonic is fitted to the raw gap, geometry and all, and
/// its amplitude is not the joint's).
fn said(f: &Finding, d: &Diagnosis) -> bool {
    !(matches!(f, Finding::FollowsJoint(_)) && d.joint_signature.is_some())
}

/// Whether `a` and `b` describe one thing (a step in time, the joint the
/// gap follows), of which the report says one.
fn one_thing(a: &Finding, b: &Finding) -> bool {
    matches!(
        (a, b),
        (Finding::Step(_), Finding::Step(_)) | (Finding::FollowsJoint(_), Finding::FollowsJoint(_))
    )
}

/// Where the whole gap lies. `after_said`: what the effects leave is
/// described too; a step or a joint found there is said there only (it is
/// the finding beyond the effects), not a second time with the whole gap's
/// numbers.
fn whole_words(d: &Diagnosis, after_said: bool) -> Vec<String> {
    let after: Vec<&Finding> = if after_said {
        d.where_after
            .findings
            .iter()
            .filter(|f| said(f, d))
            .collect()
    } else {
        Vec::new()
    };
    d.where_
        .findings
        .iter()
        .filter(|f| said(f, d) && !after.iter().any(|g| one_thing(f, g)))
        .map(Finding::words)
        .collect()
}

/// Where what is left lies, indented under the sentence that introduces
/// it; its change over time said only where it grows (it is what is left).
fn after_words(d: &Diagnosis) -> Vec<String> {
    let w = &d.where_after;
    w.time_shape
        .as_ref()
        .and_then(|t| t.words(true))
        .into_iter()
        .chain(w.findings.iter().filter(|f| said(f, d)).map(Finding::words))
        .map(|s| format!("  {s}"))
        .collect()
}

/// What to do, in one sentence.
fn advice(advice: &Advice, remedies: &Remedies) -> String {
    match advice {
        Advice::Nothing => "Nothing to do: the model is as good as the measurement.".into(),
        Advice::NoiseNotMeasured { .. } => {
            "Nothing the library has would improve the model; whether what is left is only measurement noise is not known.".into()
        }
        Advice::LookThere { axis, step_min } => {
            let mut hint = String::from("Look where it points");
            if let Some(axis) = axis {
                hint.push_str(&format!(" (axis {axis}: its gearbox or encoder)"));
            }
            if let Some((before, after)) = step_min {
                hint.push_str(&format!(
                    " (what happened between minute {before:.0} and {after:.0}: a knock, a slipping fixture or tracker)"
                ));
            }
            hint.push_str(", and measure more poses and times there before trusting a correction.");
            hint
        }
        Advice::SaveModel { from_mm, to_mm } => format!(
            "{} and correct programs with it: the held-out gap goes from {:.3} to {:.3} mm.",
            remedies.save_model, from_mm, to_mm
        ),
    }
}

impl Diagnosis {
    /// The diagnosis in sentences, with the library's own remedies
    /// ([`Remedies::default`]).
    pub fn words(&self) -> Vec<String> {
        words(self, &Remedies::default())
    }
}
