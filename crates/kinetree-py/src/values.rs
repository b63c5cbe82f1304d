//! The numbers of one input ([`Values`]): a copy, or, for a large stack of states given as a
//! C-contiguous float64 array, the array's own memory read in place.
//!
//! Copying a stack of 10 000 panda states (three inputs of 90 000 numbers) made the batched RNEA
//! spend more time in fresh memory's page faults than in the dynamics: 147 ns per state at
//! N = 10 000 against 86 ns at N = 1 000, where the copies stay small. Read in place, a stack
//! costs no copy at all.

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::ops::{Deref, Range};

/// The numbers of an input, row-major: owned, or shared with the numpy array they came from.
#[derive(Debug)]
pub(crate) enum Values {
    /// A copy (small inputs, converted ones, one state).
    Owned(Vec<f64>),
    /// A C-contiguous float64 array's buffer, read in place.
    Shared(SharedArray),
}

impl Values {
    /// The numbers as an owned vector (a copy when shared).
    pub(crate) fn into_vec(self) -> Vec<f64> {
        match self {
            Self::Owned(v) => v,
            Self::Shared(s) => s.to_vec(),
        }
    }

    /// The addresses of the numbers, when they are an array's memory (to find an `out` that
    /// overlaps them).
    pub(crate) fn shared_range(&self) -> Option<Range<usize>> {
        match self {
            Self::Owned(_) => None,
            Self::Shared(s) => Some(address_range(s)),
        }
    }
}

impl Deref for Values {
    type Target = [f64];

    fn deref(&self) -> &[f64] {
        match self {
            Self::Owned(v) => v,
            Self::Shared(s) => s,
        }
    }
}

/// The buffer of a C-contiguous float64 numpy array, kept alive by a reference to the array.
#[derive(Debug)]
pub(crate) struct SharedArray {
    /// Keeps the array (and so its buffer) alive; its data pointer never moves while referenced
    /// (numpy refuses to resize an array that other references see).
    _array: Py<PyArrayDyn<f64>>,
    ptr: *const f64,
    len: usize,
}

// SAFETY: the buffer is only read, from any thread, for as long as `_array` keeps it alive.
#[allow(unsafe_code, reason = "a numpy buffer read from the worker threads")]
unsafe impl Send for SharedArray {}
// SAFETY: as for `Send`: shared reads of memory that outlives the value.
#[allow(unsafe_code, reason = "a numpy buffer read from the worker threads")]
unsafe impl Sync for SharedArray {}

impl SharedArray {
    /// The buffer of `array`, or `None` when it is not C-contiguous, aligned and readable as a
    /// slice.
    pub(crate) fn new(array: &Bound<'_, PyArrayDyn<f64>>) -> Option<Self> {
        if !array.is_c_contiguous() {
            return None;
        }
        // SAFETY: the slice is used here only for its address and length (`as_slice` checks
        // contiguity and alignment); reads go through `deref` while `_array` keeps it alive.
        #[allow(unsafe_code, reason = "the address of a numpy buffer")]
        let slice = unsafe { array.as_slice() }.ok()?;
        Some(Self {
            _array: array.clone().unbind(),
            ptr: slice.as_ptr(),
            len: slice.len(),
        })
    }
}

impl Deref for SharedArray {
    type Target = [f64];

    fn deref(&self) -> &[f64] {
        // SAFETY: `ptr` and `len` are those of the array's C-contiguous, aligned float64 buffer
        // (checked in `new`), which lives as long as `_array` holds the array. The stacked calls
        // read it with the GIL released, as numpy's own functions do: another Python thread that
        // writes into an input during a call gets unspecified numbers (as with numpy), and the
        // result array never overlaps an input (`map_states` copies an input that `out` shares).
        #[allow(unsafe_code, reason = "a numpy buffer read in place")]
        unsafe {
            std::slice::from_raw_parts(self.ptr, self.len)
        }
    }
}

/// The addresses spanned by `values`.
pub(crate) fn address_range(values: &[f64]) -> Range<usize> {
    let start = values.as_ptr() as usize;
    start..start + std::mem::size_of_val(values)
}
