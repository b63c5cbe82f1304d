//! External datum frames (yapCAD's `datum_source` / `datum_name`): named poses kept in their
//! own file, read by the JSON loader for frames that refer to them, and available here on
//! their own and for re-reading into a loaded model.
//!
//! A datum file holds named poses in its own units (see [`crate::json`] for the format):
//!
//! ```json
//! { "units": { "length": "mm", "angle": "deg" },
//!   "datums": { "output_shaft": { "xyz": [0, 0, 12.5], "rpy": [0, 0, 90] } } }
//! ```

use crate::error::ModelError;
use crate::json::read::resolve_one;
use crate::model::Model;
use kinetree_spatial::{Inertia, Se3};
use std::path::Path;

/// Reads the pose of datum `name` from the datum file `file` (in SI units).
///
/// # Errors
/// [`ModelError::Datum`] naming the file and the datum when the file cannot be read or parsed,
/// has an unknown unit, or has no datum of that name (the names it has are listed).
///
/// # Examples
/// ```
/// # fn main() -> Result<(), kinetree_model::ModelError> {
/// let dir = std::env::temp_dir().join(format!("kinetree-datum-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let file = dir.join("servo.json");
/// std::fs::write(&file, r#"{"units": {"length": "mm"}, "datums": {"shaft": {"xyz": [0, 0, 12.5]}}}"#).unwrap();
/// let shaft = kinetree_model::datum::resolve_datum(&file, "shaft")?;
/// assert_eq!(shaft.translation.z, 0.0125);
/// let missing = kinetree_model::datum::resolve_datum(&file, "horn").unwrap_err();
/// assert!(missing.to_string().contains("horn") && missing.to_string().contains("servo.json"));
/// # Ok(())
/// # }
/// ```
pub fn resolve_datum(file: impl AsRef<Path>, name: &str) -> Result<Se3, ModelError> {
    resolve_one(None, name, &file.as_ref().display().to_string(), name)
}

impl Model {
    /// Re-reads every frame that came from a datum file and moves it (and the joints attached to
    /// it through `parent_frame`) to the pose the file now gives. Relative datum paths are
    /// resolved against `base` (the model file's directory), or the current directory when
    /// `base` is `None`. Returns the number of frames whose pose changed.
    ///
    /// Nothing is changed when any datum fails to resolve.
    ///
    /// # Errors
    /// [`ModelError::Datum`] naming the frame, the file and the datum.
    pub fn reload_datums(&mut self, base: Option<&Path>) -> Result<usize, ModelError> {
        let mut updates = Vec::new();
        for (i, frame) in self.frames.iter().enumerate() {
            let Some((file, name)) = &frame.datum else {
                continue;
            };
            let pose = resolve_one(base, &frame.name, file, name)?;
            if pose != frame.placement {
                updates.push((i, pose));
            }
        }
        for &(i, pose) in &updates {
            let (link, old) = (self.frames[i].link, self.frames[i].placement);
            let frame_name = self.frames[i].name.clone();
            self.frames[i].placement = pose;
            // Joints attached at this frame keep their offset from it.
            for j in &mut self.joints {
                if j.parent_link == Some(link) && j.parent_frame.as_deref() == Some(&frame_name) {
                    j.placement = pose * old.inverse() * j.placement;
                }
            }
        }
        if !updates.is_empty() {
            self.rederive_bodies();
        }
        Ok(updates.len())
    }

    /// Recomputes the body placements, link-in-body poses and body inertias from the joints'
    /// placements (after joint placements changed).
    fn rederive_bodies(&mut self) {
        for (ji, j) in self.joints.iter().enumerate() {
            let (pb, pb_from_parent) = match j.parent_link {
                Some(p) => (self.link_body[p], self.body_from_link[p]),
                None => (0, Se3::IDENTITY),
            };
            match self.joint_body[ji] {
                Some(b) => self.bodies[b].placement = pb_from_parent * j.placement,
                None => {
                    self.link_body[j.child_link] = pb;
                    self.body_from_link[j.child_link] = pb_from_parent * j.placement;
                }
            }
        }
        for b in &mut self.bodies {
            b.inertia = Inertia::ZERO;
        }
        for (l, link) in self.links.iter().enumerate() {
            let b = self.link_body[l];
            self.bodies[b].inertia += link.inertia().transformed(&self.body_from_link[l]);
        }
    }
}
