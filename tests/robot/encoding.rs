//! A URDF saved as UTF-16 (Windows editors offer it) is named and refused
//! at 1:1, not called "invalid utf-8"; one with a UTF-8 byte-order mark is
//! read as without it.

use rapidtherm::robot::Robot;

fn irb120() -> String {
    std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cmd/kin_data/irb120.urdf"),
    )
    .unwrap()
}

#[test]
fn a_utf16_urdf_is_named_and_a_utf8_mark_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let text = irb120();
    let utf16: Vec<u8> = std::iter::once(0xFEFF)
        .chain(text.encode_utf16())
        .flat_map(u16::to_le_bytes)
        .collect();
    let path = dir.path().join("arm.urdf");
    std::fs::write(&path, utf16).unwrap();
    let e = Robot::from_urdf_file(&path).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}:1:1: error: UTF-16 (little-endian) is not read; save the file as UTF-8",
            path.display()
        )
    );
    let marked = [&[0xEF, 0xBB, 0xBF][..], text.as_bytes()].concat();
    std::fs::write(&path, marked).unwrap();
    let with_mark = Robot::from_urdf_file(&path).unwrap();
    std::fs::write(&path, &text).unwrap();
    let without = Robot::from_urdf_file(&path).unwrap();
    let q: rapidtherm::robot::Joints = [0.0, 0.3, -0.2, 0.1, 0.5, 0.0];
    assert_eq!(with_mark.fk(&q), without.fk(&q));
}
