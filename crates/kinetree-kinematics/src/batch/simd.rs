//! The instruction set of the batched sweeps, chosen at run time, and the joint transforms of a
//! block of states in lanes.

use crate::joint::JointModel;
use crate::joint::transform::mimic_value;
use kinetree_model::spatial::Real;
use kinetree_model::spatial::lanes::{LSe3, Lanes};
use kinetree_model::{Body, Model};

/// The SIMD instruction set a batch workspace runs its sweeps with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Simd {
    /// Plain code (4 states per block; whatever vector instructions the build targets).
    Portable,
    /// AVX2: 4 states per block in 256-bit registers.
    Avx2,
    /// AVX-512F: 8 states per block in 512-bit registers.
    Avx512,
}

impl Simd {
    /// The widest instruction set this CPU has.
    #[must_use]
    pub fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return Self::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Self::Avx2;
            }
        }
        Self::Portable
    }

    /// Whether this CPU can run `self`.
    #[must_use]
    pub fn is_available(self) -> bool {
        match self {
            Self::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "x86_64")]
            Self::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// `self` if this CPU has it, else the widest set it has below it.
    #[must_use]
    pub fn or_available(self) -> Self {
        match self {
            Self::Avx512 if !self.is_available() => Self::Avx2.or_available(),
            Self::Avx2 if !self.is_available() => Self::Portable,
            s => s,
        }
    }

    /// The number of states evaluated side by side.
    #[must_use]
    pub fn lanes(self) -> usize {
        match self {
            Self::Avx512 => 8,
            _ => 4,
        }
    }
}

/// Calls `$kernel(args…)` (part of a one-state algorithm, `#[inline(always)]`) compiled for AVX2
/// when the CPU has it, else as built: its long vectorized loops (the rows of the mass matrix's
/// factorization and inverse) then take 4 numbers per instruction instead of 2. FMA is not
/// enabled and the compiler never reorders floating-point operations, so the results are the
/// portable build's bit for bit. The target-feature call is `unsafe` only because the feature
/// must be present, which the macro checks first.
#[macro_export]
#[doc(hidden)]
macro_rules! with_avx2 {
    ($kernel:path, ($($a:ident: $t:ty = $v:expr),* $(,)?) -> $r:ty) => {{
        let out: $r;
        #[cfg(target_arch = "x86_64")]
        {
            #[target_feature(enable = "avx2")]
            fn avx2($($a: $t),*) -> $r {
                $kernel($($a),*)
            }
            out = if std::arch::is_x86_feature_detected!("avx2") {
                #[allow(unsafe_code, reason = "the CPU was just checked for AVX2")]
                // SAFETY: the CPU has AVX2.
                unsafe { avx2($($v),*) }
            } else {
                $kernel($($v),*)
            };
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            out = $kernel($($v),*);
        }
        out
    }};
}

/// Calls `$kernel::<G…>(args…)` (a one-state sweep, `#[inline(always)]`, with the const
/// generic parameters listed in brackets, possibly none) compiled for AVX-512F with VL when the
/// CPU has them, else for AVX2, else as built. A one-state sweep is a long run of small products
/// on 3-vectors, two numbers per instruction at most: what the wider sets buy there is the
/// three-operand instruction forms (no register copies) and, with AVX-512, 32 vector registers
/// instead of 16 (fewer spills). FMA is not enabled and the compiler never reorders
/// floating-point operations, so the results are the portable build's bit for bit. The
/// target-feature calls are `unsafe` only because the features must be present, which the macro
/// checks first.
#[macro_export]
#[doc(hidden)]
macro_rules! with_simd {
    ($kernel:ident [$(const $g:ident: $gt:ty),*], ($($a:ident: $t:ty = $v:expr),* $(,)?) -> $r:ty) => {{
        let out: $r;
        #[cfg(target_arch = "x86_64")]
        {
            #[target_feature(enable = "avx512f,avx512vl")]
            #[allow(clippy::too_many_arguments, reason = "the kernel's own arguments, passed through")]
            fn avx512<$(const $g: $gt),*>($($a: $t),*) -> $r {
                $kernel::<$($g),*>($($a),*)
            }
            #[target_feature(enable = "avx2")]
            #[allow(clippy::too_many_arguments, reason = "the kernel's own arguments, passed through")]
            fn avx2<$(const $g: $gt),*>($($a: $t),*) -> $r {
                $kernel::<$($g),*>($($a),*)
            }
            out = if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512vl")
            {
                #[allow(unsafe_code, reason = "the CPU was just checked for AVX-512F and VL")]
                // SAFETY: the CPU has AVX-512F and AVX-512VL.
                unsafe { avx512::<$($g),*>($($v),*) }
            } else if std::arch::is_x86_feature_detected!("avx2") {
                #[allow(unsafe_code, reason = "the CPU was just checked for AVX2")]
                // SAFETY: the CPU has AVX2.
                unsafe { avx2::<$($g),*>($($v),*) }
            } else {
                $kernel::<$($g),*>($($v),*)
            };
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            out = $kernel::<$($g),*>($($v),*);
        }
        out
    }};
}

/// Makes the frame of the kernel this is inlined into start on an `A`-aligned address (an
/// aligned local whose address escapes makes the compiler realign the stack pointer on entry;
/// the local itself is never written): [`Page`] for the 512-bit kernels, [`Half`] for the
/// 256-bit ones. Two effects, both measured on the 512-bit kernels:
/// - spill slots take their natural alignment, so the kernel's many 512-bit register spills no
///   longer straddle two cache lines wherever the caller's stack depth put a frame that was
///   only 16-byte aligned;
/// - on a page, the frame sits at the same offset within a page on every call, from every
///   thread, so its spill slots alias (same address modulo 4 KiB, which the processor's
///   store-to-load checks compare first) the same lines of the workspace every time, not
///   whichever the caller's stack depth picked.
///
/// Before, the same kernel ran up to 20 % faster or slower from one process or build to the
/// next: batched RNEA on the panda, 100–122 ns/state with the stack's offset; with the frame
/// on a page, 97–99 at every offset, alone or on two threads at once.
#[doc(hidden)]
#[inline(always)]
pub fn align_frame<A>() {
    let local = core::mem::MaybeUninit::<A>::uninit();
    core::hint::black_box(local.as_ptr());
}

/// A page-aligned type, for [`align_frame`] in the 512-bit kernels.
#[doc(hidden)]
#[derive(Debug)]
#[repr(C, align(4096))]
pub struct Page([u8; 64]);

/// A 32-byte-aligned type, for [`align_frame`] in the 256-bit kernels (the page alignment is
/// not measured on them).
#[doc(hidden)]
#[derive(Debug)]
#[repr(C, align(32))]
pub struct Half([u8; 32]);

/// Runs `$kernel::<L>(bufs, args…)` compiled for the instruction set `$simd`, with `$bufs4`
/// (a `&mut $buf<4>`) or `$bufs8` (a `&mut $buf<8>`) as the kernel's first argument. The
/// target-feature calls are the only `unsafe` of the batched sweeps: a workspace picks its
/// [`Simd`] with [`Simd::or_available`], so the CPU has the feature.
#[macro_export]
#[doc(hidden)]
macro_rules! simd_dispatch {
    ($simd:expr, $buf:ident, $bufs4:expr, $bufs8:expr, $kernel:ident,
     ($($a:ident: $t:ty = $v:expr),* $(,)?) -> $r:ty) => {{
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        #[allow(clippy::too_many_arguments, reason = "the kernel's own arguments, passed through")]
        fn avx2(b: &mut $buf<4>, $($a: $t),*) -> $r {
            $crate::batch::align_frame::<$crate::batch::Half>();
            $kernel::<4>(b, $($a),*)
        }
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f")]
        #[allow(clippy::too_many_arguments, reason = "the kernel's own arguments, passed through")]
        fn avx512(b: &mut $buf<8>, $($a: $t),*) -> $r {
            $crate::batch::align_frame::<$crate::batch::Page>();
            $kernel::<8>(b, $($a),*)
        }
        match $simd {
            #[cfg(target_arch = "x86_64")]
            $crate::batch::Simd::Avx2 => {
                #[allow(unsafe_code, reason = "the workspace checked that the CPU has AVX2")]
                // SAFETY: the workspace's `Simd` is `Avx2` only when the CPU has AVX2.
                unsafe { avx2($bufs4, $($v),*) }
            }
            #[cfg(target_arch = "x86_64")]
            $crate::batch::Simd::Avx512 => {
                #[allow(unsafe_code, reason = "the workspace checked that the CPU has AVX-512F")]
                // SAFETY: the workspace's `Simd` is `Avx512` only when the CPU has AVX-512F.
                unsafe { avx512($bufs8, $($v),*) }
            }
            _ => $kernel::<4>($bufs4, $($v),*),
        }
    }};
}

/// The first state of each lane of the block starting at `start` (lanes past `n` repeat the
/// last state, so every lane computes something valid and only `n - start` are stored).
#[inline(always)]
pub fn block_states<const L: usize>(start: usize, n: usize) -> [usize; L] {
    let mut idx = [0; L];
    for (l, i) in idx.iter_mut().enumerate() {
        *i = (start + l).min(n - 1);
    }
    idx
}

/// Coordinate `at` (of each state's `stride` numbers) of the block's states.
#[inline(always)]
pub fn gather<const L: usize>(x: &[f64], stride: usize, at: usize, idx: &[usize; L]) -> Lanes<L> {
    let mut out = [0.0; L];
    for l in 0..L {
        out[l] = x[idx[l] * stride + at];
    }
    Lanes(out)
}

/// The joint coordinates of a block of states, as the lane kernels read them.
pub(crate) trait Coordinates<const L: usize> {
    /// Coordinate `at` of every lane.
    fn at(&self, at: usize) -> Lanes<L>;
    /// Lane `l`'s whole configuration.
    fn state(&self, l: usize) -> &[f64];
}

/// The coordinates of the block of states `idx` read where they lie in the stacked states `q`
/// (`nq` numbers each), one [`gather`] per coordinate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Gathered<'a, const L: usize> {
    /// The stacked states.
    pub(crate) q: &'a [f64],
    /// Numbers per state.
    pub(crate) nq: usize,
    /// The block's states.
    pub(crate) idx: [usize; L],
}

impl<const L: usize> Coordinates<L> for Gathered<'_, L> {
    #[inline(always)]
    fn at(&self, at: usize) -> Lanes<L> {
        gather(self.q, self.nq, at, &self.idx)
    }

    #[inline(always)]
    fn state(&self, l: usize) -> &[f64] {
        &self.q[self.idx[l] * self.nq..(self.idx[l] + 1) * self.nq]
    }
}

/// The coordinates of a block of states moved into lanes once (`lanes[j]` is coordinate `j` of
/// every lane), with the stacked states for the joints computed lane by lane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct InLanes<'a, const L: usize> {
    pub(crate) lanes: &'a [Lanes<L>],
    pub(crate) states: Gathered<'a, L>,
}

impl<const L: usize> Coordinates<L> for InLanes<'_, L> {
    #[inline(always)]
    fn at(&self, at: usize) -> Lanes<L> {
        self.lanes[at]
    }

    #[inline(always)]
    fn state(&self, l: usize) -> &[f64] {
        self.states.state(l)
    }
}

/// `parent_from_body` of `b` in each lane: [`JointModel::body_transform`], the one joint
/// algebra, on lanes (the rare joint kinds go lane by lane through the one-state code, see
/// `Real::each_lane`).
#[inline(always)]
pub fn body_transform<const L: usize>(
    jm: &JointModel,
    b: &Body,
    q: &[f64],
    nq: usize,
    idx: &[usize; L],
) -> LSe3<L> {
    body_transform_of(jm, b, &Gathered { q, nq, idx: *idx })
}

/// The probe `finite` (NaN in a lane where a coordinate is not finite, 0 elsewhere) with NaN
/// added in each lane where a quaternion of the coordinates `lanes` (`lanes[j]` is coordinate
/// `j`) has a sum of squares that is not well inside the unit tolerance (|norm² − 1| ≤ 1.9e-6,
/// a norm within 0.95e-6 of 1): a lane whose result is 0 holds a configuration the one-state
/// functions accept; any other lane must be checked by them.
#[inline(always)]
pub fn suspect_lanes<const L: usize>(
    model: &Model,
    lanes: &[Lanes<L>],
    finite: Lanes<L>,
) -> Lanes<L> {
    let mut suspect = finite;
    for &(_, at) in model.quaternion_blocks() {
        let (x, y, z, w) = (lanes[at], lanes[at + 1], lanes[at + 2], lanes[at + 3]);
        let squares = x * x + y * y + z * z + w * w;
        for l in 0..L {
            let fine = (squares.0[l] - 1.0).abs() <= 1.9e-6;
            suspect.0[l] += if fine { 0.0 } else { f64::NAN };
        }
    }
    suspect
}

/// [`body_transform`] with the coordinates read from `c`.
#[inline(always)]
pub(crate) fn body_transform_of<const L: usize>(
    jm: &JointModel,
    b: &Body,
    c: &impl Coordinates<L>,
) -> LSe3<L> {
    // The body's block of coordinates (a coupled mimic body's one value from its leader's), as
    // `JointModel::body_transform` reads it.
    let mut block = [Lanes::ZERO; 7];
    let n = if b.mimic.is_some() { 1 } else { b.nq.min(7) };
    for (k, x) in block[..n].iter_mut().enumerate() {
        *x = c.at(b.idx_q + k);
    }
    block[0] = mimic_value(b, block[0]);
    jm.placed_transform(&b.placement, &block[..n])
}

/// The sine and cosine of the joint value of a one-coordinate body in each lane (as the
/// one-state sweeps' [`sin_cos`](crate::joint::sin_cos)).
#[inline(always)]
pub(crate) fn joint_sin_cos<const L: usize>(
    b: &Body,
    c: &impl Coordinates<L>,
) -> (Lanes<L>, Lanes<L>) {
    mimic_value(b, c.at(b.idx_q)).sin_cos()
}
