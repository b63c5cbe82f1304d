//! Closed-form inverse kinematics and seeding the numeric solver with it.
//!
//! [`PlanarTwoLink`] is the textbook two-link planar arm: both elbow solutions and the
//! reachability test (the annulus `|l1 - l2| ≤ r ≤ l1 + l2`). [`IkSeeder`] is how any analytic
//! (or learned, or cached) solver hands start configurations to [`IkSolver`](super::IkSolver),
//! which then polishes them numerically and falls back to random restarts.

use super::target::IkTarget;
use crate::configuration::wrap_angle;
use crate::error::KinematicsError;
use kinetree_model::Model;
use kinetree_model::spatial::Se3;

/// A source of start configurations for [`IkSolver`](super::IkSolver) (install one with
/// [`IkSolver::set_seeder`](super::IkSolver::set_seeder)).
///
/// The solver asks for seeds `attempt = 0, 1, …` before it tries `q0` and random restarts, and
/// stops asking at the first `false`. Seeds are clamped into the joint limits (and quaternions
/// normalised); a seed with NaN or infinite entries is skipped. Closures
/// `FnMut(&Model, &[IkTarget], usize, &mut [f64]) -> bool` are seeders.
///
/// # Examples
/// ```
/// use kinetree_kinematics::ik::{IkSeeder, IkTarget};
/// use kinetree_kinematics::model::Model;
/// // Offer one hand-picked configuration, then let the solver continue on its own.
/// let mut seeder = |_: &Model, _: &[IkTarget], attempt: usize, q: &mut [f64]| {
///     if attempt > 0 {
///         return false;
///     }
///     q.fill(0.1);
///     true
/// };
/// # let model = kinetree_kinematics::model::samples::planar_2r(1.0, 1.0);
/// # let mut q = [0.0; 2];
/// assert!(seeder.seed(&model, &[], 0, &mut q));
/// ```
pub trait IkSeeder {
    /// Writes start configuration number `attempt` for `targets` into `q` (length `model.nq()`,
    /// pre-filled with the clamped `q0`) and returns `true`, or returns `false` when there are
    /// no more.
    fn seed(&mut self, model: &Model, targets: &[IkTarget], attempt: usize, q: &mut [f64]) -> bool;
}

impl<F> IkSeeder for F
where
    F: FnMut(&Model, &[IkTarget], usize, &mut [f64]) -> bool,
{
    fn seed(&mut self, model: &Model, targets: &[IkTarget], attempt: usize, q: &mut [f64]) -> bool {
        self(model, targets, attempt, q)
    }
}

/// The two-link planar arm: joint 1 at the origin turning about z, joint 2 at distance `l1`
/// along link 1, the tip at distance `l2` along link 2. The tip is at
/// `x = l1·cos q1 + l2·cos(q1 + q2)`, `y = l1·sin q1 + l2·sin(q1 + q2)`
/// (the geometry of [`kinetree_model::samples::planar_2r`]).
///
/// # Examples
/// ```
/// use kinetree_kinematics::ik::PlanarTwoLink;
/// let arm = PlanarTwoLink::new(1.0, 0.8).expect("positive lengths");
/// let s = arm.solve(1.2, 0.5).expect("reachable");
/// for [q1, q2] in [s.elbow_up, s.elbow_down] {
///     let (x, y) = arm.forward(q1, q2);
///     assert!((x - 1.2).abs() < 1e-12 && (y - 0.5).abs() < 1e-12);
/// }
/// assert!(arm.solve(2.0, 0.0).is_none()); // beyond l1 + l2 = 1.8
/// assert!(arm.solve(0.1, 0.0).is_none()); // inside |l1 - l2| = 0.2
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarTwoLink {
    l1: f64,
    l2: f64,
}

/// The two joint-angle pairs `[q1, q2]` (rad, in (-π, π]) that put the tip of a
/// [`PlanarTwoLink`] on a point. They coincide on the boundary of the workspace.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoLinkSolutions {
    /// `q2 = +acos(c2) ∈ [0, π]`: the elbow bends counter-clockwise (the textbook's "elbow up").
    pub elbow_up: [f64; 2],
    /// `q2 = -acos(c2) ∈ [-π, 0]`: the mirror image about the line from the base to the point.
    pub elbow_down: [f64; 2],
}

impl PlanarTwoLink {
    /// An arm with link lengths `l1` and `l2` (m); `None` unless both are finite and positive.
    #[must_use]
    pub fn new(l1: f64, l2: f64) -> Option<Self> {
        (l1.is_finite() && l2.is_finite() && l1 > 0.0 && l2 > 0.0).then_some(Self { l1, l2 })
    }

    /// The link lengths `(l1, l2)`.
    #[must_use]
    pub fn lengths(&self) -> (f64, f64) {
        (self.l1, self.l2)
    }

    /// The inner and outer radii of the reachable annulus, `(|l1 - l2|, l1 + l2)`.
    #[must_use]
    pub fn reach(&self) -> (f64, f64) {
        ((self.l1 - self.l2).abs(), self.l1 + self.l2)
    }

    /// Whether the tip can reach `(x, y)`: its distance from the base lies in [`reach`](Self::reach)
    /// (up to a relative rounding tolerance of 1e-12).
    #[must_use]
    pub fn is_reachable(&self, x: f64, y: f64) -> bool {
        let (inner, outer) = self.reach();
        let r = x.hypot(y);
        let slack = 1e-12 * outer;
        r.is_finite() && r >= inner - slack && r <= outer + slack
    }

    /// The tip position `(x, y)` for joint angles `q1`, `q2`.
    #[must_use]
    pub fn forward(&self, q1: f64, q2: f64) -> (f64, f64) {
        let a = q1 + q2;
        (
            self.l1 * q1.cos() + self.l2 * a.cos(),
            self.l1 * q1.sin() + self.l2 * a.sin(),
        )
    }

    /// Both joint solutions putting the tip on `(x, y)` (law of cosines), or `None` when the point
    /// is unreachable (see [`is_reachable`](Self::is_reachable)) or not finite. At the base itself
    /// (`l1 == l2`, `r = 0`) every `q1` works; `q1 = 0` is returned.
    #[must_use]
    pub fn solve(&self, x: f64, y: f64) -> Option<TwoLinkSolutions> {
        if !self.is_reachable(x, y) {
            return None;
        }
        let (l1, l2) = (self.l1, self.l2);
        let c2 = ((x * x + y * y - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)).clamp(-1.0, 1.0);
        let q2 = c2.acos();
        let one = |q2: f64| {
            let q1 = y.atan2(x) - (l2 * q2.sin()).atan2(l1 + l2 * q2.cos());
            [wrap_angle(q1), wrap_angle(q2)]
        };
        Some(TwoLinkSolutions {
            elbow_up: one(q2),
            elbow_down: one(-q2),
        })
    }

    /// A seeder for a model containing this arm: the first target's position, expressed in the
    /// arm's base frame `world_from_base` (joint 1 on its origin, turning about its z axis, link 1
    /// along its x axis at `q1 = 0`), is solved in closed form and the two elbow solutions are
    /// offered as seeds for the joints named `joint1` and `joint2`.
    ///
    /// # Errors
    /// [`KinematicsError::UnknownJoint`] for an unknown name,
    /// [`KinematicsError::InvalidJointValue`] when a joint does not have exactly one coordinate.
    pub fn seeder(
        self,
        model: &Model,
        joint1: &str,
        joint2: &str,
        world_from_base: Se3,
    ) -> Result<TwoLinkSeeder, KinematicsError> {
        let index = |name: &str| -> Result<usize, KinematicsError> {
            let j = model
                .joint_index(name)
                .ok_or_else(|| KinematicsError::UnknownJoint {
                    name: name.to_string(),
                })?;
            let range = model.joint_q_range(j);
            if range.len() != 1 {
                return Err(KinematicsError::InvalidJointValue {
                    joint: name.to_string(),
                    reason: format!(
                        "the two-link seeder needs a 1-coordinate joint, this one has {}",
                        range.len()
                    ),
                });
            }
            Ok(range.start)
        };
        Ok(TwoLinkSeeder {
            arm: self,
            q_index: [index(joint1)?, index(joint2)?],
            base_from_world: world_from_base.inverse(),
        })
    }
}

/// Seeds [`IkSolver`](super::IkSolver) with both elbow solutions of a [`PlanarTwoLink`] (see
/// [`PlanarTwoLink::seeder`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoLinkSeeder {
    arm: PlanarTwoLink,
    q_index: [usize; 2],
    base_from_world: Se3,
}

impl IkSeeder for TwoLinkSeeder {
    fn seed(&mut self, _: &Model, targets: &[IkTarget], attempt: usize, q: &mut [f64]) -> bool {
        let Some(target) = targets.first() else {
            return false;
        };
        let p = self
            .base_from_world
            .transform_point(target.pose.translation);
        let Some(s) = self.arm.solve(p.x, p.y) else {
            return false;
        };
        let pick = match attempt {
            0 => s.elbow_up,
            1 => s.elbow_down,
            _ => return false,
        };
        let [i1, i2] = self.q_index;
        if i1 >= q.len() || i2 >= q.len() {
            return false;
        }
        q[i1] = pick[0];
        q[i2] = pick[1];
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_elbows_reach_and_mirror() {
        let arm = PlanarTwoLink::new(1.0, 0.8).unwrap();
        for (x, y) in [
            (1.2, 0.5),
            (-0.3, 0.9),
            (0.0, -1.7),
            (0.25, 0.0),
            (1.8, 0.0),
        ] {
            let s = arm.solve(x, y).unwrap();
            for [q1, q2] in [s.elbow_up, s.elbow_down] {
                let (fx, fy) = arm.forward(q1, q2);
                assert!((fx - x).abs() < 1e-9 && (fy - y).abs() < 1e-9, "({x}, {y})");
            }
            assert!(s.elbow_up[1] >= 0.0 && s.elbow_down[1] <= 0.0);
        }
        assert!(arm.solve(0.0, 0.0).is_none());
        assert!(arm.solve(f64::NAN, 0.0).is_none());
        assert!(PlanarTwoLink::new(0.0, 1.0).is_none());
        let (inner, outer) = arm.reach();
        assert!((inner - 0.2).abs() < 1e-15 && (outer - 1.8).abs() < 1e-15);
    }
}
