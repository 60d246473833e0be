//! The controller's stopwatches: `VAR clock` data, `ClkStart`, `ClkStop`,
//! `ClkReset` and `ClkRead`, counting the controller's own time (the
//! interpreter's uptime, which [`Interp::advance`] moves), not the wall
//! clock an operator may set ([`Interp::set_clock`]).
//!
//! From the RAPID reference (clock, ClkStart, ClkStop, ClkReset,
//! ClkRead): a clock counts seconds from ClkStart until ClkStop, and goes
//! on counting while the program is stopped; ClkReset sets it to zero
//! (and stops it); ClkRead returns the seconds counted, to 0.001 s
//! (`\HighRes`: to 1 µs), running or not; a clock holds up to 4 294 967
//! s, beyond which ClkRead raises ERR_OVERFLOW; clock data are VAR only.

use super::raised::ERR_OVERFLOW;
use super::state::Interp;
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::Call;

/// The most a clock holds (s).
const CLOCK_MAX: f64 = 4_294_967.0;

impl Interp {
    /// ClkStart, ClkStop or ClkReset executed; `false` for another
    /// instruction.
    pub(super) fn clock_instruction(&mut self, c: &Call) -> Result<bool> {
        let name = c.name.to_ascii_lowercase();
        if !matches!(name.as_str(), "clkstart" | "clkstop" | "clkreset") {
            return Ok(false);
        }
        let Some(e) = c.positional().next() else {
            return Err(Error::input(format!("{} needs a clock", c.name)));
        };
        let p = self.place_of(e)?;
        let (running, since, counted) = clock_parts(self.read(&p)?)?;
        let now = self.uptime;
        let (running, since, counted) = match name.as_str() {
            // Starting a running clock changes nothing.
            "clkstart" if running => (true, since, counted),
            "clkstart" => (true, now, counted),
            "clkstop" if running => (false, 0.0, counted + (now - since)),
            "clkstop" => (false, 0.0, counted),
            _ => (false, 0.0, 0.0),
        };
        self.write(&p, clock(running, since, counted))?;
        Ok(true)
    }

    /// `ClkRead(c [\HighRes])`: the seconds clock `c` counted.
    pub(super) fn clock_read(&mut self, c: &Value, high_res: bool) -> Result<Value> {
        let (running, since, counted) = clock_parts(c)?;
        let s = counted + if running { self.uptime - since } else { 0.0 };
        if s > CLOCK_MAX {
            return Err(self.raise(
                ERR_OVERFLOW,
                Error::input(format!(
                    "the clock counted {s} s, more than a clock holds ({CLOCK_MAX} s)"
                )),
            ));
        }
        let step = if high_res { 1e6 } else { 1e3 };
        Ok(Value::Num((s * step).round() / step))
    }
}

fn clock(running: bool, since: f64, counted: f64) -> Value {
    Value::Rec(
        "clock".into(),
        vec![Value::Bool(running), Value::Num(since), Value::Num(counted)],
    )
}

fn clock_parts(v: &Value) -> Result<(bool, f64, f64)> {
    match v {
        Value::Rec(t, f) if &**t == "clock" => match f[..] {
            [Value::Bool(r), Value::Num(s), Value::Num(c)] => Ok((r, s, c)),
            _ => Err(Error::input("a clock without its parts")),
        },
        v => Err(Error::input(format!(
            "a {} where a clock is expected",
            v.kind()
        ))),
    }
}
