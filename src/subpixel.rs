//! Centerlines placed below the pixel from the gray levels (docs/design.md, "The front end"): a
//! blurred or anti-aliased stroke's cross-section is a dip in the gray whose middle is the
//! stroke's center, wherever the threshold cut it. Each polyline point of the traced graph moves
//! along its normal to the middle of the dip, the darker-than-halfway part of the cross-section
//! weighted by how much darker it is (lighter, under light ink).
//!
//! Only images with gray levels between their darkest and lightest are refined (a bilevel scan
//! has no sub-pixel information); vertices stay where the pipeline put them, and so do points
//! within a stroke width of a junction or an end, whose cross-sections hold the other arms or
//! the stroke's cap. A point moves at most [`MAX_SHIFT`] px and never off the ink, and an edge
//! never into a crossing or a touch that its path from before did not have.

use rayon::prelude::*;

use crate::binary::Binary;
use crate::geometry::{crossing_paths, dist, floor_f64, floor_i64};
use crate::gray::GrayView;
use crate::stroke_graph::StrokeGraph;

/// The largest move of a point, px: the refinement corrects where the pixel grid put the
/// centerline, it does not re-trace.
pub(crate) const MAX_SHIFT: f64 = 0.75;
/// Step of the cross-section's samples, px.
const STEP: f64 = 0.25;

/// Moves the graph's polyline points to the gray-level middle of their cross-sections (see the
/// module's text). `dark_ink` says which side of the gray is ink; `binary` is the traced ink.
pub(crate) fn center_on_gray(
    graph: &mut StrokeGraph,
    gray: GrayView<'_>,
    binary: &Binary,
    dark_ink: bool,
) {
    if !has_intermediate_levels(gray) {
        return;
    }
    let before: Vec<Vec<[f64; 2]>> = graph.edges.iter().map(|e| e.points.clone()).collect();
    let vertices = &graph.vertices;
    graph.edges.par_iter_mut().for_each(|edge| {
        let n = edge.points.len();
        if n < 3 {
            return;
        }
        let ends = [vertices[edge.from].pos, vertices[edge.to].pos];
        let clear = [vertices[edge.from].width, vertices[edge.to].width];
        let shifts: Vec<f64> = (0..n)
            .map(|i| {
                let p = edge.points[i];
                let near_vertex = i == 0
                    || i == n - 1
                    || (0..2).any(|k| dist(p, ends[k]) < clear[k].max(edge.widths[i]).max(2.0));
                if near_vertex {
                    return 0.0;
                }
                let [dx, dy] = edge.directions[i];
                cross_section_middle(gray, p, [-dy, dx], edge.widths[i] / 2.0, dark_ink)
            })
            .collect();
        // Smoothed along the edge ([1 2 1] / 4): one pixel's noise does not bend the line.
        for i in 1..n - 1 {
            let s = (shifts[i - 1] + 2.0 * shifts[i] + shifts[i + 1]) / 4.0;
            if s == 0.0 || shifts[i] == 0.0 {
                continue;
            }
            let [dx, dy] = edge.directions[i];
            let p = edge.points[i];
            let moved = [p[0] - dy * s, p[1] + dx * s];
            if binary.get(floor_i64(moved[0]), floor_i64(moved[1])) {
                edge.points[i] = moved;
            }
        }
    });
    // An edge moved into a crossing or a touch with another edge, or with itself, takes back
    // its path from before: the refinement places the graph's lines, it does not change what
    // the graph shows. An edge that crossed or touched already before keeps its move.
    let mut moved: Vec<bool> = graph
        .edges
        .iter()
        .zip(&before)
        .map(|(edge, old)| edge.points != *old)
        .collect();
    // Only pairs with a moved edge are tested: an unmoved edge's crossings cannot change.
    let before_paths: Vec<Option<&[[f64; 2]]>> =
        before.iter().map(|p| Some(p.as_slice())).collect();
    let crossed_before = crossing_paths(&before_paths, &moved);
    for &e in &crossed_before {
        moved[e] = false;
    }
    loop {
        let paths: Vec<Option<&[[f64; 2]]>> = graph
            .edges
            .iter()
            .map(|e| Some(e.points.as_slice()))
            .collect();
        let back = crossing_paths(&paths, &moved);
        if back.is_empty() {
            break;
        }
        for e in back {
            graph.edges[e].points.clone_from(&before[e]);
            moved[e] = false;
        }
    }
}

/// Whether some pixel lies strictly between the image's darkest and lightest levels.
fn has_intermediate_levels(gray: GrayView<'_>) -> bool {
    let (lo, hi) = gray
        .par_rows(1 << 16)
        .map(|row| {
            row.iter()
                .fold((u8::MAX, u8::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)))
        })
        .reduce(|| (u8::MAX, u8::MIN), |a, b| (a.0.min(b.0), a.1.max(b.1)));
    lo < hi
        && gray
            .par_rows(1 << 16)
            // Blocks of 64 pixels tested without a branch each (a two-level page has none
            // between, so every pixel is read; block by block the test runs in vector lanes).
            .any(|row| {
                row.chunks(64).any(|block| {
                    block
                        .iter()
                        .fold(false, |between, &v| between | (v != lo) & (v != hi))
                })
            })
}

/// The signed offset along `normal` (unit) from `p` to the middle of the ink's dip in the gray,
/// over a window of the half-width plus 3/4 px each side; 0 when the window shows no dip.
fn cross_section_middle(
    gray: GrayView<'_>,
    p: [f64; 2],
    normal: [f64; 2],
    half_width: f64,
    dark_ink: bool,
) -> f64 {
    let reach = (half_width + 0.75).clamp(1.0, 16.0);
    let steps = (reach / STEP).round() as i64;
    let samples: Vec<(f64, f64)> = (-steps..=steps)
        .map(|k| {
            let t = k as f64 * STEP;
            let v = bilinear(gray, p[0] + t * normal[0], p[1] + t * normal[1]);
            (t, if dark_ink { -v } else { v })
        })
        .collect();
    let (lo, hi) = samples
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &(_, v)| {
            (lo.min(v), hi.max(v))
        });
    if hi - lo < 8.0 {
        return 0.0;
    }
    let half = (lo + hi) / 2.0;
    let (mut moment, mut mass) = (0.0, 0.0);
    for &(t, v) in &samples {
        let w = (v - half).max(0.0);
        moment += t * w;
        mass += w;
    }
    if mass <= 0.0 {
        return 0.0;
    }
    (moment / mass).clamp(-MAX_SHIFT, MAX_SHIFT)
}

/// The gray level at `(x, y)` in image coordinates (pixel `(c, r)` covers `[c, c+1] x [r, r+1]`),
/// interpolated between pixel centers; the border's pixels continue outside.
fn bilinear(gray: GrayView<'_>, x: f64, y: f64) -> f64 {
    let (w, h) = (gray.width() as usize, gray.height() as usize);
    let fx = (x - 0.5).clamp(0.0, (w - 1) as f64);
    let fy = (y - 0.5).clamp(0.0, (h - 1) as f64);
    let (x0, y0) = (floor_f64(fx) as usize, floor_f64(fy) as usize);
    let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
    let (ax, ay) = (fx - x0 as f64, fy - y0 as f64);
    let (r0, r1) = (gray.row(y0), gray.row(y1));
    let top = f64::from(r0[x0]) * (1.0 - ax) + f64::from(r0[x1]) * ax;
    let bottom = f64::from(r1[x0]) * (1.0 - ax) + f64::from(r1[x1]) * ax;
    top * (1.0 - ay) + bottom * ay
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stroke_graph::{Edge, Vertex};
    use image::{GrayImage, Luma};

    #[test]
    fn intermediate_levels_are_found_block_by_block_as_pixel_by_pixel() {
        // Two-level images with none, one or a few pixels between, anywhere in a row (within a
        // block of 64 and in the last, short one), one-level images.
        let mut lcg = crate::synth::lcg(64u64);
        let mut next = move || (lcg() >> 33) as usize;
        for case in 0..200 {
            let (w, h) = (1 + next() % 150, 1 + next() % 6);
            let (lo, hi) = ((next() % 128) as u8, (128 + next() % 128) as u8);
            let mut pixels: Vec<u8> = (0..w * h)
                .map(|_| if next() % 2 == 0 { lo } else { hi })
                .collect();
            if case % 5 == 0 {
                pixels.fill(lo);
            }
            for _ in 0..case % 3 {
                let k = next() % pixels.len();
                pixels[k] = (next() % 256) as u8;
            }
            let view = GrayView::new(&pixels, w as u32, h as u32, w).expect("a view");
            let (min, max) = (
                *pixels.iter().min().expect("pixels"),
                *pixels.iter().max().expect("pixels"),
            );
            let expected = pixels.iter().any(|&v| v != min && v != max);
            assert_eq!(has_intermediate_levels(view), expected, "case {case}");
        }
    }

    /// A horizontal stroke 4 px wide centered at `y = center`, its edges anti-aliased (each
    /// pixel's gray the share of it the stroke covers).
    fn stroke(center: f64) -> (GrayImage, Binary) {
        let (w, h) = (60u32, 20u32);
        let mut binary = Binary::new(w, h);
        let img = GrayImage::from_fn(w, h, |x, y| {
            let (top, bottom) = (center - 2.0, center + 2.0);
            let cover = (f64::from(y + 1).min(bottom) - f64::from(y).max(top)).clamp(0.0, 1.0);
            if cover >= 0.5 {
                binary.ink[(y * w + x) as usize] = true;
            }
            Luma([(230.0 - 200.0 * cover).round() as u8])
        });
        (img, binary)
    }

    fn line_at(y: f64) -> StrokeGraph {
        let points: Vec<[f64; 2]> = (0..=50).map(|i| [5.0 + i as f64, y]).collect();
        let n = points.len();
        StrokeGraph {
            width: 60,
            height: 20,
            vertices: vec![
                Vertex {
                    pos: points[0],
                    degree: 1,
                    width: 4.0,
                },
                Vertex {
                    pos: points[n - 1],
                    degree: 1,
                    width: 4.0,
                },
            ],
            edges: vec![Edge {
                from: 0,
                to: 1,
                widths: vec![4.0; n],
                directions: vec![[1.0, 0.0]; n],
                points,
            }],
        }
    }

    #[test]
    fn a_centerline_a_pixel_grid_put_off_center_moves_to_the_stroke_middle() {
        // The stroke's middle is at y = 10.3; the pixel-grid centerline at 10.0.
        let (img, binary) = stroke(10.3);
        let mut graph = line_at(10.0);
        center_on_gray(&mut graph, (&img).into(), &binary, true);
        let edge = &graph.edges[0];
        let middle = &edge.points[10..40];
        for p in middle {
            assert!((p[1] - 10.3).abs() < 0.08, "{p:?}");
        }
        // The ends and the points within a width of them stay.
        assert_eq!(edge.points[0], [5.0, 10.0]);
        assert_eq!(edge.points[2], [7.0, 10.0]);
    }

    #[test]
    fn a_bilevel_image_is_left_alone() {
        let (_, binary) = stroke(10.0);
        let bilevel = GrayImage::from_fn(60, 20, |x, y| {
            Luma([if binary.get(x as i64, y as i64) {
                0
            } else {
                255
            }])
        });
        let mut graph = line_at(9.6);
        let before = graph.clone();
        center_on_gray(&mut graph, (&bilevel).into(), &binary, true);
        assert_eq!(graph, before);
    }
}
