//! The resolution an image file states, in dots per inch: PNG's `pHYs` chunk (pixels per metre)
//! and TIFF's `XResolution` with its `ResolutionUnit` (inch when absent, as TIFF 6.0 says), read
//! by the codecs' own crates, and JPEG's JFIF density (per inch or per centimetre), which the
//! JPEG codec does not read. A file
//! that gives only an aspect ratio (JFIF units 0, PNG's unspecified unit, TIFF unit 1) states
//! none.

use std::io::Cursor;

use image::ImageFormat;

/// Centimetres per inch.
const CM_PER_INCH: f64 = 2.54;

/// The horizontal resolution `bytes` (an image of `format`) states, dpi; `None` when it states
/// none or one an ISO/IEC 19794-2 record cannot hold (0, over 65535 px/cm). Of a multi-page
/// TIFF, the first page's.
pub(crate) fn stated(bytes: &[u8], format: ImageFormat) -> Option<f64> {
    let dpi = match format {
        ImageFormat::Png => png_dpi(bytes),
        ImageFormat::Jpeg => jpeg_dpi(bytes),
        ImageFormat::Tiff => tiff_dpi(bytes),
        _ => None,
    }?;
    (dpi.is_finite() && dpi > 0.0 && dpi <= f64::from(u16::MAX) * CM_PER_INCH).then_some(dpi)
}

fn png_dpi(bytes: &[u8]) -> Option<f64> {
    let reader = png::Decoder::new(Cursor::new(bytes)).read_info().ok()?;
    let dims = reader.info().pixel_dims?;
    (dims.unit == png::Unit::Meter).then(|| f64::from(dims.xppu) * CM_PER_INCH / 100.0)
}

/// JFIF's APP0 segment, the first after the start of image: `JFIF\0`, version (2 bytes), units
/// (0: aspect ratio only, 1: per inch, 2: per centimetre), X and Y density (big-endian). Read
/// here because the JPEG codec skips it.
fn jpeg_dpi(bytes: &[u8]) -> Option<f64> {
    let segment = bytes.strip_prefix(&[0xFF, 0xD8, 0xFF, 0xE0])?;
    let length = usize::from(u16::from_be_bytes([*segment.first()?, *segment.get(1)?]));
    let body = segment.get(2..length.max(2))?;
    let fields = body.strip_prefix(b"JFIF\0")?;
    let (units, density) = (*fields.get(2)?, fields.get(3..5)?);
    let density = f64::from(u16::from_be_bytes([density[0], density[1]]));
    match units {
        1 => Some(density),
        2 => Some(density * CM_PER_INCH),
        _ => None,
    }
}

fn tiff_dpi(bytes: &[u8]) -> Option<f64> {
    use tiff::decoder::ifd::Value;
    use tiff::tags::Tag;
    let mut decoder = tiff::decoder::Decoder::new(Cursor::new(bytes)).ok()?;
    let resolution = match decoder.get_tag(Tag::XResolution).ok()? {
        Value::Rational(n, d) if d > 0 => f64::from(n) / f64::from(d),
        _ => return None,
    };
    match decoder.find_tag_unsigned::<u16>(Tag::ResolutionUnit).ok()? {
        None | Some(2) => Some(resolution),
        Some(3) => Some(resolution * CM_PER_INCH),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{GrayImage, ImageEncoder, Luma};

    fn png_with(pixel_dims: Option<png::PixelDimensions>) -> Vec<u8> {
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, 4, 4);
        encoder.set_color(png::ColorType::Grayscale);
        encoder.set_pixel_dims(pixel_dims);
        let mut writer = encoder.write_header().expect("header");
        writer.write_image_data(&[200; 16]).expect("pixels");
        writer.finish().expect("finish");
        out
    }

    #[test]
    fn png_states_pixels_per_metre() {
        let dims = png::PixelDimensions {
            xppu: 19_685,
            yppu: 19_685,
            unit: png::Unit::Meter,
        };
        let dpi = stated(&png_with(Some(dims)), ImageFormat::Png).expect("stated");
        assert!((dpi - 500.0).abs() < 0.01, "{dpi}");
        let aspect = png::PixelDimensions {
            unit: png::Unit::Unspecified,
            ..dims
        };
        assert_eq!(stated(&png_with(Some(aspect)), ImageFormat::Png), None);
        assert_eq!(stated(&png_with(None), ImageFormat::Png), None);
    }

    #[test]
    fn jpeg_states_its_jfif_density() {
        let gray = GrayImage::from_pixel(8, 8, Luma([128]));
        let mut out = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, 90)
            .write_image(gray.as_raw(), 8, 8, image::ExtendedColorType::L8)
            .expect("jpeg");
        // image's encoder writes JFIF with units 0 (aspect ratio only) and density 1:1.
        assert_eq!(stated(&out, ImageFormat::Jpeg), None);
        // Units (1: per inch, 2: per centimetre) at byte 13 of the JFIF segment, densities after.
        let app0 = out
            .windows(5)
            .position(|w| w == b"JFIF\0")
            .expect("JFIF segment");
        out[app0 + 7] = 1;
        out[app0 + 8..app0 + 10].copy_from_slice(&500u16.to_be_bytes());
        assert_eq!(stated(&out, ImageFormat::Jpeg), Some(500.0));
        out[app0 + 7] = 2;
        out[app0 + 8..app0 + 10].copy_from_slice(&200u16.to_be_bytes());
        assert_eq!(stated(&out, ImageFormat::Jpeg), Some(508.0));
    }

    #[test]
    fn tiff_states_its_resolution_and_unit() {
        use tiff::encoder::{colortype, Rational, TiffEncoder};
        use tiff::tags::ResolutionUnit;
        let mut out = Cursor::new(Vec::new());
        {
            let mut encoder = TiffEncoder::new(&mut out).expect("encoder");
            let mut image = encoder.new_image::<colortype::Gray8>(4, 4).expect("image");
            image.resolution(ResolutionUnit::Centimeter, Rational { n: 400, d: 2 });
            image.write_data(&[100u8; 16]).expect("data");
        }
        let dpi = stated(out.get_ref(), ImageFormat::Tiff).expect("stated");
        assert!((dpi - 508.0).abs() < 1e-9, "{dpi}");
    }

    #[test]
    fn other_formats_and_broken_bytes_state_none() {
        assert_eq!(stated(b"BM not really", ImageFormat::Bmp), None);
        assert_eq!(stated(b"\x89PNG\r\n\x1a\n", ImageFormat::Png), None);
        assert_eq!(stated(&[0xFF, 0xD8, 0xFF], ImageFormat::Jpeg), None);
        assert_eq!(stated(b"II*\0", ImageFormat::Tiff), None);
    }
}
