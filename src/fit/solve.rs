//! The least-squares system of Eq. (4), `E(Q) = sum_i W_i |q_i - q'_i|^2 + w |L Q|^2`, solved
//! through its normal equations `(W + w L^T L) Q = W Q'` with one sparse LDL^T factorization shared
//! by the x and y coordinates.

use crate::csr::Csr;
use sprs::{CsMat, FillInReduction, SymmetryCheck};
use sprs_ldl::Ldl;

/// The rows of the smoothness operator `L`: row `r` is `q_c - mean(q_n for n in neighbours)`.
///
/// Adaptation 12 of docs/design.md (the "held" Laplacian) has one row per degree-2 chain node with
/// its two chain neighbours; the paper's uniform graph Laplacian has one row per node with all its
/// graph neighbours.
#[derive(Clone, Debug, Default)]
pub struct Smoothness {
    /// The center unknown of each row.
    pub centers: Vec<u32>,
    /// CSR offsets into `neighbors`, one more than there are rows.
    pub offsets: Vec<u32>,
    /// Flattened neighbour lists.
    pub neighbors: Vec<u32>,
}

impl Smoothness {
    /// An operator with no rows.
    pub fn new() -> Self {
        Smoothness {
            centers: Vec::new(),
            offsets: vec![0],
            neighbors: Vec::new(),
        }
    }

    /// Adds the row `q_center - mean(q_neighbors)`; a row without neighbours is ignored.
    pub fn push(&mut self, center: u32, neighbors: &[u32]) {
        if neighbors.is_empty() {
            return;
        }
        self.centers.push(center);
        self.neighbors.extend_from_slice(neighbors);
        self.offsets.push(self.neighbors.len() as u32);
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.centers.len()
    }

    fn row(&self, r: usize) -> (u32, &[u32]) {
        (
            self.centers[r],
            &self.neighbors[self.offsets[r] as usize..self.offsets[r + 1] as usize],
        )
    }
}

/// Solves `(W + w L^T L) Q = W Q'` for every unknown. `weights` must be positive (every unknown
/// then has a data term, so the matrix is symmetric positive definite).
///
/// The unknowns are factored in the caller's order (no fill-reducing permutation): the fit numbers
/// chain interiors first, chain by chain, and vertices last, which keeps the factor of a chain
/// banded and confines fill to the vertex block. Returns `None` if the factorization fails.
pub fn solve(
    targets: &[[f64; 2]],
    weights: &[f64],
    smoothness: &Smoothness,
    w: f64,
) -> Option<Vec<[f64; 2]>> {
    let n = targets.len();
    if n == 0 {
        return Some(Vec::new());
    }
    if w == 0.0 || smoothness.len() == 0 {
        return Some(targets.to_vec());
    }
    let a = normal_matrix(weights, smoothness, w);
    let ldl = Ldl::new()
        .fill_in_reduction(FillInReduction::NoReduction)
        .check_symmetry(SymmetryCheck::DontCheckSymmetry)
        .numeric(a.view())
        .ok()?;
    let bx: Vec<f64> = (0..n).map(|i| weights[i] * targets[i][0]).collect();
    let by: Vec<f64> = (0..n).map(|i| weights[i] * targets[i][1]).collect();
    let x = ldl.solve(&bx);
    let y = ldl.solve(&by);
    let solution: Vec<[f64; 2]> = x.into_iter().zip(y).map(|(x, y)| [x, y]).collect();
    solution
        .iter()
        .all(|p| p[0].is_finite() && p[1].is_finite())
        .then_some(solution)
}

/// Assembles `W + w L^T L` in compressed form directly (it is symmetric, so its rows are its
/// columns): each smoothness row adds its outer product to the rows of its unknowns; duplicates
/// are merged per row. Triplet assembly sorted globally and cost more than the factorization.
fn normal_matrix(weights: &[f64], smoothness: &Smoothness, w: f64) -> CsMat<f64> {
    let n = weights.len();
    let mut row: Vec<(usize, f64)> = Vec::new();
    // Per matrix row: the diagonal weight first, then each smoothness row's outer product.
    let mut entries = Csr::build(n, |sink| {
        for (i, &wi) in weights.iter().enumerate() {
            sink.push(i, (i, wi));
        }
        for r in 0..smoothness.len() {
            let (center, neighbors) = smoothness.row(r);
            let share = -1.0 / neighbors.len() as f64;
            row.clear();
            row.push((center as usize, 1.0));
            row.extend(neighbors.iter().map(|&m| (m as usize, share)));
            for &(i, ci) in &row {
                for &(j, cj) in &row {
                    sink.push(i, (j, w * ci * cj));
                }
            }
        }
    });
    let mut indptr = Vec::with_capacity(n + 1);
    let mut indices = Vec::with_capacity(entries.values.len());
    let mut data = Vec::with_capacity(entries.values.len());
    indptr.push(0);
    for i in 0..n {
        let slice = entries.row_mut(i);
        slice.sort_unstable_by_key(|e| e.0);
        let start = indices.len();
        for &(j, v) in slice.iter() {
            let last = indices.len().wrapping_sub(1);
            if indices.len() > start && indices[last] == j {
                data[last] += v;
            } else {
                indices.push(j);
                data.push(v);
            }
        }
        indptr.push(indices.len());
    }
    CsMat::new_csc((n, n), indptr, indices, data)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// The same system assembled densely and solved by nalgebra's Cholesky.
    fn dense(
        targets: &[[f64; 2]],
        weights: &[f64],
        smoothness: &Smoothness,
        w: f64,
    ) -> Vec<[f64; 2]> {
        let n = targets.len();
        let mut l = DMatrix::<f64>::zeros(smoothness.len(), n);
        for r in 0..smoothness.len() {
            let (c, nb) = smoothness.row(r);
            l[(r, c as usize)] += 1.0;
            for &m in nb {
                l[(r, m as usize)] -= 1.0 / nb.len() as f64;
            }
        }
        let a =
            DMatrix::from_diagonal(&DVector::from_column_slice(weights)) + l.transpose() * &l * w;
        let chol = a.cholesky().expect("SPD");
        let bx = DVector::from_iterator(n, (0..n).map(|i| weights[i] * targets[i][0]));
        let by = DVector::from_iterator(n, (0..n).map(|i| weights[i] * targets[i][1]));
        let (x, y) = (chol.solve(&bx), chol.solve(&by));
        (0..n).map(|i| [x[i], y[i]]).collect()
    }

    #[test]
    fn sparse_solve_matches_a_dense_solve() {
        // A small graph: a chain 0-1-2-3-4 and a branch 2-5-6, with held and uniform rows and
        // uneven weights (anchors, a nearly free node).
        let targets: Vec<[f64; 2]> = (0..7)
            .map(|i| {
                [
                    i as f64 * 1.7 + (i * i % 3) as f64,
                    (i * 5 % 7) as f64 - 2.0,
                ]
            })
            .collect();
        let weights = [10.0, 1.0, 10.0, 1.0, 10.0, 1e-3, 10.0];
        let mut held = Smoothness::new();
        held.push(1, &[0, 2]);
        held.push(3, &[2, 4]);
        held.push(5, &[2, 6]);
        let mut uniform = Smoothness::new();
        for (c, nb) in [
            (0, vec![1]),
            (1, vec![0, 2]),
            (2, vec![1, 3, 5]),
            (3, vec![2, 4]),
        ] {
            uniform.push(c, &nb);
        }
        uniform.push(4, &[3]);
        uniform.push(5, &[2, 6]);
        uniform.push(6, &[5]);
        for (rows, w) in [(&held, 1.0), (&held, 5.0), (&uniform, 1.0), (&uniform, 0.3)] {
            let sparse = solve(&targets, &weights, rows, w).unwrap();
            let reference = dense(&targets, &weights, rows, w);
            for (s, d) in sparse.iter().zip(&reference) {
                assert!(
                    (s[0] - d[0]).abs() < 1e-9 && (s[1] - d[1]).abs() < 1e-9,
                    "{s:?} vs {d:?}"
                );
            }
            // Smoothing must have moved something, or the comparison proves nothing.
            assert!(sparse
                .iter()
                .zip(&targets)
                .any(|(s, t)| (s[0] - t[0]).abs() > 1e-3));
        }
    }
}
