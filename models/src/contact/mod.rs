//! Self-contact search (seed 001 ch. 3): a bottom-up bounding-volume hierarchy built by face
//! clustering ([`bvh`]), the curvature criterion and the adjacency test that prune
//! neighbouring facets, the recursive pair search with cost counters ([`search`]), and the
//! master/slave facet sorting ([`sorting`]). It needs only facets and node positions
//! ([`surface`]), so it serves 3D tetrahedral boundaries (cut flanks included) and 2D
//! boundary segments alike.

pub mod bvh;
pub mod geometry;
pub mod search;
pub mod sorting;
pub mod surface;

pub use bvh::{BvKind, Bvh};
pub use search::{brute_force, Counters, Search};
pub use surface::Surface;
