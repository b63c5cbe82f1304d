//! Joint values stored in model files (kinetree JSON's `position`, yapCAD's `value`) and
//! per-coordinate units of joint values.
//!
//! A model is immutable and carries no state, but CAD files do: a chain is saved at some joint
//! values. [`positions_from_json`] reads them back as a configuration, so that export → import
//! keeps them (the kinematics layer's `Chain::from_file` starts at them).

use crate::error::ModelError;
use crate::joint::JointKind;
use crate::model::Model;
use crate::units::{AngleUnit, LengthUnit, Units};

/// What one coordinate of a joint's configuration or velocity block measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coordinate {
    /// A length (m inside), or a linear rate.
    Length,
    /// An angle (rad inside), or an angular rate.
    Angle,
    /// A unit-free number (a quaternion component).
    Unitless,
}

impl Coordinate {
    /// Converts `x` in `units` to SI.
    #[must_use]
    pub fn to_si(self, x: f64, units: Units) -> f64 {
        match self {
            Self::Length => x / units.length.per_meter(),
            Self::Angle if units.angle == AngleUnit::Degree => x.to_radians(),
            Self::Angle | Self::Unitless => x,
        }
    }

    /// Converts `x` in SI to `units`.
    #[must_use]
    pub fn from_si(self, x: f64, units: Units) -> f64 {
        match self {
            Self::Length => x * units.length.per_meter(),
            Self::Angle if units.angle == AngleUnit::Degree => x.to_degrees(),
            Self::Angle | Self::Unitless => x,
        }
    }
}

impl JointKind {
    /// What each coordinate of the joint's block of `q` measures (see [`JointKind`] for the
    /// layout): a cylindrical joint's `q` is `[Length, Angle]`, a floating joint's is three
    /// lengths and a unit-free quaternion.
    #[must_use]
    pub const fn q_coordinates(self) -> &'static [Coordinate] {
        use Coordinate::{Angle as A, Length as L, Unitless as U};
        match self {
            Self::Fixed => &[],
            Self::Revolute | Self::Continuous => &[A],
            Self::Prismatic => &[L],
            Self::Cylindrical => &[L, A],
            Self::Planar => &[L, L, A],
            Self::Spherical => &[U, U, U, U],
            Self::Floating => &[L, L, L, U, U, U, U],
        }
    }

    /// What each coordinate of the joint's block of `v` (and `a`) measures, as rates.
    #[must_use]
    pub const fn v_coordinates(self) -> &'static [Coordinate] {
        use Coordinate::{Angle as A, Length as L};
        match self {
            Self::Fixed => &[],
            Self::Revolute | Self::Continuous => &[A],
            Self::Prismatic => &[L],
            Self::Cylindrical => &[L, A],
            Self::Planar => &[L, L, A],
            Self::Spherical => &[A, A, A],
            Self::Floating => &[L, L, L, A, A, A],
        }
    }
}

impl Model {
    /// The neutral configuration: zeros, with identity quaternions for spherical and floating
    /// joints.
    #[must_use]
    pub fn neutral_q(&self) -> Vec<f64> {
        let mut q = vec![0.0; self.nq];
        for b in self.bodies.iter().skip(1).filter(|b| b.mimic.is_none()) {
            match b.kind {
                JointKind::Spherical => q[b.idx_q + 3] = 1.0,
                JointKind::Floating => q[b.idx_q + 6] = 1.0,
                _ => {}
            }
        }
        q
    }

    /// Converts a configuration between SI and `units`, coordinate by coordinate
    /// ([`JointKind::q_coordinates`]); `to_si` chooses the direction.
    ///
    /// # Errors
    /// [`ModelError::Length`] when `q.len() != self.nq()`.
    pub fn convert_q(&self, q: &mut [f64], units: Units, to_si: bool) -> Result<(), ModelError> {
        self.convert_block(q, units, to_si, false)
    }

    /// Converts a velocity-space vector (`v`, `a`, a Jacobian column's joint side) between SI
    /// and `units` ([`JointKind::v_coordinates`]).
    ///
    /// # Errors
    /// [`ModelError::Length`] when `v.len() != self.nv()`.
    pub fn convert_v(&self, v: &mut [f64], units: Units, to_si: bool) -> Result<(), ModelError> {
        self.convert_block(v, units, to_si, true)
    }

    fn convert_block(
        &self,
        x: &mut [f64],
        units: Units,
        to_si: bool,
        velocity: bool,
    ) -> Result<(), ModelError> {
        let n = if velocity { self.nv } else { self.nq };
        if x.len() != n {
            return Err(ModelError::Length {
                what: if velocity { "v" } else { "q" },
                expected: n,
                actual: x.len(),
            });
        }
        for b in self.bodies.iter().skip(1).filter(|b| b.mimic.is_none()) {
            let (start, coords) = if velocity {
                (b.idx_v, b.kind.v_coordinates())
            } else {
                (b.idx_q, b.kind.q_coordinates())
            };
            for (k, c) in coords.iter().enumerate() {
                let xi = &mut x[start + k];
                *xi = if to_si {
                    c.to_si(*xi, units)
                } else {
                    c.from_si(*xi, units)
                };
            }
        }
        Ok(())
    }
}

/// The configuration stored in a model file's joint values: kinetree JSON's `position` (in the
/// file's `units`) or yapCAD's `value`; joints without one stay neutral. `model` must be the
/// model read from the same text.
///
/// # Errors
/// [`ModelError::Json`] for malformed JSON or a position with the wrong number of values (naming
/// the joint); [`ModelError::UnknownUnit`] for an unknown unit.
///
/// # Examples
/// ```
/// use kinetree_model::{samples, JsonOptions, Model, Units, state};
/// # fn main() -> Result<(), kinetree_model::ModelError> {
/// let arm = samples::planar_2r(0.3, 0.2);
/// let q = [0.5, -0.25];
/// let json = arm.to_json_string(&JsonOptions { units: Units::MM_DEG, positions: Some(&q),
///                                              ..JsonOptions::default() })?;
/// let back = Model::from_json_str(&json, None)?;
/// let read = state::positions_from_json(&back, &json)?;
/// assert!((read[0] - 0.5).abs() < 1e-15 && (read[1] + 0.25).abs() < 1e-15);
/// # Ok(())
/// # }
/// ```
pub fn positions_from_json(model: &Model, text: &str) -> Result<Vec<f64>, ModelError> {
    let bad = |message: String| ModelError::Json {
        file: None,
        line: 0,
        column: 0,
        message,
    };
    if crate::yapcad::is_yapcad_json(text) {
        return Ok(Model::from_yapcad_str(text)?.q);
    }
    let doc: serde_json::Value = serde_json::from_str(text).map_err(|e| ModelError::Json {
        file: None,
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    let unit = |key: &str| {
        doc.get("units")
            .and_then(|u| u.get(key))
            .and_then(|x| x.as_str())
    };
    let units = Units {
        length: unit("length").map_or(Ok(LengthUnit::Meter), LengthUnit::from_name)?,
        angle: unit("angle").map_or(Ok(AngleUnit::Radian), AngleUnit::from_name)?,
    };
    let mut q = model.neutral_q();
    let joints = doc.get("joints").and_then(|j| j.as_array());
    for jd in joints.into_iter().flatten() {
        let (Some(name), Some(position)) =
            (jd.get("name").and_then(|n| n.as_str()), jd.get("position"))
        else {
            continue;
        };
        // A composite joint's position is its whole block.
        let Some(ji) = model.user_joint_index(name) else {
            continue;
        };
        let range = model.user_joint_q_range(ji);
        if range.is_empty() {
            continue;
        }
        let values: Vec<f64> = match position {
            serde_json::Value::Array(a) => a.iter().filter_map(serde_json::Value::as_f64).collect(),
            x => x.as_f64().into_iter().collect(),
        };
        let kind = model.user_joint_type(ji);
        let coords = model.user_joint_q_coordinates(ji);
        if values.len() != coords.len() {
            return Err(bad(format!(
                "joint '{name}': `position` has {} value(s), this {kind} joint has {}",
                values.len(),
                coords.len()
            )));
        }
        for ((qi, x), c) in q[range].iter_mut().zip(values).zip(coords) {
            *qi = c.to_si(x, units);
        }
    }
    Ok(q)
}
