//! Tests of the two scenes through the scene interface: the abdomen (elements, modal and
//! hyper-reduced orders), the cut block (incision, contact of the flanks) and the
//! checkpoints of both, and the cut block's derivatives in ν. One module per file, linked
//! as one binary.

mod abdomen;
mod abdomen_elements;
mod abdomen_modal;
mod abdomen_pressure;
mod abdomen_reduced;
mod checkpoint;
mod cutblock;
mod incision;
mod sensitivity;
