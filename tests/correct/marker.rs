//! The marker's time basis of a schedule is the fingerprint of its
//! documented byte encoding, version 1: pinned here, so that no change of
//! a type's derive or of the code turns every corrected file into one
//! "corrected for another basis".

use rapidtherm::correct::When;
use rapidtherm::digest::fingerprint;
use rapidtherm::model::Moment;
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
        of_program: false,
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

#[test]
fn a_moments_basis_is_its_words() {
    assert_eq!(When::At(Moment::Minute(120.0)).basis(), "minute 120");
    assert_eq!(When::At(Moment::Steady).basis(), "steady state");
}
