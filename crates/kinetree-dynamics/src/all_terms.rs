//! Every dynamics quantity of one state at once, for tools (regression suite, CLI).

use crate::data::DynamicsData;
use crate::error::{DynamicsError, check_vector};
use crate::rnea::check_inputs;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::Force;
use kinetree_kinematics::spatial::glam::DVec3;

/// Every dynamics quantity of one state `(q, v, a, tau)`, as owned values (see
/// [`compute_all_terms`]). Vectors use kinetree's `v` order; the mass matrix is row-major.
#[derive(Debug)]
#[non_exhaustive]
pub struct AllTerms {
    /// [`rnea`](crate::rnea)`(q, v, a)`.
    pub rnea: Vec<f64>,
    /// [`nonlinear_effects`](crate::nonlinear_effects)`(q, v)`.
    pub nle: Vec<f64>,
    /// [`generalized_gravity`](crate::generalized_gravity)`(q)`.
    pub gravity_torque: Vec<f64>,
    /// [`crba`](crate::crba)`(q)`: `nv x nv`, row-major.
    pub mass_matrix: Vec<f64>,
    /// [`aba`](crate::aba)`(q, v, tau)`, or why it is undefined (a singular mass matrix).
    pub aba: Result<Vec<f64>, DynamicsError>,
    /// [`moving_mass`](crate::moving_mass) (kg).
    pub moving_mass: f64,
    /// [`center_of_mass`](crate::center_of_mass)`(q)` (world frame), or why it is undefined.
    pub com: Result<DVec3, DynamicsError>,
    /// [`kinetic_energy`](crate::kinetic_energy)`(q, v)` (J).
    pub kinetic_energy: f64,
    /// [`potential_energy`](crate::potential_energy)`(q)` (J).
    pub potential_energy: f64,
    /// [`centroidal_momentum`](crate::centroidal_momentum)`(q, v)`, or why it is undefined.
    pub centroidal_momentum: Result<Force, DynamicsError>,
}

/// Computes every dynamics quantity of the state `(q, v, a, tau)` (Pinocchio's
/// `computeAllTerms` in spirit): the reference data's `rnea`, `nle`, `gravity_torque`,
/// `mass_matrix`, `aba`, `com`, `kinetic_energy` and `centroidal_momentum`, plus the total mass
/// and the potential energy.
///
/// A quantity that is undefined for this state (`aba` with a singular mass matrix, the centre of
/// mass of a massless model) is an `Err` inside [`AllTerms`]; the others are still computed.
/// This is a convenience for tools: it allocates the returned vectors.
///
/// # Errors
/// Only for bad inputs: [`DynamicsError::DimensionMismatch`] or [`DynamicsError::NonFinite`] for
/// `q`, `v`, `a` or `tau`; [`DynamicsError::DataMismatch`] when `data` belongs to another model.
pub fn compute_all_terms(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    tau: &[f64],
) -> Result<AllTerms, DynamicsError> {
    check_inputs(model, data, q, Some(v), Some(a))?;
    check_vector("tau", tau, model.nv())?;
    let rnea = crate::rnea(model, data, q, v, a)?.to_vec();
    let nle = crate::nonlinear_effects(model, data, q, v)?.to_vec();
    let gravity_torque = crate::generalized_gravity(model, data, q)?.to_vec();
    let mass_matrix = crate::crba(model, data, q)?.to_vec();
    let aba = crate::aba(model, data, q, v, tau).map(<[f64]>::to_vec);
    let com = crate::center_of_mass(model, data, q);
    let centroidal_momentum = crate::centroidal_momentum(model, data, q, v);
    let kinetic_energy = crate::kinetic_energy(model, data, q, v)?;
    let potential_energy = crate::potential_energy(model, data, q)?;
    Ok(AllTerms {
        rnea,
        nle,
        gravity_torque,
        mass_matrix,
        aba,
        moving_mass: crate::moving_mass(model),
        com,
        kinetic_energy,
        potential_energy,
        centroidal_momentum,
    })
}
