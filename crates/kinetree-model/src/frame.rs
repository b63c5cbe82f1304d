//! Named frames attached to links (yapCAD's coordinate frames / datums).

use kinetree_spatial::Se3;

/// A named frame rigidly attached to a link: a tool centre point, a mounting face, a sensor.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Unique name among frames (may equal a link name only if it is that link's own frame).
    pub name: String,
    /// Index of the link the frame is attached to.
    pub link: usize,
    /// Pose of the frame in the link frame (`link_from_frame`).
    pub placement: Se3,
    /// Free-text description.
    pub description: Option<String>,
    /// Where the frame came from when it was read from an external datum file:
    /// `(file, datum name)`.
    pub datum: Option<(String, String)>,
}
