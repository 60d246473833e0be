//! End to end through the binary: simulate → diagnose (JSON, saved model,
//! plots) → gap with the saved model.

use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
}

#[test]
fn simulate_diagnose_save_and_gap() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data.csv");
    let model = dir.path().join("model.toml");
    let plots = dir.path().join("plots");
    let out = bin()
        .args([
            "simulate",
            "--poses",
            "random:10",
            "--times",
            "0:180:9",
            "--effect",
        ])
        .arg("joint-offset-drift:c2_urad_per_k=40")
        .args(["--seed", "5", "--temps", "measured", "-o"])
        .arg(&data)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let out = bin()
        .arg("diagnose")
        .arg(&data)
        .args(["--format", "json", "--save-model"])
        .arg(&model)
        .arg("--plot")
        .arg(&plots)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["verdict"], serde_json::json!(["joint-offset-drift"]));
    for key in [
        "gap_before_mm",
        "gap_after_mm",
        "candidates",
        "ambiguous",
        "where",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    let before = v["gap_before_mm"].as_f64().unwrap();
    let after = v["gap_after_mm"].as_f64().unwrap();
    assert!(after < 0.2 * before, "{before} -> {after}");
    let candidates = v["candidates"].as_array().unwrap();
    assert_eq!(candidates.len(), 8);
    for c in candidates {
        // A candidate is scored, or says why its fit gave no score.
        assert!(c["name"].is_string() && c["params"].is_array(), "{c}");
        assert!(c["explained"].is_number() || c["error"].is_string(), "{c}");
    }
    // The c2 drift was simulated at 40 µrad/K: the saved model says so.
    let text = std::fs::read_to_string(&model).unwrap();
    let saved: toml::Value = toml::from_str(&text).unwrap();
    let c2 = saved["effects"][0]["params"]["c2_urad_per_k"]
        .as_float()
        .unwrap();
    assert!((c2 - 40.0).abs() < 3.0, "{c2}");
    for f in ["gap_over_time.svg", "gap_vectors.svg"] {
        let svg = std::fs::read_to_string(plots.join(f)).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("<circle"), "{f}");
    }

    let gap = |model: Option<&std::path::Path>| -> f64 {
        let mut c = bin();
        c.arg("gap").arg(&data).args(["--format", "json"]);
        if let Some(m) = model {
            c.arg("--model").arg(m);
        }
        let out = c.output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert!(v["n"].as_u64().unwrap() == 210);
        v["rms_mm"].as_f64().unwrap()
    };
    let base = gap(None);
    let with_model = gap(Some(&model));
    assert!(with_model < 0.025 && base > 0.1, "{base} -> {with_model}");
}

#[test]
fn nothing_is_written_on_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("bad.csv");
    std::fs::write(&data, "time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm\n0,0,0,0,0,0,0,515,0,nan\n").unwrap();
    let model = dir.path().join("m.toml");
    let out = bin()
        .arg("diagnose")
        .arg(&data)
        .arg("--save-model")
        .arg(&model)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("bad.csv:2:"));
    assert!(!model.exists());
}

/// Every usage error of `diagnose` comes before any input is read: a bad
/// `--noise` with data that do not exist is the noise's error (exit 2),
/// not the missing file's.
#[test]
fn a_bad_noise_is_refused_before_any_input_is_read() {
    for args in [
        vec!["diagnose", "no/such/data.csv", "--noise=-1"],
        vec![
            "diagnose",
            "no/such/data.csv",
            "--noise",
            "0.01",
            "--chain",
            "--robot",
            "tests/data/ur5/ur5.urdf",
        ],
    ] {
        let out = bin().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--noise"), "{args:?}: {err}");
        assert!(!err.contains("no/such"), "{args:?}: {err}");
    }
}
