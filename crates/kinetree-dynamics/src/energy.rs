//! Kinetic and potential energy.

use crate::data::DynamicsData;
use crate::error::DynamicsError;
use crate::rnea::check_inputs;
use kinetree_kinematics::forward_kinematics_with_velocity;
use kinetree_kinematics::model::Model;

/// The kinetic energy `½·q̇ᵀ·M(q)·q̇` (J) at configuration `q` and velocity `v`: the sum over
/// bodies of `½·vᵢᵀ·Iᵢ·vᵢ`, plus `½·r·q̇²` per degree of freedom for the joints' armature with
/// [`JointTerms::FromModel`](crate::JointTerms::FromModel).
///
/// Runs [`forward_kinematics_with_velocity`] on [`DynamicsData::kinematics`]. Allocates nothing.
///
/// # Errors
/// [`DynamicsError::DimensionMismatch`] or [`DynamicsError::NonFinite`] for a bad `q` or `v`;
/// [`DynamicsError::DataMismatch`] when `data` belongs to another model.
#[doc(alias = "compute_kinetic_energy")]
pub fn kinetic_energy(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
) -> Result<f64, DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    forward_kinematics_with_velocity(model, &mut data.kinematics, q, v)?;
    let velocity = data.kinematics.body_velocity();
    let mut e = 0.0;
    for (b, vi) in model.bodies().iter().zip(velocity).skip(1) {
        e += b.inertia.kinetic_energy(vi);
    }
    if data.has_joint_terms {
        for (r, vk) in data.armature.iter().zip(v) {
            e += 0.5 * r * vk * vk;
        }
    }
    if !e.is_finite() {
        return Err(crate::error::overflow(
            model,
            data,
            "kinetic energy",
            usize::MAX,
            e,
        ));
    }
    Ok(e)
}

/// The gravitational potential energy `-Σ mᵢ·g·cᵢ` (J) at configuration `q`, with `cᵢ` the
/// world position of each moving body's centre of mass and `g` = [`Model::gravity`]; zero at the
/// world origin. The links welded to the world are left out (they never move).
///
/// Runs [`forward_kinematics`](kinetree_kinematics::forward_kinematics) on
/// [`DynamicsData::kinematics`]. Allocates nothing.
///
/// # Errors
/// As [`kinetic_energy`], for `q`.
#[doc(alias = "compute_potential_energy")]
pub fn potential_energy(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
) -> Result<f64, DynamicsError> {
    check_inputs(model, data, q, None, None)?;
    kinetree_kinematics::forward_kinematics(model, &mut data.kinematics, q)?;
    let g = model.gravity();
    let placements = data.kinematics.world_from_body();
    let mut e = 0.0;
    for (b, x) in model.bodies().iter().zip(placements).skip(1) {
        e -= b.inertia.mass * g.dot(x.transform_point(b.inertia.com));
    }
    if !e.is_finite() {
        return Err(crate::error::overflow(
            model,
            data,
            "potential energy",
            usize::MAX,
            e,
        ));
    }
    Ok(e)
}

/// The mechanical energy: [`kinetic_energy`] + [`potential_energy`] (J).
///
/// # Errors
/// As [`kinetic_energy`].
#[doc(alias = "total_energy")]
pub fn mechanical_energy(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
) -> Result<f64, DynamicsError> {
    let t = kinetic_energy(model, data, q, v)?;
    // The placements are already there: sum the potential without a second sweep.
    let g = model.gravity();
    let placements = data.kinematics.world_from_body();
    let mut u = 0.0;
    for (b, x) in model.bodies().iter().zip(placements).skip(1) {
        u -= b.inertia.mass * g.dot(x.transform_point(b.inertia.com));
    }
    Ok(t + u)
}
