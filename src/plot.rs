//! What the library's SVG pictures share: the canvas, the font, the error
//! of a failed drawing.
//!
//! plotters' SVG backend without its font features writes text as `<text>`
//! elements (layout estimated from the string length), so a picture renders
//! anywhere without system fonts, and the same input gives the same bytes.

use crate::error::{Error, ErrorKind, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

/// The font family every picture names (the viewer's sans-serif).
pub const FONT: &str = "sans-serif";

/// A drawing that failed, as the library's error.
pub fn error(e: impl std::fmt::Display) -> Error {
    Error::new(ErrorKind::Io, format!("drawing the plot failed: {e}"))
}

/// An SVG picture of `size` pixels on a white canvas, drawn by `draw`.
pub fn svg(
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<()>,
) -> Result<String> {
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        root.fill(&WHITE).map_err(error)?;
        draw(&root)?;
        root.present().map_err(error)?;
    }
    Ok(text)
}
