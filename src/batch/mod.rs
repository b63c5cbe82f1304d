//! Batch evaluation of many states: what `kinetree compute` runs, and what the regression suite
//! checks against Pinocchio.
//!
//! The request is a list of [`SampleInput`]s, each a set of joint values keyed by joint name; the
//! response is a [`BatchOutput`]: the model's layout and one [`SampleOutput`] per sample (link
//! placements, requested Jacobians, collision distances, and the dynamics quantities the inputs
//! allow). The library works on these types; JSON lives in the CLI, which (de)serializes them
//! through the `serde` feature.
//!
//! JSON shape (with `serde`): a sample is `{"q": {...}, "v": {...}, "a": {...}, "tau": {...}}`,
//! each map keyed by joint name: a number for 1-DoF joints (continuous joints by angle), an array
//! for multi-DoF joints (the floating `root_joint`: q = [x, y, z, qx, qy, qz, qw], v/a/tau =
//! [linear; angular] in the base frame). A joint left out of `q` is at its neutral value, and of
//! `v`/`a`/`tau` at zero, as everywhere else in kinetree ([`BatchOptions::strict`] requires every
//! joint instead); `q` may be left out altogether. `v`, `a`, `tau` are optional: a quantity that
//! needs one is computed only when it is given.
//!
//! Response: `{"model": {"name", "nq", "nv", "joints": [{"name", "type", "idx_q", "idx_v", "nq",
//! "nv"}]}, "samples": [{"link_poses": {link: {"translation": [3], "rotation": 3x3
//! row-major}}, "frame_poses": {frame: the same, for the frames asked for}, "jacobians": {link:
//! 6 x nv, LocalWorldAligned, columns in the model's v order}, …}]}`.
//!
//! With the `dynamics` feature each sample also gets what its inputs allow: always
//! `gravity_torque`, `mass_matrix` (nv x nv, row-major), `com`, `total_mass` (the moving
//! bodies'), `potential_energy`; with `v`: `nle`, `kinetic_energy`, `centroidal_momentum`; with
//! `v` and `a`: `rnea`; with `v` and `tau`: `aba`. Vectors are in the model's `v` order, and
//! `by_joint` repeats them keyed by joint name. With [`BatchOptions::derivatives`] a sample also
//! gets `derivatives`: `{"gravity": {"dg_dq"}, "rnea": {"dtau_dq", "dtau_dv", "dtau_da"} (with
//! v and a), "aba": {"dddq_dq", "dddq_dv", "dddq_dtau"} (with v and tau)}`, each `nv` rows of
//! `nv` ([`DerivativesOutput`]). A quantity that is undefined for a sample (`aba`
//! with a singular mass matrix) is `null`, with an `errors` entry saying why; the rest of the
//! sample is still computed.
//!
//! # Examples
//! ```
//! use kinetree::batch::{BatchOptions, JointValue, SampleInput, evaluate};
//! use kinetree::model::samples;
//! # fn main() -> Result<(), kinetree::Error> {
//! let model = samples::planar_2r(0.3, 0.2);
//! let first = model.joint(model.moving_joints().next().unwrap_or(0)).name.clone();
//! let sample = SampleInput {
//!     q: Some([(first, JointValue::Scalar(0.5))].into()),
//!     ..SampleInput::default()
//! };
//! let out = evaluate(&model, &[sample], &BatchOptions::default())?;
//! assert_eq!(out.samples.len(), 1);
//! assert_eq!(out.model.nq, 2);
//! # Ok(())
//! # }
//! ```

mod types;

#[cfg(feature = "collision")]
pub use types::PairDistance;
#[cfg(feature = "dynamics")]
pub use types::{
    AbaDerivativesOutput, DerivativesOutput, DynamicsOutput, GravityDerivativesOutput,
    QuantityError, RneaDerivativesOutput,
};
pub use types::{
    BatchOutput, JointSummary, JointValue, ModelSummary, NamedValues, Placement, SampleInput,
    SampleOutput, SampleState,
};

use crate::Error;
use crate::kinematics::configuration::{Space, from_named};
use crate::kinematics::spatial::Motion;
use crate::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_joint_jacobians, frame_jacobian,
    jacobian_to_rows, update_frame_placements,
};
use crate::model::Model;
use std::collections::BTreeMap;

/// Which named frames' world poses a sample reports (`frame_poses`), besides every link's.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum FrameSelection {
    /// None (the default).
    #[default]
    None,
    /// Every named frame of the model, keyed by its name (`link/frame` when two links have a
    /// frame of the same name).
    All,
    /// These frames (or links), keyed as given (`name` or `part/name`).
    Named(Vec<String>),
}

/// What to compute besides link poses.
#[derive(Clone, Debug, Default)]
pub struct BatchOptions {
    /// Links or frames whose LocalWorldAligned Jacobian is reported.
    pub jacobians: Vec<String>,
    /// Named frames whose world pose is reported in `frame_poses`.
    pub frames: FrameSelection,
    /// Skip the dynamics quantities even when the inputs allow them.
    pub no_dynamics: bool,
    /// With the `dynamics` feature, add each sample's analytic [`DerivativesOutput`] (those its
    /// inputs allow); ignored with `no_dynamics`.
    pub derivatives: bool,
    /// Require a value for every moving joint in each given `q`, `v`, `a`, `tau` (and a `q` in
    /// every sample); by default a joint left out is neutral (`q`) or zero.
    pub strict: bool,
    /// Add the joints' damping, friction and armature from the model to the dynamics
    /// ([`JointTerms::FromModel`](crate::dynamics::JointTerms::FromModel)). Off by default: the
    /// rigid-body quantities, as Pinocchio (and its reference data) computes them.
    pub joint_dynamics: bool,
    /// When set, every sample gets `collision`: one [`PairDistance`] per candidate link pair, the
    /// minimum signed distance over their shapes (positive separation, negative penetration),
    /// built with these options.
    #[cfg(feature = "collision")]
    pub collision: Option<crate::collision::CollisionOptions>,
}

/// The model's name, sizes and every moving joint's blocks (a composite joint once, as
/// `"type": "composite"`, with its whole blocks).
#[must_use]
pub fn model_summary(model: &Model) -> ModelSummary {
    let joints = model
        .moving_user_joints()
        .map(|j| {
            let (rq, rv) = (model.user_joint_q_range(j), model.user_joint_v_range(j));
            JointSummary {
                name: model.user_joints()[j].name.clone(),
                kind: model.user_joint_type(j),
                idx_q: rq.start,
                idx_v: rv.start,
                nq: rq.len(),
                nv: rv.len(),
            }
        })
        .collect();
    ModelSummary {
        name: model.name().to_string(),
        nq: model.nq(),
        nv: model.nv(),
        joints,
        skipped_meshes: Vec::new(),
    }
}

/// A sample's named values in the model's order: joints left out are neutral (`q`) or zero
/// (`v`, `a`, `tau`), or with `strict` an error, as is a missing `q`.
///
/// # Errors
/// [`Error::Kinematics`]: an unknown joint, a wrong number of values, a non-finite value, or
/// (with `strict`) a moving joint left out
/// ([`MissingJointValue`](crate::kinematics::KinematicsError::MissingJointValue)).
pub fn resolve_sample(
    model: &Model,
    sample: &SampleInput,
    strict: bool,
) -> Result<SampleState, Error> {
    let vector = |values: Option<&NamedValues>, space| {
        let values = values.into_iter().flatten();
        from_named(model, space, values.map(|(n, x)| (n, x.as_slice())), strict)
    };
    let opt = |values: &Option<NamedValues>| {
        values
            .as_ref()
            .map(|m| vector(Some(m), Space::Velocity))
            .transpose()
    };
    Ok(SampleState {
        q: vector(sample.q.as_ref(), Space::Configuration)?,
        v: opt(&sample.v)?,
        a: opt(&sample.a)?,
        tau: opt(&sample.tau)?,
    })
}

/// Evaluates every sample.
///
/// # Errors
/// [`Error::Sample`] naming the first sample that fails, with the layer's error (unknown joints,
/// wrong value counts; see [`resolve_sample`]); errors of the layers for unknown Jacobian frames
/// or a collision model that cannot be built.
pub fn evaluate(
    model: &Model,
    samples: &[SampleInput],
    options: &BatchOptions,
) -> Result<BatchOutput, Error> {
    let frames: Vec<FrameId> = options
        .jacobians
        .iter()
        .map(|n| FrameId::find(model, n))
        .collect::<Result<_, _>>()?;
    let posed: Vec<(String, FrameId)> = match &options.frames {
        FrameSelection::None => Vec::new(),
        FrameSelection::All => model
            .frames()
            .iter()
            .enumerate()
            .map(|(f, frame)| {
                let shared = model
                    .frames()
                    .iter()
                    .filter(|o| o.name == frame.name)
                    .count()
                    > 1;
                let key = if shared {
                    format!("{}/{}", model.link(frame.link).name, frame.name)
                } else {
                    frame.name.clone()
                };
                (key, FrameId::Frame(f))
            })
            .collect(),
        FrameSelection::Named(names) => names
            .iter()
            .map(|n| Ok((n.clone(), FrameId::find(model, n)?)))
            .collect::<Result<_, Error>>()?,
    };
    let mut data = KinematicsData::new(model);
    let mut jac = vec![Motion::ZERO; model.nv()];
    #[cfg_attr(
        not(feature = "collision"),
        allow(unused_mut, reason = "only the collision feature adds skipped meshes")
    )]
    let mut summary = model_summary(model);
    #[cfg(feature = "collision")]
    let mut collision = match &options.collision {
        Some(o) => {
            let cmodel = crate::collision::CollisionModel::from_model(model, o)?;
            let cdata = crate::collision::CollisionData::new(&cmodel);
            for skipped in cmodel.skipped_meshes() {
                summary.skipped_meshes.push(skipped.to_string());
            }
            Some((cmodel, cdata))
        }
        None => None,
    };
    #[cfg(feature = "dynamics")]
    let mut dynamics_data = crate::dynamics::DynamicsData::with_joint_terms(
        model,
        if options.joint_dynamics {
            crate::dynamics::JointTerms::FromModel
        } else {
            crate::dynamics::JointTerms::Ignored
        },
    );
    #[cfg(feature = "dynamics")]
    let mut derivatives_data = options.derivatives.then(|| {
        crate::dynamics::DerivativesData::with_joint_terms(model, dynamics_data.joint_terms())
    });
    let mut out = Vec::with_capacity(samples.len());
    for (index, sample) in samples.iter().enumerate() {
        let in_sample = |source: Error| Error::Sample {
            index,
            source: Box::new(source),
        };
        let input = resolve_sample(model, sample, options.strict).map_err(in_sample)?;
        compute_joint_jacobians(model, &mut data, &input.q)?;
        let mut link_poses = BTreeMap::new();
        // A composite joint's virtual links are internal: users see its parent and child.
        for (l, link) in model.links().iter().enumerate() {
            if model.is_virtual_link(l) {
                continue;
            }
            let p = data.world_from(FrameId::Link(l))?;
            link_poses.insert(
                link.name.clone(),
                Placement {
                    translation: p.translation.to_array(),
                    rotation: p.rotation_rows(),
                },
            );
        }
        let mut frame_poses = BTreeMap::new();
        if !posed.is_empty() {
            update_frame_placements(model, &mut data)?;
        }
        for (name, frame) in &posed {
            let p = data.world_from(*frame)?;
            frame_poses.insert(
                name.clone(),
                Placement {
                    translation: p.translation.to_array(),
                    rotation: p.rotation_rows(),
                },
            );
        }
        let mut jacobians = BTreeMap::new();
        for (name, frame) in options.jacobians.iter().zip(&frames) {
            let rf = ReferenceFrame::LocalWorldAligned;
            frame_jacobian(model, &data, *frame, rf, &mut jac)?;
            jacobians.insert(name.clone(), jacobian_to_rows(&jac));
        }
        #[cfg(feature = "collision")]
        let collision = match &mut collision {
            Some((cmodel, cdata)) => {
                let pairs = crate::collision::compute_link_pair_distances(
                    model, cmodel, &mut data, cdata, &input.q,
                )
                .map_err(|e| in_sample(e.into()))?;
                Some(
                    pairs
                        .into_iter()
                        .map(|(a, b, distance)| PairDistance {
                            link_a: a.to_string(),
                            link_b: b.to_string(),
                            distance,
                        })
                        .collect(),
                )
            }
            None => None,
        };
        #[cfg(feature = "dynamics")]
        let dynamics = if options.no_dynamics {
            None
        } else {
            Some(
                dynamics::compute(model, &mut dynamics_data, derivatives_data.as_mut(), &input)
                    .map_err(in_sample)?,
            )
        };
        out.push(SampleOutput {
            link_poses,
            frame_poses,
            jacobians,
            #[cfg(feature = "collision")]
            collision,
            #[cfg(feature = "dynamics")]
            dynamics,
        });
    }
    Ok(BatchOutput {
        model: summary,
        samples: out,
    })
}

/// A vector in the model's `v` order keyed by joint name (numbers for 1-DoF joints, blocks for
/// multi-DoF joints).
#[must_use]
pub fn by_joint(model: &Model, x: &[f64]) -> NamedValues {
    model
        .moving_user_joints()
        .map(|j| {
            let value = JointValue::from_slice(&x[model.user_joint_v_range(j)]);
            (model.user_joints()[j].name.clone(), value)
        })
        .collect()
}

#[cfg(feature = "dynamics")]
mod dynamics {
    //! The dynamics quantities of a sample: what the inputs allow (q: gravity, mass matrix, COM;
    //! with v: nle, energy, momentum; with a: rnea; with tau: aba).

    use super::{
        AbaDerivativesOutput, DerivativesOutput, DynamicsOutput, GravityDerivativesOutput,
        QuantityError, RneaDerivativesOutput, SampleState, by_joint,
    };
    use crate::Error;
    use crate::dynamics::{
        DerivativesData, DynamicsData, DynamicsError, aba_derivatives, compute_all_terms,
        generalized_gravity_derivatives, rnea_derivatives,
    };
    use crate::model::Model;
    use std::collections::BTreeMap;

    /// The value, or `None` with the error recorded.
    fn defined<T>(
        errors: &mut Vec<QuantityError>,
        quantity: &'static str,
        r: Result<T, DynamicsError>,
    ) -> Option<T> {
        match r {
            Ok(x) => Some(x),
            Err(error) => {
                errors.push(QuantityError { quantity, error });
                None
            }
        }
    }

    /// An `nv x nv` row-major matrix as `nv` rows.
    fn rows(nv: usize, m: &[f64]) -> Vec<Vec<f64>> {
        m.chunks(nv.max(1)).take(nv).map(<[f64]>::to_vec).collect()
    }

    /// The analytic derivatives the sample's inputs allow: gravity always, inverse dynamics with
    /// `v` and `a`, forward dynamics with `v` and `tau` (`None` with an error when `M` is
    /// singular).
    fn derivatives(
        model: &Model,
        data: &mut DerivativesData,
        input: &SampleState,
        errors: &mut Vec<QuantityError>,
    ) -> Result<DerivativesOutput, Error> {
        let nv = model.nv();
        let q = &input.q;
        let gravity = GravityDerivativesOutput {
            dg_dq: rows(nv, generalized_gravity_derivatives(model, data, q)?),
        };
        let rnea = match (&input.v, &input.a) {
            (Some(v), Some(a)) => {
                let d = rnea_derivatives(model, data, q, v, a)?;
                Some(RneaDerivativesOutput {
                    dtau_dq: rows(nv, d.dtau_dq),
                    dtau_dv: rows(nv, d.dtau_dv),
                    dtau_da: rows(nv, d.dtau_da),
                })
            }
            _ => None,
        };
        let aba = match (&input.v, &input.tau) {
            (Some(v), Some(tau)) => Some(defined(
                errors,
                "aba_derivatives",
                aba_derivatives(model, data, q, v, tau).map(|d| AbaDerivativesOutput {
                    dddq_dq: rows(nv, d.dddq_dq),
                    dddq_dv: rows(nv, d.dddq_dv),
                    dddq_dtau: rows(nv, d.dddq_dtau),
                }),
            )),
            _ => None,
        };
        Ok(DerivativesOutput { rnea, gravity, aba })
    }

    pub(super) fn compute(
        model: &Model,
        data: &mut DynamicsData,
        derivatives_data: Option<&mut DerivativesData>,
        input: &SampleState,
    ) -> Result<DynamicsOutput, Error> {
        let zeros = vec![0.0; model.nv()];
        let v = input.v.as_deref().unwrap_or(&zeros);
        let a = input.a.as_deref().unwrap_or(&zeros);
        let tau = input.tau.as_deref().unwrap_or(&zeros);
        let t = compute_all_terms(model, data, &input.q, v, a, tau)?;
        let nv = model.nv();
        let mut by = BTreeMap::new();
        let mut errors = Vec::new();
        by.insert("gravity_torque", by_joint(model, &t.gravity_torque));
        let com = defined(&mut errors, "com", t.com.map(|c| c.to_array()));
        let with_v = input.v.is_some();
        let centroidal_momentum = with_v.then(|| {
            defined(
                &mut errors,
                "centroidal_momentum",
                t.centroidal_momentum.map(|h| h.to_array()),
            )
        });
        let aba = (with_v && input.tau.is_some()).then(|| defined(&mut errors, "aba", t.aba));
        if with_v {
            by.insert("nle", by_joint(model, &t.nle));
        }
        let rnea = (with_v && input.a.is_some()).then_some(t.rnea);
        if let Some(rnea) = &rnea {
            by.insert("rnea", by_joint(model, rnea));
        }
        if let Some(Some(ddq)) = &aba {
            by.insert("aba", by_joint(model, ddq));
        }
        let mass_matrix = rows(nv, &t.mass_matrix);
        let gravity_torque = t.gravity_torque;
        let nle = with_v.then(|| t.nle.clone());
        let (moving_mass, potential_energy, kinetic_energy) =
            (t.moving_mass, t.potential_energy, t.kinetic_energy);
        let derivatives = match derivatives_data {
            Some(d) => Some(derivatives(model, d, input, &mut errors)?),
            None => None,
        };
        Ok(DynamicsOutput {
            mass_matrix,
            com,
            moving_mass,
            potential_energy,
            nle,
            kinetic_energy: with_v.then_some(kinetic_energy),
            centroidal_momentum,
            rnea,
            aba,
            gravity_torque,
            derivatives,
            by_joint: by,
            errors,
        })
    }
}
