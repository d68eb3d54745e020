//! The test kit of ridgeline: images with known centerlines and the scorer that compares a trace
//! with them, shared by the integration tests, the examples (the quality benchmark, the sample and
//! picture generators) and the fuzzers.
//!
//! - [`synth`]: deterministic cases (crossings, junctions, Hershey text, fingerprint-like ridge
//!   fields, crowded groups), each a rendered [`ridgeline::Binary`] with the strokes it was drawn
//!   from. The Hershey fonts are compiled in from `data/hershey/`.
//! - [`score`]: precision, recall and topology of a [`ridgeline::StrokeGraph`] against the truth.

#![warn(missing_docs)]

pub mod score;
pub mod synth;
