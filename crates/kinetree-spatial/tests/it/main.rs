//! Integration tests of kinetree-spatial: algebraic identities checked on random inputs
//! (proptest, bounded case counts) and the worked numbers of a textbook chapter.

mod explog;
mod inertia;
mod motion;
mod rotation;
mod se3;
mod support;
mod textbook;
