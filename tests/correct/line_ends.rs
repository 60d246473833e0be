//! Every line end (LF, CRLF, a lone CR as classic Mac editors write) is
//! read and written alike by `correct`: the same numbers corrected, the
//! marker and numbers' lines written with the file's own line end, and
//! the corrected file checked clean. A CR-only file was refused with an
//! internal error ("the marker's place lies after the file's first
//! target") while `targets` read it.

use super::{assert_exit, rapidtherm};

fn sample(name: &str) -> Vec<u8> {
    std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("samples")
            .join(name),
    )
    .unwrap()
}

/// `src` with every line end made `eol`.
fn with_eol(src: &[u8], eol: &str) -> Vec<u8> {
    let lf: Vec<u8> = String::from_utf8_lossy(src)
        .replace("\r\n", "\n")
        .replace('\r', "\n")
        .into_bytes();
    let text = String::from_utf8(lf).unwrap();
    text.replace('\n', eol).into_bytes()
}

#[test]
fn each_line_end_is_corrected_alike_and_written_in_its_own_kind() {
    for name in ["service_positions.mod", "fixtures.mod", "arc_pendant.mod"] {
        let mut corrected = Vec::new();
        for eol in ["\n", "\r\n", "\r"] {
            let dir = tempfile::tempdir().unwrap();
            std::fs::write(dir.path().join("p.mod"), with_eol(&sample(name), eol)).unwrap();
            let out = rapidtherm(
                &["correct", "p.mod", "--at", "120", "-o", "out.mod"],
                dir.path(),
            );
            assert_exit(&out, 0);
            let bytes = std::fs::read(dir.path().join("out.mod")).unwrap();
            // No line end of another kind was written into it.
            assert_eq!(with_eol(&bytes, eol), bytes, "{name} {eol:?}");
            let check = rapidtherm(
                // fixtures.mod holds targets no move reaches: the check of
                // a corrected program reports them as the cold one's does.
                &[
                    "correct", "out.mod", "--at", "120", "--check", "--accept", "unused",
                ],
                dir.path(),
            );
            assert_exit(&check, 0);
            // The corrected text, line by line, but for the marker's
            // fingerprint of the cold bytes (which hashes their line ends)
            // and the seal, which covers that fingerprint.
            let text = String::from_utf8_lossy(&with_eol(&bytes, "\n")).into_owned();
            let lines: Vec<String> = text
                .lines()
                .map(|l| {
                    match l
                        .find("cold=sha256:")
                        .or_else(|| l.find("numbers v2 sha256:"))
                    {
                        Some(at) => l[..at].to_string(),
                        None => l.to_string(),
                    }
                })
                .collect();
            corrected.push(lines);
        }
        assert_eq!(corrected[0], corrected[1], "{name}: CRLF");
        assert_eq!(corrected[0], corrected[2], "{name}: CR");
    }
}
