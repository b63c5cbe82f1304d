//! Integration tests of the dynamics layer.

mod allocation;
mod batch;
mod batch_aba_derivatives;
mod batch_derivatives;
mod common;
mod derivatives;
mod errors;
mod exudyn;
mod identities;
mod kinematics_derivatives;
mod limits;
mod mjcf;
mod reference;
mod sdf;
mod simulation;
