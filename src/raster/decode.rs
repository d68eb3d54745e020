//! Decoding: image bytes to 8-bit grayscale within the configured limits, page by page.
//!
//! Untrusted files are the norm (batches of scans from anywhere), so the size is checked from the
//! header before any pixel buffer exists, the decoder gets strict side limits and an allocation
//! bound, and whatever a codec reports is turned into an [`Error`] a user can act on. A multi-page
//! TIFF is read one page at a time ([`Pages`]), its page count bounded by
//! [`Limits::max_pages`] before any page is decoded.
//!
//! Transparency is read as a user means it: transparent pixels are paper and opaque ones the ink
//! candidates. The paper is white, unless nearly all opaque pixels are light (white ink on a
//! transparent background), when it is black: either way the ink keeps its contrast, and
//! [`crate::Polarity`] still describes the ink's own colour (white ink is light ink).

use std::io::{BufRead, ErrorKind, Seek};
use std::path::Path;

use image::metadata::Orientation;
use image::{
    DynamicImage, ImageBuffer, ImageDecoder, ImageError, ImageFormat, ImageReader, Pixel, Primitive,
};

use super::tiff_pages::{self, PatchedReader};
use crate::error::{Error, Result};
use crate::params::Limits;
use image::GrayImage;

/// Decoder allocation bound per image pixel: an RGBA image with 16 bits per channel, the widest
/// layout the enabled codecs produce, plus room for the codec's own buffers.
const BYTES_PER_PIXEL_BOUND: u64 = 8 + 4;
/// Fixed allowance on top of the per-pixel bound (palettes, metadata, line buffers).
const ALLOC_SLACK: u64 = 64 << 20;
/// Light ink on transparent: fewer than one opaque pixel in this many is dark.
const LIGHT_INK_DARK_SHARE: u64 = 50;

/// Decodes image bytes (PNG, JPEG, TIFF, BMP, PNM, GIF, WebP; format guessed from the content) to
/// grayscale; of a multi-page TIFF, the first page. Transparent pixels are paper (see the module
/// doc). Images with more than `limits.max_pixels` pixels or a side longer than `limits.max_side`
/// are refused from their header, before their pixels are allocated.
pub fn decode(bytes: &[u8], limits: &Limits) -> Result<GrayImage> {
    guarded(|| decode_unguarded(bytes, limits))
}

fn decode_unguarded(bytes: &[u8], limits: &Limits) -> Result<GrayImage> {
    let format = check_format(bytes)?;
    let header = match format {
        ImageFormat::Tiff => tiff_pages::Header::read(bytes),
        _ => None,
    };
    let target = Target {
        bytes,
        format,
        tiff: header.as_ref().map(|header| (header, header.first)),
        single: true,
    };
    decode_page(&target, limits, false).map(|page| page.gray)
}

/// Reads and decodes an image file; see [`decode`](crate::raster::decode).
pub fn decode_file(path: &Path, limits: &Limits) -> Result<GrayImage> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode(&bytes, limits)
}

/// The pages of an image file, decoded one at a time as the iterator is advanced: one page for
/// every format but TIFF, every page (image file directory) of a TIFF file.
///
/// Build it with [`pages`](crate::raster::pages). The page count is known before any page is
/// decoded ([`Pages::page_count`]; `len()` counts the pages not yet decoded).
pub struct Pages<'a> {
    bytes: &'a [u8],
    format: ImageFormat,
    limits: Limits,
    /// The TIFF chain, when the file is a TIFF with a readable first directory.
    chain: Option<tiff_pages::Chain>,
    /// Index of the next page to decode.
    next: usize,
    pictures: bool,
}

/// One decoded page.
#[derive(Clone, Debug)]
pub struct Page {
    /// 1-based page number.
    pub number: usize,
    /// The 8-bit gray image the pipeline traces.
    pub gray: GrayImage,
    /// How transparency was read, when the page has some (not every pixel opaque).
    pub transparency: Option<Transparency>,
    /// What to show under the centerlines; [`Picture::Gray`] unless asked for with
    /// [`Pages::with_pictures`].
    pub picture: Picture,
}

/// What to show under the centerlines of a page, closest to what the user gave.
#[derive(Clone, Debug, PartialEq)]
pub enum Picture {
    /// The page's gray image: the source was gray (or no picture was asked for).
    Gray,
    /// The input bytes themselves, in a format browsers show (PNG, JPEG, GIF, WebP): a
    /// single-image file whose pixels are shown as decoded (no orientation tag to apply).
    Original {
        /// The format's MIME type, e.g. `image/png`.
        mime: &'static str,
    },
    /// The page's pixels in colour, 8 bits per channel: RGB, RGBA (transparency) or gray with
    /// alpha. For formats browsers do not show (TIFF, BMP, PNM) or pixels that are not shown as
    /// decoded.
    Color(DynamicImage),
}

/// How a page's transparency was read: transparent pixels are paper, opaque ones the ink
/// candidates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Transparency {
    /// Pixels at least half opaque.
    pub opaque_pixels: u64,
    /// Nearly all opaque pixels are light (fewer than 1 in 50 darker than mid-gray): white ink on
    /// a transparent background, composited over black paper instead of white so that it keeps
    /// its contrast.
    pub light_ink: bool,
}

/// The pages of image `bytes`, not yet decoded; see [`Pages`]. Fails when the bytes are empty or
/// not a supported format, or when a TIFF has more than `limits.max_pages` pages.
pub fn pages<'a>(bytes: &'a [u8], limits: &Limits) -> Result<Pages<'a>> {
    let format = check_format(bytes)?;
    let chain = match format {
        ImageFormat::Tiff => tiff_pages::chain(bytes, limits.max_pages),
        _ => None,
    };
    if let Some(chain) = &chain {
        if chain.count > limits.max_pages {
            return Err(Error::Limit {
                what: "TIFF pages",
                actual: chain.count,
                limit: limits.max_pages,
                field: "limits.max_pages",
            });
        }
    }
    Ok(Pages {
        bytes,
        format,
        limits: *limits,
        chain,
        next: 0,
        pictures: false,
    })
}

impl std::fmt::Debug for Pages<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pages")
            .field("format", &self.format)
            .field("bytes", &self.bytes.len())
            .field("pages", &self.page_count())
            .field("next", &self.next)
            .field("pictures", &self.pictures)
            .finish()
    }
}

impl Pages<'_> {
    /// Number of pages, decoded or not (at least 1: a TIFF whose first directory cannot be read
    /// counts as one page, whose decoding says what is wrong).
    pub fn page_count(&self) -> usize {
        self.chain
            .as_ref()
            .map_or(1, |chain| chain.pages.len().max(1))
    }

    /// The file's format.
    pub fn format(&self) -> ImageFormat {
        self.format
    }

    /// The resolution the file states, dots per inch: PNG's `pHYs` in pixels per metre, JPEG's
    /// JFIF density per inch or centimetre, TIFF's `XResolution` and `ResolutionUnit` (of the
    /// first page); `None` where it states none or only an aspect ratio, and for other formats.
    pub fn resolution(&self) -> Option<f64> {
        super::resolution::stated(self.bytes, self.format)
    }

    /// The TIFF's chain of pages does not end properly (it points outside the file, at a
    /// truncated directory, or back at an earlier page): the pages before the break are all there
    /// is.
    pub fn chain_damaged(&self) -> bool {
        self.chain.as_ref().is_some_and(|chain| chain.damaged)
    }

    /// Also give each page its [`Picture`] (the original bytes, or the colour pixels, when they
    /// differ from the gray). Without it every picture is [`Picture::Gray`] and no colour copy is
    /// kept.
    pub fn with_pictures(mut self, pictures: bool) -> Self {
        self.pictures = pictures;
        self
    }
}

impl Iterator for Pages<'_> {
    type Item = Result<Page>;

    fn next(&mut self) -> Option<Result<Page>> {
        let index = self.next;
        if index >= self.page_count() {
            return None;
        }
        self.next += 1;
        let tiff = self
            .chain
            .as_ref()
            .and_then(|chain| chain.pages.get(index).map(|&ifd| (&chain.header, ifd)));
        let target = Target {
            bytes: self.bytes,
            format: self.format,
            tiff,
            single: self.page_count() == 1,
        };
        let result = guarded(|| decode_page(&target, &self.limits, self.pictures));
        Some(result.map(|page| Page {
            number: index + 1,
            ..page
        }))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = self.page_count() - self.next.min(self.page_count());
        (left, Some(left))
    }
}

impl ExactSizeIterator for Pages<'_> {}

/// What one page decode reads: the file, and for a TIFF the page's directory.
struct Target<'a, 'h> {
    bytes: &'a [u8],
    format: ImageFormat,
    tiff: Option<(&'h tiff_pages::Header, u64)>,
    /// The file holds this one image (its bytes can stand for the page).
    single: bool,
}

/// A codec that panics on malformed data must not take the caller down: the input is untrusted
/// and a panic is a decoding failure like any other.
fn guarded<T>(decode: impl FnOnce() -> Result<T>) -> Result<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(decode)) {
        Ok(result) => result,
        Err(_) => Err(Error::Decode(
            "the image decoder failed on malformed data".into(),
        )),
    }
}

fn check_format(bytes: &[u8]) -> Result<ImageFormat> {
    if bytes.is_empty() {
        return Err(Error::Decode("the input is empty (0 bytes)".into()));
    }
    // The image crate's guess knows classic TIFF only; its TIFF codec reads BigTIFF too.
    if tiff_pages::Header::read(bytes).is_some() {
        return Ok(ImageFormat::Tiff);
    }
    guess_format(bytes)
}

fn decode_page(target: &Target, limits: &Limits, pictures: bool) -> Result<Page> {
    let format = target.format;
    let fix = match target.tiff {
        Some((header, ifd)) => tiff_pages::page_fix(target.bytes, header, ifd)
            .map_err(|reason| Error::Decode(format!("unsupported TIFF variant: {reason}")))?,
        None => tiff_pages::PageFix::default(),
    };
    let reader = || PatchedReader::new(target.bytes, fix.patches.clone());
    let mut decoder =
        match image_reader(reader(), format, image_limits(limits, true)).into_decoder() {
            Ok(decoder) => decoder,
            Err(ImageError::Limits(_)) => {
                return Err(side_limit_error(
                    image_reader(reader(), format, image_limits(limits, false)),
                    format,
                    limits,
                ))
            }
            Err(e) => return Err(decode_error(e, format)),
        };
    let (width, height) = decoder.dimensions();
    check_size(width, height, limits)?;
    let mime = browser_mime(format).filter(|_| pictures && target.single);
    // A viewer applies an orientation tag to the file's pixels; the trace follows the pixels as
    // stored, so such a file is shown by its decoded pixels instead.
    let original = mime.filter(|_| {
        matches!(
            decoder.orientation(),
            Ok(Orientation::NoTransforms) | Err(_)
        )
    });
    let mut image = DynamicImage::from_decoder(decoder).map_err(|e| decode_error(e, format))?;
    if fix.ycbcr {
        if let DynamicImage::ImageRgb8(pixels) = &mut image {
            ycbcr_to_rgb(pixels);
        }
    }
    let (gray, transparency, color) = to_gray(image, pictures && original.is_none());
    let picture = match (original, color) {
        (Some(mime), _) => Picture::Original { mime },
        (None, Some(color)) => Picture::Color(color),
        (None, None) => Picture::Gray,
    };
    Ok(Page {
        number: 1,
        gray,
        transparency,
        picture,
    })
}

/// JPEG's YCbCr (full range, the JFIF equations as TIFF Technical Note 2 adopts them) to RGB, in
/// place.
fn ycbcr_to_rgb(pixels: &mut image::RgbImage) {
    for pixel in pixels.pixels_mut() {
        let [y, cb, cr] = pixel.0.map(f32::from);
        let (cb, cr) = (cb - 128.0, cr - 128.0);
        let rgb = [
            y + 1.402 * cr,
            y - 0.344_136 * cb - 0.714_136 * cr,
            y + 1.772 * cb,
        ];
        pixel.0 = rgb.map(|v| v.round().clamp(0.0, 255.0) as u8);
    }
}

/// The MIME type of the formats browsers show in an SVG `<image>`.
fn browser_mime(format: ImageFormat) -> Option<&'static str> {
    match format {
        ImageFormat::Png => Some("image/png"),
        ImageFormat::Jpeg => Some("image/jpeg"),
        ImageFormat::Gif => Some("image/gif"),
        ImageFormat::WebP => Some("image/webp"),
        _ => None,
    }
}

/// The formats ridgeline decodes, for messages.
const SUPPORTED: &str = "PNG, JPEG, TIFF, BMP, PNM, GIF or WebP";

fn guess_format(bytes: &[u8]) -> Result<ImageFormat> {
    let format = image::guess_format(bytes).map_err(|_| {
        Error::Decode(format!(
            "not a recognized image format (expected {SUPPORTED})"
        ))
    })?;
    // The image crate recognizes more formats (ICO, QOI, AVIF, ...) than this build decodes: name
    // the format instead of reporting an "unsupported variant".
    if !format.reading_enabled() {
        let name = format
            .extensions_str()
            .first()
            .map_or_else(|| format!("{format:?}"), |e| e.to_uppercase());
        return Err(Error::Decode(format!(
            "{name} images are not supported (expected {SUPPORTED}); convert the file first"
        )));
    }
    Ok(format)
}

fn image_reader<R: BufRead + Seek>(
    source: R,
    format: ImageFormat,
    limits: image::Limits,
) -> ImageReader<R> {
    let mut reader = ImageReader::with_format(source, format);
    reader.limits(limits);
    reader
}

/// The decoder's limits: strict side limits (some decoders ignore `max_alloc`) and an allocation
/// bound derived from `max_pixels`.
fn image_limits(limits: &Limits, with_sides: bool) -> image::Limits {
    let mut bound = image::Limits::no_limits();
    if with_sides {
        bound.max_image_width = Some(limits.max_side);
        bound.max_image_height = Some(limits.max_side);
    }
    bound.max_alloc = Some(
        limits
            .max_pixels
            .saturating_mul(BYTES_PER_PIXEL_BOUND)
            .saturating_add(ALLOC_SLACK),
    );
    bound
}

fn check_size(width: u32, height: u32, limits: &Limits) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(Error::Decode(format!(
            "the image is empty ({width}x{height} pixels)"
        )));
    }
    let pixels = width as u64 * height as u64;
    if pixels > limits.max_pixels {
        return Err(Error::Limit {
            what: "image pixels",
            actual: pixels,
            limit: limits.max_pixels,
            field: "limits.max_pixels",
        });
    }
    let side = width.max(height);
    if side > limits.max_side {
        return Err(Error::Limit {
            what: "image side",
            actual: side as u64,
            limit: limits.max_side as u64,
            field: "limits.max_side",
        });
    }
    Ok(())
}

/// The decoder refused the header against the side limits: read the header again without them to
/// say which limit and by how much.
fn side_limit_error<R: BufRead + Seek>(
    reader: ImageReader<R>,
    format: ImageFormat,
    limits: &Limits,
) -> Error {
    match reader.into_dimensions() {
        Ok((width, height)) => match check_size(width, height, limits) {
            Err(e) => e,
            Ok(()) => Error::Decode(format!(
                "the {} decoder refused a {width}x{height} image within the limits",
                format_name(format)
            )),
        },
        Err(e) => decode_error(e, format),
    }
}

fn format_name(format: ImageFormat) -> &'static str {
    match format {
        ImageFormat::Png => "PNG",
        ImageFormat::Jpeg => "JPEG",
        ImageFormat::Tiff => "TIFF",
        ImageFormat::Bmp => "BMP",
        ImageFormat::Pnm => "PNM",
        ImageFormat::Gif => "GIF",
        ImageFormat::WebP => "WebP",
        _ => "image",
    }
}

fn decode_error(error: ImageError, format: ImageFormat) -> Error {
    let name = format_name(format);
    match error {
        ImageError::Decoding(e) => Error::Decode(format!("truncated or corrupt {name} data: {e}")),
        ImageError::IoError(e) if e.kind() == ErrorKind::UnexpectedEof => {
            Error::Decode(format!("truncated {name} data: the file ends early"))
        }
        ImageError::IoError(e) => Error::Decode(format!("truncated or corrupt {name} data: {e}")),
        ImageError::Limits(e) => Error::Decode(format!(
            "the {name} image needs more memory than limits.max_pixels allows: {e}"
        )),
        ImageError::Unsupported(e) => Error::Decode(format!("unsupported {name} variant: {e}")),
        other => Error::Decode(format!("{name}: {other}")),
    }
}

/// Luminance (Rec. 709 weights, as the image crate uses) of straight-alpha pixels composited over
/// the paper (white, or black for light ink: see [`Transparency`]); with `keep_color`, also the
/// pixels in 8-bit colour when they are not gray and opaque.
fn to_gray(
    image: DynamicImage,
    keep_color: bool,
) -> (GrayImage, Option<Transparency>, Option<DynamicImage>) {
    let (width, height) = (image.width(), image.height());
    let (values, look) = match &image {
        DynamicImage::ImageLuma8(_) => {
            let gray = image.into_luma8();
            return (gray, None, None);
        }
        DynamicImage::ImageLumaA8(img) => composite(img),
        DynamicImage::ImageRgb8(img) => composite(img),
        DynamicImage::ImageRgba8(img) => composite(img),
        DynamicImage::ImageLuma16(img) => composite(img),
        DynamicImage::ImageLumaA16(img) => composite(img),
        DynamicImage::ImageRgb16(img) => composite(img),
        DynamicImage::ImageRgba16(img) => composite(img),
        DynamicImage::ImageRgb32F(img) => composite(img),
        DynamicImage::ImageRgba32F(img) => composite(img),
        other => (other.to_luma8().into_raw(), Look::default()),
    };
    let gray =
        GrayImage::from_raw(width, height, values).unwrap_or_else(|| GrayImage::new(width, height));
    let color = (keep_color && !(look.gray && look.transparency.is_none())).then(|| {
        match (look.gray, look.transparency.is_some()) {
            (true, _) => DynamicImage::ImageLumaA8(image.into_luma_alpha8()),
            (false, true) => DynamicImage::ImageRgba8(image.into_rgba8()),
            (false, false) => DynamicImage::ImageRgb8(image.into_rgb8()),
        }
    });
    (gray, look.transparency, color)
}

/// What a pass over the pixels found besides their gray values.
#[derive(Clone, Copy, Debug, Default)]
struct Look {
    /// Every pixel has equal red, green and blue.
    gray: bool,
    /// Some pixel is not fully opaque.
    transparency: Option<Transparency>,
}

/// The gray values of [`to_gray`] for any pixel layout: channels scaled to `[0, 1]` (no alpha
/// channel reads as opaque), then [`composite_unit`].
fn composite<P>(image: &ImageBuffer<P, Vec<P::Subpixel>>) -> (Vec<u8>, Look)
where
    P: Pixel,
    P::Subpixel: Into<f32>,
{
    let scale = 1.0 / P::Subpixel::DEFAULT_MAX_VALUE.into();
    let unit = move |p: &P| p.to_rgba().0.map(|v| (v.into() * scale).clamp(0.0, 1.0));
    let has_alpha = P::CHANNEL_COUNT == 2 || P::CHANNEL_COUNT == 4;
    composite_unit(|| image.pixels().map(unit), has_alpha)
}

/// Luminance of `[r, g, b, alpha]` pixels in `[0, 1]` composited over the paper, as 8-bit gray. A
/// first pass over the alpha decides the paper (white, or black behind light ink; see
/// [`Transparency`]); pixels without alpha (`has_alpha` false) take one pass.
fn composite_unit<I>(pixels: impl Fn() -> I, has_alpha: bool) -> (Vec<u8>, Look)
where
    I: Iterator<Item = [f32; 4]>,
{
    let luma = |[r, g, b, _]: [f32; 4]| 0.2126 * r + 0.7152 * g + 0.0722 * b;
    let mut look = Look {
        gray: true,
        transparency: None,
    };
    if has_alpha {
        let (mut transparent, mut opaque, mut dark) = (false, 0u64, 0u64);
        for rgba in pixels() {
            transparent |= rgba[3] < 1.0;
            if rgba[3] >= 0.5 {
                opaque += 1;
                dark += u64::from(luma(rgba) < 0.5);
            }
        }
        look.transparency = transparent.then_some(Transparency {
            opaque_pixels: opaque,
            light_ink: opaque > 0 && dark * LIGHT_INK_DARK_SHARE < opaque,
        });
    }
    let paper = match look.transparency {
        Some(t) if t.light_ink => 0.0,
        _ => 1.0,
    };
    let mut gray = true;
    let values = pixels()
        .map(|rgba| {
            gray &= rgba[0] == rgba[1] && rgba[1] == rgba[2];
            let over_paper = luma(rgba) * rgba[3] + paper * (1.0 - rgba[3]);
            (over_paper.clamp(0.0, 1.0) * 255.0).round() as u8
        })
        .collect();
    look.gray = gray;
    (values, look)
}

/// The 8-bit gray image a file with these pixels decodes to: `pixels()` yields the
/// `width x height` pixels row by row as `[red, green, blue, alpha]` in `[0, 1]` (gray as equal
/// red, green and blue; alpha 1 without an alpha channel, and `has_alpha` false), read once, or
/// twice when `has_alpha`. Luminance with Rec. 709 weights; transparent pixels are paper, as a
/// file's are (see the module doc). For pixels held elsewhere than in a file (the Python
/// package's colour, 16-bit and float arrays), so that they trace as the same pixels saved as
/// PNG do.
pub fn gray_from_unit_pixels<I>(
    width: u32,
    height: u32,
    pixels: impl Fn() -> I,
    has_alpha: bool,
) -> Result<(GrayImage, Option<Transparency>)>
where
    I: Iterator<Item = [f32; 4]>,
{
    let (values, look) = composite_unit(pixels, has_alpha);
    let gray = GrayImage::from_raw(width, height, values).ok_or_else(|| {
        Error::InvalidParams(format!(
            "{width} x {height} pixels expected, and the pixels given are not as many"
        ))
    })?;
    Ok((gray, look.transparency))
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{ImageEncoder, Luma, Rgba};
    use std::io::Cursor;

    fn png(encode: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
        let mut bytes = Vec::new();
        encode(&mut bytes);
        bytes
    }

    fn encode_png(
        bytes: &mut Vec<u8>,
        raw: &[u8],
        width: u32,
        height: u32,
        color: image::ExtendedColorType,
    ) {
        image::codecs::png::PngEncoder::new(bytes)
            .write_image(raw, width, height, color)
            .expect("encode fixture");
    }

    fn message(e: Error) -> String {
        e.to_string()
    }

    #[test]
    fn zero_bytes_and_text_are_refused() {
        let limits = Limits::default();
        assert!(matches!(decode(&[], &limits), Err(Error::Decode(_))));
        let text = b"x y\n1 2\nthis is not an image at all\n";
        let e = message(decode(text, &limits).unwrap_err());
        assert!(e.contains("not a recognized image format"), "{e}");
    }

    #[test]
    fn truncated_png_is_refused() {
        let raw: Vec<u8> = (0..64 * 64).map(|i| (i % 251) as u8).collect();
        let bytes = png(|b| encode_png(b, &raw, 64, 64, image::ExtendedColorType::L8));
        let limits = Limits::default();
        assert!(decode(&bytes, &limits).is_ok());
        for cut in [9, 20, 33, 60, bytes.len() / 2, bytes.len() - 13] {
            let e = decode(&bytes[..cut], &limits).unwrap_err();
            let text = message(e);
            assert!(text.contains("PNG"), "cut {cut}: {text}");
        }
    }

    #[test]
    fn sixteen_bit_gray_png() {
        let values = [0u16, 65535, 32768, 257 * 10];
        let raw: Vec<u8> = values.iter().flat_map(|v| v.to_ne_bytes()).collect();
        let bytes = png(|b| encode_png(b, &raw, 2, 2, image::ExtendedColorType::L16));
        let gray = decode(&bytes, &Limits::default()).unwrap();
        assert_eq!(gray.as_raw(), &vec![0, 255, 128, 10]);
    }

    #[test]
    fn rgba_png_composites_over_white() {
        let mut img = image::RgbaImage::new(3, 1);
        img.put_pixel(0, 0, Rgba([0, 0, 0, 255]));
        img.put_pixel(1, 0, Rgba([0, 0, 0, 0]));
        img.put_pixel(2, 0, Rgba([0, 0, 0, 128]));
        let bytes = png(|b| encode_png(b, img.as_raw(), 3, 1, image::ExtendedColorType::Rgba8));
        let gray = decode(&bytes, &Limits::default()).unwrap();
        assert_eq!(gray.as_raw(), &vec![0, 255, 127]);
    }

    #[test]
    fn other_formats_decode() {
        let mut img = GrayImage::new(16, 16);
        for y in 4..12 {
            for x in 4..12 {
                img.put_pixel(x, y, Luma([220]));
            }
        }
        for format in [
            ImageFormat::Bmp,
            ImageFormat::Pnm,
            ImageFormat::Tiff,
            ImageFormat::Gif,
            ImageFormat::Jpeg,
            ImageFormat::WebP,
        ] {
            let mut bytes = Vec::new();
            let rgb = DynamicImage::ImageLuma8(img.clone()).to_rgb8();
            DynamicImage::ImageRgb8(rgb)
                .write_to(&mut Cursor::new(&mut bytes), format)
                .expect("encode fixture");
            let gray = decode(&bytes, &Limits::default()).unwrap();
            assert_eq!(gray.dimensions(), (16, 16), "{format:?}");
            assert!(gray.get_pixel(8, 8).0[0] > 150, "{format:?}");
            assert!(gray.get_pixel(0, 0).0[0] < 50, "{format:?}");
        }
    }

    /// Deterministic byte flips and truncations of small valid files of every format: the
    /// codecs must return errors, not panic (tested below the panic guard).
    #[test]
    fn corrupted_files_give_errors() {
        let img = GrayImage::from_fn(24, 17, |x, y| Luma([((x * 37 + y * 11) % 256) as u8]));
        let mut state = 99u64;
        for format in [
            ImageFormat::Png,
            ImageFormat::Bmp,
            ImageFormat::Pnm,
            ImageFormat::Tiff,
            ImageFormat::Gif,
            ImageFormat::Jpeg,
            ImageFormat::WebP,
        ] {
            let mut bytes = Vec::new();
            DynamicImage::ImageRgb8(DynamicImage::ImageLuma8(img.clone()).to_rgb8())
                .write_to(&mut Cursor::new(&mut bytes), format)
                .expect("encode fixture");
            let limits = Limits {
                max_pixels: 1 << 20,
                ..Limits::default()
            };
            for cut in (0..bytes.len()).step_by(7) {
                let _ = decode_unguarded(&bytes[..cut], &limits);
            }
            for _ in 0..300 {
                let mut broken = bytes.clone();
                for _ in 0..3 {
                    state = state
                        .wrapping_mul(6_364_136_223_846_793_005)
                        .wrapping_add(1);
                    let at = (state >> 33) as usize % broken.len();
                    broken[at] ^= 1 << ((state >> 20) % 8);
                }
                let _ = decode_unguarded(&broken, &limits);
            }
        }
    }

    #[test]
    fn file_errors_are_io_errors() {
        let missing = Path::new("/nonexistent/ridgeline/scan.png");
        assert!(matches!(
            decode_file(missing, &Limits::default()),
            Err(Error::Io { .. })
        ));
    }
}
