//! What a marker's basis and model say, as types: a run compares what it
//! would write with what a file's marker says by meaning (case and
//! spacing aside, as a hand or an editor may change them), and writes a
//! marker's text back exactly as it was read or made.
//!
//! The meaning is read from the field's canonical form ([`canonical`]),
//! and written back as that form: two fields mean the same exactly where
//! their canonical forms are equal, as when they were compared as
//! strings, and the seal covers the same bytes.

use std::fmt;

/// A field as compared and sealed: ASCII case folded, every run of
/// spaces one space, none at the ends (what a hand or an editor may
/// change without changing what the marker says).
pub(super) fn canonical(field: &str) -> String {
    field
        .split_ascii_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_lowercase()
}

/// When a marker's targets were corrected for, as its text says it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Basis {
    /// As made or read (a marker read keeps its case).
    text: String,
    kind: BasisKind,
}

/// What a basis means (its parts in canonical form).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BasisKind {
    /// `minute 120`: one moment (the minute as written).
    Minute(String),
    /// `steady state`.
    Steady,
    /// `schedule v1 sha256:…`: a schedule, by the version of its encoding
    /// and its fingerprint.
    Schedule { version: String, print: String },
    /// `estimate v1 sha256:…`: the times estimated from the program, by
    /// the version of the request's encoding and its fingerprint.
    Estimate { version: String, print: String },
    /// `runtime RtWarm`: the correction made on the controller by the
    /// module named.
    Runtime(String),
    /// Any other text (a marker of another version, or edited by hand).
    Other(String),
}

impl Basis {
    /// The basis a text says.
    pub fn parse(text: &str) -> Basis {
        let c = canonical(text);
        let words: Vec<&str> = c.split(' ').collect();
        let kind = match words.as_slice() {
            ["minute", t] => BasisKind::Minute(t.to_string()),
            ["steady", "state"] => BasisKind::Steady,
            ["schedule", v, p] => BasisKind::Schedule {
                version: v.to_string(),
                print: p.to_string(),
            },
            ["estimate", v, p] => BasisKind::Estimate {
                version: v.to_string(),
                print: p.to_string(),
            },
            ["runtime", m] => BasisKind::Runtime(m.to_string()),
            _ => BasisKind::Other(c),
        };
        Basis {
            text: text.to_string(),
            kind,
        }
    }

    /// What it means.
    pub fn kind(&self) -> &BasisKind {
        &self.kind
    }

    /// Both say the same (case and spacing aside).
    pub fn same(&self, other: &Basis) -> bool {
        self.kind == other.kind
    }

    /// The canonical form, as sealed.
    pub(super) fn canonical(&self) -> String {
        self.kind.to_string()
    }
}

impl From<&str> for Basis {
    fn from(text: &str) -> Basis {
        Basis::parse(text)
    }
}

impl fmt::Display for BasisKind {
    /// The canonical form.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BasisKind::Minute(t) => write!(f, "minute {t}"),
            BasisKind::Steady => f.write_str("steady state"),
            BasisKind::Schedule { version, print } => write!(f, "schedule {version} {print}"),
            BasisKind::Estimate { version, print } => write!(f, "estimate {version} {print}"),
            BasisKind::Runtime(m) => write!(f, "runtime {m}"),
            BasisKind::Other(c) => f.write_str(c),
        }
    }
}

impl fmt::Display for Basis {
    /// The text as made or read.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// The model and arm a marker's targets were corrected with
/// (`embedded default model, embedded IRB 140 arm`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MarkerModel {
    /// As made or read.
    text: String,
    kind: ModelArmKind,
}

/// What a model field means (its parts in canonical form).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModelArmKind {
    /// `<model> model, <arm> arm`.
    Of { model: ModelUsed, arm: String },
    /// Any other text.
    Other(String),
}

/// The model of a marker's field.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModelUsed {
    /// `embedded default`.
    Default,
    /// `embedded <name>`: a model of the library by name.
    Named(String),
    /// `sha256:…`: a model file, by its fingerprint.
    File(String),
    /// Any other text.
    Other(String),
}

impl MarkerModel {
    /// The model and arm a text says.
    pub fn parse(text: &str) -> MarkerModel {
        let c = canonical(text);
        let of = c.split_once(", ").and_then(|(model, arm)| {
            Some((model.strip_suffix(" model")?, arm.strip_suffix(" arm")?))
        });
        let kind = match of {
            Some((model, arm)) => ModelArmKind::Of {
                model: ModelUsed::parse(model),
                arm: arm.to_string(),
            },
            None => ModelArmKind::Other(c),
        };
        MarkerModel {
            text: text.to_string(),
            kind,
        }
    }

    /// What it means.
    pub fn kind(&self) -> &ModelArmKind {
        &self.kind
    }

    /// Both say the same (case and spacing aside).
    pub fn same(&self, other: &MarkerModel) -> bool {
        self.kind == other.kind
    }

    /// The canonical form, as sealed.
    pub(super) fn canonical(&self) -> String {
        self.kind.to_string()
    }
}

impl From<&str> for MarkerModel {
    fn from(text: &str) -> MarkerModel {
        MarkerModel::parse(text)
    }
}

impl ModelUsed {
    /// From a canonical model part (before ` model`).
    fn parse(c: &str) -> ModelUsed {
        if c == "embedded default" {
            ModelUsed::Default
        } else if let Some(name) = c.strip_prefix("embedded ") {
            ModelUsed::Named(name.to_string())
        } else if c.starts_with("sha256:") && !c.contains(' ') {
            ModelUsed::File(c.to_string())
        } else {
            ModelUsed::Other(c.to_string())
        }
    }
}

impl fmt::Display for ModelUsed {
    /// The canonical form.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelUsed::Default => f.write_str("embedded default"),
            ModelUsed::Named(n) => write!(f, "embedded {n}"),
            ModelUsed::File(print) | ModelUsed::Other(print) => f.write_str(print),
        }
    }
}

impl fmt::Display for ModelArmKind {
    /// The canonical form.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelArmKind::Of { model, arm } => write!(f, "{model} model, {arm} arm"),
            ModelArmKind::Other(c) => f.write_str(c),
        }
    }
}

impl fmt::Display for MarkerModel {
    /// The text as made or read.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every basis the runs write, and texts a hand may leave: read as
    /// what they mean, written back byte for byte, and canonical as the
    /// strings were.
    #[test]
    fn a_basis_reads_as_its_meaning_and_writes_back_as_it_was() {
        let cases = [
            ("minute 120", BasisKind::Minute("120".into())),
            ("Minute  120 ", BasisKind::Minute("120".into())),
            ("minute 0.5", BasisKind::Minute("0.5".into())),
            ("steady state", BasisKind::Steady),
            (
                "schedule v1 sha256:0123456789abcdef",
                BasisKind::Schedule {
                    version: "v1".into(),
                    print: "sha256:0123456789abcdef".into(),
                },
            ),
            (
                "estimate v1 sha256:FEDC",
                BasisKind::Estimate {
                    version: "v1".into(),
                    print: "sha256:fedc".into(),
                },
            ),
            ("runtime RtWarm", BasisKind::Runtime("rtwarm".into())),
            ("minute 1 2", BasisKind::Other("minute 1 2".into())),
            ("", BasisKind::Other(String::new())),
        ];
        for (text, kind) in cases {
            let b = Basis::parse(text);
            assert_eq!(b.kind(), &kind, "{text:?}");
            assert_eq!(b.to_string(), text);
            assert_eq!(b.canonical(), canonical(text), "{text:?}");
        }
        assert!(Basis::parse("MINUTE 120").same(&Basis::parse("minute 120")));
        // Not the same minute by value: `120.0` was never `120`.
        assert!(!Basis::parse("minute 120.0").same(&Basis::parse("minute 120")));
        assert!(!Basis::parse("minute 120").same(&Basis::parse("steady state")));
    }

    #[test]
    fn a_model_reads_as_its_meaning_and_writes_back_as_it_was() {
        let of = |model: ModelUsed, arm: &str| ModelArmKind::Of {
            model,
            arm: arm.into(),
        };
        let cases = [
            (
                "embedded default model, embedded IRB 140 arm",
                of(ModelUsed::Default, "embedded irb 140"),
            ),
            (
                "embedded irb140-hot model, urdf sha256:ab (arm, two) arm",
                of(
                    ModelUsed::Named("irb140-hot".into()),
                    "urdf sha256:ab (arm, two)",
                ),
            ),
            (
                "sha256:0123  model,  embedded IRB 140 arm",
                of(ModelUsed::File("sha256:0123".into()), "embedded irb 140"),
            ),
            (
                "embedded model, x arm",
                of(ModelUsed::Other("embedded".into()), "x"),
            ),
            ("m", ModelArmKind::Other("m".into())),
            ("a model, b", ModelArmKind::Other("a model, b".into())),
        ];
        for (text, kind) in cases {
            let m = MarkerModel::parse(text);
            assert_eq!(m.kind(), &kind, "{text:?}");
            assert_eq!(m.to_string(), text);
            assert_eq!(m.canonical(), canonical(text), "{text:?}");
        }
        assert!(
            MarkerModel::parse("Embedded Default model, embedded IRB 140 arm").same(
                &MarkerModel::parse("embedded default model, embedded irb 140 arm")
            )
        );
        assert!(
            !MarkerModel::parse("embedded default model, embedded IRB 140 arm").same(
                &MarkerModel::parse("embedded default model, embedded IRB 1200 arm")
            )
        );
    }
}
