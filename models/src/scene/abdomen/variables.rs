//! The abdomen's variable table (value references, names, units, start values, ranges,
//! descriptions) — what `modelDescription.xml` is generated from. The sources of the
//! defaults (tissues from MR and shear-wave elastography and in-vivo measurement, the press
//! from a bear-down pressure, supports from anatomy) are in the repository's
//! docs/theory/abdomen.md, with what is assumed.

use crate::scene::{memory_limit, Variability, Variable};

/// Tissue names as used in variable names: the cavity (triangles) and the three membranes
/// (line regions 0, 1, 2).
pub const TISSUES: [&str; 4] = ["cavity", "diaphragm", "wall", "floor"];

// Value references (indices into the table built by `table`).
pub const CONFIGURATION: u32 = 0;
pub const TARGET_TRIANGLES: u32 = 1;
pub const WALL_SUPPORT: u32 = 2;
pub const INTEGRATOR: u32 = 3;
pub const MAX_STEP: u32 = 4;
pub const MEMORY_LIMIT: u32 = 5;
pub const MODEL_ORDER: u32 = 6;
pub const MODES: u32 = 7;
/// First of the 4 × 4 tissue parameters: E, ν or area, density, damping per tissue.
pub const TISSUE_BASE: u32 = 8;
pub const PRESS_AMPLITUDE: u32 = 24;
pub const PRESS_FREQUENCY: u32 = 25;
pub const PRESS_FORCE: u32 = 26;
pub const FIRST_OUTPUT: u32 = 27;
// Added after the outputs (issue 12), so that the earlier value references stay.
pub const ELEMENT: u32 = 40;
pub const FORMULATION: u32 = 41;
pub const KINEMATICS: u32 = 42;
pub const SUBDIVISIONS: u32 = 43;
pub const GRADING: u32 = 44;
// Added by issue 26.
pub const COSTAL_MARGIN: u32 = 45;
// Added by issue 29.
pub const TRAINING_PRESS: u32 = 46;
pub const TRAINING_FREQUENCY: u32 = 47;
pub const ERROR_INDICATOR: u32 = 48;
// Added by issue 53.
pub const CAVITY_PRESSURE: u32 = 49;
pub const PRESS_MODE: u32 = 50;
pub const TARGET_PRESSURE: u32 = 51;
pub const PRESS_MUSCLES: u32 = 52;
pub const DIAPHRAGM_TRANSVERSE_CURVATURE: u32 = 53;
pub const WALL_TRANSVERSE_CURVATURE: u32 = 54;
pub const FLOOR_TRANSVERSE_CURVATURE: u32 = 55;
pub const MEMBRANE_LAW: u32 = 56;
pub const PRESS_LOAD: u32 = 57;

/// Value reference of field `field` (0 E, 1 ν or area, 2 density, 3 damping) of a tissue.
pub fn tissue_vr(tissue: usize, field: u32) -> u32 {
    TISSUE_BASE + 4 * tissue as u32 + field
}

/// The table, in value-reference order.
pub fn table() -> Vec<Variable> {
    use Variability::{Fixed, Tunable};
    let mut t = vec![
        Variable::string("configuration", "", "pelvis/spine configuration: empty = built-in default, a shipped name (normal, narrow, wide, lordotic, tilted) or a TOML file path"),
        Variable::parameter("target_triangles", Fixed, "1", 750.0, (50.0, 500_000.0), "mesh resolution: approximate number of triangles (before `mesh_subdivisions`)"),
        Variable::string("abdominal_wall", "fixed", "`fixed` (the default: the wall braced, as the contracted abdominal muscles hold it while a person bears down) or `free` (a passive membrane of wall_E; seed 003 offered both)"),
        Variable::string("integrator", "houbolt", "houbolt, newmark, central_difference or rk4"),
        Variable::parameter("max_step", Fixed, "s", 1e-2, (1e-8, 10.0), "largest internal time step; a communication step is split into equal substeps (at most 100000 per communication step); the reduced order's training presses are stepped at it or, where it is coarser, at 1/(20 training_frequency)"),
        memory_limit(),
        Variable::string("model_order", "full", "`full` (every dof); `modal`: `modes` load-dependent Ritz vectors of the pressing load (a Krylov basis holding its static response; within 1 % of full order at the default settings: docs/verification.md in the tissuefmu sources); `eigenmodes`: the lowest `modes` eigenmodes plus the load's static correction; `eigenmodes_truncated`: the eigenmodes alone (these three need kinematics = linear); `reduced`: the hyper-reduced finite-strain model (a POD basis of training states, ECSW-sampled elements; trained up to training_press and training_frequency, warns beyond)"),
        Variable::parameter("modes", Fixed, "1", 80.0, (1.0, 2000.0), "basis vectors of a reduced model order (modal, eigenmodes; for reduced the most its POD may keep)"),
    ];
    let defaults = [(0.005, 0.49), (0.2, 4.0), (0.0225, 20.0), (0.05, 8.0)];
    for (i, name) in TISSUES.iter().enumerate() {
        let (e, second) = defaults[i];
        t.push(Variable::parameter(
            &format!("{name}_E"),
            Tunable,
            "MPa",
            e,
            (1e-9, 1e6),
            &format!(
                "Young's modulus of the {name}{}",
                if i == 2 {
                    " (acts with abdominal_wall = free)"
                } else {
                    ""
                }
            ),
        ));
        t.push(if i == 0 {
            Variable::parameter(
                "cavity_nu",
                Tunable,
                "1",
                second,
                (-0.99, 0.499_999),
                "Poisson's ratio of the cavity contents",
            )
        } else {
            Variable::parameter(
                &format!("{name}_area"),
                Fixed,
                "mm2",
                second,
                (1e-6, 1e4),
                &format!("cross-section of the {name} line elements per mm of depth"),
            )
        });
        t.push(Variable::parameter(
            &format!("{name}_density"),
            Fixed,
            "t/mm3",
            1e-9,
            (1e-15, 1e-6),
            &format!("density of the {name}"),
        ));
        t.push(Variable::parameter(
            &format!("{name}_damping"),
            Fixed,
            "1/s",
            5.0,
            (0.0, 1e6),
            &format!("mass-proportional damping coefficient of the {name}"),
        ));
    }
    t.extend([
        Variable::input(
            "press_amplitude",
            "N/mm",
            0.8,
            (-1e3, 1e3),
            "peak of the press F(t) = press_force + press_amplitude · (1 − cos 2πft)/2 that the contracting diaphragm exerts on the cavity, per mm depth (at finite strain an active tension F/Θ₀ of the diaphragm, Θ₀ its turning between its supports at rest)",
        ),
        Variable::input(
            "press_frequency",
            "Hz",
            0.5,
            (0.0, 1e3),
            "frequency f of the press: one press from rest to its peak and back takes 1/f",
        ),
        Variable::input(
            "press_force",
            "N/mm",
            0.0,
            (-1e3, 1e3),
            "pressing force added to the press, supplied each step by the importer (negative: the diaphragm drawn out of the cavity, a dead load)",
        ),
        Variable::output(
            "floor_stress_mean",
            "MPa",
            1,
            "length-weighted mean axial stress of the pelvic-floor line elements (tension > 0)",
        ),
        Variable::output(
            "floor_stress_max",
            "MPa",
            1,
            "largest axial stress of the pelvic-floor line elements",
        ),
        Variable::output(
            "floor_triangles_vm_mean",
            "MPa",
            1,
            "area-weighted mean von Mises stress of the triangles along the pelvic floor",
        ),
        Variable::output(
            "floor_triangles_vm_max",
            "MPa",
            1,
            "largest von Mises stress of the triangles along the pelvic floor",
        ),
        Variable::output(
            "cavity_vm_mean",
            "MPa",
            1,
            "area-weighted mean von Mises stress of all triangles",
        ),
        Variable::output(
            "cavity_vm_max",
            "MPa",
            1,
            "largest von Mises stress of all triangles",
        ),
        Variable::output(
            "apex_ux",
            "mm",
            1,
            "x-displacement of the diaphragm apex (highest diaphragm node)",
        ),
        Variable::output("apex_uy", "mm", 1, "y-displacement of the diaphragm apex"),
        Variable::output(
            "floor_mid_ux",
            "mm",
            1,
            "x-displacement of the pelvic-floor midpoint",
        ),
        Variable::output(
            "floor_mid_uy",
            "mm",
            1,
            "y-displacement of the pelvic-floor midpoint",
        ),
        Variable::output(
            "wall_mid_ux",
            "mm",
            1,
            "x-displacement of the abdominal-wall midpoint",
        ),
        Variable::output(
            "wall_mid_uy",
            "mm",
            1,
            "y-displacement of the abdominal-wall midpoint",
        ),
        Variable::output(
            "press_total",
            "N/mm",
            1,
            "pressing force applied at the current time",
        ),
        Variable::string("element", "tri6", "cavity element: `tri3` (3-node triangles, 2-node membranes; lock as ν → 0.5) or `tri6` (6-node triangles, 3-node membranes)"),
        Variable::string("formulation", "displacement", "`displacement` or, with tri6, `mixed` (element-wise pressure condensed at element level, P2/P0; at finite strain the three-field form: no locking up to ν = 0.4999)"),
        Variable::string("kinematics", "finite", "`finite` (the default: total Lagrangian, plane-strain neo-Hookean contents in either formulation, membranes at finite strain, the diaphragm contracting; Newton's method in each Houbolt/Newmark step; needs tri6) or `linear` (small strain: the fast opt-in, valid while strains stay below 5 %, which the default press exceeds; modal order needs it)"),
        Variable::parameter("mesh_subdivisions", Fixed, "1", 0.0, (0.0, 4.0), "times every triangle of the mesh of target_triangles is split into four (new boundary nodes on the curve): nested meshes with 4^n times the triangles, for convergence studies"),
        Variable::parameter("mesh_grading", Fixed, "1", 0.5, (0.0, 0.5), "exponent β of the boundary spacing h·(s/R)^β towards the ends of the boundary parts (R = 60 mm), where stresses are singular: 0 uniform; 0.5 gives the 6-node triangle second-order stresses under refinement (Richardson references)"),
        Variable::string("costal_margin", "fixed", "where the abdominal wall meets the diaphragm: `fixed` (the rib cage, to which both attach, held: the default) or `free` (seed 003: the junction moves with the tissues; at finite strain the wall then works as a column in compression and buckles under the press)"),
        Variable::parameter("training_press", Fixed, "N/mm", 1.2, (1e-6, 1e3), "model_order = reduced: the largest total press the hyper-reduced model is trained for (static equilibria from 0 to it — with abdominal_wall = free a slow press to it — and presses to 1/8, 3/8 and all of it at training_frequency); beyond it, or drawn out (negative), the run warns"),
        Variable::parameter("training_frequency", Fixed, "Hz", 5.0, (1e-3, 1e3), "model_order = reduced: the highest press frequency the hyper-reduced model is trained for (its dynamic training presses have this frequency); beyond it the run warns"),
        Variable::output("error_indicator", "1", 1, "error indicator η of the current state: the full model's residual r = f − Mü − Cu̇ − f_int(u) there (a reduced order's coordinates expanded) as the static correction K₀⁻¹r it calls for, relative to the displacement, both in the energy norm of the stiffness at rest K₀ (exactly the relative error of a linear static state); at Newton's tolerance in full order with houbolt or newmark (the explicit integrators' lumped mass shows in it), the reduction's error in a reduced order; infinite where the expanded state inverts an element. Computed only when read: one full-order force evaluation and solve"),
        Variable::output("cavity_pressure", "MPa", 1, "the contents' mean pressure, the model's intra-abdominal pressure: −tr σ/3 of the Cauchy stress at each triangle's centroid (its plane-strain σ_zz included), averaged weighted by the triangles' reference areas; positive in compression"),
        Variable::string("press_mode", "force", "`force` (the press F(t) of press_force, press_amplitude and press_frequency drives the muscles) or `pressure` (each step finds the muscles' active tension that makes cavity_pressure equal target_pressure; needs model_order = full and houbolt or newmark)"),
        Variable::input("target_pressure", "MPa", 0.0, (0.0, 0.05), "press_mode = pressure: the contents' mean pressure (intra-abdominal pressure, as a bladder catheter measures it) that the contracting muscles produce at the end of each communication step (within a step the target runs linearly from the last one met; the muscles can raise the contents' pressure, not lower it, so a target falling faster than the contents recoil is not met: a step ending more than 0.1 kPa above it with the muscles relaxed warns, once per run); the clinical load presets are experiments/clinical_rest, _cough, _valsalva and _bear_down.toml (bearing down 0.0099 MPa, 101 cmH2O)"),
        Variable::string("press_muscles", "diaphragm", "the muscles that contract in a press: `diaphragm` or `diaphragm_and_wall` (the abdominal wall with the same active tension, as in a Valsalva manoeuvre; needs abdominal_wall = free; at linear kinematics the dead load of both tensions)"),
        Variable::parameter("diaphragm_transverse_curvature", Fixed, "1/mm", 0.0, (0.0, 0.02), "curvature of the diaphragm across the slice, from side to side (1/radius, up to a radius of 50 mm, the least measured; needs element = tri6): contracting with tension T it presses on the contents with T times it as well, and passively it resists being drawn out of its dome (Laplace's law of a doubly curved sheet); 0: flat across, the slice's own curvature alone"),
        Variable::parameter("wall_transverse_curvature", Fixed, "1/mm", 0.0, (0.0, 0.01), "curvature of the abdominal wall across the slice, round the waist (1/radius, up to a radius of 100 mm; needs element = tri6): its hoop tension resists bulging, and it presses with its active tension while it contracts (press_muscles = diaphragm_and_wall); acts with abdominal_wall = free"),
        Variable::parameter("floor_transverse_curvature", Fixed, "1/mm", 0.0, (0.0, 0.04), "curvature of the pelvic floor across the slice, the levator bowl from side to side (1/radius, up to a radius of 25 mm; needs element = tri6): its transverse tension holds the contents as a bowl does"),
        Variable::string("membrane_law", "hencky", "the sheets' (diaphragm, wall, floor) law in tension at finite kinematics, slack in compression either way: `hencky` (P = E ln λ / λ: the shipped figures'; its stress peaks at E/e at λ = e, where a pressed floor necks: statically from 9.1 kPa on the normal pelvis in the clinical settings on the default mesh) or `neo-hookean` (the incompressible neo-Hookean sheet in plane strain, P = (E/4)(λ − λ⁻³), the Mooney–Rivlin law of pelvic-floor models reduced to plane strain: it rises without bound, and the pressure press reaches 10 kPa on every shipped configuration)"),
        Variable::string("press_load", "contraction", "how the press loads the diaphragm: `contraction` (its active tension: at small strain the dead load of a unit tension, Laplace's law with the pull at its ends; at finite strain a tension that follows it) or `pressure` (seed 003's press, §5.4.4: a uniform pressure over the diaphragm, normal to it at rest, a dead load of resultant F; needs kinematics = linear — a passive diaphragm pressed at finite strain wrinkles)"),
    ]);
    debug_assert_eq!(t.len(), PRESS_LOAD as usize + 1);
    t
}
