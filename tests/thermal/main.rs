//! Integration tests of the `thermal` layer, one binary (one link) for all
//! of them: a test binary per file made the clean build minutes longer.

mod csv_rules;
mod errors;
mod forecast;
mod plot;
mod props;
mod sample;
