//! The scene interface (DESIGN.md "One interface, two doors"): a scene is built from a
//! configuration, exposes a table of variables, accepts `set`/`get`, and advances with
//! `do_step(t, h)`. The FMU layer and the harness drive every scene through this trait only;
//! `modelDescription.xml` is generated from the same table.

pub mod abdomen;
pub mod cutblock;
mod error;
mod inert;
mod state;
mod variables;

pub use error::{ErrorKind, SceneError};
pub use inert::Inert;
pub use state::SceneState;
pub use variables::{
    outputs, Causality, Start, Values, ValuesState, Variability, Variable, VariableKind,
};

/// The scenes by name (the FMI model identifiers): `abdomen` and `cutblock`.
pub const SCENES: [&str; 2] = ["abdomen", "cutblock"];

/// A file compiled in (shipped configurations, experiments, measurement sets): its text by
/// name from `table`, or the names the table has, comma-separated.
pub fn shipped(table: &[(&'static str, &'static str)], name: &str) -> Result<&'static str, String> {
    table
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, text)| *text)
        .ok_or_else(|| {
            let names: Vec<&str> = table.iter().map(|(n, _)| *n).collect();
            names.join(", ")
        })
}

/// The one-line description of a scene (the FMUs' `description`), by name.
pub fn description(name: &str) -> Result<&'static str, SceneError> {
    match name {
        "abdomen" => Ok(abdomen::DESCRIPTION),
        "cutblock" => Ok(cutblock::DESCRIPTION),
        _ => Err(unknown(name)),
    }
}

fn unknown(name: &str) -> SceneError {
    SceneError::Config(format!(
        "unknown scene `{name}` (known: {})",
        SCENES.join(", ")
    ))
}

/// A new scene with default parameters, by name.
pub fn create(name: &str) -> Result<Box<dyn Scene>, SceneError> {
    match name {
        "abdomen" => Ok(Box::new(abdomen::Abdomen::new())),
        "cutblock" => Ok(Box::new(cutblock::CutBlock::new())),
        _ => Err(unknown(name)),
    }
}

/// A parameter outside the variable table from which a scene writes its own configuration
/// file (the abdomen's outline generator: `anatomy.outlet`, …).
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratorParameter {
    /// The parameter's name (`anatomy.<field>`), as the generator takes it.
    pub name: String,
    /// The unit of its value (`mm`, `°`, …).
    pub unit: &'static str,
    /// The smallest value the generator accepts, in the unit.
    pub min: f64,
    /// The largest value the generator accepts, in the unit.
    pub max: f64,
    /// What the parameter is, in words.
    pub description: &'static str,
}

/// A configuration file a scene generated: its text, and the string parameter that takes the
/// file's path.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratedConfiguration {
    /// The name of the string parameter that takes the file's path (`configuration`).
    pub parameter: &'static str,
    /// The file's text (TOML for the abdomen).
    pub text: String,
}

/// A simulation scene. All methods return errors instead of panicking.
pub trait Scene: Send {
    /// The variable table; value references are indices into it.
    fn variables(&self) -> &[Variable];

    /// Sets a real variable (a scalar, or all elements of an array).
    fn set_real(&mut self, vr: u32, values: &[f64]) -> Result<(), SceneError>;

    /// Reads a real variable into `out` (its length must match). Outputs are computed on
    /// first request after a step.
    fn get_real(&mut self, vr: u32, out: &mut [f64]) -> Result<(), SceneError>;

    /// Sets a string parameter.
    fn set_string(&mut self, vr: u32, value: &str) -> Result<(), SceneError>;

    /// Reads a string variable.
    fn get_string(&self, vr: u32) -> Result<String, SceneError>;

    /// Checks that the values set so far describe a model the scene can build — what no
    /// single set can see: values that must fit together (the cut plane inside the block),
    /// a configuration that resolves, a model order the kinematics allow — without building
    /// it (no mesh, no matrix). [`Scene::initialize`] refuses what this refuses, with the
    /// same error, before its work.
    fn check(&self) -> Result<(), SceneError>;

    /// Builds everything the configuration needs (mesh, matrices, factorization) and solves
    /// the initial state at `start_time` (s). Fixed parameters cannot change afterwards.
    fn initialize(&mut self, start_time: f64) -> Result<(), SceneError>;

    /// Advances from `t` to `t + h` with the current inputs. Time-dependent loads follow
    /// the caller's time `t` (the FMI time), whatever the start time.
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), SceneError>;

    /// The scene's state: values and everything a later step depends on (see
    /// [`SceneState`]).
    fn save(&self) -> SceneState;

    /// Puts a state taken by [`Scene::save`] back; the scene then continues bit for bit as
    /// the one it was taken from. A state of another scene or table is refused; on error
    /// the scene is as it was.
    fn restore(&mut self, state: &SceneState) -> Result<(), SceneError>;

    /// Warnings since the last call, each once per run: where an input has taken the
    /// model beyond what it is valid for (strain, mesh resolution). The FMUs log them with
    /// status Warning.
    fn take_warnings(&mut self) -> Vec<String> {
        Vec::new()
    }

    /// The parameters outside the variable table from which this scene can generate its
    /// configuration file; none by default.
    fn generator_parameters(&self) -> Vec<GeneratorParameter> {
        Vec::new()
    }

    /// The configuration file generated from generator-parameter `values` (the others at
    /// their defaults), with a name and a description; errors name the bad parameter.
    fn generate_configuration(
        &self,
        _name: &str,
        _description: &str,
        _values: &[(&str, f64)],
    ) -> Result<GeneratedConfiguration, SceneError> {
        Err(SceneError::Config(
            "this scene has no configuration generator".into(),
        ))
    }

    /// Looks a variable up by name.
    fn lookup(&self, name: &str) -> Result<u32, SceneError> {
        self.variables()
            .iter()
            .find(|v| v.name == name)
            .map(|v| v.vr)
            .ok_or_else(|| SceneError::UnknownName(name.to_string()))
    }
}

/// The default `memory_limit` (MB): a third of a 24 GB machine, leaving room for the
/// importer and a second instance.
pub const DEFAULT_MEMORY_LIMIT_MB: f64 = 8000.0;

/// The largest principal strain a small-strain model (linear law, linear kinematics) is
/// trusted to, 5 %: beyond it a scene warns, once per run, and names the strain.
pub const SMALL_STRAIN_LIMIT: f64 = 0.05;

/// The `memory_limit` parameter every scene has: what a build may claim (see
/// [`crate::budget`]).
fn memory_limit() -> Variable {
    Variable::parameter(
        "memory_limit",
        Variability::Fixed,
        "MB",
        DEFAULT_MEMORY_LIMIT_MB,
        (1.0, 1e7),
        "largest memory the model may claim while it is built (mesh, sparse system, \
         factorizations); a larger model is refused with a message instead of exhausting \
         the host",
    )
}

/// A `memory_limit` value (MB) in bytes.
fn megabytes(mb: f64) -> usize {
    (mb * 1e6) as usize
}

/// Refuses a step from a time `t` that is not finite, or of a size `h` that is not finite
/// and positive.
fn check_step(t: f64, h: f64) -> Result<(), SceneError> {
    if !t.is_finite() {
        return Err(SceneError::InvalidArgument {
            name: "step start time t",
            value: t,
            reason: "must be finite",
        });
    }
    if h.is_finite() && h > 0.0 {
        Ok(())
    } else {
        Err(SceneError::InvalidArgument {
            name: "step size h",
            value: h,
            reason: "must be finite and > 0",
        })
    }
}
