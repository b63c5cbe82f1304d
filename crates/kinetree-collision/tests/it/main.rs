//! Integration tests of the collision layer.

mod allocation;
mod batch;
mod common;
mod degenerate;
mod hand;
mod mesh_primitives;
mod meshes;
mod reference;
mod srdf;
mod tolerance;
mod world;
