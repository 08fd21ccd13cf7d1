//! The models this library exports: a name (the FMI model identifier), a constructor, and a
//! token (FMI 2 GUID / FMI 3 instantiation token) derived from the variable table, so that
//! an FMU whose description does not match the binary is refused at instantiation.

use models::scene::abdomen::Abdomen;
use models::scene::cutblock::CutBlock;
use models::scene::Scene;

/// One exported model.
#[derive(Debug, Clone, Copy)]
pub struct Model {
    pub identifier: &'static str,
    pub description: &'static str,
    pub create: fn() -> Box<dyn Scene>,
    /// Default experiment: stop time and step size (s).
    pub stop_time: f64,
    pub step_size: f64,
}

/// All exported models.
pub const MODELS: [Model; 2] = [
    Model {
        identifier: "abdomen",
        description: "2D midsagittal FE model of the abdominal cavity: pelvis/spine configuration, per-tissue stiffness, pressing force on the diaphragm, pelvic-floor stress (seed 003 §5.4)",
        create: || Box::new(Abdomen::new()),
        stop_time: 2.0,
        step_size: 1e-3,
    },
    Model {
        identifier: "cutblock",
        description: "3D linear-tetrahedron silicone block with a growing scalpel incision, pulled and pressed; reaction force and laser profiles (seed 002)",
        create: || Box::new(CutBlock::new()),
        stop_time: 1.0,
        step_size: 0.1,
    },
];

impl Model {
    /// The model with this token, if any.
    pub fn by_token(token: &str) -> Option<&'static Model> {
        MODELS.iter().find(|m| m.token() == token)
    }

    /// A deterministic token: FNV-1a over the identifier and every variable's name, kind,
    /// causality, variability and length, formatted like a GUID.
    pub fn token(&self) -> String {
        let scene = (self.create)();
        let mut text = String::from(self.identifier);
        for v in scene.variables() {
            text.push_str(&format!(
                "|{}:{:?}:{:?}:{:?}:{}",
                v.name, v.kind, v.causality, v.variability, v.len
            ));
        }
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
}
