//! Each file's cold fingerprint: what a corrected file's marker records
//! of its original. Hashing a file of 100 MB takes a twentieth of a
//! second on one core, and a run that hashed after its parse waited for
//! it with the other core idle; a job that reads the files hashes them
//! beside the parse instead, and the run takes the fingerprints where
//! they are of its own program's bytes.

use crate::digest::fingerprint;
use crate::rapid::Program;

/// The fingerprints of some files' bytes, with where those bytes are.
pub(crate) struct ColdPrints {
    /// Each file's bytes (address and length), for [`ColdPrints::fits`].
    of: Vec<(usize, usize)>,
    prints: Vec<String>,
}

impl ColdPrints {
    /// The fingerprints of `files`, in order.
    pub fn of<'b>(files: impl Iterator<Item = &'b [u8]>) -> ColdPrints {
        let (of, prints) = files
            .map(|b| ((b.as_ptr() as usize, b.len()), fingerprint(b)))
            .unzip();
        ColdPrints { of, prints }
    }

    /// The fingerprints of `program`'s files.
    pub fn of_program(program: &Program) -> ColdPrints {
        ColdPrints::of((0..program.files.len()).map(|f| program.source(f)))
    }

    /// Whether they are of `program`'s bytes: the very bytes it holds (a
    /// program's sources are shared with what it was parsed from, never
    /// copied), file by file.
    pub fn fits(&self, program: &Program) -> bool {
        self.of.len() == program.files.len()
            && self.of.iter().enumerate().all(|(f, &(at, len))| {
                let b = program.source(f);
                b.as_ptr() as usize == at && b.len() == len
            })
    }

    /// Each file's fingerprint, in the program's file order.
    pub fn into_prints(self) -> Vec<String> {
        self.prints
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fingerprints_fit_only_the_bytes_they_were_made_of() {
        let text = b"MODULE m\nCONST robtarget p := [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\nENDMODULE\n";
        let program = crate::rapid::parse("m.mod", text).expect("parses");
        let same = ColdPrints::of_program(&program);
        assert!(same.fits(&program));
        // Equal bytes elsewhere are not the program's: its own are hashed.
        let copy = text.to_vec();
        let elsewhere = ColdPrints::of(std::iter::once(&copy[..]));
        assert!(!elsewhere.fits(&program));
        assert_eq!(elsewhere.into_prints(), same.into_prints());
        let none = ColdPrints::of(std::iter::empty());
        assert!(!none.fits(&program));
    }
}
