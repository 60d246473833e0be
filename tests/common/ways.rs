//! One harness for the reader's ways, shared by the test binaries of the
//! layers that read programs (`rapid`, `schedule`, `correct`): a case is
//! read every way the reader reads (`rapid::Reading`: the fast lane
//! reading ahead on every core, the lane at the parse's place, the
//! grammar alone), and each layer holds what it makes of every way's
//! program to what it makes of the grammar's. A generated comparison
//! ([`counted`]) fails if a way ran no case, and unless the lane held
//! targets in most cases (else it would compare the grammar with itself).

// Each binary takes what its layer compares.
#![allow(dead_code)]

use proptest::strategy::Strategy;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use rapidtherm::rapid::{self, Program, Reading, Source};
use std::cell::Cell;

thread_local! {
    /// The cases each way read or refused on this thread (a runner runs
    /// its cases on the thread that calls it).
    static RAN: Cell<[usize; 3]> = const { Cell::new([0; 3]) };
}

fn ran_now() -> [usize; 3] {
    RAN.with(Cell::get)
}

/// `src`, one file, read the way `reading` says.
pub fn read(src: &[u8], reading: Reading) -> rapidtherm::error::Result<Program> {
    let program = rapid::parse_read(vec![("p.mod".to_string(), Source::copied(src))], reading);
    RAN.with(|r| {
        let mut n = r.get();
        if let Some(k) = Reading::ALL.iter().position(|&w| w == reading) {
            n[k] += 1;
        }
        r.set(n);
    });
    program
}

/// Every way's program, the grammar's last.
pub struct Ways {
    pub read: Vec<(Reading, Program)>,
}

impl Ways {
    /// The grammar's program.
    pub fn grammar(&self) -> &Program {
        &self.read.last().expect("every way read").1
    }
    /// What every command reads: the lane's, reading ahead.
    pub fn lane(&self) -> &Program {
        &self.read[0].1
    }
    /// Each way's program but the grammar's, with its way.
    pub fn others(&self) -> impl Iterator<Item = (Reading, &Program)> {
        let n = self.read.len() - 1;
        self.read[..n].iter().map(|(w, p)| (*w, p))
    }
}

/// `src` read every way: every way reads it (`Some`), or every way
/// refuses it with the grammar's error (`None`).
pub fn read_every_way(src: &[u8]) -> Result<Option<Ways>, TestCaseError> {
    let mut read = Vec::new();
    let mut refused = Vec::new();
    for way in Reading::ALL {
        match self::read(src, way) {
            Ok(p) => read.push((way, p)),
            Err(e) => refused.push((way, e.to_string())),
        }
    }
    match (read.is_empty(), refused.as_slice()) {
        (false, []) => Ok(Some(Ways { read })),
        (true, [.., (_, grammar)]) => {
            for (way, e) in &refused {
                if e != grammar {
                    return Err(TestCaseError::fail(format!(
                        "{way:?} refused otherwise:\n {e}\n the grammar: {grammar}"
                    )));
                }
            }
            Ok(None)
        }
        _ => Err(TestCaseError::fail(format!(
            "some ways read, others refused: read {:?}, refused {refused:?}",
            read.iter().map(|(w, _)| w).collect::<Vec<_>>()
        ))),
    }
}

/// [`read_every_way`], and what `look` makes of each way's program the
/// same as what it makes of the grammar's.
pub fn same_every_way<T: PartialEq + std::fmt::Debug>(
    src: &[u8],
    look: impl Fn(&Program) -> T,
) -> Result<Option<Ways>, TestCaseError> {
    let Some(ways) = read_every_way(src)? else {
        return Ok(None);
    };
    let want = look(ways.grammar());
    for (way, p) in ways.others() {
        let got = look(p);
        if got != want {
            return Err(TestCaseError::fail(format!(
                "{way:?} reads otherwise:\n {got:?}\n the grammar: {want:?}"
            )));
        }
    }
    Ok(Some(ways))
}

/// Run `test` on `cases` generated values (a fixed seed: the count must
/// not pass or fail by chance), counting the cases where the lane held
/// targets (`test` says how many); fails if a way ran no case or fewer
/// than every case, and unless the lane held targets in at least `tenths`
/// tenths of them.
pub fn counted<S: Strategy>(
    what: &str,
    cases: u32,
    tenths: usize,
    strategy: S,
    test: impl Fn(S::Value) -> Result<usize, TestCaseError>,
) {
    let before = ran_now();
    let (ran, took) = (Cell::new(0usize), Cell::new(0usize));
    let mut runner = TestRunner::new_with_rng(
        Config::with_cases(cases),
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    runner
        .run(&strategy, |v| {
            let held = test(v)?;
            ran.set(ran.get() + 1);
            took.set(took.get() + usize::from(held > 0));
            Ok(())
        })
        .unwrap();
    let (ran, took) = (ran.get(), took.get());
    let after = ran_now();
    for (k, way) in Reading::ALL.iter().enumerate() {
        let n = after[k] - before[k];
        eprintln!("{what}: {way:?} read {n} cases");
        assert!(n > 0, "{what}: {way:?} ran no case");
        assert!(n >= ran, "{what}: {way:?} ran {n} of {ran} cases");
    }
    eprintln!("{what}: the lane held targets in {took} of {ran} generated programs");
    assert!(
        took * 10 >= ran * tenths,
        "{what}: the lane held targets in {took} of {ran} cases only"
    );
}

/// The harness fails a comparison in which a way read no case: a test
/// that reads its cases one way only compares nothing.
#[test]
#[should_panic(expected = "ran no case")]
fn a_way_that_ran_no_case_fails() {
    counted("one way only", 4, 0, proptest::strategy::Just(()), |()| {
        read(b"MODULE m\nENDMODULE\n", Reading::Grammar).unwrap();
        Ok(1)
    });
}
