//! Small geometry for the fit: L1 medians (Weiszfeld), principal directions, least-squares line
//! intersections and arc-length walks along polylines.

use crate::geometry::principal;
pub(crate) use crate::geometry::{line_intersection, unit};

/// Working arrays of [`l1_median`], kept between calls so that nothing is allocated per node.
#[derive(Clone, Debug, Default)]
pub struct MedianScratch {
    /// Member coordinates, one array per axis (structure of arrays: the per-member pass below
    /// runs on two members per instruction).
    xs: Vec<f64>,
    ys: Vec<f64>,
    /// Per member: the weight `1 / d` (0 for a coincident member) and the weighted coordinates.
    w: Vec<f64>,
    wx: Vec<f64>,
    wy: Vec<f64>,
}

/// Geometric (L1) median of `points[members]` by Weiszfeld's iteration from the mean (§3.4: the
/// paper's `q'_i`, robust to outliers where the mean is not).
///
/// A point that coincides with the current estimate would get an infinite weight; it is handled as
/// in Vardi and Zhang (2000): the step moves only as far as the pull of the other points exceeds
/// the number of coincident points, and stops when it does not. Returns `None` for no members.
///
/// The iteration stops after `iterations` steps or when a step moves less than `tolerance`
/// (Weiszfeld converges linearly, so the estimate is then within a few `tolerance` of the
/// median).
///
/// The members are copied into `scratch` first: the iteration reads them `iterations` times, and
/// a node's points lie on several image rows, far apart in the point array.
pub fn l1_median(
    points: &[[f64; 2]],
    members: &[u32],
    iterations: usize,
    tolerance: f64,
    scratch: &mut MedianScratch,
) -> Option<[f64; 2]> {
    if members.is_empty() {
        return None;
    }
    let MedianScratch { xs, ys, w, wx, wy } = scratch;
    xs.clear();
    ys.clear();
    let n = members.len() as f64;
    let mut x = [0.0, 0.0];
    for &m in members {
        let p = points[m as usize];
        xs.push(p[0]);
        ys.push(p[1]);
        x[0] += p[0];
        x[1] += p[1];
    }
    x = [x[0] / n, x[1] / n];
    w.resize(members.len(), 0.0);
    wx.resize(members.len(), 0.0);
    wy.resize(members.len(), 0.0);
    for _ in 0..iterations {
        // The square roots and divisions, independent per member, in one vectorizable pass; a
        // coincident member gets weight 0, and adding its zero terms below leaves the sums as
        // skipping it would (a sum that starts at +0.0 never becomes -0.0).
        let mut coincident = 0usize;
        for ((((&px, &py), wi), wxi), wyi) in xs
            .iter()
            .zip(ys.iter())
            .zip(w.iter_mut())
            .zip(wx.iter_mut())
            .zip(wy.iter_mut())
        {
            let d = distance([px, py], x);
            let near = d < 1e-9;
            coincident += usize::from(near);
            let weight = if near { 0.0 } else { 1.0 / d };
            *wi = weight;
            *wxi = weight * px;
            *wyi = weight * py;
        }
        // The sums in member order, as the sequential iteration adds them.
        let mut weighted = [0.0, 0.0];
        let mut total = 0.0;
        for ((&wi, &wxi), &wyi) in w.iter().zip(wx.iter()).zip(wy.iter()) {
            weighted[0] += wxi;
            weighted[1] += wyi;
            total += wi;
        }
        if total == 0.0 {
            break; // every member sits on x
        }
        let target = [weighted[0] / total, weighted[1] / total];
        let next = if coincident == 0 {
            target
        } else {
            // Vardi-Zhang: |pull| = |sum w (p - x)| = total * |target - x|.
            let pull = total * distance(target, x);
            let c = coincident as f64;
            if pull <= c {
                break; // x itself is the median
            }
            let g = c / pull;
            [
                (1.0 - g) * target[0] + g * x[0],
                (1.0 - g) * target[1] + g * x[1],
            ]
        };
        let step = distance(next, x);
        x = next;
        if step < tolerance {
            break;
        }
    }
    Some(x)
}

/// Centroid and unit principal direction of a point sample (closed-form 2x2 PCA); `None` when the
/// sample has no spread.
pub fn principal_line(sample: &[[f64; 2]]) -> Option<([f64; 2], [f64; 2])> {
    if sample.len() < 2 {
        return None;
    }
    let n = sample.len() as f64;
    let c = sample
        .iter()
        .fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
    let c = [c[0] / n, c[1] / n];
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in sample {
        let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    if sxx + syy < 1e-12 {
        return None;
    }
    Some((c, principal(sxx, sxy, syy).1))
}

/// Euclidean distance by `sqrt` (`f64::hypot` guards against overflow that pixel coordinates
/// cannot reach, and is several times slower in the per-point loops).
#[inline]
pub fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
    (dx * dx + dy * dy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(points: &[[f64; 2]]) -> Vec<u32> {
        (0..points.len() as u32).collect()
    }

    #[test]
    fn weiszfeld_finds_the_diagonal_crossing_of_a_quadrilateral() {
        // The geometric median of four points in convex position is where the diagonals cross.
        let points = [[0.0, 0.0], [4.0, 0.0], [5.0, 6.0], [0.0, 2.0]];
        let m = l1_median(
            &points,
            &all(&points),
            200,
            1e-9,
            &mut MedianScratch::default(),
        )
        .unwrap();
        // Diagonals (0,0)-(5,6) and (4,0)-(0,2) meet at t = 4/17 along the first.
        let t = 4.0 / 17.0;
        assert!(
            (m[0] - 5.0 * t).abs() < 1e-3 && (m[1] - 6.0 * t).abs() < 1e-3,
            "{m:?}"
        );
    }

    #[test]
    fn weiszfeld_ignores_an_outlier_and_survives_coincident_points() {
        // Collinear: the median is the middle point, whatever the outlier's distance.
        let points = [
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [3.0, 0.0],
            [1000.0, 0.0],
        ];
        let m = l1_median(
            &points,
            &all(&points),
            100,
            1e-9,
            &mut MedianScratch::default(),
        )
        .unwrap();
        assert!((m[0] - 2.0).abs() < 1e-2 && m[1].abs() < 1e-9, "{m:?}");
        // The mean (1, 1) is itself a member: the iteration must not divide by zero.
        let points = [[1.0, 1.0], [0.0, 0.0], [2.0, 2.0], [0.0, 2.0], [2.0, 0.0]];
        let m = l1_median(
            &points,
            &all(&points),
            20,
            1e-9,
            &mut MedianScratch::default(),
        )
        .unwrap();
        assert!(
            (m[0] - 1.0).abs() < 1e-9 && (m[1] - 1.0).abs() < 1e-9,
            "{m:?}"
        );
        assert_eq!(
            l1_median(&points, &[], 20, 1e-9, &mut MedianScratch::default()),
            None
        );
    }

    #[test]
    fn lines_meet_where_they_cross() {
        let lines = [
            ([0.0, 1.0], [1.0, 0.0]),
            ([3.0, 5.0], [0.0, 1.0]),
            ([-2.0, 1.0], [-1.0, 0.0]),
        ];
        let x = line_intersection(&lines, 1e-3).unwrap();
        assert!((x[0] - 3.0).abs() < 1e-9 && (x[1] - 1.0).abs() < 1e-9);
        assert_eq!(line_intersection(&lines[..1], 1e-3), None);
        let (c, d) = principal_line(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).unwrap();
        assert!((c[0] - 1.0).abs() < 1e-12 && (d[0].abs() - d[1].abs()).abs() < 1e-12);
    }

    /// The normal equations of [`line_intersection`] solved by nalgebra: the refusal test from
    /// the smallest eigenvalue, the point from a Cholesky solve.
    fn line_intersection_nalgebra(
        lines: &[([f64; 2], [f64; 2])],
        min_eigen: f64,
    ) -> Option<[f64; 2]> {
        let mut a = nalgebra::Matrix2::<f64>::zeros();
        let mut r = nalgebra::Vector2::<f64>::zeros();
        for &(c, u) in lines {
            let u = nalgebra::Vector2::new(u[0], u[1]);
            let projector = nalgebra::Matrix2::identity() - u * u.transpose();
            a += projector;
            r += projector * nalgebra::Vector2::new(c[0], c[1]);
        }
        if a.symmetric_eigenvalues().min() <= min_eigen {
            return None;
        }
        let x = a.cholesky()?.solve(&r);
        Some([x[0], x[1]])
    }

    #[test]
    fn line_intersection_agrees_with_nalgebra() {
        let sets: [&[([f64; 2], [f64; 2])]; 3] = [
            &[([0.0, 1.0], [1.0, 0.0]), ([3.0, 5.0], [0.0, 1.0])],
            &[
                ([1.0, 1.0], [0.6, 0.8]),
                ([4.0, 0.0], [-0.8, 0.6]),
                ([2.5, 3.0], [1.0, 0.0]),
            ],
            &[([0.0, 0.0], [1.0, 0.0]), ([0.0, 1.0], [1.0, 0.0])],
        ];
        for lines in sets {
            let (ours, theirs) = (
                line_intersection(lines, 1e-3),
                line_intersection_nalgebra(lines, 1e-3),
            );
            assert_eq!(ours.is_some(), theirs.is_some(), "{lines:?}");
            if let (Some(x), Some(y)) = (ours, theirs) {
                assert!(distance(x, y) < 1e-9, "{x:?} {y:?}");
            }
        }
    }
}
