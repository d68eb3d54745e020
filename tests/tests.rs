//! The one integration-test binary: each module tests one side of ridgeline.

mod cli;
mod debug;
mod features;
mod golden;
mod hostile;
mod house;
mod inputs;
mod pipeline;
mod points3d;
mod properties;
mod readme;
mod score;
mod strips;
mod support;
mod trust;
