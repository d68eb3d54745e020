//! A borrowed grayscale image: the front end's input, read in place.
//!
//! [`GrayView`] is what [`crate::trace_image`], [`crate::trace_image_with_stages`] and
//! [`crate::raster::binarize`] read: rows of 8-bit gray levels `stride` bytes apart in a buffer
//! the caller owns (a `GrayImage`, a memory-mapped file, a numpy array). `image`'s own
//! `ImageBuffer` needs its rows packed, so it cannot show a crop of a larger buffer without
//! copying it, and its `flat::View` reads one pixel at a time; the front end reads whole rows.

use image::{ImageBuffer, Luma};
use rayon::prelude::*;

/// A grayscale image borrowed from its owner: `height` rows of `width` levels (0 black, 255
/// white), row `y` starting at byte `y * stride` of the buffer. A `&GrayImage` (or any
/// `&ImageBuffer<Luma<u8>, _>`) converts into one without copying.
///
/// ```
/// use ridgeline::{GrayView, Params};
///
/// // A 3-px dark bar in the middle of a 40 x 20 region of a wider buffer (rows 64 bytes apart).
/// let (width, height, stride) = (40, 20, 64);
/// let mut buffer = vec![255u8; stride * height];
/// for row in buffer.chunks_mut(stride).skip(9).take(3) {
///     row[5..35].fill(0);
/// }
/// let view = GrayView::new(&buffer, width as u32, height as u32, stride).expect("layout");
/// let trace = ridgeline::trace_image(view, &Params::default())?;
/// assert_eq!(trace.graph.edges.len(), 1);
/// assert_eq!(trace.graph.endpoints().count(), 2);
/// # Ok::<(), ridgeline::Error>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct GrayView<'a> {
    pixels: &'a [u8],
    width: u32,
    height: u32,
    stride: usize,
}

impl<'a> GrayView<'a> {
    /// The `width x height` image whose row `y` is `pixels[y * stride..y * stride + width]`.
    /// `None` when `stride < width` (rows would overlap) or `pixels` is too short to hold the
    /// last row; bytes between rows and after the last one are never read.
    pub fn new(pixels: &'a [u8], width: u32, height: u32, stride: usize) -> Option<Self> {
        let columns = width as usize;
        if height > 0 && columns > 0 {
            let end = (height as usize - 1)
                .checked_mul(stride)?
                .checked_add(columns)?;
            if stride < columns || pixels.len() < end {
                return None;
            }
        }
        Some(GrayView {
            pixels,
            width,
            height,
            stride,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// `(width, height)`.
    pub fn dimensions(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Bytes from the start of one row to the start of the next.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Row `y`'s `width` gray levels. Panics when `y >= height`, like slice indexing.
    pub fn row(&self, y: usize) -> &'a [u8] {
        assert!(y < self.height as usize, "row {y} of {} rows", self.height);
        let start = y * self.stride;
        &self.pixels[start..start + self.width as usize]
    }

    /// The rows, top to bottom.
    pub fn rows(&self) -> impl ExactSizeIterator<Item = &'a [u8]> + '_ {
        (0..self.height as usize).map(move |y| self.row(y))
    }

    /// The rows in parallel, in groups of at least `min_pixels` pixels per task.
    pub(crate) fn par_rows(
        &self,
        min_pixels: usize,
    ) -> impl IndexedParallelIterator<Item = &'a [u8]> + '_ {
        let rows_per_task = (min_pixels / (self.width as usize).max(1)).max(1);
        (0..self.height as usize)
            .into_par_iter()
            .with_min_len(rows_per_task)
            .map(move |y| self.row(y))
    }

    /// The pixels as one row-major slice when the rows are packed (`stride == width`).
    pub fn as_contiguous(&self) -> Option<&'a [u8]> {
        let len = self.width as usize * self.height as usize;
        (self.stride == self.width as usize || self.height <= 1 || len == 0)
            .then(|| &self.pixels[..len])
    }

    /// A packed copy of the pixels.
    pub fn to_image(&self) -> image::GrayImage {
        let mut pixels = Vec::with_capacity(self.width as usize * self.height as usize);
        for row in self.rows() {
            pixels.extend_from_slice(row);
        }
        image::GrayImage::from_raw(self.width, self.height, pixels)
            .unwrap_or_else(|| image::GrayImage::new(self.width, self.height))
    }
}

impl<'a, C: std::ops::Deref<Target = [u8]>> From<&'a ImageBuffer<Luma<u8>, C>> for GrayView<'a> {
    fn from(image: &'a ImageBuffer<Luma<u8>, C>) -> Self {
        let (width, height) = image.dimensions();
        GrayView {
            // `ImageBuffer` guarantees at least `width * height` samples.
            pixels: image.as_raw(),
            width,
            height,
            stride: width as usize,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_is_checked() {
        // The last row of 3 x 3 pixels 4 bytes apart ends at byte 2 * 4 + 3 = 11.
        let buffer = [0u8; 11];
        assert!(GrayView::new(&buffer, 3, 3, 4).is_some());
        assert!(GrayView::new(&buffer[..10], 3, 3, 4).is_none(), "too short");
        assert!(GrayView::new(&buffer, 3, 3, 3).is_some());
        assert!(GrayView::new(&buffer, 4, 3, 3).is_none(), "rows overlap");
        assert!(GrayView::new(&buffer, 3, 4, 3).is_none(), "too short");
        assert!(GrayView::new(&buffer, 0, 100, 0).is_some());
        assert!(GrayView::new(&[], 5, 0, 5).is_some());
        assert!(
            GrayView::new(&buffer, 1, 2, usize::MAX).is_none(),
            "overflow"
        );
    }

    #[test]
    fn rows_skip_the_padding() {
        let buffer: Vec<u8> = (0..12).collect();
        let view = GrayView::new(&buffer, 2, 3, 4).expect("layout");
        let rows: Vec<&[u8]> = view.rows().collect();
        assert_eq!(rows, [&[0, 1][..], &[4, 5], &[8, 9]]);
        assert_eq!(view.as_contiguous(), None);
        assert_eq!(view.to_image().into_raw(), vec![0, 1, 4, 5, 8, 9]);
        let packed = GrayView::new(&buffer, 4, 3, 4).expect("layout");
        assert_eq!(packed.as_contiguous(), Some(&buffer[..]));
        let parallel: Vec<&[u8]> = view.par_rows(1).collect();
        assert_eq!(parallel, rows);
    }
}
