//! Raster front end: decode, grayscale, binarize, and turn ink pixels into the point set.

use crate::{Binary, GrayImage, Limits, Params, PointSet, Result};

/// Decodes image bytes to grayscale within `limits`.
pub fn decode(_bytes: &[u8], _limits: &Limits) -> Result<GrayImage> {
    todo!("decode")
}

/// Binarizes a grayscale image (threshold and polarity from `params`).
pub fn binarize(_gray: &GrayImage, _params: &Params) -> Result<Binary> {
    todo!("binarize")
}

/// Turns the ink pixels into the point set (neighbours, half-widths, dropout mode).
pub fn points(_binary: &Binary, _params: &Params) -> Result<PointSet> {
    todo!("points")
}
