//! numpy in and out: checked inputs ([`States`]) and the batch runner ([`run`]).
//!
//! Every per-state call takes one state (`q` of shape `(nq,)`) or a stack (`(N, nq)`); [`run`]
//! evaluates the stack in parallel (rayon) with the GIL released, one `DynamicsData` per worker
//! thread, so each state gets exactly the arithmetic of a one-state call.

use crate::errors::{Family, family_of, to_py};
use crate::model::PyModel;
use kinetree::dynamics::{DerivativesData, DynamicsData, JointTerms};
use kinetree::model::Model;
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{AllowTypeChange, IntoPyArray, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyFloat;
use rayon::prelude::*;

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
pub(crate) fn states(
    obj: &Bound<'_, PyAny>,
    name: &'static str,
    width: usize,
    family: Family,
) -> PyResult<States> {
    let expected = format!("({width},) or (N, {width})");
    // numpy would drop the imaginary part of complex numbers (and read text or objects): only
    // real numbers convert.
    if let Ok(kind) = obj
        .getattr(pyo3::intern!(obj.py(), "dtype"))
        .and_then(|d| d.getattr(pyo3::intern!(obj.py(), "kind")))
        .and_then(|k| k.extract::<String>())
        && !matches!(kind.as_str(), "f" | "i" | "u")
    {
        return Err(family.err(format!(
            "{name} must be a float64 array of shape {expected}; got dtype kind {kind:?}"
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
                "{name} must be a float64 array of shape {expected}; got a {kind} that does not convert ({e})"
            ))
        })?;
    let shape = array.shape().to_vec();
    let count = match shape.as_slice() {
        [n] if *n == width => None,
        [n, w] if *w == width => Some(*n),
        _ => {
            return Err(family.err(format!(
                "{name} must have shape {expected}, got {}",
                shape_text(&shape)
            )));
        }
    };
    let values: Vec<f64> = array.as_array().iter().copied().collect();
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

/// As [`run`] for the analytic derivatives: `f(data, states, out)` fills `parts` matrices of
/// `nv x nv` one after the other in `out`; returns them as `parts` arrays of shape `(nv, nv)`,
/// or `(N, nv, nv)` for a stack (computed in parallel with the GIL released).
pub(crate) fn run_derivatives<'py, F>(
    py: Python<'py>,
    model: &PyModel,
    inputs: &[&States],
    parts: usize,
    family: Family,
    f: F,
) -> PyResult<Vec<Bound<'py, numpy::PyArrayDyn<f64>>>>
where
    F: Fn(&mut DerivativesData, &[&[f64]], &mut [f64]) -> Result<(), kinetree::Error> + Sync,
{
    let nv = model.model.nv();
    let size = nv * nv;
    let slices = |i: usize| -> [&[f64]; 4] {
        let mut s: [&[f64]; 4] = [&[]; 4];
        for (k, input) in inputs.iter().enumerate().take(4) {
            s[k] = input.state(i);
        }
        s
    };
    let n_in = inputs.len();
    let count = batch_count(inputs, family)?;
    let n = count.unwrap_or(1);
    let mut out = vec![0.0; n * parts * size];
    match count {
        None => model
            .with_derivatives_scratch(|data| f(data, &slices(0)[..n_in], &mut out))
            .map_err(|e| to_py(&e, false))?,
        Some(_) => {
            let m: &Model = &model.model;
            let result = py.detach(|| {
                out.par_chunks_mut((parts * size).max(1))
                    .enumerate()
                    .try_for_each_init(
                        || new_derivatives_data(m),
                        |data, (i, chunk)| {
                            f(data, &slices(i)[..n_in], chunk).map_err(|e| Box::new((i, e)))
                        },
                    )
            });
            if let Err(failed) = result {
                let (i, e) = *failed;
                return Err(family_of(&e).err(format!("state {i}: {e}")));
            }
        }
    }
    let mut shape = count.map_or_else(Vec::new, |n| vec![n]);
    shape.extend([nv, nv]);
    (0..parts)
        .map(|p| {
            let mut values = Vec::with_capacity(n * size);
            for i in 0..n {
                let start = (i * parts + p) * size;
                values.extend_from_slice(&out[start..start + size]);
            }
            to_numpy(py, &shape, values)
        })
        .collect()
}

/// Runs `f(data, states, out)` on one state or on every state of a stack.
///
/// `out_shape` is the shape of one result; a stack of `N` gets `(N, *out_shape)`. One state with
/// an empty `out_shape` returns a Python float. Stacks run in parallel with the GIL released; an
/// error names the state it came from.
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
    let size: usize = out_shape.iter().product();
    let slices = |i: usize| -> [&[f64]; 4] {
        let mut s: [&[f64]; 4] = [&[]; 4];
        for (k, input) in inputs.iter().enumerate().take(4) {
            s[k] = input.state(i);
        }
        s
    };
    let n_in = inputs.len();
    match batch_count(inputs, family)? {
        None => {
            let mut out = vec![0.0; size];
            model
                .with_scratch(|data| f(data, &slices(0)[..n_in], &mut out))
                .map_err(|e| to_py(&e, false))?;
            if out_shape.is_empty() {
                return Ok(PyFloat::new(py, out[0]).into_any());
            }
            Ok(to_numpy(py, out_shape, out)?.into_any())
        }
        Some(n) => {
            let m: &Model = &model.model;
            let mut out = vec![0.0; n * size];
            let result = py.detach(|| {
                if size == 0 {
                    (0..n).into_par_iter().try_for_each_init(
                        || new_data(m),
                        |data, i| {
                            f(data, &slices(i)[..n_in], &mut []).map_err(|e| Box::new((i, e)))
                        },
                    )
                } else {
                    out.par_chunks_mut(size).enumerate().try_for_each_init(
                        || new_data(m),
                        |data, (i, chunk)| {
                            f(data, &slices(i)[..n_in], chunk).map_err(|e| Box::new((i, e)))
                        },
                    )
                }
            });
            if let Err(failed) = result {
                let (i, e) = *failed;
                return Err(family_of(&e).err(format!("state {i}: {e}")));
            }
            let mut shape = vec![n];
            shape.extend_from_slice(out_shape);
            Ok(to_numpy(py, &shape, out)?.into_any())
        }
    }
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
