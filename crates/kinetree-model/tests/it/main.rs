//! Integration tests of the model layer.

mod reference;
