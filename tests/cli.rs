//! CLI behaviour as golden transcripts (trycmd): every `tests/cmd/*.toml`
//! case runs the `rapidtherm` binary and compares its stdout, stderr and
//! exit code with the files beside it. Regenerate with
//! `TRYCMD=overwrite cargo test --test cli` (see docs/development.md).

#[test]
fn cli_transcripts() {
    trycmd::TestCases::new().case("tests/cmd/*.toml");
}
