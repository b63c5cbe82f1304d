//! Integration tests of the model layer.

mod errors;
mod reference;
mod roots;
mod roundtrip;
mod tree;
