//! The batched algorithms on every core: the entry points of
//! [`kinematics::batch`](crate::kinematics::batch), [`dynamics::batch`](crate::dynamics::batch)
//! (feature `dynamics`) and [`collision::batch`](crate::collision::batch) (feature `collision`:
//! [`distances_batch`] and [`min_distance_batch`]) with the same signatures, splitting the `N`
//! states over rayon's thread pool.
//!
//! A [`Parallel`] holds one batch workspace per thread of the pool it is created in
//! ([`rayon::current_num_threads`]); each thread evaluates blocks of states with the vectorised
//! one-core kernels. The results do not depend on the number of threads. Run inside
//! [`rayon::ThreadPool::install`] to choose the pool.
//!
//! - Called on a thread of the pool, a batch is split in one contiguous block per workspace.
//! - Called from any other thread, the calling thread works too: it starts on the first of
//!   smaller blocks at once, and the pool's threads take the others as they come. A worker idle
//!   for a few milliseconds sleeps and takes a while to wake; this way it no longer delays the
//!   batch ([`Parallel::for_each_block`], public for batches of other shapes; the panda's CRBA
//!   on 1 024 states after 1 ms of other work: 201-220 ns/state before, 94-112 now on 2 cores).
//!
//! Nothing is allocated per call after [`Parallel::new`] (rayon's pool itself is started on
//! first use), but for one small job per extra thread spawned into the pool by a call from
//! outside it.
//!
//! # Examples
//! ```
//! use kinetree::parallel::{Parallel, forward_kinematics_batch};
//! use kinetree::kinematics::batch::KinematicsBatch;
//! use kinetree::spatial::Se3;
//! # fn main() -> Result<(), kinetree::Error> {
//! let model = kinetree::model::samples::planar_2r(0.3, 0.2);
//! let n = 1000;
//! let q: Vec<f64> = (0..2 * n).map(|i| (i as f64 * 0.01).sin()).collect();
//! let mut pool = Parallel::<KinematicsBatch>::new(&model);
//! let mut links = vec![Se3::IDENTITY; n * model.links().len()];
//! forward_kinematics_batch(&model, &mut pool, &q, &mut links, None)?;
//! # Ok(())
//! # }
//! ```

use crate::kinematics::batch::{self as kb, KinematicsBatch};
use crate::kinematics::model::Model;
use crate::kinematics::spatial::{Motion, Se3};
use crate::kinematics::{FrameId, KinematicsError, ReferenceFrame};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// One batch workspace per thread of a rayon pool.
#[derive(Clone, Debug)]
pub struct Parallel<W> {
    workers: Vec<W>,
}

/// A workspace of a batched algorithm that [`Parallel`] can hold one of per thread.
pub trait Workspace: Send + Sized {
    /// Allocates the workspace for `model`.
    fn for_model(model: &Model) -> Self;
}

impl Workspace for KinematicsBatch {
    fn for_model(model: &Model) -> Self {
        KinematicsBatch::new(model)
    }
}

#[cfg(feature = "dynamics")]
impl Workspace for crate::dynamics::batch::DynamicsBatch {
    fn for_model(model: &Model) -> Self {
        crate::dynamics::batch::DynamicsBatch::new(model)
    }
}

#[cfg(feature = "dynamics")]
impl Workspace for crate::dynamics::batch::DerivativesBatch {
    fn for_model(model: &Model) -> Self {
        crate::dynamics::batch::DerivativesBatch::new(model)
    }
}

impl<W: Workspace> Parallel<W> {
    /// One workspace for `model` per thread of the current rayon pool.
    #[must_use]
    pub fn new(model: &Model) -> Self {
        Self::with_threads(model, rayon::current_num_threads())
    }

    /// `threads` workspaces for `model` (at least one): a batch runs on that many threads.
    #[must_use]
    pub fn with_threads(model: &Model, threads: usize) -> Self {
        Self {
            workers: (0..threads.max(1)).map(|_| W::for_model(model)).collect(),
        }
    }
}

impl<W> Parallel<W> {
    /// One workspace per thread, `threads` of them (at least one), built by `make` (for
    /// workspaces with options, such as
    /// [`DynamicsBatch::with_joint_terms`](crate::dynamics::batch::DynamicsBatch::with_joint_terms)).
    #[must_use]
    pub fn from_fn(threads: usize, make: impl FnMut(usize) -> W) -> Self {
        Self {
            workers: (0..threads.max(1)).map(make).collect(),
        }
    }

    /// The number of blocks a batch is split in.
    #[must_use]
    pub fn threads(&self) -> usize {
        self.workers.len()
    }
}

/// States per block are rounded to this, so that every block fills whole SIMD lanes.
const ALIGN: usize = 8;

/// A set of per-state buffers that splits at a state boundary.
trait Split: Sized + Send {
    fn split_at_state(self, k: usize) -> (Self, Self);
}

/// An input of `.1` numbers per state.
struct In<'a, T>(&'a [T], usize);
/// An output of `.1` numbers per state.
struct Out<'a, T>(&'a mut [T], usize);

impl<T: Sync> Split for In<'_, T> {
    fn split_at_state(self, k: usize) -> (Self, Self) {
        let (a, b) = self.0.split_at(k * self.1);
        (In(a, self.1), In(b, self.1))
    }
}

impl<T: Send> Split for Out<'_, T> {
    fn split_at_state(self, k: usize) -> (Self, Self) {
        let (a, b) = self.0.split_at_mut(k * self.1);
        (Out(a, self.1), Out(b, self.1))
    }
}

impl<S: Split> Split for Option<S> {
    fn split_at_state(self, k: usize) -> (Self, Self) {
        match self {
            None => (None, None),
            Some(s) => {
                let (a, b) = s.split_at_state(k);
                (Some(a), Some(b))
            }
        }
    }
}

macro_rules! split_tuple {
    ($($t:ident),+) => {
        impl<$($t: Split),+> Split for ($($t,)+) {
            #[allow(non_snake_case, reason = "the tuple's fields are named by their types")]
            fn split_at_state(self, k: usize) -> (Self, Self) {
                let ($($t,)+) = self;
                $(let $t = $t.split_at_state(k);)+
                (($($t.0,)+), ($($t.1,)+))
            }
        }
    };
}
split_tuple!(A, B);
split_tuple!(A, B, C);
split_tuple!(A, B, C, D);

/// Blocks per workspace of a batch: enough for the threads to even out when one of them is
/// slowed down (by other work on the machine, or a late wake-up), few enough that the cost of a
/// block (its checks and set-up) is noise.
const BLOCKS_PER_WORKER: usize = 8;

/// Blocks kept on the stack by [`Parallel::for_each_block`] (more are put in a `Vec`); a batch
/// of [`run`] is cut in at most this many.
const MAX_BLOCKS: usize = 64;

/// States per block at least, unless the batch is smaller.
const MIN_BLOCK: usize = 2 * ALIGN;

/// The blocks of a [`Parallel::for_each_block`] call, which the threads take in turn.
struct Queue<T, E> {
    /// Block `i < MAX_BLOCKS` until a thread takes it.
    slots: [Mutex<Option<T>>; MAX_BLOCKS],
    /// Block `MAX_BLOCKS + i` until a thread takes it.
    more: Vec<Mutex<Option<T>>>,
    /// How many blocks there are.
    count: usize,
    /// The next block to take.
    next: AtomicUsize,
    /// The error of the lowest failed block, with that block's index.
    failed: Mutex<Option<(usize, E)>>,
}

/// A lock that a panic elsewhere left poisoned still holds a consistent value here (every
/// critical section is a single `take` or assignment).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

impl<T, E> Queue<T, E> {
    fn new(blocks: impl IntoIterator<Item = T>) -> Self {
        let mut blocks = blocks.into_iter();
        let mut count = 0;
        let slots = core::array::from_fn(|_| {
            let block = blocks.next();
            count += usize::from(block.is_some());
            Mutex::new(block)
        });
        let more: Vec<_> = blocks.map(|b| Mutex::new(Some(b))).collect();
        Self {
            slots,
            count: count + more.len(),
            more,
            next: AtomicUsize::new(0),
            failed: Mutex::new(None),
        }
    }

    /// Runs `f` with `w` on blocks until none is left, keeping the lowest block's error.
    fn drain<W>(&self, w: &mut W, f: &impl Fn(&mut W, T) -> Result<(), E>) {
        loop {
            let i = self.next.fetch_add(1, Ordering::Relaxed);
            if i >= self.count {
                return;
            }
            let slot = match i.checked_sub(MAX_BLOCKS) {
                None => &self.slots[i],
                Some(j) => &self.more[j],
            };
            let Some(block) = lock(slot).take() else {
                continue;
            };
            if let Err(e) = f(w, block) {
                let mut failed = lock(&self.failed);
                if failed.as_ref().is_none_or(|(j, _)| i < *j) {
                    *failed = Some((i, e));
                }
            }
        }
    }
}

impl<W: Send> Parallel<W> {
    /// Runs `f` on every block of `blocks`, each with one workspace, on as many threads as
    /// there are workspaces: the calling thread starts on the first block at once, and one job
    /// per other workspace, spawned into rayon's current pool, takes the next block no thread
    /// has taken as its thread comes. A worker asleep after a few milliseconds without work
    /// joins late instead of delaying the whole call, and a thread slowed down by other work
    /// takes fewer blocks.
    ///
    /// This is what the batched functions of this module run on when called from outside the
    /// pool; it is public for batches of other shapes (the Python package cuts its stacked
    /// calls with it). Nothing is allocated for at most 64 blocks but one small job per extra
    /// thread.
    ///
    /// # Errors
    /// The error of the first block (in the order of `blocks`) for which `f` failed, whichever
    /// thread ran it. Every other block is still run.
    ///
    /// # Examples
    /// ```
    /// use kinetree::parallel::Parallel;
    /// use std::sync::atomic::{AtomicU64, Ordering};
    ///
    /// // Blocks of 100 numbers on two threads, with no workspace (`()`): each adds its sum to
    /// // a total, and fails if it holds a number above 650.
    /// let numbers: Vec<u64> = (0..1000).collect();
    /// let total = AtomicU64::new(0);
    /// let mut threads = Parallel::from_fn(2, |_| ());
    /// let result = threads.for_each_block(numbers.chunks(100).enumerate(), &|_, (i, block)| {
    ///     total.fetch_add(block.iter().sum(), Ordering::Relaxed);
    ///     if block.iter().any(|&x| x > 650) { Err(format!("block {i}")) } else { Ok(()) }
    /// });
    /// // Every block ran; blocks 6 to 9 failed, and the first of them is reported.
    /// assert_eq!(total.into_inner(), 499_500);
    /// assert_eq!(result, Err("block 6".to_string()));
    /// ```
    pub fn for_each_block<T: Send, E: Send>(
        &mut self,
        blocks: impl IntoIterator<Item = T>,
        f: &(impl Fn(&mut W, T) -> Result<(), E> + Sync),
    ) -> Result<(), E> {
        let queue = Queue::new(blocks);
        // A `Parallel` holds at least one workspace.
        let (own, helpers) = self.workers.split_at_mut(1);
        let used = queue.count.saturating_sub(1).min(helpers.len());
        rayon::in_place_scope(|s| {
            for w in &mut helpers[..used] {
                let queue = &queue;
                s.spawn(move |_| queue.drain(w, f));
            }
            queue.drain(&mut own[0], f);
        });
        match queue
            .failed
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner)
        {
            Some((_, e)) => Err(e),
            None => Ok(()),
        }
    }
}

/// Runs `f` on the `n` states of `parts` with every workspace, each on its own thread; `f` gets
/// the index of its block's first state. The error of the first failing block (by state) wins.
///
/// - On a thread of a rayon pool (as inside [`rayon::ThreadPool::install`]), the states are split
///   in one contiguous block per workspace with `rayon::join`: the caller runs the first, and a
///   block that no other thread has taken by the time the caller is done is run by the caller.
/// - From any other thread, `join` would hand the whole batch to the pool and put the caller to
///   sleep until a worker has woken up and finished it. Instead the states are cut in smaller
///   blocks ([`BLOCKS_PER_WORKER`] per workspace) run by [`Parallel::for_each_block`], which
///   the caller starts on at once.
fn run<W: Send, S: Split, E: Send>(
    pool: &mut Parallel<W>,
    n: usize,
    parts: S,
    f: &(impl Fn(&mut W, S, usize) -> Result<(), E> + Sync),
) -> Result<(), E> {
    if rayon::current_thread_index().is_some() {
        return split(&mut pool.workers, n, 0, parts, f);
    }
    let size = n
        .div_ceil(pool.workers.len() * BLOCKS_PER_WORKER)
        .max(n.div_ceil(MAX_BLOCKS))
        .max(MIN_BLOCK)
        .next_multiple_of(ALIGN);
    if pool.workers.len() == 1 || n <= size {
        return f(&mut pool.workers[0], parts, 0);
    }
    // Blocks of `size` states, the last one shorter.
    let (mut rest, mut first) = (Some(parts), 0);
    let blocks = core::iter::from_fn(|| {
        let p = rest.take()?;
        let block = if n - first > size {
            let (a, b) = p.split_at_state(size);
            rest = Some(b);
            a
        } else {
            p
        };
        first += size;
        Some((first - size, block))
    });
    pool.for_each_block(blocks, &|w, (first, block)| f(w, block, first))
}

/// [`run`] on a thread of a pool: `workers.len()` contiguous blocks of the `n` states of
/// `parts` (the first of which is state `first` of the batch), split in halves with
/// `rayon::join`.
fn split<W: Send, S: Split, E: Send>(
    workers: &mut [W],
    n: usize,
    first: usize,
    parts: S,
    f: &(impl Fn(&mut W, S, usize) -> Result<(), E> + Sync),
) -> Result<(), E> {
    if workers.len() == 1 || n <= ALIGN {
        return f(&mut workers[0], parts, first);
    }
    let half = workers.len() / 2;
    let k = (n * half / workers.len()).div_ceil(ALIGN) * ALIGN;
    let k = k.min(n);
    let (wa, wb) = workers.split_at_mut(half);
    let (pa, pb) = parts.split_at_state(k);
    let (ra, rb) = rayon::join(
        || split(wa, k, first, pa, f),
        || split(wb, n - k, first + k, pb, f),
    );
    ra.and(rb)
}

/// Moves a batch error of a block starting at state `first` to the whole batch's numbering.
fn shift_kinematics(e: KinematicsError, first: usize) -> KinematicsError {
    match e {
        KinematicsError::InBatchState { index, source } => KinematicsError::InBatchState {
            index: index + first,
            source,
        },
        e => e,
    }
}

/// [`kinematics::batch::forward_kinematics_batch`](kb::forward_kinematics_batch) on every core.
///
/// # Errors
/// As the one-core function; a bad state is reported with its index in the whole batch.
pub fn forward_kinematics_batch(
    model: &Model,
    pool: &mut Parallel<KinematicsBatch>,
    q: &[f64],
    world_from_link: &mut [Se3],
    world_from_frame: Option<&mut [Se3]>,
) -> Result<(), KinematicsError> {
    let (nq, nl, nf) = (model.nq(), model.links().len(), model.frames().len());
    let n = kb::batch_size("world_from_link", world_from_link.len(), nl)?;
    // The one-core function checks every length; here only the block split needs them to agree.
    if q.len() != n * nq || world_from_frame.as_ref().is_some_and(|f| f.len() != n * nf) {
        return kb::forward_kinematics_batch(
            model,
            &mut pool.workers[0],
            q,
            world_from_link,
            world_from_frame,
        );
    }
    let parts = (
        In(q, nq),
        Out(world_from_link, nl),
        world_from_frame.map(|f| Out(f, nf)),
    );
    run(pool, n, parts, &|w, (q, l, f), first| {
        kb::forward_kinematics_batch(model, w, q.0, l.0, f.map(|f| f.0))
            .map_err(|e| shift_kinematics(e, first))
    })
}

/// [`kinematics::batch::forward_kinematics_matrices_batch`](kb::forward_kinematics_matrices_batch)
/// on every core.
///
/// # Errors
/// As the one-core function; a bad state is reported with its index in the whole batch.
pub fn forward_kinematics_matrices_batch(
    model: &Model,
    pool: &mut Parallel<KinematicsBatch>,
    q: &[f64],
    links: Option<&[usize]>,
    out: &mut [f64],
) -> Result<(), KinematicsError> {
    let nq = model.nq();
    let per_state = 16 * links.map_or(model.links().len(), <[usize]>::len);
    let n = if nq > 0 {
        kb::batch_size("q", q.len(), nq)?
    } else {
        kb::batch_size("matrices", out.len(), per_state)?
    };
    // The one-core function checks every length and link; here only the block split needs the
    // lengths to agree.
    if out.len() != n * per_state || q.len() != n * nq || per_state == 0 {
        return kb::forward_kinematics_matrices_batch(model, &mut pool.workers[0], q, links, out);
    }
    let parts = (In(q, nq), Out(out, per_state));
    run(pool, n, parts, &|w, (q, o), first| {
        kb::forward_kinematics_matrices_batch(model, w, q.0, links, o.0)
            .map_err(|e| shift_kinematics(e, first))
    })
}

/// [`kinematics::batch::frame_jacobian_batch`](kb::frame_jacobian_batch) on every core.
///
/// # Errors
/// As the one-core function; a bad state is reported with its index in the whole batch.
pub fn frame_jacobian_batch(
    model: &Model,
    pool: &mut Parallel<KinematicsBatch>,
    q: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    out: &mut [Motion],
) -> Result<(), KinematicsError> {
    let (nq, nv) = (model.nq(), model.nv());
    let n = if nq > 0 {
        kb::batch_size("q", q.len(), nq)?
    } else {
        kb::batch_size("jacobian", out.len(), nv)?
    };
    if out.len() != n * nv || q.len() != n * nq {
        return kb::frame_jacobian_batch(model, &mut pool.workers[0], q, frame, reference, out);
    }
    let parts = (In(q, nq), Out(out, nv));
    run(pool, n, parts, &|w, (q, o), first| {
        kb::frame_jacobian_batch(model, w, q.0, frame, reference, o.0)
            .map_err(|e| shift_kinematics(e, first))
    })
}

/// [`kinematics::batch::frame_jacobian_rows_batch`](kb::frame_jacobian_rows_batch) on every
/// core.
///
/// # Errors
/// As the one-core function; a bad state is reported with its index in the whole batch.
pub fn frame_jacobian_rows_batch(
    model: &Model,
    pool: &mut Parallel<KinematicsBatch>,
    q: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    out: &mut [f64],
) -> Result<(), KinematicsError> {
    let (nq, nv) = (model.nq(), model.nv());
    let n = if nq > 0 {
        kb::batch_size("q", q.len(), nq)?
    } else {
        kb::batch_size("jacobian", out.len(), 6 * nv)?
    };
    if out.len() != n * 6 * nv || q.len() != n * nq {
        return kb::frame_jacobian_rows_batch(
            model,
            &mut pool.workers[0],
            q,
            frame,
            reference,
            out,
        );
    }
    let parts = (In(q, nq), Out(out, 6 * nv));
    run(pool, n, parts, &|w, (q, o), first| {
        kb::frame_jacobian_rows_batch(model, w, q.0, frame, reference, o.0)
            .map_err(|e| shift_kinematics(e, first))
    })
}

#[cfg(feature = "dynamics")]
pub use dynamics::{
    aba_batch, aba_derivatives_batch, crba_batch, rnea_batch, rnea_derivatives_batch,
};

#[cfg(feature = "dynamics")]
mod dynamics {
    use super::{In, Out, Parallel, run};
    use crate::dynamics::DynamicsError;
    use crate::dynamics::batch::{self as db, DerivativesBatch, DynamicsBatch};
    use crate::kinematics::batch::batch_size;
    use crate::kinematics::model::Model;

    fn shift(e: DynamicsError, first: usize) -> DynamicsError {
        match e {
            DynamicsError::InBatchState { index, source } => DynamicsError::InBatchState {
                index: index + first,
                source,
            },
            e => e,
        }
    }

    /// The number of states, or `None` when the lengths disagree (the one-core function then
    /// reports which).
    fn states(model: &Model, q: usize, vs: &[usize], per_out: usize) -> Option<usize> {
        let (nq, nv) = (model.nq(), model.nv());
        let n = if nq > 0 {
            batch_size("q", q, nq).ok()?
        } else {
            batch_size("out", *vs.last()?, per_out).ok()?
        };
        let ok = q == n * nq
            && vs[..vs.len() - 1].iter().all(|&l| l == n * nv)
            && vs[vs.len() - 1] == n * per_out;
        ok.then_some(n)
    }

    /// [`dynamics::batch::rnea_batch`](db::rnea_batch) on every core.
    ///
    /// # Errors
    /// As the one-core function; a bad state is reported with its index in the whole batch.
    pub fn rnea_batch(
        model: &Model,
        pool: &mut Parallel<DynamicsBatch>,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        tau: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let (nq, nv) = (model.nq(), model.nv());
        let Some(n) = states(model, q.len(), &[v.len(), a.len(), tau.len()], nv) else {
            return db::rnea_batch(model, &mut pool.workers[0], q, v, a, tau);
        };
        let parts = (In(q, nq), In(v, nv), In(a, nv), Out(tau, nv));
        run(pool, n, parts, &|w, (q, v, a, t), first| {
            db::rnea_batch(model, w, q.0, v.0, a.0, t.0).map_err(|e| shift(e, first))
        })
    }

    /// [`dynamics::batch::aba_batch`](db::aba_batch) on every core.
    ///
    /// # Errors
    /// As the one-core function; a bad state is reported with its index in the whole batch.
    pub fn aba_batch(
        model: &Model,
        pool: &mut Parallel<DynamicsBatch>,
        q: &[f64],
        v: &[f64],
        tau: &[f64],
        ddq: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let (nq, nv) = (model.nq(), model.nv());
        let Some(n) = states(model, q.len(), &[v.len(), tau.len(), ddq.len()], nv) else {
            return db::aba_batch(model, &mut pool.workers[0], q, v, tau, ddq);
        };
        let parts = (In(q, nq), In(v, nv), In(tau, nv), Out(ddq, nv));
        run(pool, n, parts, &|w, (q, v, t, o), first| {
            db::aba_batch(model, w, q.0, v.0, t.0, o.0).map_err(|e| shift(e, first))
        })
    }

    /// [`dynamics::batch::crba_batch`](db::crba_batch) on every core.
    ///
    /// # Errors
    /// As the one-core function; a bad state is reported with its index in the whole batch.
    pub fn crba_batch(
        model: &Model,
        pool: &mut Parallel<DynamicsBatch>,
        q: &[f64],
        mass_matrix: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let (nq, nv) = (model.nq(), model.nv());
        let Some(n) = states(model, q.len(), &[mass_matrix.len()], nv * nv) else {
            return db::crba_batch(model, &mut pool.workers[0], q, mass_matrix);
        };
        let parts = (In(q, nq), Out(mass_matrix, nv * nv));
        run(pool, n, parts, &|w, (q, m), first| {
            db::crba_batch(model, w, q.0, m.0).map_err(|e| shift(e, first))
        })
    }

    /// [`dynamics::batch::rnea_derivatives_batch`](db::rnea_derivatives_batch) on every core.
    ///
    /// # Errors
    /// As the one-core function; a bad state is reported with its index in the whole batch.
    #[allow(
        clippy::too_many_arguments,
        reason = "three inputs and three outputs of one batch, as the one-core function"
    )]
    pub fn rnea_derivatives_batch(
        model: &Model,
        pool: &mut Parallel<DerivativesBatch>,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        dtau_dq: &mut [f64],
        dtau_dv: &mut [f64],
        dtau_da: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let outputs = [dtau_dq, dtau_dv, dtau_da];
        derivatives(db::rnea_derivatives_batch, model, pool, [q, v, a], outputs)
    }

    /// [`dynamics::batch::aba_derivatives_batch`](db::aba_derivatives_batch) on every core.
    ///
    /// # Errors
    /// As the one-core function; a bad state is reported with its index in the whole batch.
    #[allow(
        clippy::too_many_arguments,
        reason = "three inputs and three outputs of one batch, as the one-core function"
    )]
    pub fn aba_derivatives_batch(
        model: &Model,
        pool: &mut Parallel<DerivativesBatch>,
        q: &[f64],
        v: &[f64],
        tau: &[f64],
        dddq_dq: &mut [f64],
        dddq_dv: &mut [f64],
        dddq_dtau: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let outputs = [dddq_dq, dddq_dv, dddq_dtau];
        derivatives(db::aba_derivatives_batch, model, pool, [q, v, tau], outputs)
    }

    /// A one-core batched derivatives function: `(q, v, a or tau)` in, three `nv x nv` matrices
    /// per state out.
    type DerivativesFn = fn(
        &Model,
        &mut DerivativesBatch,
        &[f64],
        &[f64],
        &[f64],
        &mut [f64],
        &mut [f64],
        &mut [f64],
    ) -> Result<(), DynamicsError>;

    /// Splits a batch of `f` over the pool (wrong lengths go to one worker, which names them).
    fn derivatives(
        f: DerivativesFn,
        model: &Model,
        pool: &mut Parallel<DerivativesBatch>,
        [q, v, x]: [&[f64]; 3],
        [o0, o1, o2]: [&mut [f64]; 3],
    ) -> Result<(), DynamicsError> {
        let (nq, nv) = (model.nq(), model.nv());
        let nn = nv * nv;
        let lengths = [v.len(), x.len(), o0.len()];
        let Some(n) = states(model, q.len(), &lengths, nn)
            .filter(|&n| o1.len() == n * nn && o2.len() == n * nn)
        else {
            return f(model, &mut pool.workers[0], q, v, x, o0, o1, o2);
        };
        let inputs = (In(q, nq), In(v, nv), In(x, nv));
        let outputs = (Out(o0, nn), Out(o1, nn), Out(o2, nn));
        run(pool, n, (inputs, outputs), &|w, (i, o), first| {
            f(model, w, i.0.0, i.1.0, i.2.0, o.0.0, o.1.0, o.2.0).map_err(|e| shift(e, first))
        })
    }
}

#[cfg(feature = "collision")]
pub use collision::{distances_batch, min_distance_batch};

#[cfg(feature = "collision")]
mod collision {
    use super::{In, Out, Parallel, run};
    use crate::collision::batch::{self as cb, CollisionBatch};
    use crate::collision::{CollisionError, CollisionModel};
    use crate::kinematics::model::Model;

    fn shift(e: CollisionError, first: usize) -> CollisionError {
        match e {
            CollisionError::InBatchState { index, source } => CollisionError::InBatchState {
                index: index + first,
                source,
            },
            e => e,
        }
    }

    /// The number of states when `q` and the output (`per_out` numbers per state) agree.
    fn states(model: &Model, q: usize, out: usize, per_out: usize) -> Option<usize> {
        let nq = model.nq();
        let n = q.checked_div(nq).unwrap_or(out / per_out.max(1));
        (q == n * nq && out == n * per_out).then_some(n)
    }

    /// [`collision::batch::distances_batch`](cb::distances_batch) on every core (one
    /// [`CollisionBatch`] per block: build the pool with [`Parallel::from_fn`]).
    ///
    /// # Errors
    /// As the one-core function; a bad state is reported with its index in the whole batch.
    pub fn distances_batch(
        model: &Model,
        cmodel: &CollisionModel,
        pool: &mut Parallel<CollisionBatch>,
        q: &[f64],
        distances: &mut [f64],
    ) -> Result<(), CollisionError> {
        let (nq, np) = (model.nq(), cmodel.pairs().len());
        let Some(n) = states(model, q.len(), distances.len(), np) else {
            return cb::distances_batch(model, cmodel, &mut pool.workers[0], q, distances);
        };
        let parts = (In(q, nq), Out(distances, np));
        run(pool, n, parts, &|w, (q, d), first| {
            cb::distances_batch(model, cmodel, w, q.0, d.0).map_err(|e| shift(e, first))
        })
    }

    /// [`collision::batch::min_distance_batch`](cb::min_distance_batch) on every core.
    ///
    /// # Errors
    /// As the one-core function; a bad state is reported with its index in the whole batch.
    pub fn min_distance_batch(
        model: &Model,
        cmodel: &CollisionModel,
        pool: &mut Parallel<CollisionBatch>,
        q: &[f64],
        min: &mut [f64],
    ) -> Result<(), CollisionError> {
        let nq = model.nq();
        let Some(n) = states(model, q.len(), min.len(), 1) else {
            return cb::min_distance_batch(model, cmodel, &mut pool.workers[0], q, min);
        };
        let parts = (In(q, nq), Out(min, 1));
        run(pool, n, parts, &|w, (q, m), first| {
            cb::min_distance_batch(model, cmodel, w, q.0, m.0).map_err(|e| shift(e, first))
        })
    }
}
