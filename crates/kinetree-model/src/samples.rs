//! Ready-made models for documentation, tests and benchmarks.
//!
//! Every function here builds a known-good model and cannot fail (except where a `# Panics`
//! section says so for non-finite arguments); the values are documented so that tests can compute
//! expected results by hand.
//!
//! ```
//! use kinetree_model::samples;
//! let arm = samples::six_axis();
//! assert_eq!((arm.nq(), arm.nv()), (6, 6));
//! let tree = samples::random_tree(7, 20);
//! assert_eq!(tree.links().len(), 21);
//! ```

use crate::builder::{FrameSpec, JointSpec, ModelBuilder};
use crate::dh::{DhConvention, DhRow, DhTable, dh_model};
use crate::joint::{JointKind, JointLimits};
use crate::link::{Collision, Geometry, Inertial, Link, Visual};
use crate::model::{Model, RootJoint};
use core::f64::consts::{FRAC_PI_2, PI, TAU};
use glam::{DQuat, DVec3};
use kinetree_spatial::{Se3, Symmetric3};

fn limits(lower: f64, upper: f64, velocity: f64, effort: f64) -> JointLimits {
    JointLimits {
        lower,
        upper,
        velocity,
        effort,
    }
}

/// A point mass on a massless rod: mass `m` at `com`, zero rotational inertia.
fn point_mass(m: f64, com: DVec3) -> Inertial {
    Inertial {
        origin: Se3::from_translation(com),
        mass: m,
        inertia: Symmetric3::ZERO,
    }
}

/// A single pendulum: a 1 kg point mass hanging 1 m below a revolute joint about y.
///
/// Links `base` and `bob`; joint `hinge` (revolute, axis y, limits ±π, velocity 10 rad/s, effort
/// 100 N·m) at the origin; the mass is at `(0, 0, -1)` in `bob`'s frame, where frame `tip` also
/// is. At angle `q` the mass is at `(-sin q, 0, -cos q)` and gravity's torque on the joint is
/// `m·g·l·sin q` (g = 9.81). A sphere of radius 0.05 m (visual and collision) marks the mass.
#[must_use]
pub fn pendulum() -> Model {
    let mut b = ModelBuilder::new("pendulum");
    b.add_link(Link::new("base"));
    b.add_part(
        bob("bob"),
        JointSpec::new("hinge", JointKind::Revolute, "base", "bob")
            .with_axis(DVec3::Y)
            .with_limits(limits(-PI, PI, 10.0, 100.0)),
    );
    b.add_frame(FrameSpec::new(
        "tip",
        "bob",
        Se3::from_translation(DVec3::NEG_Z),
    ));
    b.build().expect("the pendulum sample is valid")
}

fn bob(name: &str) -> Link {
    let at = Se3::from_translation(DVec3::NEG_Z);
    let sphere = Geometry::Sphere { radius: 0.05 };
    Link {
        inertial: Some(point_mass(1.0, DVec3::NEG_Z)),
        visuals: vec![Visual {
            name: None,
            origin: at,
            geometry: sphere.clone(),
            material: None,
            color: Some([0.8, 0.2, 0.2, 1.0]),
        }],
        collisions: vec![Collision {
            name: None,
            origin: at,
            geometry: sphere,
        }],
        ..Link::new(name)
    }
}

/// A double pendulum: two 1 m massless rods about y, each ending in a 1 kg point mass.
///
/// Links `base`, `link1`, `link2`; joints `joint1` (at the origin) and `joint2` (at `(0, 0, -1)`
/// in `link1`), both revolute about y with limits ±π, velocity 10 rad/s and effort 100 N·m. Each
/// link's mass is at `(0, 0, -1)` in its frame; frame `tip` is at `(0, 0, -1)` in `link2`.
#[must_use]
pub fn double_pendulum() -> Model {
    let mut b = ModelBuilder::new("double_pendulum");
    b.add_link(Link::new("base"));
    let lim = limits(-PI, PI, 10.0, 100.0);
    b.add_part(
        bob("link1"),
        JointSpec::new("joint1", JointKind::Revolute, "base", "link1")
            .with_axis(DVec3::Y)
            .with_limits(lim),
    );
    b.add_part(
        bob("link2"),
        JointSpec::new("joint2", JointKind::Revolute, "link1", "link2")
            .with_placement(Se3::from_translation(DVec3::NEG_Z))
            .with_axis(DVec3::Y)
            .with_limits(lim),
    );
    b.add_frame(FrameSpec::new(
        "tip",
        "link2",
        Se3::from_translation(DVec3::NEG_Z),
    ));
    b.build().expect("the double pendulum sample is valid")
}

/// A uniform rod of mass `m` and length `l` along x from the origin.
fn rod(m: f64, l: f64) -> Inertial {
    let i = m * l * l / 12.0;
    Inertial {
        origin: Se3::from_translation(DVec3::new(l / 2.0, 0.0, 0.0)),
        mass: m,
        inertia: Symmetric3::from_diagonal(DVec3::new(0.0, i, i)),
    }
}

/// The textbook two-link planar arm, moving in the horizontal xy plane.
///
/// Links `base`, `link1`, `link2`; joints `joint1` (at the origin) and `joint2` (at `(l1, 0, 0)`
/// in `link1`), both revolute about z with limits ±π, velocity 3 rad/s, effort 20 N·m. Each link
/// is a 1 kg uniform rod along its x axis (centre of mass at half length, inertia `m·l²/12`
/// about y and z). Frame `tool` is at `(l2, 0, 0)` in `link2`, so at `q` it is at
/// `x = l1·cos q1 + l2·cos(q1 + q2)`, `y = l1·sin q1 + l2·sin(q1 + q2)`. Gravity (along -z) does
/// no work on this arm.
///
/// # Panics
/// When `l1` or `l2` is not finite.
#[must_use]
pub fn planar_2r(l1: f64, l2: f64) -> Model {
    let mut b = ModelBuilder::new("planar_2r");
    b.add_link(Link::new("base"));
    let lim = limits(-PI, PI, 3.0, 20.0);
    b.add_part(
        Link::new("link1").with_inertial(rod(1.0, l1)),
        JointSpec::new("joint1", JointKind::Revolute, "base", "link1").with_limits(lim),
    );
    b.add_part(
        Link::new("link2").with_inertial(rod(1.0, l2)),
        JointSpec::new("joint2", JointKind::Revolute, "link1", "link2")
            .with_placement(Se3::from_translation(DVec3::new(l1, 0.0, 0.0)))
            .with_limits(lim),
    );
    b.add_frame(FrameSpec::new(
        "tool",
        "link2",
        Se3::from_translation(DVec3::new(l2, 0.0, 0.0)),
    ));
    b.build()
        .expect("planar_2r is valid for finite link lengths")
}

/// A solid cylinder along `axis` (x or z) of mass `m`, radius `r`, length `l`.
fn cylinder_inertia(m: f64, r: f64, l: f64, along_x: bool) -> Symmetric3 {
    let axial = m * r * r / 2.0;
    let transverse = m * (3.0 * r * r + l * l) / 12.0;
    if along_x {
        Symmetric3::from_diagonal(DVec3::new(axial, transverse, transverse))
    } else {
        Symmetric3::from_diagonal(DVec3::new(transverse, transverse, axial))
    }
}

/// The DH table of [`six_axis`] (standard DH, UR5 geometry), with masses and centres of mass.
///
/// Useful to compare the model against a DH formula or to rebuild it in modified DH.
#[must_use]
pub fn six_axis_dh() -> DhTable {
    // Universal Robots' published UR5 kinematics and masses; centres of mass in DH frame i.
    let d = [0.089159, 0.0, 0.0, 0.10915, 0.09465, 0.0823];
    let a: [f64; 6] = [0.0, -0.425, -0.39225, 0.0, 0.0, 0.0];
    let alpha = [FRAC_PI_2, 0.0, 0.0, FRAC_PI_2, -FRAC_PI_2, 0.0];
    let mass = [3.7, 8.393, 2.33, 1.219, 1.219, 0.1879];
    let com = [
        [0.0, -0.02561, 0.00193],
        [0.2125, 0.0, 0.11336],
        [0.15, 0.0, 0.0265],
        [0.0, -0.0018, 0.01634],
        [0.0, 0.0018, 0.01634],
        [0.0, 0.0, -0.001159],
    ];
    let effort = [150.0, 150.0, 150.0, 28.0, 28.0, 28.0];
    let names = [
        ("shoulder_pan", "shoulder"),
        ("shoulder_lift", "upper_arm"),
        ("elbow", "forearm"),
        ("wrist_1", "wrist_1"),
        ("wrist_2", "wrist_2"),
        ("wrist_3", "wrist_3"),
    ];
    let mut table = DhTable::new("six_axis", DhConvention::Standard).with_tool(Se3::IDENTITY);
    for i in 0..6 {
        // Rotational inertias approximate each link as a solid cylinder (radius 6 cm) along the
        // link (x in DH frames 2 and 3) or along z (the short links).
        let along_x = a[i] != 0.0;
        let length = if along_x { a[i].abs() } else { 0.12 };
        table = table.with_row(
            DhRow::revolute(a[i], alpha[i], d[i], 0.0)
                .with_limits(limits(-TAU, TAU, PI, effort[i]))
                .with_inertial(Inertial {
                    origin: Se3::from_translation(DVec3::from_array(com[i])),
                    mass: mass[i],
                    inertia: cylinder_inertia(mass[i], 0.06, length, along_x),
                })
                .with_names(
                    format!("{}_joint", names[i].0),
                    format!("{}_link", names[i].1),
                ),
        );
    }
    table.base_name = Some("base_link".into());
    table
}

/// A six-axis industrial arm with UR5 geometry (standard DH, see [`six_axis_dh`]).
///
/// Links `base_link`, `shoulder_link`, `upper_arm_link`, `forearm_link`, `wrist_1_link`,
/// `wrist_2_link`, `wrist_3_link`; joints `shoulder_pan_joint` … `wrist_3_joint`, revolute about
/// their z axes with limits ±2π, velocity π rad/s and efforts 150, 150, 150, 28, 28, 28 N·m.
/// Masses and centres of mass are UR5's published values; rotational inertias approximate the
/// links as cylinders. Frames `dh1` … `dh6` are the DH frames and `tool` equals `dh6`; at
/// `q = 0` the tool is at `(-0.81725, -0.19145, -0.005491)`. The upper arm and forearm carry
/// capsule collision shapes of radius 6 cm along their length, and every link a sphere.
#[must_use]
pub fn six_axis() -> Model {
    let table = six_axis_dh();
    let a: Vec<f64> = table.rows.iter().map(|r| r.a).collect();
    dh_model(&table, |i, link, link_from_dh| {
        let shape = if a[i] == 0.0 {
            (Se3::IDENTITY, Geometry::Sphere { radius: 0.06 })
        } else {
            // A capsule from DH frame i's origin to the previous joint, along x.
            let along_x = Se3::from_rotation_y(FRAC_PI_2);
            (
                Se3::from_translation(DVec3::new(-a[i] / 2.0, 0.0, 0.0)) * along_x,
                Geometry::Capsule {
                    radius: 0.06,
                    length: a[i].abs(),
                },
            )
        };
        let origin = *link_from_dh * shape.0;
        link.collisions.push(Collision {
            name: None,
            origin,
            geometry: shape.1.clone(),
        });
        link.visuals.push(Visual {
            name: None,
            origin,
            geometry: shape.1,
            material: Some("aluminium".into()),
            color: Some([0.7, 0.7, 0.75, 1.0]),
        });
    })
    .expect("the six-axis sample is valid")
}

/// splitmix64: a tiny, well-mixed deterministic generator (Steele, Lea and Flood 2014).
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in `0..n` (`n > 0`).
    fn below(&mut self, n: usize) -> usize {
        ((self.unit() * n as f64) as usize).min(n - 1)
    }

    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    fn vec3(&mut self, half: f64) -> DVec3 {
        DVec3::new(
            self.range(-half, half),
            self.range(-half, half),
            self.range(-half, half),
        )
    }

    fn unit_vec3(&mut self) -> DVec3 {
        loop {
            let v = self.vec3(1.0);
            let n = v.length();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }

    fn rotation(&mut self) -> Se3 {
        loop {
            let q = DQuat::from_xyzw(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let n = q.length();
            if n > 0.1 && n <= 1.0 {
                return Se3::from_quat(q / n);
            }
        }
    }
}

/// A random tree of `n_bodies` links below a root link, the same for the same `seed`.
///
/// Equivalent to [`random_tree_with_root`] with [`RootJoint::Fixed`].
#[must_use]
pub fn random_tree(seed: u64, n_bodies: usize) -> Model {
    random_tree_with_root(seed, n_bodies, RootJoint::Fixed)
}

/// A random tree: root link `link0` plus `n_bodies` links `link1` … `linkN`, each attached by a
/// joint `joint{i}` to a random earlier link (half the time the one just before, which makes
/// chains). The same `seed` gives the same model on every platform.
///
/// Joint kinds are mixed: revolute, continuous, prismatic, cylindrical, spherical, planar and
/// fixed (fixed joints, about one in five, often follow each other to form fixed chains). Axes
/// are axis-aligned (±x, ±y, ±z) half the time and arbitrary otherwise; placements are random
/// within ±0.3 m with random rotations. Every link driven by a moving joint has a mass between
/// 0.2 and 2 kg with a random centre of mass and a random physically valid inertia; links on
/// fixed joints are massless half the time. Revolute, prismatic and cylindrical joints have
/// finite position limits; every moving joint has velocity and effort limits. About one link in
/// five carries an extra frame `frame{i}`, and every massive link a collision shape.
#[must_use]
pub fn random_tree_with_root(seed: u64, n_bodies: usize, root: RootJoint) -> Model {
    let mut rng = SplitMix64(seed ^ 0x6B69_6E65_7472_6565);
    let mut b = ModelBuilder::new(format!("random_tree_{seed}_{n_bodies}"));
    b.root_joint(root);
    let root_mass = random_inertial(&mut rng);
    b.add_link(Link::new("link0").with_inertial(root_mass));
    let kinds = [
        (JointKind::Revolute, 0.25),
        (JointKind::Continuous, 0.08),
        (JointKind::Prismatic, 0.14),
        (JointKind::Cylindrical, 0.08),
        (JointKind::Spherical, 0.1),
        (JointKind::Planar, 0.07),
        (JointKind::Fixed, 0.28),
    ];
    let mut last_fixed = false;
    for i in 1..=n_bodies {
        let parent = if rng.chance(0.5) { i - 1 } else { rng.below(i) };
        let kind = if last_fixed && parent == i - 1 && rng.chance(0.5) {
            JointKind::Fixed
        } else {
            let mut x = rng.unit();
            let mut pick = JointKind::Fixed;
            for (k, p) in kinds {
                if x < p {
                    pick = k;
                    break;
                }
                x -= p;
            }
            pick
        };
        last_fixed = kind == JointKind::Fixed;
        let axis = if rng.chance(0.5) {
            let e = [DVec3::X, DVec3::Y, DVec3::Z][rng.below(3)];
            if rng.chance(0.5) { e } else { -e }
        } else {
            rng.unit_vec3()
        };
        let rotation = if rng.chance(0.3) {
            Se3::IDENTITY
        } else {
            rng.rotation()
        };
        let placement = Se3::from_translation(rng.vec3(0.3)) * rotation;
        let (velocity, effort) = if kind.is_moving() {
            (rng.range(1.0, 10.0), rng.range(5.0, 100.0))
        } else {
            (f64::INFINITY, f64::INFINITY)
        };
        let (lower, upper) = match kind {
            JointKind::Revolute => (rng.range(-3.0, -0.5), rng.range(0.5, 3.0)),
            JointKind::Prismatic => (rng.range(-0.5, -0.05), rng.range(0.05, 0.5)),
            JointKind::Cylindrical => (rng.range(-1.0, -0.1), rng.range(0.1, 1.0)),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        };
        let name = format!("link{i}");
        let mut link = Link::new(name.clone());
        if kind.is_moving() || rng.chance(0.5) {
            link.inertial = Some(random_inertial(&mut rng));
            let origin = Se3::from_translation(rng.vec3(0.1)) * rng.rotation();
            let geometry = match rng.below(3) {
                0 => Geometry::Sphere {
                    radius: rng.range(0.02, 0.1),
                },
                1 => Geometry::Box {
                    size: [
                        rng.range(0.02, 0.2),
                        rng.range(0.02, 0.2),
                        rng.range(0.02, 0.2),
                    ],
                },
                _ => Geometry::Capsule {
                    radius: rng.range(0.02, 0.06),
                    length: rng.range(0.05, 0.3),
                },
            };
            link.collisions.push(Collision {
                name: None,
                origin,
                geometry,
            });
        }
        b.add_part(
            link,
            JointSpec::new(
                format!("joint{i}"),
                kind,
                format!("link{parent}"),
                name.clone(),
            )
            .with_placement(placement)
            .with_axis(axis)
            .with_limits(limits(lower, upper, velocity, effort)),
        );
        if rng.chance(0.2) {
            let at = Se3::from_translation(rng.vec3(0.2)) * rng.rotation();
            b.add_frame(FrameSpec::new(format!("frame{i}"), name, at));
        }
    }
    b.build().expect("random trees are valid by construction")
}

/// A random physically valid inertial: mass in [0.2, 2] kg, centre of mass within ±0.1 m, and
/// principal moments built from positive second moments (so the triangle inequality holds),
/// turned by a random rotation.
fn random_inertial(rng: &mut SplitMix64) -> Inertial {
    let m = rng.range(0.2, 2.0);
    let s = DVec3::new(
        rng.range(0.001, 0.02),
        rng.range(0.001, 0.02),
        rng.range(0.001, 0.02),
    ) * m;
    let principal = Symmetric3::from_diagonal(DVec3::new(s.y + s.z, s.x + s.z, s.x + s.y));
    Inertial {
        origin: Se3::from_translation(rng.vec3(0.1)),
        mass: m,
        inertia: principal.rotate(&rng.rotation().rotation),
    }
}

/// A humanoid-like robot on a floating base: a deep tree with many fixed joints, as real
/// humanoid descriptions have.
///
/// `pelvis` (floating root, `root_joint`) carries a torso (`torso_yaw`), a head
/// (`neck_yaw`, `neck_pitch`), two arms (`{l,r}_shoulder_{pitch,roll,yaw}`, `{l,r}_elbow`) and
/// two legs (`{l,r}_hip_{yaw,roll,pitch}`, `{l,r}_knee`, `{l,r}_ankle_{pitch,roll}`), all
/// revolute: nq = 7 + 27 = 34 and nv = 33. Fixed joints attach an IMU to the torso, a camera to
/// the head, a hand to each forearm and a sole to each foot; frames `l_sole_contact`,
/// `r_sole_contact`, `l_grasp` and `r_grasp` sit on those. Total mass 47.2 kg.
#[must_use]
pub fn humanoid_like() -> Model {
    let mut b = ModelBuilder::new("humanoid_like");
    b.root_joint(RootJoint::Floating);
    let body = |name: &str, m: f64, com: DVec3, size: DVec3| -> Link {
        // A solid box of the given size around the centre of mass.
        let i = DVec3::new(
            size.y * size.y + size.z * size.z,
            size.x * size.x + size.z * size.z,
            size.x * size.x + size.y * size.y,
        ) * (m / 12.0);
        let shape = Geometry::Box {
            size: size.to_array(),
        };
        Link {
            inertial: Some(Inertial {
                origin: Se3::from_translation(com),
                mass: m,
                inertia: Symmetric3::from_diagonal(i),
            }),
            collisions: vec![Collision {
                name: None,
                origin: Se3::from_translation(com),
                geometry: shape,
            }],
            ..Link::new(name)
        }
    };
    let rev = |name: &str, parent: &str, child: &str, at: DVec3, axis: DVec3, range: f64| {
        JointSpec::new(name, JointKind::Revolute, parent, child)
            .with_placement(Se3::from_translation(at))
            .with_axis(axis)
            .with_limits(limits(-range, range, 6.0, 100.0))
    };
    let fixed = |name: &str, parent: &str, child: &str, at: DVec3| {
        JointSpec::new(name, JointKind::Fixed, parent, child)
            .with_placement(Se3::from_translation(at))
    };
    let v = DVec3::new;
    b.add_link(body("pelvis", 8.0, v(0.0, 0.0, 0.0), v(0.2, 0.3, 0.15)));
    b.add_part(
        body("torso", 12.0, v(0.0, 0.0, 0.2), v(0.2, 0.35, 0.4)),
        rev(
            "torso_yaw",
            "pelvis",
            "torso",
            v(0.0, 0.0, 0.1),
            DVec3::Z,
            1.0,
        ),
    );
    b.add_part(
        Link::new("imu"),
        fixed("imu_mount", "torso", "imu", v(0.0, 0.0, 0.1)),
    );
    b.add_part(
        body("neck", 0.5, v(0.0, 0.0, 0.03), v(0.05, 0.05, 0.06)),
        rev(
            "neck_yaw",
            "torso",
            "neck",
            v(0.0, 0.0, 0.45),
            DVec3::Z,
            1.2,
        ),
    );
    b.add_part(
        body("head", 2.5, v(0.0, 0.0, 0.1), v(0.18, 0.16, 0.2)),
        rev(
            "neck_pitch",
            "neck",
            "head",
            v(0.0, 0.0, 0.06),
            DVec3::Y,
            0.8,
        ),
    );
    b.add_part(
        Link::new("camera"),
        fixed("camera_mount", "head", "camera", v(0.09, 0.0, 0.12)),
    );
    for (side, y) in [("l", 1.0), ("r", -1.0)] {
        let n = |s: &str| format!("{side}_{s}");
        b.add_part(
            body(&n("shoulder"), 0.6, v(0.0, 0.0, 0.0), v(0.08, 0.08, 0.08)),
            rev(
                &n("shoulder_pitch"),
                "torso",
                &n("shoulder"),
                v(0.0, 0.22 * y, 0.35),
                DVec3::Y,
                3.0,
            ),
        );
        b.add_part(
            body(
                &n("upper_arm_roll"),
                0.4,
                v(0.0, 0.0, 0.0),
                v(0.06, 0.06, 0.06),
            ),
            rev(
                &n("shoulder_roll"),
                &n("shoulder"),
                &n("upper_arm_roll"),
                v(0.0, 0.05 * y, 0.0),
                DVec3::X,
                1.5,
            ),
        );
        b.add_part(
            body(
                &n("upper_arm"),
                1.5,
                v(0.0, 0.0, -0.13),
                v(0.07, 0.07, 0.26),
            ),
            rev(
                &n("shoulder_yaw"),
                &n("upper_arm_roll"),
                &n("upper_arm"),
                v(0.0, 0.0, -0.03),
                DVec3::Z,
                2.0,
            ),
        );
        b.add_part(
            body(&n("forearm"), 1.0, v(0.0, 0.0, -0.12), v(0.06, 0.06, 0.24)),
            rev(
                &n("elbow"),
                &n("upper_arm"),
                &n("forearm"),
                v(0.0, 0.0, -0.26),
                DVec3::Y,
                2.2,
            ),
        );
        b.add_part(
            body(&n("hand"), 0.4, v(0.0, 0.0, -0.05), v(0.04, 0.08, 0.1)),
            fixed(&n("wrist"), &n("forearm"), &n("hand"), v(0.0, 0.0, -0.24)),
        );
        b.add_frame(FrameSpec::new(
            n("grasp"),
            n("hand"),
            Se3::from_translation(v(0.0, 0.0, -0.08)),
        ));
        b.add_part(
            body(&n("hip"), 0.8, v(0.0, 0.0, -0.03), v(0.08, 0.08, 0.08)),
            rev(
                &n("hip_yaw"),
                "pelvis",
                &n("hip"),
                v(0.0, 0.1 * y, -0.08),
                DVec3::Z,
                0.8,
            ),
        );
        b.add_part(
            body(
                &n("hip_roll_link"),
                0.8,
                v(0.0, 0.0, 0.0),
                v(0.08, 0.08, 0.08),
            ),
            rev(
                &n("hip_roll"),
                &n("hip"),
                &n("hip_roll_link"),
                v(0.0, 0.0, -0.06),
                DVec3::X,
                0.6,
            ),
        );
        b.add_part(
            body(&n("thigh"), 3.5, v(0.0, 0.0, -0.2), v(0.12, 0.12, 0.4)),
            rev(
                &n("hip_pitch"),
                &n("hip_roll_link"),
                &n("thigh"),
                v(0.0, 0.0, 0.0),
                DVec3::Y,
                2.0,
            ),
        );
        b.add_part(
            body(&n("shin"), 2.0, v(0.0, 0.0, -0.2), v(0.1, 0.1, 0.4)),
            rev(
                &n("knee"),
                &n("thigh"),
                &n("shin"),
                v(0.0, 0.0, -0.4),
                DVec3::Y,
                2.3,
            ),
        );
        b.add_part(
            body(&n("ankle"), 0.3, v(0.0, 0.0, 0.0), v(0.05, 0.05, 0.05)),
            rev(
                &n("ankle_pitch"),
                &n("shin"),
                &n("ankle"),
                v(0.0, 0.0, -0.4),
                DVec3::Y,
                1.0,
            ),
        );
        b.add_part(
            body(&n("foot"), 0.8, v(0.03, 0.0, -0.04), v(0.22, 0.1, 0.04)),
            rev(
                &n("ankle_roll"),
                &n("ankle"),
                &n("foot"),
                v(0.0, 0.0, 0.0),
                DVec3::X,
                0.5,
            ),
        );
        b.add_part(
            Link::new(n("sole")),
            fixed(
                &n("sole_mount"),
                &n("foot"),
                &n("sole"),
                v(0.03, 0.0, -0.06),
            ),
        );
        b.add_frame(FrameSpec::new(n("sole_contact"), n("sole"), Se3::IDENTITY));
    }
    b.build().expect("the humanoid sample is valid")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_have_the_documented_sizes() {
        let p = pendulum();
        assert_eq!((p.nq(), p.nv(), p.links().len()), (1, 1, 2));
        assert_eq!(p.total_mass(), 1.0);
        let d = double_pendulum();
        assert_eq!((d.nq(), d.nv(), d.total_mass()), (2, 2, 2.0));
        let a = planar_2r(0.5, 0.3);
        assert_eq!((a.nq(), a.nv(), a.total_mass()), (2, 2, 2.0));
        let s = six_axis();
        assert_eq!((s.nq(), s.nv(), s.links().len()), (6, 6, 7));
        assert!((s.total_mass() - 17.0489).abs() < 1e-12);
        let h = humanoid_like();
        assert_eq!(
            (h.nq(), h.nv(), h.root_joint()),
            (30, 29, RootJoint::Floating)
        );
        assert!((h.total_mass() - 47.2).abs() < 1e-12, "{}", h.total_mass());
        // Fixed joints are merged: 23 revolute bodies plus the floating base plus the world.
        assert_eq!(h.nbodies(), 25);
        for m in [&p, &d, &a, &s, &h] {
            assert!(m.warnings().is_empty(), "{}: {:?}", m.name(), m.warnings());
        }
    }

    #[test]
    fn six_axis_tool_at_zero_is_the_ur5_home_pose() {
        let s = six_axis();
        // Sum the placements at q = 0 by hand over the body chain.
        let mut world = Se3::IDENTITY;
        for b in s.bodies().iter().skip(1) {
            world *= b.placement;
        }
        let (body, body_from_tool) = s.frame_body(s.frame_index("tool").unwrap());
        assert_eq!(body, 6);
        let tool = world * body_from_tool;
        let expected = DVec3::new(-0.81725, -0.19145, -0.005491);
        assert!(
            (tool.translation - expected).length() < 1e-12,
            "{}",
            tool.translation
        );
    }

    #[test]
    fn random_trees_are_deterministic_and_mixed() {
        let a = random_tree(42, 60);
        let b = random_tree(42, 60);
        assert_eq!(a, b);
        assert_ne!(a, random_tree(43, 60));
        assert_eq!(a.links().len(), 61);
        let has = |k: JointKind| a.joints().iter().any(|j| j.kind == k);
        for k in [
            JointKind::Revolute,
            JointKind::Continuous,
            JointKind::Prismatic,
            JointKind::Cylindrical,
            JointKind::Spherical,
            JointKind::Planar,
            JointKind::Fixed,
        ] {
            assert!(has(k), "no {k} joint");
        }
        // At least one fixed joint whose parent link also hangs on a fixed joint: a fixed chain.
        let fixed_chain = a.joints().iter().any(|j| {
            j.kind == JointKind::Fixed
                && j.parent_link
                    .and_then(|p| a.parent_joint(p))
                    .is_some_and(|pj| a.joint(pj).kind == JointKind::Fixed)
        });
        assert!(fixed_chain);
        assert!(a.warnings().is_empty(), "{:?}", a.warnings());
        let f = random_tree_with_root(42, 60, RootJoint::Floating);
        assert_eq!((f.nq(), f.nv()), (a.nq() + 7, a.nv() + 6));
        for seed in 0..200 {
            let m = random_tree(seed, seed as usize % 40);
            assert!(m.warnings().is_empty());
        }
    }
}
