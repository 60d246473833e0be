//! SVG plots of a diagnosis (to be filled).
