//! JSON as every command writes it (docs/formats.md): pretty-printed, a
//! `"schema": "rapidtherm.<command>/1"` field first, and each number
//! rounded to the digits that mean something for its unit, read from its
//! field's name (`_mm`, `_deg`, `_c`, a pose, a quaternion). The rounding
//! is done here, in the one writer every command's JSON goes through, so
//! that no field is forgotten: `-0.06999999999999318` is written `-0.07`.

use crate::error::{Error, Result};
use serde::ser::SerializeMap;
use serde::Serialize;
use serde_json::ser::{Formatter, PrettyFormatter};
use std::io::{self, Write};

/// The version of every command's JSON shape; a change that could break a
/// reader raises it (and the name of its file in `schemas/`).
pub const SCHEMA_VERSION: u32 = 1;

/// `rapidtherm.<command>/1`: the value of the `schema` field.
pub fn schema_name(command: &str) -> String {
    format!("rapidtherm.{command}/{SCHEMA_VERSION}")
}

/// Decimal places kept for a number in field `key`, at position `index`
/// of the array that field holds (`None` when it holds no array).
/// Millimetres and degrees to 1e-6 (a thousandth of the tolerance, and of
/// the smallest turn a gate takes), temperatures to 1e-3 °C (the sensors
/// read tenths), quaternions to 1e-9 (a turn of 1e-7°); a pose holds
/// millimetres then a quaternion. Any other number (minutes, fit
/// statistics, counts) is written as computed.
fn places(key: &str, index: Option<usize>) -> Option<i32> {
    match key {
        "original" | "corrected" | "pose" => match index {
            Some(i) if i < 3 => Some(6),
            _ => Some(9),
        },
        "rot" | "q" | "quaternion" => Some(9),
        "trans" | "extax" | "robax" => Some(6),
        k if k.ends_with("_mm") || k.contains("_mm_") => Some(6),
        k if k.ends_with("_deg") || k.contains("_deg_") => Some(6),
        k if k.ends_with("_c") => Some(3),
        _ => None,
    }
}

/// `x` to `places` decimals; a value already coarser than that (9E9) is
/// left as it is, and a rounded zero has no sign.
pub fn round(x: f64, places: i32) -> f64 {
    let scale = 10f64.powi(places);
    let scaled = x * scale;
    if !scaled.is_finite() || scaled.abs() >= 4.5e15 {
        return x;
    }
    let r = scaled.round() / scale;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

enum Frame {
    Object { key: String },
    Array { index: usize },
}

/// serde_json's pretty formatter that knows the field each number is in.
struct Rounding {
    pretty: PrettyFormatter<'static>,
    frames: Vec<Frame>,
    in_key: bool,
}

impl Rounding {
    fn places(&self) -> Option<i32> {
        let mut index = None;
        for f in self.frames.iter().rev() {
            match f {
                Frame::Array { index: i } => {
                    if index.is_none() {
                        index = Some(*i);
                    }
                }
                Frame::Object { key } => return places(key, index),
            }
        }
        None
    }
}

impl Formatter for Rounding {
    fn write_f64<W: ?Sized + Write>(&mut self, w: &mut W, value: f64) -> io::Result<()> {
        let value = match self.places() {
            Some(p) => round(value, p),
            None => value,
        };
        self.pretty.write_f64(w, value)
    }
    fn write_string_fragment<W: ?Sized + Write>(&mut self, w: &mut W, s: &str) -> io::Result<()> {
        if self.in_key {
            if let Some(Frame::Object { key }) = self.frames.last_mut() {
                key.push_str(s);
            }
        }
        self.pretty.write_string_fragment(w, s)
    }
    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.frames.push(Frame::Array { index: 0 });
        self.pretty.begin_array(w)
    }
    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.frames.pop();
        self.pretty.end_array(w)
    }
    fn begin_array_value<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        if let Some(Frame::Array { index }) = self.frames.last_mut() {
            if !first {
                *index += 1;
            }
        }
        self.pretty.begin_array_value(w, first)
    }
    fn end_array_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.pretty.end_array_value(w)
    }
    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.frames.push(Frame::Object { key: String::new() });
        self.pretty.begin_object(w)
    }
    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.frames.pop();
        self.pretty.end_object(w)
    }
    fn begin_object_key<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        if let Some(Frame::Object { key }) = self.frames.last_mut() {
            key.clear();
        }
        self.in_key = true;
        self.pretty.begin_object_key(w, first)
    }
    fn end_object_key<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.in_key = false;
        self.pretty.end_object_key(w)
    }
    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.pretty.begin_object_value(w)
    }
    fn end_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.pretty.end_object_value(w)
    }
}

/// `value` as pretty JSON with its numbers rounded (no schema field, no
/// final line end): a part of a document written piece by piece.
pub fn to_string<T: Serialize + ?Sized>(value: &T) -> Result<String> {
    let mut out = Vec::new();
    let formatter = Rounding {
        pretty: PrettyFormatter::new(),
        frames: Vec::new(),
        in_key: false,
    };
    let mut ser = serde_json::Serializer::with_formatter(&mut out, formatter);
    value
        .serialize(&mut ser)
        .map_err(|e| Error::input(format!("cannot write JSON: {e}")))?;
    String::from_utf8(out).map_err(|e| Error::input(e.to_string()))
}

/// A command's JSON document whose body is an object (a struct or a map):
/// `{"schema": …, <the body's fields>}` and a line end.
pub fn document<T: Serialize + ?Sized>(command: &str, body: &T) -> Result<String> {
    #[derive(Serialize)]
    struct Doc<'a, T: Serialize + ?Sized> {
        schema: String,
        #[serde(flatten)]
        body: &'a T,
    }
    let doc = Doc {
        schema: schema_name(command),
        body,
    };
    Ok(to_string(&doc)? + "\n")
}

/// A command's JSON document whose rows are a list:
/// `{"schema": …, "<key>": [rows]}` and a line end.
pub fn rows<T: Serialize + ?Sized>(command: &str, key: &str, rows: &T) -> Result<String> {
    struct Doc<'a, T: ?Sized> {
        schema: String,
        key: &'a str,
        rows: &'a T,
    }
    impl<T: Serialize + ?Sized> Serialize for Doc<'_, T> {
        fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
            let mut map = s.serialize_map(Some(2))?;
            map.serialize_entry("schema", &self.schema)?;
            map.serialize_entry(self.key, self.rows)?;
            map.end()
        }
    }
    Ok(to_string(&Doc {
        schema: schema_name(command),
        key,
        rows,
    })? + "\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounds_by_unit_in_one_place() {
        let v = serde_json::json!({
            "correction_mm": [-0.06999999999999318, 0.1234567891],
            "temps_c": [16.582051100763938],
            "dangle_deg": 6.708982531212105e-16,
            "original": [99.95059336324971, 0.0, 0.0, 0.1234567894999, 0.0, 0.0, 0.99],
            "tau_min": 12.041999999999,
            "nested": [{"x_mm": -1e-9}],
            "extax": [9e9],
        });
        let text = to_string(&v).unwrap();
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back["correction_mm"][0], -0.07);
        assert_eq!(back["correction_mm"][1], 0.123457);
        assert_eq!(back["temps_c"][0], 16.582);
        // A rounded zero has no sign.
        assert_eq!(back["dangle_deg"].to_string(), "0.0");
        assert_eq!(back["nested"][0]["x_mm"].to_string(), "0.0");
        // A pose: millimetres, then a quaternion.
        assert_eq!(back["original"][0], 99.950593);
        assert_eq!(back["original"][3], 0.123456789);
        // Minutes are not a unit rounded here.
        assert_eq!(back["tau_min"], 12.041999999999);
        assert_eq!(back["extax"][0], 9e9);
    }

    #[test]
    fn documents_carry_their_schema_first() {
        let text = rows("targets", "targets", &[1, 2]).unwrap();
        assert!(text.starts_with("{\n  \"schema\": \"rapidtherm.targets/1\",\n  \"targets\": ["));
        #[derive(Serialize)]
        struct Body {
            b: u8,
            a: u8,
        }
        let text = document("diff", &Body { b: 1, a: 2 }).unwrap();
        assert_eq!(
            text,
            "{\n  \"schema\": \"rapidtherm.diff/1\",\n  \"b\": 1,\n  \"a\": 2\n}\n"
        );
    }
}
