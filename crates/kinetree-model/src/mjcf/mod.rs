//! MJCF (MuJoCo's XML) import ([`Model::from_mjcf_file`], [`Model::from_mjcf_str`]), export
//! ([`Model::to_mjcf_string`]), and the conversions between MuJoCo's
//! `qpos`/`qvel`/`qacc`/`qfrc` and kinetree's `q`/`v`/`a`/`tau`.
//!
//! ## What is read
//!
//! The loader follows MuJoCo's compiler (checked against MuJoCo 4.0 on gymnasium and dm_control
//! models, see `tests/data/reference/mjcf`):
//! - `<include file=…>` anywhere, looked up relative to the main file's folder and then to the
//!   including file's; a file included twice is an error, as in MuJoCo;
//! - `<default>` classes, nested, with `class=` on elements and `childclass=` on bodies and
//!   frames; attributes fall back through the class's ancestors to `main`, and a partial `size`
//!   replaces only the leading numbers it gives;
//! - `<compiler>`: `angle`, `eulerseq`, `autolimits`, `inertiafromgeom`, `inertiagrouprange`,
//!   `boundmass`, `boundinertia`, `balanceinertia`, `settotalmass`, `meshdir`, `assetdir`;
//! - every orientation form (`quat`, `axisangle`, `euler`, `xyaxes`, `zaxis`), `<frame>`s,
//!   geoms given by `fromto`;
//! - bodies with `<inertial>` (`diaginertia` or `fullinertia`), or with mass and inertia
//!   inferred from their geoms (spheres, capsules, cylinders, ellipsoids, boxes; solid or
//!   `shellinertia`; `mass=` or `density=`);
//! - joints `hinge`, `slide`, `ball`, `free` (and `<freejoint>`), several in one body, each at
//!   its own `pos` anchor, with `ref`, `range`/`limited`, `armature`, `damping` and
//!   `frictionloss` (kept as [`JointDynamics`](crate::JointDynamics): off in the dynamics by
//!   default, as for URDF);
//! - `<site>`s as named frames, geoms as visuals and (when `contype` or `conaffinity` is
//!   non-zero) collision shapes, gravity from `<option gravity=…>` and `<flag gravity=…>`.
//!
//! What kinetree does not model is listed in [`Model::ignored`] with counts: actuators,
//! tendons, equality constraints, sensors, contact pairs and exclusions, keyframes, cameras and
//! lights, joint stiffness, ball-joint cone limits, and geoms without a collision shape yet
//! (ellipsoids, planes, height fields). Elements that generate bodies (`<replicate>`,
//! `<composite>`, `<flexcomp>`, `<attach>`) are refused with an error naming the line, as are
//! mesh geoms whose inertia MuJoCo would infer from the mesh.
//!
//! ## The tree
//!
//! The world body is a link called `world`, the root of the model. Each body is a link with its
//! MuJoCo name (an unnamed body is `body<id>`, its id in MuJoCo's depth-first order, world = 0).
//! Each MuJoCo joint is a kinetree joint with its MuJoCo name (an unnamed joint is
//! `<body>:<k>`, `k` its position among the body's joints). When a body has several joints, or
//! its last joint's anchor is not at the body origin, the joints are chained through massless
//! links `<body>:<k>`, and a fixed joint `<body>:anchor` brings the anchor back to the body
//! frame; a body without joints hangs from its parent by a fixed joint `<body>:fixed`. These
//! extra links and fixed joints have no coordinates, so `q` has exactly MuJoCo's `nq` entries
//! in MuJoCo's order. Unnamed sites are `site<id>`.
//!
//! ## Coordinates
//!
//! | MuJoCo joint | kinetree joint | `qpos` → `q` | `qvel` → `v` |
//! |---|---|---|---|
//! | `hinge` | revolute (limited) or continuous | same number | same |
//! | `slide` | prismatic | same number | same |
//! | `ball` | spherical | `[w, x, y, z]` → `[x, y, z, w]` | same (child frame) |
//! | `free` | floating | `[p, w, x, y, z]` → `[p, x, y, z, w]` | `[v_world, ω_body]` → `[Rᵀ v_world, ω_body]` |
//!
//! A hinge or slide joint's `ref` is folded into the joint placement, so kinetree's `q` is
//! MuJoCo's `qpos` itself (the body is where the file puts it at `q = ref`), and its limits are
//! `range` as written. A free joint's linear velocity is in the world frame in MuJoCo and in the
//! body frame in kinetree, so accelerations and generalized forces differ too:
//! `a_lin = Rᵀ qacc_lin − ω × v_lin` and `tau_lin = Rᵀ qfrc_lin`, with `R` the body's
//! orientation. [`Model::q_from_mujoco`], [`Model::v_from_mujoco`],
//! [`Model::a_from_mujoco`], [`Model::tau_from_mujoco`] and their inverses do this for whole
//! vectors (on any model: every floating joint is treated as a free joint attached to the
//! world, every spherical joint as a ball joint).
//!
//! ```
//! use kinetree_model::Model;
//! # fn main() -> Result<(), kinetree_model::ModelError> {
//! let xml = r#"<mujoco>
//!   <worldbody>
//!     <body name="box" pos="0 0 1">
//!       <freejoint name="root"/>
//!       <geom type="box" size="0.1 0.2 0.3" mass="2"/>
//!     </body>
//!   </worldbody>
//! </mujoco>"#;
//! let model = Model::from_mjcf_str(xml)?;
//! assert_eq!((model.nq(), model.nv()), (7, 6));
//! // MuJoCo's qpos [x y z qw qx qy qz] is kinetree's [x y z qx qy qz qw].
//! let half = std::f64::consts::FRAC_1_SQRT_2;
//! let qpos = [0.0, 0.0, 1.0, half, 0.0, 0.0, half];
//! let q = model.q_from_mujoco(&qpos)?;
//! assert_eq!(q, [0.0, 0.0, 1.0, 0.0, 0.0, half, half]);
//! // A world-frame velocity along x is along −y in a body turned a quarter about z.
//! let v = model.v_from_mujoco(&qpos, &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0])?;
//! assert!((v[1] + 1.0).abs() < 1e-12 && v[0].abs() < 1e-12);
//! assert_eq!(model.q_to_mujoco(&q)?, qpos);
//! # Ok(())
//! # }
//! ```

mod inertia;
mod orient;
mod read;
mod write;

use crate::error::ModelError;
use crate::joint::JointKind;
use crate::model::Model;
use glam::{DMat3, DQuat, DVec3};
use std::path::Path;

pub(crate) use read::from_mjcf;

impl Model {
    /// Loads an MJCF (MuJoCo XML) file; `<include>`s and mesh folders are resolved relative to
    /// its folder. See [`crate::mjcf`] for what is read and how bodies and joints are named.
    ///
    /// # Errors
    /// [`ModelError::Io`]/[`ModelError::Encoding`] when the file cannot be read as text,
    /// [`ModelError::Xml`] for malformed XML, [`ModelError::Mjcf`] naming the file, line and
    /// element for what MuJoCo's compiler would refuse (and for what kinetree cannot load yet),
    /// [`ModelError::Invalid`] when the tree fails the builder's checks.
    pub fn from_mjcf_file(path: impl AsRef<Path>) -> Result<Model, ModelError> {
        let path = path.as_ref();
        let text = crate::json::read_file(path)?;
        from_mjcf(&text, Some(path))
    }

    /// Loads an MJCF document from a string; `<include>`s and mesh folders are resolved
    /// relative to the current directory.
    ///
    /// # Errors
    /// As [`Model::from_mjcf_file`].
    pub fn from_mjcf_str(text: &str) -> Result<Model, ModelError> {
        from_mjcf(text, None)
    }

    /// Converts a MuJoCo `qpos` (length `nq`) into kinetree's `q`: quaternions of floating and
    /// spherical joints go from `[w, x, y, z]` to `[x, y, z, w]`.
    ///
    /// # Errors
    /// [`ModelError::Length`] when `qpos` does not have [`Model::nq`] entries.
    pub fn q_from_mujoco(&self, qpos: &[f64]) -> Result<Vec<f64>, ModelError> {
        check_len("qpos", self.nq(), qpos)?;
        let mut q = qpos.to_vec();
        for (joint, kind) in self.quaternion_joints() {
            let r = self.joint_q_range(joint);
            let at = if kind == JointKind::Floating {
                r.start + 3
            } else {
                r.start
            };
            q[at..at + 4].copy_from_slice(&[qpos[at + 1], qpos[at + 2], qpos[at + 3], qpos[at]]);
        }
        Ok(q)
    }

    /// Converts kinetree's `q` (length `nq`) into a MuJoCo `qpos`: the inverse of
    /// [`Model::q_from_mujoco`].
    ///
    /// # Errors
    /// [`ModelError::Length`] when `q` does not have [`Model::nq`] entries.
    pub fn q_to_mujoco(&self, q: &[f64]) -> Result<Vec<f64>, ModelError> {
        check_len("q", self.nq(), q)?;
        let mut qpos = q.to_vec();
        for (joint, kind) in self.quaternion_joints() {
            let r = self.joint_q_range(joint);
            let at = if kind == JointKind::Floating {
                r.start + 3
            } else {
                r.start
            };
            qpos[at..at + 4].copy_from_slice(&[q[at + 3], q[at], q[at + 1], q[at + 2]]);
        }
        Ok(qpos)
    }

    /// Converts a MuJoCo `qvel` (length `nv`) at `qpos` into kinetree's `v`: a floating joint's
    /// linear velocity goes from the world frame to the body frame.
    ///
    /// # Errors
    /// [`ModelError::Length`] when `qpos` or `qvel` has the wrong length.
    pub fn v_from_mujoco(&self, qpos: &[f64], qvel: &[f64]) -> Result<Vec<f64>, ModelError> {
        let q = self.q_from_mujoco(qpos)?;
        check_len("qvel", self.nv(), qvel)?;
        Ok(self.map_linear(&q, qvel, |r, x| r.transpose() * x))
    }

    /// Converts kinetree's `v` (length `nv`) at `q` into a MuJoCo `qvel`: the inverse of
    /// [`Model::v_from_mujoco`].
    ///
    /// # Errors
    /// [`ModelError::Length`] when `q` or `v` has the wrong length.
    pub fn v_to_mujoco(&self, q: &[f64], v: &[f64]) -> Result<Vec<f64>, ModelError> {
        check_len("q", self.nq(), q)?;
        check_len("v", self.nv(), v)?;
        Ok(self.map_linear(q, v, |r, x| r * x))
    }

    /// Converts a MuJoCo `qacc` (length `nv`) at `qpos`, `qvel` into kinetree's `a`: for a
    /// floating joint `a_lin = Rᵀ qacc_lin − ω × v_lin`, the derivative of the body-frame
    /// velocity.
    ///
    /// # Errors
    /// [`ModelError::Length`] when a vector has the wrong length.
    pub fn a_from_mujoco(
        &self,
        qpos: &[f64],
        qvel: &[f64],
        qacc: &[f64],
    ) -> Result<Vec<f64>, ModelError> {
        let q = self.q_from_mujoco(qpos)?;
        let v = self.v_from_mujoco(qpos, qvel)?;
        check_len("qacc", self.nv(), qacc)?;
        let mut a = self.map_linear(&q, qacc, |r, x| r.transpose() * x);
        self.add_transport(&v, &mut a, -1.0);
        Ok(a)
    }

    /// Converts kinetree's `a` (length `nv`) at `q`, `v` into a MuJoCo `qacc`: the inverse of
    /// [`Model::a_from_mujoco`].
    ///
    /// # Errors
    /// [`ModelError::Length`] when a vector has the wrong length.
    pub fn a_to_mujoco(&self, q: &[f64], v: &[f64], a: &[f64]) -> Result<Vec<f64>, ModelError> {
        check_len("q", self.nq(), q)?;
        check_len("v", self.nv(), v)?;
        check_len("a", self.nv(), a)?;
        let mut body = a.to_vec();
        self.add_transport(v, &mut body, 1.0);
        Ok(self.map_linear(q, &body, |r, x| r * x))
    }

    /// Converts MuJoCo generalized forces (`qfrc_*`, length `nv`) at `qpos` into kinetree's
    /// `tau`: a floating joint's force goes from the world frame to the body frame (the power
    /// `tau · v` is the same in both).
    ///
    /// # Errors
    /// [`ModelError::Length`] when `qpos` or `qfrc` has the wrong length.
    pub fn tau_from_mujoco(&self, qpos: &[f64], qfrc: &[f64]) -> Result<Vec<f64>, ModelError> {
        let q = self.q_from_mujoco(qpos)?;
        check_len("qfrc", self.nv(), qfrc)?;
        Ok(self.map_linear(&q, qfrc, |r, x| r.transpose() * x))
    }

    /// Converts kinetree's `tau` (length `nv`) at `q` into MuJoCo generalized forces: the
    /// inverse of [`Model::tau_from_mujoco`].
    ///
    /// # Errors
    /// [`ModelError::Length`] when `q` or `tau` has the wrong length.
    pub fn tau_to_mujoco(&self, q: &[f64], tau: &[f64]) -> Result<Vec<f64>, ModelError> {
        check_len("q", self.nq(), q)?;
        check_len("tau", self.nv(), tau)?;
        Ok(self.map_linear(q, tau, |r, x| r * x))
    }

    /// The joints whose configuration holds a quaternion.
    fn quaternion_joints(&self) -> impl Iterator<Item = (usize, JointKind)> + '_ {
        self.moving_joints().filter_map(|j| {
            let kind = self.joint(j).kind;
            matches!(kind, JointKind::Floating | JointKind::Spherical)
                .then_some((j, kind))
                .filter(|_| !self.joint_q_range(j).is_empty())
        })
    }

    /// `x` with every floating joint's linear block mapped by `f(R, block)`, `R` the joint's
    /// rotation in kinetree's `q`.
    fn map_linear(&self, q: &[f64], x: &[f64], f: impl Fn(DMat3, DVec3) -> DVec3) -> Vec<f64> {
        let mut out = x.to_vec();
        for (joint, kind) in self.quaternion_joints() {
            if kind != JointKind::Floating {
                continue;
            }
            let (qr, vr) = (self.joint_q_range(joint), self.joint_v_range(joint));
            let quat = DQuat::from_xyzw(
                q[qr.start + 3],
                q[qr.start + 4],
                q[qr.start + 5],
                q[qr.start + 6],
            )
            .normalize();
            let lin = f(
                DMat3::from_quat(quat),
                DVec3::from_slice(&x[vr.start..vr.start + 3]),
            );
            out[vr.start..vr.start + 3].copy_from_slice(&lin.to_array());
        }
        out
    }

    /// Adds `sign · ω × v_lin` to every floating joint's linear block of `a`.
    fn add_transport(&self, v: &[f64], a: &mut [f64], sign: f64) {
        for (joint, kind) in self.quaternion_joints() {
            if kind != JointKind::Floating {
                continue;
            }
            let s = self.joint_v_range(joint).start;
            let lin = DVec3::from_slice(&v[s..s + 3]);
            let w = DVec3::from_slice(&v[s + 3..s + 6]);
            let t = w.cross(lin) * sign;
            for k in 0..3 {
                a[s + k] += t[k];
            }
        }
    }
}

fn check_len(what: &'static str, expected: usize, x: &[f64]) -> Result<(), ModelError> {
    if x.len() == expected {
        Ok(())
    } else {
        Err(ModelError::Length {
            what,
            expected,
            actual: x.len(),
        })
    }
}
