//! Integration tests of the kinematics layer.

mod actuated_ik;
mod allocation;
mod bad_input;
mod common;
mod dh;
mod finite_differences;
mod frame_id;
mod ik;
mod mimic;
mod reachable;
mod reference;
mod yapcad;
