//! `kinetree` for Python: the extension module `kinetree._kinetree`, built by maturin into the
//! `kinetree` package (see `python/kinetree/__init__.py`, which re-exports it).
//!
//! A map of the crate:
//! - `errors`: the exception classes, one per kinetree error family, and the mapping from
//!   [`kinetree::Error`];
//! - `arrays`: numpy inputs (shape, dtype and finiteness checks) and the batch runner, which
//!   computes stacked states in parallel with the GIL released;
//! - `parts`: calls with several matrices per state (the derivatives), each its own array;
//! - `scratch`: the workspaces calls reuse (pooled per model);
//! - `model`: the `Model` class (loading, sizes, names, limits, configuration-space helpers,
//!   pickling);
//! - `kinematics` and `dynamics`: `Model` methods for poses, Jacobians, velocities and for
//!   RNEA, CRBA, ABA, energies, momentum and simulation;
//! - `ik`, `workspace` and `collision`: `IkSolver`, workspace sampling and the collision
//!   model.
//!
//! No algorithm lives here: every number comes from the `kinetree` facade.
//!
//! # Examples
//! From Python, after `pip install ./crates/kinetree-py`:
//! ```text
//! >>> import kinetree, numpy as np
//! >>> panda = kinetree.Model.from_urdf("tests/data/robots/panda.urdf")
//! >>> panda.link_placements(panda.neutral()).shape
//! (13, 4, 4)
//! ```

mod arrays;
mod collision;
mod dynamics;
mod errors;
mod formats;
mod ik;
mod kinematics;
mod model;
mod parts;
mod scratch;
mod values;
mod workspace;

use pyo3::prelude::*;

/// The extension module `kinetree._kinetree`.
#[pymodule]
fn _kinetree(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<model::PyModel>()?;
    m.add_class::<model::PyJoint>()?;
    ik::register(m)?;
    workspace::register(m)?;
    collision::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
