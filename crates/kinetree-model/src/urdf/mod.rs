//! URDF import ([`Model::from_urdf_str`], [`Model::from_urdf_file`]) and export
//! ([`Model::to_urdf_string`]).
//!
//! ## Import
//!
//! Import goes through urdf-rs.
//!
//! The XML is first scanned with quick-xml so that malformed files are reported with a line and
//! column, and so that elements kinetree does not model (transmissions, gazebo tags, calibration,
//! safety controllers, textures, …) are reported by [`Model::ignored`] instead of being dropped
//! silently.
//!
//! Real files are repaired rather than rejected where the intent is clear:
//! - `<texture>` elements are removed before urdf-rs sees them (urdf-rs rejects a `<texture/>`
//!   without `filename`, which iCub and Romeo carry) and listed in [`Model::ignored`];
//! - a `<robot>` without links loads as the empty model;
//! - a `<mimic>` naming a joint that does not exist is dropped and reported in
//!   [`Model::warnings`] as [`Issue::UnknownMimicTarget`]: kinetree treats mimic joints as
//!   independent degrees of freedom (as Pinocchio does), so the tag carries no information the
//!   model needs. [`ModelBuilder::build`](crate::ModelBuilder::build) used directly still rejects
//!   an unknown mimic target.
//!
//! ## Export
//!
//! [`Model::to_urdf_string`] writes a model as URDF.
//!
//! The XML is written by hand (urdf-rs's writer drops infinite limits, which URDF 1.0 readers then
//! take as zero), so that loading the output with [`Model::from_urdf_str`] gives the same model:
//! the same links, joints, placements (to round-off of the roll-pitch-yaw conversion), limits,
//! geometry and mimic tags, with `package://` and other mesh names exactly as written.
//!
//! What URDF cannot hold is left out: the floating root joint (a load option, not part of the
//! file), named frames, link metadata, joint armature, gravity, and position limits on joint
//! kinds that URDF gives none (fixed, continuous, floating, planar, spherical). Cylindrical joints
//! cannot be expressed at all and are an error.
//!
//! The file declares URDF 1.0 unless a limit is unbounded (a revolute or prismatic joint without
//! position bounds, or a joint without velocity or effort limit): URDF 1.0 has no way to say
//! so, and the file then declares version 1.2, in which an omitted limit means "none".

#[cfg(doc)]
use crate::{Issue, Model, ModelBuilder};

mod read;
pub(crate) mod write;

pub use read::LoadOptions;
pub(crate) use read::from_urdf;
