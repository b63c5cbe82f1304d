//! The request and response types of a batch evaluation. With the `serde` feature the request
//! types derive `Serialize` and `Deserialize` and the response types `Serialize`, in the JSON
//! shape documented in [`crate::batch`].

use std::collections::BTreeMap;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// One joint's value: a number for a 1-DoF joint, the joint's whole block for a multi-DoF joint
/// (the floating `root_joint`: q = [x, y, z, qx, qy, qz, qw], v/a/tau = [linear; angular]).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize), serde(untagged))]
pub enum JointValue {
    /// One number.
    Scalar(f64),
    /// A block of numbers.
    Block(Vec<f64>),
}

impl JointValue {
    /// The value as a slice (one entry for [`JointValue::Scalar`]).
    #[must_use]
    pub fn as_slice(&self) -> &[f64] {
        match self {
            Self::Scalar(x) => std::slice::from_ref(x),
            Self::Block(x) => x,
        }
    }

    /// A scalar for one entry, a block otherwise.
    #[must_use]
    pub fn from_slice(x: &[f64]) -> Self {
        match x {
            [x] => Self::Scalar(*x),
            _ => Self::Block(x.to_vec()),
        }
    }
}

#[cfg(feature = "serde")]
impl<'de> Deserialize<'de> for JointValue {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = JointValue;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number or an array of numbers")
            }
            fn visit_f64<E>(self, x: f64) -> Result<JointValue, E> {
                Ok(JointValue::Scalar(x))
            }
            #[allow(clippy::cast_precision_loss, reason = "joint values are f64")]
            fn visit_i64<E>(self, x: i64) -> Result<JointValue, E> {
                Ok(JointValue::Scalar(x as f64))
            }
            #[allow(clippy::cast_precision_loss, reason = "joint values are f64")]
            fn visit_u64<E>(self, x: u64) -> Result<JointValue, E> {
                Ok(JointValue::Scalar(x as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<JointValue, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0));
                while let Some(x) = seq.next_element::<f64>()? {
                    out.push(x);
                }
                Ok(JointValue::Block(out))
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// Joint values keyed by joint name.
pub type NamedValues = BTreeMap<String, JointValue>;

/// The inputs of one sample, keyed by joint name. A joint left out of `q` is at its neutral value
/// and of `v`/`a`/`tau` at zero (unless [`BatchOptions::strict`](super::BatchOptions::strict));
/// `q` may be left out altogether. A quantity that needs `v`, `a` or `tau` is computed only when
/// it is given.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct SampleInput {
    /// Configuration values.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub q: Option<NamedValues>,
    /// Velocities.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub v: Option<NamedValues>,
    /// Accelerations.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub a: Option<NamedValues>,
    /// Joint efforts.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub tau: Option<NamedValues>,
}

/// A sample's inputs in the model's order (what [`SampleInput`] resolves to).
#[derive(Clone, Debug, PartialEq)]
pub struct SampleState {
    /// Configuration (length nq).
    pub q: Vec<f64>,
    /// Velocity (length nv), if given.
    pub v: Option<Vec<f64>>,
    /// Acceleration (length nv), if given.
    pub a: Option<Vec<f64>>,
    /// Joint effort (length nv), if given.
    pub tau: Option<Vec<f64>>,
}

/// The result of a batch: the model's layout and one output per sample.
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct BatchOutput {
    /// The model's name, sizes and joint blocks.
    pub model: ModelSummary,
    /// One output per input sample, in order.
    pub samples: Vec<SampleOutput>,
}

/// A model's name, sizes and every moving joint's blocks.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct ModelSummary {
    /// The model's name.
    pub name: String,
    /// Configuration size.
    pub nq: usize,
    /// Velocity size.
    pub nv: usize,
    /// The moving joints, in the model's order.
    pub joints: Vec<JointSummary>,
    /// Collision meshes that were left out (with `skip_missing_meshes`), described.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Vec::is_empty"))]
    pub skipped_meshes: Vec<String>,
}

/// One moving joint's blocks of `q` and `v`.
#[derive(Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct JointSummary {
    /// The joint's name.
    pub name: String,
    /// Its kind (`"revolute"`, `"floating"`, …).
    #[cfg_attr(feature = "serde", serde(rename = "type"))]
    pub kind: &'static str,
    /// First index of its block of `q`.
    pub idx_q: usize,
    /// First index of its block of `v`.
    pub idx_v: usize,
    /// Its number of configuration coordinates.
    pub nq: usize,
    /// Its number of velocity coordinates.
    pub nv: usize,
}

/// A world placement as written in a batch response.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Placement {
    /// Translation (m).
    pub translation: [f64; 3],
    /// Rotation matrix, row-major.
    pub rotation: [[f64; 3]; 3],
}

/// The minimum signed distance between the shapes of two links.
#[cfg(feature = "collision")]
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct PairDistance {
    /// The first link.
    pub link_a: String,
    /// The second link.
    pub link_b: String,
    /// Positive separation or negative penetration (m).
    pub distance: f64,
}

/// What one sample gives.
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct SampleOutput {
    /// World placement (`world_from_link`) of every link, by link name.
    pub link_poses: BTreeMap<String, Placement>,
    /// World placement (`world_from_frame`) of each named frame asked for
    /// ([`BatchOptions::frames`](crate::batch::BatchOptions::frames)), by name.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "BTreeMap::is_empty"))]
    pub frame_poses: BTreeMap<String, Placement>,
    /// LocalWorldAligned Jacobian (6 x nv, rows `[linear; angular]`, columns in the model's `v`
    /// order) of each requested link or frame.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "BTreeMap::is_empty"))]
    pub jacobians: BTreeMap<String, Vec<Vec<f64>>>,
    /// One entry per candidate link pair, when collision was asked for.
    #[cfg(feature = "collision")]
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub collision: Option<Vec<PairDistance>>,
    /// The dynamics quantities, unless turned off.
    #[cfg(feature = "dynamics")]
    #[cfg_attr(feature = "serde", serde(flatten))]
    pub dynamics: Option<DynamicsOutput>,
}

/// The dynamics quantities of one sample: what its inputs allow. A quantity that is undefined
/// for the sample (`aba` with a singular mass matrix) is `Some(None)` (`null` in JSON), with an
/// entry in `errors` saying why.
#[cfg(feature = "dynamics")]
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct DynamicsOutput {
    /// Generalized gravity `g(q)`.
    pub gravity_torque: Vec<f64>,
    /// Mass matrix, `nv` rows of `nv`.
    pub mass_matrix: Vec<Vec<f64>>,
    /// Centre of mass (world frame), `None` when undefined (no moving mass).
    pub com: Option<[f64; 3]>,
    /// Mass of the moving bodies ([`moving_mass`](crate::dynamics::moving_mass)), written as
    /// `total_mass`.
    #[cfg_attr(feature = "serde", serde(rename = "total_mass"))]
    pub moving_mass: f64,
    /// Potential energy (J).
    pub potential_energy: f64,
    /// Nonlinear effects `C(q, v)·v + g(q)`, with `v`.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub nle: Option<Vec<f64>>,
    /// Kinetic energy (J), with `v`.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub kinetic_energy: Option<f64>,
    /// Centroidal momentum `[linear; angular]`, with `v`.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub centroidal_momentum: Option<Option<[f64; 6]>>,
    /// Inverse dynamics `τ(q, v, a)`, with `v` and `a`.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub rnea: Option<Vec<f64>>,
    /// Forward dynamics `q̈(q, v, τ)`, with `v` and `tau`.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub aba: Option<Option<Vec<f64>>>,
    /// The analytic derivatives, when asked for
    /// ([`BatchOptions::derivatives`](crate::batch::BatchOptions::derivatives)).
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub derivatives: Option<DerivativesOutput>,
    /// The joint-space vectors above (`gravity_torque`, `nle`, `rnea`, `aba`) keyed by joint name.
    pub by_joint: BTreeMap<&'static str, NamedValues>,
    /// Why a quantity is undefined.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Vec::is_empty"))]
    pub errors: Vec<QuantityError>,
}

/// The analytic derivatives of one sample (see [`crate::dynamics::derivatives`] for the
/// tangent-space convention): each matrix is `nv` rows of `nv`, rows and columns in the model's
/// `v` order.
#[cfg(feature = "dynamics")]
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct DerivativesOutput {
    /// Of inverse dynamics, with `v` and `a`.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub rnea: Option<RneaDerivativesOutput>,
    /// Of the generalized gravity.
    pub gravity: GravityDerivativesOutput,
    /// Of forward dynamics, with `v` and `tau`; `Some(None)` (`null`) when `M` is singular, with
    /// an `aba_derivatives` entry in the sample's `errors`.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub aba: Option<Option<AbaDerivativesOutput>>,
}

/// The derivatives of `τ = rnea(q, v, a)`.
#[cfg(feature = "dynamics")]
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct RneaDerivativesOutput {
    /// `∂τ/∂q` (tangent space).
    pub dtau_dq: Vec<Vec<f64>>,
    /// `∂τ/∂v`.
    pub dtau_dv: Vec<Vec<f64>>,
    /// `∂τ/∂a = M(q)`.
    pub dtau_da: Vec<Vec<f64>>,
}

/// The derivative of the generalized gravity `g(q)`.
#[cfg(feature = "dynamics")]
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct GravityDerivativesOutput {
    /// `∂g/∂q` (tangent space).
    pub dg_dq: Vec<Vec<f64>>,
}

/// The derivatives of `q̈ = aba(q, v, τ)`.
#[cfg(feature = "dynamics")]
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct AbaDerivativesOutput {
    /// `∂q̈/∂q` (tangent space).
    pub dddq_dq: Vec<Vec<f64>>,
    /// `∂q̈/∂v`.
    pub dddq_dv: Vec<Vec<f64>>,
    /// `∂q̈/∂τ = M(q)⁻¹`.
    pub dddq_dtau: Vec<Vec<f64>>,
}

/// Why one dynamics quantity of a sample is undefined.
#[cfg(feature = "dynamics")]
#[derive(Debug)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct QuantityError {
    /// The quantity (`"com"`, `"centroidal_momentum"`, `"aba"`, `"aba_derivatives"`).
    pub quantity: &'static str,
    /// The dynamics layer's error (written as its message).
    #[cfg_attr(feature = "serde", serde(serialize_with = "display"))]
    pub error: crate::dynamics::DynamicsError,
}

#[cfg(all(feature = "serde", feature = "dynamics"))]
fn display<S: serde::Serializer>(
    e: &crate::dynamics::DynamicsError,
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_str(e)
}
