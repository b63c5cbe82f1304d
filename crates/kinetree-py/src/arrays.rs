//! numpy in and out: checked inputs ([`States`]) and the one map over stacked states
//! ([`map_states`], wrapped by [`run`] and [`run_parts`]).
//!
//! Every per-state call takes one state (`q` of shape `(nq,)`) or a stack (`(N, nq)`). One state
//! runs directly, with a workspace from the model's [`Pool`]; a stack runs in parallel (rayon)
//! with the GIL released, in a few contiguous blocks with one pooled workspace each, so each
//! state gets exactly the arithmetic of a one-state call. Results are written straight into the
//! numpy array returned.

use crate::errors::{Family, family_of, to_py};
use crate::model::PyModel;
use kinetree::dynamics::batch::DynamicsBatch;
use kinetree::dynamics::{DerivativesData, DynamicsData, JointTerms};
use kinetree::kinematics::batch::KinematicsBatch;
use kinetree::kinematics::spatial::{Motion, Se3};
use kinetree::model::Model;
use numpy::ndarray::{ArrayD, ArrayViewD, IxDyn};
use numpy::{
    AllowTypeChange, IntoPyArray, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods,
    PyUntypedArrayMethods, ToPyArray,
};
use pyo3::prelude::*;
use pyo3::types::PyFloat;
use rayon::prelude::*;
use std::sync::{Mutex, PoisonError};

/// Two arrays returned together (`simulate`'s configurations and velocities, `bounds`' corners).
pub(crate) type ArrayPair<'py> = (
    Bound<'py, numpy::PyArrayDyn<f64>>,
    Bound<'py, numpy::PyArrayDyn<f64>>,
);

/// One input: a single state or a stack of states, each `width` numbers, all finite.
#[derive(Debug)]
pub(crate) struct States {
    /// Row-major values, `width` per state.
    pub(crate) values: Vec<f64>,
    /// Numbers per state.
    pub(crate) width: usize,
    /// `None` for one state (a 1-D array), `Some(N)` for a stack (a 2-D array).
    pub(crate) count: Option<usize>,
    /// The argument's name, for messages.
    pub(crate) name: &'static str,
}

impl States {
    /// The values of state `i` (the only state when not stacked).
    pub(crate) fn state(&self, i: usize) -> &[f64] {
        &self.values[i * self.width..(i + 1) * self.width]
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
    let values = match obj.cast::<PyArrayDyn<f64>>() {
        Ok(array) if array.is_c_contiguous() => {
            let count = count_of(array.shape(), name, width, family)?;
            let unreadable = |e: &dyn std::fmt::Display| {
                family.err(format!("{name} cannot be read as a float64 buffer: {e}"))
            };
            let readonly = array.try_readonly().map_err(|e| unreadable(&e))?;
            let slice = readonly.as_slice().map_err(|e| unreadable(&e))?;
            let mut values = reserve(slice.len(), name, family)?;
            values.extend_from_slice(slice);
            (values, count)
        }
        _ => converted(obj, name, width, family)?,
    };
    let (values, count) = values;
    if let Some(k) = values.iter().position(|x| !x.is_finite()) {
        let at = if count.is_some() && width > 0 {
            format!("[{}, {}]", k / width, k % width)
        } else {
            format!("[{k}]")
        };
        return Err(family.err(format!(
            "{name}{at} is {}: inputs must be finite",
            values[k]
        )));
    }
    Ok(States {
        values,
        width,
        count,
        name,
    })
}

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

/// The values and stack size of an argument that is not a C-contiguous float64 ndarray (a list,
/// an integer array, a strided view …), converted by numpy.
fn converted(
    obj: &Bound<'_, PyAny>,
    name: &str,
    width: usize,
    family: Family,
) -> PyResult<(Vec<f64>, Option<usize>)> {
    // numpy would drop the imaginary part of complex numbers (and read text or objects): only
    // real numbers convert.
    if let Ok(kind) = obj
        .getattr(pyo3::intern!(obj.py(), "dtype"))
        .and_then(|d| d.getattr(pyo3::intern!(obj.py(), "kind")))
        .and_then(|k| k.extract::<String>())
        && !matches!(kind.as_str(), "f" | "i" | "u")
    {
        return Err(family.err(format!(
            "{name} must be a float64 array of shape {}; got dtype kind {kind:?}",
            expected(width)
        )));
    }
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

/// A fresh workspace for `model`: rigid-body dynamics (the joints' damping, friction and armature
/// left out, as in Pinocchio and the contract).
pub(crate) fn new_data(model: &Model) -> DynamicsData {
    DynamicsData::with_joint_terms(model, JointTerms::Ignored)
}

/// A fresh workspace for the analytic derivatives, rigid-body as [`new_data`].
pub(crate) fn new_derivatives_data(model: &Model) -> DerivativesData {
    DerivativesData::with_joint_terms(model, JointTerms::Ignored)
}

/// Workspaces of one kind kept by a model for reuse: a one-state call takes one and gives it
/// back, and each worker of a stacked call takes one for its whole block of states, so calls
/// after the first allocate no workspace.
#[derive(Debug)]
pub(crate) struct Pool<S>(Mutex<Vec<S>>);

impl<S> Default for Pool<S> {
    fn default() -> Self {
        Self(Mutex::new(Vec::new()))
    }
}

impl<S> Pool<S> {
    /// Runs `f` with a workspace of the pool, made by `fresh` when none is free.
    fn with<R>(&self, fresh: impl FnOnce() -> S, f: impl FnOnce(&mut S) -> R) -> R {
        let taken = self.0.lock().unwrap_or_else(PoisonError::into_inner).pop();
        let mut scratch = taken.unwrap_or_else(fresh);
        let result = f(&mut scratch);
        self.0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(scratch);
        result
    }
}

/// The workspace a per-state computation needs, and where a model keeps spare ones.
pub(crate) trait Scratch: Send + Sized {
    /// Runs `f` with a workspace for `model` (taken from its pool, or made).
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R;
}

/// Computations that need no workspace (the configuration-space operations).
impl Scratch for () {
    fn with<R>(_: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        f(&mut ())
    }
}

impl Scratch for DynamicsData {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        model.dynamics_pool.with(|| new_data(&model.model), f)
    }
}

impl Scratch for DerivativesData {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        model
            .derivatives_pool
            .with(|| new_derivatives_data(&model.model), f)
    }
}

impl Scratch for DynamicsBatch {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        model.dynamics_batch_pool.with(
            || DynamicsBatch::with_joint_terms(&model.model, JointTerms::Ignored),
            f,
        )
    }
}

/// The workspace of the batched kinematics, with room for a block's placements or Jacobian
/// columns before they are written out as numpy rows.
#[derive(Debug)]
pub(crate) struct KinematicsBlock {
    /// The batched kernels' buffers.
    pub(crate) batch: KinematicsBatch,
    /// Link placements of a block of states.
    pub(crate) poses: Vec<Se3>,
    /// Jacobian columns of a block of states.
    pub(crate) columns: Vec<Motion>,
}

impl KinematicsBlock {
    /// The kernels' buffers and the first `n` placements (the buffer grown, once, when a block
    /// needs more).
    pub(crate) fn poses(&mut self, n: usize) -> (&mut KinematicsBatch, &mut [Se3]) {
        if self.poses.len() < n {
            self.poses.resize(n, Se3::IDENTITY);
        }
        (&mut self.batch, &mut self.poses[..n])
    }

    /// The kernels' buffers and the first `n` Jacobian columns, grown as
    /// [`poses`](Self::poses).
    pub(crate) fn columns(&mut self, n: usize) -> (&mut KinematicsBatch, &mut [Motion]) {
        if self.columns.len() < n {
            self.columns.resize(n, Motion::ZERO);
        }
        (&mut self.batch, &mut self.columns[..n])
    }
}

impl Scratch for KinematicsBlock {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        let fresh = || KinematicsBlock {
            batch: KinematicsBatch::new(&model.model),
            poses: Vec::new(),
            columns: Vec::new(),
        };
        model.kinematics_batch_pool.with(fresh, f)
    }
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
fn block_of<'a>(inputs: &[&'a States], first: usize, last: usize) -> [&'a [f64]; 4] {
    let mut s: [&[f64]; 4] = [&[]; 4];
    for (x, input) in s.iter_mut().zip(inputs) {
        *x = &input.values[first * input.width..last * input.width];
    }
    s
}

/// Blocks per worker thread of a stacked call: enough for the workers to even out when one is
/// slowed down (the machine is shared), few enough that taking a workspace per block is free.
const BLOCKS_PER_THREAD: usize = 8;

/// States per block are a multiple of this, so that the batched kernels fill whole SIMD lanes.
const LANES: usize = 8;

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
/// workspace, writing straight into its rows of `out` (`size` numbers per state). An error names
/// the failing state.
fn map_stack<S, F>(
    py: Python<'_>,
    model: &PyModel,
    inputs: &[&States],
    n: usize,
    size: usize,
    out: &mut [f64],
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
        blocks.into_par_iter().try_for_each(|(first, chunk)| {
            let last = (first + block).min(n);
            S::with(model, |scratch| {
                f(
                    scratch,
                    last - first,
                    &block_of(inputs, first, last)[..n_in],
                    chunk,
                )
            })
            .map_err(|mut failed| {
                failed.0 += first;
                failed
            })
        })
    });
    result.map_err(|failed| {
        let (i, e) = &*failed;
        family_of(e).err(format!("state {i}: {e}"))
    })
}

/// Runs the block computation `f` on one state or on every state of a stack; returns a new
/// numpy array of shape `out_shape`, or `(N, *out_shape)` for a stack of `N`, and the stack
/// size.
///
/// One state runs as [`one_state`] and is copied into the array; a stack runs as [`map_stack`],
/// writing straight into the array. Both give each state exactly the same arithmetic.
pub(crate) fn map_states<'py, S, F>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    out_shape: &[usize],
    family: Family,
    f: F,
) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Option<usize>)>
where
    S: Scratch,
    F: Fn(&mut S, usize, &[&[f64]], &mut [f64]) -> BlockResult + Sync,
{
    let size: usize = out_shape.iter().product();
    match batch_count(inputs, family)? {
        None => {
            let mut out = vec![0.0; size];
            one_state(model, inputs, &mut out, &f)?;
            Ok((view(out_shape, &out)?.to_pyarray(py), None))
        }
        Some(n) => {
            let mut shape = Vec::with_capacity(out_shape.len() + 1);
            shape.push(n);
            shape.extend_from_slice(out_shape);
            fits(n.checked_mul(size), "the stacked result", family)?;
            let array = PyArrayDyn::<f64>::zeros(py, IxDyn(&shape), false);
            {
                let mut writable = array.readwrite();
                let out = writable.as_slice_mut()?;
                map_stack(py, model, inputs, n, size, out, &f)?;
            }
            Ok((array, Some(n)))
        }
    }
}

/// `values` seen as an array of `shape` (row-major).
fn view<'a>(shape: &[usize], values: &'a [f64]) -> PyResult<ArrayViewD<'a, f64>> {
    ArrayViewD::from_shape(IxDyn(shape), values).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("internal shape error: {e}"))
    })
}

/// [`map_states`] of a block computation (a batched entry point of the Rust crates), as an
/// array.
pub(crate) fn run_blocks<'py, S, F>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    out_shape: &[usize],
    family: Family,
    f: F,
) -> PyResult<Bound<'py, PyAny>>
where
    S: Scratch,
    F: Fn(&mut S, usize, &[&[f64]], &mut [f64]) -> BlockResult + Sync,
{
    Ok(map_states(py, model, inputs, out_shape, family, f)?
        .0
        .into_any())
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
    Ok(map_states(py, model, inputs, out_shape, family, f)?
        .0
        .into_any())
}

/// [`map_states`] for calls with `P` results of `nv x nv` each (the analytic derivatives):
/// `f(data, state)` returns the `P` matrices (row-major slices of the workspace); they come back
/// as `P` arrays of shape `(nv, nv)`, or `(N, nv, nv)` for a stack.
pub(crate) fn run_parts<'py, const P: usize, F>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    family: Family,
    f: F,
) -> PyResult<[Bound<'py, PyArrayDyn<f64>>; P]>
where
    F: for<'d> Fn(&'d mut DerivativesData, &[&[f64]]) -> Result<[&'d [f64]; P], kinetree::Error>
        + Sync,
{
    let nv = model.model.nv();
    let size = nv * nv;
    let f = each_state(
        move |d: &mut DerivativesData, x: &[&[f64]], out: &mut [f64]| {
            for (m, o) in f(d, x)?.iter().zip(out.chunks_exact_mut(size.max(1))) {
                o.copy_from_slice(m);
            }
            Ok(())
        },
    );
    let parts: Vec<_> = if batch_count(inputs, family)?.is_none() {
        let mut out = vec![0.0; P * size];
        one_state(model, inputs, &mut out, &f)?;
        (0..P)
            .map(|p| Ok(view(&[nv, nv], &out[p * size..(p + 1) * size])?.to_pyarray(py)))
            .collect::<PyResult<_>>()?
    } else {
        let (all, count) = map_states(py, model, inputs, &[P, nv, nv], family, f)?;
        let n = count.unwrap_or(1);
        let readonly = all.readonly();
        let values = readonly.as_slice()?;
        (0..P)
            .map(|p| {
                let part = PyArrayDyn::<f64>::zeros(py, IxDyn(&[n, nv, nv]), false);
                {
                    let mut writable = part.readwrite();
                    let dst = writable.as_slice_mut()?;
                    for (i, d) in dst.chunks_exact_mut(size.max(1)).enumerate() {
                        let start = (i * P + p) * size;
                        d.copy_from_slice(&values[start..start + size]);
                    }
                }
                Ok(part)
            })
            .collect::<PyResult<_>>()?
    };
    parts
        .try_into()
        .map_err(|_| pyo3::exceptions::PyRuntimeError::new_err("internal: wrong number of results"))
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
