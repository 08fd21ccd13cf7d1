//! FMU states (FMI 2 `fmi2GetFMUstate` …, FMI 3 `fmi3GetFMUState` …): what an instance is
//! at one moment — its phase and times and its scene's state
//! ([`models::scene::SceneState`]) — taken, put back into the same or another instance, and
//! serialized to bytes that a new process can read. A restored instance continues bit for
//! bit as the one the state was taken from.
//!
//! The serialized form, all integers little-endian:
//!
//! ```text
//! magic            16 bytes  "tissuefmu state\0"
//! format version    4 bytes  FORMAT
//! model             1 byte n, n bytes: the model identifier (`abdomen`, `cutblock`)
//! token             1 byte n, n bytes: the instantiation token of the build that wrote it
//! payload           8 bytes n, n bytes: postcard encoding of the instance's state
//! checksum          4 bytes  CRC-32 of everything before it
//! ```
//!
//! Bytes that are not a state, of another format version, of another model or another build
//! (the token hashes the variable table and the build), or that fail the checksum are
//! refused with a message saying which.

use std::cell::OnceCell;

use models::scene::SceneState;
use serde::{Deserialize, Serialize};

use crate::exports::Export;
use crate::machine::Phase;

/// The first bytes of every serialized state.
const MAGIC: &[u8; 16] = b"tissuefmu state\0";
/// The version of the serialized form this build writes and reads.
pub const FORMAT: u32 = 1;

/// The instance's part of a state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InstanceState {
    /// Where the instance was in its life cycle.
    pub phase: Phase,
    /// Whether the scene was built with every value set so far (see module `instance`).
    pub built: bool,
    /// Why the initialization failed, if it did.
    pub failure: Option<String>,
    /// The start time of the experiment (s).
    pub start_time: f64,
    /// The stop time the importer defined, if any (s).
    pub stop_time: Option<f64>,
    /// The instance time (s).
    pub time: f64,
}

/// An FMU state: the instance's part, the scene's, and (made on first request) the bytes.
#[derive(Debug)]
pub struct FmuState {
    /// The identifier of the model the state belongs to.
    pub model: &'static str,
    /// The instance's part: phase, build and times.
    pub instance: InstanceState,
    /// The scene's part.
    pub scene: SceneState,
    bytes: OnceCell<Vec<u8>>,
}

impl FmuState {
    /// A state of `model` from its two parts; the bytes are made when first asked for.
    pub fn new(model: &'static str, instance: InstanceState, scene: SceneState) -> Self {
        Self {
            model,
            instance,
            scene,
            bytes: OnceCell::new(),
        }
    }

    /// The serialized form (made once, then kept for the size query and the copy).
    pub fn bytes(&self, model: &Export) -> Result<&[u8], String> {
        if let Some(b) = self.bytes.get() {
            return Ok(b);
        }
        let payload = postcard::to_allocvec(&(&self.instance, &self.scene))
            .map_err(|e| format!("the state could not be serialized: {e}"))?;
        let token = model.token();
        let mut out = Vec::with_capacity(payload.len() + 128);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT.to_le_bytes());
        for field in [model.identifier.as_bytes(), token.as_bytes()] {
            out.push(field.len() as u8);
            out.extend_from_slice(field);
        }
        out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        out.extend_from_slice(&payload);
        out.extend_from_slice(&crc32fast::hash(&out).to_le_bytes());
        Ok(self.bytes.get_or_init(|| out))
    }

    /// Reads serialized bytes for `model`, refusing what is not a state of this model and
    /// build, or is damaged; the message says which.
    pub fn from_bytes(model: &Export, bytes: &[u8]) -> Result<Self, String> {
        let mut r = Reader { bytes, at: 0 };
        if r.take(MAGIC.len()) != Some(&MAGIC[..]) {
            return Err(format!(
                "these {} bytes are not a serialized tissuefmu FMU state",
                bytes.len()
            ));
        }
        let body = bytes.len().checked_sub(4).ok_or("the state is truncated")?;
        let stored = u32::from_le_bytes(bytes[body..].try_into().map_err(|_| "truncated")?);
        if crc32fast::hash(&bytes[..body]) != stored {
            return Err(format!(
                "the serialized state is corrupted: its checksum does not match ({} bytes)",
                bytes.len()
            ));
        }
        let version = u32::from_le_bytes(r.array()?);
        if version != FORMAT {
            return Err(format!(
                "the state is in format version {version}; this build reads version {FORMAT}"
            ));
        }
        let identifier = r.field()?;
        if identifier != model.identifier.as_bytes() {
            return Err(format!(
                "the state is of the `{}` model; this FMU is `{}`",
                String::from_utf8_lossy(identifier),
                model.identifier
            ));
        }
        let token = r.field()?;
        if token != model.token().as_bytes() {
            return Err(format!(
                "the state comes from another build of the `{}` FMU (token {}; this build's is \
                 {}): its variables or code may differ",
                model.identifier,
                String::from_utf8_lossy(token),
                model.token()
            ));
        }
        let n = u64::from_le_bytes(r.array()?) as usize;
        let payload = r.take(n).ok_or("the state is truncated")?;
        if r.at != body {
            return Err("the state has bytes after its payload".into());
        }
        let (instance, scene): (InstanceState, SceneState) = postcard::from_bytes(payload)
            .map_err(|e| format!("the state's payload cannot be read: {e}"))?;
        Ok(Self::new(model.identifier, instance, scene))
    }
}

/// Reads the serialized form front to back.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let out = self.bytes.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(out)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], String> {
        self.take(N)
            .and_then(|b| b.try_into().ok())
            .ok_or_else(|| "the state is truncated".into())
    }

    /// A field of one length byte and that many bytes.
    fn field(&mut self) -> Result<&'a [u8], String> {
        let [n] = self.array::<1>()?;
        self.take(usize::from(n))
            .ok_or_else(|| "the state is truncated".into())
    }
}
