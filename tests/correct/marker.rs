//! The marker's time basis of a schedule is the fingerprint of its
//! documented byte encoding, version 1: pinned here, so that no change of
//! a type's derive or of the code turns every corrected file into one
//! "corrected for another basis".

use nalgebra::Isometry3;
use rapidtherm::correct::{ScheduleSource, When};
use rapidtherm::digest::fingerprint;
use rapidtherm::model::Moment;
use rapidtherm::schedule::EstimateOptions;
use rapidtherm::schedule::Schedule;

#[test]
fn a_schedules_basis_is_pinned() {
    let mut robtargets = Schedule::new();
    robtargets.visit("p10", 12.5);
    robtargets.visit("MAIN#1", 13.0);
    robtargets.visit("P10", 14.25);
    let mut joints = Schedule::new();
    joints.visit("jHome", 0.0);
    let when = When::Schedule {
        schedule: robtargets,
        joints: Some(joints),
        default: Some(Moment::Minute(60.0)),
        source: ScheduleSource::File,
    };
    // The bytes, as docs/correct.md writes them down.
    let mut b = b"rapidtherm schedule 1\0".to_vec();
    let put_id = |b: &mut Vec<u8>, id: &str| {
        b.extend_from_slice(&(id.len() as u32).to_le_bytes());
        b.extend_from_slice(id.as_bytes());
    };
    b.extend_from_slice(&2u32.to_le_bytes());
    put_id(&mut b, "p10");
    b.extend_from_slice(&2u32.to_le_bytes());
    b.extend_from_slice(&12.5f64.to_bits().to_le_bytes());
    b.extend_from_slice(&14.25f64.to_bits().to_le_bytes());
    put_id(&mut b, "main#1");
    b.extend_from_slice(&1u32.to_le_bytes());
    b.extend_from_slice(&13.0f64.to_bits().to_le_bytes());
    b.push(1);
    b.extend_from_slice(&1u32.to_le_bytes());
    put_id(&mut b, "jhome");
    b.extend_from_slice(&1u32.to_le_bytes());
    b.extend_from_slice(&0.0f64.to_bits().to_le_bytes());
    b.push(1);
    b.extend_from_slice(&60.0f64.to_bits().to_le_bytes());
    assert_eq!(when.basis(), format!("schedule v1 {}", fingerprint(&b)));
    assert_eq!(when.basis(), "schedule v1 sha256:110f3f31e3cd1de4");
}

/// An estimate's basis is its request, not its times: a second `--start`
/// run on the corrected program (whose times differ by microseconds)
/// recognises its own output.
#[test]
fn an_estimates_basis_is_its_request_pinned() {
    let mut times = Schedule::new();
    times.visit("p10", 60.5);
    let request = EstimateOptions {
        entry: "Main".to_string(),
        start_min: 60.0,
        cycles: 2,
        base_frame: Some(Isometry3::translation(100.0, 0.0, 0.0)),
    };
    let when = |schedule: Schedule| When::Schedule {
        schedule,
        joints: Some(Schedule::new()),
        default: Some(Moment::Steady),
        source: ScheduleSource::Estimate(Box::new(request.clone())),
    };
    // The bytes, as docs/correct.md writes them down.
    let mut b = b"rapidtherm estimate 1\0".to_vec();
    b.extend_from_slice(&60.0f64.to_bits().to_le_bytes());
    b.extend_from_slice(&4u32.to_le_bytes());
    b.extend_from_slice(b"main");
    b.extend_from_slice(&2u32.to_le_bytes());
    b.push(1);
    for v in [100.0f64, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0] {
        b.extend_from_slice(&v.to_bits().to_le_bytes());
    }
    b.push(2);
    assert_eq!(
        when(times.clone()).basis(),
        format!("estimate v1 {}", fingerprint(&b))
    );
    assert_eq!(
        when(times.clone()).basis(),
        "estimate v1 sha256:ff86e2502ac9adbd"
    );
    // Other times, the same request: the same basis.
    let mut later = Schedule::new();
    later.visit("p10", 60.500001);
    assert_eq!(when(later).basis(), when(times).basis());
}

#[test]
fn a_moments_basis_is_its_words() {
    assert_eq!(When::At(Moment::Minute(120.0)).basis(), "minute 120");
    assert_eq!(When::At(Moment::Steady).basis(), "steady state");
}

mod proof {
    //! The marker proves what it claims: a corrected file's numbers are
    //! fingerprinted, so a target re-taught or added after the correction,
    //! or a marker pasted into a cold file, is found. Before, `--check`
    //! passed on all three.

    use std::path::Path;
    use std::process::{Command, Output};

    fn rapidtherm(args: &[&str], dir: &Path) -> Output {
        Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
            .args(args)
            .current_dir(dir)
            .output()
            .unwrap()
    }

    fn text(o: &Output) -> String {
        format!(
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        )
    }

    const COLD: &str = "MODULE Cell\n    CONST robtarget p10:=[[400,150,380],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n    CONST robtarget p20:=[[450,250,380],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n    PROC main()\n        MoveJ p10, v1000, z10, tool0;\n        MoveL p20, v100, fine, tool0;\n    ENDPROC\nENDMODULE\n";

    /// A corrected copy of [`COLD`] in a temporary folder.
    fn corrected() -> (tempfile::TempDir, String) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("cold.mod"), COLD).unwrap();
        let out = rapidtherm(
            &["correct", "cold.mod", "--at", "120", "-o", "warm.mod"],
            dir.path(),
        );
        assert!(out.status.success(), "{}", text(&out));
        let warm = std::fs::read_to_string(dir.path().join("warm.mod")).unwrap();
        (dir, warm)
    }

    /// `--check` fails (exit 1) and says the marker is not trusted; a run
    /// that would write refuses (exit 2) and leaves the file as it is.
    fn found(dir: &Path, name: &str, says: &str) {
        let out = rapidtherm(&["correct", name, "--at", "120", "--check"], dir);
        let log = text(&out);
        assert_eq!(out.status.code(), Some(1), "{name}: {log}");
        assert!(log.contains("marker is not trusted"), "{name}: {log}");
        assert!(log.contains(says), "{name}: {log}");
        let before = std::fs::read(dir.join(name)).unwrap();
        let out = rapidtherm(&["correct", name, "--at", "120", "--in-place"], dir);
        assert_eq!(out.status.code(), Some(2), "{name}: {}", text(&out));
        assert_eq!(std::fs::read(dir.join(name)).unwrap(), before);
    }

    /// `--start 60 --in-place` run twice: the second run recognises its
    /// own output and leaves it byte for byte (before, it refused it as
    /// corrected "for another basis": the estimate walked on the corrected
    /// numbers differs by microseconds). Another start is still refused.
    #[test]
    fn a_start_run_twice_does_nothing_the_second_time() {
        let dir = tempfile::tempdir().unwrap();
        let cold = include_str!("../cmd/correct_data/glue_bead.mod");
        std::fs::write(dir.path().join("glue.mod"), cold).unwrap();
        let args = ["correct", "glue.mod", "--start", "60", "--in-place"];
        let out = rapidtherm(&args, dir.path());
        assert!(out.status.success(), "{}", text(&out));
        let once = std::fs::read(dir.path().join("glue.mod")).unwrap();
        assert_ne!(once, cold.as_bytes(), "the first run corrects");
        let out = rapidtherm(&args, dir.path());
        assert!(out.status.success(), "{}", text(&out));
        assert!(text(&out).contains("nothing to do"), "{}", text(&out));
        assert_eq!(std::fs::read(dir.path().join("glue.mod")).unwrap(), once);
        let out = rapidtherm(
            &["correct", "glue.mod", "--start", "30", "--in-place"],
            dir.path(),
        );
        assert_eq!(out.status.code(), Some(2), "{}", text(&out));
        assert_eq!(std::fs::read(dir.path().join("glue.mod")).unwrap(), once);
    }

    #[test]
    fn an_untouched_corrected_file_passes() {
        let (dir, warm) = corrected();
        assert!(warm.contains("! rapidtherm numbers v2 sha256:"), "{warm}");
        let out = rapidtherm(
            &["correct", "warm.mod", "--at", "120", "--check"],
            dir.path(),
        );
        assert_eq!(out.status.code(), Some(0), "{}", text(&out));
        // Layout, comments and line ends do not count; numbers written
        // another way (as a controller saving the module may) do not either.
        let edited = warm.replace('\n', "\r\n").replace("9E9", "9E+09").replace(
            "    PROC main()",
            "    ! taught on the pendant\r\n  PROC main()",
        );
        std::fs::write(dir.path().join("edited.mod"), edited).unwrap();
        let out = rapidtherm(
            &["correct", "edited.mod", "--at", "120", "--check"],
            dir.path(),
        );
        assert_eq!(out.status.code(), Some(0), "{}", text(&out));
    }

    #[test]
    fn a_target_retaught_after_the_correction_is_found() {
        let (dir, warm) = corrected();
        let at = warm.find("p20:=[[").unwrap() + 7;
        let retaught = format!(
            "{}451.5{}",
            &warm[..at],
            &warm[warm[at..].find(',').unwrap() + at..]
        );
        assert_ne!(retaught, warm);
        std::fs::write(dir.path().join("retaught.mod"), retaught).unwrap();
        found(
            dir.path(),
            "retaught.mod",
            "its numbers or its marker's text changed since",
        );
    }

    #[test]
    fn a_cold_target_added_after_the_correction_is_found() {
        let (dir, warm) = corrected();
        let added = warm.replace(
            "    PROC main()",
            "    CONST robtarget p30:=[[300,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n    PROC main()",
        );
        std::fs::write(dir.path().join("added.mod"), added).unwrap();
        found(
            dir.path(),
            "added.mod",
            "its numbers or its marker's text changed since",
        );
    }

    #[test]
    fn a_marker_pasted_into_a_cold_file_is_not_trusted() {
        let (dir, warm) = corrected();
        let marker = warm.lines().nth(1).unwrap();
        assert!(marker.contains("corrected:"), "{marker}");
        let pasted = COLD.replacen("MODULE Cell\n", &format!("MODULE Cell\n{marker}\n"), 1);
        std::fs::write(dir.path().join("pasted.mod"), &pasted).unwrap();
        found(dir.path(), "pasted.mod", "it has no seal");
        // Both lines pasted: the numbers are not the ones they prove.
        let numbers = warm
            .lines()
            .find(|l| l.contains("rapidtherm numbers"))
            .unwrap();
        let both = pasted.replace("ENDMODULE", &format!("{numbers}\nENDMODULE"));
        std::fs::write(dir.path().join("both.mod"), both).unwrap();
        found(
            dir.path(),
            "both.mod",
            "its numbers or its marker's text changed since",
        );
    }
}
