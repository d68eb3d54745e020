//! Pages: text with what real pages hold besides strokes (a halftone photo, a scanner's dark
//! frame, the thin edges of a bound book's pages around a 1-bit scan, a dark field beyond a torn
//! page edge, a textured background, show-through from the back
//! of the sheet, a photograph's uneven light), and a page of rules and a table grid, whose lines
//! are content. The truth is the text's strokes (and the rules and grid lines where they are
//! content); the case's binary is those strokes alone, so the quality example's `clean` row is the
//! same text traced on a clean page, and its off-ink share is the traced length outside the text.
//!
//! Everything is seeded: the same call gives the same pixels.

use image::{GrayImage, Luma};

use super::hershey::{Font, CAP_HEIGHT};
use super::{degrade, render, Case, Degraded, Recipe, SplitMix64, Stroke};

/// The page cases, by name, in order.
pub const PAGE_CASES: [&str; 9] = [
    "page_clean",
    "page_halftone",
    "page_frame",
    "page_rules",
    "page_grille",
    "page_show_through",
    "page_edge",
    "page_photographed",
    "page_book_edges",
];

/// Page size, px.
const WIDTH: u32 = 480;
/// See [`WIDTH`].
const HEIGHT: u32 = 360;
/// Capital height of the text, px.
const CAP: f64 = 16.0;
/// Stroke width of the text, px.
const STROKE: f64 = 2.5;
/// Baseline to baseline, px.
const PITCH: f64 = 30.0;
/// Paper and ink gray levels.
const PAPER: u8 = 232;
/// See [`PAPER`].
const INK: u8 = 30;

const WORDS: [&str; 16] = [
    "the", "quick", "brown", "fox", "jumps", "over", "lazy", "dog", "pack", "my", "box", "with",
    "five", "dozen", "liquor", "jugs",
];

/// The pages group: each case of [`PAGE_CASES`] as a gray capture (group `pages`) with its truth.
pub fn page_cases() -> Vec<Degraded> {
    PAGE_CASES
        .iter()
        .enumerate()
        .map(|(i, &name)| page_case(name, 0x9A6E ^ (i as u64 + 1).wrapping_mul(0x9E37_79B9)))
        .collect()
}

/// Lines of words filling `[x0, x1] x [y0, y1]`, drawn from `rng`.
fn text_block(rng: &mut SplitMix64, x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Stroke> {
    let font = Font::futural();
    let scale = CAP / CAP_HEIGHT;
    let mut strokes = Vec::new();
    let mut baseline = y0 + CAP;
    while baseline + 0.5 * CAP <= y1 {
        let mut text = String::new();
        loop {
            let word = WORDS[rng.below(WORDS.len())];
            let candidate = if text.is_empty() {
                word.to_string()
            } else {
                format!("{text} {word}")
            };
            if x0 + font.advance(&candidate) * scale > x1 {
                break;
            }
            text = candidate;
        }
        let (line, _) = font.line(&text, x0, baseline, scale, STROKE);
        strokes.extend(line);
        baseline += PITCH;
    }
    strokes
}

/// The gray page of `ink` on paper, with `paint` then drawing over each pixel (given its gray
/// and position, returning the new gray).
fn page_gray(ink: &ridgeline::Binary, paint: impl Fn(u32, u32, u8) -> u8) -> GrayImage {
    GrayImage::from_fn(WIDTH, HEIGHT, |x, y| {
        let base = if ink.ink[(y * WIDTH + x) as usize] {
            INK
        } else {
            PAPER
        };
        Luma([paint(x, y, base)])
    })
}

/// A scan's light blur and noise.
fn scanned(gray: GrayImage, rng: &mut SplitMix64) -> GrayImage {
    let mut out = imageproc::filter::gaussian_blur_f32(&gray, 0.6);
    for p in out.pixels_mut() {
        let noise = (rng.next_f64() - 0.5) * 6.0;
        p.0[0] = (f64::from(p.0[0]) + noise).round().clamp(0.0, 255.0) as u8;
    }
    out
}

fn page_case(name: &str, seed: u64) -> Degraded {
    let mut rng = SplitMix64::new(seed);
    let (w, h) = (f64::from(WIDTH), f64::from(HEIGHT));
    let mut recipe = Recipe {
        inverted: false,
        paper: PAPER,
        ink: INK,
        blur: 0.6,
        falloff: 0.0,
        light_angle: 0.0,
        noise: 1.7,
        jpeg_quality: 100,
    };
    let (strokes, gray) = match name {
        "page_halftone" => {
            // A photo of dots on a 4 px screen, their radius following a smooth scene.
            let strokes = text_block(&mut rng, 24.0, 24.0, 250.0, h - 24.0);
            let binary = render(&strokes, WIDTH, HEIGHT);
            let (px0, py0, px1, py1) = (280.0, 40.0, 450.0, 300.0);
            let gray = page_gray(&binary, |x, y, g| {
                let (fx, fy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                if fx < px0 || fx >= px1 || fy < py0 || fy >= py1 {
                    return g;
                }
                let tone = 0.5 + 0.45 * ((fx / 23.0).sin() * (fy / 31.0).cos());
                let (cx, cy) = (
                    (fx / 4.0).floor() * 4.0 + 2.0,
                    (fy / 4.0).floor() * 4.0 + 2.0,
                );
                let r = 2.3 * tone.sqrt();
                if (fx - cx).hypot(fy - cy) <= r {
                    INK
                } else {
                    PAPER
                }
            });
            (strokes, gray)
        }
        "page_frame" => {
            // A scanner's dark frame, its inner edge wavering.
            let strokes = text_block(&mut rng, 48.0, 44.0, w - 48.0, h - 40.0);
            let binary = render(&strokes, WIDTH, HEIGHT);
            let gray = page_gray(&binary, |x, y, g| {
                let (fx, fy) = (f64::from(x), f64::from(y));
                let band = 16.0 + 3.0 * ((fx + fy) / 37.0).sin();
                let d = fx.min(fy).min(w - 1.0 - fx).min(h - 1.0 - fy);
                if d < band {
                    18
                } else {
                    g
                }
            });
            (strokes, gray)
        }
        "page_book_edges" => {
            // A bound book on a 1-bit scanner: the edge of the page along the top, the edges of
            // the pages under it down the right (a thick line and two thin ones, with specks of
            // dust between them) and along the bottom, apart.
            let strokes = text_block(&mut rng, 40.0, 40.0, w - 70.0, h - 40.0);
            let binary = render(&strokes, WIDTH, HEIGHT);
            let specks: Vec<(u32, u32)> = (0..12)
                .map(|_| (443 + rng.below(3) as u32, 20 + rng.below(320) as u32))
                .collect();
            let gray = page_gray(&binary, |x, y, g| {
                let top = (14..16).contains(&y) && x <= 452;
                let right = matches!(x, 439..=441 | 447 | 452) && (14..=350).contains(&y);
                let bottom = (347..349).contains(&y) && x <= 435;
                let speck = specks
                    .iter()
                    .any(|&(sx, sy)| x == sx && (sy..sy + 2).contains(&y));
                if top || right || bottom || speck {
                    INK
                } else {
                    g
                }
            });
            (strokes, gray)
        }
        "page_rules" => {
            // Rules above and below the text and a table grid: content, in the truth.
            let mut strokes = text_block(&mut rng, 30.0, 30.0, w - 30.0, 150.0);
            for y in [22.0, 160.0] {
                strokes.push(Stroke::new(vec![[24.0, y], [w - 24.0, y]], STROKE));
            }
            let (tx0, ty0, tx1, ty1) = (40.0, 190.0, w - 40.0, 330.0);
            let (cols, rows) = (4, 3);
            for i in 0..=cols {
                let x = tx0 + (tx1 - tx0) * f64::from(i) / f64::from(cols);
                strokes.push(Stroke::new(vec![[x, ty0], [x, ty1]], STROKE));
            }
            for j in 0..=rows {
                let y = ty0 + (ty1 - ty0) * f64::from(j) / f64::from(rows);
                strokes.push(Stroke::new(vec![[tx0, y], [tx1, y]], STROKE));
            }
            let font = Font::futural();
            let scale = CAP / CAP_HEIGHT;
            for j in 0..rows {
                for i in 0..cols {
                    let x = tx0 + (tx1 - tx0) * f64::from(i) / f64::from(cols) + 12.0;
                    let y = ty0 + (ty1 - ty0) * (f64::from(j) + 0.5) / f64::from(rows) + CAP / 2.0;
                    let word = WORDS[rng.below(WORDS.len())];
                    strokes.extend(font.line(word, x, y, scale, STROKE).0);
                }
            }
            let binary = render(&strokes, WIDTH, HEIGHT);
            (strokes, page_gray(&binary, |_, _, g| g))
        }
        "page_grille" => {
            // A grille of thin dark bars beside the text: a textured background.
            let strokes = text_block(&mut rng, 24.0, 24.0, 250.0, h - 24.0);
            let binary = render(&strokes, WIDTH, HEIGHT);
            let gray = page_gray(&binary, |x, y, g| {
                if !(280..460).contains(&x) || !(30..330).contains(&y) {
                    return g;
                }
                if (x + y) % 5 < 2 || (x + 2 * HEIGHT - y) % 7 < 2 {
                    50
                } else {
                    g
                }
            });
            (strokes, gray)
        }
        "page_show_through" => {
            // The back of the sheet's text, mirrored, faint and blurred.
            let strokes = text_block(&mut rng, 30.0, 24.0, w - 30.0, h - 24.0);
            let mut back_rng = SplitMix64::new(seed ^ 0xBAC);
            let back = text_block(&mut back_rng, 30.0, 39.0, w - 30.0, h - 10.0);
            let back = render(&back, WIDTH, HEIGHT);
            let back_gray = GrayImage::from_fn(WIDTH, HEIGHT, |x, y| {
                Luma([if back.ink[(y * WIDTH + WIDTH - 1 - x) as usize] {
                    255
                } else {
                    0
                }])
            });
            let back_gray = imageproc::filter::gaussian_blur_f32(&back_gray, 1.5);
            let binary = render(&strokes, WIDTH, HEIGHT);
            let gray = page_gray(&binary, |x, y, g| {
                let shade = f64::from(back_gray.get_pixel(x, y).0[0]) / 255.0;
                (f64::from(g) - 55.0 * shade).max(f64::from(INK)).round() as u8
            });
            (strokes, gray)
        }
        "page_edge" => {
            // The dark beyond a torn page edge along the right side.
            let strokes = text_block(&mut rng, 24.0, 24.0, 370.0, h - 24.0);
            let binary = render(&strokes, WIDTH, HEIGHT);
            let tears: Vec<f64> = (0..HEIGHT).map(|_| rng.range(-2.0, 2.0)).collect();
            let gray = page_gray(&binary, |x, y, g| {
                let fy = f64::from(y);
                let edge = 405.0 + 8.0 * (fy / 29.0).sin() + tears[y as usize];
                if f64::from(x) >= edge {
                    40
                } else {
                    g
                }
            });
            (strokes, gray)
        }
        "page_photographed" => {
            let strokes = text_block(&mut rng, 30.0, 24.0, w - 30.0, h - 24.0);
            recipe = Recipe {
                inverted: false,
                paper: 225,
                ink: 40,
                blur: 0.8,
                falloff: 0.45,
                light_angle: 0.6,
                noise: 6.0,
                jpeg_quality: 80,
            };
            let gray = degrade(&strokes, WIDTH, HEIGHT, &recipe, &mut rng);
            return with_truth(name, strokes, gray, recipe);
        }
        _ => {
            let strokes = text_block(&mut rng, 30.0, 24.0, w - 30.0, h - 24.0);
            let binary = render(&strokes, WIDTH, HEIGHT);
            (strokes, page_gray(&binary, |_, _, g| g))
        }
    };
    let gray = scanned(gray, &mut rng);
    with_truth(name, strokes, gray, recipe)
}

fn with_truth(name: &str, strokes: Vec<Stroke>, gray: GrayImage, recipe: Recipe) -> Degraded {
    let binary = render(&strokes, WIDTH, HEIGHT);
    Degraded {
        case: Case {
            name: name.to_string(),
            group: "pages".to_string(),
            binary,
            strokes,
        },
        gray,
        recipe,
    }
}
