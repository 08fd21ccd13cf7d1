//! The models this library exports: a name (the FMI model identifier), a constructor, and a
//! token (FMI 2 GUID / FMI 3 instantiation token) derived from the variable table, so that
//! an FMU whose description does not match the binary is refused at instantiation.

use models::scene::abdomen::Abdomen;
use models::scene::cutblock::CutBlock;
use models::scene::{Scene, Variable};

/// The FMI versions every model is exported in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Version {
    /// FMI 2.0 co-simulation (`<model>-fmi2.fmu`, the functions of module `fmi2`).
    Fmi2,
    /// FMI 3.0 co-simulation (`<model>-fmi3.fmu`, the functions of module `fmi3`).
    Fmi3,
}

impl Version {
    /// `fmi2` or `fmi3`, as in file and function names.
    pub fn tag(self) -> &'static str {
        match self {
            Version::Fmi2 => "fmi2",
            Version::Fmi3 => "fmi3",
        }
    }
}

/// One exported model.
#[derive(Debug, Clone, Copy)]
pub struct Export {
    /// The model identifier: `modelName` and `modelIdentifier` in the model description,
    /// the name of the binary and of the archive, and the model named in saved FMU states.
    pub identifier: &'static str,
    /// The model description's `description` attribute.
    pub description: &'static str,
    /// A new scene of this model with its defaults, not yet initialized.
    pub create: fn() -> Box<dyn Scene>,
    /// Default experiment: stop time and step size (s).
    pub stop_time: f64,
    /// Default experiment: communication step size (s).
    pub step_size: f64,
}

/// All exported models.
pub const EXPORTS: [Export; 2] = [
    Export {
        identifier: "abdomen",
        description: models::scene::abdomen::DESCRIPTION,
        create: || Box::new(Abdomen::new()),
        stop_time: 2.0,
        step_size: 1e-2,
    },
    Export {
        identifier: "cutblock",
        description: models::scene::cutblock::DESCRIPTION,
        create: || Box::new(CutBlock::new()),
        stop_time: 1.0,
        step_size: 0.1,
    },
];

impl Export {
    /// The model with this token, if any.
    pub fn by_token(token: &str) -> Option<&'static Export> {
        EXPORTS.iter().find(|m| m.token() == token)
    }

    /// The token of this model's variable table in this build.
    pub fn token(&self) -> String {
        token(self.identifier, (self.create)().variables())
    }
}

/// A deterministic token, formatted like a GUID: FNV-1a over the identifier, the build
/// (crate version and commit, see `build.rs`) and every field of every variable (name,
/// reference, causality, variability, kind, length, unit, start, range, description), so
/// that a description from another build or with other start values, ranges or units is
/// refused at instantiation.
pub fn token(identifier: &str, variables: &[Variable]) -> String {
    let text = format!(
        "{identifier}|{}|{}|{variables:?}",
        env!("CARGO_PKG_VERSION"),
        env!("TISSUEFMU_COMMIT")
    );
    let hash = |seed: u64| {
        text.bytes().fold(seed, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        })
    };
    let (a, b) = (hash(0xcbf2_9ce4_8422_2325), hash(0x8422_2325_cbf2_9ce4));
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}
