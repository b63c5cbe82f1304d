//! Obstacle scenes: world obstacles in a JSON file, as `kinetree collide --obstacles` reads them.
//!
//! A scene is `{"obstacles": [{"name": "table", "geometry": {"type": "box", "size": [1, 1,
//! 0.1]}, "xyz": [0.5, 0, 0.3], "rpy": [0, 0, 0]}]}`: each obstacle has a name, a geometry as in
//! kinetree's JSON model format (box, cylinder, sphere, capsule, mesh; SI units) and a world
//! placement given as a translation `xyz` (m) and roll-pitch-yaw angles `rpy` (rad), both zero
//! when left out. Unknown fields are errors.

use crate::{CollisionData, CollisionError, CollisionOptions, ObstacleId};
use kinetree_kinematics::model::Geometry;
use kinetree_kinematics::spatial::Se3;

/// World obstacles read from (or written to) a scene file.
///
/// # Examples
/// ```
/// use kinetree_collision::ObstacleScene;
/// use kinetree_collision::kinematics::model::Geometry;
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let scene = ObstacleScene::from_json_str(
///     r#"{"obstacles": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.2},
///                        "xyz": [5, 0, 0]}]}"#,
/// )?;
/// assert_eq!(scene.obstacles[0].name, "ball");
/// assert_eq!(scene.obstacles[0].geometry, Geometry::Sphere { radius: 0.2 });
/// assert_eq!(scene.obstacles[0].placement().translation.x, 5.0);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleScene {
    /// The obstacles, in file order.
    pub obstacles: Vec<SceneObstacle>,
}

/// One obstacle of an [`ObstacleScene`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneObstacle {
    /// The obstacle's name (reported by the queries).
    pub name: String,
    /// Its shape, as in a model's collision geometry.
    pub geometry: Geometry,
    /// World position of the geometry's origin (m); zero when left out.
    #[serde(default)]
    pub xyz: [f64; 3],
    /// World orientation as roll, pitch, yaw (rad, URDF's convention); zero when left out.
    #[serde(default)]
    pub rpy: [f64; 3],
}

impl SceneObstacle {
    /// The obstacle's placement in the world frame (`world_from_obstacle`).
    #[must_use]
    pub fn placement(&self) -> Se3 {
        Se3::from_xyz_rpy(self.xyz, self.rpy)
    }
}

impl ObstacleScene {
    /// Reads a scene from JSON text.
    ///
    /// # Errors
    /// [`CollisionError::InvalidScene`] with the line and column of malformed JSON, a missing
    /// field or an unknown one.
    pub fn from_json_str(text: &str) -> Result<Self, CollisionError> {
        serde_json::from_str(text).map_err(|e| CollisionError::InvalidScene {
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        })
    }

    /// The scene as pretty-printed JSON, which [`ObstacleScene::from_json_str`] reads back.
    #[must_use]
    pub fn to_json_string(&self) -> String {
        // Plain data with string keys: serialization cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Adds every obstacle to `data` (meshes are found through `options`) and returns their ids
    /// in scene order.
    ///
    /// # Errors
    /// The first failing obstacle's error from [`CollisionData::add_obstacle`] (an invalid
    /// geometry names the obstacle); obstacles before it stay added.
    pub fn add_to(
        &self,
        data: &mut CollisionData,
        options: &CollisionOptions,
    ) -> Result<Vec<ObstacleId>, CollisionError> {
        self.obstacles
            .iter()
            .map(|o| data.add_obstacle(o.name.clone(), &o.geometry, &o.placement(), options))
            .collect()
    }
}
