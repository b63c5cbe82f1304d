//! Integration tests of the model layer.

mod errors;
mod mjcf;
mod reference;
mod roots;
mod roundtrip;
mod sdf;
mod tree;
