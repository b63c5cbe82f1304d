//! Length and angle units of model files. Everything inside kinetree is SI (m, rad); units exist
//! only at the file edges, where [`Units`] converts on load and back on export.

use crate::error::ModelError;

/// A length unit of a JSON file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LengthUnit {
    /// Metres (`"m"`), the SI unit.
    #[default]
    Meter,
    /// Centimetres (`"cm"`).
    Centimeter,
    /// Millimetres (`"mm"`), common in CAD exports.
    Millimeter,
}

impl LengthUnit {
    const KNOWN: &'static str = "m, cm, mm";

    /// The unit's name in files (`"m"`, `"cm"`, `"mm"`).
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Meter => "m",
            Self::Centimeter => "cm",
            Self::Millimeter => "mm",
        }
    }

    /// Parses a unit name (`"m"`, `"cm"`, `"mm"`).
    ///
    /// # Errors
    /// [`ModelError::UnknownUnit`] for any other name.
    pub fn from_name(name: &str) -> Result<Self, ModelError> {
        match name {
            "m" => Ok(Self::Meter),
            "cm" => Ok(Self::Centimeter),
            "mm" => Ok(Self::Millimeter),
            _ => Err(ModelError::UnknownUnit {
                quantity: "length",
                unit: name.to_string(),
                known: Self::KNOWN,
            }),
        }
    }

    /// How many of this unit make one metre (1, 100 or 1000).
    #[must_use]
    pub const fn per_meter(self) -> f64 {
        match self {
            Self::Meter => 1.0,
            Self::Centimeter => 100.0,
            Self::Millimeter => 1000.0,
        }
    }

    pub(crate) fn to_si(self, x: f64) -> f64 {
        x / self.per_meter()
    }

    pub(crate) fn si_to_unit(self, x: f64) -> f64 {
        x * self.per_meter()
    }
}

/// An angle unit of a JSON file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AngleUnit {
    /// Radians (`"rad"`), the SI unit.
    #[default]
    Radian,
    /// Degrees (`"deg"`).
    Degree,
}

impl AngleUnit {
    const KNOWN: &'static str = "rad, deg";

    /// The unit's name in files (`"rad"`, `"deg"`).
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Radian => "rad",
            Self::Degree => "deg",
        }
    }

    /// Parses a unit name (`"rad"`, `"deg"`).
    ///
    /// # Errors
    /// [`ModelError::UnknownUnit`] for any other name.
    pub fn from_name(name: &str) -> Result<Self, ModelError> {
        match name {
            "rad" => Ok(Self::Radian),
            "deg" => Ok(Self::Degree),
            _ => Err(ModelError::UnknownUnit {
                quantity: "angle",
                unit: name.to_string(),
                known: Self::KNOWN,
            }),
        }
    }

    pub(crate) fn to_si(self, x: f64) -> f64 {
        match self {
            Self::Radian => x,
            Self::Degree => x.to_radians(),
        }
    }

    pub(crate) fn si_to_unit(self, x: f64) -> f64 {
        match self {
            Self::Radian => x,
            Self::Degree => x.to_degrees(),
        }
    }
}

/// The length and angle units of a JSON file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Units {
    /// Unit of lengths.
    pub length: LengthUnit,
    /// Unit of angles.
    pub angle: AngleUnit,
}

impl Units {
    /// Metres and radians.
    pub const SI: Self = Self {
        length: LengthUnit::Meter,
        angle: AngleUnit::Radian,
    };

    /// Millimetres and degrees, as CAD tools (yapCAD among them) write.
    pub const MM_DEG: Self = Self {
        length: LengthUnit::Millimeter,
        angle: AngleUnit::Degree,
    };

    pub(crate) fn is_si(self) -> bool {
        self == Self::SI
    }
}
