//! Raster front end: decode, grayscale, binarize, and turn ink pixels into the point set.
//!
//! ```text
//! bytes ─pages─> Page (GrayImage, transparency, picture) per page
//! bytes ─decode─> GrayImage ─binarize─> Binary ─points─> PointSet (pixel centers, 8- or 5x5
//!                                                         neighbours, half-width, Dis_ave)
//! ```
//! docs/design.md, adaptations 1 (points) and 2 (dropout mode), live in [`points`].

mod binarize;
mod chunks;
mod decode;
mod dropout;
mod evidence;
mod grounds;
mod points;
mod regions;
mod resolution;
mod tiff_pages;
mod valleys;

pub use crate::decisions::Ground;
pub(crate) use binarize::{binarize_deciding, decide_polarity};
pub(crate) use chunks::pixel_chunks;
pub use decode::{decode_file, gray_from_unit_pixels, Page, Pages, Picture, Transparency};
pub(crate) use dropout::split as split_dropout;
pub(crate) use evidence::chords;
pub(crate) use points::{add_neighbours, kept_pixels, restore, set_aside, Aside};

use crate::binary::{Binary, MaskView};
use crate::error::Result;
use crate::gray::GrayView;
use crate::mask::{label_components, Connectivity};
use crate::params::{Limits, Params};
use crate::point_set::PointSet;
use image::GrayImage;

/// Decodes image bytes to grayscale within `limits`.
///
/// PNG, JPEG, TIFF, BMP, PNM, GIF and WebP, guessed from the content; any bit depth, gray, RGB,
/// palette or alpha (transparent pixels are paper: white, or black behind white ink; see
/// [`Transparency`]). Of a multi-page TIFF, the first page (all of them: [`pages`]). The size is
/// checked from the header before the pixels are allocated: more than `limits.max_pixels` gives
/// [`crate::Error::Limit`].
pub fn decode(bytes: &[u8], limits: &Limits) -> Result<GrayImage> {
    decode::decode(bytes, limits)
}

/// The pages of image `bytes`, decoded one at a time by the returned iterator: every page of a
/// multi-page TIFF, the one image of other formats.
///
/// A TIFF with more than `limits.max_pages` pages gives [`crate::Error::Limit`] before any page is
/// decoded; each page is decoded like [`decode`], within the same limits. With
/// [`Pages::with_pictures`], each [`Page`] also says what to show under the centerlines.
///
/// ```
/// use ridgeline::{raster, Limits};
///
/// let mut png = Vec::new();
/// image::GrayImage::from_pixel(4, 3, image::Luma([200]))
///     .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
///     .expect("encode");
/// let mut pages = raster::pages(&png, &Limits::default())?.with_pictures(true);
/// assert_eq!(pages.page_count(), 1);
/// let page = pages.next().expect("one page")?;
/// assert_eq!((page.number, page.gray.dimensions()), (1, (4, 3)));
/// assert_eq!(page.picture, raster::Picture::Original { mime: "image/png" });
/// # Ok::<(), ridgeline::Error>(())
/// ```
pub fn pages<'a>(bytes: &'a [u8], limits: &Limits) -> Result<Pages<'a>> {
    decode::pages(bytes, limits)
}

/// Binarizes a grayscale image (threshold and polarity from `params`).
///
/// A uniform image gives an empty mask. With [`crate::Polarity::Auto`] the side of the threshold
/// holding most of the image border is paper. `gray` is a `&GrayImage` or a [`GrayView`] of
/// borrowed pixels, read in place.
pub fn binarize<'a>(gray: impl Into<GrayView<'a>>, params: &Params) -> Result<Binary> {
    Ok(binarize::binarize_deciding(gray.into(), params)?.0)
}

/// `binary` without its ink components (8-connected) of fewer than `min_area` pixels.
/// A mask whose `ink` is not `width x height` pixels is returned as it is, for the points to
/// refuse.
pub(crate) fn drop_small_components(binary: MaskView<'_>, min_area: usize) -> Binary {
    let mut kept = binary.to_binary();
    if binary.check_size().is_err() {
        return kept;
    }
    let (w, h) = (binary.width as usize, binary.height as usize);
    let (labels, sizes) = label_components(binary.ink, w, h, true, Connectivity::Eight);
    for (ink, &label) in kept.ink.iter_mut().zip(&labels) {
        let l = label as usize;
        *ink = *ink && l > 0 && sizes[l] >= min_area;
    }
    kept
}

/// Turns the ink pixels into the point set (neighbours, half-widths, dropout mode).
///
/// Refuses more than `params.front_end.limits.max_points` ink pixels before allocating the points.
/// `binary` is a `&Binary` or a [`MaskView`].
pub fn points<'a>(binary: impl Into<MaskView<'a>>, params: &Params) -> Result<PointSet> {
    points::points(binary.into(), params, params.front_end.dropout)
}

/// [`points`] with dropout mode `dropout` when given: the pipeline's groups of components whose
/// mode is already decided (docs/design.md, "The front end").
pub(crate) fn points_in_mode(
    binary: MaskView<'_>,
    params: &Params,
    dropout: Option<bool>,
) -> Result<PointSet> {
    points::points(binary, params, dropout)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_components_go_from_a_one_pixel_mask_too() {
        // A one-pixel mask with `min_area` set once panicked here: imageproc's labelling, which
        // `mask::label_components` used to call, indexes past its union-find on one pixel.
        let ink = [true];
        let mask = MaskView {
            width: 1,
            height: 1,
            ink: &ink,
        };
        assert_eq!(drop_small_components(mask, 2).ink, vec![false]);
        assert_eq!(drop_small_components(mask, 1).ink, vec![true]);
    }
}
