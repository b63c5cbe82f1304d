//! Moving a block's results out of the lanes: `R` rows of `L` lanes become `L` records of `R`
//! numbers (a [`Motion`] is 6, an [`Se3`] 12), each stored in its own state's place.
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
pub(crate) enum Io {
    /// One number at a time.
    Plain,
    /// 8×8 transposes in AVX-512F registers (8 lanes only).
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Io {
    /// The transposes for a kernel run with `simd`: AVX-512F only when the CPU has it (checked
    /// here, so the `unsafe` calls below rely on nothing else).
    pub(crate) fn new(simd: Simd) -> Self {
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
#[inline(always)]
fn motion_rows<const L: usize>(x: &LMotion<L>) -> [Lanes<L>; 6] {
    let (a, b) = (&x.linear, &x.angular);
    [a.x, a.y, a.z, b.x, b.y, b.z]
}

/// The 12 rows of a lane placement, in `Se3`'s field order (the rotation's columns, then the
/// translation).
#[inline(always)]
fn se3_rows<const L: usize>(x: &LSe3<L>) -> [Lanes<L>; 12] {
    let (r, t) = (&x.rotation, &x.translation);
    let (c0, c1, c2) = (&r.x_axis, &r.y_axis, &r.z_axis);
    [
        c0.x, c0.y, c0.z, c1.x, c1.y, c1.z, c2.x, c2.y, c2.z, t.x, t.y, t.z,
    ]
}

/// The rows as 8-lane arrays when `L` is 8 (decided at compile time).
#[inline(always)]
fn rows8<const L: usize, const R: usize>(rows: &[Lanes<L>; R]) -> Option<[[f64; 8]; R]> {
    if L != 8 {
        return None;
    }
    Some(core::array::from_fn(|i| {
        <[f64; 8]>::try_from(&rows[i].0[..]).unwrap_or_default()
    }))
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
        __m512d, _mm512_loadu_pd, _mm512_mask_storeu_pd, _mm512_setzero_pd, _mm512_shuffle_f64x2,
        _mm512_storeu_pd, _mm512_unpackhi_pd, _mm512_unpacklo_pd,
    };

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
