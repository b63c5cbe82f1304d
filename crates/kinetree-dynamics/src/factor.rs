//! The sparse `Lᵀ·D·L` factorization of the mass matrix along the kinematic tree (Featherstone's
//! LTDL), solves with it and the inverse mass matrix.

use crate::data::{DynamicsData, NO_PARENT};
use crate::error::{DynamicsError, check_len, check_vector};
use crate::rnea::check_inputs;
use kinetree_kinematics::model::Model;

/// Relative size of a pivot below which the mass matrix counts as singular.
pub(crate) const PIVOT_TOLERANCE: f64 = 1e-13;

/// Computes the mass matrix at `q` ([`crba`](crate::crba)) and factorizes it as `M = Lᵀ·D·L`,
/// with `L` unit lower triangular and `D` diagonal, exploiting the tree's sparsity: `L[i][j]` is
/// nonzero only when degree of freedom `j` is an ancestor of `i`, so the factorization costs
/// O(Σ depth²) instead of O(n³) and creates no fill-in (Featherstone, *Rigid Body Dynamics
/// Algorithms*, §6.5).
///
/// The factor is kept in `data` for [`solve_mass_matrix`]; [`DynamicsData::mass_matrix`] holds
/// `M(q)`. Allocates nothing (except the joint names of an error).
///
/// # Errors
/// [`DynamicsError::SingularMassMatrix`], naming the joints whose pivots vanish, when `M(q)` is
/// not positive definite (massless subtrees); as [`crba`](crate::crba) for bad inputs.
///
/// # Examples
/// ```
/// use kinetree_dynamics::{factorize_mass_matrix, solve_mass_matrix, DynamicsData};
/// use kinetree_dynamics::model::{Model, RootJoint};
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data/reference/urdf/ur5.urdf");
/// let model = Model::from_urdf_file(path, RootJoint::Fixed)?;
/// let mut data = DynamicsData::new(&model);
/// let q = [0.1, -0.8, 1.2, 0.4, -0.3, 0.9];
/// factorize_mass_matrix(&model, &mut data, &q)?;
/// // Two right-hand sides, one after the other: the unit vectors e0 and e5.
/// let mut b = vec![0.0; 12];
/// b[0] = 1.0;
/// b[11] = 1.0;
/// solve_mass_matrix(&model, &mut data, &mut b)?;
/// // b now holds columns 0 and 5 of M⁻¹; M times the first gives e0.
/// let m = data.mass_matrix();
/// let row0: f64 = (0..6).map(|j| m[j] * b[j]).sum();
/// assert!((row0 - 1.0).abs() < 1e-10);
/// # Ok(())
/// # }
/// ```
#[doc(alias = "ltdl")]
#[doc(alias = "cholesky")]
pub fn factorize_mass_matrix(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
) -> Result<(), DynamicsError> {
    check_inputs(model, data, q, None, None)?;
    crate::crba::compute(model, data, q);
    factorize(model, data)
}

/// Factorizes `data.mass_matrix` into `data.factor`.
pub(crate) fn factorize(model: &Model, data: &mut DynamicsData) -> Result<(), DynamicsError> {
    let nv = data.nv;
    data.factorized = false;
    let h = &mut data.factor;
    h.copy_from_slice(&data.mass_matrix);
    let parent = &data.dof_parent;
    let scale = (0..nv)
        .map(|k| data.mass_matrix[k * nv + k])
        .fold(0.0, f64::max);
    let tolerance = scale * PIVOT_TOLERANCE;
    let mut singular = false;
    for k in (0..nv).rev() {
        let d = h[k * nv + k];
        if d.is_nan() || d <= tolerance {
            singular = true;
            // Drop the row so that the remaining pivots are still meaningful.
            let mut i = parent[k];
            while i != NO_PARENT {
                h[k * nv + i] = 0.0;
                i = parent[i];
            }
            continue;
        }
        let mut i = parent[k];
        while i != NO_PARENT {
            let a = h[k * nv + i] / d;
            let mut j = i;
            while j != NO_PARENT {
                h[i * nv + j] -= a * h[k * nv + j];
                j = parent[j];
            }
            h[k * nv + i] = a;
            i = parent[i];
        }
    }
    if singular {
        let dofs: Vec<usize> = (0..nv)
            .filter(|&k| {
                let d = data.factor[k * nv + k];
                d.is_nan() || d <= tolerance
            })
            .collect();
        return Err(DynamicsError::SingularMassMatrix {
            joints: data.joint_names(model, &dofs),
        });
    }
    data.factorized = true;
    Ok(())
}

/// Solves `M·x = b` in place with the factorization of the last [`factorize_mass_matrix`], for
/// one or several right-hand sides: `b` holds `k` vectors of length `nv` one after the other
/// (an `nv x k` column-major matrix), each replaced by its solution. O(k·Σ depth); allocates
/// nothing.
///
/// # Errors
/// [`DynamicsError::NotFactorized`] without a successful factorization;
/// [`DynamicsError::DimensionMismatch`] when `b.len()` is not a multiple of `nv` (or is zero
/// while `nv > 0`); [`DynamicsError::NonFinite`] for a NaN in `b`;
/// [`DynamicsError::DataMismatch`] when `data` belongs to another model.
pub fn solve_mass_matrix(
    model: &Model,
    data: &mut DynamicsData,
    b: &mut [f64],
) -> Result<(), DynamicsError> {
    data.check_model(model)?;
    if !data.factorized {
        return Err(DynamicsError::NotFactorized);
    }
    let nv = data.nv;
    if nv == 0 {
        return check_len("rhs", b, 0);
    }
    if b.is_empty() || b.len() % nv != 0 {
        return Err(DynamicsError::DimensionMismatch {
            what: "rhs",
            expected: nv * (b.len() / nv).max(1),
            actual: b.len(),
        });
    }
    check_vector("rhs", b, b.len())?;
    for x in b.chunks_exact_mut(nv) {
        solve_in_place(&data.factor, &data.dof_parent, x);
    }
    Ok(())
}

/// `x ← M⁻¹·x` with `M = Lᵀ·D·L` stored in `h` (`L` strictly below the diagonal, `D` on it).
#[inline]
pub(crate) fn solve_in_place(h: &[f64], parent: &[usize], x: &mut [f64]) {
    let nv = x.len();
    // Lᵀ·y = b: from the leaves up.
    for i in (0..nv).rev() {
        let xi = x[i];
        let mut j = parent[i];
        while j != NO_PARENT {
            x[j] -= h[i * nv + j] * xi;
            j = parent[j];
        }
    }
    // D·z = y.
    for i in 0..nv {
        x[i] /= h[i * nv + i];
    }
    // L·x = z: from the root down.
    for i in 0..nv {
        let mut s = x[i];
        let mut j = parent[i];
        while j != NO_PARENT {
            s -= h[i * nv + j] * x[j];
            j = parent[j];
        }
        x[i] = s;
    }
}

/// The inverse of the mass matrix at `q`: `nv x nv`, row-major, full and symmetric, stored in
/// [`DynamicsData::mass_matrix_inverse`] and returned. [`DynamicsData::mass_matrix`] holds
/// `M(q)` afterwards and the factorization is ready for [`solve_mass_matrix`].
///
/// Computed from the tree-sparse factorization: with `P = L⁻¹` (which keeps `L`'s sparsity),
/// `M⁻¹ = P·D⁻¹·Pᵀ = Σₖ pₖ·pₖᵀ / Dₖ`, where column `pₖ` is nonzero only on the subtree of
/// degree of freedom `k`. Allocates nothing.
///
/// # Errors
/// As [`factorize_mass_matrix`] (a singular mass matrix has no inverse).
#[doc(alias = "minverse")]
#[doc(alias = "compute_minverse")]
pub fn mass_matrix_inverse<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
) -> Result<&'d [f64], DynamicsError> {
    factorize_mass_matrix(model, data, q)?;
    invert(data);
    Ok(&data.mass_matrix_inverse)
}

/// Fills `data.mass_matrix_inverse` from the factorization.
fn invert(data: &mut DynamicsData) {
    let nv = data.nv;
    let h = &data.factor;
    let parent = &data.dof_parent;
    let end = &data.dof_subtree_end;
    let minv = &mut data.mass_matrix_inverse;
    minv.fill(0.0);
    // Column k of P lives in rhs[k..end[k]]; P[i][k] = -Σ_{l ∈ anc(i), l ≥ k} L[i][l]·P[l][k].
    let p = &mut data.rhs;
    for k in 0..nv {
        let e = end[k];
        p[k] = 1.0;
        for i in k + 1..e {
            let mut s = 0.0;
            let mut l = parent[i];
            while l != NO_PARENT && l >= k {
                s -= h[i * nv + l] * p[l];
                l = parent[l];
            }
            p[i] = s;
        }
        let dinv = 1.0 / h[k * nv + k];
        // Lower triangle of the rank-one update on the block [k, e) x [k, e).
        for i in k..e {
            let pi = p[i] * dinv;
            let row = &mut minv[i * nv + k..i * nv + i + 1];
            for (r, pj) in row.iter_mut().zip(&p[k..=i]) {
                *r += pi * pj;
            }
        }
    }
    for i in 0..nv {
        for j in i + 1..nv {
            minv[i * nv + j] = minv[j * nv + i];
        }
    }
}
