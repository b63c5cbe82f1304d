//! Links (parts): inertial data, geometry and metadata, as plain data.

use kinetree_spatial::{Inertia, Se3, Symmetric3};

/// The inertial properties of a link as written in URDF: a frame at the centre of mass, the mass,
/// and the rotational inertia about the centre of mass in that frame's axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertial {
    /// Pose of the inertial frame in the link frame; its origin is the centre of mass.
    pub origin: Se3,
    /// Mass (kg).
    pub mass: f64,
    /// Rotational inertia about the centre of mass, in the inertial frame's axes (kg·m²).
    pub inertia: Symmetric3,
}

impl Inertial {
    /// The spatial inertia expressed in the link frame.
    #[must_use]
    pub fn to_inertia(&self) -> Inertia {
        Inertia::new(
            self.mass,
            self.origin.translation,
            self.inertia.rotate(&self.origin.rotation),
        )
    }
}

/// A geometric shape, in the frame of its visual or collision element.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", tag = "type", deny_unknown_fields)]
pub enum Geometry {
    /// A box centred at the origin with the given full side lengths (m).
    Box {
        /// Side lengths along x, y, z.
        size: [f64; 3],
    },
    /// A cylinder centred at the origin, its axis along z (URDF: `length` is the full length).
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Full length along z (m).
        length: f64,
    },
    /// A sphere centred at the origin.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A capsule along z: a cylinder of the given length capped by two hemispheres.
    Capsule {
        /// Radius (m).
        radius: f64,
        /// Length of the cylindrical part along z (m).
        length: f64,
    },
    /// A triangle mesh in a file, kept as written (`package://…`, relative or absolute path).
    Mesh {
        /// File name or URI as written in the model.
        filename: String,
        /// Scale along x, y, z: finite and non-zero; a negative factor mirrors the mesh (as
        /// `scale="1 -1 1"` for a robot's other arm).
        scale: [f64; 3],
    },
}

/// A visual element of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct Visual {
    /// Optional name.
    pub name: Option<String>,
    /// Pose of the geometry in the link frame.
    pub origin: Se3,
    /// Shape.
    pub geometry: Geometry,
    /// Material name, if any.
    pub material: Option<String>,
    /// Colour as RGBA in [0, 1], if given.
    pub color: Option<[f64; 4]>,
}

/// A collision element of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct Collision {
    /// Optional name.
    pub name: Option<String>,
    /// Pose of the geometry in the link frame.
    pub origin: Se3,
    /// Shape.
    pub geometry: Geometry,
}

/// Descriptive data about a part that the algorithms do not use (yapCAD's part metadata).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkMetadata {
    /// Free-text description.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// Material name (e.g. "PLA", "aluminium").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Display colour RGBA in [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<[f64; 4]>,
    /// Path of a mesh or STL file describing the part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<String>,
    /// Whether the part is meant to be 3D-printed.
    #[serde(default, skip_serializing_if = "core::ops::Not::not")]
    pub printable: bool,
}

/// A rigid link (part) of the model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Link {
    /// Unique name.
    pub name: String,
    /// Inertial properties; `None` means massless.
    pub inertial: Option<Inertial>,
    /// Visual elements.
    pub visuals: Vec<Visual>,
    /// Collision elements.
    pub collisions: Vec<Collision>,
    /// Descriptive metadata.
    pub metadata: LinkMetadata,
}

impl Link {
    /// A massless link with no geometry.
    #[must_use]
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            ..Self::default()
        }
    }

    /// Sets the inertial properties.
    #[must_use]
    pub fn with_inertial(mut self, inertial: Inertial) -> Self {
        self.inertial = Some(inertial);
        self
    }

    /// Sets the inertial properties from mass, centre of mass (in the link frame) and rotational
    /// inertia about the centre of mass (in the link frame's axes).
    #[must_use]
    pub fn with_mass(mut self, mass: f64, com: glam::DVec3, inertia: Symmetric3) -> Self {
        self.inertial = Some(Inertial {
            origin: Se3::from_translation(com),
            mass,
            inertia,
        });
        self
    }

    /// The spatial inertia in the link frame (zero when massless).
    #[must_use]
    pub fn inertia(&self) -> Inertia {
        self.inertial.map_or(Inertia::ZERO, |i| i.to_inertia())
    }
}
