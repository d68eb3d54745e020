//! End-to-end: render known centerlines thickly, trace, compare.
