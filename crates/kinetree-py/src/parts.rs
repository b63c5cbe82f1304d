//! Calls with several `nv x nv` results per state (the analytic derivatives): each result is its
//! own array, made here and written in place, by the workers for a stack.

use crate::arrays::{
    BLOCKS_PER_THREAD, BlockResult, INLINE_STATES, LANES, States, batch_count, block_of, fits,
    stack_error,
};
use crate::errors::{Family, to_py};
use crate::model::PyModel;
use crate::scratch::Scratch;
use kinetree::dynamics::DerivativesData;
use numpy::ndarray::IxDyn;
use numpy::{PyArrayDyn, PyArrayMethods};
use pyo3::prelude::*;
use rayon::prelude::*;

/// Makes the `P` result arrays, zero, of shape `(nv, nv)`, or `(N, nv, nv)` for
/// `count = Some(N)`; runs `fill` with a slice of each to write them through, and returns them.
fn with_parts<'py, const P: usize>(
    py: Python<'py>,
    nv: usize,
    count: Option<usize>,
    family: Family,
    fill: impl FnOnce([&mut [f64]; P]) -> PyResult<()>,
) -> PyResult<[Bound<'py, PyArrayDyn<f64>>; P]> {
    let n = count.unwrap_or(1);
    let mut shape = Vec::with_capacity(3);
    shape.extend(count);
    shape.extend([nv, nv]);
    let len = n.checked_mul(nv * nv).and_then(|k| k.checked_mul(P));
    fits(len, "the results", family)?;
    let arrays: [Bound<'py, PyArrayDyn<f64>>; P] =
        std::array::from_fn(|_| PyArrayDyn::<f64>::zeros(py, IxDyn(&shape), false));
    let mut outs: [&mut [f64]; P] = std::array::from_fn(|_| <&mut [f64]>::default());
    for (o, a) in outs.iter_mut().zip(&arrays) {
        // SAFETY: the arrays were made just above and are not yet visible to Python or to any
        // other code, so these slices are the only access to their memory until they are
        // returned (after the slices' last use, in `fill`); numpy allocates them C-contiguous
        // and aligned.
        #[allow(
            unsafe_code,
            reason = "fresh arrays written without numpy's borrow tracking"
        )]
        let slice = unsafe { a.as_slice_mut() }.map_err(|e| {
            pyo3::exceptions::PyRuntimeError::new_err(format!("internal: a new array: {e}"))
        })?;
        *o = slice;
    }
    fill(outs)?;
    Ok(arrays)
}

/// Runs `f(data, state)`, which returns `P` matrices of `nv x nv` (row-major slices of the
/// workspace), on one state or on every state of a stack, and returns them as `P` arrays of
/// shape `(nv, nv)`, or `(N, nv, nv)` for a stack of `N` (computed in parallel with the GIL
/// released, each state exactly as one call would). Each matrix is copied once, from the
/// workspace into its array.
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
    let count = batch_count(inputs, family)?;
    let n = count.unwrap_or(1);
    let k = inputs.len();
    // States `first..last` into `outs`, which hold their rows of each result.
    let run = |(first, last, mut outs): (usize, usize, [&mut [f64]; P])| -> BlockResult {
        DerivativesData::with(model, |d| {
            for j in first..last {
                let parts = f(d, &block_of(inputs, j, j + 1)[..k]).map_err(|e| Box::new((j, e)))?;
                let at = (j - first) * size;
                for (o, m) in outs.iter_mut().zip(parts) {
                    for (to, from) in o[at..at + size].iter_mut().zip(m) {
                        *to = *from;
                    }
                }
            }
            Ok(())
        })
    };
    with_parts(py, nv, count, family, |outs| {
        if count.is_none() {
            return run((0, 1, outs)).map_err(|failed| to_py(&failed.1, false));
        }
        let threads = rayon::current_num_threads().max(1);
        let block = n.div_ceil(threads * BLOCKS_PER_THREAD).max(1);
        // (`max(1)`: with nv = 0 the results are empty, and a chunk size of 0 would panic.)
        let mut chunks = outs.map(|o| o.chunks_mut((block * size).max(1)));
        let blocks: Vec<(usize, usize, [&mut [f64]; P])> = (0..n.div_ceil(block))
            .map(|b| {
                let rows = std::array::from_fn(|p| chunks[p].next().unwrap_or_default());
                (b * block, ((b + 1) * block).min(n), rows)
            })
            .collect();
        let result = if n <= INLINE_STATES {
            blocks.into_iter().try_for_each(run)
        } else {
            py.detach(|| blocks.into_par_iter().try_for_each(run))
        };
        result.map_err(stack_error)
    })
}

/// As [`run_parts`], with a stack computed block by block through the batched entry point
/// `block(workspace, inputs, outputs)` (a block's states one after the other in each input and
/// output; an error names the state by its index in the block): blocks of whole SIMD lane
/// groups, spread over the worker threads with the GIL released. One state goes through `f`.
pub(crate) fn run_parts_batched<'py, const P: usize, S, F, B>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    family: Family,
    f: F,
    block: B,
) -> PyResult<[Bound<'py, PyArrayDyn<f64>>; P]>
where
    S: Scratch,
    F: for<'d> Fn(&'d mut DerivativesData, &[&[f64]]) -> Result<[&'d [f64]; P], kinetree::Error>
        + Sync,
    B: Fn(&mut S, &[&[f64]], [&mut [f64]; P]) -> BlockResult + Sync,
{
    let Some(n) = batch_count(inputs, family)? else {
        return run_parts(py, model, inputs, family, f);
    };
    let nv = model.model.nv();
    let size = nv * nv;
    let k = inputs.len();
    let run = |(first, last, outs): (usize, usize, [&mut [f64]; P])| -> BlockResult {
        S::with(model, |w| {
            block(w, &block_of(inputs, first, last)[..k], outs)
        })
        .map_err(|mut failed| {
            failed.0 += first;
            failed
        })
    };
    with_parts(py, nv, Some(n), family, |outs| {
        if n <= INLINE_STATES {
            // Too little work to pay for releasing the GIL and waking the workers.
            return run((0, n, outs)).map_err(stack_error);
        }
        let threads = rayon::current_num_threads().max(1);
        let per = n
            .div_ceil(threads * BLOCKS_PER_THREAD)
            .next_multiple_of(LANES);
        // (`max(1)`: with nv = 0 the results are empty, and a chunk size of 0 would panic.)
        let mut chunks = outs.map(|o| o.chunks_mut((per * size).max(1)));
        let blocks: Vec<(usize, usize, [&mut [f64]; P])> = (0..n.div_ceil(per))
            .map(|b| {
                let rows = std::array::from_fn(|p| chunks[p].next().unwrap_or_default());
                (b * per, ((b + 1) * per).min(n), rows)
            })
            .collect();
        py.detach(|| blocks.into_par_iter().try_for_each(run))
            .map_err(stack_error)
    })
}
