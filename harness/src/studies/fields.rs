//! The fields the reports draw and write for ParaView: the abdomen under a static press
//! (seed 003 Fig. 5.8/5.9) and the cut block fully cut and pulled.

use anyhow::Result;
use models::scene::abdomen::Abdomen;
use models::scene::cutblock::CutBlock;
use models::scene::Scene;

use super::verification::cutblock::solved;

/// The abdomen on built-in defaults and its static displacement (all dofs) under a pressing
/// force `press` (N/mm).
pub fn abdomen_pressed(press: f64) -> Result<(Abdomen, Vec<f64>)> {
    let mut a = Abdomen::new();
    a.initialize(0.0)?;
    let u = a.static_displacement(press)?;
    Ok((a, u))
}

/// The default cut block with the full-width cut, pulled `pull` mm.
pub fn cutblock_pulled(pull: f64) -> Result<CutBlock> {
    solved(&[], &[], &[("pull", pull), ("scalpel_x", 100.0)])
}
