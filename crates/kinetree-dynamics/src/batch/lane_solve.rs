//! `M⁻¹` and `-M⁻¹·[X_q X_v]` for a block of states at once, from each state's tree-sparse
//! factor `M = Lᵀ·D·L`, with the states in SIMD lanes.
//!
//! The one-state solves (`derivatives/solve.rs`) vectorise over a row's columns; here each
//! matrix entry is a [`Lanes`] value and every operation covers the block's states, so nothing
//! is padded and no state's solve runs alone. Every entry sees the one-state operations in the
//! same order (the first pass updates the same column ranges, so even the signs of zeros
//! agree): the results are equal bit for bit.

use crate::derivatives::solve::DofTree;
use kinetree_kinematics::batch::Io;
use kinetree_kinematics::spatial::lanes::Lanes;

/// The factor, the pair and `M⁻¹` of a block of states in lanes, and the tree's structure.
#[derive(Clone, Debug)]
pub(crate) struct LaneSolve<const L: usize> {
    nv: usize,
    /// The ancestors of each degree of freedom.
    tree: DofTree,
    /// The columns that row `i` updates in the first pass: those `i`'s padded segments cover,
    /// without the padding, as `(half, lo, hi)` with `half` 0 for `X_q` and 1 for `X_v`
    /// (`seg[seg_start[i]..seg_start[i + 1]]`).
    seg: Vec<(usize, usize, usize)>,
    seg_start: Vec<usize>,
    /// Scratch: `L[i][j]` along the ancestors `j` of one row.
    l: Vec<Lanes<L>>,
    /// The factor, `nv x nv` row-major: `D` on the diagonal, `L[i][j]` at the ancestors `j` of
    /// row `i` (nothing else is read).
    pub(crate) factor: Vec<Lanes<L>>,
    /// The pair: `X_q` then `X_v`, each `nv x nv` row-major from a multiple of 8 (`half`),
    /// which [`neg_solve`](Self::neg_solve) turns into `-M⁻¹·X_q` and `-M⁻¹·X_v`.
    pub(crate) pair: Vec<Lanes<L>>,
    /// Where `X_v` starts in `pair`: `nv²` rounded up to 8, as the transposes of
    /// `Io::store_coordinates` want.
    pub(crate) half: usize,
    /// `M⁻¹`, `nv x nv` row-major (`half` long), after [`invert`](Self::invert).
    inverse: Vec<Lanes<L>>,
}

impl<const L: usize> Default for LaneSolve<L> {
    /// Empty buffers (for a lane width that is not used).
    fn default() -> Self {
        Self::new(DofTree::new(&[]), 0)
    }
}

impl<const L: usize> LaneSolve<L> {
    /// The buffers for the tree `tree` (of `nv` degrees of freedom).
    pub(crate) fn new(tree: DofTree, nv: usize) -> Self {
        let np = tree.padded();
        let (mut seg, mut seg_start) = (Vec::new(), vec![0]);
        for i in 0..nv {
            for &(lo, hi) in tree.segments(i) {
                // A padded range can run from the first half into the second.
                let first = (0, lo.min(nv), hi.min(nv));
                let second = (1, lo.max(np) - np, (hi.max(np) - np).min(nv));
                for (h, a, b) in [first, second] {
                    if a < b {
                        seg.push((h, a, b));
                    }
                }
            }
            seg_start.push(seg.len());
        }
        let depth = (0..nv).map(|i| tree.ancestors(i).len()).max().unwrap_or(0);
        let half = (nv * nv).next_multiple_of(8);
        Self {
            nv,
            tree,
            seg,
            seg_start,
            l: vec![Lanes::ZERO; depth],
            factor: vec![Lanes::ZERO; nv * nv],
            pair: vec![Lanes::ZERO; 2 * half],
            half,
            inverse: vec![Lanes::ZERO; half],
        }
    }

    /// The ancestors of `i` (ascending), with `L[i][j]` along them gathered into `l`.
    #[inline(always)]
    fn row<'a>(
        tree: &'a DofTree,
        factor: &[Lanes<L>],
        l: &'a mut [Lanes<L>],
        nv: usize,
        i: usize,
    ) -> (&'a [usize], &'a [Lanes<L>]) {
        let anc = tree.ancestors(i);
        let l = &mut l[..anc.len()];
        let row = &factor[i * nv..(i + 1) * nv];
        for (x, &j) in l.iter_mut().zip(anc) {
            *x = row[j];
        }
        (anc, l)
    }

    /// `inverse ← M⁻¹` (as `DofTree::invert`: row by row, each mirrored at once).
    #[inline(always)]
    pub(crate) fn invert(&mut self) {
        let nv = self.nv;
        let Self {
            tree,
            l,
            factor,
            inverse,
            ..
        } = self;
        for i in 0..nv {
            let d = factor[i * nv + i];
            let (anc, l) = Self::row(tree, factor, l, nv, i);
            let (above, below) = inverse.split_at_mut(i * nv);
            let row = &mut below[..nv];
            for (c, out) in row[..i].iter_mut().enumerate() {
                *out = minus_along(Lanes::ZERO, anc, l, above, nv, c);
            }
            row[i] = minus_along(d.map(|d| 1.0 / d), anc, l, row, 1, 0);
            for (c, &x) in row[..i].iter().enumerate() {
                above[c * nv + i] = x;
            }
        }
    }

    /// `pair ← -M⁻¹·pair` (as `DofTree::neg_solve_filled`): `Lᵀ·Y = X` from the leaves up on
    /// the columns each row can touch, then `L·out = -D⁻¹·Y` from the root down.
    #[inline(always)]
    pub(crate) fn neg_solve(&mut self) {
        let nv = self.nv;
        let Self {
            tree,
            seg,
            seg_start,
            l,
            factor,
            pair,
            half,
            ..
        } = self;
        let (xq, xv) = pair.split_at_mut(*half);
        let mut halves = [&mut xq[..nv * nv], &mut xv[..nv * nv]];
        for i in (1..nv).rev() {
            let (anc, l) = Self::row(tree, factor, l, nv, i);
            if anc.is_empty() {
                continue;
            }
            for &(h, lo, hi) in &seg[seg_start[i]..seg_start[i + 1]] {
                let (above, below) = halves[h].split_at_mut(i * nv);
                for (c, &x) in below.iter().enumerate().take(hi).skip(lo) {
                    for (&j, &lj) in anc.iter().zip(l.iter()) {
                        above[j * nv + c] -= lj * x;
                    }
                }
            }
        }
        for i in 0..nv {
            let scale = factor[i * nv + i].map(|d| -1.0 / d);
            let (anc, l) = Self::row(tree, factor, l, nv, i);
            for x in &mut halves {
                let (above, below) = x.split_at_mut(i * nv);
                for (c, out) in below[..nv].iter_mut().enumerate() {
                    *out = minus_along(*out * scale, anc, l, above, nv, c);
                }
            }
        }
    }

    /// Writes the solves of the states `first..first + count` (lane `k` is state `first + k`):
    /// `-M⁻¹·X_q`, `-M⁻¹·X_v` and `M⁻¹` into `dq`, `dv` and `inverse` (each state's `nv x nv`
    /// row-major).
    #[inline(always)]
    pub(crate) fn store(
        &self,
        io: Io,
        first: usize,
        count: usize,
        [dq, dv, inverse]: [&mut [f64]; 3],
    ) {
        let (nn, half) = (self.nv * self.nv, self.half);
        let (xq, xv) = self.pair.split_at(half);
        io.store_coordinates(xq, nn, dq, first, nn, count);
        io.store_coordinates(xv, nn, dv, first, nn, count);
        io.store_coordinates(&self.inverse, nn, inverse, first, nn, count);
    }
}

/// `acc - Σ l[k]·m[anc[k]·stride + c]`, subtracted term by term in ancestor order (as the
/// one-state `accumulate`).
#[inline(always)]
fn minus_along<const L: usize>(
    mut acc: Lanes<L>,
    anc: &[usize],
    l: &[Lanes<L>],
    m: &[Lanes<L>],
    stride: usize,
    c: usize,
) -> Lanes<L> {
    for (&j, &lj) in anc.iter().zip(l) {
        acc -= lj * m[j * stride + c];
    }
    acc
}
