//! # kinetree-test-support
//!
//! What kinetree's test crates share (a dev-dependency only; never published):
//! - `reference`: the Pinocchio reference files in `tests/data/reference` ([`reference_dir`],
//!   [`robots`]) and their name-keyed states as our vectors ([`q_of`], [`v_of`]);
//! - `alloc`: [`CountingAllocator`], a global allocator that counts the current thread's
//!   allocations and reallocations, and [`allocations_during`], for the tests that prove a hot
//!   path allocates nothing;
//! - `close`: [`assert_close!`] with the reference files' suggested tolerance ([`ABS_TOL`] +
//!   [`REL_TOL`] × |expected|) or a given one, for numbers, slices and 3-vectors.
//!
//! ```
//! use kinetree_test_support::{assert_close, robots};
//! let robots = robots();
//! assert_eq!(robots.len(), 7);
//! let (name, reference, model) = &robots[0];
//! assert_close!(model.nv() as f64, reference["nv"].as_f64().unwrap());
//! assert_close!([1.0, 2.0], vec![1.0, 2.0 + 1e-12]);
//! # let _ = name;
//! ```
//!
//! An allocation test binary installs the allocator once:
//! ```
//! use kinetree_test_support::{CountingAllocator, allocations_during};
//! #[global_allocator]
//! static GLOBAL: CountingAllocator = CountingAllocator;
//! # fn main() {
//! let mut v: Vec<f64> = Vec::with_capacity(4);
//! assert_eq!(allocations_during(|| v.push(1.0)), 0);
//! assert_eq!(allocations_during(|| v.extend([2.0; 10])), 1); // one reallocation
//! # }
//! ```

mod alloc;
mod close;
mod reference;

pub use alloc::{CountingAllocator, allocations_during};
pub use close::{ABS_TOL, Close, REL_TOL, mismatch as close_mismatch};
pub use reference::{data_dir, q_of, reference_dir, robots, v_of, values};
