//! Moving a block's coordinates into the lanes, and its results out of them: `R` rows of `L`
//! lanes become `L` records of `R` numbers (a [`Motion`] is 6, an [`Se3`] 12), each stored in its
//! own state's place, and the reverse for the states' coordinates.
//!
//! The plain form reads and writes one number at a time (12 loads and 12 stores per placement and
//! state). With AVX-512F the rows are loaded whole, transposed in registers (8×8 blocks of
//! unpacks and 128-bit shuffles) and each state's record stored with one or two vector stores.
//! Only numbers move, so the results are the same bit for bit either way.

use super::simd::Simd;
use kinetree_model::spatial::lanes::{LMotion, LSe3, Lanes};
use kinetree_model::spatial::{Motion, Se3};

/// How a kernel moves records out of the lanes: chosen once per call from the workspace's
/// [`Simd`], so that every instruction set's path runs in the tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Io {
    /// One number at a time.
    Plain,
    /// 8×8 transposes in AVX-512F registers (8 lanes only).
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Io {
    /// The transposes for a kernel run with `simd`: AVX-512F only when the CPU has it (checked
    /// here, so the `unsafe` calls below rely on nothing else).
    #[must_use]
    pub fn new(simd: Simd) -> Self {
        #[cfg(target_arch = "x86_64")]
        if simd == Simd::Avx512 && std::arch::is_x86_feature_detected!("avx512f") {
            return Self::Avx512;
        }
        let _ = simd;
        Self::Plain
    }

    /// `out[first + k·stride] = x.lane(k)` for the first `count` lanes.
    #[inline(always)]
    pub(crate) fn store_motions<const L: usize>(
        self,
        x: &LMotion<L>,
        out: &mut [Motion],
        first: usize,
        stride: usize,
        count: usize,
    ) {
        #[cfg(target_arch = "x86_64")]
        if let (Self::Avx512, Some(rows)) = (self, rows8(&motion_rows(x))) {
            let last = first + (count.max(1) - 1) * stride;
            if count <= 8 && last < out.len() {
                #[allow(unsafe_code, reason = "AVX-512F calls")]
                // SAFETY: `Io::Avx512` exists only when the CPU has AVX-512F (`Io::new`).
                unsafe {
                    avx512::store::<6, 1>(&rows, Place::motions(out, first, stride), count)
                };
                return;
            }
        }
        for k in 0..count {
            out[first + k * stride] = x.lane(k);
        }
    }

    /// Moves the `nq` coordinates of the block of states `idx` (rows of `q`) into lanes:
    /// `out[j]` becomes coordinate `j` of every lane (`out` holds `nq` rounded up to 8). Returns
    /// the block's finiteness probe: NaN in a lane where a coordinate is not finite, ±0
    /// elsewhere.
    #[inline(always)]
    pub fn load_coordinates<const L: usize>(
        self,
        q: &[f64],
        nq: usize,
        idx: &[usize; L],
        out: &mut [Lanes<L>],
    ) -> Lanes<L> {
        #[cfg(target_arch = "x86_64")]
        if let (Self::Avx512, Some(out8)) = (self, as8(out)) {
            let starts: [usize; 8] = core::array::from_fn(|l| idx[l % L] * nq);
            if starts.iter().all(|&s| s + nq <= q.len()) && out8.len() >= nq.next_multiple_of(8) {
                #[allow(unsafe_code, reason = "AVX-512F calls")]
                // SAFETY: `Io::Avx512` exists only when the CPU has AVX-512F (`Io::new`); every
                // row and `out` were just checked to be long enough.
                let p = unsafe { avx512::load(q, starts, nq, out8) };
                return Lanes(core::array::from_fn(|l| p[l % 8]));
            }
        }
        for l in 0..L {
            let row = &q[idx[l] * nq..(idx[l] + 1) * nq];
            for (j, x) in row.iter().enumerate() {
                out[j].0[l] = *x;
            }
        }
        let mut probe = Lanes::ZERO;
        for x in &out[..nq] {
            probe += *x * 0.0;
        }
        probe
    }

    /// The reverse of [`Io::load_coordinates`]: `out[(first + k)·stride + j] = rows[j]` of lane
    /// `k`, for the `nrows` rows and the first `count` lanes (`rows` holds `nrows` rounded up to
    /// 8).
    #[inline(always)]
    pub fn store_coordinates<const L: usize>(
        self,
        rows: &[Lanes<L>],
        nrows: usize,
        out: &mut [f64],
        first: usize,
        stride: usize,
        count: usize,
    ) {
        #[cfg(target_arch = "x86_64")]
        if let (Self::Avx512, Some(rows8)) = (self, as8_ref(rows)) {
            let end = (first + count.max(1) - 1) * stride + nrows;
            if count <= 8 && end <= out.len() && rows8.len() >= nrows.next_multiple_of(8) {
                #[allow(unsafe_code, reason = "AVX-512F calls")]
                // SAFETY: `Io::Avx512` exists only when the CPU has AVX-512F (`Io::new`); the
                // rows and every record written were just checked to be in bounds.
                unsafe {
                    avx512::store_rows(
                        rows8,
                        nrows,
                        out.as_mut_ptr().add(first * stride),
                        stride,
                        count,
                    )
                };
                return;
            }
        }
        for k in 0..count {
            let record = &mut out[(first + k) * stride..(first + k) * stride + nrows];
            for (j, x) in record.iter_mut().enumerate() {
                *x = rows[j].0[k];
            }
        }
    }

    /// Writes `x` as a row-major 4×4 homogeneous matrix (rotation rows with the translation as
    /// last column, then `0 0 0 1`), lane `k` as matrix `slot` of `per_state` in state
    /// `first + k`'s record: `out[((first + k)·per_state + slot)·16 ..][..16]`, for the first
    /// `count` lanes.
    #[inline(always)]
    pub(crate) fn store_matrix<const L: usize>(
        self,
        x: &LSe3<L>,
        out: &mut [f64],
        slot: usize,
        per_state: usize,
        first: usize,
        count: usize,
    ) {
        let (r, t) = (&x.rotation, &x.translation);
        let (c0, c1, c2) = (&r.x_axis, &r.y_axis, &r.z_axis);
        let (zero, one) = (Lanes::ZERO, Lanes::splat(1.0));
        let rows = [
            c0.x, c1.x, c2.x, t.x, c0.y, c1.y, c2.y, t.y, c0.z, c1.z, c2.z, t.z, zero, zero, zero,
            one,
        ];
        self.store_coordinates(
            &rows,
            16,
            &mut out[slot * 16..],
            first,
            per_state * 16,
            count,
        );
    }

    /// Sets every motion of `out` to zero (without a call to `memset`, whose set-up costs more
    /// than the few columns of a run off a Jacobian's path).
    #[inline(always)]
    pub(crate) fn zero_motions(self, out: &mut [Motion]) {
        #[cfg(target_arch = "x86_64")]
        if self == Self::Avx512 {
            #[allow(unsafe_code, reason = "AVX-512F calls")]
            // SAFETY: `Io::Avx512` exists only when the CPU has AVX-512F (`Io::new`); the
            // pointer starts `6·out.len()` writable numbers.
            unsafe {
                avx512::zero(out.as_mut_ptr().cast::<f64>(), 6 * out.len())
            };
            return;
        }
        out.fill(Motion::ZERO);
    }

    /// `out[first + k·stride] = x.lane(k)` for the first `count` lanes.
    #[inline(always)]
    pub(crate) fn store_placements<const L: usize>(
        self,
        x: &LSe3<L>,
        out: &mut [Se3],
        first: usize,
        stride: usize,
        count: usize,
    ) {
        #[cfg(target_arch = "x86_64")]
        if let (Self::Avx512, Some(rows)) = (self, rows8(&se3_rows(x))) {
            let last = first + (count.max(1) - 1) * stride;
            if count <= 8 && last < out.len() {
                #[allow(unsafe_code, reason = "AVX-512F calls")]
                // SAFETY: `Io::Avx512` exists only when the CPU has AVX-512F (`Io::new`).
                unsafe {
                    avx512::store::<12, 2>(&rows, Place::placements(out, first, stride), count)
                };
                return;
            }
        }
        for k in 0..count {
            out[first + k * stride] = x.lane(k);
        }
    }
}

/// The 6 rows of a lane motion, in `Motion`'s field order.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn motion_rows<const L: usize>(x: &LMotion<L>) -> [Lanes<L>; 6] {
    let (a, b) = (&x.linear, &x.angular);
    [a.x, a.y, a.z, b.x, b.y, b.z]
}

/// The 12 rows of a lane placement, in `Se3`'s field order (the rotation's columns, then the
/// translation).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn se3_rows<const L: usize>(x: &LSe3<L>) -> [Lanes<L>; 12] {
    let (r, t) = (&x.rotation, &x.translation);
    let (c0, c1, c2) = (&r.x_axis, &r.y_axis, &r.z_axis);
    [
        c0.x, c0.y, c0.z, c1.x, c1.y, c1.z, c2.x, c2.y, c2.z, t.x, t.y, t.z,
    ]
}

/// The rows as 8-lane arrays when `L` is 8 (decided at compile time).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn rows8<const L: usize, const R: usize>(rows: &[Lanes<L>; R]) -> Option<[[f64; 8]; R]> {
    if L != 8 {
        return None;
    }
    Some(core::array::from_fn(|i| {
        <[f64; 8]>::try_from(&rows[i].0[..]).unwrap_or_default()
    }))
}

/// `x` as 8-lane values when `L` is 8 (decided at compile time).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn as8<const L: usize>(x: &mut [Lanes<L>]) -> Option<&mut [Lanes<8>]> {
    if L != 8 {
        return None;
    }
    #[allow(unsafe_code, reason = "a cast between one type's two spellings")]
    // SAFETY: `L` is 8, so `Lanes<L>` is `Lanes<8>`: same type, same length.
    Some(unsafe { &mut *(core::ptr::from_mut(x) as *mut [Lanes<8>]) })
}

/// `x` as 8-lane values when `L` is 8 (decided at compile time).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn as8_ref<const L: usize>(x: &[Lanes<L>]) -> Option<&[Lanes<8>]> {
    if L != 8 {
        return None;
    }
    #[allow(unsafe_code, reason = "a cast between one type's two spellings")]
    // SAFETY: `L` is 8, so `Lanes<L>` is `Lanes<8>`: same type, same length.
    Some(unsafe { &*(core::ptr::from_ref(x) as *const [Lanes<8>]) })
}

/// Where the records of a block go: the first state's record and the distance to the next, as
/// a raw pointer into a slice whose bounds the caller checked for every record written.
#[cfg(target_arch = "x86_64")]
struct Place {
    first: *mut f64,
    /// In numbers.
    stride: usize,
}

#[cfg(target_arch = "x86_64")]
impl Place {
    fn motions(out: &mut [Motion], first: usize, stride: usize) -> Self {
        // `Motion` is `repr(C)`: six `f64` in field order.
        Self {
            first: out.as_mut_ptr().wrapping_add(first).cast::<f64>(),
            stride: 6 * stride,
        }
    }

    fn placements(out: &mut [Se3], first: usize, stride: usize) -> Self {
        // `Se3` is `repr(C)`: twelve `f64` in field order.
        Self {
            first: out.as_mut_ptr().wrapping_add(first).cast::<f64>(),
            stride: 12 * stride,
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code, reason = "AVX-512F loads and stores through pointers")]
mod avx512 {
    use super::Place;
    use core::arch::x86_64::{
        __m512d, _mm256_storeu_pd, _mm512_add_pd, _mm512_castpd512_pd256, _mm512_extractf64x4_pd,
        _mm512_loadu_pd, _mm512_mask_storeu_pd, _mm512_maskz_loadu_pd, _mm512_mul_pd,
        _mm512_permutex2var_pd, _mm512_set_epi64, _mm512_setzero_pd, _mm512_shuffle_f64x2,
        _mm512_storeu_pd, _mm512_unpackhi_pd, _mm512_unpacklo_pd,
    };
    use kinetree_model::spatial::lanes::Lanes;

    /// Moves `nq` numbers from each of the eight rows of `q` starting at `starts` into lanes
    /// (`out[j]` = number `j` of every row, `out[nq..]` up to the next multiple of 8 zero), eight
    /// numbers at a time with an 8×8 transpose; returns the probe `Σ x·0` of every row.
    ///
    /// # Safety
    /// The CPU has AVX-512F, `starts[l] + nq <= q.len()` for every row, and
    /// `out.len() >= nq` rounded up to 8.
    #[target_feature(enable = "avx512f")]
    #[inline]
    pub(super) unsafe fn load(
        q: &[f64],
        starts: [usize; 8],
        nq: usize,
        out: &mut [Lanes<8>],
    ) -> [f64; 8] {
        let zero = _mm512_setzero_pd();
        let mut probe = zero;
        let mut j0 = 0;
        while j0 < nq {
            let n = (nq - j0).min(8);
            let mask = if n == 8 { 0xff } else { (1u8 << n) - 1 };
            let r: [__m512d; 8] = core::array::from_fn(|l| {
                // SAFETY: numbers starts[l] + j0 .. starts[l] + j0 + n lie in `q` (the caller's
                // promise); the mask reads only those.
                unsafe { _mm512_maskz_loadu_pd(mask, q.as_ptr().add(starts[l] + j0)) }
            });
            for (j, t) in transpose(r).iter().enumerate() {
                probe = _mm512_add_pd(probe, _mm512_mul_pd(*t, zero));
                // SAFETY: `out[j0 + j]` is eight numbers (indexing checks it is there).
                unsafe { _mm512_storeu_pd(out[j0 + j].0.as_mut_ptr(), *t) };
            }
            j0 += 8;
        }
        let mut p = [0.0; 8];
        // SAFETY: `p` is eight numbers.
        unsafe { _mm512_storeu_pd(p.as_mut_ptr(), probe) };
        p
    }

    /// Stores `nrows` rows of eight lanes as eight records of `nrows` numbers (the first
    /// `count` of them, record `k` from `at + k·stride`), eight rows at a time with an 8×8
    /// transpose.
    ///
    /// # Safety
    /// The CPU has AVX-512F, `rows.len() >= nrows` rounded up to 8, `count <= 8`, and
    /// `at + k·stride` starts `nrows` writable numbers for every `k < count`.
    #[target_feature(enable = "avx512f")]
    #[inline]
    pub(super) unsafe fn store_rows(
        rows: &[Lanes<8>],
        nrows: usize,
        at: *mut f64,
        stride: usize,
        count: usize,
    ) {
        let mut j0 = 0;
        while j0 < nrows {
            let n = (nrows - j0).min(8);
            let mask = if n == 8 { 0xff } else { (1u8 << n) - 1 };
            // SAFETY: rows j0..j0 + 8 exist (the caller's promise), eight numbers each.
            let r: [__m512d; 8] =
                core::array::from_fn(|i| unsafe { _mm512_loadu_pd(rows[j0 + i].0.as_ptr()) });
            for (k, col) in transpose(r).iter().enumerate().take(count) {
                // SAFETY: record k's numbers j0..j0 + n are writable (the caller's promise).
                unsafe { _mm512_mask_storeu_pd(at.add(k * stride + j0), mask, *col) };
            }
            j0 += 8;
        }
    }

    /// Writes `len` zeros from `at`, eight at a time.
    ///
    /// # Safety
    /// The CPU has AVX-512F and `at` starts `len` writable numbers.
    #[target_feature(enable = "avx512f")]
    #[inline]
    pub(super) unsafe fn zero(at: *mut f64, len: usize) {
        let z = _mm512_setzero_pd();
        let mut i = 0;
        while i + 8 <= len {
            // SAFETY: numbers i..i + 8 are writable.
            unsafe { _mm512_storeu_pd(at.add(i), z) };
            i += 8;
        }
        if i < len {
            let mask = (1u8 << (len - i)) - 1;
            // SAFETY: the mask writes numbers i..len only.
            unsafe { _mm512_mask_storeu_pd(at.add(i), mask, z) };
        }
    }

    /// The 8×8 transpose: `out[k][i] = rows[i][k]`.
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn transpose(r: [__m512d; 8]) -> [__m512d; 8] {
        // Pairs of rows, interleaved: 128-bit block j of t[2i] holds lane 2j of rows 2i, 2i+1;
        // of t[2i+1], lane 2j+1.
        let t = [
            _mm512_unpacklo_pd(r[0], r[1]),
            _mm512_unpackhi_pd(r[0], r[1]),
            _mm512_unpacklo_pd(r[2], r[3]),
            _mm512_unpackhi_pd(r[2], r[3]),
            _mm512_unpacklo_pd(r[4], r[5]),
            _mm512_unpackhi_pd(r[4], r[5]),
            _mm512_unpacklo_pd(r[6], r[7]),
            _mm512_unpackhi_pd(r[6], r[7]),
        ];
        // Four rows: u[0] holds lanes 0 and 4 of rows 0..4 (as two 256-bit halves), u[1] lanes
        // 2 and 6, u[2] lanes 1 and 5, u[3] lanes 3 and 7; u[4..] the same for rows 4..8.
        let even = |a: __m512d, b: __m512d| _mm512_shuffle_f64x2::<0b10_00_10_00>(a, b);
        let odd = |a: __m512d, b: __m512d| _mm512_shuffle_f64x2::<0b11_01_11_01>(a, b);
        let u = [
            even(t[0], t[2]),
            odd(t[0], t[2]),
            even(t[1], t[3]),
            odd(t[1], t[3]),
            even(t[4], t[6]),
            odd(t[4], t[6]),
            even(t[5], t[7]),
            odd(t[5], t[7]),
        ];
        [
            even(u[0], u[4]),
            even(u[2], u[6]),
            even(u[1], u[5]),
            even(u[3], u[7]),
            odd(u[0], u[4]),
            odd(u[2], u[6]),
            odd(u[1], u[5]),
            odd(u[3], u[7]),
        ]
    }

    /// Stores the first `count` lanes of four rows as records of four numbers, `at + k·stride`
    /// for lane `k`: a 4×8 transpose in 4 unpacks and 4 two-source permutes (each vector then
    /// holds two records, stored as two 256-bit halves), where the 8×8 transpose of [`store`]
    /// took 24 shuffles on four rows and four zeros.
    ///
    /// # Safety
    /// The CPU has AVX-512F, `count <= 8`, and `at + k·stride` starts four writable numbers for
    /// every `k < count`.
    #[target_feature(enable = "avx512f")]
    #[inline]
    unsafe fn store4(r: [__m512d; 4], at: *mut f64, stride: usize, count: usize) {
        // unpacklo(r0, r1) = [r0[0], r1[0], r0[2], r1[2], r0[4], r1[4], r0[6], r1[6]], and
        // likewise for the other pairs; each permute picks two of these pairs from each input.
        let (lo01, hi01) = (
            _mm512_unpacklo_pd(r[0], r[1]),
            _mm512_unpackhi_pd(r[0], r[1]),
        );
        let (lo23, hi23) = (
            _mm512_unpacklo_pd(r[2], r[3]),
            _mm512_unpackhi_pd(r[2], r[3]),
        );
        // Element i of the index takes element (i & 7) of the first input, or of the second
        // when bit 3 is set: [a0, a1, b0, b1, a2, a3, b2, b3] and the same two pairs on.
        let first = _mm512_set_epi64(11, 10, 3, 2, 9, 8, 1, 0);
        let second = _mm512_set_epi64(15, 14, 7, 6, 13, 12, 5, 4);
        // Records (0, 2), (4, 6), (1, 3), (5, 7).
        let pairs = [
            (_mm512_permutex2var_pd(lo01, first, lo23), 0),
            (_mm512_permutex2var_pd(lo01, second, lo23), 4),
            (_mm512_permutex2var_pd(hi01, first, hi23), 1),
            (_mm512_permutex2var_pd(hi01, second, hi23), 5),
        ];
        for (two, k) in pairs {
            if k < count {
                // SAFETY: record k starts four writable numbers (the caller's promise).
                unsafe { _mm256_storeu_pd(at.add(k * stride), _mm512_castpd512_pd256(two)) };
            }
            if k + 2 < count {
                // SAFETY: as above, for record k + 2.
                unsafe {
                    _mm256_storeu_pd(at.add((k + 2) * stride), _mm512_extractf64x4_pd::<1>(two))
                };
            }
        }
    }

    /// Stores the first `count` lanes of `R` rows as records of `R` numbers: `G` groups of up to
    /// eight rows, each transposed and stored with one (masked) vector store per state.
    ///
    /// # Safety
    /// The CPU has AVX-512F, `count <= 8`, and `at.first + k·at.stride` starts `R` writable
    /// numbers for every `k < count`.
    #[target_feature(enable = "avx512f")]
    #[inline]
    pub(super) unsafe fn store<const R: usize, const G: usize>(
        rows: &[[f64; 8]; R],
        at: Place,
        count: usize,
    ) {
        for g in 0..G {
            let n = (R - 8 * g).min(8);
            let r: [__m512d; 8] = core::array::from_fn(|i| {
                if i < n {
                    // SAFETY: a row is eight numbers.
                    unsafe { _mm512_loadu_pd(rows[8 * g + i].as_ptr()) }
                } else {
                    _mm512_setzero_pd()
                }
            });
            if n == 4 {
                // SAFETY: the caller's promise, for numbers 8g..8g + 4 of each record.
                unsafe {
                    store4(
                        [r[0], r[1], r[2], r[3]],
                        at.first.add(8 * g),
                        at.stride,
                        count,
                    )
                };
                continue;
            }
            let cols = transpose(r);
            let mask = if n == 8 { 0xff } else { (1u8 << n) - 1 };
            for (k, col) in cols.iter().enumerate().take(count) {
                // SAFETY: record k starts `R` writable numbers (the caller's promise), of which
                // the mask writes numbers 8g..8g + n.
                unsafe { _mm512_mask_storeu_pd(at.first.add(k * at.stride + 8 * g), mask, *col) };
            }
        }
    }
}
