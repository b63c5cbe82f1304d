//! trip_kinematics' runtime mapping arguments and inverse kinematics through an
//! [`ActuatedChain`], answered in actuated coordinates.

use super::{ActuatedChain, Actuation};
use crate::error::KinematicsError;
use crate::ik::{IkSolver, IkStatus, IkTarget};
use std::fmt;
use std::sync::{Arc, PoisonError, RwLock};

/// Parameters of a mapping that can change while the mechanism runs (trip_kinematics'
/// `pass_arg_a_to_v` / `pass_arg_v_to_a`): a measured rod length, a calibration offset, a gear
/// ratio. Clones share the values, so the caller keeps one handle and the [`ArgActuation`]
/// inside an [`ActuatedChain`] reads the same numbers.
#[derive(Clone, Debug, Default)]
pub struct ActuationArgs(Arc<RwLock<Vec<f64>>>);

impl ActuationArgs {
    /// A handle holding `values`.
    #[must_use]
    pub fn new(values: impl Into<Vec<f64>>) -> Self {
        Self(Arc::new(RwLock::new(values.into())))
    }

    /// Replaces the values. The chain's joints follow at the next
    /// [`ActuatedChain::set_actuated_state`] (see [`ActuatedChain::remap`]).
    pub fn set(&self, values: &[f64]) {
        let mut v = self.0.write().unwrap_or_else(PoisonError::into_inner);
        v.clear();
        v.extend_from_slice(values);
    }

    /// A copy of the current values.
    #[must_use]
    pub fn get(&self) -> Vec<f64> {
        self.0
            .read()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }

    fn with<R>(&self, f: impl FnOnce(&[f64]) -> R) -> R {
        f(&self.0.read().unwrap_or_else(PoisonError::into_inner))
    }
}

/// An [`Actuation`] of two closures that also receive the current [`ActuationArgs`]:
/// `to_virtual(args, actuated, out)` and `to_actuated(args, virtual_q, out)`.
///
/// # Examples
/// ```
/// use kinetree_kinematics::{ActuatedChain, ActuationArgs, ActuationGroup, ArgActuation, Chain,
///                           GroupSpec};
/// use kinetree_kinematics::model::samples;
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let arm = samples::planar_2r(0.3, 0.2);
/// let joint = arm.joint(arm.moving_joints().next().unwrap()).name.clone();
/// // A belt whose reduction ratio is set at run time.
/// let ratio = ActuationArgs::new([2.0]);
/// let belt = ArgActuation::new(
///     ratio.clone(),
///     |r: &[f64], motor: &[f64], q: &mut Vec<f64>| q.push(motor[0] / r[0]),
///     |r: &[f64], q: &[f64], motor: &mut Vec<f64>| motor.push(q[0] * r[0]),
/// );
/// let group = ActuationGroup::new(&arm, GroupSpec::new("belt", ["motor"], [joint.as_str()], [0.0]), belt)?;
/// let mut robot = ActuatedChain::new(Chain::new(arm), vec![group])?;
/// robot.set_actuated("motor", 1.0)?;
/// assert_eq!(robot.chain().q()[0], 0.5);
/// ratio.set(&[4.0]);
/// robot.remap()?; // the joints follow the new ratio, the motor stays
/// assert_eq!(robot.chain().q()[0], 0.25);
/// # Ok(())
/// # }
/// ```
pub struct ArgActuation<F, G> {
    args: ActuationArgs,
    to_virtual: F,
    to_actuated: G,
}

impl<F, G> ArgActuation<F, G>
where
    F: Fn(&[f64], &[f64], &mut Vec<f64>) + Send + Sync,
    G: Fn(&[f64], &[f64], &mut Vec<f64>) + Send + Sync,
{
    /// Pairs the two closures with the argument handle they read.
    pub fn new(args: ActuationArgs, to_virtual: F, to_actuated: G) -> Self {
        Self {
            args,
            to_virtual,
            to_actuated,
        }
    }
}

impl<F, G> Actuation for ArgActuation<F, G>
where
    F: Fn(&[f64], &[f64], &mut Vec<f64>) + Send + Sync,
    G: Fn(&[f64], &[f64], &mut Vec<f64>) + Send + Sync,
{
    fn to_virtual(&self, actuated: &[f64], virtual_q: &mut Vec<f64>) {
        self.args
            .with(|a| (self.to_virtual)(a, actuated, virtual_q));
    }

    fn to_actuated(&self, virtual_q: &[f64], actuated: &mut Vec<f64>) {
        self.args
            .with(|a| (self.to_actuated)(a, virtual_q, actuated));
    }
}

impl<F, G> fmt::Debug for ArgActuation<F, G> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ArgActuation")
            .field("args", &self.args)
            .finish_non_exhaustive()
    }
}

/// What [`ActuatedChain::solve_ik`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct ActuatedIkReport {
    /// The solver's status on the joint-space problem.
    pub status: IkStatus,
    /// The actuated state that places the frame (in the order of
    /// [`ActuatedChain::actuator_names`]); the chain is left there.
    pub actuated: Vec<f64>,
    /// Position error (m) of the frame at `actuated`, after the mappings (larger than the
    /// solver's when a group cannot reach the joint values the solver chose).
    pub position_error: f64,
    /// Orientation error (rad) of the frame at `actuated`, against the target pose's rotation
    /// (meaningful when the target constrains the orientation).
    pub orientation_error: f64,
}

impl ActuatedChain {
    /// Runs every group's actuated → virtual mapping again at the current actuated state (after
    /// [`ActuationArgs::set`]), moving the joints; the actuated state is unchanged.
    ///
    /// # Errors
    /// A failing mapping, as in [`ActuatedChain::set_actuated_state`]; nothing changes then.
    pub fn remap(&mut self) -> Result<(), KinematicsError> {
        let state = self.actuated_state().to_vec();
        self.set_actuated_state(&state)
    }

    /// Inverse kinematics in actuated coordinates (as trip_kinematics' solvers work through its
    /// groups): solves for the joint values that place `target.frame` with `solver`, starting at
    /// the chain's configuration, maps them through each group to its actuated coordinates,
    /// moves the chain there and returns the actuated state with the frame's remaining error.
    ///
    /// # Errors
    /// The solver's errors (unknown frame, bad target); a failing mapping. On error the chain
    /// is unchanged.
    pub fn solve_ik(
        &mut self,
        solver: &mut IkSolver,
        target: &IkTarget,
    ) -> Result<ActuatedIkReport, KinematicsError> {
        let model = self.chain().model().clone();
        let mut data = crate::KinematicsData::new(&model);
        let q0 = self.chain().q().to_vec();
        let report = solver.solve(&model, &mut data, target, &q0)?;
        let (status, q) = (report.status, report.q.to_vec());
        let before = self.actuated_state().to_vec();
        let grouped: Vec<String> = self
            .groups()
            .iter()
            .flat_map(|g| g.joints().iter().cloned())
            .collect();
        let mut result = Ok(());
        for j in model.moving_joints() {
            let name = &model.joint(j).name;
            if grouped.contains(name) {
                result = self.set_joint_q(name, &q[model.joint_q_range(j)]);
                if result.is_err() {
                    break;
                }
            }
        }
        if let Err(e) = result {
            self.set_actuated_state(&before)?;
            return Err(e);
        }
        // Joints no group drives are actuated coordinates themselves.
        let mut state = self.actuated_state().to_vec();
        for (k, name) in self.actuator_names().iter().enumerate() {
            if let Some(j) = model.joint_index(name)
                && !grouped.contains(name)
            {
                state[k] = q[model.joint_q_range(j).start];
            }
        }
        self.set_actuated_state(&state)?;
        let pose = *self.data().world_from(target.frame)?;
        let position_error = (pose.translation - target.pose.translation).length();
        let orientation_error = kinetree_model::spatial::rotation::log3(
            &(pose.rotation.transpose() * target.pose.rotation),
        )
        .length();
        Ok(ActuatedIkReport {
            status,
            actuated: state,
            position_error,
            orientation_error,
        })
    }
}
