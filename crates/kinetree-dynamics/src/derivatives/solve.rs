//! `M⁻¹` and `-M⁻¹·X` from the tree-sparse factorization `M = Lᵀ·D·L`, on whole rows.
//!
//! Every product walks the ancestor lists of the degrees of freedom (precomputed once in
//! [`DofTree`]) and keeps a chunk of up to 16 columns of the row being built in registers while
//! it accumulates over the ancestors, so each multiply-add costs one load instead of a load, a
//! load and a store.

use crate::data::NO_PARENT;

/// Runs `$f::<W>(args.., c)` over the columns `lo..hi` in chunks of `W` = 16, then 8, 4, 2 and 1.
macro_rules! by_chunks {
    ($lo:expr, $hi:expr, $f:ident $(<$($g:tt),*>)? ( $($arg:expr),* )) => {{
        let (mut c, hi) = ($lo, $hi);
        while c + 16 <= hi {
            $f::<$($($g,)*)? 16>($($arg,)* c);
            c += 16;
        }
        if c + 8 <= hi {
            $f::<$($($g,)*)? 8>($($arg,)* c);
            c += 8;
        }
        if c + 4 <= hi {
            $f::<$($($g,)*)? 4>($($arg,)* c);
            c += 4;
        }
        if c + 2 <= hi {
            $f::<$($($g,)*)? 2>($($arg,)* c);
            c += 2;
        }
        if c < hi {
            $f::<$($($g,)*)? 1>($($arg,)* c);
        }
    }};
}

/// The ancestor structure of the degrees of freedom, and padded work space for the row products.
///
/// The work matrices have rows of `np` columns (`nv` rounded up to a multiple of 4, the padding
/// kept at zero), so that every chunk is 4 or 8 columns wide.
#[derive(Clone, Debug)]
pub(crate) struct DofTree {
    nv: usize,
    np: usize,
    /// The strict ancestors of each degree of freedom (ascending): those of `i` are
    /// `anc[anc_start[i]..anc_start[i + 1]]`.
    anc: Vec<usize>,
    anc_start: Vec<usize>,
    /// The columns of the pair `[X_q X_v]` (`2·np` wide) where row `i` can be nonzero (the
    /// ancestors of `i`, `i` and its subtree, in both halves), as half-open ranges aligned to 4
    /// columns, stored as `anc`.
    seg: Vec<(usize, usize)>,
    seg_start: Vec<usize>,
    /// Scratch: the entries `L[i][j]` of one row along its ancestors `j`.
    l: Vec<f64>,
    /// `nv x 2·np`: the pair being solved.
    pair: Vec<f64>,
    /// `nv x np`: `M⁻¹` being built.
    inverse: Vec<f64>,
}

impl DofTree {
    /// The structure of the tree whose degree of freedom `i` has parent `parent[i]` (subtrees
    /// are contiguous, parents come first).
    pub(crate) fn new(parent: &[usize]) -> Self {
        let nv = parent.len();
        let np = nv.div_ceil(4) * 4;
        let mut subtree = vec![1; nv];
        for i in (0..nv).rev() {
            if parent[i] != NO_PARENT {
                subtree[parent[i]] += subtree[i];
            }
        }
        let (mut anc, mut anc_start) = (Vec::new(), vec![0]);
        let (mut seg, mut seg_start) = (Vec::new(), vec![0]);
        let mut depth_max = 0;
        for i in 0..nv {
            let first = anc.len();
            let mut j = parent[i];
            while j != NO_PARENT {
                anc.push(j);
                j = parent[j];
            }
            anc[first..].reverse();
            depth_max = depth_max.max(anc.len() - first);
            let columns = anc[first..]
                .iter()
                .copied()
                .chain(i..i + subtree[i])
                .collect::<Vec<_>>();
            let mut ranges: Vec<(usize, usize)> = Vec::new();
            for half in [0, np] {
                for &c in &columns {
                    let (lo, hi) = (half + c / 4 * 4, half + c / 4 * 4 + 4);
                    match ranges.last_mut() {
                        Some(r) if r.1 >= lo => r.1 = r.1.max(hi),
                        _ => ranges.push((lo, hi)),
                    }
                }
            }
            seg.extend(ranges);
            anc_start.push(anc.len());
            seg_start.push(seg.len());
        }
        Self {
            nv,
            np,
            anc,
            anc_start,
            seg,
            seg_start,
            l: vec![0.0; depth_max],
            pair: vec![0.0; nv * 2 * np],
            inverse: vec![0.0; nv * np],
        }
    }

    /// The strict ancestors of degree of freedom `i`, ascending.
    #[inline(always)]
    pub(crate) fn ancestors(&self, i: usize) -> &[usize] {
        &self.anc[self.anc_start[i]..self.anc_start[i + 1]]
    }

    /// The columns of the padded pair (`2·np` wide) that the solve's first pass updates from
    /// row `i`, as half-open ranges (the batched solves in lanes repeat them).
    #[inline(always)]
    pub(crate) fn segments(&self, i: usize) -> &[(usize, usize)] {
        &self.seg[self.seg_start[i]..self.seg_start[i + 1]]
    }

    /// The ancestors of `i`, and `L[i][j]` along them in `l` (`h` is the factor).
    #[inline(always)]
    fn row<'a>(
        anc: &'a [usize],
        anc_start: &[usize],
        l: &'a mut [f64],
        h: &[f64],
        nv: usize,
        i: usize,
    ) -> (&'a [usize], &'a [f64]) {
        let anc = &anc[anc_start[i]..anc_start[i + 1]];
        let l = &mut l[..anc.len()];
        let h_row = &h[i * nv..(i + 1) * nv];
        for (x, &j) in l.iter_mut().zip(anc) {
            *x = h_row[j];
        }
        (anc, l)
    }

    /// `y ← M⁻¹` (full, symmetric, row-major `nv x nv`), from the factor `h` (`L` strictly below
    /// the diagonal, `D` on it).
    ///
    /// From `L·M⁻¹ = D⁻¹·L⁻ᵀ` (upper triangular): for `j < i`, `M⁻¹[i][j] = -Σ L[i][l]·M⁻¹[l][j]`
    /// over the ancestors `l` of `i`, and `M⁻¹[i][i] = 1/D[i] - Σ L[i][l]·M⁻¹[i][l]`. Rows go in
    /// order and are mirrored at once, so every `M⁻¹[l][j]` needed is known.
    #[inline(always)]
    pub(crate) fn invert(&mut self, h: &[f64], y: &mut [f64]) {
        let (nv, np) = (self.nv, self.np);
        let Self {
            anc,
            anc_start,
            l,
            inverse,
            ..
        } = self;
        for i in 0..nv {
            let d = h[i * nv + i];
            let (anc, l) = Self::row(anc, anc_start, l, h, nv, i);
            let (above, below) = inverse.split_at_mut(i * np);
            let row = &mut below[..np];
            // Columns `i..` of the last chunk read stale values; they are overwritten below
            // (the diagonal) or by the mirror of later rows, and never read before.
            by_chunks!(0, i.div_ceil(4) * 4, accumulate<true>(above, np, anc, l, row, 0.0));
            let mut diag = 1.0 / d;
            for (&j, &lj) in anc.iter().zip(l) {
                diag -= lj * row[j];
            }
            row[i] = diag;
            for (j, &x) in row[..i].iter().enumerate() {
                above[j * np + i] = x;
            }
        }
        for (out, work) in y.chunks_exact_mut(nv).zip(inverse.chunks_exact(np)) {
            out.copy_from_slice(&work[..nv]);
        }
    }

    /// The number of columns of each half of a pair row (`nv` rounded up to a multiple of 4).
    #[inline(always)]
    pub(crate) fn padded(&self) -> usize {
        self.np
    }

    /// `out_q ← -M⁻¹·x_q` and `out_v ← -M⁻¹·x_v` for row-major `nv x nv` matrices whose row `i`
    /// is zero outside the ancestors and subtree of `i` (as the inverse-dynamics derivatives),
    /// from the factor `h`.
    #[inline(always)]
    pub(crate) fn neg_solve_pair(
        &mut self,
        h: &[f64],
        x_q: &[f64],
        x_v: &[f64],
        out_q: &mut [f64],
        out_v: &mut [f64],
    ) {
        let (nv, np) = (self.nv, self.np);
        let mut pair = core::mem::take(&mut self.pair);
        for ((row, q), v) in pair
            .chunks_exact_mut(2 * np)
            .zip(x_q.chunks_exact(nv))
            .zip(x_v.chunks_exact(nv))
        {
            row[..nv].copy_from_slice(q);
            row[np..np + nv].copy_from_slice(v);
        }
        self.neg_solve_filled(h, &mut pair, out_q, out_v);
        self.pair = pair;
    }

    /// As [`neg_solve_pair`](Self::neg_solve_pair), with the pair `[x_q x_v]` already in `pair`
    /// (`nv` rows of `2·np` columns: `x_q` in columns `0..nv`, `x_v` in `np..np + nv`, zero
    /// elsewhere), which the solve overwrites.
    ///
    /// Two triangular solves on the pair: `Lᵀ·Y = x` from the leaves up, which keeps the
    /// sparsity of `x` (row `i` only touches its ancestors' rows, on its own nonzero columns),
    /// then `L·out = -D⁻¹·Y` from the root down, on whole rows.
    #[inline(always)]
    pub(crate) fn neg_solve_filled(
        &mut self,
        h: &[f64],
        pair: &mut [f64],
        out_q: &mut [f64],
        out_v: &mut [f64],
    ) {
        let (nv, np) = (self.nv, self.np);
        let w = 2 * np;
        let Self {
            anc,
            anc_start,
            seg,
            seg_start,
            l,
            ..
        } = self;
        for i in (1..nv).rev() {
            let (anc, l) = Self::row(anc, anc_start, l, h, nv, i);
            if anc.is_empty() {
                continue;
            }
            let (above, below) = pair.split_at_mut(i * w);
            let row = &below[..w];
            for &(lo, hi) in &seg[seg_start[i]..seg_start[i + 1]] {
                by_chunks!(lo, hi, scatter(above, w, anc, l, row));
            }
        }
        for i in 0..nv {
            let scale = -1.0 / h[i * nv + i];
            let (anc, l) = Self::row(anc, anc_start, l, h, nv, i);
            let (above, below) = pair.split_at_mut(i * w);
            let row = &mut below[..w];
            by_chunks!(0, w, accumulate<false>(above, w, anc, l, row, scale));
            out_q[i * nv..(i + 1) * nv].copy_from_slice(&row[..nv]);
            out_v[i * nv..(i + 1) * nv].copy_from_slice(&row[np..np + nv]);
        }
    }
}

/// `row[c..c + W] ← scale·row[c..c + W] - Σ l[k]·above[anc[k]][c..c + W]` (`above` holds rows of
/// length `n`); with `ZERO`, the old values are not read (`0` instead).
#[inline(always)]
fn accumulate<const ZERO: bool, const W: usize>(
    above: &[f64],
    n: usize,
    anc: &[usize],
    l: &[f64],
    row: &mut [f64],
    scale: f64,
    c: usize,
) {
    let out: &mut [f64; W] = match (&mut row[c..c + W]).try_into() {
        Ok(out) => out,
        Err(_) => return,
    };
    let mut acc = [0.0; W];
    if !ZERO {
        for w in 0..W {
            acc[w] = out[w] * scale;
        }
    }
    for (&j, &lj) in anc.iter().zip(l) {
        let src: &[f64; W] = match above[j * n + c..j * n + c + W].try_into() {
            Ok(src) => src,
            Err(_) => return,
        };
        for w in 0..W {
            acc[w] -= lj * src[w];
        }
    }
    *out = acc;
}

/// `above[anc[k]][c..c + W] -= l[k]·row[c..c + W]` for every `k`.
#[inline(always)]
fn scatter<const W: usize>(
    above: &mut [f64],
    n: usize,
    anc: &[usize],
    l: &[f64],
    row: &[f64],
    c: usize,
) {
    let src: [f64; W] = match row[c..c + W].try_into() {
        Ok(src) => src,
        Err(_) => return,
    };
    for (&j, &lj) in anc.iter().zip(l) {
        let dst: &mut [f64; W] = match (&mut above[j * n + c..j * n + c + W]).try_into() {
            Ok(dst) => dst,
            Err(_) => return,
        };
        for w in 0..W {
            dst[w] -= lj * src[w];
        }
    }
}
