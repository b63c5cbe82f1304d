//! A [`Chain`] and its files: starting at the joint values a file stores, re-reading external
//! datum frames into a live chain.

use crate::chain::Chain;
use crate::error::KinematicsError;
use kinetree_model::{Model, ModelError, state};
use std::path::Path;

impl Chain {
    /// Loads a model file (URDF, kinetree JSON or a yapCAD export; see
    /// [`Model::from_file`]) and starts at the joint values the file stores (JSON `position`,
    /// yapCAD `value`), neutral for joints without one.
    ///
    /// # Errors
    /// [`KinematicsError::Model`] when the file cannot be read or loaded, or a stored position
    /// has the wrong number of values.
    ///
    /// # Examples
    /// ```
    /// use kinetree_kinematics::Chain;
    /// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"),
    ///                    "/../../tests/data/yapcad/yap_quickstart.yapcad.json");
    /// let chain = Chain::from_file(path)?;
    /// assert!((chain.joint_value_deg("joint1")? - 45.0).abs() < 1e-12);
    /// # Ok(())
    /// # }
    /// ```
    pub fn from_file(path: impl AsRef<Path>) -> Result<Chain, KinematicsError> {
        let path = path.as_ref();
        let model = Model::from_file(path, None)?;
        let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let q = if text.trim_start().starts_with('{') {
            state::positions_from_json(&model, &text)?
        } else {
            model.neutral_q()
        };
        let mut chain = Chain::new(model);
        chain.set_q(&q)?;
        Ok(chain)
    }

    /// Re-reads every frame that came from a datum file (yapCAD's `datum_source`), moving it
    /// and the parts attached to it, and keeps the current configuration. Relative datum paths
    /// are resolved against `base` (the model file's directory; the current directory when
    /// `None`). Returns the number of frames whose pose changed; cached poses are recomputed on
    /// the next query.
    ///
    /// # Errors
    /// [`KinematicsError::Model`] wrapping [`ModelError::Datum`](crate::model::ModelError::Datum)
    /// (naming the frame, the file and the datum) when a file or datum is missing; the chain is
    /// unchanged then.
    pub fn reload_datums(&mut self, base: Option<&Path>) -> Result<usize, KinematicsError> {
        let mut model = self.model().clone();
        let changed = model.reload_datums(base)?;
        if changed > 0 {
            let q = self.q().to_vec();
            let mut fresh = Chain::new(model);
            fresh.set_q(&q)?;
            *self = fresh;
        }
        Ok(changed)
    }
}
