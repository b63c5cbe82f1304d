//! Workspaces: the buffers a computation needs, made once per model and reused by later calls.
//!
//! A one-state call takes a workspace from the model's [`Pool`] and gives it back; each worker of
//! a stacked call takes one for its whole block of states.

use crate::model::PyModel;
use kinetree::dynamics::batch::{DerivativesBatch, DynamicsBatch};
use kinetree::dynamics::{DerivativesData, DynamicsData, JointTerms};
use kinetree::kinematics::batch::KinematicsBatch;
use kinetree::model::Model;
use std::sync::{Mutex, PoisonError};

/// A fresh workspace for `model`: rigid-body dynamics (the joints' damping, friction and armature
/// left out, as in Pinocchio and the contract).
pub(crate) fn new_data(model: &Model) -> DynamicsData {
    DynamicsData::with_joint_terms(model, JointTerms::Ignored)
}

/// A fresh workspace for the analytic derivatives, rigid-body as [`new_data`].
pub(crate) fn new_derivatives_data(model: &Model) -> DerivativesData {
    DerivativesData::with_joint_terms(model, JointTerms::Ignored)
}

/// Workspaces of one kind kept by a model for reuse: a one-state call takes one and gives it
/// back, and each worker of a stacked call takes one for its whole block of states, so calls
/// after the first allocate no workspace.
#[derive(Debug)]
pub(crate) struct Pool<S>(Mutex<Vec<Box<S>>>);

impl<S> Default for Pool<S> {
    fn default() -> Self {
        Self(Mutex::new(Vec::new()))
    }
}

impl<S> Pool<S> {
    /// Runs `f` with a workspace of the pool, made by `fresh` when none is free.
    fn with<R>(&self, fresh: impl FnOnce() -> S, f: impl FnOnce(&mut S) -> R) -> R {
        // Boxed, so that taking and returning a workspace moves a pointer, not the workspace.
        let taken = self.0.lock().unwrap_or_else(PoisonError::into_inner).pop();
        let mut scratch = taken.unwrap_or_else(|| Box::new(fresh()));
        let result = f(&mut scratch);
        self.0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(scratch);
        result
    }
}

/// The workspace a per-state computation needs, and where a model keeps spare ones.
pub(crate) trait Scratch: Send + Sized {
    /// Runs `f` with a workspace for `model` (taken from its pool, or made).
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R;
}

/// Computations that need no workspace (the configuration-space operations).
impl Scratch for () {
    fn with<R>(_: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        f(&mut ())
    }
}

impl Scratch for DynamicsData {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        model.dynamics_pool.with(|| new_data(&model.model), f)
    }
}

impl Scratch for DerivativesData {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        model
            .derivatives_pool
            .with(|| new_derivatives_data(&model.model), f)
    }
}

impl Scratch for DynamicsBatch {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        model.dynamics_batch_pool.with(
            || DynamicsBatch::with_joint_terms(&model.model, JointTerms::Ignored),
            f,
        )
    }
}

impl Scratch for DerivativesBatch {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        model.derivatives_batch_pool.with(
            || DerivativesBatch::with_joint_terms(&model.model, JointTerms::Ignored),
            f,
        )
    }
}

impl Scratch for KinematicsBatch {
    fn with<R>(model: &PyModel, f: impl FnOnce(&mut Self) -> R) -> R {
        model
            .kinematics_batch_pool
            .with(|| KinematicsBatch::new(&model.model), f)
    }
}
