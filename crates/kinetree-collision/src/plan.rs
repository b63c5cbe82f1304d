//! The candidate pairs grouped by shape kinds for [`compute_distances`](crate::compute_distances):
//! ball–ball, ball–cylinder and cylinder–cylinder pairs run in their own loops over the shapes'
//! world frames, with the radii and half heights at hand, so the common robot models (spheres
//! and cylinders, as panda_collision) skip the per-pair dispatch on shape kinds. Every other pair
//! goes through [`frames::distance`](crate::frames::distance). Each loop does the same arithmetic
//! as the general path, so the results are the same bit for bit.

use crate::cylinders::{Sides, cylinders as solve};
use crate::frames::{Frame, ball_cylinder};
use crate::gjk::signed_distance_mat;
use crate::model::CollisionModel;
use crate::narrow::{Kind, Scratch, Witness};
use glam::DVec3;
use parry3d_f64::shape::Cylinder;

/// Two balls.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BallBall {
    /// Index of the pair in [`CollisionModel::pairs`].
    pub k: usize,
    pub a: usize,
    pub b: usize,
    pub ra: f64,
    pub rb: f64,
}

/// A ball and a cylinder, in either order.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BallCylinder {
    pub k: usize,
    pub ball: usize,
    pub cylinder: usize,
    /// Whether the ball is the pair's first shape.
    pub ball_first: bool,
    pub radius: f64,
    pub shape: Cylinder,
}

/// Two cylinders.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CylinderCylinder {
    pub k: usize,
    pub a: usize,
    pub b: usize,
    pub sa: Cylinder,
    pub sb: Cylinder,
}

/// The candidate pairs of a [`CollisionModel`] by shape kinds.
#[derive(Clone, Debug, Default)]
pub(crate) struct PairPlan {
    pub ball_ball: Vec<BallBall>,
    pub ball_cylinder: Vec<BallCylinder>,
    pub cylinder_cylinder: Vec<CylinderCylinder>,
    /// Every other pair (indices into [`CollisionModel::pairs`]).
    pub general: Vec<usize>,
}

impl PairPlan {
    /// Groups the pairs of `cmodel` (whose `pairs` are already built).
    pub(crate) fn of(cmodel: &CollisionModel) -> PairPlan {
        let mut plan = PairPlan::default();
        for (k, p) in cmodel.pairs.iter().enumerate() {
            let (a, b) = (p.shape_a, p.shape_b);
            match (
                &cmodel.shapes[p.shape_a].kind,
                &cmodel.shapes[p.shape_b].kind,
            ) {
                (Kind::Ball(ba), Kind::Ball(bb)) => plan.ball_ball.push(BallBall {
                    k,
                    a,
                    b,
                    ra: ba.radius,
                    rb: bb.radius,
                }),
                (Kind::Ball(ball), Kind::Cylinder(c)) => plan.ball_cylinder.push(BallCylinder {
                    k,
                    ball: a,
                    cylinder: b,
                    ball_first: true,
                    radius: ball.radius,
                    shape: *c,
                }),
                (Kind::Cylinder(c), Kind::Ball(ball)) => plan.ball_cylinder.push(BallCylinder {
                    k,
                    ball: b,
                    cylinder: a,
                    ball_first: false,
                    radius: ball.radius,
                    shape: *c,
                }),
                (Kind::Cylinder(sa), Kind::Cylinder(sb)) => {
                    plan.cylinder_cylinder.push(CylinderCylinder {
                        k,
                        a,
                        b,
                        sa: *sa,
                        sb: *sb,
                    });
                }
                _ => plan.general.push(k),
            }
        }
        plan
    }
}

/// Two balls, as [`frames::distance`](crate::frames::distance) computes them.
#[inline(always)]
pub(crate) fn ball_ball(fa: &Frame, fb: &Frame, ra: f64, rb: f64) -> Witness {
    let d = fb.origin - fa.origin;
    let len = d.length();
    let normal = if len > 0.0 { d / len } else { DVec3::X };
    Witness {
        distance: len - ra - rb,
        point_a: fa.origin + normal * ra,
        point_b: fb.origin - normal * rb,
        normal,
    }
}

/// A ball and a cylinder in the pair's order, as [`frames::distance`](crate::frames::distance)
/// computes them.
#[inline(always)]
pub(crate) fn ball_and_cylinder(p: &BallCylinder, fball: &Frame, fcyl: &Frame) -> Witness {
    let r = ball_cylinder(fball.origin, p.radius, &p.shape, &fcyl.rot, fcyl.origin);
    if p.ball_first {
        Witness {
            distance: r.distance,
            point_a: r.point_b,
            point_b: r.point_a,
            normal: -r.normal,
        }
    } else {
        r
    }
}

/// Two cylinders, as [`frames::distance`](crate::frames::distance) computes them; `None` when
/// the crate's GJK/EPA does not settle (the caller then takes the general path, which ends in
/// parry's).
#[inline(always)]
pub(crate) fn cylinders(
    p: &CylinderCylinder,
    fa: &Frame,
    fb: &Frame,
    scratch: &mut Scratch,
) -> Option<Witness> {
    let rot_t = fa.rot.transpose();
    let rot12 = rot_t * fb.rot;
    let t12 = rot_t * (fb.origin - fa.origin);
    let local = match solve(rot12.y_axis, t12, &p.sa, &p.sb, scratch.polytope.tol) {
        Sides::Exact(local) => local,
        Sides::Fallback(start) => {
            signed_distance_mat(&rot12, t12, &p.sa, &p.sb, start.dir, &mut scratch.polytope)?
        }
    };
    let (p1, p2, n, distance) = local;
    Some(Witness {
        distance,
        point_a: fa.rot * p1 + fa.origin,
        point_b: fa.rot * p2 + fa.origin,
        normal: fa.rot * n,
    })
}

#[cfg(test)]
mod tests {
    use crate::kinematics::KinematicsData;
    use crate::kinematics::configuration::random_configuration;
    use crate::kinematics::model::{Model, RootJoint};
    use crate::{CollisionData, CollisionError, CollisionModel, CollisionOptions};
    use crate::{compute_distances, query};
    use glam::DVec3;
    use rand::SeedableRng;

    fn panda() -> (Model, CollisionModel) {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/reference/urdf/panda_collision.urdf"
        );
        let model = Model::from_urdf_file(path, RootJoint::Fixed).unwrap();
        let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
        (model, cmodel)
    }

    /// The loops by kind give what the general path gives for each pair, bit for bit, and
    /// cover every pair of panda_collision but none twice.
    #[test]
    fn by_kind_equals_the_general_path() {
        let (model, cmodel) = panda();
        let plan = &cmodel.plan;
        let mut seen = vec![0; cmodel.pairs.len()];
        for k in plan
            .ball_ball
            .iter()
            .map(|p| p.k)
            .chain(plan.ball_cylinder.iter().map(|p| p.k))
        {
            seen[k] += 1;
        }
        for k in plan
            .cylinder_cylinder
            .iter()
            .map(|p| p.k)
            .chain(plan.general.iter().copied())
        {
            seen[k] += 1;
        }
        assert!(seen.iter().all(|&s| s == 1));
        assert_eq!(
            (
                plan.ball_ball.len(),
                plan.ball_cylinder.len(),
                plan.cylinder_cylinder.len()
            ),
            (228, 228, 57)
        );
        let mut kin = KinematicsData::new(&model);
        let mut data = CollisionData::new(&cmodel);
        let mut rng = rand::rngs::SmallRng::seed_from_u64(3);
        let mut q = vec![0.0; model.nq()];
        for _ in 0..100 {
            random_configuration(&model, &mut rng, &mut q).unwrap();
            data.compute_placements(&model, &cmodel, &mut kin, &q)
                .unwrap();
            let ours = compute_distances(&cmodel, &mut data).unwrap().to_vec();
            for (k, p) in ours.iter().enumerate() {
                assert_eq!(
                    *p,
                    query::pair_distance(&cmodel, &mut data, k).unwrap(),
                    "{k}"
                );
            }
        }
    }

    /// A pair whose distance overflows is named, the first such pair in pair order.
    #[test]
    fn overflow_names_the_first_pair() {
        let (model, cmodel) = panda();
        let mut kin = KinematicsData::new(&model);
        let mut data = CollisionData::new(&cmodel);
        let q = vec![0.3; model.nq()];
        for shape in 0..cmodel.shapes.len() {
            data.compute_placements(&model, &cmodel, &mut kin, &q)
                .unwrap();
            data.frames[shape].origin = DVec3::splat(f64::MAX);
            data.world_from_shape[shape].translation = DVec3::splat(f64::MAX);
            let first = cmodel
                .pairs
                .iter()
                .find(|p| p.shape_a == shape || p.shape_b == shape)
                .unwrap();
            match compute_distances(&cmodel, &mut data) {
                Err(CollisionError::Overflow { shape_a, shape_b }) => assert_eq!(
                    (shape_a.as_str(), shape_b.as_str()),
                    (
                        cmodel.shapes[first.shape_a].name(),
                        cmodel.shapes[first.shape_b].name()
                    ),
                    "{shape}"
                ),
                other => panic!("{shape}: {other:?}"),
            }
        }
    }
}
