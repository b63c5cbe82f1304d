//! The facade's error type, wrapping every layer's error.

/// Any error from any kinetree layer, so that `?` works in code that mixes layers.
///
/// Each variant wraps one layer's error unchanged (with `#[from]`); match on it when the layer
/// matters, or just print it: the message is the layer's own.
///
/// # Examples
/// ```
/// # #[cfg(feature = "model")] {
/// use kinetree::model::{Model, RootJoint};
/// fn load(path: &str) -> Result<Model, kinetree::Error> {
///     Ok(Model::from_urdf_file(path, RootJoint::Fixed)?)
/// }
/// let err = load("no/such/robot.urdf").unwrap_err();
/// assert!(matches!(err, kinetree::Error::Model(_)));
/// assert!(err.to_string().contains("no/such/robot.urdf"));
/// # }
/// ```
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Loading or building a model failed.
    #[cfg(feature = "model")]
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
    /// A kinematics algorithm rejected its input.
    #[cfg(feature = "kinematics")]
    #[error(transparent)]
    Kinematics(#[from] crate::kinematics::KinematicsError),
    /// Reachable-workspace sampling rejected its input.
    #[cfg(feature = "workspace")]
    #[error(transparent)]
    Reachable(#[from] crate::workspace::ReachableError),
    /// A sample of a batch ([`crate::batch::evaluate`]) failed: which one, and why (the layer's
    /// error, e.g. [`Error::Kinematics`] for an unknown joint).
    #[cfg(feature = "kinematics")]
    #[error("sample {index}: {source}")]
    Sample {
        /// The sample's index in the request.
        index: usize,
        /// The layer's error.
        #[source]
        source: Box<Error>,
    },
    /// A dynamics algorithm rejected its input.
    #[cfg(feature = "dynamics")]
    #[error(transparent)]
    Dynamics(#[from] crate::dynamics::DynamicsError),
    /// Building a collision model or a collision query failed.
    #[cfg(feature = "collision")]
    #[error(transparent)]
    Collision(#[from] crate::collision::CollisionError),
    // A layer error that wraps the one below (KinematicsError::Model) stays in its own variant:
    // `From` goes by type, so `?` on a KinematicsError gives Error::Kinematics.
}
