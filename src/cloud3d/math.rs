//! Vectors in space and the principal axes of a covariance (Eq. (2)-(3) with three axes).

pub(super) type V3 = [f64; 3];

pub(super) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(super) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(super) fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

pub(super) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

pub(super) fn dist2(a: V3, b: V3) -> f64 {
    let d = sub(a, b);
    dot(d, d)
}

/// Running moments of a point set about a fixed origin: count, sums and sums of products, from
/// which the covariance of Eq. (2) follows.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Moments {
    pub n: f64,
    pub s: V3,
    /// xx, xy, xz, yy, yz, zz.
    pub ss: [f64; 6],
}

impl Moments {
    pub fn add(&mut self, p: V3) {
        self.n += 1.0;
        for (s, x) in self.s.iter_mut().zip(p) {
            *s += x;
        }
        self.ss[0] += p[0] * p[0];
        self.ss[1] += p[0] * p[1];
        self.ss[2] += p[0] * p[2];
        self.ss[3] += p[1] * p[1];
        self.ss[4] += p[1] * p[2];
        self.ss[5] += p[2] * p[2];
    }

    /// Adds `other`, whose sums were taken about an origin `offset` away from this one's.
    pub fn add_shifted(&mut self, other: &Moments, offset: V3) {
        let (n, s, o) = (other.n, other.s, offset);
        self.n += n;
        for k in 0..3 {
            self.s[k] += s[k] + o[k] * n;
        }
        let pairs = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];
        for (slot, &(a, b)) in pairs.iter().enumerate() {
            self.ss[slot] += other.ss[slot] + o[a] * s[b] + o[b] * s[a] + o[a] * o[b] * n;
        }
    }

    pub fn mean(&self) -> V3 {
        scale(self.s, 1.0 / self.n.max(1.0))
    }

    /// The covariance (Eq. (2), divided by the count) as a symmetric matrix.
    pub fn covariance(&self) -> [[f64; 3]; 3] {
        let n = self.n.max(1.0);
        let m = self.mean();
        let c = |slot: usize, a: usize, b: usize| self.ss[slot] / n - m[a] * m[b];
        let (xx, xy, xz, yy, yz, zz) = (
            c(0, 0, 0).max(0.0),
            c(1, 0, 1),
            c(2, 0, 2),
            c(3, 1, 1).max(0.0),
            c(4, 1, 2),
            c(5, 2, 2).max(0.0),
        );
        [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]
    }
}

/// The eigenvalues of a symmetric 3 x 3 matrix, ascending (`lambda_0 <= lambda_1 <= lambda_2` of
/// Eq. (3)), and their unit eigenvectors, by cyclic Jacobi rotations.
pub(super) fn eigen(matrix: [[f64; 3]; 3]) -> ([f64; 3], [V3; 3]) {
    let mut a = matrix;
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..32 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in &mut a {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
            let (row_p, row_q) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * row_p[k] - s * row_q[k]);
            a[q] = std::array::from_fn(|k| s * row_p[k] + c * row_q[k]);
            for row in &mut v {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let values = order.map(|i| a[i][i].max(0.0));
    let vectors = order.map(|i| {
        let e = [v[0][i], v[1][i], v[2][i]];
        let n = norm(e).max(f64::MIN_POSITIVE);
        scale(e, 1.0 / n)
    });
    (values, vectors)
}

/// Linearity `l(S)` of Eq. (3): the largest eigenvalue's share of their sum (1 for a set on a
/// line, 1/3 for an isotropic one; 0 for a single point).
pub(super) fn linearity(values: [f64; 3]) -> f64 {
    let sum = values[0] + values[1] + values[2];
    if sum > 0.0 {
        values[2] / sum
    } else {
        0.0
    }
}

/// The diameter of a tube filled uniformly whose cross-section has the variances `lambda_0` and
/// `lambda_1`: a disk of radius `R` has variance `R^2 / 4` along each of its axes, so
/// `lambda_0 + lambda_1 = R^2 / 2` and the diameter is `2 sqrt(2 (lambda_0 + lambda_1))`.
pub(super) fn tube_diameter(values: [f64; 3]) -> f64 {
    2.0 * (2.0 * (values[0] + values[1])).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_of_a_rotated_diagonal_matrix() {
        // R diag(1, 4, 9) R^T with R a rotation about (1, 1, 1).
        let (c, s) = (0.6f64, 0.8f64);
        let r = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let d = [1.0, 4.0, 9.0];
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = (0..3).map(|k| r[i][k] * d[k] * r[j][k]).sum();
            }
        }
        let (values, vectors) = eigen(m);
        for (got, want) in values.iter().zip(d) {
            assert!((got - want).abs() < 1e-9, "{values:?}");
        }
        // The largest axis is R's third column, (0, 0, 1).
        assert!((vectors[2][2].abs() - 1.0).abs() < 1e-9);
        assert!((vectors[0][0].abs() - c).abs() < 1e-9);
        assert!((linearity(values) - 9.0 / 14.0).abs() < 1e-12);
    }

    #[test]
    fn shifted_moments_equal_direct_ones() {
        let points = [[1.0, 2.0, 3.0], [4.0, -1.0, 0.5], [2.0, 2.0, 2.0]];
        let mut direct = Moments::default();
        for p in points {
            direct.add(p);
        }
        let offset = [10.0, -3.0, 7.0];
        let mut local = Moments::default();
        for p in points {
            local.add(sub(p, offset));
        }
        let mut shifted = Moments::default();
        shifted.add_shifted(&local, offset);
        for (a, b) in direct.ss.iter().zip(shifted.ss) {
            assert!((a - b).abs() < 1e-9);
        }
        let (a, b) = (direct.covariance(), shifted.covariance());
        for i in 0..3 {
            for j in 0..3 {
                assert!((a[i][j] - b[i][j]).abs() < 1e-9);
            }
        }
    }
}
