//! Integration tests of the model layer.

mod corpus;
mod reference;
mod roundtrip;
