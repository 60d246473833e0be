//! Program displacement: the predefined `C_PROGDISP` (progdisp: `pdisp`
//! pose, `eoffs` extjoint), `PDispSet`, `PDispOff`, `EOffsSet`,
//! `EOffsOff`, and the displaced object frame the robot's functions use.
//!
//! From the RAPID reference (progdisp, PDispSet, PDispOff): the
//! displacement is a frame in the object frame, a target's TCP in the
//! world being uframe · oframe · pdisp · target; it is off (identity,
//! eoffs 0) after a cold start, a new program loaded and a program
//! started from the beginning, and kept otherwise. CalcJointT and
//! CalcRobT compute with the active displacement; CRobT reads the
//! position in the displaced frame. `PDispOn` (a displacement measured
//! from the robot's position) is not run.

use super::kin;
use super::state::{Global, Interp};
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::{Call, Storage};
use crate::robot::WobjFrames;
use nalgebra::Isometry3;

const NAME: &str = "c_progdisp";

/// No displacement: identity pose, external offsets 0.
fn off() -> Value {
    Value::Rec(
        "progdisp".into(),
        vec![
            kin::pose([0.0; 3], [1.0, 0.0, 0.0, 0.0]),
            Value::Rec("extjoint".into(), vec![Value::Num(0.0); 6]),
        ],
    )
}

impl Interp {
    /// `C_PROGDISP` as predefined data, off.
    pub(super) fn predefined_progdisp(&mut self) {
        self.globals.insert(
            NAME.into(),
            vec![Global {
                module: usize::MAX,
                local: false,
                storage: Storage::Var,
                value: off(),
            }],
        );
    }

    /// The displacement switched off (a program started from the
    /// beginning).
    pub(super) fn progdisp_off(&mut self) {
        let v = self.stored(off());
        if let Some(g) = self.globals.get_mut(NAME).and_then(|g| g.first_mut()) {
            g.value = v;
        }
    }

    fn progdisp(&self) -> Result<&[Value]> {
        match self
            .globals
            .get(NAME)
            .and_then(|g| g.first())
            .map(|g| &g.value)
        {
            Some(Value::Rec(_, f)) if f.len() == 2 => Ok(f),
            _ => Err(Error::input("C_PROGDISP is not a progdisp")),
        }
    }

    /// The active displacement frame.
    pub(super) fn pdisp(&self) -> Result<Isometry3<f64>> {
        kin::pose_of(&self.progdisp()?[0])
    }

    /// The active external axis offsets.
    pub(super) fn eoffs(&self) -> Result<[f64; 6]> {
        let n = self.progdisp()?[1].numbers();
        n.try_into()
            .map_err(|_| Error::input("C_PROGDISP.eoffs is not an extjoint"))
    }

    /// `wobj` with the active displacement in its object frame (oframe ·
    /// pdisp): the frame a robtarget is written in.
    pub(super) fn displaced(&self, wobj: &WobjFrames) -> Result<WobjFrames> {
        let mut w = wobj.clone();
        w.oframe = wobj.oframe * self.pdisp()?;
        Ok(w)
    }

    /// PDispSet, PDispOff, EOffsSet, EOffsOff executed; `false` for
    /// another instruction.
    pub(super) fn progdisp_instruction(&mut self, c: &Call) -> Result<bool> {
        let name = c.name.to_ascii_lowercase();
        let (part, value) = match name.as_str() {
            "pdispset" | "eoffsset" => {
                let e = c
                    .positional()
                    .next()
                    .ok_or_else(|| Error::input(format!("{} needs a value", c.name)))?;
                let v = self.eval(e)?;
                if name == "pdispset" {
                    // Kept as written; a pose that is none refused.
                    let v = self.types.coerce_to(v, "pose")?;
                    kin::pose_of(&v)?;
                    (0, v)
                } else {
                    (1, self.types.coerce_to(v, "extjoint")?)
                }
            }
            "pdispoff" => (0, kin::pose([0.0; 3], [1.0, 0.0, 0.0, 0.0])),
            "eoffsoff" => (1, Value::Rec("extjoint".into(), vec![Value::Num(0.0); 6])),
            "pdispon" => {
                return Err(self.unsupported("PDispOn (a displacement measured from the robot)"))
            }
            _ => return Ok(false),
        };
        let v = self.stored(value);
        if let Some(Value::Rec(_, f)) = self
            .globals
            .get_mut(NAME)
            .and_then(|g| g.first_mut())
            .map(|g| &mut g.value)
        {
            f[part] = v;
        }
        Ok(true)
    }
}
