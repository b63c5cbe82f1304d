//! kinetree facade (placeholder while the layers are built).
pub use kinetree_spatial as spatial;
