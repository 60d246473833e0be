//! RAPID's built-in functions the module and a cell's program use: math
//! (angles in degrees, as RAPID's), poses, strings, the controller clock
//! and the robot's `CalcJointT`/`CalcRobT`. Each is described in ABB's
//! RAPID reference under its name (docs/runtime.md lists them).

use super::kin::{self, pose_of};
use super::state::Interp;
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::{Expr, FunctionCall};
use crate::robot::frames::pose_to_rapid;
use nalgebra::{Point3, Vector3};

impl Interp {
    /// The value of built-in function `c`; `None` for a function the
    /// interpreter does not know.
    pub(super) fn builtin(&mut self, c: &FunctionCall) -> Result<Option<Value>> {
        let name = c.name.to_ascii_lowercase();
        let exprs: Vec<&Expr> = c.positional().collect();
        let switch = |s: &str| c.optional(s).is_some();
        // Functions that read a parameter, not a value.
        match name.as_str() {
            "present" => {
                let n = exprs
                    .first()
                    .and_then(|e| e.as_name())
                    .ok_or_else(|| Error::input("Present of no parameter name"))?;
                let here = self
                    .frames
                    .last()
                    .is_some_and(|f| f.vars.contains_key(&n.to_ascii_lowercase()));
                return Ok(Some(Value::Bool(here)));
            }
            "strtoval" => {
                let [s, out] = exprs[..] else {
                    return Err(Error::input("StrToVal takes a string and a datum"));
                };
                let s = self.eval(s)?;
                let text = s
                    .string()
                    .ok_or_else(|| Error::input("StrToVal of no string"))?;
                let p = self.place_of(out)?;
                return Ok(Some(Value::Bool(match text.trim().parse::<f64>() {
                    Ok(v) if self.read(&p)?.num().is_some() => {
                        self.write(&p, Value::Num(v))?;
                        true
                    }
                    _ => false,
                })));
            }
            _ => {}
        }
        let mut args = Vec::with_capacity(exprs.len());
        for e in &exprs {
            args.push(self.eval(e)?);
        }
        let mut opt = |n: &str| -> Result<Option<Value>> {
            let given = c.optional(n);
            match given.and_then(|a| a.value.as_ref()) {
                Some(e) => Ok(Some(self.eval(e)?)),
                None => Ok(None),
            }
        };
        let wobj = opt("WObj")?;
        let dec = opt("Dec")?.and_then(|v| v.num());
        let wobj = match wobj {
            Some(w) => w,
            None => self.global("wobj0").cloned().unwrap_or(Value::Num(0.0)),
        };
        let num = |i: usize| -> Result<f64> {
            args.get(i).and_then(Value::num).ok_or_else(|| {
                Error::input(format!("`{}` needs a num as argument {}", c.name, i + 1))
            })
        };
        let v = match name.as_str() {
            "sin" => Value::Num(num(0)?.to_radians().sin()),
            "cos" => Value::Num(num(0)?.to_radians().cos()),
            "tan" => Value::Num(num(0)?.to_radians().tan()),
            "asin" => Value::Num(num(0)?.asin().to_degrees()),
            "acos" => Value::Num(num(0)?.acos().to_degrees()),
            "atan" => Value::Num(num(0)?.atan().to_degrees()),
            "atan2" => Value::Num(num(0)?.atan2(num(1)?).to_degrees()),
            "exp" => Value::Num(num(0)?.exp()),
            "sqrt" => Value::Num(num(0)?.sqrt()),
            "abs" => Value::Num(num(0)?.abs()),
            "pow" => Value::Num(num(0)?.powf(num(1)?)),
            "round" | "trunc" => {
                let k = 10f64.powi(dec.unwrap_or(0.0) as i32);
                let x = num(0)? * k;
                Value::Num(
                    if name == "round" {
                        x.round()
                    } else {
                        x.trunc()
                    } / k,
                )
            }
            "posemult" => {
                let p = pose_of(arg(&args, 0)?)? * pose_of(arg(&args, 1)?)?;
                let (t, r) = pose_to_rapid(&p);
                kin::pose(t, r)
            }
            "poseinv" => {
                let (t, r) = pose_to_rapid(&pose_of(arg(&args, 0)?)?.inverse());
                kin::pose(t, r)
            }
            "posevect" => {
                let p = pose_of(arg(&args, 0)?)?;
                let v = three(arg(&args, 1)?)?;
                let out = p * Point3::from(Vector3::from(v));
                kin::pos([out.x, out.y, out.z])
            }
            "offs" => {
                let mut p = arg(&args, 0)?.clone();
                let d = [num(1)?, num(2)?, num(3)?];
                match &mut p {
                    Value::Rec(t, f) if &**t == "robtarget" => {
                        let old = three(&f[0])?;
                        f[0] = kin::pos(std::array::from_fn(|i| old[i] + d[i]));
                    }
                    v => return Err(Error::input(format!("Offs of a {}", v.kind()))),
                }
                p
            }
            "calcjointt" => self
                .kin
                .calc_joint_t(arg(&args, 0)?, arg(&args, 1)?, &wobj)?,
            "calcrobt" => self.kin.calc_rob_t(arg(&args, 0)?, arg(&args, 1)?, &wobj)?,
            "cdate" => Value::Str(self.clock.date()),
            "ctime" => Value::Str(self.clock.time()),
            "gettime" => {
                let (h, m, s) = self.clock.hms();
                let v = if switch("Hour") {
                    h
                } else if switch("Min") {
                    m
                } else if switch("Sec") {
                    s
                } else if switch("WDay") {
                    self.clock.weekday()
                } else {
                    return Err(Error::input("GetTime needs \\WDay, \\Hour, \\Min or \\Sec"));
                };
                Value::Num(v as f64)
            }
            "strpart" => {
                let s = arg(&args, 0)?
                    .string()
                    .ok_or_else(|| Error::input("StrPart of no string"))?;
                let (start, len) = (num(1)? as usize, num(2)? as usize);
                let part = s
                    .get(start.saturating_sub(1)..start.saturating_sub(1) + len)
                    .ok_or_else(|| {
                        Error::input(format!(
                            "StrPart({s:?}, {start}, {len}) is outside the string"
                        ))
                    })?;
                Value::Str(part.to_string())
            }
            "strlen" => Value::Num(
                arg(&args, 0)?
                    .string()
                    .ok_or_else(|| Error::input("StrLen of no string"))?
                    .chars()
                    .count() as f64,
            ),
            "numtostr" => Value::Str(format!("{:.*}", num(1)?.max(0.0) as usize, num(0)?)),
            "dim" => {
                let mut a = arg(&args, 0)?;
                for _ in 1..num(1)? as usize {
                    a = match a {
                        Value::Arr(x) => x
                            .first()
                            .ok_or_else(|| Error::input("Dim of an empty array"))?,
                        _ => return Err(Error::input("Dim beyond the array's dimensions")),
                    };
                }
                match a {
                    Value::Arr(x) => Value::Num(x.len() as f64),
                    _ => return Err(Error::input("Dim of no array")),
                }
            }
            _ => return Ok(None),
        };
        Ok(Some(v))
    }
}

fn arg(args: &[Value], i: usize) -> Result<&Value> {
    args.get(i)
        .ok_or_else(|| Error::input(format!("argument {} missing", i + 1)))
}

fn three(v: &Value) -> Result<[f64; 3]> {
    v.numbers()
        .try_into()
        .map_err(|_| Error::input(format!("a {} where a pos is expected", v.kind())))
}
