//! The studies: what the harness computes about the scenes, each over the one simulation
//! loop ([`crate::sweep::simulate()`]) where it runs a scene over time.
//!
//! - [`measurements`]: a cut-block measurement set and the specimen it was taken on;
//! - [`identify`]: E and ν of the cut block from force–displacement data and laser profiles;
//! - [`profiles`]: scanner profiles against the model, in the lab frame and aligned;
//! - [`secant`]: seed 002's own identification (eqs. 4.1, 4.2) beside the FE fit;
//! - [`speed_error`]: run time against error for the abdomen;
//! - [`stability`]: the abdomen's integrators on hard cases;
//! - [`model_orders`]: the shipped configurations in full, hyper-reduced and modal order;
//! - [`cut_speed_error`]: run time against error for the cut block's models;
//! - [`blade_path`]: the cut block's outputs as the blade crosses it, on two meshes;
//! - [`verification`]: the FE core and both scenes against analytical and seed results;
//! - [`findings`]: seed 003's findings on the abdomen at small and finite strain;
//! - [`physiology`]: the abdomen's static response beside published figures;
//! - [`peer`]: the default abdomen's matrices and times for the peer benchmark (scipy, CHOLMOD);
//! - [`fields`]: the displacement fields the reports draw and write for ParaView.

pub mod blade_path;
pub mod cut_speed_error;
pub mod discretization;
pub mod fields;
pub mod findings;
pub mod identify;
pub mod measurements;
pub mod model_orders;
pub mod peer;
pub mod physiology;
pub mod profiles;
pub mod rankings;
pub mod secant;
pub mod speed_error;
pub mod stability;
pub mod verification;
