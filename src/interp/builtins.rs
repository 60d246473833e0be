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
        if let Some(v) = self.of_parameter(&name, &exprs)? {
            return Ok(Some(v));
        }
        let given = self.given(c, &exprs)?;
        if let Some(v) = math(&name, &given)? {
            return Ok(Some(v));
        }
        if let Some(v) = self.pose_function(&name, &given)? {
            return Ok(Some(v));
        }
        if let Some(v) = self.clock_function(&name, &given)? {
            return Ok(Some(v));
        }
        if let Some(v) = self.robot_function(&name, &given)? {
            return Ok(Some(v));
        }
        text_or_array(&name, &given)
    }

    /// The robot's: `CalcJointT`, `CalcRobT` (with the active program
    /// displacement), `CRobT`, `CJointT`; and `ClkRead`.
    fn robot_function(&mut self, name: &str, given: &Given) -> Result<Option<Value>> {
        let v = match name {
            "calcjointt" | "calcrobt" => {
                self.calc(name, given.arg(0)?, given.arg(1)?, &given.wobj)?
            }
            "crobt" => self.c_rob_t(given.tool.clone(), given.wobj_given.clone())?,
            "cjointt" => self.c_joint_t()?,
            "clkread" => self.clock_read(given.arg(0)?, given.switch("HighRes"))?,
            _ => return Ok(None),
        };
        Ok(Some(v))
    }

    /// Functions that read a parameter, not a value: `Present` and
    /// `StrToVal` (which writes its datum); `None` for any other.
    fn of_parameter(&mut self, name: &str, exprs: &[&Expr]) -> Result<Option<Value>> {
        match name {
            "present" => {
                let n = exprs
                    .first()
                    .and_then(|e| e.as_name())
                    .ok_or_else(|| Error::input("Present of no parameter name"))?;
                let here = self
                    .frames
                    .last()
                    .is_some_and(|f| f.vars.contains_key(&n.to_ascii_lowercase()));
                Ok(Some(Value::Bool(here)))
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
                Ok(Some(Value::Bool(match text.trim().parse::<f64>() {
                    Ok(v) if self.read(&p)?.num().is_some() => {
                        self.write(&p, Value::Num(v))?;
                        true
                    }
                    _ => false,
                })))
            }
            _ => Ok(None),
        }
    }

    /// A built-in's arguments evaluated: the positional ones, then
    /// `\WObj` and `\Dec` (whichever function it is).
    fn given<'c>(&mut self, c: &'c FunctionCall, exprs: &[&Expr]) -> Result<Given<'c>> {
        let mut args = Vec::with_capacity(exprs.len());
        for e in exprs {
            args.push(self.eval(e)?);
        }
        // An optional argument passed on from a parameter the caller left
        // out (`\WObj?W`) is not given.
        let mut opt = |n: &str| -> Result<Option<Value>> {
            let given = c.optional(n);
            match given.and_then(|a| a.value.as_ref()) {
                Some(e) if self.absent_argument(e) => Ok(None),
                Some(e) => Ok(Some(self.eval(e)?)),
                None => Ok(None),
            }
        };
        let wobj_given = opt("WObj")?;
        let tool = opt("Tool")?;
        let dec = opt("Dec")?.and_then(|v| v.num());
        let wobj = match &wobj_given {
            Some(w) => w.clone(),
            None => self.global("wobj0").cloned().unwrap_or(Value::Num(0.0)),
        };
        Ok(Given {
            call: c,
            args,
            wobj,
            wobj_given,
            tool,
            dec,
        })
    }

    /// Poses: `PoseMult`, `PoseInv`, `PoseVect`, `Offs`.
    fn pose_function(&self, name: &str, given: &Given) -> Result<Option<Value>> {
        let v = match name {
            "posemult" => {
                let p = pose_of(given.arg(0)?)? * pose_of(given.arg(1)?)?;
                let (t, r) = pose_to_rapid(&p);
                kin::pose(t, r)
            }
            "poseinv" => {
                let (t, r) = pose_to_rapid(&pose_of(given.arg(0)?)?.inverse());
                kin::pose(t, r)
            }
            "posevect" => {
                let p = pose_of(given.arg(0)?)?;
                let v = three(given.arg(1)?)?;
                let out = p * Point3::from(Vector3::from(v));
                kin::pos([out.x, out.y, out.z])
            }
            "offs" => {
                let mut p = given.arg(0)?.clone();
                let d = [given.num(1)?, given.num(2)?, given.num(3)?];
                match &mut p {
                    Value::Rec(t, f) if &**t == "robtarget" => {
                        let old = three(&f[0])?;
                        f[0] = kin::pos(std::array::from_fn(|i| old[i] + d[i]));
                    }
                    v => return Err(Error::input(format!("Offs of a {}", v.kind()))),
                }
                p
            }
            _ => return Ok(None),
        };
        Ok(Some(v))
    }

    /// The controller clock: `CDate`, `CTime`, `GetTime`.
    fn clock_function(&self, name: &str, given: &Given) -> Result<Option<Value>> {
        let v = match name {
            "cdate" => Value::Str(self.clock.date()),
            "ctime" => Value::Str(self.clock.time()),
            "gettime" => {
                let (h, m, s) = self.clock.hms();
                let v = if given.switch("Hour") {
                    h
                } else if given.switch("Min") {
                    m
                } else if given.switch("Sec") {
                    s
                } else if given.switch("WDay") {
                    // The RAPID reference (GetTime): 1 to 7, Monday to
                    // Sunday.
                    match self.clock.weekday() {
                        0 => 7,
                        d => d,
                    }
                } else {
                    return Err(Error::input("GetTime needs \\WDay, \\Hour, \\Min or \\Sec"));
                };
                Value::Num(v as f64)
            }
            _ => return Ok(None),
        };
        Ok(Some(v))
    }
}

/// A built-in's arguments, evaluated.
struct Given<'c> {
    call: &'c FunctionCall,
    args: Vec<Value>,
    /// `\WObj`, or `wobj0` where not given.
    wobj: Value,
    wobj_given: Option<Value>,
    tool: Option<Value>,
    dec: Option<f64>,
}

impl Given<'_> {
    fn num(&self, i: usize) -> Result<f64> {
        self.args.get(i).and_then(Value::num).ok_or_else(|| {
            Error::input(format!(
                "`{}` needs a num as argument {}",
                self.call.name,
                i + 1
            ))
        })
    }

    fn arg(&self, i: usize) -> Result<&Value> {
        arg(&self.args, i)
    }

    fn switch(&self, s: &str) -> bool {
        self.call.optional(s).is_some()
    }
}

/// The math (angles in degrees): `Sin` ... `Pow`, `Round`, `Trunc`.
fn math(name: &str, given: &Given) -> Result<Option<Value>> {
    let v = match name {
        "sin" => Value::Num(given.num(0)?.to_radians().sin()),
        "cos" => Value::Num(given.num(0)?.to_radians().cos()),
        "tan" => Value::Num(given.num(0)?.to_radians().tan()),
        "asin" => Value::Num(given.num(0)?.asin().to_degrees()),
        "acos" => Value::Num(given.num(0)?.acos().to_degrees()),
        "atan" => Value::Num(given.num(0)?.atan().to_degrees()),
        "atan2" => Value::Num(given.num(0)?.atan2(given.num(1)?).to_degrees()),
        "exp" => Value::Num(given.num(0)?.exp()),
        "sqrt" => Value::Num(given.num(0)?.sqrt()),
        "abs" => Value::Num(given.num(0)?.abs()),
        "pow" => Value::Num(given.num(0)?.powf(given.num(1)?)),
        "round" | "trunc" => {
            let k = 10f64.powi(given.dec.unwrap_or(0.0) as i32);
            let x = given.num(0)? * k;
            Value::Num(
                if name == "round" {
                    x.round()
                } else {
                    x.trunc()
                } / k,
            )
        }
        _ => return Ok(None),
    };
    Ok(Some(v))
}

/// Strings and arrays: `StrPart`, `StrLen`, `NumToStr`, `Dim`.
fn text_or_array(name: &str, given: &Given) -> Result<Option<Value>> {
    let v = match name {
        "strpart" => {
            let s = given
                .arg(0)?
                .string()
                .ok_or_else(|| Error::input("StrPart of no string"))?;
            let (start, len) = (given.num(1)? as usize, given.num(2)? as usize);
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
            given
                .arg(0)?
                .string()
                .ok_or_else(|| Error::input("StrLen of no string"))?
                .chars()
                .count() as f64,
        ),
        "numtostr" => Value::Str(format!(
            "{:.*}",
            given.num(1)?.max(0.0) as usize,
            given.num(0)?
        )),
        "dim" => {
            let mut a = given.arg(0)?;
            for _ in 1..given.num(1)? as usize {
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

fn arg(args: &[Value], i: usize) -> Result<&Value> {
    args.get(i)
        .ok_or_else(|| Error::input(format!("argument {} missing", i + 1)))
}

fn three(v: &Value) -> Result<[f64; 3]> {
    v.numbers()
        .try_into()
        .map_err(|_| Error::input(format!("a {} where a pos is expected", v.kind())))
}
