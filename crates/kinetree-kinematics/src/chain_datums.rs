//! Re-reading external datum frames into a live [`Chain`].

use crate::chain::Chain;
use crate::error::KinematicsError;
use std::path::Path;

impl Chain {
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
