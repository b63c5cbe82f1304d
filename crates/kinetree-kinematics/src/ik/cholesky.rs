//! A small dense Cholesky factorisation for the solver's normal equations.
//!
//! The systems are `(JᵀJ + λI)` with `n` = the number of moving coordinates (6 or 7 for an arm, up
//! to a few dozen for a humanoid). At these sizes a plain row-oriented loop beats faer's blocked
//! `cholesky_in_place` + `solve_in_place` (measured 2x faster for n = 6, 7; see the commit
//! message), and it keeps faer out of this crate.

/// The dot product of two equally long slices (four accumulators, so it vectorises).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
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

/// Factorises the symmetric positive definite `n x n` matrix `a` (row-major; only the lower
/// triangle is read) in place into `L` with `a = L Lᵀ` (lower triangle). Returns `false` when a
/// pivot is not positive (the matrix is not numerically positive definite).
pub(crate) fn factor(a: &mut [f64], n: usize) -> bool {
    for i in 0..n {
        let (done, rest) = a.split_at_mut(i * n);
        let row = &mut rest[..n];
        for j in 0..i {
            let lj = &done[j * n..j * n + j + 1];
            row[j] = (row[j] - dot(&row[..j], &lj[..j])) / lj[j];
        }
        let d = row[i] - dot(&row[..i], &row[..i]);
        // Also rejects NaN.
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        row[i] = d.sqrt();
    }
    true
}

/// Solves `L Lᵀ x = b` in place (`b` becomes `x`) with the factor from [`factor`].
pub(crate) fn solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let row = &l[i * n..i * n + i + 1];
        b[i] = (b[i] - dot(&row[..i], &b[..i])) / row[i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_random_spd_system() {
        for n in [1usize, 2, 5, 7, 13] {
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
            assert!(factor(&mut l, n));
            solve(&l, n, &mut b);
            for (xi, bi) in x.iter().zip(&b) {
                assert!((xi - bi).abs() < 1e-8 * n as f64, "n = {n}: {xi} vs {bi}");
            }
        }
    }

    #[test]
    fn rejects_an_indefinite_matrix() {
        let mut a = [1.0, 2.0, 2.0, 1.0];
        assert!(!factor(&mut a, 2));
        let mut nan = [f64::NAN];
        assert!(!factor(&mut nan, 1));
    }
}
