//! The SVG plot: deterministic bytes, text as <text> elements (renders
//! without system fonts), one panel per axis with measured and fitted
//! curves and a legend.

use rapidtherm::thermal::fit::{fit_axis, ModelKind};
use rapidtherm::thermal::plot::plot_fits;
use rapidtherm::thermal::HeatingRecord;

#[test]
fn plot_is_deterministic_and_labelled() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/cmd/heating_small.csv");
    let rec = HeatingRecord::parse("small.csv", &std::fs::read(path).unwrap()).unwrap();
    let mut fits = Vec::new();
    for axis in [2, 5] {
        for kind in [ModelKind::Poly(1), ModelKind::TwoTau] {
            fits.push(fit_axis(&rec, axis, kind, None).unwrap());
        }
    }
    let a = plot_fits(&rec, &fits).unwrap();
    let b = plot_fits(&rec, &fits).unwrap();
    assert_eq!(a, b);
    assert!(a.starts_with("<svg"));
    for label in [
        "axis 2",
        "axis 5",
        "measured",
        "poly1",
        "two-tau",
        "minutes since cold start",
        "motor temperature (°C)",
    ] {
        assert!(a.contains(&format!("\n{label}\n")), "missing text {label}");
    }
    assert!(!a.contains("axis 1\n"));
    // Two panels, each with the measured curve (grey) and the two fitted
    // ones (first and second palette colours), each once more in its legend.
    for colour in ["#AAAAAA", "#D62728", "#1F77B4"] {
        assert_eq!(
            a.matches(&format!("stroke=\"{colour}\"")).count(),
            4,
            "{colour}"
        );
    }
}
