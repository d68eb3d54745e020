//! Raster front end: decode, grayscale, binarize, and turn ink pixels into the point set.
//!
//! ```text
//! bytes ─decode─> GrayImage ─binarize─> Binary ─points─> PointSet (pixel centers, 8- or 5x5
//!                                                         neighbours, half-width, Dis_ave)
//! ```
//! Design item 1 (points, dropout mode) and item 11 (the dropout test) live in [`points`].

mod binarize;
mod chunks;
mod decode;
mod points;

pub use binarize::otsu_level;
pub(crate) use chunks::pixel_chunks;
pub use decode::decode_file;

use crate::{Binary, GrayImage, Limits, Params, PointSet, Result};

/// Decodes image bytes to grayscale within `limits`.
///
/// PNG, JPEG, TIFF, BMP, PNM, GIF and WebP, guessed from the content; any bit depth, gray, RGB,
/// palette or alpha (composited over white paper). The size is checked from the header before the
/// pixels are allocated: more than `limits.max_pixels` gives [`crate::Error::Limit`].
pub fn decode(bytes: &[u8], limits: &Limits) -> Result<GrayImage> {
    decode::decode(bytes, limits)
}

/// Binarizes a grayscale image (threshold and polarity from `params`).
///
/// A uniform image gives an empty mask. With [`crate::Polarity::Auto`] the side of the threshold
/// holding most of the image border is paper.
pub fn binarize(gray: &GrayImage, params: &Params) -> Result<Binary> {
    binarize::binarize(gray, params)
}

/// Turns the ink pixels into the point set (neighbours, half-widths, dropout mode).
///
/// Refuses more than `params.limits.max_points` ink pixels before allocating the points.
pub fn points(binary: &Binary, params: &Params) -> Result<PointSet> {
    points::points(binary, params)
}
