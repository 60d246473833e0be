//! SVG plot of measured and fitted heating curves.
