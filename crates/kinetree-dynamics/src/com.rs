//! Total mass, centre of mass (position, velocity, Jacobian) and centroidal momentum.

use crate::data::DynamicsData;
use crate::error::DynamicsError;
use crate::rnea::check_inputs;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::Force;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::{forward_kinematics, forward_kinematics_with_velocity};

/// The mass (kg) of every moving body: the links welded to the world (the root link and its
/// fixed attachments, for a fixed root) are left out, as Pinocchio's `computeTotalMass` does.
/// [`Model::total_mass`] counts every link.
#[must_use]
#[doc(alias = "compute_total_mass")]
#[doc(alias = "total_mass")]
pub fn moving_mass(model: &Model) -> f64 {
    model.bodies().iter().skip(1).map(|b| b.inertia.mass).sum()
}

/// Fills the subtree masses and mass moments (world frame) from world body placements.
fn subtree_moments(model: &Model, data: &mut DynamicsData) {
    let bodies = model.bodies();
    let placements = data.kinematics.world_from_body();
    for i in 1..bodies.len() {
        let b = &bodies[i];
        data.subtree_mass[i] = b.inertia.mass;
        data.subtree_moment[i] = placements[i].transform_point(b.inertia.com) * b.inertia.mass;
    }
    data.subtree_mass[0] = 0.0;
    data.subtree_moment[0] = DVec3::ZERO;
    for i in (1..bodies.len()).rev() {
        let p = bodies[i].parent;
        data.subtree_mass[p] += data.subtree_mass[i];
        let m = data.subtree_moment[i];
        data.subtree_moment[p] += m;
    }
}

fn com_from_moments(data: &mut DynamicsData) -> Result<DVec3, DynamicsError> {
    let mass = data.subtree_mass[0];
    if mass.is_nan() || mass <= 0.0 {
        return Err(DynamicsError::ZeroMass);
    }
    data.com = data.subtree_moment[0] / mass;
    Ok(data.com)
}

/// The centre of mass of the moving bodies (world frame, m) at configuration `q`; see
/// [`moving_mass`] for which links count.
///
/// Stored in [`DynamicsData::com`]. Runs forward kinematics on [`DynamicsData::kinematics`].
/// Allocates nothing.
///
/// # Errors
/// [`DynamicsError::ZeroMass`] when the moving bodies have no mass;
/// [`DynamicsError::DimensionMismatch`] or [`DynamicsError::NonFinite`] for a bad `q`;
/// [`DynamicsError::DataMismatch`] when `data` belongs to another model.
#[doc(alias = "com")]
#[doc(alias = "compute_com")]
pub fn center_of_mass(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
) -> Result<DVec3, DynamicsError> {
    check_inputs(model, data, q, None, None)?;
    forward_kinematics(model, &mut data.kinematics, q)?;
    subtree_moments(model, data);
    com_from_moments(data)
}

/// The velocity of the centre of mass (world frame, m/s) at configuration `q` and velocity `v`.
///
/// Stored in [`DynamicsData::com_velocity`] (and the position in [`DynamicsData::com`]). Runs
/// forward kinematics with velocities on [`DynamicsData::kinematics`]. Allocates nothing.
///
/// # Errors
/// As [`center_of_mass`], and for a bad `v`.
pub fn center_of_mass_velocity(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
) -> Result<DVec3, DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    forward_kinematics_with_velocity(model, &mut data.kinematics, q, v)?;
    subtree_moments(model, data);
    com_from_moments(data)?;
    let mass = data.subtree_mass[0];
    let bodies = model.bodies();
    let placements = data.kinematics.world_from_body();
    let velocity = data.kinematics.body_velocity();
    let mut momentum = DVec3::ZERO;
    for i in 1..bodies.len() {
        let inertia = &bodies[i].inertia;
        // Velocity of the body's centre of mass, in world axes.
        let vi = &velocity[i];
        let vc = vi.linear + vi.angular.cross(inertia.com);
        momentum += placements[i].rotation * vc * inertia.mass;
    }
    data.com_velocity = momentum / mass;
    Ok(data.com_velocity)
}

/// The Jacobian of the centre of mass (world frame): `nv` columns with `ċ = Σ J[k]·q̇[k]`.
///
/// Stored in [`DynamicsData::com_jacobian`] and returned (and the centre of mass in
/// [`DynamicsData::com`]). Runs forward kinematics on [`DynamicsData::kinematics`]. O(n),
/// allocates nothing.
///
/// # Errors
/// As [`center_of_mass`].
#[doc(alias = "jacobian_center_of_mass")]
#[doc(alias = "com_jacobian")]
pub fn center_of_mass_jacobian<'d>(
    model: &Model,
    data: &'d mut DynamicsData,
    q: &[f64],
) -> Result<&'d [DVec3], DynamicsError> {
    check_inputs(model, data, q, None, None)?;
    forward_kinematics(model, &mut data.kinematics, q)?;
    subtree_moments(model, data);
    com_from_moments(data)?;
    let mass = data.subtree_mass[0];
    let bodies = model.bodies();
    let joint_models = data.kinematics.joint_models();
    let placements = data.kinematics.world_from_body();
    for i in 1..bodies.len() {
        let b = &bodies[i];
        let x = &placements[i];
        let (m, moment) = (data.subtree_mass[i], data.subtree_moment[i]);
        for k in 0..b.nv {
            // Twist of the subtree (at the world origin, world axes) for a unit joint velocity;
            // the subtree's mass moment moves with it.
            let s = x.act_motion(&joint_models[i].subspace_column(k));
            data.com_jacobian[b.idx_v + k] = (s.linear * m + s.angular.cross(moment)) / mass;
        }
    }
    Ok(&data.com_jacobian)
}

/// The centroidal momentum `[m·ċ; L_c]` at configuration `q` and velocity `v`: the linear
/// momentum and the angular momentum about the centre of mass, both in world axes (Pinocchio's
/// `computeCentroidalMomentum`).
///
/// Stored in [`DynamicsData::centroidal_momentum`] (and the centre of mass and its velocity in
/// [`DynamicsData::com`] and [`DynamicsData::com_velocity`]). Runs forward kinematics with
/// velocities on [`DynamicsData::kinematics`]. Allocates nothing.
///
/// # Errors
/// As [`center_of_mass_velocity`].
#[doc(alias = "compute_centroidal_momentum")]
#[doc(alias = "hg")]
pub fn centroidal_momentum(
    model: &Model,
    data: &mut DynamicsData,
    q: &[f64],
    v: &[f64],
) -> Result<Force, DynamicsError> {
    check_inputs(model, data, q, Some(v), None)?;
    forward_kinematics_with_velocity(model, &mut data.kinematics, q, v)?;
    subtree_moments(model, data);
    let com = com_from_moments(data)?;
    let mass = data.subtree_mass[0];
    let bodies = model.bodies();
    let placements = data.kinematics.world_from_body();
    let velocity = data.kinematics.body_velocity();
    // Total momentum about the world origin, world axes.
    let mut h = Force::ZERO;
    for i in 1..bodies.len() {
        let local = bodies[i].inertia.mul_motion(&velocity[i]);
        h += placements[i].act_force(&local);
    }
    data.com_velocity = h.linear / mass;
    data.centroidal_momentum = Force::new(h.linear, h.angular - com.cross(h.linear));
    Ok(data.centroidal_momentum)
}
