//! Decoding: image bytes to 8-bit grayscale within the configured limits.
//!
//! Untrusted files are the norm (batches of scans from anywhere), so the size is checked from the
//! header before any pixel buffer exists, the decoder gets strict side limits and an allocation
//! bound, and whatever a codec reports is turned into an [`Error`] a user can act on.

use std::io::{Cursor, ErrorKind};
use std::path::Path;

use image::{
    DynamicImage, ImageBuffer, ImageDecoder, ImageError, ImageFormat, ImageReader, Pixel, Primitive,
};

use crate::{Error, GrayImage, Limits, Result};

/// Decoder allocation bound per image pixel: an RGBA image with 16 bits per channel, the widest
/// layout the enabled codecs produce, plus room for the codec's own buffers.
const BYTES_PER_PIXEL_BOUND: u64 = 8 + 4;
/// Fixed allowance on top of the per-pixel bound (palettes, metadata, line buffers).
const ALLOC_SLACK: u64 = 64 << 20;

/// Decodes image bytes (PNG, JPEG, TIFF, BMP, PNM, GIF, WebP; format guessed from the content) to
/// grayscale. Transparent pixels are composited over white paper. Images with more than
/// `limits.max_pixels` pixels or a side longer than `limits.max_side` are refused from their header,
/// before their pixels are allocated.
pub fn decode(bytes: &[u8], limits: &Limits) -> Result<GrayImage> {
    // A codec that panics on malformed data must not take the caller down: the input is
    // untrusted and a panic is a decoding failure like any other.
    match std::panic::catch_unwind(|| decode_unguarded(bytes, limits)) {
        Ok(result) => result,
        Err(_) => Err(Error::Decode(
            "the image decoder failed on malformed data".into(),
        )),
    }
}

/// Reads and decodes an image file; see [`decode`](crate::raster::decode).
pub fn decode_file(path: &Path, limits: &Limits) -> Result<GrayImage> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode(&bytes, limits)
}

fn decode_unguarded(bytes: &[u8], limits: &Limits) -> Result<GrayImage> {
    if bytes.is_empty() {
        return Err(Error::Decode("the input is empty (0 bytes)".into()));
    }
    let format = guess_format(bytes)?;
    let decoder = match reader(bytes, format, image_limits(limits, true)).into_decoder() {
        Ok(decoder) => decoder,
        Err(ImageError::Limits(_)) => return Err(side_limit_error(bytes, format, limits)),
        Err(e) => return Err(decode_error(e, format)),
    };
    let (width, height) = decoder.dimensions();
    check_size(width, height, limits)?;
    let image = DynamicImage::from_decoder(decoder).map_err(|e| decode_error(e, format))?;
    Ok(to_gray(image))
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

fn reader(bytes: &[u8], format: ImageFormat, limits: image::Limits) -> ImageReader<Cursor<&[u8]>> {
    let mut reader = ImageReader::with_format(Cursor::new(bytes), format);
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
            flag: "--max-pixels",
        });
    }
    let side = width.max(height);
    if side > limits.max_side {
        return Err(Error::Limit {
            what: "image side",
            actual: side as u64,
            limit: limits.max_side as u64,
            flag: "--max-side",
        });
    }
    Ok(())
}

/// The decoder refused the header against the side limits: read the header again without them to
/// say which limit and by how much.
fn side_limit_error(bytes: &[u8], format: ImageFormat, limits: &Limits) -> Error {
    match reader(bytes, format, image_limits(limits, false)).into_dimensions() {
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
            "the {name} image needs more memory than --max-pixels allows: {e}"
        )),
        ImageError::Unsupported(e) => Error::Decode(format!("unsupported {name} variant: {e}")),
        other => Error::Decode(format!("{name}: {other}")),
    }
}

/// Luminance (Rec. 709 weights, as the image crate uses) of straight-alpha pixels composited over
/// white paper: a transparent background reads as paper, not as black ink.
fn to_gray(image: DynamicImage) -> GrayImage {
    let (width, height) = (image.width(), image.height());
    let values = match image {
        DynamicImage::ImageLuma8(gray) => return gray,
        DynamicImage::ImageLumaA8(img) => over_white(&img),
        DynamicImage::ImageRgb8(img) => over_white(&img),
        DynamicImage::ImageRgba8(img) => over_white(&img),
        DynamicImage::ImageLuma16(img) => over_white(&img),
        DynamicImage::ImageLumaA16(img) => over_white(&img),
        DynamicImage::ImageRgb16(img) => over_white(&img),
        DynamicImage::ImageRgba16(img) => over_white(&img),
        DynamicImage::ImageRgb32F(img) => over_white(&img),
        DynamicImage::ImageRgba32F(img) => over_white(&img),
        other => return other.to_luma8(),
    };
    GrayImage::from_raw(width, height, values).unwrap_or_else(|| GrayImage::new(width, height))
}

/// The gray values of [`to_gray`] for any pixel layout: channels scaled to `[0, 1]` (no alpha
/// channel reads as opaque), luminance, then the composite over white.
fn over_white<P>(image: &ImageBuffer<P, Vec<P::Subpixel>>) -> Vec<u8>
where
    P: Pixel,
    P::Subpixel: Into<f32>,
{
    let scale = 1.0 / P::Subpixel::DEFAULT_MAX_VALUE.into();
    image
        .pixels()
        .map(|p| {
            let [r, g, b, a] = p.to_rgba().0.map(|v| (v.into() * scale).clamp(0.0, 1.0));
            let luma = 0.2126 * r + 0.7152 * g + 0.0722 * b;
            let over_white = luma * a + (1.0 - a);
            (over_white.clamp(0.0, 1.0) * 255.0).round() as u8
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{ImageEncoder, Luma, Rgba};

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
