//! Integration tests of the model layer.

mod corpus;
mod errors;
mod reference;
mod roundtrip;
mod tree;
