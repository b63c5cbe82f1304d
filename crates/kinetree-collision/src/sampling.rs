//! Proposing link pairs to disable by sampling random configurations, as MoveIt's setup
//! assistant does.

use crate::data::CollisionData;
use crate::error::CollisionError;
use crate::model::CollisionModel;
use crate::query::compute_self_collisions;
use crate::srdf::DisabledPair;
use kinetree_kinematics::model::Model;
use kinetree_kinematics::{KinematicsData, configuration};
use rand::SeedableRng;
use rand::rngs::SmallRng;

/// Settings of [`propose_disabled_pairs`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairSampling {
    /// Number of random configurations (uniform within the joint limits). MoveIt uses 10 000.
    pub samples: usize,
    /// Seed of the random generator (the result is reproducible).
    pub seed: u64,
    /// A pair colliding in at least this fraction of the samples is proposed as
    /// [`DisableReason::Always`] (MoveIt: 0.95).
    pub always_fraction: f64,
}

impl Default for PairSampling {
    fn default() -> Self {
        Self {
            samples: 10_000,
            seed: 0,
            always_fraction: 0.95,
        }
    }
}

/// Why a link pair is proposed for disabling (MoveIt's reasons, minus `Adjacent`: adjacent
/// bodies are never candidates here).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DisableReason {
    /// In collision at the neutral configuration (usually a modelling overlap).
    Default,
    /// In collision in (almost) every sample.
    Always,
    /// In collision in no sample.
    Never,
}

impl DisableReason {
    /// The SRDF spelling: `Default`, `Always`, `Never`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            DisableReason::Default => "Default",
            DisableReason::Always => "Always",
            DisableReason::Never => "Never",
        }
    }
}

impl core::fmt::Display for DisableReason {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A link pair proposed for disabling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairProposal {
    /// Index into [`CollisionModel::link_pairs`].
    pub link_pair: usize,
    /// First link (index into `model.links()`).
    pub link_a: usize,
    /// Second link.
    pub link_b: usize,
    /// Why.
    pub reason: DisableReason,
    /// Fraction of the random samples in which the pair collided.
    pub collision_fraction: f64,
}

impl PairProposal {
    /// The SRDF entry for this proposal.
    #[must_use]
    pub fn to_disabled_pair(&self, model: &Model) -> DisabledPair {
        DisabledPair {
            link1: model.link(self.link_a).name.clone(),
            link2: model.link(self.link_b).name.clone(),
            reason: self.reason.to_string(),
        }
    }
}

/// Proposes link pairs that need no collision checking: those colliding at the neutral
/// configuration ([`DisableReason::Default`]), in at least `settings.always_fraction` of
/// `settings.samples` random configurations ([`DisableReason::Always`]), or in none of them
/// ([`DisableReason::Never`]). Ordered as [`CollisionModel::link_pairs`].
///
/// "Never" is a statistical statement: a pair that collides in a small region of the
/// configuration space may be missed; use enough samples (MoveIt's default is 10 000), and
/// review the list.
///
/// # Errors
/// The errors of the queries; [`CollisionError::Kinematics`] if random sampling fails.
pub fn propose_disabled_pairs(
    model: &Model,
    cmodel: &CollisionModel,
    settings: &PairSampling,
) -> Result<Vec<PairProposal>, CollisionError> {
    let mut kinematics = KinematicsData::new(model);
    let mut data = CollisionData::new(cmodel);
    let nlp = cmodel.link_pairs.len();
    let colliding = |data: &mut CollisionData, hit: &mut [bool]| -> Result<(), CollisionError> {
        hit.fill(false);
        for c in compute_self_collisions(cmodel, data)? {
            if let Some(k) = cmodel.pair_index(c.a, c.b) {
                hit[cmodel.pairs[k].link_pair] = true;
            }
        }
        Ok(())
    };
    let mut hit = vec![false; nlp];
    let mut q = configuration::neutral_configuration(model);
    data.compute_placements(model, cmodel, &mut kinematics, &q)?;
    colliding(&mut data, &mut hit)?;
    let default = hit.clone();
    let mut counts = vec![0usize; nlp];
    let mut rng = SmallRng::seed_from_u64(settings.seed);
    for _ in 0..settings.samples {
        configuration::random_configuration(model, &mut rng, &mut q)?;
        data.compute_placements(model, cmodel, &mut kinematics, &q)?;
        colliding(&mut data, &mut hit)?;
        for (c, h) in counts.iter_mut().zip(&hit) {
            *c += usize::from(*h);
        }
    }
    let mut out = Vec::new();
    for (k, lp) in cmodel.link_pairs.iter().enumerate() {
        let fraction = if settings.samples == 0 {
            0.0
        } else {
            counts[k] as f64 / settings.samples as f64
        };
        let reason = if default[k] {
            DisableReason::Default
        } else if settings.samples == 0 {
            continue;
        } else if fraction >= settings.always_fraction {
            DisableReason::Always
        } else if counts[k] == 0 {
            DisableReason::Never
        } else {
            continue;
        };
        out.push(PairProposal {
            link_pair: k,
            link_a: lp.link_a,
            link_b: lp.link_b,
            reason,
            collision_fraction: fraction,
        });
    }
    Ok(out)
}
