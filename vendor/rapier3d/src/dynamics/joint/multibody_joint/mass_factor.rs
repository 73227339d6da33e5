//! carl-spec patch: tree-sparse factorization of a multibody's augmented mass matrices.
//!
//! A multibody's joint-space mass matrix `A` has branch-induced sparsity: `A[i, j]` can be
//! nonzero only when DoF `i` is DoF `j`, one of its ancestors or one of its descendants
//! (numbering DoFs so that a parent precedes its children). Eliminating the DoFs from the last
//! to the first (leaves first) then creates no fill-in, because the Schur complement of DoF `k`
//! only couples pairs of `k`'s ancestors, which are ancestors of one another. This is
//! Featherstone's LTDL factorization ("Efficient factorization of the joint-space inertia
//! matrix for branched kinematic trees", IJRR 24(6), 2005), written here from the paper and
//! extended to matrices with the same sparsity pattern that are not symmetric (rapier's
//! accelerated mass matrix carries the implicit gyroscopic and Coriolis terms):
//! `A = (I + U)·D·(I + L)`, `U` strictly upper and `L` strictly lower with the pattern of `A`,
//! `D` diagonal. For a symmetric `A`, `U = Lᵀ` and this is the paper's `LᵀDL`.
//!
//! Factorization costs `O(Σₖ depth(k)²)` and a solve `O(Σₖ depth(k))`, against `O(n³)` and
//! `O(n²)` for the dense LU. No pivoting: the factorization is only used when every pivot is
//! positive and not tiny relative to its original diagonal entry, which holds for a matrix whose
//! symmetric part is positive definite (the mass matrix always, the accelerated one for small
//! enough time steps); otherwise, and whenever kinematic DoFs reorder the matrix, the caller
//! falls back to upstream's dense LU with partial pivoting.

use crate::alloc_prelude::*;
use crate::math::Real;
use na::{DMatrix, Dim, Dyn, LU, Matrix, StorageMut};
use na::constraint::{SameNumberOfRows, ShapeConstraint};

/// `parent[k]` when DoF `k` has no ancestor DoF.
pub const NO_PARENT: usize = usize::MAX;

/// A pivot smaller than this fraction of its original diagonal entry sends the matrix to the
/// dense LU (near-singular or not positive: partial pivoting is then the safer choice).
const MIN_RELATIVE_PIVOT: Real = 1.0e-5;

/// The factorization of a multibody's (augmented) mass matrix, as used to solve `A·x = b`.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug)]
pub enum MassMatrixFactor {
    /// Tree-sparse `(I + U)·D·(I + L)` (carl-spec patch).
    Tree(TreeFactor),
    /// Upstream's dense LU with partial pivoting.
    Dense(LU<Real, Dyn, Dyn>),
}

impl Default for MassMatrixFactor {
    fn default() -> Self {
        MassMatrixFactor::Tree(TreeFactor::default())
    }
}

impl MassMatrixFactor {
    /// Solves `A·x = b` in place, for every column of `b`. Returns `false` if `A` was found
    /// singular (only the dense LU can tell; `b` may then hold garbage).
    pub fn solve_mut<R2: Dim, C2: Dim, S2>(&self, b: &mut Matrix<Real, R2, C2, S2>) -> bool
    where
        S2: StorageMut<Real, R2, C2>,
        ShapeConstraint: SameNumberOfRows<R2, Dyn>,
    {
        match self {
            MassMatrixFactor::Tree(f) => {
                f.solve_mut(b);
                true
            }
            MassMatrixFactor::Dense(lu) => lu.solve_mut(b),
        }
    }

    /// Whether the tree-sparse factorization is in use (for tests).
    pub fn is_tree_sparse(&self) -> bool {
        matches!(self, MassMatrixFactor::Tree(_))
    }

    /// Factorizes the top-left `n × n` block of `a` (the DoFs' parents in `parent`, each
    /// `< k` or [`NO_PARENT`]), reusing this factor's storage: tree-sparse when every pivot
    /// qualifies, dense LU otherwise. `symmetric`: `a` is symmetric (then only its lower
    /// triangle is read, and `U = Lᵀ`). Public for carl-spec's tests (`tests/rapier_patch.rs`).
    #[doc(hidden)]
    pub fn factorize(
        &mut self,
        a: &DMatrix<Real>,
        n: usize,
        parent: Option<&[usize]>,
        symmetric: bool,
    ) {
        if let Some(parent) = parent {
            match self {
                MassMatrixFactor::Tree(tree) => {
                    if tree.factorize(a, n, parent, symmetric) {
                        return;
                    }
                }
                MassMatrixFactor::Dense(_) => {
                    let mut tree = TreeFactor::default();
                    if tree.factorize(a, n, parent, symmetric) {
                        *self = MassMatrixFactor::Tree(tree);
                        return;
                    }
                }
            }
        }
        *self = MassMatrixFactor::Dense(LU::new(a.view((0, 0), (n, n)).into_owned()));
    }
}

/// `A = (I + U)·D·(I + L)` in compact storage: DoF `k`'s ancestors (parent first) are
/// `ancestors[offsets[k]..offsets[k + 1]]`, and at the same positions `lower` holds `L[k, j]`
/// and `upper` holds `U[j, k]` for those ancestors `j` (before factorization: `A[k, j]` and
/// `A[j, k]`). An ancestor's own ancestors are the tail of the list after it, so each
/// elimination step updates contiguous runs.
#[cfg_attr(feature = "serde-serialize", derive(Serialize, Deserialize))]
#[derive(Clone, Debug, Default)]
pub struct TreeFactor {
    parent: Vec<usize>,
    offsets: Vec<usize>,
    ancestors: Vec<usize>,
    lower: Vec<Real>,
    upper: Vec<Real>,
    diag: Vec<Real>,
    inv_diag: Vec<Real>,
    /// `U = Lᵀ`: `upper` is unused.
    symmetric: bool,
}

impl TreeFactor {
    /// Rebuilds the ancestor lists when the tree changed.
    fn set_tree(&mut self, parent: &[usize]) {
        if self.parent == parent {
            return;
        }
        self.parent.clear();
        self.parent.extend_from_slice(parent);
        self.offsets.clear();
        self.ancestors.clear();
        self.offsets.push(0);
        for k in 0..parent.len() {
            let mut i = parent[k];
            while i != NO_PARENT {
                assert!(i < k, "a DoF must come after its parent DoF");
                self.ancestors.push(i);
                i = parent[i];
            }
            self.offsets.push(self.ancestors.len());
        }
        let len = self.ancestors.len();
        self.lower.resize(len, 0.0);
        self.upper.resize(len, 0.0);
        self.diag.resize(parent.len(), 0.0);
        self.inv_diag.resize(parent.len(), 0.0);
    }

    /// Factorizes the top-left `n × n` block of `a`; `false` (and an unusable factor) when a
    /// pivot is not positive or tiny, see [`MIN_RELATIVE_PIVOT`].
    fn factorize(&mut self, a: &DMatrix<Real>, n: usize, parent: &[usize], symmetric: bool) -> bool {
        assert_eq!(parent.len(), n, "one parent per DoF");
        self.set_tree(parent);
        self.symmetric = symmetric;
        let rows = a.nrows();
        let a = a.as_slice(); // column-major
        for k in 0..n {
            self.diag[k] = a[k + k * rows];
            for p in self.offsets[k]..self.offsets[k + 1] {
                let j = self.ancestors[p];
                self.lower[p] = a[k + j * rows];
                if !symmetric {
                    self.upper[p] = a[j + k * rows];
                }
            }
        }

        // Eliminate DoF k (leaves first): for every pair (p, q) of k's ancestors,
        // A[p, q] -= A[p, k]·A[k, q] / A[k, k]; the multipliers become L and U.
        for k in (0..n).rev() {
            let pivot = self.diag[k];
            if !(pivot.is_finite() && pivot > MIN_RELATIVE_PIVOT * a[k + k * rows].abs()) {
                return false;
            }
            let inv_pivot = 1.0 / pivot;
            self.inv_diag[k] = inv_pivot;
            let start = self.offsets[k];
            let depth = self.offsets[k + 1] - start;
            // Row/column storage of the DoFs before k, and k's own.
            let (lower_before, lower_k) = self.lower.split_at_mut(start);
            let (upper_before, upper_k) = self.upper.split_at_mut(start);
            let lower_k = &mut lower_k[..depth];
            let upper_k = &mut upper_k[..depth];
            for idx in 0..depth {
                let i = self.ancestors[start + idx];
                // k's entries beyond idx (i's ancestors) are still the unfactored ones.
                let a_ki = lower_k[idx];
                let l_ki = a_ki * inv_pivot;
                let u_ik = if symmetric { l_ki } else { upper_k[idx] * inv_pivot };
                self.diag[i] -= u_ik * a_ki;
                let i_start = self.offsets[i];
                let i_len = self.offsets[i + 1] - i_start;
                debug_assert_eq!(i_len, depth - idx - 1);
                let lower_i = &mut lower_before[i_start..i_start + i_len];
                for (x, y) in lower_i.iter_mut().zip(&lower_k[idx + 1..]) {
                    *x -= u_ik * *y;
                }
                lower_k[idx] = l_ki;
                if !symmetric {
                    let upper_i = &mut upper_before[i_start..i_start + i_len];
                    for (x, y) in upper_i.iter_mut().zip(&upper_k[idx + 1..]) {
                        *x -= *y * l_ki;
                    }
                    upper_k[idx] = u_ik;
                }
            }
        }
        true
    }

    fn solve_mut<R2: Dim, C2: Dim, S2>(&self, b: &mut Matrix<Real, R2, C2, S2>)
    where
        S2: StorageMut<Real, R2, C2>,
    {
        let n = self.parent.len();
        assert_eq!(n, b.nrows(), "mass matrix solve: dimension mismatch.");
        let upper = if self.symmetric { &self.lower } else { &self.upper };
        let mut stack = [0.0; 128];
        let mut heap = Vec::new();
        let x: &mut [Real] = if n <= stack.len() {
            &mut stack[..n]
        } else {
            heap.resize(n, 0.0);
            &mut heap
        };
        for c in 0..b.ncols() {
            let mut col = b.column_mut(c);
            for (r, v) in x.iter_mut().enumerate() {
                *v = col[r];
            }
            // (I + U)·z = b, from the leaves up.
            for k in (0..n).rev() {
                let zk = x[k];
                if zk != 0.0 {
                    let range = self.offsets[k]..self.offsets[k + 1];
                    for (&i, &u) in self.ancestors[range.clone()].iter().zip(&upper[range]) {
                        x[i] -= u * zk;
                    }
                }
            }
            // (I + L)·x = D⁻¹·z, from the root down.
            for k in 0..n {
                let mut acc = x[k] * self.inv_diag[k];
                let range = self.offsets[k]..self.offsets[k + 1];
                for (&i, &l) in self.ancestors[range.clone()].iter().zip(&self.lower[range]) {
                    acc -= l * x[i];
                }
                x[k] = acc;
            }
            for (r, v) in x.iter().enumerate() {
                col[r] = *v;
            }
        }
    }
}
