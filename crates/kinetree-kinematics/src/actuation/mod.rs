//! Actuation groups: actuated coordinates coupled to the joints they drive through a pair of
//! mappings (trip_kinematics' kinematic groups), and a chain driven through them.
//!
//! - this file: the [`Actuation`] mappings trait, [`FnActuation`] and [`ROUND_TRIP_TOLERANCE`];
//! - `group`: [`GroupSpec`] and [`ActuationGroup`] (one group, its mappings checked);
//! - `chain`: [`ActuatedChain`], a [`Chain`](crate::Chain) driven through its groups;
//! - `linear_actuator`: [`LinearActuator`], a linear actuator driving a revolute joint;
//! - `ik`: mappings with runtime arguments ([`ArgActuation`], [`ActuationArgs`]) and inverse
//!   kinematics in actuated coordinates ([`ActuatedChain::solve_ik`]).

mod chain;
mod group;
mod ik;
mod linear_actuator;
#[cfg(test)]
mod tests;

pub use crate::error::MappingDirection;
pub use chain::ActuatedChain;
pub use group::{ActuationGroup, GroupSpec};
pub use ik::{ActuatedIkReport, ActuationArgs, ArgActuation};
pub use linear_actuator::LinearActuator;

use core::fmt;

/// Default tolerance of the round-trip check of a group's mappings (see [`GroupSpec::tolerance`]).
pub const ROUND_TRIP_TOLERANCE: f64 = 1e-9;

/// The two mappings of an [`ActuationGroup`].
///
/// Each appends its result to an empty vector (so a mapping that writes the wrong number of values
/// is caught, and no allocation happens once the vector has grown). Virtual coordinates are the
/// configuration blocks of the group's joints, concatenated in the order the group lists them
/// (SI units; see [`JointKind`](kinetree_model::JointKind) for multi-DoF layouts). A mapping signals an input outside its
/// domain by writing NaN, which the group reports as [`KinematicsError::MappingNonFinite`](crate::KinematicsError::MappingNonFinite).
///
/// Implement it on a type that holds the mechanism's parameters (as [`LinearActuator`] does), or
/// wrap two closures in [`FnActuation`].
pub trait Actuation: Send + Sync {
    /// Appends the virtual joint coordinates produced by the actuated coordinates `actuated`.
    fn to_virtual(&self, actuated: &[f64], virtual_q: &mut Vec<f64>);
    /// Appends the actuated coordinates that produce the virtual joint coordinates `virtual_q`.
    fn to_actuated(&self, virtual_q: &[f64], actuated: &mut Vec<f64>);
}

/// An [`Actuation`] made of two closures.
///
/// # Examples
/// ```
/// use kinetree_kinematics::{Actuation, FnActuation};
/// // A belt with a 3:1 reduction.
/// let belt = FnActuation::new(
///     |motor: &[f64], joint: &mut Vec<f64>| joint.push(motor[0] / 3.0),
///     |joint: &[f64], motor: &mut Vec<f64>| motor.push(joint[0] * 3.0),
/// );
/// let mut joint = Vec::new();
/// belt.to_virtual(&[1.5], &mut joint);
/// assert_eq!(joint, [0.5]);
/// ```
pub struct FnActuation<F, G> {
    to_virtual: F,
    to_actuated: G,
}

impl<F, G> FnActuation<F, G>
where
    F: Fn(&[f64], &mut Vec<f64>) + Send + Sync,
    G: Fn(&[f64], &mut Vec<f64>) + Send + Sync,
{
    /// Pairs `to_virtual` (actuated → virtual) with `to_actuated` (virtual → actuated).
    pub fn new(to_virtual: F, to_actuated: G) -> Self {
        Self {
            to_virtual,
            to_actuated,
        }
    }
}

impl<F, G> Actuation for FnActuation<F, G>
where
    F: Fn(&[f64], &mut Vec<f64>) + Send + Sync,
    G: Fn(&[f64], &mut Vec<f64>) + Send + Sync,
{
    fn to_virtual(&self, actuated: &[f64], virtual_q: &mut Vec<f64>) {
        (self.to_virtual)(actuated, virtual_q);
    }

    fn to_actuated(&self, virtual_q: &[f64], actuated: &mut Vec<f64>) {
        (self.to_actuated)(virtual_q, actuated);
    }
}

impl<F, G> fmt::Debug for FnActuation<F, G> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FnActuation").finish_non_exhaustive()
    }
}
