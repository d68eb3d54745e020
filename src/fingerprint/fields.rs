//! The plain data between the fingerprint stages (docs/fingerprints.md, "Stages"): a grid of
//! square blocks, a floating-point image plane, and one value per block for the segmentation,
//! the orientation field and the ridge period.
//!
//! Coordinates as everywhere in ridgeline: pixel `(c, r)` covers `[c, c+1] x [r, r+1]`; block
//! `(i, j)` covers pixels `i·block .. (i+1)·block` by `j·block .. (j+1)·block` (the last column
//! and row of blocks may be cut by the image edge). Angles are radians in image coordinates (x to
//! the right, y down).

use serde::Serialize;
use std::ops::Range;

/// The blocks an image is cut into.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct BlockGrid {
    /// Image width, px.
    pub width: u32,
    /// Image height, px.
    pub height: u32,
    /// Side of a block, px (> 0).
    pub block: u32,
    /// Blocks per row.
    pub cols: u32,
    /// Rows of blocks.
    pub rows: u32,
}

impl BlockGrid {
    /// The grid of `block`-pixel blocks over a `width x height` image (`block` is taken as at
    /// least 1).
    pub fn new(width: u32, height: u32, block: u32) -> Self {
        let block = block.max(1);
        BlockGrid {
            width,
            height,
            block,
            cols: width.div_ceil(block),
            rows: height.div_ceil(block),
        }
    }

    /// Number of blocks.
    pub fn len(&self) -> usize {
        self.cols as usize * self.rows as usize
    }

    /// Whether there are no blocks.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Index of block `(i, j)`.
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.cols as usize + i
    }

    /// The block holding the point `pos` (clamped to the grid), as `(i, j)`.
    pub fn block_of(&self, pos: [f64; 2]) -> (usize, usize) {
        let b = f64::from(self.block);
        let clamp = |v: f64, n: u32| {
            if v.is_finite() && v > 0.0 {
                ((v / b) as usize).min(n.saturating_sub(1) as usize)
            } else {
                0
            }
        };
        (clamp(pos[0], self.cols), clamp(pos[1], self.rows))
    }

    /// The pixel range `[x0, x1) x [y0, y1)` of block `(i, j)`.
    pub fn pixels(&self, i: usize, j: usize) -> (usize, usize, usize, usize) {
        let b = self.block as usize;
        let x0 = (i * b).min(self.width as usize);
        let y0 = (j * b).min(self.height as usize);
        (
            x0,
            (x0 + b).min(self.width as usize),
            y0,
            (y0 + b).min(self.height as usize),
        )
    }

    /// The center of block `(i, j)` (of its part inside the image).
    pub fn center(&self, i: usize, j: usize) -> [f64; 2] {
        let (x0, x1, y0, y1) = self.pixels(i, j);
        [(x0 + x1) as f64 / 2.0, (y0 + y1) as f64 / 2.0]
    }
}

/// A gray-level image as floating-point values, row-major.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Plane {
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// `values[y * width + x]`.
    pub values: Vec<f32>,
}

impl Plane {
    /// The value at pixel `(x, y)`, clamped to the image (0 for an empty plane).
    #[inline]
    pub fn at(&self, x: i64, y: i64) -> f32 {
        if self.width == 0 || self.height == 0 {
            return 0.0;
        }
        let x = x.clamp(0, i64::from(self.width) - 1) as usize;
        let y = y.clamp(0, i64::from(self.height) - 1) as usize;
        self.values
            .get(y * self.width as usize + x)
            .copied()
            .unwrap_or(0.0)
    }

    /// Bilinear interpolation at the point `(x, y)` in pixel-center coordinates (pixel `(c, r)`'s
    /// value is at `(c + 0.5, r + 0.5)`), clamped to the image.
    pub fn sample(&self, x: f64, y: f64) -> f32 {
        let (fx, fy) = (x - 0.5, y - 0.5);
        let (cx, cy) = (floor(fx), floor(fy));
        let (tx, ty) = ((fx - cx as f64) as f32, (fy - cy as f64) as f32);
        let (w, h) = (i64::from(self.width), i64::from(self.height));
        let four = if cx >= 0 && cy >= 0 && cx < w - 1 && cy < h - 1 {
            // Inside: the four pixels directly (the same values as `at` gives).
            self.four(cy as usize * self.width as usize + cx as usize)
        } else if w == 0 || h == 0 {
            [0.0; 4]
        } else {
            // As four calls of `at`, each coordinate clamped once.
            let (x0, x1) = (cx.clamp(0, w - 1), (cx + 1).clamp(0, w - 1));
            let (y0, y1) = (cy.clamp(0, h - 1), (cy + 1).clamp(0, h - 1));
            let value = |x: i64, y: i64| {
                self.values
                    .get((y * w + x) as usize)
                    .copied()
                    .unwrap_or(0.0)
            };
            [value(x0, y0), value(x1, y0), value(x0, y1), value(x1, y1)]
        };
        bilinear(four, tx, ty)
    }

    /// The values of the pixel at index `i` and of those right of it, below it and below right.
    #[inline]
    fn four(&self, i: usize) -> [f32; 4] {
        let next = i + self.width as usize;
        [
            self.values[i],
            self.values[i + 1],
            self.values[next],
            self.values[next + 1],
        ]
    }

    /// [`Plane::sample`] at a point whose four pixels are all inside the image (`x` and `y` in
    /// `[0.5, width - 0.5)` and `[0.5, height - 0.5)`): the same value, without the clamping.
    #[inline]
    pub(crate) fn sample_inside(&self, x: f64, y: f64) -> f32 {
        let (fx, fy) = (x - 0.5, y - 0.5);
        debug_assert!(fx >= 0.0 && fy >= 0.0, "{x} {y} outside");
        // Not negative: truncation is the floor (as `i32`, whose conversions both ways are one
        // instruction each on x86-64, where `usize`'s are several).
        let (cx, cy) = (fx as i32, fy as i32);
        let (tx, ty) = ((fx - f64::from(cx)) as f32, (fy - f64::from(cy)) as f32);
        bilinear(
            self.four(cy as usize * self.width as usize + cx as usize),
            tx,
            ty,
        )
    }
}

#[cfg(test)]
impl Plane {
    /// A plane of uneven values for the tests: pixel `i`'s is `(i · step mod modulus) · scale +
    /// offset` (`[step, modulus]` as `walk`).
    pub(crate) fn uneven(
        width: u32,
        height: u32,
        walk: [u32; 2],
        scale: f32,
        offset: f32,
    ) -> Plane {
        Plane {
            width,
            height,
            values: (0..width * height)
                .map(|i| ((i * walk[0]) % walk[1]) as f32 * scale + offset)
                .collect(),
        }
    }
}

/// Samples whose coordinates [`Plane::add_samples_inside`] works out side by side.
const SAMPLE_LANES: usize = 16;

impl Plane {
    /// Adds to each `sums[t]` the sample at `(xs[t] + offset[0], ys[t] + offset[1])`, every one
    /// of which has its four pixels inside the image: the value [`Plane::sample_inside`] gives,
    /// from the same operations. The coordinates, pixels and fractions of 16 samples are worked
    /// out side by side (vector lanes) before their pixels are read.
    #[inline(always)]
    pub(crate) fn add_samples_inside(
        &self,
        xs: &[f64],
        ys: &[f64],
        offset: [f64; 2],
        sums: &mut [f32],
    ) {
        let chunks = xs
            .chunks(SAMPLE_LANES)
            .zip(ys.chunks(SAMPLE_LANES))
            .zip(sums.chunks_mut(SAMPLE_LANES));
        for ((xs, ys), sums) in chunks {
            if let (Ok(xs), Ok(ys), Ok(lanes)) = (
                <&[f64; SAMPLE_LANES]>::try_from(xs),
                <&[f64; SAMPLE_LANES]>::try_from(ys),
                <&mut [f32; SAMPLE_LANES]>::try_from(&mut *sums),
            ) {
                self.add_lanes(xs, ys, offset, lanes);
            } else {
                for ((&x, &y), sum) in xs.iter().zip(ys).zip(sums.iter_mut()) {
                    *sum += self.sample_inside(x + offset[0], y + offset[1]);
                }
            }
        }
    }

    /// [`Plane::add_samples_inside`] for `N` samples.
    #[inline(always)]
    fn add_lanes<const N: usize>(
        &self,
        xs: &[f64; N],
        ys: &[f64; N],
        offset: [f64; 2],
        sums: &mut [f32; N],
    ) {
        let width = f64::from(self.width);
        let (mut pixel, mut tx, mut ty) = ([0u64; N], [0.0f32; N], [0.0f32; N]);
        for l in 0..N {
            // As `sample_inside`: the point less half a pixel, its whole part (truncation, the
            // floor of a value not negative) and the fractions (the same differences).
            let (fx, fy) = (xs[l] + offset[0] - 0.5, ys[l] + offset[1] - 0.5);
            debug_assert!(fx >= 0.0 && fy >= 0.0, "{fx} {fy} outside");
            let (cx, cy) = (floor_small(fx), floor_small(fy));
            tx[l] = (fx - cx) as f32;
            ty[l] = (fy - cy) as f32;
            pixel[l] = whole_small(cy * width + cx);
        }
        let (mut a, mut b, mut c, mut d) = ([0.0f32; N], [0.0f32; N], [0.0f32; N], [0.0f32; N]);
        let stride = self.width as usize;
        for l in 0..N {
            // The pixel, the one right of it, below it and below right: one slice, one bounds
            // check.
            let i = pixel[l] as usize;
            let square = &self.values[i..i + stride + 2];
            [a[l], b[l], c[l], d[l]] = [square[0], square[1], square[stride], square[stride + 1]];
        }
        for l in 0..N {
            sums[l] += bilinear([a[l], b[l], c[l], d[l]], tx[l], ty[l]);
        }
    }
}

/// 2⁵²: adding it to a value in `[0, 2⁵²)` rounds the value to a whole number.
const TWO_52: f64 = 4_503_599_627_370_496.0;

/// `v.floor()` for `v` in `[0, 2⁵²)`, without an integer conversion (which vector lanes of
/// baseline x86-64 lack for `f64`): `v + 2⁵² - 2⁵²` is `v` rounded to a whole number, one less
/// when that rounded up. Exact, as every step is (whole numbers below 2⁵³).
#[inline]
pub(super) fn floor_small(v: f64) -> f64 {
    let rounded = v + TWO_52 - TWO_52;
    // One less where it rounded up (less 0 otherwise: the same value), a mask and a difference
    // in vector lanes rather than a choice between two.
    rounded - if rounded > v { 1.0 } else { 0.0 }
}

/// The whole number `v` (in `[0, 2⁵²)`) as an integer, from the bits of `v + 2⁵²`, whose
/// mantissa it is.
#[inline]
pub(super) fn whole_small(v: f64) -> u64 {
    (v + TWO_52).to_bits() - TWO_52.to_bits()
}

/// The bilinear mix of four pixels' values (top left, top right, bottom left, bottom right) at
/// the fractions `tx` across and `ty` down.
#[inline]
fn bilinear([a, b, c, d]: [f32; 4], tx: f32, ty: f32) -> f32 {
    let top = a * (1.0 - tx) + b * tx;
    let bottom = c * (1.0 - tx) + d * tx;
    top * (1.0 - ty) + bottom * ty
}

/// `v.floor()` as an integer, without the library call that `f64::floor` is on targets without
/// SSE4.1 (the sampling's hot path): exact for every finite `v` within `i64`'s range; NaN gives 0
/// as `v.floor() as i64` does.
#[inline]
fn floor(v: f64) -> i64 {
    let t = v as i64;
    if (t as f64) > v {
        t - 1
    } else {
        t
    }
}

/// Which blocks belong to the print (the segmentation stage's output).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Segmentation {
    /// The blocks.
    pub grid: BlockGrid,
    /// One flag per block: true inside the print.
    pub inside: Vec<bool>,
}

impl Segmentation {
    /// Whether pixel `(x, y)` lies in the print (false outside the image).
    pub fn contains_pixel(&self, x: usize, y: usize) -> bool {
        if x >= self.grid.width as usize || y >= self.grid.height as usize {
            return false;
        }
        let b = self.grid.block as usize;
        self.inside
            .get(self.grid.index(x / b, y / b))
            .is_some_and(|&v| v)
    }

    /// The print as one flag per pixel.
    pub fn pixel_mask(&self) -> Vec<bool> {
        let (w, h) = (self.grid.width as usize, self.grid.height as usize);
        let b = (self.grid.block as usize).max(1);
        let mut mask = Vec::with_capacity(w * h);
        // Each row of blocks once, copied to its rows of pixels.
        let mut row = Vec::with_capacity(w);
        for y in 0..h {
            if y % b == 0 {
                row.clear();
                row.extend((0..w).map(|x| self.contains_pixel(x, y)));
            }
            mask.extend_from_slice(&row);
        }
        mask
    }

    /// Visits the pixels outside the print as ranges of indices into the row-major image (width
    /// `grid.width`), each run of neighbouring blocks outside a row of blocks once per row of
    /// pixels: the pixels [`Segmentation::pixel_mask`] has false, without a flag per pixel.
    pub(crate) fn outside_runs(&self, mut visit: impl FnMut(Range<usize>)) {
        let g = &self.grid;
        let w = g.width as usize;
        if self.inside.len() != g.len() {
            return;
        }
        for j in 0..g.rows as usize {
            let mut i = 0;
            while i < g.cols as usize {
                if self.inside[g.index(i, j)] {
                    i += 1;
                    continue;
                }
                let first = i;
                while i < g.cols as usize && !self.inside[g.index(i, j)] {
                    i += 1;
                }
                let (x0, _, y0, y1) = g.pixels(first, j);
                let x1 = g.pixels(i - 1, j).1;
                for y in y0..y1 {
                    visit(y * w + x0..y * w + x1);
                }
            }
        }
    }

    /// Number of blocks inside the print.
    pub fn area_blocks(&self) -> usize {
        self.inside.iter().filter(|&&v| v).count()
    }
}

/// The ridge orientation per block.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct OrientationField {
    /// The blocks.
    pub grid: BlockGrid,
    /// Ridge direction per block, radians in `[0, π)` (an orientation: `θ` and `θ + π` are the
    /// same ridge), y down.
    pub angle: Vec<f32>,
    /// Coherence per block in `[0, 1]`: `|Σ (g_x² - g_y², 2 g_x g_y)| / Σ (g_x² + g_y²)` over the
    /// smoothing window, 1 for parallel ridges, 0 for no dominant direction.
    pub coherence: Vec<f32>,
}

impl OrientationField {
    /// The ridge direction at `pos`, interpolated between block centers as a doubled-angle
    /// vector (so orientations near 0 and near π average correctly).
    pub fn angle_at(&self, pos: [f64; 2]) -> f64 {
        let g = &self.grid;
        if g.is_empty() || self.angle.len() != g.len() {
            return 0.0;
        }
        let b = f64::from(g.block);
        let fx = (pos[0] / b - 0.5).clamp(0.0, f64::from(g.cols - 1));
        let fy = (pos[1] / b - 0.5).clamp(0.0, f64::from(g.rows - 1));
        let (i0, j0) = (fx.floor() as usize, fy.floor() as usize);
        let (i1, j1) = (
            (i0 + 1).min(g.cols as usize - 1),
            (j0 + 1).min(g.rows as usize - 1),
        );
        let (tx, ty) = (fx - i0 as f64, fy - j0 as f64);
        let mut v = [0.0f64; 2];
        for (i, j, w) in [
            (i0, j0, (1.0 - tx) * (1.0 - ty)),
            (i1, j0, tx * (1.0 - ty)),
            (i0, j1, (1.0 - tx) * ty),
            (i1, j1, tx * ty),
        ] {
            let a = 2.0 * f64::from(self.angle[g.index(i, j)]);
            v[0] += w * a.cos();
            v[1] += w * a.sin();
        }
        (v[1].atan2(v[0]) / 2.0).rem_euclid(std::f64::consts::PI)
    }
}

/// The ridge period (distance between neighbouring ridges) per block.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RidgePeriods {
    /// The blocks.
    pub grid: BlockGrid,
    /// Period per block, px, every block filled (measured, or interpolated from its neighbours).
    pub period: Vec<f32>,
    /// Whether the block's period was measured (false: interpolated).
    pub measured: Vec<bool>,
}

impl RidgePeriods {
    /// The period of the block holding `pos`, px.
    pub fn at(&self, pos: [f64; 2]) -> f64 {
        let (i, j) = self.grid.block_of(pos);
        self.period
            .get(self.grid.index(i, j))
            .map_or(0.0, |&p| f64::from(p))
    }

    /// The median period of the blocks inside the print, px (0 for an empty print; of an even
    /// count, the upper middle one).
    pub fn median_inside(&self, segmentation: &Segmentation) -> f64 {
        let mut inside: Vec<f32> = self
            .period
            .iter()
            .zip(&segmentation.inside)
            .filter(|(_, &i)| i)
            .map(|(&p, _)| p)
            .collect();
        crate::median::upper_median_by(&mut inside, f32::total_cmp).map_or(0.0, f64::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn grid_covers_the_image_with_cut_last_blocks() {
        let g = BlockGrid::new(20, 9, 8);
        assert_eq!((g.cols, g.rows, g.len()), (3, 2, 6));
        assert_eq!(g.pixels(2, 1), (16, 20, 8, 9));
        assert_eq!(g.center(2, 1), [18.0, 8.5]);
        assert_eq!(g.block_of([19.9, 8.9]), (2, 1));
        assert_eq!(g.block_of([-5.0, f64::NAN]), (0, 0));
        assert_eq!(g.block_of([500.0, 500.0]), (2, 1));
        assert!(BlockGrid::new(0, 0, 0).is_empty());
    }

    #[test]
    fn bilinear_sample_interpolates_between_pixel_centers() {
        let p = Plane {
            width: 2,
            height: 1,
            values: vec![0.0, 10.0],
        };
        assert_eq!(p.sample(0.5, 0.5), 0.0);
        assert_eq!(p.sample(1.0, 0.5), 5.0);
        assert_eq!(p.sample(1.5, 0.5), 10.0);
        assert_eq!(p.sample(9.0, -3.0), 10.0, "clamped");
        assert_eq!(Plane::default().sample(1.0, 1.0), 0.0);
    }

    #[test]
    fn a_sample_is_the_mix_of_its_four_pixels_each_clamped() {
        // Points inside, on and across every edge and corner, and far outside, on quarter
        // pixels and at random: the value from four calls of `at`, bit for bit.
        let p = Plane::uneven(9, 6, [37, 23], 0.7, -3.0);
        let by_at = |x: f64, y: f64| {
            let (fx, fy) = (x - 0.5, y - 0.5);
            let (cx, cy) = (fx.floor() as i64, fy.floor() as i64);
            let four = [
                p.at(cx, cy),
                p.at(cx + 1, cy),
                p.at(cx, cy + 1),
                p.at(cx + 1, cy + 1),
            ];
            bilinear(four, (fx - cx as f64) as f32, (fy - cy as f64) as f32)
        };
        let mut seed = 11u64;
        let mut unit = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let quarters = (-16..=56).map(|k| f64::from(k) / 4.0);
        let mut points: Vec<[f64; 2]> = quarters
            .clone()
            .flat_map(|x| quarters.clone().map(move |y| [x, y]))
            .collect();
        points.extend((0..20_000).map(|_| [unit() * 40.0 - 15.0, unit() * 30.0 - 12.0]));
        for [x, y] in points {
            assert_eq!(p.sample(x, y).to_bits(), by_at(x, y).to_bits(), "{x} {y}");
        }
    }

    #[test]
    fn floors_without_conversion_are_the_library_ones() {
        for v in [
            0.0f64,
            0.25,
            0.5,
            0.999_999_999,
            1.0,
            1.5,
            2.5,
            3.5,
            1e6 + 0.5,
            4e9 + 0.75,
            1e15,
        ] {
            for v in [
                v,
                f64::from_bits(v.to_bits() + 1),
                f64::from_bits(v.to_bits().max(1) - 1),
            ] {
                assert_eq!(floor_small(v), v.floor(), "{v}");
                assert_eq!(whole_small(v.floor()), v.floor() as u64, "{v}");
            }
        }
    }

    #[test]
    fn samples_added_in_lanes_are_the_single_samples_bit_for_bit() {
        // A plane of uneven values and rows of points at odd angles and offsets, 48 and 37
        // samples long (three full chunks of lanes, and a remainder).
        let (width, height) = (61u32, 47u32);
        let values = (0..width * height)
            .map(|i| ((i * 7919) % 251) as f32 * 0.37 - 11.0)
            .collect();
        let plane = Plane {
            width,
            height,
            values,
        };
        for (n, angle) in [(48usize, 0.3f64), (37, 1.9), (48, 2.75), (16, 0.0)] {
            let (normal, along) = ([-angle.sin(), angle.cos()], [angle.cos(), angle.sin()]);
            let centre = [30.3, 22.9];
            let u = |t: usize| t as f64 - n as f64 / 2.0 + 0.5;
            let xs: Vec<f64> = (0..n).map(|t| centre[0] + u(t) * 0.4 * normal[0]).collect();
            let ys: Vec<f64> = (0..n).map(|t| centre[1] + u(t) * 0.4 * normal[1]).collect();
            for k in [-7.5f64, -0.5, 0.0, 3.25, 7.5] {
                let offset = [k * along[0], k * along[1]];
                let mut sums = vec![1.5f32; n];
                plane.add_samples_inside(&xs, &ys, offset, &mut sums);
                for t in 0..n {
                    let one = 1.5 + plane.sample_inside(xs[t] + offset[0], ys[t] + offset[1]);
                    assert_eq!(sums[t].to_bits(), one.to_bits(), "angle {angle}, t {t}");
                }
            }
        }
    }

    #[test]
    fn orientation_interpolation_wraps_at_pi() {
        // Two blocks, one at 5 degrees, one at 175: halfway between them the ridge is horizontal,
        // not vertical, as averaging the angles themselves would give.
        let field = OrientationField {
            grid: BlockGrid::new(16, 8, 8),
            angle: vec![5f32.to_radians(), 175f32.to_radians()],
            coherence: vec![1.0; 2],
        };
        let mid = field.angle_at([8.0, 4.0]);
        assert!(mid.min(PI - mid) < 1e-6, "{mid}");
    }

    #[test]
    fn pixel_mask_follows_the_blocks() {
        let s = Segmentation {
            grid: BlockGrid::new(4, 2, 2),
            inside: vec![false, true],
        };
        assert_eq!(
            s.pixel_mask(),
            vec![false, false, true, true, false, false, true, true]
        );
        assert!(!s.contains_pixel(4, 0));
        assert_eq!(s.area_blocks(), 1);
    }

    #[test]
    fn outside_runs_are_the_pixel_masks_false_pixels() {
        // Grids whose last column and row of blocks are cut, with runs of blocks outside at
        // either end of a row and inside it.
        for (width, height, block) in [(11, 7, 3), (12, 9, 4), (5, 5, 8), (1, 1, 1)] {
            let grid = BlockGrid::new(width, height, block);
            for pattern in [0b1011_0110_1101u32, 0, u32::MAX, 0b0110] {
                let s = Segmentation {
                    grid,
                    inside: (0..grid.len())
                        .map(|b| pattern >> (b % 32) & 1 == 1)
                        .collect(),
                };
                let mut outside = vec![false; (width * height) as usize];
                s.outside_runs(|run| outside[run].iter_mut().for_each(|o| *o = true));
                let mask: Vec<bool> = s.pixel_mask().iter().map(|&p| !p).collect();
                assert_eq!(outside, mask, "{width} x {height} by {block}, {pattern:b}");
            }
        }
    }
}
