//! Inputs people have: multi-page TIFFs, JPEG-compressed TIFF pages with a predictor tag, colour
//! images (embedded in the SVG as given), and ink on a transparent background.
//!
//! Every file is built here: TIFFs byte by byte with [`tiff`], the others with the `image` crate.

use std::fs;
use std::io::Cursor;
use std::path::Path;
use std::time::Instant;

use crate::support::{entries, mask_image, ridgeline, run_ok, stderr, temp_dir};

use base64::Engine;
use image::{DynamicImage, GrayImage, ImageFormat, Luma, Rgb, RgbImage, Rgba, RgbaImage};
use ridgeline::Limits;
use ridgeline_testkit::synth::{render, Stroke};

// ---------------------------------------------------------------------------------------------
// Hand-made TIFF files

/// One directory entry: tag, field type, count, and the value's bytes (little-endian).
struct Entry {
    tag: u16,
    kind: u16,
    count: u64,
    value: Vec<u8>,
}

fn shorts(tag: u16, values: &[u16]) -> Entry {
    Entry {
        tag,
        kind: 3,
        count: values.len() as u64,
        value: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
    }
}

/// A page: its entries (the strip tags are added by [`tiff`]) and its one strip of data.
struct TiffPage {
    entries: Vec<Entry>,
    strip: Vec<u8>,
}

const COMPRESSION: u16 = 259;
const PREDICTOR: u16 = 317;

/// Entries of an uncompressed 8-bit page of `width` x `height` with `samples` per pixel.
fn basic_entries(width: u32, height: u32, samples: u16, photometric: u16) -> Vec<Entry> {
    vec![
        Entry {
            tag: 256,
            kind: 4,
            count: 1,
            value: width.to_le_bytes().to_vec(),
        },
        Entry {
            tag: 257,
            kind: 4,
            count: 1,
            value: height.to_le_bytes().to_vec(),
        },
        shorts(258, &vec![8; usize::from(samples)]),
        shorts(COMPRESSION, &[1]),
        shorts(262, &[photometric]),
        shorts(277, &[samples]),
        Entry {
            tag: 278,
            kind: 4,
            count: 1,
            value: height.to_le_bytes().to_vec(),
        },
    ]
}

fn gray_page(gray: &GrayImage) -> TiffPage {
    TiffPage {
        entries: basic_entries(gray.width(), gray.height(), 1, 1),
        strip: gray.as_raw().clone(),
    }
}

fn rgb_page(rgb: &RgbImage) -> TiffPage {
    TiffPage {
        entries: basic_entries(rgb.width(), rgb.height(), 3, 2),
        strip: rgb.as_raw().clone(),
    }
}

/// A gray page whose strip is `gray` as a whole JPEG file (compression 7), with a Predictor tag
/// when given; returns the JPEG too.
fn jpeg_page(gray: &GrayImage, predictor: Option<u16>) -> (TiffPage, Vec<u8>) {
    let jpeg = encode(&DynamicImage::ImageLuma8(gray.clone()), ImageFormat::Jpeg);
    let mut entries = basic_entries(gray.width(), gray.height(), 1, 1);
    set(&mut entries, shorts(COMPRESSION, &[7]));
    if let Some(predictor) = predictor {
        set(&mut entries, shorts(PREDICTOR, &[predictor]));
    }
    (
        TiffPage {
            entries,
            strip: jpeg.clone(),
        },
        jpeg,
    )
}

/// Replaces or adds an entry.
fn set(entries: &mut Vec<Entry>, entry: Entry) {
    entries.retain(|e| e.tag != entry.tag);
    entries.push(entry);
}

/// A little-endian TIFF (BigTIFF when `big`) of `pages`, each IFD after its strip; returns the
/// bytes and each IFD's offset.
fn tiff_with_offsets(pages: &[TiffPage], big: bool) -> (Vec<u8>, Vec<u64>) {
    let word = if big { 8 } else { 4 };
    let mut out = if big {
        let mut header = b"II\x2b\x00\x08\x00\x00\x00".to_vec();
        header.extend_from_slice(&0u64.to_le_bytes());
        header
    } else {
        b"II\x2a\x00\x00\x00\x00\x00".to_vec()
    };
    let number = |value: u64| -> Vec<u8> {
        if big {
            value.to_le_bytes().to_vec()
        } else {
            (value as u32).to_le_bytes().to_vec()
        }
    };
    // Where the previous "next IFD" pointer is, to be filled in.
    let mut pointer_at = if big { 8 } else { 4 };
    let mut offsets = Vec::new();
    for page in pages {
        let strip_at = out.len() as u64;
        out.extend_from_slice(&page.strip);
        let mut entries: Vec<Entry> = page
            .entries
            .iter()
            .map(|e| Entry {
                tag: e.tag,
                kind: e.kind,
                count: e.count,
                value: e.value.clone(),
            })
            .collect();
        let offset_kind = if big { 16 } else { 4 };
        set(
            &mut entries,
            Entry {
                tag: 273,
                kind: offset_kind,
                count: 1,
                value: number(strip_at),
            },
        );
        set(
            &mut entries,
            Entry {
                tag: 279,
                kind: offset_kind,
                count: 1,
                value: number(page.strip.len() as u64),
            },
        );
        entries.sort_by_key(|e| e.tag);
        // Values that do not fit in the entry go before the IFD.
        let mut fields = Vec::new();
        for entry in &entries {
            if entry.value.len() > word {
                if out.len() % 2 == 1 {
                    out.push(0);
                }
                let at = out.len() as u64;
                out.extend_from_slice(&entry.value);
                let mut field = number(at);
                field.resize(word, 0);
                fields.push(field);
            } else {
                let mut field = entry.value.clone();
                field.resize(word, 0);
                fields.push(field);
            }
        }
        if out.len() % 2 == 1 {
            out.push(0);
        }
        let ifd = out.len() as u64;
        offsets.push(ifd);
        out[pointer_at..pointer_at + word].copy_from_slice(&number(ifd));
        if big {
            out.extend_from_slice(&(entries.len() as u64).to_le_bytes());
        } else {
            out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
        }
        for (entry, field) in entries.iter().zip(fields) {
            out.extend_from_slice(&entry.tag.to_le_bytes());
            out.extend_from_slice(&entry.kind.to_le_bytes());
            out.extend_from_slice(&number(entry.count));
            out.extend_from_slice(&field);
        }
        pointer_at = out.len();
        out.extend_from_slice(&number(0));
    }
    (out, offsets)
}

fn tiff(pages: &[TiffPage]) -> Vec<u8> {
    tiff_with_offsets(pages, false).0
}

/// Where the "next IFD" pointer of the classic TIFF IFD at `ifd` is.
fn next_pointer_at(bytes: &[u8], ifd: u64) -> usize {
    let at = ifd as usize;
    let count = u16::from_le_bytes([bytes[at], bytes[at + 1]]) as usize;
    at + 2 + 12 * count
}

// ---------------------------------------------------------------------------------------------
// Pictures

fn encode(image: &DynamicImage, format: ImageFormat) -> Vec<u8> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut Cursor::new(&mut bytes), format)
        .expect("encode fixture");
    bytes
}

/// Dark strokes on light paper: a cross, a bar, or a vee, by `kind`, at `width` x `height`.
fn drawing(kind: usize, width: u32, height: u32) -> GrayImage {
    let (w, h) = (width as f64, height as f64);
    let strokes = match kind {
        0 => vec![
            Stroke::new(vec![[0.15 * w, 0.15 * h], [0.85 * w, 0.85 * h]], 5.0),
            Stroke::new(vec![[0.15 * w, 0.85 * h], [0.85 * w, 0.15 * h]], 5.0),
        ],
        1 => vec![Stroke::new(
            vec![[0.1 * w, 0.5 * h], [0.9 * w, 0.5 * h]],
            6.0,
        )],
        _ => vec![Stroke::new(
            vec![[0.2 * w, 0.2 * h], [0.5 * w, 0.8 * h], [0.8 * w, 0.2 * h]],
            5.0,
        )],
    };
    mask_image(&render(&strokes, width, height))
}

/// `gray` in colour: ink dark blue, paper a light yellow.
fn colored(gray: &GrayImage) -> RgbImage {
    RgbImage::from_fn(gray.width(), gray.height(), |x, y| {
        if gray.get_pixel(x, y).0[0] < 128 {
            Rgb([20, 30, 140])
        } else {
            Rgb([250, 240, 200])
        }
    })
}

/// The ink of `gray` in `ink` colour on a fully transparent background.
fn on_transparent(gray: &GrayImage, ink: [u8; 3]) -> RgbaImage {
    RgbaImage::from_fn(gray.width(), gray.height(), |x, y| {
        let [r, g, b] = ink;
        if gray.get_pixel(x, y).0[0] < 128 {
            Rgba([r, g, b, 255])
        } else {
            Rgba([0, 0, 0, 0])
        }
    })
}

/// The JSON document of `ridgeline <args> -f json -o -` in `dir`.
fn json_of(args: &[&str], dir: &Path) -> serde_json::Value {
    let mut all = args.to_vec();
    all.extend(["-f", "json", "-o", "-"]);
    let output = run_ok(&all, dir);
    serde_json::from_slice(&output.stdout).expect("JSON")
}

/// The graph part of a JSON document.
fn graph_of(document: &serde_json::Value) -> (serde_json::Value, serde_json::Value) {
    (document["vertices"].clone(), document["edges"].clone())
}

fn edge_count(document: &serde_json::Value) -> usize {
    document["edges"].as_array().map_or(0, Vec::len)
}

/// The MIME type and decoded bytes of the SVG's embedded image.
fn embedded(svg: &str) -> (String, Vec<u8>) {
    let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
    let node = doc
        .descendants()
        .find(|n| n.has_tag_name("image"))
        .expect("an <image>");
    let href = node.attribute("href").expect("href");
    let (mime, data) = href
        .strip_prefix("data:")
        .and_then(|rest| rest.split_once(";base64,"))
        .expect("a base64 data URL");
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(data)
        .expect("base64");
    (mime.to_string(), bytes)
}

fn file_names(dir: &Path) -> Vec<String> {
    entries(dir)
        .into_iter()
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Multi-page TIFF

#[test]
fn every_page_of_a_multi_page_tiff_is_traced() {
    let dir = temp_dir();
    let pages: Vec<GrayImage> = vec![drawing(0, 80, 60), drawing(1, 90, 50), drawing(2, 70, 70)];
    let tiff_pages: Vec<TiffPage> = pages.iter().map(gray_page).collect();
    fs::write(dir.path().join("book.tif"), tiff(&tiff_pages)).expect("write");
    for (k, page) in pages.iter().enumerate() {
        page.save(dir.path().join(format!("page{}.png", k + 1)))
            .expect("png");
    }

    run_ok(&["book.tif"], dir.path());
    let names = file_names(dir.path());
    for name in ["book.svg", "book.p2.svg", "book.p3.svg"] {
        assert!(
            names.contains(&name.to_string()),
            "{name} missing: {names:?}"
        );
    }
    assert!(!names.iter().any(|n| n.contains(".p1.")), "{names:?}");
    // Each page's SVG has the page's own size.
    for (name, page) in ["book.svg", "book.p2.svg", "book.p3.svg"]
        .iter()
        .zip(&pages)
    {
        let text = fs::read_to_string(dir.path().join(name)).expect("read");
        let doc = roxmltree::Document::parse(&text).expect("SVG");
        let root = doc.root_element();
        assert_eq!(
            root.attribute("width"),
            Some(page.width().to_string().as_str())
        );
        assert_eq!(
            root.attribute("height"),
            Some(page.height().to_string().as_str())
        );
    }

    // JSON: one document per page, each recording its page, each the graph of that page alone.
    let out = dir.path().join("out");
    fs::create_dir(&out).expect("mkdir");
    run_ok(&["book.tif", "-o", "out/book.json"], dir.path());
    assert_eq!(
        file_names(&out),
        ["book.json", "book.p2.json", "book.p3.json"]
    );
    for (number, name) in ["book.json", "book.p2.json", "book.p3.json"]
        .iter()
        .enumerate()
    {
        let text = fs::read(out.join(name)).expect("read");
        let document: serde_json::Value = serde_json::from_slice(&text).expect("JSON");
        assert_eq!(document["source"]["page"], number + 1, "{name}");
        assert_eq!(document["source"]["pages"], 3, "{name}");
        let alone = json_of(&[&format!("page{}.png", number + 1)], dir.path());
        assert_eq!(graph_of(&document), graph_of(&alone), "{name}");
        assert!(
            alone["source"].get("page").is_none(),
            "single images have no page"
        );
    }
}

#[test]
fn a_tiff_with_thousands_of_pages_is_refused_by_its_page_count() {
    let dir = temp_dir();
    let dot = GrayImage::from_pixel(2, 2, Luma([200]));
    let pages: Vec<TiffPage> = (0..5000).map(|_| gray_page(&dot)).collect();
    fs::write(dir.path().join("many.tif"), tiff(&pages)).expect("write");
    let start = Instant::now();
    let output = ridgeline(&["many.tif"], dir.path());
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    for word in [
        "TIFF pages",
        "TIFF pages: 5000, over the limit of 1000",
        "--max-pages",
    ] {
        assert!(err.contains(word), "{word:?} missing from {err}");
    }
    assert!(start.elapsed().as_secs() < 10, "took {:?}", start.elapsed());
    assert_eq!(file_names(dir.path()), ["many.tif"], "nothing written");
    // A lower limit refuses a small book too; a raised one traces every page.
    let book: Vec<TiffPage> = (0..3).map(|k| gray_page(&drawing(k, 40, 40))).collect();
    fs::write(dir.path().join("book.tif"), tiff(&book)).expect("write");
    let output = ridgeline(&["book.tif", "--max-pages", "2"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("3, over the limit of 2"),
        "{}",
        stderr(&output)
    );
    run_ok(&["book.tif", "--max-pages", "3", "-o", "out/"], dir.path());
    let output = ridgeline(&["book.tif", "--max-pages", "0"], dir.path());
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("--max-pages"),
        "{}",
        stderr(&output)
    );
    assert_eq!(
        file_names(&dir.path().join("out")),
        ["book.p2.svg", "book.p3.svg", "book.svg"]
    );
}

#[test]
fn stdout_takes_single_page_inputs_only() {
    let dir = temp_dir();
    let book: Vec<TiffPage> = (0..2).map(|k| gray_page(&drawing(k, 40, 40))).collect();
    fs::write(dir.path().join("book.tif"), tiff(&book)).expect("write");
    let output = ridgeline(&["book.tif", "-o", "-"], dir.path());
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(err.contains("2 pages") && err.contains("-o -"), "{err}");
    assert!(output.stdout.is_empty());
    // One page is fine.
    fs::write(dir.path().join("one.tif"), tiff(&book[..1])).expect("write");
    let output = run_ok(&["one.tif", "-o", "-"], dir.path());
    assert!(output.stdout.starts_with(b"<svg"));
}

#[test]
fn a_damaged_page_chain_traces_the_pages_before_the_break() {
    let dir = temp_dir();
    let book: Vec<TiffPage> = (0..3).map(|k| gray_page(&drawing(k, 40, 40))).collect();
    // Page 3 points back at page 2: a loop.
    let (mut looped, offsets) = tiff_with_offsets(&book, false);
    let at = next_pointer_at(&looped, offsets[2]);
    looped[at..at + 4].copy_from_slice(&(offsets[1] as u32).to_le_bytes());
    // Page 2 points past the end of the file.
    let (mut cut, offsets) = tiff_with_offsets(&book, false);
    let at = next_pointer_at(&cut, offsets[1]);
    cut[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    for (name, bytes, pages) in [("looped", looped, 3), ("cut", cut, 2)] {
        fs::create_dir(dir.path().join(name)).expect("mkdir");
        fs::write(dir.path().join(name).join("book.tif"), bytes).expect("write");
        let output = run_ok(&[&format!("{name}/book.tif")], dir.path());
        let err = stderr(&output);
        assert!(err.contains("damaged after page"), "{name}: {err}");
        let svgs = file_names(&dir.path().join(name))
            .into_iter()
            .filter(|n| n.ends_with(".svg"))
            .count();
        assert_eq!(svgs, pages, "{name}");
    }
}

#[test]
fn a_broken_page_fails_by_number_and_the_others_are_written() {
    let dir = temp_dir();
    let mut book: Vec<TiffPage> = (0..3).map(|k| gray_page(&drawing(k, 40, 40))).collect();
    // Compression 2 (CCITT modified Huffman run lengths) is one the decoder does not read.
    set(&mut book[1].entries, shorts(COMPRESSION, &[2]));
    fs::write(dir.path().join("book.tif"), tiff(&book)).expect("write");
    let output = ridgeline(&["book.tif"], dir.path());
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(
        err.contains("page 2") && err.contains("1 of 3 pages"),
        "{err}"
    );
    assert_eq!(
        file_names(dir.path()),
        ["book.p3.svg", "book.svg", "book.tif"]
    );
}

// ---------------------------------------------------------------------------------------------
// JPEG-compressed TIFF pages with a Predictor tag

#[test]
fn a_jpeg_tiff_page_with_a_predictor_tag_reads_like_its_jpeg() {
    let dir = temp_dir();
    let page = drawing(0, 96, 64);
    // Horizontal differencing (2) means nothing for JPEG data, nor does a value TIFF does not
    // define: either way the page is its JPEG.
    for predictor in [2, 0, 9] {
        let (tiff_page, jpeg) = jpeg_page(&page, Some(predictor));
        fs::write(dir.path().join("page.tif"), tiff(&[tiff_page])).expect("write");
        fs::write(dir.path().join("page.jpg"), &jpeg).expect("write");
        let from_tiff = json_of(&["page.tif"], dir.path());
        let from_jpeg = json_of(&["page.jpg"], dir.path());
        assert!(edge_count(&from_jpeg) >= 4, "{}", from_jpeg["stats"]);
        assert_eq!(
            graph_of(&from_tiff),
            graph_of(&from_jpeg),
            "predictor {predictor}"
        );
    }
}

#[test]
fn a_colour_jpeg_tiff_page_in_ycbcr_reads_like_its_jpeg() {
    use ridgeline::raster::Picture;
    let rgb = colored(&drawing(0, 48, 32));
    let jpeg = encode(&DynamicImage::ImageRgb8(rgb), ImageFormat::Jpeg);
    // Photometric interpretation 6 (YCbCr), as JPEG-compressed colour TIFFs are written, with a
    // predictor tag for good measure.
    let mut entries = basic_entries(48, 32, 3, 6);
    set(&mut entries, shorts(COMPRESSION, &[7]));
    set(&mut entries, shorts(PREDICTOR, &[2]));
    let bytes = tiff(&[TiffPage {
        entries,
        strip: jpeg.clone(),
    }]);
    let direct = image::load_from_memory(&jpeg).expect("JPEG").to_rgb8();
    let mut pages = ridgeline::raster::pages(&bytes, &Limits::default())
        .expect("pages")
        .with_pictures(true);
    let page = pages.next().expect("a page").expect("decodes");
    let Picture::Color(DynamicImage::ImageRgb8(shown)) = &page.picture else {
        panic!("expected RGB pixels, got {:?}", page.picture);
    };
    let off = |a: &[u8], b: &[u8]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0)
    };
    assert!(off(shown.as_raw(), direct.as_raw()) <= 2, "colours differ");
    let gray = ridgeline::decode(&jpeg, &Limits::default()).expect("JPEG");
    assert!(off(page.gray.as_raw(), gray.as_raw()) <= 2, "gray differs");
}

// ---------------------------------------------------------------------------------------------
// Colour in the SVG

#[test]
fn colour_png_and_jpeg_are_embedded_as_given() {
    let dir = temp_dir();
    let picture = DynamicImage::ImageRgb8(colored(&drawing(0, 64, 48)));
    for (name, format, mime) in [
        ("page.png", ImageFormat::Png, "image/png"),
        ("page.jpg", ImageFormat::Jpeg, "image/jpeg"),
        ("page.gif", ImageFormat::Gif, "image/gif"),
    ] {
        let bytes = encode(&picture, format);
        fs::write(dir.path().join(name), &bytes).expect("write");
        let output = run_ok(&[name, "-o", "-"], dir.path());
        let svg = String::from_utf8(output.stdout).expect("UTF-8");
        let (found_mime, found) = embedded(&svg);
        assert_eq!(found_mime, mime, "{name}");
        assert!(found == bytes, "{name}: the embedded image is not the file");
    }
}

#[test]
fn colour_bmp_and_tiff_are_embedded_as_colour_pngs() {
    let dir = temp_dir();
    let rgb = colored(&drawing(1, 64, 48));
    fs::write(
        dir.path().join("page.bmp"),
        encode(&DynamicImage::ImageRgb8(rgb.clone()), ImageFormat::Bmp),
    )
    .expect("write");
    // Page 2 of a TIFF in colour, page 1 gray.
    let gray = drawing(0, 50, 40);
    fs::write(
        dir.path().join("book.tif"),
        tiff(&[gray_page(&gray), rgb_page(&rgb)]),
    )
    .expect("write");
    run_ok(&["page.bmp", "book.tif", "-o", "out/"], dir.path());
    let out = dir.path().join("out");
    for (name, expected) in [
        ("page.svg", DynamicImage::ImageRgb8(rgb.clone())),
        ("book.svg", DynamicImage::ImageLuma8(gray)),
        ("book.p2.svg", DynamicImage::ImageRgb8(rgb.clone())),
    ] {
        let (mime, png) = embedded(&fs::read_to_string(out.join(name)).expect("read"));
        assert_eq!(mime, "image/png", "{name}");
        let shown = image::load_from_memory(&png).expect("a PNG");
        assert_eq!(shown.color(), expected.color(), "{name}");
        assert!(shown == expected, "{name}: the embedded pixels differ");
    }
    // --no-image embeds nothing.
    let output = run_ok(&["page.bmp", "--no-image", "-o", "-"], dir.path());
    assert!(!String::from_utf8_lossy(&output.stdout).contains("<image"));
}

// ---------------------------------------------------------------------------------------------
// Transparency

#[test]
fn white_and_black_ink_on_transparent_trace_the_same_strokes() {
    let dir = temp_dir();
    let ink = drawing(2, 80, 60);
    ink.save(dir.path().join("paper.png")).expect("png");
    let on_paper = json_of(&["paper.png"], dir.path());
    assert!(edge_count(&on_paper) >= 1, "{}", on_paper["stats"]);
    for (name, colour) in [
        ("white.png", [255, 255, 255]),
        ("black.png", [0, 0, 0]),
        ("yellow.png", [250, 230, 40]),
    ] {
        on_transparent(&ink, colour)
            .save(dir.path().join(name))
            .expect("png");
        let output = run_ok(&[name, "-f", "json", "-o", "-"], dir.path());
        assert!(
            !stderr(&output).contains("warning"),
            "{name}: {}",
            stderr(&output)
        );
        let document: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
        assert_eq!(graph_of(&document), graph_of(&on_paper), "{name}");
    }
    // Gray with alpha, white ink, as a TIFF-free BMP-free case the PNG encoder writes directly.
    let la = image::GrayAlphaImage::from_fn(ink.width(), ink.height(), |x, y| {
        if ink.get_pixel(x, y).0[0] < 128 {
            image::LumaA([255, 255])
        } else {
            image::LumaA([255, 0])
        }
    });
    la.save(dir.path().join("white-la.png")).expect("png");
    assert_eq!(
        graph_of(&json_of(&["white-la.png"], dir.path())),
        graph_of(&on_paper)
    );
}

#[test]
fn a_transparent_image_says_why_no_ink_was_found() {
    let dir = temp_dir();
    RgbaImage::from_pixel(40, 30, Rgba([255, 255, 255, 0]))
        .save(dir.path().join("clear.png"))
        .expect("png");
    // Half-transparent black everywhere: dark ink candidates, but one uniform gray.
    RgbaImage::from_pixel(40, 30, Rgba([0, 0, 0, 160]))
        .save(dir.path().join("veil.png"))
        .expect("png");
    for name in ["clear.png", "veil.png"] {
        let output = run_ok(&[name, "-f", "json", "-o", "-"], dir.path());
        let err = stderr(&output);
        assert!(
            err.contains("blank page") && err.contains("transparen"),
            "{name}: {err}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The library: pages, pictures, transparency

#[test]
fn pages_are_decoded_one_at_a_time_and_decode_gives_the_first() {
    let drawings: Vec<GrayImage> = (0..3).map(|k| drawing(k, 30 + 10 * k as u32, 40)).collect();
    let tiff_pages: Vec<TiffPage> = drawings.iter().map(gray_page).collect();
    for big in [false, true] {
        let (bytes, _) = tiff_with_offsets(&tiff_pages, big);
        let pages = ridgeline::raster::pages(&bytes, &Limits::default()).expect("pages");
        assert_eq!(pages.page_count(), 3, "big {big}");
        assert!(!pages.chain_damaged());
        let decoded: Vec<_> = pages.map(|page| page.expect("page")).collect();
        for (k, (page, drawn)) in decoded.iter().zip(&drawings).enumerate() {
            assert_eq!(page.number, k + 1);
            assert_eq!(&page.gray, drawn, "big {big}, page {}", k + 1);
            assert_eq!(page.picture, ridgeline::raster::Picture::Gray);
            assert_eq!(page.transparency, None);
        }
        let first = ridgeline::decode(&bytes, &Limits::default()).expect("decode");
        assert_eq!(first, drawings[0], "big {big}");
    }
    // Not a TIFF: one page.
    let png = encode(
        &DynamicImage::ImageLuma8(drawings[0].clone()),
        ImageFormat::Png,
    );
    let mut pages = ridgeline::raster::pages(&png, &Limits::default()).expect("pages");
    assert_eq!(pages.page_count(), 1);
    assert_eq!(pages.next().expect("page").expect("ok").gray, drawings[0]);
    assert!(pages.next().is_none());
    // decode() of a TIFF with more pages than the limit still gives page 1.
    let many: Vec<TiffPage> = (0..5).map(|k| gray_page(&drawing(k, 20, 20))).collect();
    let bytes = tiff(&many);
    let mut limits = Limits::default();
    limits.max_pages = 2;
    assert!(matches!(
        ridgeline::raster::pages(&bytes, &limits),
        Err(ridgeline::Error::Limit { actual: 5, .. })
    ));
    assert_eq!(
        ridgeline::decode(&bytes, &limits).expect("decode"),
        drawing(0, 20, 20)
    );
}

#[test]
fn pictures_are_kept_only_when_they_show_more_than_the_gray() {
    use ridgeline::raster::Picture;
    let gray = drawing(0, 40, 30);
    let rgb = colored(&gray);
    let picture_of = |bytes: &[u8]| {
        let mut pages = ridgeline::raster::pages(bytes, &Limits::default())
            .expect("pages")
            .with_pictures(true);
        pages.next().expect("a page").expect("decodes").picture
    };
    let gray_bmp = encode(&DynamicImage::ImageLuma8(gray.clone()), ImageFormat::Bmp);
    assert_eq!(
        picture_of(&gray_bmp),
        Picture::Gray,
        "a gray BMP keeps no copy"
    );
    // A gray image stored as RGB is gray too.
    let gray_rgb = DynamicImage::ImageLuma8(gray.clone()).to_rgb8();
    let bmp = encode(&DynamicImage::ImageRgb8(gray_rgb), ImageFormat::Bmp);
    assert_eq!(picture_of(&bmp), Picture::Gray);
    let colour_bmp = encode(&DynamicImage::ImageRgb8(rgb.clone()), ImageFormat::Bmp);
    assert_eq!(
        picture_of(&colour_bmp),
        Picture::Color(DynamicImage::ImageRgb8(rgb.clone()))
    );
    let png = encode(&DynamicImage::ImageRgb8(rgb.clone()), ImageFormat::Png);
    assert_eq!(picture_of(&png), Picture::Original { mime: "image/png" });
    let webp = encode(&DynamicImage::ImageRgb8(rgb.clone()), ImageFormat::WebP);
    assert_eq!(picture_of(&webp), Picture::Original { mime: "image/webp" });
    // Without pictures asked for, nothing is kept.
    let mut pages = ridgeline::raster::pages(&colour_bmp, &Limits::default()).expect("pages");
    let page = pages.next().expect("a page").expect("decodes");
    assert_eq!(page.picture, Picture::Gray);

    // A JPEG whose EXIF orientation a viewer would apply is shown by its decoded pixels.
    let jpeg = encode(&DynamicImage::ImageRgb8(rgb.clone()), ImageFormat::Jpeg);
    assert_eq!(picture_of(&jpeg), Picture::Original { mime: "image/jpeg" });
    let rotated = with_exif_orientation(&jpeg, 6);
    assert!(matches!(picture_of(&rotated), Picture::Color(_)));
}

/// `jpeg` with an APP1 EXIF segment holding one Orientation tag (274) after its SOI marker.
fn with_exif_orientation(jpeg: &[u8], orientation: u16) -> Vec<u8> {
    let mut exif = b"Exif\0\0II\x2a\x00\x08\x00\x00\x00".to_vec();
    exif.extend_from_slice(&1u16.to_le_bytes());
    exif.extend_from_slice(&274u16.to_le_bytes());
    exif.extend_from_slice(&3u16.to_le_bytes());
    exif.extend_from_slice(&1u32.to_le_bytes());
    exif.extend_from_slice(&orientation.to_le_bytes());
    exif.extend_from_slice(&[0, 0]);
    exif.extend_from_slice(&0u32.to_le_bytes());
    let mut out = jpeg[..2].to_vec();
    out.extend_from_slice(&[0xFF, 0xE1]);
    out.extend_from_slice(&((exif.len() + 2) as u16).to_be_bytes());
    out.extend_from_slice(&exif);
    out.extend_from_slice(&jpeg[2..]);
    out
}

#[test]
fn an_undefined_predictor_on_lzw_names_the_tag() {
    let gray = drawing(0, 16, 16);
    let mut page = gray_page(&gray);
    set(&mut page.entries, shorts(COMPRESSION, &[5]));
    set(&mut page.entries, shorts(PREDICTOR, &[7]));
    let bytes = tiff(&[page]);
    let err = ridgeline::decode(&bytes, &Limits::default())
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains("predictor (tag 317) is 7") && err.contains("TIFF"),
        "{err}"
    );
}

#[test]
fn transparency_is_reported_with_the_ink_it_found() {
    let ink = drawing(1, 40, 30);
    let page_of = |image: RgbaImage| {
        let bytes = encode(&DynamicImage::ImageRgba8(image), ImageFormat::Png);
        let mut pages = ridgeline::raster::pages(&bytes, &Limits::default()).expect("pages");
        pages.next().expect("a page").expect("decodes")
    };
    let white = page_of(on_transparent(&ink, [255, 255, 255]));
    let t = white.transparency.expect("transparency");
    assert!(t.light_ink);
    let ink_pixels = ink.pixels().filter(|p| p.0[0] < 128).count() as u64;
    assert_eq!(t.opaque_pixels, ink_pixels);
    // White ink over black paper: the ink is light.
    assert_eq!(white.gray.get_pixel(20, 15).0[0], 255);
    assert_eq!(white.gray.get_pixel(0, 0).0[0], 0);
    let black = page_of(on_transparent(&ink, [0, 0, 0]));
    assert!(!black.transparency.expect("transparency").light_ink);
    assert_eq!(black.gray.get_pixel(0, 0).0[0], 255);
    // All opaque: no transparency to report.
    let opaque = RgbaImage::from_pixel(4, 4, Rgba([10, 20, 30, 255]));
    assert_eq!(page_of(opaque).transparency, None);
}

#[test]
fn a_later_page_never_replaces_another_inputs_output() {
    let dir = temp_dir();
    let pages: Vec<GrayImage> = vec![drawing(0, 80, 60), drawing(1, 90, 50)];
    let tiff_pages: Vec<TiffPage> = pages.iter().map(gray_page).collect();
    fs::write(dir.path().join("book.tif"), tiff(&tiff_pages)).expect("write");
    // An input whose own output is the name page 2 of book.tif would take.
    drawing(2, 70, 70)
        .save(dir.path().join("book.p2.png"))
        .expect("png");
    let output = ridgeline(&["book.tif", "book.p2.png", "--jobs", "1"], dir.path());
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(err.contains("also the output of another input"), "{err}");
    // book.p2.svg is book.p2.png's drawing, 70 px wide, not page 2's (90).
    let text = fs::read_to_string(dir.path().join("book.p2.svg")).expect("book.p2.svg");
    let doc = roxmltree::Document::parse(&text).expect("SVG");
    assert_eq!(doc.root_element().attribute("width"), Some("70"));
}
