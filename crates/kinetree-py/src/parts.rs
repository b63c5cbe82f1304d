//! Calls with several `nv x nv` results per state (the analytic derivatives): each result is its
//! own array, made here and written in place, by the workers for a stack.

use crate::arrays::{
    BLOCKS_PER_THREAD, BlockResult, INLINE_STATES, LANES, States, apart, batch_count,
    checked_block, copies_apart, fits, output, par_blocks, shape_text, stack_failure,
};
use crate::errors::{Family, to_py};
use crate::model::PyModel;
use crate::scratch::Scratch;
use kinetree::dynamics::DerivativesData;
use numpy::ndarray::IxDyn;
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};
use std::ops::Range;

/// The `P` result arrays, of shape `(nv, nv)`, or `(N, nv, nv)` for `count = Some(N)`: the
/// caller's `out` (one array for `P = 1`, else a tuple or list of `P` separate arrays, each
/// checked as [`output`] checks one), or new zeroed ones. Runs `fill` with a slice of each to
/// write them through and the inputs to read (an input read in place from memory that an `out`
/// array shares is copied first), and returns the arrays.
fn with_parts<'py, const P: usize>(
    py: Python<'py>,
    nv: usize,
    count: Option<usize>,
    inputs: &[&States],
    out: Option<&Bound<'py, PyAny>>,
    family: Family,
    fill: impl FnOnce([&mut [f64]; P], &[&States]) -> PyResult<()>,
) -> PyResult<[Bound<'py, PyArrayDyn<f64>>; P]> {
    let n = count.unwrap_or(1);
    let mut shape = Vec::with_capacity(3);
    shape.extend(count);
    shape.extend([nv, nv]);
    let Some(out) = out else {
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
        fill(outs, inputs)?;
        return Ok(arrays);
    };
    let arrays = given::<P>(py, out, &shape, family)?;
    let ranges: Vec<Range<usize>> = arrays
        .iter()
        .map(|a| {
            let start = a.data() as usize;
            start..start + a.len() * std::mem::size_of::<f64>()
        })
        .collect();
    for (i, r) in ranges.iter().enumerate() {
        if let Some(j) = ranges[..i]
            .iter()
            .position(|t| r.start < t.end && t.start < r.end)
        {
            return Err(family.err(format!(
                "out[{j}] and out[{i}] share memory: give each result its own array"
            )));
        }
    }
    let mut guards = Vec::with_capacity(P);
    for a in &arrays {
        guards.push(a.try_readwrite().map_err(|e| {
            family.err(format!(
                "out cannot be written ({e}): pass writeable float64 arrays of shape {}",
                shape_text(&shape)
            ))
        })?);
    }
    let mut slices = Vec::with_capacity(P);
    for g in &mut guards {
        slices.push(g.as_slice_mut()?);
    }
    let outs: [&mut [f64]; P] = slices
        .try_into()
        .map_err(|_| pyo3::exceptions::PyRuntimeError::new_err("internal: result count"))?;
    let copies = copies_apart(inputs, &ranges, family)?;
    fill(outs, &apart(inputs, &copies))?;
    drop(guards);
    Ok(arrays)
}

/// The caller's `P` result arrays: `out` itself for `P = 1`, else the items of a tuple or list of
/// `P`, each of `shape` (see [`output`]).
fn given<'py, const P: usize>(
    py: Python<'py>,
    out: &Bound<'py, PyAny>,
    shape: &[usize],
    family: Family,
) -> PyResult<[Bound<'py, PyArrayDyn<f64>>; P]> {
    let items: Vec<Bound<'py, PyAny>> = if P == 1 {
        vec![out.clone()]
    } else if let Ok(t) = out.cast::<PyTuple>() {
        t.iter().collect()
    } else if let Ok(l) = out.cast::<PyList>() {
        l.iter().collect()
    } else {
        Vec::new()
    };
    if items.len() != P {
        return Err(family.err(format!(
            "out must be a tuple of {P} C-contiguous, writeable float64 numpy arrays of shape {}",
            shape_text(shape)
        )));
    }
    let arrays = items
        .iter()
        .map(|item| output(py, Some(item), shape, family))
        .collect::<PyResult<Vec<_>>>()?;
    arrays
        .try_into()
        .map_err(|_| pyo3::exceptions::PyRuntimeError::new_err("internal: result count"))
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
    out: Option<&Bound<'py, PyAny>>,
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
    with_parts(py, nv, count, inputs, out, family, |outs, inputs| {
        // States `first..last` into `outs`, which hold their rows of each result.
        let run = |(first, last, mut outs): (usize, usize, [&mut [f64]; P])| -> BlockResult {
            DerivativesData::with(model, |d| {
                for j in first..last {
                    let parts = f(d, &checked_block(inputs, j, j + 1)?[..k])
                        .map_err(|e| Box::new((j, e)))?;
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
            py.detach(|| par_blocks(blocks, run))
        };
        result.map_err(|failed| stack_failure(inputs, family, failed))
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
    out: Option<&Bound<'py, PyAny>>,
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
        return run_parts(py, model, inputs, out, family, f);
    };
    let nv = model.model.nv();
    let size = nv * nv;
    let k = inputs.len();
    with_parts(py, nv, Some(n), inputs, out, family, |outs, inputs| {
        let run = |(first, last, outs): (usize, usize, [&mut [f64]; P])| -> BlockResult {
            S::with(model, |w| {
                block(w, &checked_block(inputs, first, last)?[..k], outs)
            })
            .map_err(|mut failed| {
                failed.0 += first;
                failed
            })
        };
        if n <= INLINE_STATES {
            // Too little work to pay for releasing the GIL and waking the workers.
            return run((0, n, outs)).map_err(|failed| stack_failure(inputs, family, failed));
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
        py.detach(|| par_blocks(blocks, run))
            .map_err(|failed| stack_failure(inputs, family, failed))
    })
}
