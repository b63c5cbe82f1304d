//! A small dense Cholesky (LDLᵀ) factorisation for the solver's normal equations.
//!
//! The systems are `JᵀJ + λI` or `JJᵀ + λI`, whichever is smaller: 6 x 6 for an arm, rarely more
//! than 20 x 20 (three targets on a humanoid). At these sizes a plain row-oriented loop beats
//! faer's blocked `cholesky_in_place` + `solve_in_place` (measured in the commit messages), and it
//! keeps faer out of this crate.

/// The dot product of two equally long slices (four accumulators, so it vectorises).
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut s = [0.0f64; 4];
    let mut ca = a.chunks_exact(4);
    let mut cb = b.chunks_exact(4);
    for (x, y) in (&mut ca).zip(&mut cb) {
        s[0] += x[0] * y[0];
        s[1] += x[1] * y[1];
        s[2] += x[2] * y[2];
        s[3] += x[3] * y[3];
    }
    let mut t = (s[0] + s[2]) + (s[1] + s[3]);
    for (x, y) in ca.remainder().iter().zip(cb.remainder()) {
        t += x * y;
    }
    t
}

/// The lower triangle of `JᵀJ` (into `a`, `f x f` row-major) and `Jᵀw` (into `rhs`) for the
/// `m x f` row-major `j`, when `f` is at most 8; `false` (nothing written) otherwise. Sums run
/// over the rows in order, as the general loop's outer products do, so the result is the same;
/// with `f` known at compile time the loops unroll into registers.
pub(crate) fn normal_cols(j: &[f64], m: usize, w: &[f64], a: &mut [f64], rhs: &mut [f64]) -> bool {
    let f = j.len().checked_div(m).unwrap_or(0);
    match f {
        1 => normal_cols_fixed::<1>(j, w, a, rhs),
        2 => normal_cols_fixed::<2>(j, w, a, rhs),
        3 => normal_cols_fixed::<3>(j, w, a, rhs),
        4 => normal_cols_fixed::<4>(j, w, a, rhs),
        5 => normal_cols_fixed::<5>(j, w, a, rhs),
        6 => normal_cols_fixed::<6>(j, w, a, rhs),
        7 => normal_cols_fixed::<7>(j, w, a, rhs),
        8 => normal_cols_fixed::<8>(j, w, a, rhs),
        _ => return false,
    }
    true
}

#[inline(always)]
fn normal_cols_fixed<const F: usize>(j: &[f64], w: &[f64], a: &mut [f64], rhs: &mut [f64]) {
    let mut g = [[0.0f64; F]; F];
    let mut r = [0.0f64; F];
    for (row, &wk) in j.chunks_exact(F).zip(w) {
        let row: &[f64; F] = row.try_into().expect("chunks of F");
        for i in 0..F {
            r[i] += row[i] * wk;
            for c in 0..=i {
                g[i][c] += row[i] * row[c];
            }
        }
    }
    for (i, gi) in g.iter().enumerate() {
        a[i * F..i * F + i + 1].copy_from_slice(&gi[..=i]);
    }
    rhs[..F].copy_from_slice(&r);
}

/// The lower triangle of `JJᵀ` (into `a`, `m x m` row-major) for the `m x f` row-major `j`, when
/// `f` is at most 8; `false` (nothing written) otherwise. Each entry is [`dot`] of two rows, as
/// in the general loop.
pub(crate) fn normal_rows(j: &[f64], m: usize, a: &mut [f64]) -> bool {
    let f = j.len().checked_div(m).unwrap_or(0);
    match f {
        1 => normal_rows_fixed::<1>(j, m, a),
        2 => normal_rows_fixed::<2>(j, m, a),
        3 => normal_rows_fixed::<3>(j, m, a),
        4 => normal_rows_fixed::<4>(j, m, a),
        5 => normal_rows_fixed::<5>(j, m, a),
        6 => normal_rows_fixed::<6>(j, m, a),
        7 => normal_rows_fixed::<7>(j, m, a),
        8 => normal_rows_fixed::<8>(j, m, a),
        _ => return false,
    }
    true
}

#[inline(always)]
fn normal_rows_fixed<const F: usize>(j: &[f64], m: usize, a: &mut [f64]) {
    let rows: &[[f64; F]] = j.as_chunks::<F>().0;
    for (k, rk) in rows.iter().enumerate() {
        for (l, rl) in rows[..=k].iter().enumerate() {
            a[k * m + l] = dot(rk, rl);
        }
    }
}

/// Factorises the symmetric positive definite `n x n` matrix `a` (row-major; only the lower
/// triangle is read) in place as `a = L D Lᵀ`: the strict lower triangle of `a` becomes the unit
/// lower-triangular `L` and `inv_d` (length `n`) receives `1 / D`. No square root, one division
/// per pivot. Returns `false` when a pivot is not positive (the matrix is not numerically
/// positive definite).
pub(crate) fn factor(a: &mut [f64], n: usize, inv_d: &mut [f64]) -> bool {
    match n {
        1 => return factor_fixed::<1>(a, inv_d),
        2 => return factor_fixed::<2>(a, inv_d),
        3 => return factor_fixed::<3>(a, inv_d),
        4 => return factor_fixed::<4>(a, inv_d),
        5 => return factor_fixed::<5>(a, inv_d),
        6 => return factor_fixed::<6>(a, inv_d),
        7 => return factor_fixed::<7>(a, inv_d),
        8 => return factor_fixed::<8>(a, inv_d),
        _ => {}
    }
    for i in 0..n {
        let (done, rest) = a.split_at_mut(i * n);
        let row = &mut rest[..n];
        // First u_j = L_ij · D_j, from the finished rows of L.
        for j in 0..i {
            row[j] -= dot(&row[..j], &done[j * n..j * n + j]);
        }
        // Then D_i = a_ii - Σ u_k L_ik, and L_ik = u_k / D_k.
        let mut d = row[i];
        for k in 0..i {
            let l = row[k] * inv_d[k];
            d -= row[k] * l;
            row[k] = l;
        }
        // Also rejects NaN.
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        inv_d[i] = 1.0 / d;
    }
    true
}

/// [`factor`] for a size known at compile time (an arm's 6 x 6 or 7 x 7): the same
/// elimination on a copy held in registers and on the stack, with the loops unrolled and no
/// bounds checks inside; several times fewer instructions than the general loop at these sizes.
#[inline(always)]
fn factor_fixed<const N: usize>(a: &mut [f64], inv_d: &mut [f64]) -> bool {
    let (Some(a), Some(inv_d)) = (a.get_mut(..N * N), inv_d.get_mut(..N)) else {
        return false;
    };
    let mut l = [[0.0f64; N]; N];
    let mut id = [0.0f64; N];
    for i in 0..N {
        // u_j = L_ij · D_j, from the finished rows of L.
        let mut u = [0.0f64; N];
        for j in 0..i {
            let mut s = a[i * N + j];
            for k in 0..j {
                s -= u[k] * l[j][k];
            }
            u[j] = s;
        }
        // D_i = a_ii - Σ u_k L_ik, and L_ik = u_k / D_k.
        let mut d = a[i * N + i];
        for k in 0..i {
            let lk = u[k] * id[k];
            d -= u[k] * lk;
            l[i][k] = lk;
        }
        // Also rejects NaN.
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        id[i] = 1.0 / d;
    }
    for i in 0..N {
        a[i * N..i * N + i].copy_from_slice(&l[i][..i]);
    }
    inv_d.copy_from_slice(&id);
    true
}

/// [`solve`] for a size known at compile time.
#[inline(always)]
fn solve_fixed<const N: usize>(l: &[f64], inv_d: &[f64], b: &mut [f64]) {
    let (Some(l), Some(inv_d), Some(b)) = (l.get(..N * N), inv_d.get(..N), b.get_mut(..N)) else {
        return;
    };
    let mut x = [0.0f64; N];
    x.copy_from_slice(b);
    for i in 0..N {
        for k in 0..i {
            x[i] -= l[i * N + k] * x[k];
        }
    }
    for i in 0..N {
        x[i] *= inv_d[i];
    }
    for i in (0..N).rev() {
        for k in i + 1..N {
            x[i] -= l[k * N + i] * x[k];
        }
    }
    b.copy_from_slice(&x);
}

/// Solves `L D Lᵀ x = b` in place (`b` becomes `x`) with the factor from [`factor`].
pub(crate) fn solve(l: &[f64], n: usize, inv_d: &[f64], b: &mut [f64]) {
    match n {
        1 => return solve_fixed::<1>(l, inv_d, b),
        2 => return solve_fixed::<2>(l, inv_d, b),
        3 => return solve_fixed::<3>(l, inv_d, b),
        4 => return solve_fixed::<4>(l, inv_d, b),
        5 => return solve_fixed::<5>(l, inv_d, b),
        6 => return solve_fixed::<6>(l, inv_d, b),
        7 => return solve_fixed::<7>(l, inv_d, b),
        8 => return solve_fixed::<8>(l, inv_d, b),
        _ => {}
    }
    for i in 0..n {
        b[i] -= dot(&l[i * n..i * n + i], &b[..i]);
    }
    for (bi, id) in b[..n].iter_mut().zip(inv_d) {
        *bi *= id;
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_random_spd_system() {
        for n in [1usize, 2, 5, 6, 7, 8, 9, 13] {
            let m = n + 2;
            let j: Vec<f64> = (0..m * n)
                .map(|k| ((k * 7919 % 101) as f64) / 50.0 - 1.0)
                .collect();
            let mut a = vec![0.0; n * n];
            for r in 0..n {
                for c in 0..n {
                    a[r * n + c] = (0..m).map(|k| j[k * n + r] * j[k * n + c]).sum::<f64>()
                        + if r == c { 1e-3 } else { 0.0 };
                }
            }
            let x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
            let mut b: Vec<f64> = (0..n)
                .map(|r| (0..n).map(|c| a[r * n + c] * x[c]).sum())
                .collect();
            let mut l = a.clone();
            let mut inv = vec![0.0; n];
            assert!(factor(&mut l, n, &mut inv));
            solve(&l, n, &inv, &mut b);
            for (xi, bi) in x.iter().zip(&b) {
                assert!((xi - bi).abs() < 1e-8 * n as f64, "n = {n}: {xi} vs {bi}");
            }
        }
    }

    #[test]
    fn fixed_size_normal_equations_match_the_sums() {
        for (m, f) in [
            (6usize, 1usize),
            (6, 5),
            (6, 6),
            (6, 7),
            (3, 8),
            (12, 7),
            (6, 9),
        ] {
            let j: Vec<f64> = (0..m * f)
                .map(|k| ((k * 7919 % 101) as f64) / 50.0 - 1.0)
                .collect();
            let w: Vec<f64> = (0..m).map(|k| 0.3 * k as f64 - 0.7).collect();
            let (mut a, mut rhs) = (vec![7.0; f * f], vec![7.0; f]);
            let mut g = vec![7.0; m * m];
            let fixed = f <= 8;
            assert_eq!(normal_cols(&j, m, &w, &mut a, &mut rhs), fixed);
            assert_eq!(normal_rows(&j, m, &mut g), fixed);
            if !fixed {
                assert!(a.iter().chain(&rhs).chain(&g).all(|x| *x == 7.0));
                continue;
            }
            for r in 0..f {
                let jw: f64 = (0..m).map(|k| j[k * f + r] * w[k]).sum();
                assert!((rhs[r] - jw).abs() < 1e-12, "m {m} f {f}");
                for c in 0..=r {
                    let s: f64 = (0..m).map(|k| j[k * f + r] * j[k * f + c]).sum();
                    assert!((a[r * f + c] - s).abs() < 1e-12, "m {m} f {f}");
                }
            }
            for k in 0..m {
                for l in 0..=k {
                    let s: f64 = (0..f).map(|c| j[k * f + c] * j[l * f + c]).sum();
                    assert!((g[k * m + l] - s).abs() < 1e-12, "m {m} f {f}");
                }
            }
        }
    }

    #[test]
    fn rejects_an_indefinite_matrix() {
        let mut inv = [0.0; 2];
        let mut a = [1.0, 2.0, 2.0, 1.0];
        assert!(!factor(&mut a, 2, &mut inv));
        let mut nan = [f64::NAN];
        assert!(!factor(&mut nan, 1, &mut inv));
    }
}
