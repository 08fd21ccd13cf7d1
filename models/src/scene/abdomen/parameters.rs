//! The abdomen's parameters read into what its build needs: the per-tissue properties and
//! damping, the supports, the reduced model order and the whole-number counts. Each
//! refusal names the parameter and its value.

use super::discretization::{Choice, Discretization, Element};
use super::variables::{
    tissue_vr, DIAPHRAGM_TRANSVERSE_CURVATURE, FLOOR_TRANSVERSE_CURVATURE, KINEMATICS,
    MEMBRANE_LAW, MODEL_ORDER, MODES, PRESS_AMPLITUDE, PRESS_FORCE, PRESS_FREQUENCY, PRESS_LOAD,
    PRESS_MODE, PRESS_MUSCLES, SUBDIVISIONS, TARGET_PRESSURE, TISSUES, TRAINING_FREQUENCY,
    TRAINING_PRESS, WALL_SUPPORT, WALL_TRANSVERSE_CURVATURE,
};
use crate::assembly::plane::{Continuum, PlaneProperties, Truss};
use crate::element::membrane::Law;
use crate::element::Elastic;
use crate::error::ModelError;
use crate::scene::{SceneError, Values};
use crate::solve::{IntegratorKind, Reduction};

/// Per-tissue properties from the current parameter values.
pub fn properties(values: &Values) -> Result<PlaneProperties, SceneError> {
    let v = |tissue: usize, field: u32| values.real(tissue_vr(tissue, field));
    let continuum = Continuum {
        elastic: Elastic::new("cavity", v(0, 0), v(0, 1))?,
        density: v(0, 2),
    };
    let mut trusses: Vec<Truss> = (1..4)
        .map(|t| Truss::new(TISSUES[t], v(t, 0), v(t, 1), v(t, 2)))
        .collect::<Result<_, _>>()?;
    let wall_contracts = wall_contracts(values.string(PRESS_MUSCLES)?)?;
    trusses[0].contracts = true;
    trusses[0].transverse_curvature = values.real(DIAPHRAGM_TRANSVERSE_CURVATURE);
    trusses[1].contracts = wall_contracts;
    trusses[1].transverse_curvature = values.real(WALL_TRANSVERSE_CURVATURE);
    trusses[2].transverse_curvature = values.real(FLOOR_TRANSVERSE_CURVATURE);
    let law = membrane_law(values.string(MEMBRANE_LAW)?)?;
    for truss in &mut trusses {
        truss.law = law;
    }
    Ok(PlaneProperties {
        continua: vec![continuum],
        trusses,
    })
}

/// Properties whose "density" is α_t ρ_t: their mass matrix is the damping matrix.
pub(super) fn damping_properties(values: &Values, props: &PlaneProperties) -> PlaneProperties {
    let alpha = |t: usize| values.real(tissue_vr(t, 3));
    let mut d = props.clone();
    d.continua[0].density *= alpha(0);
    for (i, truss) in d.trusses.iter_mut().enumerate() {
        truss.density *= alpha(i + 1);
    }
    d
}

/// The dofs held fixed: spine and pelvic bone, the abdominal wall when `wall` is `fixed`,
/// and the costal margin (the node where wall and diaphragm meet) when `margin` is.
pub(super) fn supports(
    disc: &Discretization,
    wall: &str,
    margin: &str,
) -> Result<Vec<usize>, SceneError> {
    let mut supported = vec!["spine", "pelvic_bone"];
    match wall {
        "free" => {}
        "fixed" => supported.push("abdominal_wall"),
        other => return Err(wall_error(other)),
    }
    let mut fixed = Vec::new();
    for set in supported {
        fixed.extend(disc.boundary_dofs(set)?);
    }
    match margin {
        "free" => {}
        "fixed" => {
            let sets = disc.mesh().node_sets();
            let wall = sets.get("abdominal_wall")?;
            let diaphragm = sets.get("diaphragm")?;
            fixed.extend(
                diaphragm
                    .iter()
                    .filter(|n| wall.contains(n))
                    .flat_map(|n| [2 * n, 2 * n + 1]),
            );
        }
        other => return Err(margin_error(other)),
    }
    Ok(fixed)
}

/// The error for a `costal_margin` value other than `fixed` or `free`.
pub fn margin_error(value: &str) -> SceneError {
    ModelError::unknown("costal_margin", value, "fixed or free").into()
}

/// A whole-number parameter (`modes`, `mesh_subdivisions`); a fractional value is refused.
fn whole(values: &Values, vr: u32, name: &str, reason: &'static str) -> Result<usize, SceneError> {
    let x = values.real(vr);
    if x.fract() != 0.0 {
        return Err(SceneError::Model(ModelError::InvalidParameter {
            name: name.into(),
            value: x,
            reason,
        }));
    }
    Ok(x as usize)
}

/// The `modes` parameter as a count.
pub(super) fn modes(values: &Values) -> Result<usize, SceneError> {
    whole(
        values,
        MODES,
        "modes",
        "must be a whole number of basis vectors",
    )
}

/// The number of `mesh_subdivisions`, a whole number.
pub(super) fn subdivisions(values: &Values) -> Result<u32, SceneError> {
    let n = whole(
        values,
        SUBDIVISIONS,
        "mesh_subdivisions",
        "must be a whole number of subdivisions",
    )?;
    Ok(n as u32)
}

/// Refuses a `model_order` (`value`, read as `order`) that the kinematics do not allow:
/// the modal bases reduce the linear model, the hyper-reduced model the finite-strain one.
pub fn order_allows(
    value: &str,
    order: Option<ReducedOrder>,
    finite: bool,
) -> Result<(), SceneError> {
    let message = match (order, finite) {
        (Some(ReducedOrder::Modal(_)), true) => format!(
            "model_order = \"{value}\" reduces the linear model: use kinematics = \"linear\" \
             (at finite strain model_order = \"reduced\" is the reduced model)"
        ),
        (Some(ReducedOrder::Hyper), false) => format!(
            "model_order = \"{value}\" is the hyper-reduced finite-strain model: use \
             kinematics = \"finite\" (at linear kinematics model_order = \"modal\" is the \
             reduced model)"
        ),
        _ => return Ok(()),
    };
    Err(SceneError::Config(message))
}

/// A reduced `model_order`: a modal basis of the linear model, or the hyper-reduced
/// finite-strain model trained at initialization (`training`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReducedOrder {
    Modal(Reduction),
    Hyper,
}

/// The reduced order of a `model_order` value: `None` for `full`.
pub fn order(value: &str) -> Result<Option<ReducedOrder>, SceneError> {
    match value {
        "full" => Ok(None),
        "modal" => Ok(Some(ReducedOrder::Modal(Reduction::Ritz))),
        "eigenmodes" => Ok(Some(ReducedOrder::Modal(Reduction::Eigenmodes))),
        "eigenmodes_truncated" => Ok(Some(ReducedOrder::Modal(Reduction::Truncated))),
        "reduced" => Ok(Some(ReducedOrder::Hyper)),
        other => Err(ModelError::unknown(
            "model_order",
            other,
            "full, modal, eigenmodes, eigenmodes_truncated or reduced",
        )
        .into()),
    }
}

/// What drives the press (`press_mode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PressMode {
    /// The pressing force F(t) of `press_force`, `press_amplitude` and `press_frequency`.
    Force,
    /// The contents' mean pressure `target_pressure`: each step finds the force that makes
    /// `cavity_pressure` equal it.
    Pressure,
}

/// Parses the `press_mode` parameter.
pub fn press_mode(value: &str) -> Result<PressMode, SceneError> {
    match value {
        "force" => Ok(PressMode::Force),
        "pressure" => Ok(PressMode::Pressure),
        other => Err(ModelError::unknown("press_mode", other, "force or pressure").into()),
    }
}

/// Parses the `press_muscles` parameter: whether the abdominal wall contracts with the
/// diaphragm.
pub fn wall_contracts(value: &str) -> Result<bool, SceneError> {
    match value {
        "diaphragm" => Ok(false),
        "diaphragm_and_wall" => Ok(true),
        other => {
            let choices = "diaphragm or diaphragm_and_wall";
            Err(ModelError::unknown("press_muscles", other, choices).into())
        }
    }
}

/// How the press loads the diaphragm (`press_load`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PressLoad {
    /// Its active tension: Laplace's law with the pull at its ends.
    Contraction,
    /// Seed 003's: a uniform pressure over it, a dead load.
    Pressure,
}

/// Parses the `press_load` parameter.
pub fn press_load(value: &str) -> Result<PressLoad, SceneError> {
    match value {
        "contraction" => Ok(PressLoad::Contraction),
        "pressure" => Ok(PressLoad::Pressure),
        other => Err(ModelError::unknown("press_load", other, "contraction or pressure").into()),
    }
}

/// Parses the `membrane_law` parameter: the sheets' law in tension.
pub fn membrane_law(value: &str) -> Result<Law, SceneError> {
    match value {
        "hencky" => Ok(Law::Hencky),
        "neo-hookean" => Ok(Law::NeoHookean),
        other => Err(ModelError::unknown("membrane_law", other, "hencky or neo-hookean").into()),
    }
}

/// The press's settings checked together: `press_mode` is known and, for `pressure`, the
/// order full and the integrator implicit (an explicit step's end state does not depend on the load there);
/// `press_muscles` is known and a contracting wall free; `press_load` known and seed 003's
/// pressure at small strain; a transverse curvature on the 6-node element (the seed's
/// 2-node lines have none).
pub fn press(
    values: &Values,
    choice: Choice,
    kind: IntegratorKind,
) -> Result<PressMode, SceneError> {
    let mode = press_mode(values.string(PRESS_MODE)?)?;
    let order = values.string(MODEL_ORDER)?;
    if mode == PressMode::Pressure && order != "full" {
        return Err(SceneError::Config(format!(
            "press_mode = \"pressure\" needs model_order = \"full\" (got `{order}`): the \
             pressure is found on the full model's field"
        )));
    }
    if mode == PressMode::Pressure && !kind.steps_finite_strain() {
        return Err(SceneError::Config(format!(
            "press_mode = \"pressure\" needs an implicit integrator (houbolt or newmark): the \
             state after a {} step does not depend on the press at its end",
            kind.name()
        )));
    }
    let wall_contracts = wall_contracts(values.string(PRESS_MUSCLES)?)?;
    if wall_contracts && values.string(WALL_SUPPORT)? == "fixed" {
        return Err(SceneError::Config(
            "press_muscles = \"diaphragm_and_wall\" needs abdominal_wall = \"free\": a held \
             wall's contraction moves nothing"
                .into(),
        ));
    }
    let load = press_load(values.string(PRESS_LOAD)?)?;
    if load == PressLoad::Pressure && choice.finite {
        return Err(SceneError::Config(
            "press_load = \"pressure\" needs kinematics = \"linear\": a passive diaphragm \
             carrying a pressure at finite strain is an arch in compression and wrinkles"
                .into(),
        ));
    }
    let curved = [
        (
            DIAPHRAGM_TRANSVERSE_CURVATURE,
            "diaphragm_transverse_curvature",
        ),
        (WALL_TRANSVERSE_CURVATURE, "wall_transverse_curvature"),
        (FLOOR_TRANSVERSE_CURVATURE, "floor_transverse_curvature"),
    ]
    .into_iter()
    .find(|&(vr, _)| values.real(vr) != 0.0);
    if let (Some((vr, name)), Element::Tri3) = (curved, choice.element) {
        return Err(SceneError::Config(format!(
            "{name} = {} needs element = \"tri6\" (the seed's 2-node lines are flat across)",
            values.real(vr)
        )));
    }
    Ok(mode)
}

/// The error for an `abdominal_wall` value other than `free` or `fixed`.
pub fn wall_error(value: &str) -> SceneError {
    ModelError::unknown("abdominal_wall", value, "free or fixed").into()
}

/// Why the parameter `vr` cannot act under the present values, if it cannot: the wall's
/// properties (its curvature too) with the wall held (every node of it is), the training
/// range of a model that is not trained, the basis size of the full order, the press of the
/// mode not chosen, the membranes' law at linear kinematics.
pub fn inert(values: &Values, vr: u32) -> Option<&'static str> {
    let wall = (tissue_vr(2, 0)..=tissue_vr(2, 3)).contains(&vr) || vr == WALL_TRANSVERSE_CURVATURE;
    if wall && values.string(WALL_SUPPORT).is_ok_and(|w| w == "fixed") {
        return Some(
            "abdominal_wall = \"fixed\" holds every node of the wall, so its properties act \
             only with abdominal_wall = \"free\"",
        );
    }
    let order = values.string(MODEL_ORDER).unwrap_or("full");
    if (vr == TRAINING_PRESS || vr == TRAINING_FREQUENCY) && order != "reduced" {
        return Some("only the hyper-reduced model (model_order = \"reduced\") is trained");
    }
    if vr == MODES && order == "full" {
        return Some("the full order has no basis: modes acts with a reduced model_order");
    }
    let pressure = values.string(PRESS_MODE).is_ok_and(|m| m == "pressure");
    if vr == TARGET_PRESSURE && !pressure {
        return Some("the press follows press_force and press_amplitude: target_pressure acts with press_mode = \"pressure\"");
    }
    if [PRESS_AMPLITUDE, PRESS_FREQUENCY, PRESS_FORCE].contains(&vr) && pressure {
        return Some("press_mode = \"pressure\" drives the press by target_pressure alone");
    }
    if vr == MEMBRANE_LAW && values.string(KINEMATICS).is_ok_and(|k| k == "linear") {
        return Some("at kinematics = \"linear\" the sheets are linear bars: membrane_law acts at finite kinematics");
    }
    None
}
