//! Integration tests of the kinematics layer.

mod actuated_ik;
mod allocation;
mod bad_input;
mod codegen;
mod common;
mod dh;
mod finite_differences;
mod frame_id;
mod ik;
mod ik_axes;
mod mimic;
mod reference;
mod yapcad;
