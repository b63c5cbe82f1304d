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
/// nonzero only when degree of freedom `j` is an ancestor of `i`, so the factorization creates
/// no fill-in and visits only ancestor pairs: O(n·Σ depth) at worst instead of O(n³)
/// (Featherstone, *Rigid Body Dynamics Algorithms*, §6.5).
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
///
/// `L` has no fill-in: `L[i][j]` is nonzero only when `j` is an ancestor of `i`, and every other
/// entry of the lower triangle stays exactly zero (as in `M`). The row updates therefore run over
/// whole contiguous prefixes `0..=i` (vectorizable) instead of walking the ancestor lists.
#[inline(always)]
pub(crate) fn factorize(model: &Model, data: &mut DynamicsData) -> Result<(), DynamicsError> {
    let nv = data.nv;
    data.factorized = false;
    let parent = &data.dof_parent;
    let h = &mut data.factor;
    let mut scale: f64 = 0.0;
    for k in 0..nv {
        let row = k * nv;
        h[row..=row + k].copy_from_slice(&data.mass_matrix[row..=row + k]);
        scale = scale.max(h[row + k]);
    }
    let tolerance = scale * PIVOT_TOLERANCE;
    let mut singular = false;
    for k in (0..nv).rev() {
        let (above, below) = h.split_at_mut(k * nv);
        let row_k = &mut below[..=k];
        let d = row_k[k];
        if d.is_nan() || d <= tolerance {
            // Drop the row so that the remaining pivots are still meaningful.
            singular = true;
            row_k[..k].fill(0.0);
            continue;
        }
        // For each ancestor i of k, nearest first: a = H[k][i] / d,
        // H[i][0..=i] -= a·H[k][0..=i], then H[k][i] = a.
        let mut i = parent[k];
        while i != NO_PARENT {
            let a = row_k[i] / d;
            let row_i = &mut above[i * nv..=i * nv + i];
            for (x, y) in row_i.iter_mut().zip(&row_k[..=i]) {
                *x -= a * y;
            }
            row_k[i] = a;
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
        // A pivot that is NaN, or a scale that is not finite, is an overflow (huge masses,
        // inertias or lengths), not a massless subtree.
        if let Some(&k) = dofs
            .iter()
            .find(|&&k| !data.factor[k * nv + k].is_finite())
            .or_else(|| (!tolerance.is_finite()).then_some(&0))
        {
            return Err(crate::error::overflow(
                model,
                data,
                "the mass matrix",
                k,
                f64::NAN,
            ));
        }
        // The world placements tell a diverged state (links far out) from a massless subtree.
        let _ = kinetree_kinematics::update_world_placements(model, &mut data.kinematics);
        return Err(crate::aba::singular_error(model, data, &dofs));
    }
    data.factorized = true;
    Ok(())
}

/// Solves `M·x = b` in place with the factorization of the last [`factorize_mass_matrix`], for
/// one or several right-hand sides: `b` holds `k` vectors of length `nv` one after the other
/// (an `nv x k` column-major matrix), each replaced by its solution. Each right-hand side costs
/// two triangular sweeps (at most `nv²` multiply-adds, fewer on branched trees); allocates
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
    if b.is_empty() || !b.len().is_multiple_of(nv) {
        return Err(DynamicsError::DimensionMismatch {
            what: "rhs",
            expected: nv * (b.len() / nv).max(1),
            actual: b.len(),
        });
    }
    check_vector("rhs", b, b.len())?;
    for x in b.chunks_exact_mut(nv) {
        solve_in_place(&data.factor, x);
    }
    Ok(())
}

/// `x ← M⁻¹·x` with `M = Lᵀ·D·L` stored in `h` (`L` strictly below the diagonal, `D` on it,
/// zeros elsewhere in the lower triangle).
#[inline]
pub(crate) fn solve_in_place(h: &[f64], x: &mut [f64]) {
    let nv = x.len();
    // Lᵀ·y = b: from the leaves up.
    for i in (1..nv).rev() {
        let xi = x[i];
        if xi != 0.0 {
            let (head, _) = x.split_at_mut(i);
            for (xj, l) in head.iter_mut().zip(&h[i * nv..i * nv + i]) {
                *xj -= l * xi;
            }
        }
    }
    // D·z = y.
    for i in 0..nv {
        x[i] /= h[i * nv + i];
    }
    // L·x = z: from the root down.
    for i in 1..nv {
        let sum: f64 = h[i * nv..i * nv + i]
            .iter()
            .zip(&x[..i])
            .map(|(l, y)| l * y)
            .sum();
        x[i] -= sum;
    }
}

/// The inverse of the mass matrix at `q`: `nv x nv`, row-major, full and symmetric, stored in
/// [`DynamicsData::mass_matrix_inverse`] and returned. [`DynamicsData::mass_matrix`] holds
/// `M(q)` afterwards and the factorization is ready for [`solve_mass_matrix`].
///
/// Computed from the tree-sparse factorization by the recurrence of `L·M⁻¹ = D⁻¹·L⁻ᵀ` (upper
/// triangular): row `i` of `M⁻¹` is `-Σ L[i][l]·(row l)` over the ancestors `l` of `i`, plus
/// `1/D[i]` on the diagonal: O(n·Σ depth). Allocates nothing.
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
    check_inputs(model, data, q, None, None)?;
    crate::crba::compute(model, data, q);
    // The row loops of the factorization and the inverse in 256-bit vectors where the CPU has
    // them (talos_full_v2: -13 % time); the CRBA sweep is latency-bound and gains nothing.
    kinetree_kinematics::with_avx2!(
        factorize_and_invert,
        (model: &Model = model, data: &mut DynamicsData = data) -> Result<(), DynamicsError>
    )?;
    Ok(&data.mass_matrix_inverse)
}

/// [`mass_matrix_inverse`] after the mass matrix: the factorization and the inverse.
#[inline(always)]
fn factorize_and_invert(model: &Model, data: &mut DynamicsData) -> Result<(), DynamicsError> {
    factorize(model, data)?;
    invert(data);
    Ok(())
}

/// Fills `data.mass_matrix_inverse` from the factorization.
///
/// From `L·Y = D⁻¹·L⁻ᵀ` (upper triangular) with `Y = M⁻¹` symmetric: for `j < i`,
/// `Y[i][j] = -Σ_{l ∈ anc(i)} L[i][l]·Y[l][j]`, and `Y[i][i] = 1/D[i] - Σ_{l ∈ anc(i)} L[i][l]·Y[i][l]`.
/// Rows are computed in order and mirrored at once, so every `Y[l][j]` needed is known.
#[inline(always)]
pub(crate) fn invert(data: &mut DynamicsData) {
    let nv = data.nv;
    let h = &data.factor;
    let parent = &data.dof_parent;
    let y = &mut data.mass_matrix_inverse;
    for i in 0..nv {
        let (above, below) = y.split_at_mut(i * nv);
        let row_i = &mut below[..=i];
        row_i.fill(0.0);
        let l_row = &h[i * nv..=i * nv + i];
        let mut l = parent[i];
        while l != NO_PARENT {
            let a = l_row[l];
            for (x, yl) in row_i[..i].iter_mut().zip(&above[l * nv..l * nv + i]) {
                *x -= a * yl;
            }
            l = parent[l];
        }
        let mut diag = 1.0 / l_row[i];
        let mut l = parent[i];
        while l != NO_PARENT {
            diag -= l_row[l] * row_i[l];
            l = parent[l];
        }
        row_i[i] = diag;
        for j in 0..i {
            above[j * nv + i] = row_i[j];
        }
    }
}
