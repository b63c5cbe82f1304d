//! Configuration spaces: neutral and random configurations, integration and difference on the
//! joints' manifolds, interpolation, normalization, clamping and distance.
//!
//! Per joint kind (see [`kinetree_model::JointKind`] for the q/v layouts):
//! - revolute, prismatic: the real line; `integrate` adds.
//! - continuous: the circle; `difference` is wrapped to (-π, π] so it follows the short way
//!   round, and `integrate(q0, difference(q0, q1))` equals `q1` up to a multiple of 2π.
//! - cylindrical: line × circle (no wrapping of the angle: it may carry limits).
//! - spherical: SO(3), `q ⊕ ω = q · exp(ω)` with ω in the child frame.
//! - planar: SE(2) with the velocity in the child frame, `q ⊕ v = q · exp(v)`.
//! - floating: SE(3) with the twist in the child frame, `q ⊕ v = q · exp6(v)` (Pinocchio's
//!   convention).
//!
//! Random configurations are uniform within finite position limits. Joints without finite limits
//! (or with `lower == upper`, e.g. placeholder URDF limits) sample angles in [-π, π] and
//! translations in [-1, 1] m; rotations of spherical and floating joints are uniform on SO(3).

use crate::error::{KinematicsError, check_q, check_vector};
pub use crate::joint::{difference_joint, integrate_joint, wrap_angle};
use glam::DQuat;
use kinetree_model::{JointKind, Model};
use rand::Rng;
use std::f64::consts::PI;

/// Writes the neutral configuration (zero angles and displacements, identity rotations) into `q`.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] when `q.len() != model.nq()`.
pub fn neutral(model: &Model, q: &mut [f64]) -> Result<(), KinematicsError> {
    check_len("q", q, model.nq())?;
    q.fill(0.0);
    for b in model.bodies() {
        match b.kind {
            JointKind::Spherical => q[b.idx_q + 3] = 1.0,
            JointKind::Floating => q[b.idx_q + 6] = 1.0,
            _ => {}
        }
    }
    Ok(())
}

/// The neutral configuration as a new vector.
#[must_use]
pub fn neutral_configuration(model: &Model) -> Vec<f64> {
    let mut q = vec![0.0; model.nq()];
    // Cannot fail: the length is right by construction.
    let _ = neutral(model, &mut q);
    q
}

fn check_len(what: &'static str, x: &[f64], n: usize) -> Result<(), KinematicsError> {
    if x.len() == n {
        Ok(())
    } else {
        Err(KinematicsError::DimensionMismatch {
            what,
            expected: n,
            actual: x.len(),
        })
    }
}

/// The sampling interval of a 1-DoF coordinate with limits `lower`/`upper` (see the module docs).
#[must_use]
pub fn sampling_range(kind: JointKind, lower: f64, upper: f64) -> (f64, f64) {
    let angular = !matches!(kind, JointKind::Prismatic);
    if kind != JointKind::Continuous && lower.is_finite() && upper.is_finite() && lower < upper {
        (lower, upper)
    } else if angular {
        (-PI, PI)
    } else {
        (-1.0, 1.0)
    }
}

fn random_quat<R: Rng + ?Sized>(rng: &mut R) -> DQuat {
    // Shoemake's uniform sampling of unit quaternions.
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let (t2, t3) = (2.0 * PI * u2, 2.0 * PI * u3);
    DQuat::from_xyzw(a * t2.sin(), a * t2.cos(), b * t3.sin(), b * t3.cos())
}

/// Writes a random configuration into `q`, uniform within the limits (see the module docs).
/// Deterministic for a given generator state. Allocates nothing.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] when `q.len() != model.nq()`.
pub fn random_configuration<R: Rng + ?Sized>(
    model: &Model,
    rng: &mut R,
    q: &mut [f64],
) -> Result<(), KinematicsError> {
    check_len("q", q, model.nq())?;
    // Interpolated as lo·(1 − t) + hi·t, not lo + (hi − lo)·t: the width of limits such as
    // ±1e308 overflows to infinity, while every term here stays within the limits.
    let uniform = |(lo, hi): (f64, f64), rng: &mut R| {
        let t = rng.random::<f64>();
        lo * (1.0 - t) + hi * t
    };
    for b in model.bodies().iter().skip(1).filter(|b| b.mimic.is_none()) {
        let lim = &model.joint(b.joint.unwrap_or(0)).limits;
        let qi = &mut q[b.idx_q..b.idx_q + b.nq];
        match b.kind {
            JointKind::Fixed => {}
            JointKind::Revolute | JointKind::Continuous | JointKind::Prismatic => {
                qi[0] = uniform(sampling_range(b.kind, lim.lower, lim.upper), rng);
            }
            JointKind::Cylindrical => {
                qi[0] = uniform(
                    sampling_range(JointKind::Prismatic, lim.lower, lim.upper),
                    rng,
                );
                qi[1] = uniform(
                    sampling_range(JointKind::Revolute, lim.lower, lim.upper),
                    rng,
                );
            }
            JointKind::Spherical => qi.copy_from_slice(&random_quat(rng).to_array()),
            JointKind::Planar => {
                qi[0] = uniform((-1.0, 1.0), rng);
                qi[1] = uniform((-1.0, 1.0), rng);
                qi[2] = uniform((-PI, PI), rng);
            }
            JointKind::Floating => {
                for x in qi[..3].iter_mut() {
                    *x = uniform((-1.0, 1.0), rng);
                }
                qi[3..].copy_from_slice(&random_quat(rng).to_array());
            }
        }
    }
    Ok(())
}

/// Writes `q ⊕ v` (the configuration reached from `q` after moving with velocity `v` for unit
/// time) into `q_out`. Quaternions in the result are normalized. Allocates nothing.
///
/// # Errors
/// Length or finiteness errors for `q`, `v`, `q_out`; [`KinematicsError::Overflow`] naming the
/// first joint's body whose result is not finite (a velocity too large for `f64`, as `1e154` on
/// a free joint).
pub fn integrate(
    model: &Model,
    q: &[f64],
    v: &[f64],
    q_out: &mut [f64],
) -> Result<(), KinematicsError> {
    check_q(model, "q", q)?;
    check_vector("v", v, model.nv())?;
    check_len("q_out", q_out, model.nq())?;
    for b in model.bodies().iter().skip(1).filter(|b| b.mimic.is_none()) {
        integrate_joint(
            b.kind,
            &q[b.idx_q..b.idx_q + b.nq],
            &v[b.idx_v..b.idx_v + b.nv],
            &mut q_out[b.idx_q..b.idx_q + b.nq],
        );
    }
    check_result(model, q_out)
}

/// [`KinematicsError::Overflow`] of the `"configuration"` naming the first body whose
/// coordinates in `q` (a result of [`integrate`] or [`interpolate`]) are not finite.
fn check_result(model: &Model, q: &[f64]) -> Result<(), KinematicsError> {
    match model
        .bodies()
        .iter()
        .position(|b| q[b.idx_q..b.idx_q + b.nq].iter().any(|x| !x.is_finite()))
    {
        None => Ok(()),
        Some(i) => Err(crate::forward::overflow(model, "configuration", i)),
    }
}

/// Writes the velocity `v` with `q0 ⊕ v = q1` into `v_out` (continuous joints take the short way
/// round). Allocates nothing.
///
/// # Errors
/// Length or finiteness errors for `q0`, `q1`, `v_out`.
pub fn difference(
    model: &Model,
    q0: &[f64],
    q1: &[f64],
    v_out: &mut [f64],
) -> Result<(), KinematicsError> {
    check_q(model, "q0", q0)?;
    check_q(model, "q1", q1)?;
    check_len("v_out", v_out, model.nv())?;
    for b in model.bodies().iter().skip(1).filter(|b| b.mimic.is_none()) {
        difference_joint(
            b.kind,
            &q0[b.idx_q..b.idx_q + b.nq],
            &q1[b.idx_q..b.idx_q + b.nq],
            &mut v_out[b.idx_v..b.idx_v + b.nv],
        );
    }
    Ok(())
}

/// Writes the configuration a fraction `t` of the way from `q0` to `q1` (geodesic on each joint's
/// manifold) into `q_out`. Allocates nothing.
///
/// # Errors
/// Length or finiteness errors (of `q0`, `q1`, `t`); [`KinematicsError::Overflow`] when the
/// result is not finite (a `t` too large for `f64`).
pub fn interpolate(
    model: &Model,
    q0: &[f64],
    q1: &[f64],
    t: f64,
    q_out: &mut [f64],
) -> Result<(), KinematicsError> {
    check_q(model, "q0", q0)?;
    check_q(model, "q1", q1)?;
    check_vector("t", &[t], 1)?;
    check_len("q_out", q_out, model.nq())?;
    // Per joint, without a scratch buffer: integrate(q0, t · difference(q0, q1)).
    let mut v = [0.0f64; 6];
    for b in model.bodies().iter().skip(1).filter(|b| b.mimic.is_none()) {
        let (a, c) = (&q0[b.idx_q..b.idx_q + b.nq], &q1[b.idx_q..b.idx_q + b.nq]);
        let v = &mut v[..b.nv];
        difference_joint(b.kind, a, c, v);
        for x in v.iter_mut() {
            *x *= t;
        }
        integrate_joint(b.kind, a, v, &mut q_out[b.idx_q..b.idx_q + b.nq]);
    }
    check_result(model, q_out)
}

/// Checks that `q` is a configuration of `model`: length `nq`, finite, and every quaternion
/// (spherical and floating joints) of norm within
/// [`QUATERNION_NORM_TOLERANCE`](crate::QUATERNION_NORM_TOLERANCE) of 1. Every algorithm taking
/// a configuration runs this check; a quaternion within the tolerance is normalized where it is
/// used. Allocates nothing unless it fails.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`], [`KinematicsError::NonFinite`],
/// [`KinematicsError::NonUnitQuaternion`] (naming the joint and the norm).
pub fn check_configuration(model: &Model, q: &[f64]) -> Result<(), KinematicsError> {
    check_q(model, "q", q)
}

/// Normalizes the quaternions of spherical and floating joints in place.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] for a wrong length; [`KinematicsError::NonFinite`] when a
/// quaternion is zero or not finite.
pub fn normalize(model: &Model, q: &mut [f64]) -> Result<(), KinematicsError> {
    check_vector("q", q, model.nq())?;
    for b in model.bodies().iter().skip(1) {
        let start = match b.kind {
            JointKind::Spherical => b.idx_q,
            JointKind::Floating => b.idx_q + 3,
            _ => continue,
        };
        let n = crate::error::quaternion_norm(&q[start..start + 4]);
        if !(n.is_finite() && n > 0.0) {
            return Err(KinematicsError::NonFinite {
                what: "q (quaternion)",
                index: start,
            });
        }
        for x in q[start..start + 4].iter_mut() {
            *x /= n;
        }
    }
    Ok(())
}

/// Clamps every coordinate that has finite position limits into them, in place.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] for a wrong length.
pub fn clamp(model: &Model, q: &mut [f64]) -> Result<(), KinematicsError> {
    check_len("q", q, model.nq())?;
    for b in model.bodies().iter().skip(1) {
        if !b.kind.has_position_limits() {
            continue;
        }
        let lim = &model.joint(b.joint.unwrap_or(0)).limits;
        for x in q[b.idx_q..b.idx_q + b.nq].iter_mut() {
            *x = x.clamp(lim.lower.min(lim.upper), lim.upper.max(lim.lower));
        }
    }
    Ok(())
}

/// Whether every coordinate with position limits is within them (by at most `tolerance` outside).
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] for a wrong length.
pub fn is_within_limits(model: &Model, q: &[f64], tolerance: f64) -> Result<bool, KinematicsError> {
    check_len("q", q, model.nq())?;
    Ok(model.bodies().iter().skip(1).all(|b| {
        let lim = &model.joint(b.joint.unwrap_or(0)).limits;
        !b.kind.has_position_limits()
            || q[b.idx_q..b.idx_q + b.nq]
                .iter()
                .all(|x| *x >= lim.lower - tolerance && *x <= lim.upper + tolerance)
    }))
}

/// The length of `difference(q0, q1)`: a distance on the configuration manifold. Allocates
/// nothing.
///
/// # Errors
/// Length or finiteness errors for `q0`, `q1`.
pub fn distance(model: &Model, q0: &[f64], q1: &[f64]) -> Result<f64, KinematicsError> {
    check_q(model, "q0", q0)?;
    check_q(model, "q1", q1)?;
    let mut v = [0.0f64; 6];
    let mut sum = 0.0;
    for b in model.bodies().iter().skip(1).filter(|b| b.mimic.is_none()) {
        let v = &mut v[..b.nv];
        difference_joint(
            b.kind,
            &q0[b.idx_q..b.idx_q + b.nq],
            &q1[b.idx_q..b.idx_q + b.nq],
            v,
        );
        sum += v.iter().map(|x| x * x).sum::<f64>();
    }
    Ok(sum.sqrt())
}

/// The elementary joints a name stands for: a user joint (a composite joint's pieces together),
/// or else one elementary joint (a composite's piece `hip.ry` alone).
fn named_joints(model: &Model, name: &str) -> Option<core::ops::Range<usize>> {
    match model.user_joint_index(name) {
        Some(u) => Some(model.user_joints()[u].joints.clone()),
        None => model.joint_index(name).map(|j| j..j + 1),
    }
}

fn joint_block(
    model: &Model,
    name: &str,
    values: &[f64],
    velocity: bool,
) -> Result<core::ops::Range<usize>, KinematicsError> {
    let (j, range, kind) = match model.user_joint_index(name) {
        Some(u) => {
            let range = if velocity {
                model.user_joint_v_range(u)
            } else {
                model.user_joint_q_range(u)
            };
            let j = model.user_joints()[u].joints.start;
            (j, range, model.user_joint_type(u))
        }
        None => {
            let j = model
                .joint_index(name)
                .ok_or_else(|| KinematicsError::UnknownJoint {
                    name: name.to_string(),
                })?;
            let range = if velocity {
                model.joint_v_range(j)
            } else {
                model.joint_q_range(j)
            };
            (j, range, model.joint(j).kind.as_str())
        }
    };
    if range.is_empty() {
        let reason = match model.joint_body(j).and_then(|b| model.bodies()[b].mimic) {
            Some(m) => format!(
                "it follows '{}' (coupled mimic) and has no coordinate of its own",
                model.joint(m.leader).name
            ),
            None => "a fixed joint has no coordinates".into(),
        };
        return Err(KinematicsError::InvalidJointValue {
            joint: name.to_string(),
            reason,
        });
    }
    if values.len() != range.len() {
        return Err(KinematicsError::InvalidJointValue {
            joint: name.to_string(),
            reason: format!(
                "{} joint takes {} {} value(s), got {}",
                kind,
                range.len(),
                if velocity { "velocity" } else { "position" },
                values.len()
            ),
        });
    }
    if let Some(i) = values.iter().position(|x| !x.is_finite()) {
        // Name the value itself (NaN, inf, -inf); the position only matters for a joint that
        // takes several values, and is then said as an ordinal, not as a bare index.
        let which = if values.len() == 1 {
            String::new()
        } else {
            format!(" (value {} of {})", i + 1, values.len())
        };
        return Err(KinematicsError::InvalidJointValue {
            joint: name.to_string(),
            reason: format!(
                "{} {} is not a finite number{which}",
                if velocity { "velocity" } else { "position" },
                values[i]
            ),
        });
    }
    Ok(range)
}

/// Writes the configuration block of the joint named `name` into `q` (continuous joints by angle,
/// spherical joints as quaternion x, y, z, w, floating joints as [x, y, z, qx, qy, qz, qw], a
/// composite joint's state variables in its factors' order; a composite's piece `NAME.rz` alone
/// is addressed by its own name).
///
/// # Errors
/// [`KinematicsError::UnknownJoint`]; [`KinematicsError::InvalidJointValue`] for a fixed joint, a
/// wrong number of values or a non-finite value; [`KinematicsError::DimensionMismatch`] for `q`.
pub fn set_joint_q(
    model: &Model,
    q: &mut [f64],
    name: &str,
    values: &[f64],
) -> Result<(), KinematicsError> {
    check_len("q", q, model.nq())?;
    let r = joint_block(model, name, values, false)?;
    q[r].copy_from_slice(values);
    Ok(())
}

/// Writes the velocity-space block (velocity, acceleration or effort) of the joint named `name`
/// into `v` (floating joints: [linear; angular] in the child frame).
///
/// # Errors
/// As [`set_joint_q`].
pub fn set_joint_v(
    model: &Model,
    v: &mut [f64],
    name: &str,
    values: &[f64],
) -> Result<(), KinematicsError> {
    check_len("v", v, model.nv())?;
    let r = joint_block(model, name, values, true)?;
    v[r].copy_from_slice(values);
    Ok(())
}

/// Which vector named joint values ([`set_named`], [`from_named`]) go into.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Space {
    /// A configuration `q` (`nq` entries, per-joint blocks as [`set_joint_q`]).
    Configuration,
    /// A velocity-space vector (`nv` entries: velocity, acceleration or effort, per-joint blocks
    /// as [`set_joint_v`]).
    Velocity,
}

impl Space {
    /// `"q"` or `"v"`, as in error messages.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Configuration => "q",
            Self::Velocity => "v",
        }
    }
}

/// Writes joint values keyed by joint name into `out` (a configuration or a velocity-space
/// vector, per `space`); joints not named keep their value. Each value is the joint's whole block
/// (one number for 1-DoF joints).
///
/// # Errors
/// As [`set_joint_q`] / [`set_joint_v`] for the first name or value that is wrong.
///
/// # Examples
/// ```
/// use kinetree_kinematics::configuration::{Space, neutral_configuration, set_named};
/// use kinetree_kinematics::model::samples;
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let model = samples::planar_2r(0.3, 0.2);
/// let mut q = neutral_configuration(&model);
/// let first = model.joint(model.moving_joints().next().unwrap_or(0)).name.clone();
/// set_named(&model, Space::Configuration, &mut q, [(first.as_str(), [0.5])])?;
/// assert_eq!(q, [0.5, 0.0]);
/// # Ok(())
/// # }
/// ```
pub fn set_named<N: AsRef<str>, V: AsRef<[f64]>>(
    model: &Model,
    space: Space,
    out: &mut [f64],
    values: impl IntoIterator<Item = (N, V)>,
) -> Result<(), KinematicsError> {
    for (name, value) in values {
        match space {
            Space::Configuration => set_joint_q(model, out, name.as_ref(), value.as_ref())?,
            Space::Velocity => set_joint_v(model, out, name.as_ref(), value.as_ref())?,
        }
    }
    Ok(())
}

/// A vector from joint values keyed by joint name: the neutral configuration (for
/// [`Space::Configuration`]) or zero (for [`Space::Velocity`]) with the named blocks written as
/// [`set_named`] does. With `every_joint`, each moving joint must be named.
///
/// # Errors
/// As [`set_named`]; [`KinematicsError::MissingJointValue`] naming the first moving joint left
/// out when `every_joint` is set.
pub fn from_named<N: AsRef<str>, V: AsRef<[f64]>>(
    model: &Model,
    space: Space,
    values: impl IntoIterator<Item = (N, V)>,
    every_joint: bool,
) -> Result<Vec<f64>, KinematicsError> {
    let mut out = match space {
        Space::Configuration => neutral_configuration(model),
        Space::Velocity => vec![0.0; model.nv()],
    };
    let mut named = vec![false; model.joints().len()];
    for (name, value) in values {
        let name = name.as_ref();
        set_named(model, space, &mut out, [(name, value)])?;
        for j in named_joints(model, name).into_iter().flatten() {
            named[j] = true;
        }
    }
    let missing = model.moving_joints().find(|&j| !named[j]);
    match missing {
        Some(j) if every_joint => Err(KinematicsError::MissingJointValue {
            joint: model.user_joints()[model.user_joint_of(j)].name.clone(),
            space: space.as_str(),
        }),
        _ => Ok(out),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use kinetree_model::spatial::Se3;
    use kinetree_model::{JointSpec, Link, ModelBuilder};
    use rand::SeedableRng;

    /// One joint of every kind in a chain.
    pub(crate) fn every_kind() -> Model {
        let mut b = ModelBuilder::new("kinds");
        b.add_link(Link::new("l0"));
        let kinds = [
            JointKind::Revolute,
            JointKind::Continuous,
            JointKind::Prismatic,
            JointKind::Cylindrical,
            JointKind::Spherical,
            JointKind::Planar,
            JointKind::Floating,
        ];
        for (i, k) in kinds.iter().enumerate() {
            b.add_link(Link::new(format!("l{}", i + 1)));
            b.add_joint(
                JointSpec::new(
                    format!("j{}", i + 1),
                    *k,
                    format!("l{i}"),
                    format!("l{}", i + 1),
                )
                .with_axis(DVec3::new(0.3, -0.5, 0.8))
                .with_limits(kinetree_model::JointLimits::position(-2.0, 2.5))
                .with_placement(Se3::from_xyz_rpy([0.1, 0.2, 0.3], [0.3, 0.2, 0.1])),
            );
        }
        b.build().unwrap()
    }

    #[test]
    fn integrate_difference_round_trip_on_every_kind() {
        let model = every_kind();
        let mut rng = rand::rngs::SmallRng::seed_from_u64(7);
        let (mut q0, mut q1) = (vec![0.0; model.nq()], vec![0.0; model.nq()]);
        let mut v = vec![0.0; model.nv()];
        let mut back = vec![0.0; model.nq()];
        for _ in 0..50 {
            random_configuration(&model, &mut rng, &mut q0).unwrap();
            random_configuration(&model, &mut rng, &mut q1).unwrap();
            difference(&model, &q0, &q1, &mut v).unwrap();
            integrate(&model, &q0, &v, &mut back).unwrap();
            // Compare through the joint's difference: zero means the same point on the manifold.
            let mut residual = vec![0.0; model.nv()];
            difference(&model, &q1, &back, &mut residual).unwrap();
            assert!(residual.iter().all(|r| r.abs() < 1e-10), "{residual:?}");
            assert!(is_within_limits(&model, &q0, 0.0).unwrap());
        }
    }

    #[test]
    fn interpolation_hits_both_ends() {
        let model = every_kind();
        let mut rng = rand::rngs::SmallRng::seed_from_u64(3);
        let (mut q0, mut q1) = (vec![0.0; model.nq()], vec![0.0; model.nq()]);
        random_configuration(&model, &mut rng, &mut q0).unwrap();
        random_configuration(&model, &mut rng, &mut q1).unwrap();
        let mut out = vec![0.0; model.nq()];
        interpolate(&model, &q0, &q1, 0.0, &mut out).unwrap();
        assert!(distance(&model, &out, &q0).unwrap() < 1e-12);
        interpolate(&model, &q0, &q1, 1.0, &mut out).unwrap();
        assert!(distance(&model, &out, &q1).unwrap() < 1e-10);
        // Halfway is equidistant.
        interpolate(&model, &q0, &q1, 0.5, &mut out).unwrap();
        let (d0, d1) = (
            distance(&model, &q0, &out).unwrap(),
            distance(&model, &out, &q1).unwrap(),
        );
        assert!((d0 - d1).abs() < 1e-9, "{d0} vs {d1}");
    }

    #[test]
    fn continuous_difference_takes_the_short_way() {
        assert!((wrap_angle(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-15);
        let mut out = [0.0];
        difference_joint(JointKind::Continuous, &[3.0], &[-3.0], &mut out);
        assert!((out[0] - (2.0 * PI - 6.0)).abs() < 1e-12);
        difference_joint(JointKind::Revolute, &[3.0], &[-3.0], &mut out);
        assert_eq!(out[0], -6.0);
    }

    #[test]
    fn clamp_normalize_and_setters() {
        let model = every_kind();
        let mut q = neutral_configuration(&model);
        set_joint_q(&model, &mut q, "j1", &[5.0]).unwrap();
        clamp(&model, &mut q).unwrap();
        assert_eq!(q[0], 2.5);
        let fq = model.joint_q_range(model.joint_index("j7").unwrap());
        set_joint_q(&model, &mut q, "j7", &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0]).unwrap();
        normalize(&model, &mut q).unwrap();
        assert_eq!(q[fq.end - 1], 1.0);
        assert!(matches!(
            set_joint_q(&model, &mut q, "nope", &[1.0]),
            Err(KinematicsError::UnknownJoint { .. })
        ));
        assert!(matches!(
            set_joint_q(&model, &mut q, "j7", &[1.0]),
            Err(KinematicsError::InvalidJointValue { .. })
        ));
        let mut v = vec![0.0; model.nv()];
        set_joint_v(&model, &mut v, "j4", &[1.0, 2.0]).unwrap();
        assert_eq!(&v[3..5], &[1.0, 2.0]);
    }

    #[test]
    fn named_values_fill_their_blocks() {
        let model = every_kind();
        let names: Vec<String> = model
            .moving_joints()
            .map(|j| model.joint(j).name.clone())
            .collect();
        // Every joint named: each block holds its values, in the model's order.
        let mut q = vec![0.0; model.nq()];
        random_configuration(&model, &mut rand::rngs::SmallRng::seed_from_u64(5), &mut q).unwrap();
        let blocks: Vec<(&str, &[f64])> = model
            .moving_joints()
            .zip(&names)
            .map(|(j, n)| (n.as_str(), &q[model.joint_q_range(j)]))
            .collect();
        assert_eq!(
            from_named(&model, Space::Configuration, blocks.iter().copied(), true).unwrap(),
            q
        );
        // One joint named: the others keep the neutral configuration (or zero velocity).
        let j = model.moving_joints().nth(2).unwrap();
        let partial = [(names[2].as_str(), [0.25])];
        let mut expected = neutral_configuration(&model);
        expected[model.joint_q_range(j)].copy_from_slice(&[0.25]);
        assert_eq!(
            from_named(&model, Space::Configuration, partial, false).unwrap(),
            expected
        );
        let mut v = vec![1.0; model.nv()];
        set_named(&model, Space::Velocity, &mut v, partial).unwrap();
        assert_eq!(v[model.joint_v_range(j)], [0.25]);
        assert_eq!(v.iter().filter(|&&x| x == 1.0).count(), model.nv() - 1);
        // Leaving a joint out when every joint is required names the first one left out.
        assert!(matches!(
            from_named(&model, Space::Velocity, partial, true),
            Err(KinematicsError::MissingJointValue { ref joint, space: "v" }) if *joint == names[0]
        ));
        assert!(matches!(
            from_named(&model, Space::Configuration, [("nope", [0.0])], false),
            Err(KinematicsError::UnknownJoint { .. })
        ));
    }
}
