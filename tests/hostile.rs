//! Hostile and broken input (docs/bad-input.md): every kind of bad file gets a clear message and a
//! non-zero exit, never a panic; degenerate but valid input traces or warns; outputs are never
//! clobbered; and the output does not depend on the run or the thread count.
//!
//! CLI-level cases run the real binary; the rest call the library. Every input is built here, in
//! the test, byte by byte where it matters (the decompression bomb, the palette PNG).

#[path = "../fuzz/fuzz_targets/point_bytes.rs"]
mod point_bytes;

use std::fs;
use std::io::Cursor;
use std::path::PathBuf;

use crate::support::{entries, mask_image, ridgeline, stderr, temp_dir};

use image::{DynamicImage, ImageFormat, Luma};
use ridgeline::{
    trace_binary, trace_image, trace_points, Binary, Error, GrayImage, Limits, Params, StrokeGraph,
};
use ridgeline_testkit::synth::{render, Stroke};

// ---------------------------------------------------------------------------------------------
// Helpers

/// A cross and a bar of dark ink on white paper.
fn strokes_gray(width: u32, height: u32) -> GrayImage {
    let (w, h) = (width as f64, height as f64);
    let strokes = [
        Stroke::new(vec![[0.12 * w, 0.12 * h], [0.88 * w, 0.6 * h]], 5.0),
        Stroke::new(vec![[0.12 * w, 0.6 * h], [0.88 * w, 0.12 * h]], 5.0),
        Stroke::new(vec![[0.2 * w, 0.85 * h], [0.8 * w, 0.85 * h]], 4.0),
    ];
    mask_image(&render(&strokes, width, height))
}

fn encode(gray: &GrayImage, format: ImageFormat) -> Vec<u8> {
    let mut bytes = Vec::new();
    DynamicImage::ImageLuma8(gray.clone())
        .write_to(&mut Cursor::new(&mut bytes), format)
        .expect("encode fixture");
    bytes
}

/// The PNG CRC-32 (polynomial 0xEDB88320), so the hand-made chunks are valid.
fn crc32(data: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &byte in data {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], body: &[u8]) {
    out.extend_from_slice(&(body.len() as u32).to_be_bytes());
    let mut crc_input = kind.to_vec();
    crc_input.extend_from_slice(body);
    out.extend_from_slice(&crc_input);
    out.extend_from_slice(&crc32(&crc_input).to_be_bytes());
}

/// zlib stream of `data` in stored (uncompressed) deflate blocks.
fn zlib_stored(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = if data.is_empty() {
        vec![&[][..]]
    } else {
        data.chunks(65_535).collect()
    };
    for (i, block) in blocks.iter().enumerate() {
        out.push(u8::from(i + 1 == blocks.len()));
        let len = block.len() as u16;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(block);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &v in data {
        a = (a + u32::from(v)) % 65_521;
        b = (b + a) % 65_521;
    }
    out.extend_from_slice(&((b << 16) | a).to_be_bytes());
    out
}

/// A PNG built by hand: `ihdr_tail` = bit depth, color type, 0, 0, 0; `chunks` go before IDAT;
/// `scanlines` are the filtered rows (filter byte first).
fn hand_png(
    width: u32,
    height: u32,
    ihdr_tail: [u8; 5],
    chunks: &[(&[u8; 4], &[u8])],
    scanlines: &[u8],
) -> Vec<u8> {
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&ihdr_tail);
    chunk(&mut out, b"IHDR", &ihdr);
    for (kind, body) in chunks {
        chunk(&mut out, kind, body);
    }
    chunk(&mut out, b"IDAT", &zlib_stored(scanlines));
    chunk(&mut out, b"IEND", &[]);
    out
}

/// The decompression bomb: 100 000 x 100 000 8-bit gray pixels declared in a PNG of a few dozen
/// bytes (the IDAT holds a few zero bytes; inflating the whole image would need 10 GB).
fn bomb_png() -> Vec<u8> {
    hand_png(100_000, 100_000, [8, 0, 0, 0, 0], &[], &[0; 64])
}

/// A palette PNG of `gray`: entry 0 is the ink (dark), entry 1 the paper.
fn palette_png(gray: &GrayImage) -> Vec<u8> {
    let mut scanlines = Vec::new();
    for row in gray.rows() {
        scanlines.push(0);
        scanlines.extend(row.map(|p| u8::from(p.0[0] >= 128)));
    }
    let palette = [20, 20, 20, 235, 235, 235];
    hand_png(
        gray.width(),
        gray.height(),
        [8, 3, 0, 0, 0],
        &[(b"PLTE", &palette)],
        &scanlines,
    )
}

/// The same picture with 16 bits per sample (v * 257, so it decodes to the same 8-bit levels).
fn png16(gray: &GrayImage) -> Vec<u8> {
    let wide =
        image::ImageBuffer::<Luma<u16>, Vec<u16>>::from_fn(gray.width(), gray.height(), |x, y| {
            Luma([u16::from(gray.get_pixel(x, y).0[0]) * 257])
        });
    let mut bytes = Vec::new();
    DynamicImage::ImageLuma16(wide)
        .write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png)
        .expect("encode fixture");
    bytes
}

/// A JPEG whose Huffman table segment is overwritten with an impossible one (code lengths adding
/// up to more codes than exist): the header is intact, the decoder must refuse the file.
fn corrupt_jpeg() -> Vec<u8> {
    let mut bytes = encode(&strokes_gray(64, 48), ImageFormat::Jpeg);
    let dht = bytes
        .windows(2)
        .position(|w| w == [0xFF, 0xC4])
        .expect("a DHT marker");
    // Segment length, then the table class/id, then 16 counts of code lengths: all 255.
    for b in &mut bytes[dht + 5..dht + 5 + 16] {
        *b = 0xFF;
    }
    bytes
}

/// Forbidden words in a message: a panic or an internal error must never reach the user.
fn assert_no_panic(err: &str) {
    for bad in ["panicked", "internal error", "RUST_BACKTRACE", "unwrap"] {
        assert!(!err.contains(bad), "{bad:?} in {err}");
    }
}

fn trace_ok(binary: &Binary) -> StrokeGraph {
    let trace = trace_binary(binary, &Params::default()).expect("trace succeeds");
    trace.graph.validate().expect("valid stroke graph");
    trace.graph
}

// ---------------------------------------------------------------------------------------------
// Broken files: a clear message, status 1, nothing written

/// Each broken input, its file name, and words its message must contain.
fn broken_inputs() -> Vec<(&'static str, Vec<u8>, &'static [&'static str])> {
    let png = encode(&strokes_gray(64, 48), ImageFormat::Png);
    let truncated = png[..png.len() / 2].to_vec();
    let mut ico = vec![0, 0, 1, 0, 1, 0, 16, 16, 0, 0, 1, 0, 32, 0];
    ico.extend_from_slice(&[0; 32]);
    vec![
        ("zero.png", Vec::new(), &["empty", "0 bytes"][..]),
        ("truncated.png", truncated, &["truncated", "PNG"]),
        ("corrupt.jpg", corrupt_jpeg(), &["corrupt", "JPEG"]),
        (
            "notes.png",
            b"These are my notes, not a picture.\n".to_vec(),
            &["not a recognized image format"],
        ),
        ("icon.ico", ico, &["ICO", "not supported"]),
        (
            "paper.pdf",
            b"%PDF-1.4\n1 0 obj\n<< >>\nendobj\n".to_vec(),
            &["not a recognized image format"],
        ),
        (
            "bomb.png",
            bomb_png(),
            &[
                "image pixels: 10000000000, over the limit of 100000000",
                "--max-pixels",
            ],
        ),
        (
            "nan.txt",
            b"x y\n1 2\nNaN 3\n".to_vec(),
            &["line 3", "not finite"],
        ),
        (
            "inf.xy",
            b"1 2\n3 inf\n".to_vec(),
            &["line 2", "not finite"],
        ),
        (
            "three.csv",
            b"1,2\n3,4,5\n".to_vec(),
            &["line 2", "expected 2 numbers"],
        ),
        (
            "words.pts",
            b"1 2\nthree four\n".to_vec(),
            &["line 2", "not a number"],
        ),
    ]
}

#[test]
fn each_broken_file_gets_a_clear_message_and_status_1() {
    let dir = temp_dir();
    for (name, bytes, words) in broken_inputs() {
        fs::write(dir.path().join(name), &bytes).expect("write");
        let output = ridgeline(&[name, "-o", "out.svg"], dir.path());
        let err = stderr(&output);
        assert_eq!(output.status.code(), Some(1), "{name}: {err}");
        assert!(err.starts_with("error: "), "{name}: {err}");
        assert!(err.contains(name), "{name} is not named: {err}");
        for word in words {
            assert!(err.contains(word), "{name}: {word:?} missing from {err}");
        }
        assert_no_panic(&err);
        assert!(output.stdout.is_empty(), "{name}: something on stdout");
        assert!(
            !dir.path().join("out.svg").exists(),
            "{name}: output written"
        );
    }
}

#[test]
fn missing_files_and_empty_directories_fail_by_name() {
    let dir = temp_dir();
    fs::create_dir(dir.path().join("nothing")).expect("mkdir");
    fs::create_dir(dir.path().join("nothing/deeper")).expect("mkdir");
    fs::write(dir.path().join("nothing/deeper/notes.md"), b"text").expect("write");
    let output = ridgeline(&["no-such-scan.png"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    assert!(
        err.contains("no-such-scan.png") && err.contains("No such file"),
        "{err}"
    );
    assert_no_panic(&err);

    let output = ridgeline(&["nothing"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    assert!(err.contains("nothing") && err.contains("no image"), "{err}");
    assert_no_panic(&err);
    // Nothing was created next to the inputs.
    assert_eq!(entries(dir.path()).len(), 1, "{:?}", entries(dir.path()));
}

#[test]
fn a_batch_of_broken_files_names_each_and_traces_the_good_one() {
    let dir = temp_dir();
    let scans = dir.path().join("scans");
    fs::create_dir(&scans).expect("mkdir");
    let cases = broken_inputs();
    let mut args = Vec::new();
    for (name, bytes, _) in &cases {
        fs::write(scans.join(name), bytes).expect("write");
        args.push(format!("scans/{name}"));
    }
    strokes_gray(64, 48)
        .save(scans.join("good.png"))
        .expect("png");
    args.push("scans/good.png".into());
    args.extend(["-o", "out/", "--jobs", "2"].map(String::from));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let output = ridgeline(&args, dir.path());
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(
        err.contains(&format!(
            "{} of {} inputs failed",
            cases.len(),
            cases.len() + 1
        )),
        "{err}"
    );
    for (name, _, words) in &cases {
        let line = err
            .lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("{name} not named: {err}"));
        for word in *words {
            assert!(line.contains(word), "{name}: {word:?} missing from {line}");
        }
    }
    assert_no_panic(&err);
    let written: Vec<_> = entries(&dir.path().join("out"))
        .into_iter()
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    assert_eq!(written, ["good.svg"]);
}

#[test]
fn broken_bytes_give_errors_from_the_library() {
    let limits = Limits::default();
    for (name, bytes, _) in broken_inputs() {
        if name.ends_with(".txt") || name.ends_with(".xy") || name.ends_with(".csv") {
            assert!(
                matches!(
                    ridgeline::point_list::parse(&String::from_utf8_lossy(&bytes)),
                    Err(Error::PointParse { .. })
                ),
                "{name}"
            );
        } else if name.ends_with(".pts") {
            assert!(ridgeline::point_list::parse(&String::from_utf8_lossy(&bytes)).is_err());
        } else {
            match ridgeline::decode(&bytes, &limits) {
                Err(Error::Decode(_)) | Err(Error::Limit { .. }) => {}
                other => panic!("{name}: expected a decode or limit error, got {other:?}"),
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Limits

#[test]
fn the_bomb_is_refused_before_allocating_and_a_raised_limit_still_refuses_bad_data() {
    let limits = Limits::default();
    match ridgeline::decode(&bomb_png(), &limits) {
        Err(err @ Error::Limit { .. }) => {
            // The library names the field; the command line names its flag (below).
            assert!(
                err.to_string()
                    .ends_with("raise limits.max_pixels if the input is trusted"),
                "{err}"
            );
            let Error::Limit { field, actual, .. } = err else {
                unreachable!()
            };
            assert_eq!(field, "limits.max_pixels");
            assert_eq!(actual, 100_000u64 * 100_000);
        }
        other => panic!("expected a limit error, got {other:?}"),
    }
    // Trusting the input (limits raised) must not make the 64 bytes of IDAT a 10 GB image: the
    // side limit still refuses it, and within it the missing data is a decode error.
    let mut raised = Limits::default();
    raised.max_pixels = u64::MAX;
    match ridgeline::decode(&bomb_png(), &raised) {
        Err(Error::Limit { field, .. }) => assert_eq!(field, "limits.max_side"),
        other => panic!("expected the side limit, got {other:?}"),
    }
    // Within the side limit but over the pixel limit.
    let mut tight = Limits::default();
    tight.max_pixels = 1000;
    let mid = hand_png(40_000, 40_000, [8, 0, 0, 0, 0], &[], &[0; 64]);
    assert!(matches!(
        ridgeline::decode(&mid, &tight),
        Err(Error::Limit { .. })
    ));
    // Within every limit: the tiny IDAT is simply not enough data.
    let small = hand_png(100, 100, [8, 0, 0, 0, 0], &[], &[0; 64]);
    assert!(matches!(
        ridgeline::decode(&small, &limits),
        Err(Error::Decode(_))
    ));
}

#[test]
fn palette_transparency_and_one_bit_pngs_decode_to_paper_and_ink() {
    // 2x1 palette image: entry 0 opaque black, entry 1 fully transparent red.
    let palette = hand_png(
        2,
        1,
        [8, 3, 0, 0, 0],
        &[(b"PLTE", &[0, 0, 0, 255, 0, 0]), (b"tRNS", &[255, 0])],
        &[0, 0, 1],
    );
    let gray = ridgeline::decode(&palette, &Limits::default()).expect("decodes");
    assert_eq!(
        gray.as_raw(),
        &vec![0, 255],
        "a transparent pixel reads as white paper"
    );
    // 8x1 pixels 10110000, bit depth 1, color type 0.
    let one_bit = hand_png(8, 1, [1, 0, 0, 0, 0], &[], &[0, 0b1011_0000]);
    let gray = ridgeline::decode(&one_bit, &Limits::default()).expect("decodes");
    assert_eq!(gray.as_raw(), &vec![255, 0, 255, 255, 0, 0, 0, 0]);
}

#[test]
fn hand_made_chunks_carry_the_png_crc() {
    // The PNG spec's CRC of "IEND" is AE 42 60 82.
    assert_eq!(crc32(b"IEND"), 0xAE42_6082);
}

#[test]
fn limit_flags_are_obeyed_with_a_clear_message() {
    let dir = temp_dir();
    strokes_gray(80, 60)
        .save(dir.path().join("page.png"))
        .expect("png");
    for (flag, value, words) in [
        (
            "--max-pixels",
            "1000",
            &["image pixels: 4800, over the limit of 1000", "--max-pixels"][..],
        ),
        (
            "--max-side",
            "64",
            &["image side: 80, over the limit of 64", "--max-side"],
        ),
        (
            "--max-points",
            "50",
            &[
                "foreground points: ",
                ", over the limit of 50",
                "--max-points",
            ],
        ),
    ] {
        let output = ridgeline(&["page.png", flag, value], dir.path());
        let err = stderr(&output);
        assert_eq!(output.status.code(), Some(1), "{flag}: {err}");
        for word in words {
            assert!(err.contains(word), "{flag}: {word:?} missing from {err}");
        }
        assert!(!dir.path().join("page.svg").exists());
    }
    fs::write(dir.path().join("many.xy"), "0 0\n1 0\n2 0\n3 0\n").expect("write");
    let output = ridgeline(&["many.xy", "--max-points", "3"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("--max-points"),
        "{}",
        stderr(&output)
    );
}

// ---------------------------------------------------------------------------------------------
// Degenerate but valid images: traced or warned about, status 0

#[test]
fn uniform_and_one_pixel_images_are_blank_pages() {
    let dir = temp_dir();
    let cases = [
        ("black.png", GrayImage::from_pixel(50, 40, Luma([0]))),
        ("white.png", GrayImage::from_pixel(50, 40, Luma([255]))),
        ("dot.png", GrayImage::from_pixel(1, 1, Luma([0]))),
    ];
    for (name, image) in &cases {
        image.save(dir.path().join(name)).expect("png");
        let output = ridgeline(&[name, "-f", "json", "-o", "-"], dir.path());
        let err = stderr(&output);
        assert!(output.status.success(), "{name}: {err}");
        assert!(
            err.contains("warning") && err.contains("blank page"),
            "{name}: {err}"
        );
        let value: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
        assert_eq!(value["stats"]["edges"], 0, "{name}");
        assert_eq!(value["stats"]["vertices"], 0, "{name}");
    }
}

#[test]
fn an_all_foreground_image_with_forced_polarity_is_traced() {
    let dir = temp_dir();
    // A uniform image has no threshold: even with the polarity forced it is a blank page.
    GrayImage::from_pixel(60, 40, Luma([0]))
        .save(dir.path().join("black.png"))
        .expect("png");
    let output = ridgeline(&["black.png", "--polarity", "dark", "-o", "-"], dir.path());
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("blank page"),
        "{}",
        stderr(&output)
    );
    // Ink everywhere but a 1-px paper frame: the block is traced.
    let framed = GrayImage::from_fn(60, 40, |x, y| {
        Luma([if x == 0 || y == 0 || x == 59 || y == 39 {
            255
        } else {
            0
        }])
    });
    framed.save(dir.path().join("ink.png")).expect("png");
    let output = ridgeline(
        &["ink.png", "--polarity", "dark", "-f", "json", "-o", "-"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let value: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    let vertices = value["vertices"].as_array().expect("vertices");
    assert!(!vertices.is_empty(), "a solid block is not nothing");
    for v in vertices {
        let (x, y) = (v["x"].as_f64().expect("x"), v["y"].as_f64().expect("y"));
        assert!(
            (0.0..=60.0).contains(&x) && (0.0..=40.0).contains(&y),
            "{v}"
        );
    }

    // The library on a whole-image mask, and on a 1x1 one.
    let mut full = Binary::new(60, 40);
    full.ink.fill(true);
    let graph = trace_ok(&full);
    assert!(!graph.vertices.is_empty());
    let mut one = Binary::new(1, 1);
    one.ink[0] = true;
    let graph = trace_ok(&one);
    assert!(graph.edges.is_empty());
    assert!(graph.vertices.len() <= 1);
}

#[test]
fn a_one_pixel_wide_strip_of_100000_pixels() {
    // The library on the mask: one straight stroke, one edge end to end.
    for (w, h) in [(1u32, 100_000u32), (100_000, 1)] {
        let mut strip = Binary::new(w, h);
        strip.ink.fill(true);
        let graph = trace_ok(&strip);
        let longest = graph.edges.iter().map(|e| e.length()).fold(0.0, f64::max);
        let total: f64 = graph.edges.iter().map(|e| e.length()).sum();
        assert!(longest > 90_000.0, "{w}x{h}: longest edge {longest}");
        assert!(total < 100_500.0, "{w}x{h}: total length {total}");
        for v in &graph.vertices {
            let across = if w == 1 { v.pos[0] } else { v.pos[1] };
            assert!((0.0..=1.0).contains(&across), "{w}x{h}: {:?}", v.pos);
        }
    }
    // The binary: over the default side limit (65 535) the file is refused by name; raising the
    // limit traces it.
    let dir = temp_dir();
    let mut gray = GrayImage::from_pixel(1, 100_000, Luma([235]));
    for y in 1_000..99_000 {
        gray.put_pixel(0, y, Luma([10]));
    }
    gray.save(dir.path().join("strip.png")).expect("png");
    let output = ridgeline(&["strip.png"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("--max-side"),
        "{}",
        stderr(&output)
    );
    let output = ridgeline(
        &["strip.png", "--max-side", "100000", "-f", "json", "-o", "-"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let value: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert!(
        value["stats"]["edges"].as_u64().unwrap_or(0) >= 1,
        "{}",
        value["stats"]
    );
}

#[test]
fn sixteen_bit_and_palette_images_trace_like_the_8_bit_one() {
    let dir = temp_dir();
    let gray = strokes_gray(80, 60);
    gray.save(dir.path().join("eight.png")).expect("png");
    fs::write(dir.path().join("sixteen.png"), png16(&gray)).expect("write");
    fs::write(dir.path().join("palette.png"), palette_png(&gray)).expect("write");
    let graph_of = |name: &str| {
        let output = ridgeline(&[name, "-f", "json", "-o", "-"], dir.path());
        assert!(output.status.success(), "{name}: {}", stderr(&output));
        let value: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
        (value["vertices"].clone(), value["edges"].clone())
    };
    let eight = graph_of("eight.png");
    assert!(
        eight.1.as_array().is_some_and(|e| e.len() >= 3),
        "{:?}",
        eight.1
    );
    assert_eq!(graph_of("sixteen.png"), eight);
    assert_eq!(graph_of("palette.png"), eight);
}

// ---------------------------------------------------------------------------------------------
// Point lists

fn trace_list(list: &[[f64; 2]]) -> StrokeGraph {
    let trace = trace_points(list, &Params::default()).expect("trace succeeds");
    trace.graph.validate().expect("valid stroke graph");
    trace.graph
}

#[test]
fn non_finite_points_are_refused_by_the_library_too() {
    for bad in [
        [f64::NAN, 1.0],
        [1.0, f64::INFINITY],
        [f64::NEG_INFINITY, 0.0],
    ] {
        let list = [[0.0, 0.0], [1.0, 0.0], bad, [3.0, 0.0]];
        match trace_points(&list, &Params::default()) {
            Err(Error::PointParse { line, .. }) => assert_eq!(line, 3),
            other => panic!("{bad:?}: expected a point error, got {other:?}"),
        }
    }
    // Finite but absurd: coordinates whose extent overflows squared distances.
    let far = [[-1e300, 0.0], [1e300, 0.0], [0.0, 0.0]];
    assert!(matches!(
        trace_points(&far, &Params::default()),
        Err(Error::InvalidParams(_))
    ));
}

#[test]
fn empty_and_tiny_point_lists() {
    let empty = trace_list(&[]);
    assert!(empty.vertices.is_empty() && empty.edges.is_empty());
    let one = trace_list(&[[3.0, 4.0]]);
    assert_eq!(one.vertices.len(), 1);
    assert!(one.edges.is_empty());
    assert!(ridgeline::dist(one.vertices[0].pos, [3.0, 4.0]) < 1e-9);
    let two = trace_list(&[[0.0, 0.0], [4.0, 0.0]]);
    assert_eq!(two.components(), 1, "{two:?}");
    for v in &two.vertices {
        assert!(
            (-0.01..=4.01).contains(&v.pos[0]) && v.pos[1].abs() < 1e-6,
            "{v:?}"
        );
    }

    // The binary: an empty or header-only list is an error (no empty drawing written); 1 and 2
    // points trace.
    let dir = temp_dir();
    for (name, text) in [
        ("empty.xy", ""),
        ("header.csv", "x,y\n"),
        ("comments.txt", "# nothing yet\n\n"),
        ("one.xy", "3 4\n"),
        ("two.xy", "0 0\n4 0\n"),
    ] {
        fs::write(dir.path().join(name), text).expect("write");
        let output = ridgeline(&[name, "-f", "json", "-o", "-"], dir.path());
        let err = stderr(&output);
        if text.contains(|c: char| c.is_ascii_digit()) {
            assert!(output.status.success(), "{name}: {err}");
            let value: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
            assert_eq!(value["stats"]["components"], 1, "{name}");
        } else {
            assert_eq!(output.status.code(), Some(1), "{name}: {err}");
            assert!(
                err.starts_with("error: ") && err.contains(name) && err.contains("no points"),
                "{name}: {err}"
            );
            assert!(output.stdout.is_empty(), "{name}: nothing written");
        }
    }
    // In a batch, the same file fails and the others are written.
    let output = ridgeline(&["header.csv", "one.xy", "-o", "out/"], dir.path());
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).contains("header.csv: the point list has no points"));
    assert_eq!(
        entries(&dir.path().join("out")),
        [dir.path().join("out/one.svg")]
    );
}

#[test]
fn duplicate_points_change_nothing() {
    let line: Vec<[f64; 2]> = (0..80).map(|i| [i as f64, 10.0 + 0.3 * i as f64]).collect();
    let mut repeated = Vec::new();
    for (i, p) in line.iter().enumerate() {
        repeated.push(*p);
        for _ in 0..(i % 4) {
            repeated.push(*p);
        }
    }
    repeated.extend_from_slice(&line);
    assert_eq!(trace_list(&repeated), trace_list(&line));
    // All points the same: one lone vertex, not a crash.
    let same = vec![[5.0, 5.0]; 50];
    let graph = trace_list(&same);
    assert_eq!(graph.vertices.len(), 1);
    assert!(graph.edges.is_empty());
}

#[test]
fn collinear_points_give_one_stroke_on_the_line() {
    for (name, list) in [
        (
            "diagonal",
            (0..200)
                .map(|i| [i as f64 * 0.5, 3.0 + i as f64 * 0.25])
                .collect::<Vec<_>>(),
        ),
        ("vertical", (0..200).map(|i| [7.0, i as f64]).collect()),
        ("horizontal", (0..200).map(|i| [i as f64, 7.0]).collect()),
    ] {
        let graph = trace_list(&list);
        assert_eq!(graph.components(), 1, "{name}: {graph:?}");
        assert!(
            graph.junctions().next().is_none(),
            "{name}: a junction on a line"
        );
        let total: f64 = graph.edges.iter().map(|e| e.length()).sum();
        let span = ridgeline::dist(list[0], list[list.len() - 1]);
        assert!(
            total > 0.8 * span && total < 1.1 * span,
            "{name}: {total} vs {span}"
        );
        // Every output point lies on the line through the input.
        let (a, b) = (list[0], list[list.len() - 1]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = d[0].hypot(d[1]);
        for e in &graph.edges {
            for p in &e.points {
                let off = ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]).abs() / len;
                assert!(off < 0.5, "{name}: {p:?} is {off} off the line");
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Output safety

#[test]
fn failed_runs_never_touch_existing_outputs() {
    let dir = temp_dir();
    let scans = dir.path().join("scans");
    let out = dir.path().join("out");
    fs::create_dir(&scans).expect("mkdir");
    fs::create_dir(&out).expect("mkdir");
    strokes_gray(64, 48).save(scans.join("a.png")).expect("png");
    let png = encode(&strokes_gray(64, 48), ImageFormat::Png);
    fs::write(scans.join("b.png"), &png[..png.len() - 40]).expect("write");
    fs::write(out.join("a.svg"), b"old a").expect("write");
    fs::write(out.join("b.svg"), b"old b").expect("write");
    let output = ridgeline(&["scans", "-o", "out"], dir.path());
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    // The good input replaced its output; the bad one left its old output exactly as it was.
    assert!(fs::read_to_string(out.join("a.svg"))
        .expect("a")
        .starts_with("<svg"));
    assert_eq!(fs::read(out.join("b.svg")).expect("b"), b"old b");
    assert_eq!(
        entries(&out).len(),
        2,
        "no temporary file left: {:?}",
        entries(&out)
    );

    // A failed run to stdout writes nothing there.
    let output = ridgeline(&["scans/b.png", "-o", "-"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(output.stdout.is_empty());

    // An output that cannot be created (its folder is a file): a message, the input untouched.
    fs::write(dir.path().join("blocker"), b"a file").expect("write");
    let output = ridgeline(&["scans/a.png", "-o", "blocker/a.svg"], dir.path());
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(err.contains("blocker"), "{err}");
    assert_no_panic(&err);
    assert_eq!(
        fs::read(dir.path().join("blocker")).expect("read"),
        b"a file"
    );
}

#[test]
fn dash_writes_the_same_bytes_as_a_file() {
    let dir = temp_dir();
    strokes_gray(64, 48)
        .save(dir.path().join("page.png"))
        .expect("png");
    for format in ["svg", "json"] {
        let output = ridgeline(&["page.png", "-f", format, "-o", "-"], dir.path());
        assert!(output.status.success(), "{}", stderr(&output));
        let file = format!("page.{format}");
        let written = ridgeline(&["page.png", "-f", format, "-o", &file], dir.path());
        assert!(written.status.success(), "{}", stderr(&written));
        assert!(written.stdout.is_empty());
        assert_eq!(
            output.stdout,
            fs::read(dir.path().join(&file)).expect("read"),
            "{format}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Determinism

/// A page with more ink than one parallel chunk (65 536 points), so the library's own
/// parallel path runs: strokes of many widths and crossings.
fn busy_page() -> GrayImage {
    let mut strokes = Vec::new();
    for i in 0..14 {
        let y = 20.0 + i as f64 * 33.0;
        let width = 3.0 + (i % 5) as f64 * 2.0;
        strokes.push(Stroke::new(
            vec![[15.0, y], [250.0, y + 9.0], [470.0, y - 6.0]],
            width,
        ));
        let x = 25.0 + i as f64 * 32.0;
        strokes.push(Stroke::new(vec![[x, 10.0], [x + 12.0, 470.0]], width + 1.0));
    }
    mask_image(&render(&strokes, 490, 490))
}

#[test]
fn output_is_byte_identical_across_runs_and_thread_counts() {
    let dir = temp_dir();
    let page = busy_page();
    let ink = page.pixels().filter(|p| p.0[0] < 128).count();
    assert!(
        ink > 65_536,
        "the page must exercise the parallel path: {ink} ink pixels"
    );
    page.save(dir.path().join("page.png")).expect("png");
    for format in ["svg", "json"] {
        let run = |jobs: &str| {
            let output = ridgeline(
                &["page.png", "-f", format, "-o", "-", "--jobs", jobs],
                dir.path(),
            );
            assert!(output.status.success(), "{}", stderr(&output));
            output.stdout
        };
        let first = run("1");
        assert_eq!(run("2"), first, "{format}: --jobs 1 vs 2");
        assert_eq!(run("2"), first, "{format}: a second run");
    }
    // And the library, called twice in one process.
    let params = Params::default();
    let a = trace_image(&page, &params).expect("trace");
    let b = trace_image(&page, &params).expect("trace");
    assert_eq!(a.graph, b.graph);
    a.graph.validate().expect("valid");
}

// ---------------------------------------------------------------------------------------------
// Fuzzing regressions: every input the fuzzers (fuzz/) found a crash, hang or memory blow-up
// with, replayed through the same code as the fuzz targets. Each must finish quickly with an
// error or a valid graph.

fn regressions(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = crate::support::repository_root()
        .join("tests/fuzz_regressions")
        .join(target);
    let mut files: Vec<(PathBuf, Vec<u8>)> = entries(&dir)
        .into_iter()
        .map(|p| {
            let bytes = fs::read(&p).expect("read regression input");
            (p, bytes)
        })
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "no regression inputs in {}",
        dir.display()
    );
    files
}

#[test]
fn fuzz_regressions_decode_and_trace() {
    // fuzz/fuzz_targets/decode_trace.rs
    let mut limits = Limits::default();
    limits.max_pixels = 256 * 256;
    limits.max_side = 256;
    limits.max_points = 256 * 256;
    limits.max_pages = 4;
    for (path, bytes) in regressions("decode_trace") {
        let Ok(pages) = ridgeline::raster::pages(&bytes, &limits) else {
            continue;
        };
        for page in pages.with_pictures(true) {
            let Ok(page) = page else {
                continue;
            };
            if page.number == 1 {
                let first = ridgeline::decode(&bytes, &limits).ok();
                assert_eq!(first.as_ref(), Some(&page.gray), "{path:?}: decode differs");
            }
            for params in [Params::default(), Params::paper()] {
                let mut params = params;
                params.front_end.limits = limits;
                if let Ok(trace) = trace_image(&page.gray, &params) {
                    trace
                        .graph
                        .validate()
                        .unwrap_or_else(|e| panic!("{path:?}: {e}"));
                }
            }
        }
    }
}

#[test]
fn fuzz_regressions_point_sets() {
    // fuzz/fuzz_targets/trace_points.rs
    for (path, bytes) in regressions("trace_points") {
        let Some((list, params)) = point_bytes::points_and_params(&bytes) else {
            continue;
        };
        let start = std::time::Instant::now();
        if let Ok(trace) = trace_points(&list, &params) {
            trace
                .graph
                .validate()
                .unwrap_or_else(|e| panic!("{path:?}: {e}"));
        }
        // The blow-ups took 18 s and gigabytes; a generous bound for slow debug builds.
        assert!(
            start.elapsed().as_secs() < 10,
            "{path:?} took {:?}",
            start.elapsed()
        );
    }
}

#[test]
fn point_lists_trace_the_same_in_any_unit() {
    // Found by fuzzing: lists in units far from pixels (1e87, 1e-150) asked for 51 GB or gave
    // infinite widths. They run in pixel-like units now, so scaling by a power of two scales the
    // graph exactly.
    let list: Vec<[f64; 2]> = (0..60)
        .map(|i| [i as f64 * 0.5, 10.0 + 0.2 * i as f64])
        .chain((0..40).map(|i| [10.0 + 0.1 * i as f64, 25.0 - 0.5 * i as f64]))
        .collect();
    let base = trace_list(&list);
    assert!(!base.edges.is_empty());
    for power in [-500, -40, 40, 280] {
        let scale = 2f64.powi(power);
        let scaled: Vec<[f64; 2]> = list.iter().map(|p| [p[0] * scale, p[1] * scale]).collect();
        let graph = trace_points(&scaled, &Params::default())
            .expect("trace")
            .graph;
        graph.validate().expect("valid");
        assert_eq!(graph.vertices.len(), base.vertices.len(), "2^{power}");
        assert_eq!(graph.edges.len(), base.edges.len(), "2^{power}");
        for (v, w) in graph.vertices.iter().zip(&base.vertices) {
            let back = [v.pos[0] / scale, v.pos[1] / scale];
            assert!(
                ridgeline::dist(back, w.pos) < 1e-6,
                "2^{power}: {back:?} vs {:?}",
                w.pos
            );
            assert!((v.width / scale - w.width).abs() < 1e-4, "2^{power}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Values a user can build: the public data types' checks and helpers never panic on them

/// A '+' of two 5 px strokes on a 40 px square.
fn small_plus() -> Binary {
    render(
        &[
            Stroke::new(vec![[5.0, 20.0], [35.0, 20.0]], 5.0),
            Stroke::new(vec![[20.0, 5.0], [20.0, 35.0]], 5.0),
        ],
        40,
        40,
    )
}

/// The point set of [`small_plus`] from the raster stage (valid to start from).
fn plus_points() -> ridgeline::PointSet {
    let points = ridgeline::raster::points(&small_plus(), &Params::default()).expect("points");
    points.validate().expect("the raster's point set is valid");
    points
}

/// Each broken invariant of a point set is reported by `PointSet::validate`, which formerly
/// panicked on some of them itself (offsets beyond the neighbour list), and that the stages
/// (crate-private now: sampling read out-of-range neighbours, the skeleton an index beyond its
/// window) could only have met by panicking.
#[test]
fn broken_point_sets_are_reported_not_panicked_on() {
    let good = plus_points();
    let n = good.len();
    let mut cases: Vec<(&str, ridgeline::PointSet)> = Vec::new();
    let mut out_of_range = good.clone();
    out_of_range.neighbors[0] = n as u32 + 7;
    cases.push(("neighbour out of range", out_of_range));
    let mut self_loop = good.clone();
    self_loop.neighbors[0] = 0;
    cases.push(("self-loop", self_loop));
    let mut beyond = good.clone();
    beyond.offsets[n] = u32::MAX;
    cases.push(("offsets beyond the neighbours", beyond));
    let mut falling = good.clone();
    falling.offsets[1] = falling.offsets[2] + 1;
    cases.push(("falling offsets", falling));
    let mut short = good.clone();
    short.offsets.pop();
    cases.push(("offsets missing", short));
    let mut nan = good.clone();
    nan.half_width[3] = f32::NAN;
    cases.push(("NaN half-width", nan));
    let mut spacing = good.clone();
    spacing.spacing = 0.0;
    cases.push(("zero spacing", spacing));
    let mut far = good.clone();
    far.points[5][0] = f64::INFINITY;
    cases.push(("infinite point", far));
    let mut moved = good.clone();
    moved.points[5][0] += 1.0;
    cases.push(("point off its grid pixel", moved));
    let mut small = good.clone();
    small.grid.as_mut().expect("grid").index.truncate(10);
    cases.push(("grid index shorter than its window", small));
    let mut wrong = good.clone();
    let grid = wrong.grid.as_mut().expect("grid");
    let ink = grid.index.iter().position(|&i| i != ridgeline::Grid::NONE);
    grid.index[ink.expect("ink")] = n as u32 + 1;
    cases.push(("grid indexes a missing point", wrong));
    for (what, set) in cases {
        assert!(set.validate().is_err(), "{what} passed validation");
        // The accessors stay total on the same values.
        for i in [0, 1, n as u32 - 1, n as u32, u32::MAX] {
            let _ = set.neighbors_of(i);
        }
    }
}

/// `Grid::point_at` and `PointSet::neighbors_of` answer "nothing" for what is not there, however
/// the public fields were filled (both formerly indexed past the end).
#[test]
fn grid_and_neighbour_lookups_are_total() {
    let mut set = plus_points();
    let grid = set.grid.as_mut().expect("grid");
    assert!(grid.point_at(20, 20).is_some());
    grid.index.truncate(3);
    assert_eq!(grid.point_at(20, 20), None);
    assert_eq!(grid.point_at(i64::MIN, i64::MAX), None);
    grid.x0 = i64::MIN;
    assert_eq!(grid.point_at(i64::MAX, 0), None);
    set.offsets = vec![5, 2, u32::MAX];
    assert!(set.neighbors_of(0).is_empty() && set.neighbors_of(1).is_empty());
}

/// `ridgeline::thin` (the thinning baseline's public entry; its stage functions `zhang_suen` and
/// `pixel_graph` were public and indexed a short mask past its end) refuses a mask whose pixels do
/// not fill its size, and thins an empty one to nothing.
#[test]
fn thinning_refuses_a_mask_of_the_wrong_size() {
    let short = Binary {
        width: 30,
        height: 30,
        ink: vec![true; 100],
    };
    match ridgeline::thin(&short) {
        Err(Error::InvalidParams(message)) => assert!(message.contains("100 pixels"), "{message}"),
        other => panic!("expected an error, got {other:?}"),
    }
    for (w, h) in [(0, 0), (0, 5), (7, 0)] {
        let empty = ridgeline::thin(&Binary::new(w, h)).expect("empty mask");
        assert!(empty.vertices.is_empty() && empty.edges.is_empty());
    }
    let bar = render(&[Stroke::new(vec![[5.0, 10.0], [45.0, 10.0]], 5.0)], 50, 20);
    let graph = ridgeline::thin(&bar).expect("thinned");
    graph.validate().expect("a valid stroke graph");
    assert_eq!(graph.endpoints().count(), 2);
}

/// The node graphs and samples a user can put into `Stages` (for the debug pictures) are checked
/// by their `validate`, and the pictures of out-of-range ones draw what exists.
#[test]
fn broken_stages_are_reported_and_drawn_without_panicking() {
    let plus = small_plus();
    let trace = ridgeline::trace_binary_with_stages(&plus, &Params::default()).expect("trace");
    let mut stages = trace.stages.expect("stages kept");
    let n = stages.points.len();
    stages.node_graph.edges.push([0, 9_999]);
    stages.refined.edges.push([9_998, 9_999]);
    stages.refined.owner[0] = 9_999;
    stages.samples.owner[0] = 9_999;
    stages.points.neighbors[0] = u32::MAX - 1;
    assert!(stages.node_graph.validate(n).is_err());
    assert!(stages.refined.validate(n).is_err());
    assert!(stages.samples.validate(n).is_err());
    assert!(stages.points.validate().is_err());
    let pictures = ridgeline::debug::stage_pictures(&plus, &stages, &trace.graph);
    assert_eq!(pictures.len(), ridgeline::debug::PICTURE_NAMES.len());
}
