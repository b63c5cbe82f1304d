//! # kinetree-model
//!
//! The model layer of kinetree: an immutable [`Model`] of links (parts), joints and named
//! frames, validated once by [`ModelBuilder`] and loaded from URDF ([`Model::from_urdf_file`]).
//! It sits on `kinetree-spatial` and below the kinematics layer; the algorithms above it sweep
//! over [`Model::bodies`], the moving-body tree in which chains of fixed joints are merged.
//!
//! ```
//! use kinetree_model::{Model, RootJoint};
//! # fn main() -> Result<(), kinetree_model::ModelError> {
//! let urdf = r#"<robot name="pendulum">
//!   <link name="base"/>
//!   <link name="bob"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
//!   <joint name="hinge" type="revolute">
//!     <parent link="base"/><child link="bob"/><axis xyz="0 1 0"/>
//!     <limit lower="-3" upper="3" effort="10" velocity="5"/>
//!   </joint>
//! </robot>"#;
//! let model = Model::from_urdf_str(urdf, RootJoint::Fixed)?;
//! assert_eq!((model.nq(), model.nv()), (1, 1));
//! let hinge = model.joint(model.joint_index("hinge").unwrap());
//! assert_eq!(hinge.axis.to_array(), [0.0, 1.0, 0.0]);
//! # Ok(())
//! # }
//! ```
//!
//! ## Conventions
//! - SI units inside (m, rad, kg). Degrees and millimetres exist only at the file edges.
//! - `q` has [`Model::nq`] entries and `v`/`a`/`tau` have [`Model::nv`]; each moving joint owns a
//!   contiguous block (see [`JointKind`] for the per-kind layout). Quaternions are x, y, z, w.
//! - A joint's `placement` is the pose of its frame in the parent link's frame at zero
//!   configuration; the child link's frame is the joint frame.
//! - Links and joints are stored depth-first from the root: parents precede children.
//!
//! ## Errors
//! Every loader returns [`ModelError`], which names the offending link, joint, frame or file; a
//! failed load returns nothing half-built.

mod builder;
mod compare;
pub mod dh;
mod error;
mod frame;
mod joint;
pub mod json;
mod link;
mod model;
pub mod samples;
mod urdf;
pub mod urdf_export;

pub use builder::{FrameSpec, INERTIA_TOLERANCE, InertiaCheck, JointSpec, ModelBuilder};
pub use error::{Issue, ItemKind, ModelError};
pub use frame::Frame;
pub use joint::{Joint, JointDynamics, JointKind, JointLimits, Mimic, plane_basis};
pub use json::{AngleUnit, DatumExport, JSON_SCHEMA_VERSION, JsonOptions, LengthUnit, Units};
pub use kinetree_spatial as spatial;
pub use link::{Collision, Geometry, Inertial, Link, LinkMetadata, Visual};
pub use model::{Body, Model, ROOT_JOINT_NAME, RootJoint};
