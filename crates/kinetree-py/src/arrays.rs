//! numpy in and out: checked inputs ([`States`]) and the one map over stacked states
//! ([`map_states`], wrapped by [`run`] and [`run_blocks`]; calls with several results per state
//! use [`crate::parts`]).
//!
//! Every per-state call takes one state (`q` of shape `(nq,)`) or a stack (`(N, nq)`; a large one
//! read in place, see [`crate::values`]). One state
//! runs directly, with a workspace from the model's [`Pool`]; a stack runs in parallel (rayon)
//! with the GIL released, in a few contiguous blocks with one pooled workspace each, so each
//! state gets exactly the arithmetic of a one-state call. Results are written straight into the
//! numpy array returned.

use crate::errors::{Family, family_of, to_py};
use crate::model::PyModel;
use crate::scratch::Scratch;
use crate::values::{SharedArray, Values, address_range};
use kinetree::dynamics::DynamicsData;
use kinetree::parallel::Parallel;
use numpy::ndarray::{ArrayD, ArrayViewD, IxDyn};
use numpy::{
    AllowTypeChange, IntoPyArray, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods,
    PyUntypedArrayMethods, ToPyArray,
};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyComplex, PyFloat, PyInt};
use std::cell::RefCell;
use std::ops::Range;

/// Two arrays returned together (`simulate`'s configurations and velocities, `bounds`' corners).
pub(crate) type ArrayPair<'py> = (
    Bound<'py, numpy::PyArrayDyn<f64>>,
    Bound<'py, numpy::PyArrayDyn<f64>>,
);

/// One input: a single state or a stack of states, each `width` numbers, all finite.
#[derive(Debug)]
pub(crate) struct States {
    /// Row-major values, `width` per state (a copy, or a large stack's own memory).
    pub(crate) values: Values,
    /// Numbers per state.
    pub(crate) width: usize,
    /// `None` for one state (a 1-D array), `Some(N)` for a stack (a 2-D array).
    pub(crate) count: Option<usize>,
    /// The argument's name, for messages.
    pub(crate) name: &'static str,
    /// Whether the values are yet to be checked finite: a large stack read by
    /// [`stack_states`], which the workers check block by block ([`checked_block`]).
    pub(crate) unchecked: bool,
}

impl States {
    /// The values of state `i` (the only state when not stacked).
    pub(crate) fn state(&self, i: usize) -> &[f64] {
        &self.values[i * self.width..(i + 1) * self.width]
    }

    /// The same states with their values copied (refused when the copy does not fit in memory).
    pub(crate) fn copied(&self, family: Family) -> PyResult<Self> {
        let mut values = reserve(self.values.len(), self.name, family)?;
        values.extend_from_slice(&self.values);
        Ok(Self {
            values: Values::Owned(values),
            width: self.width,
            count: self.count,
            name: self.name,
            unchecked: self.unchecked,
        })
    }

    /// An error naming the first number that is not finite (`q[3, 2] is nan`), if any.
    pub(crate) fn check_finite(&self, family: Family) -> PyResult<()> {
        let Some(k) = first_non_finite(&self.values) else {
            return Ok(());
        };
        let (name, width) = (self.name, self.width);
        let at = if self.count.is_some() && width > 0 {
            format!("[{}, {}]", k / width, k % width)
        } else {
            format!("[{k}]")
        };
        Err(family.err(format!(
            "{name}{at} is {}: inputs must be finite",
            self.values[k]
        )))
    }
}

/// Reads argument `name`: any array-like of numbers convertible to float64, of shape `(width,)`
/// or `(N, width)`, every entry finite. Errors are of `family` and name the expected shape.
///
/// A C-contiguous float64 ndarray (the common case) is copied straight from its buffer; anything
/// else goes through numpy's conversion.
pub(crate) fn states(
    obj: &Bound<'_, PyAny>,
    name: &'static str,
    width: usize,
    family: Family,
) -> PyResult<States> {
    let s = read_states(obj, name, width, family)?;
    s.check_finite(family)?;
    Ok(s)
}

/// As [`states`], for the calls that run through [`map_states`] or [`crate::parts`]: a large
/// stack read in place is not scanned here, on the calling thread with the GIL held, but block by
/// block by the workers ([`checked_block`]), and a bad number is then named as [`states`] names
/// it ([`stack_failure`]). Single states and small stacks are checked here.
pub(crate) fn stack_states(
    obj: &Bound<'_, PyAny>,
    name: &'static str,
    width: usize,
    family: Family,
) -> PyResult<States> {
    let mut s = read_states(obj, name, width, family)?;
    if matches!(s.values, Values::Shared(_)) {
        s.unchecked = true;
    } else {
        s.check_finite(family)?;
    }
    Ok(s)
}

/// [`states`] without the finiteness check.
fn read_states(
    obj: &Bound<'_, PyAny>,
    name: &'static str,
    width: usize,
    family: Family,
) -> PyResult<States> {
    let (values, count) = match obj.cast::<PyArrayDyn<f64>>() {
        Ok(array) if array.is_c_contiguous() => {
            let count = count_of(array.shape(), name, width, family)?;
            let unreadable = |e: &dyn std::fmt::Display| {
                family.err(format!("{name} cannot be read as a float64 buffer: {e}"))
            };
            if array.len() <= SMALL_INPUT {
                // A small copy needs no memory check, nor numpy's borrow tracking: the GIL is held.
                (
                    Values::Owned(array.to_vec().map_err(|e| unreadable(&e))?),
                    count,
                )
            } else if let Some(shared) = SharedArray::new(array).filter(|_| count.is_some()) {
                // A large stack is read in place (see `crate::values`).
                (Values::Shared(shared), count)
            } else {
                let readonly = array.try_readonly().map_err(|e| unreadable(&e))?;
                let slice = readonly.as_slice().map_err(|e| unreadable(&e))?;
                let mut values = reserve(slice.len(), name, family)?;
                values.extend_from_slice(slice);
                (Values::Owned(values), count)
            }
        }
        _ => {
            let (values, count) = converted(obj, name, width, family)?;
            (Values::Owned(values), count)
        }
    };
    Ok(States {
        values,
        width,
        count,
        name,
        unchecked: false,
    })
}

/// The index of the first number of `values` that is not finite. The usual all-finite case is
/// a branch-free pass that the compiler vectorises (it runs with the GIL held, on one thread,
/// over stacks of 10 000 states: a search with a branch per number took about 8 ns per panda
/// state of a batched RNEA, this pass about 4); only a failure searches for the index.
fn first_non_finite(values: &[f64]) -> Option<usize> {
    if values.iter().fold(true, |ok, x| ok & x.is_finite()) {
        None
    } else {
        values.iter().position(|x| !x.is_finite())
    }
}

/// Inputs of at most this many numbers are copied, without a check that the copy fits in memory;
/// a larger stack is read in place (a copy of it costs page faults: see `crate::values`).
const SMALL_INPUT: usize = 1 << 12;

/// The expected shape of argument `name`, for messages.
fn expected(width: usize) -> String {
    format!("({width},) or (N, {width})")
}

/// `None` for shape `(width,)`, `Some(N)` for `(N, width)`, else an error naming the shapes.
fn count_of(shape: &[usize], name: &str, width: usize, family: Family) -> PyResult<Option<usize>> {
    match shape {
        [n] if *n == width => Ok(None),
        [n, w] if *w == width => Ok(Some(*n)),
        _ => Err(family.err(format!(
            "{name} must have shape {}, got {}",
            expected(width),
            shape_text(shape)
        ))),
    }
}

/// Refuses an array (anything with a numpy `dtype`) whose numbers are not real: numpy would drop
/// the imaginary part of complex numbers with only a warning (and read text or objects).
/// `what` completes "`name` must be …".
pub(crate) fn real_dtype(
    obj: &Bound<'_, PyAny>,
    name: &str,
    what: &str,
    family: Family,
) -> PyResult<()> {
    if let Ok(kind) = obj
        .getattr(pyo3::intern!(obj.py(), "dtype"))
        .and_then(|d| d.getattr(pyo3::intern!(obj.py(), "kind")))
        .and_then(|k| k.extract::<String>())
        && !matches!(kind.as_str(), "f" | "i" | "u")
    {
        return Err(family.err(format!("{name} must be {what}; got dtype kind {kind:?}")));
    }
    Ok(())
}

/// `N` real numbers (a sequence or an array of shape `(N,)`), refused when complex (see
/// [`real_dtype`]).
pub(crate) fn reals<const N: usize>(
    obj: &Bound<'_, PyAny>,
    name: &str,
    family: Family,
) -> PyResult<[f64; N]> {
    let what = format!("{N} real numbers");
    real_dtype(obj, name, &what, family)?;
    obj.extract()
        .map_err(|_| family.err(format!("{name} must be {what}")))
}

/// The values and stack size of an argument that is not a C-contiguous float64 ndarray (a list,
/// an integer array, a strided view …), converted by numpy.
fn converted(
    obj: &Bound<'_, PyAny>,
    name: &str,
    width: usize,
    family: Family,
) -> PyResult<(Vec<f64>, Option<usize>)> {
    real_dtype(
        obj,
        name,
        &format!("a float64 array of shape {}", expected(width)),
        family,
    )?;
    let array = obj
        .extract::<PyArrayLikeDyn<'_, f64, AllowTypeChange>>()
        .map_err(|e| {
            let kind = obj
                .get_type()
                .name()
                .map_or_else(|_| "?".to_string(), |n| n.to_string());
            family.err(format!(
                "{name} must be a float64 array of shape {}; got a {kind} that does not convert ({e})",
                expected(width)
            ))
        })?;
    let count = count_of(array.shape(), name, width, family)?;
    let view = array.as_array();
    // A broadcast view (`np.broadcast_to(q, (10**9, nq))`) is small in memory but not its copy.
    let mut values = reserve(view.len(), name, family)?;
    match view.as_slice() {
        Some(s) => values.extend_from_slice(s),
        None => values.extend(view.iter().copied()),
    }
    Ok((values, count))
}

/// An empty vector with room for `len` values, or an error naming `what` when that much memory
/// cannot be had: a failed allocation would abort the interpreter.
pub(crate) fn reserve(len: usize, what: &str, family: Family) -> PyResult<Vec<f64>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|_| too_big(len, what, family))?;
    Ok(v)
}

/// Refuses a result of `len` values that cannot be allocated (checked before numpy allocates it).
pub(crate) fn fits(len: Option<usize>, what: &str, family: Family) -> PyResult<()> {
    let len = len.ok_or_else(|| too_big(usize::MAX, what, family))?;
    reserve(len, what, family).map(drop)
}

fn too_big(len: usize, what: &str, family: Family) -> PyErr {
    family.err(format!(
        "{what}: {len} values ({:.1e} bytes) do not fit in memory",
        len as f64 * 8.0
    ))
}

/// A real scalar argument: what an `f64` parameter accepts, except complex numbers.
///
/// PyO3 converts through `float()`, and numpy's complex scalars answer that by dropping their
/// imaginary part with only a `ComplexWarning`: a silent wrong input. They are a `TypeError`
/// naming the argument here, as Python's own `complex` already is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Real(pub(crate) f64);

impl<'a, 'py> FromPyObject<'a, 'py> for Real {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        // A float (numpy's float64 included) or an int is the common case: no dtype lookup.
        if let Ok(x) = obj.cast::<PyFloat>() {
            return Ok(Self(x.value()));
        }
        if !obj.is_instance_of::<PyInt>() {
            let complex = obj.is_instance_of::<PyComplex>()
                || obj
                    .getattr(pyo3::intern!(obj.py(), "dtype"))
                    .and_then(|d| d.getattr(pyo3::intern!(obj.py(), "kind")))
                    .and_then(|k| k.extract::<String>())
                    .is_ok_and(|kind| kind == "c");
            if complex {
                return Err(PyTypeError::new_err(
                    "a complex number where a real number is expected",
                ));
            }
        }
        obj.extract::<f64>().map(Self)
    }
}

/// A whole-number argument (a count, a size, a seed): any Python `int`, checked by name where
/// it is used ([`Count::get`]).
///
/// A `usize` or `u64` parameter would let PyO3 raise `OverflowError` for `-1` or `10**30`, not
/// a kinetree error naming the argument; other types stay a `TypeError` naming it.
#[derive(Clone, Debug)]
pub(crate) struct Count(Result<u64, String>);

impl<'a, 'py> FromPyObject<'a, 'py> for Count {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        match obj.extract::<u64>() {
            Ok(n) => Ok(Self(Ok(n))),
            // Negative or too large: kept as text for the error that names the argument.
            Err(_) if obj.is_instance_of::<PyInt>() => Ok(Self(Err(obj.str()?.to_string()))),
            Err(e) => Err(e),
        }
    }
}

impl Count {
    /// A default value in a `#[pyo3(signature)]`.
    pub(crate) const fn of(n: u64) -> Self {
        Self(Ok(n))
    }

    /// The value, or the `family`'s error naming `name` for a negative or too large one.
    pub(crate) fn get(&self, name: &str, family: Family) -> PyResult<u64> {
        self.0.clone().map_err(|text| {
            family.err(format!(
                "{name} must be a whole number from 0 to {}, got {text}",
                u64::MAX
            ))
        })
    }

    /// [`Count::get`] as a `usize`.
    pub(crate) fn size(&self, name: &str, family: Family) -> PyResult<usize> {
        let n = self.get(name, family)?;
        usize::try_from(n).map_err(|_| family.err(format!("{name} = {n} does not fit a usize")))
    }
}

/// A finite scalar argument.
pub(crate) fn finite(x: f64, name: &str, family: Family) -> PyResult<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(family.err(format!("{name} is {x}: inputs must be finite")))
    }
}

/// `(a, b)` for a shape.
pub(crate) fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The common stack size of `inputs`: `None` when all are single states.
pub(crate) fn batch_count(inputs: &[&States], family: Family) -> PyResult<Option<usize>> {
    let first = inputs.first().and_then(|s| s.count);
    for s in inputs {
        if s.count != first {
            let describe = |s: &States| match s.count {
                None => format!("{} is one state", s.name),
                Some(n) => format!("{} stacks {n} states", s.name),
            };
            return Err(family.err(format!(
                "{} but {}: stack all inputs alike",
                describe(inputs[0]),
                describe(s)
            )));
        }
    }
    Ok(first)
}

/// The result of a computation over a block of states: on failure, the index of the failing
/// state within the block and its error (boxed: errors are rare and large).
pub(crate) type BlockResult = Result<(), Box<(usize, kinetree::Error)>>;

/// Turns a per-state computation `f(scratch, state, out)` into one over a block of `n`
/// consecutive states (`block[k]` holds input `k` of every state of the block, one after the
/// other; `out` their results, one after the other).
pub(crate) fn each_state<S, F>(
    f: F,
) -> impl Fn(&mut S, usize, &[&[f64]], &mut [f64]) -> BlockResult + Sync
where
    F: Fn(&mut S, &[&[f64]], &mut [f64]) -> Result<(), kinetree::Error> + Sync,
{
    move |scratch, n, block, out| {
        let size = out.len() / n.max(1);
        for j in 0..n {
            let mut state: [&[f64]; 4] = [&[]; 4];
            for (x, input) in state.iter_mut().zip(block) {
                let width = input.len() / n;
                *x = &input[j * width..(j + 1) * width];
            }
            f(
                scratch,
                &state[..block.len()],
                &mut out[j * size..(j + 1) * size],
            )
            .map_err(|e| Box::new((j, e)))?;
        }
        Ok(())
    }
}

/// The error of a batched entry point of the Rust crates as [`BlockResult`] wants it: the state
/// it names and that state's own error.
pub(crate) fn in_block(error: kinetree::Error) -> Box<(usize, kinetree::Error)> {
    use kinetree::Error as E;
    use kinetree::dynamics::DynamicsError;
    use kinetree::kinematics::KinematicsError;
    Box::new(match error {
        E::Kinematics(KinematicsError::InBatchState { index, source }) => (index, (*source).into()),
        E::Dynamics(DynamicsError::InBatchState { index, source }) => (index, (*source).into()),
        other => (0, other),
    })
}

/// Inputs of states `first..last` (all inputs stacked alike): one slice per input.
pub(crate) fn block_of<'a>(inputs: &[&'a States], first: usize, last: usize) -> [&'a [f64]; 4] {
    let mut s: [&[f64]; 4] = [&[]; 4];
    for (x, input) in s.iter_mut().zip(inputs) {
        *x = &input.values[first * input.width..last * input.width];
    }
    s
}

/// [`block_of`], after checking that the block's numbers of the inputs left unchecked by
/// [`stack_states`] are finite. The error (its state numbered in the block, as a block
/// computation's) only marks the block as failed: [`stack_failure`] names the first bad number
/// of the whole stack.
pub(crate) fn checked_block<'a>(
    inputs: &[&'a States],
    first: usize,
    last: usize,
) -> Result<[&'a [f64]; 4], Box<(usize, kinetree::Error)>> {
    let block = block_of(inputs, first, last);
    for (x, input) in block.iter().zip(inputs) {
        if input.unchecked
            && let Some(k) = first_non_finite(x)
        {
            let what = input.name;
            let index = k % input.width.max(1);
            let error = kinetree::kinematics::KinematicsError::NonFinite { what, index };
            return Err(Box::new((k / input.width.max(1), error.into())));
        }
    }
    Ok(block)
}

/// The Python error of a failed stack: the first number that is not finite of an input left
/// unchecked by [`stack_states`] (named as [`states`] names it), else the failed state's error.
pub(crate) fn stack_failure(
    inputs: &[&States],
    family: Family,
    failed: Box<(usize, kinetree::Error)>,
) -> PyErr {
    for input in inputs.iter().filter(|s| s.unchecked) {
        if let Err(e) = input.check_finite(family) {
            return e;
        }
    }
    stack_error(failed)
}

/// Runs `run` on every block, on the calling thread and on rayon's workers at once
/// ([`Parallel::for_each_block`]), each taking the next block no one has taken; returns the
/// error of the lowest failing state (whichever thread ran its block).
///
/// The calling thread starts at once instead of waiting for a sleeping worker to pick the call
/// up: on this project's 2-vCPU VM a worker woken after a few milliseconds idle took about as
/// long as a whole derivatives call of 1 000 states, so a call made between Python work (a
/// loop, another library) ran slower than on one thread. Workers that wake in time take their
/// share of the blocks; the result does not depend on who ran which. The blocks take their
/// workspaces from the model's pool, so the threads need none of their own.
pub(crate) fn par_blocks<T: Send>(
    blocks: Vec<T>,
    run: impl Fn(T) -> BlockResult + Sync,
) -> BlockResult {
    let mut threads = Parallel::from_fn(rayon::current_num_threads(), |_| ());
    threads.for_each_block(blocks, &|_, block| run(block))
}

/// Blocks per worker thread of a stacked call: enough for the workers to even out when one is
/// slowed down (the machine is shared), few enough that taking a workspace per block is free.
pub(crate) const BLOCKS_PER_THREAD: usize = 8;

/// States per block are a multiple of this, so that the batched kernels fill whole SIMD lanes.
pub(crate) const LANES: usize = 8;

/// Stacks of at most this many states run on the calling thread with the GIL held: one SIMD
/// block, a few microseconds at most, less than handing it to the workers costs.
pub(crate) const INLINE_STATES: usize = LANES;

/// Runs the block computation `f` on the one state of `inputs`, here (the GIL held), with a
/// workspace of the model's pool.
fn one_state<S, F>(model: &PyModel, inputs: &[&States], out: &mut [f64], f: &F) -> PyResult<()>
where
    S: Scratch,
    F: Fn(&mut S, usize, &[&[f64]], &mut [f64]) -> BlockResult,
{
    S::with(model, |scratch| {
        f(scratch, 1, &block_of(inputs, 0, 1)[..inputs.len()], out)
    })
    .map_err(|failed| to_py(&failed.1, false))
}

/// Runs the block computation `f` on every state of a stack of `n`, in parallel with the GIL
/// released: the states are cut into a few contiguous blocks, each run by one worker with one
/// workspace, writing straight into its rows of `out` (`size` numbers per state). Each worker
/// checks its block of an input left unchecked by [`stack_states`] first. An error (of `family`
/// for a bad number) names the first bad number, else the failing state.
fn map_stack<S, F>(
    py: Python<'_>,
    model: &PyModel,
    inputs: &[&States],
    (n, size): (usize, usize),
    out: &mut [f64],
    family: Family,
    f: &F,
) -> PyResult<()>
where
    S: Scratch,
    F: Fn(&mut S, usize, &[&[f64]], &mut [f64]) -> BlockResult + Sync,
{
    if n == 0 {
        return Ok(());
    }
    let n_in = inputs.len();
    if n <= INLINE_STATES {
        // Too little work to pay for releasing the GIL and waking the workers.
        return S::with(model, |scratch| {
            f(scratch, n, &checked_block(inputs, 0, n)?[..n_in], out)
        })
        .map_err(|failed| stack_failure(inputs, family, failed));
    }
    let threads = rayon::current_num_threads().max(1);
    let block = n
        .div_ceil(threads * BLOCKS_PER_THREAD)
        .next_multiple_of(LANES);
    let blocks: Vec<(usize, &mut [f64])> = if size == 0 {
        (0..n.div_ceil(block))
            .map(|b| (b * block, &mut [][..]))
            .collect()
    } else {
        out.chunks_mut(block * size)
            .enumerate()
            .map(|(b, chunk)| (b * block, chunk))
            .collect()
    };
    let result = py.detach(|| {
        par_blocks(blocks, |(first, chunk)| {
            let last = (first + block).min(n);
            S::with(model, |scratch| {
                f(
                    scratch,
                    last - first,
                    &checked_block(inputs, first, last)?[..n_in],
                    chunk,
                )
            })
            .map_err(|mut failed| {
                failed.0 += first;
                failed
            })
        })
    });
    result.map_err(|failed| stack_failure(inputs, family, failed))
}

/// The Python error of a failed state of a stack, naming the state.
#[allow(clippy::boxed_local, reason = "the error as the blocks return it")]
pub(crate) fn stack_error(failed: Box<(usize, kinetree::Error)>) -> PyErr {
    let (i, e) = &*failed;
    family_of(e).err(format!("state {i}: {e}"))
}

/// The array a call writes its result into: the caller's `out` when given, checked to be a
/// float64 ndarray of exactly `shape` and C-contiguous (errors of `family` name the expected
/// shape; [`map_states`] refuses one that cannot be written); else a new zeroed array of `shape`, refused with an error when it would not fit
/// in memory.
pub(crate) fn output<'py>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyAny>>,
    shape: &[usize],
    family: Family,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let Some(obj) = out else {
        let len = shape.iter().try_fold(1usize, |n, &k| n.checked_mul(k));
        fits(len, "the result", family)?;
        return Ok(PyArrayDyn::<f64>::zeros(py, IxDyn(shape), false));
    };
    let wanted = || {
        format!(
            "out must be a C-contiguous, writeable float64 numpy array of shape {}",
            shape_text(shape)
        )
    };
    let Ok(array) = obj.cast::<PyArrayDyn<f64>>() else {
        let got = match obj
            .getattr(pyo3::intern!(py, "dtype"))
            .and_then(|d| d.str())
        {
            Ok(dtype) => format!("an array of dtype {dtype}"),
            Err(_) => format!(
                "a {}",
                obj.get_type()
                    .name()
                    .map_or_else(|_| "?".to_string(), |n| n.to_string())
            ),
        };
        return Err(family.err(format!("{}; got {got}", wanted())));
    };
    if array.shape() != shape {
        return Err(family.err(format!(
            "{}; got shape {}",
            wanted(),
            shape_text(array.shape())
        )));
    }
    if !array.is_c_contiguous() {
        return Err(family.err(format!("{}; got a non-contiguous view", wanted())));
    }
    Ok(array.clone())
}

/// Runs a computation on one state or on every state of a stack and returns its results as one
/// array of shape `out_shape`, or `(N, *out_shape)` for a stack of `N`, with the stack size.
///
/// The array is the caller's `out` when given (see [`output`]), else a new one. One state runs
/// as `one(out)`, here with the GIL held; a stack runs the block computation `f` as
/// [`map_stack`]. Both write straight into the array, and give each state the same arithmetic.
#[allow(
    clippy::too_many_arguments,
    reason = "the one map every per-state call goes through"
)]
pub(crate) fn map_states<'py, S, O, F>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    out_shape: &[usize],
    out: Option<&Bound<'py, PyAny>>,
    family: Family,
    one: O,
    f: F,
) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Option<usize>)>
where
    S: Scratch,
    O: FnOnce(&mut [f64]) -> PyResult<()>,
    F: Fn(&mut S, usize, &[&[f64]], &mut [f64]) -> BlockResult + Sync,
{
    let size: usize = out_shape.iter().product();
    let count = batch_count(inputs, family)?;
    let mut shape = Vec::with_capacity(out_shape.len() + 1);
    shape.extend(count);
    shape.extend_from_slice(out_shape);
    if count.is_none() && out.is_none() {
        // One state into a new array: computed in a scratch buffer of this thread and copied into
        // an array made for it (cheaper than a zeroed array and numpy's borrow tracking).
        let array = with_scratch(size, |values| {
            one(values)?;
            PyResult::Ok(view(out_shape, values)?.to_pyarray(py))
        })?;
        return Ok((array, None));
    }
    let array = output(py, out, &shape, family)?;
    let not_writeable = |e: &dyn std::fmt::Display| {
        family.err(format!(
            "out cannot be written ({e}): pass a writeable float64 array of shape {}",
            shape_text(&shape)
        ))
    };
    if count.is_none() {
        // One state into the caller's array, written here with the GIL held: no other Python
        // code runs until the call returns, so numpy's borrow tracking (a third of the cost of a
        // small call) is not needed. The flags are checked as the tracking would.
        if !is_writeable(&array) {
            return Err(not_writeable(&"the array is read-only"));
        }
        // SAFETY: `array` is a C-contiguous float64 array of `size` numbers (checked by
        // `output`), aligned (numpy aligns float64 arrays it allocates; a misaligned view fails
        // `as_slice_mut`) and writeable. The slice lives only during `one`, which is Rust code
        // run with the GIL held (it calls no Python code), and the inputs were copied out of
        // their arrays before, so nothing else reads or writes this memory meanwhile.
        #[allow(unsafe_code, reason = "numpy's borrow tracking skipped under the GIL")]
        let values = unsafe { array.as_slice_mut() }.map_err(|e| not_writeable(&e))?;
        one(values)?;
        return Ok((array, None));
    }
    {
        let mut writable = array.try_readwrite().map_err(|e| not_writeable(&e))?;
        let values = writable.as_slice_mut()?;
        match count {
            None => one(values)?,
            Some(n) => {
                let copies = copies_apart(inputs, &[address_range(values)], family)?;
                let inputs = apart(inputs, &copies);
                map_stack(py, model, &inputs, (n, size), values, family, &f)?;
            }
        }
    }
    Ok((array, count))
}

/// Copies of the inputs read in place from memory that one of `targets` (the addresses of the
/// results) shares, `None` for the others: results are written while the inputs are read. Pass
/// them to [`apart`].
pub(crate) fn copies_apart(
    inputs: &[&States],
    targets: &[Range<usize>],
    family: Family,
) -> PyResult<Vec<Option<States>>> {
    inputs
        .iter()
        .map(|s| {
            let shared = s.values.shared_range();
            shared
                .filter(|r| targets.iter().any(|t| r.start < t.end && t.start < r.end))
                .map(|_| s.copied(family))
                .transpose()
        })
        .collect()
}

/// The inputs with the copies of [`copies_apart`] in place of the originals.
pub(crate) fn apart<'a>(inputs: &[&'a States], copies: &'a [Option<States>]) -> Vec<&'a States> {
    inputs
        .iter()
        .zip(copies)
        .map(|(s, copy)| copy.as_ref().unwrap_or(s))
        .collect()
}

/// Whether numpy may write into `array` (its `WRITEABLE` flag).
fn is_writeable(array: &Bound<'_, PyArrayDyn<f64>>) -> bool {
    // SAFETY: `array` is a live numpy array (a checked cast), so its object holds the flags.
    #[allow(unsafe_code, reason = "numpy's array flags have no safe accessor")]
    let flags = unsafe { (*numpy::npyffi::_PyArray_GET_ITEM_DATA(array.as_array_ptr())).flags };
    flags & numpy::npyffi::NPY_ARRAY_WRITEABLE != 0
}

thread_local! {
    /// The result of a one-state call on this thread, before it is copied into its array.
    static SCRATCH: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with `len` numbers of this thread's scratch buffer (a fresh buffer when it is in use).
fn with_scratch<R>(len: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
    SCRATCH.with(|s| match s.try_borrow_mut() {
        Ok(mut s) => {
            if s.len() < len {
                s.resize(len, 0.0);
            }
            f(&mut s[..len])
        }
        Err(_) => f(&mut vec![0.0; len]),
    })
}

/// `values` seen as an array of `shape` (row-major).
fn view<'a>(shape: &[usize], values: &'a [f64]) -> PyResult<ArrayViewD<'a, f64>> {
    ArrayViewD::from_shape(IxDyn(shape), values).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("internal shape error: {e}"))
    })
}

/// [`map_states`] of a call with a batched entry point in the Rust crates: one state runs the
/// one-state function `one(data, state, out)` with a pooled workspace (a batched kernel would
/// compute a whole SIMD block for it), a stack runs the block computation `f`. Returns `out`
/// when given, else a new array.
#[allow(
    clippy::too_many_arguments,
    reason = "map_states' arguments and the one-state function"
)]
pub(crate) fn run_blocks<'py, S, O, F>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    out_shape: &[usize],
    out: Option<&Bound<'py, PyAny>>,
    family: Family,
    one: O,
    f: F,
) -> PyResult<Bound<'py, PyAny>>
where
    S: Scratch,
    O: FnOnce(&mut DynamicsData, &[&[f64]], &mut [f64]) -> Result<(), kinetree::Error>,
    F: Fn(&mut S, usize, &[&[f64]], &mut [f64]) -> BlockResult + Sync,
{
    let one = |values: &mut [f64]| {
        <DynamicsData as Scratch>::with(model, |d| {
            one(d, &block_of(inputs, 0, 1)[..inputs.len()], values)
        })
        .map_err(|e| to_py(&e, false))
    };
    Ok(
        map_states(py, model, inputs, out_shape, out, family, one, f)?
            .0
            .into_any(),
    )
}

/// [`run_with`] a dynamics workspace: the per-state calls of the kinematics and dynamics layers.
pub(crate) fn run<'py, F>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    out_shape: &[usize],
    family: Family,
    f: F,
) -> PyResult<Bound<'py, PyAny>>
where
    F: Fn(&mut DynamicsData, &[&[f64]], &mut [f64]) -> Result<(), kinetree::Error> + Sync,
{
    run_with(py, model, inputs, out_shape, family, f)
}

/// [`map_states`] for the per-state calls: one state with an empty `out_shape` gives a Python
/// float, anything else the array.
pub(crate) fn run_with<'py, S, F>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    out_shape: &[usize],
    family: Family,
    f: F,
) -> PyResult<Bound<'py, PyAny>>
where
    S: Scratch,
    F: Fn(&mut S, &[&[f64]], &mut [f64]) -> Result<(), kinetree::Error> + Sync,
{
    let f = each_state(f);
    if out_shape.is_empty() && batch_count(inputs, family)?.is_none() {
        let mut out = [0.0];
        one_state(model, inputs, &mut out, &f)?;
        return Ok(PyFloat::new(py, out[0]).into_any());
    }
    let one = |values: &mut [f64]| one_state(model, inputs, values, &f);
    Ok(
        map_states(py, model, inputs, out_shape, None, family, one, &f)?
            .0
            .into_any(),
    )
}

/// A numpy array of `shape` owning `values` (row-major).
pub(crate) fn to_numpy<'py>(
    py: Python<'py>,
    shape: &[usize],
    values: Vec<f64>,
) -> PyResult<Bound<'py, numpy::PyArrayDyn<f64>>> {
    let array = ArrayD::from_shape_vec(IxDyn(shape), values).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("internal shape error: {e}"))
    })?;
    Ok(array.into_pyarray(py))
}
