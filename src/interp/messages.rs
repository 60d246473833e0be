//! What a program tells the operator: `ErrWrite` (the event log: an
//! error, or a warning with `\W`, or information with `\I`; a header and
//! up to four reason lines `Reason`, `\RL2`, `\RL3`, `\RL4`) and `TPWrite`
//! (a line on the FlexPendant, a `\Num`, `\Bool`, `\Pos` or `\Orient`
//! written after the text), kept in order ([`Interp::messages`]).

use super::state::Interp;
use super::told::{MessageKind, OperatorMessage};
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::{Call, Expr};

impl Interp {
    /// The operator messages written so far, in order.
    pub fn messages(&self) -> &[OperatorMessage] {
        &self.messages
    }

    /// `ErrWrite` or `TPWrite` executed; `false` for another instruction.
    pub(super) fn message_instruction(&mut self, c: &Call) -> Result<bool> {
        let name = c.name.to_ascii_lowercase();
        let positional: Vec<&Expr> = c.positional().collect();
        let message = match name.as_str() {
            "errwrite" => {
                let kind = if c.optional("W").is_some() {
                    MessageKind::Warning
                } else if c.optional("I").is_some() {
                    MessageKind::Info
                } else {
                    MessageKind::Error
                };
                let [header, reason] = positional[..] else {
                    return Err(Error::input("ErrWrite takes a header and a reason"));
                };
                let header = self.text(header)?;
                let mut reasons = vec![self.text(reason)?];
                for line in ["RL2", "RL3", "RL4"] {
                    if let Some(e) = c.optional(line).and_then(|a| a.value.as_ref()) {
                        reasons.push(self.text(e)?);
                    }
                }
                OperatorMessage {
                    kind,
                    header,
                    reasons,
                }
            }
            "tpwrite" => {
                let [text] = positional[..] else {
                    return Err(Error::input("TPWrite takes one string"));
                };
                let mut header = self.text(text)?;
                for opt in ["Num", "Dnum", "Bool", "Pos", "Orient"] {
                    if let Some(e) = c.optional(opt).and_then(|a| a.value.as_ref()) {
                        let v = self.eval(e)?;
                        header.push_str(&written(&v));
                    }
                }
                OperatorMessage {
                    kind: MessageKind::Pendant,
                    header,
                    reasons: Vec::new(),
                }
            }
            _ => return Ok(false),
        };
        self.messages.push(message);
        Ok(true)
    }

    fn text(&mut self, e: &Expr) -> Result<String> {
        match self.eval(e)? {
            Value::Str(s) => Ok(s),
            v => Err(Error::input(format!(
                "a {} where a string is expected",
                v.kind()
            ))),
        }
    }
}

/// A value as TPWrite writes it after the text: a num with at most six
/// decimals (trailing zeros dropped), TRUE/FALSE, a pos or orient as its
/// aggregate.
fn written(v: &Value) -> String {
    match v {
        Value::Num(x) => {
            let s = format!("{x:.6}");
            let s = s.trim_end_matches('0').trim_end_matches('.');
            if s == "-0" {
                "0".into()
            } else {
                s.into()
            }
        }
        Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.into(),
        Value::Str(s) => s.clone(),
        Value::Rec(_, items) | Value::Arr(items) => {
            let inner: Vec<String> = items.iter().map(written).collect();
            format!("[{}]", inner.join(","))
        }
    }
}
