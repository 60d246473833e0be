//! A URDF that is not a six-axis arm in metres is refused (issue 53): one
//! written in millimetres, one whose joints all sit at the origin, one
//! whose arm joint mimics another. The lengths are worked from
//! `data/irb140/irb140.urdf` by hand: its chain is
//! sqrt(70² + 352²) + 360 + 380 + 65 = 1163.89 mm.

use proptest::prelude::*;
use rapidtherm::error::ErrorKind;
use rapidtherm::robot::Robot;

const IRB140: &str = include_str!("../../data/irb140/irb140.urdf");

/// `IRB140` with every `<origin xyz>` scaled by `s` (the axes left).
fn scaled(s: f64) -> String {
    let re = regex::Regex::new(r#"(<origin[^>]*?xyz=")([^"]*)""#).unwrap();
    re.replace_all(IRB140, |c: &regex::Captures| {
        let v: Vec<String> = c[2]
            .split_whitespace()
            .map(|x| format!("{}", x.parse::<f64>().unwrap() * s))
            .collect();
        format!("{}{}\"", &c[1], v.join(" "))
    })
    .into_owned()
}

#[test]
fn the_embedded_arm_in_metres_is_taken() {
    assert!(Robot::from_urdf_str("irb140.urdf", IRB140).is_ok());
}

#[test]
fn a_urdf_in_millimetres_is_refused() {
    // 1163.89 mm × 1000: a chain of 1164 m.
    let e = Robot::from_urdf_str("mm.urdf", &scaled(1000.0)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    assert!(e.message.contains("1164 m long"), "{}", e.message);
    assert!(e.message.contains("in millimetres"), "{}", e.message);
    assert!(e.location.is_some());
}

#[test]
fn joints_all_at_the_origin_are_refused() {
    let e = Robot::from_urdf_str("zero.urdf", &scaled(0.0)).unwrap_err();
    assert!(e.message.contains("0.0 mm long"), "{}", e.message);
}

#[test]
fn a_mimic_joint_on_the_arm_is_refused_at_it() {
    let text = IRB140.replacen(
        "<joint name=\"joint_3\" type=\"revolute\">",
        "<joint name=\"joint_3\" type=\"revolute\">\n    <mimic joint=\"joint_2\" multiplier=\"-1\"/>",
        1,
    );
    assert_ne!(text, IRB140);
    let e = Robot::from_urdf_str("mimic.urdf", &text).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported);
    assert!(
        e.message.contains("joint `joint_3` mimics joint `joint_2`"),
        "{}",
        e.message
    );
    let at = e.location.unwrap();
    let line = 1 + IRB140[..IRB140.find("<joint name=\"joint_3\"").unwrap()]
        .matches('\n')
        .count();
    assert_eq!(at.line, line);
}

/// Cases per test: 20, or `PROPTEST_CASES`.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// The arm scaled by any factor is taken exactly when its chain is
    /// from 50 mm to 20 m long (data/urdf_size.toml).
    #[test]
    fn a_scaled_arm_is_taken_only_within_an_arms_size(log_s in -2.5f64..4.0) {
        let s = 10f64.powf(log_s);
        let length = 1163.89 * s;
        // Away from the bounds' rounding.
        prop_assume!((length - 50.0).abs() > 0.1 && (length - 20000.0).abs() > 1.0);
        let taken = Robot::from_urdf_str("s.urdf", &scaled(s)).is_ok();
        prop_assert_eq!(taken, (50.0..=20000.0).contains(&length), "x{} ({} mm)", s, length);
    }
}
