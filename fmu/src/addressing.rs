//! Value references as each FMI version numbers them: FMI 2 one per scalar (an array
//! variable's elements numbered one by one, `name[i]`), FMI 3 one per variable (arrays
//! whole) plus the independent variable `time`. An instance resolves the references of a
//! call to its scene's variables here, and names them as its model description does.

use models::scene::{Causality, Variable};

use crate::exports::Version;

/// One FMI 2 scalar: a scalar variable, or element `index` of an array variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Scalar {
    /// The name in the FMI 2 model description: the variable's name, or `name[i]` for
    /// element `i` of an array variable.
    pub name: String,
    /// The scene's value reference of the variable the scalar belongs to.
    pub scene_vr: u32,
    /// The element within that variable (0 for a scalar variable).
    pub index: usize,
}

/// The FMI 2 scalars of a variable table, in value-reference order.
pub fn fmi2_scalars(vars: &[Variable]) -> Vec<Scalar> {
    vars.iter()
        .flat_map(|v| {
            (0..v.len).map(move |i| Scalar {
                name: if v.len == 1 {
                    v.name.clone()
                } else {
                    format!("{}[{i}]", v.name)
                },
                scene_vr: v.vr,
                index: i,
            })
        })
        .collect()
}

/// FMI 3 value reference of the independent variable `time`.
pub fn time_vr(vars: &[Variable]) -> u32 {
    vars.len() as u32
}

/// A value reference resolved: the scene variable, the first element and the count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Resolved {
    /// The scene variable's value reference; for FMI 3 `time`, [`time_vr`] (one past the
    /// last variable).
    pub vr: u32,
    /// The first element addressed: the element of an FMI 2 scalar, else 0.
    pub index: usize,
    /// The number of values addressed: 1 for an FMI 2 scalar or `time`, the variable's
    /// length for an FMI 3 variable.
    pub len: usize,
}

/// The value references of one FMI version over one variable table.
#[derive(Debug, Clone)]
pub struct Addressing {
    version: Version,
    /// FMI 2's scalars (empty for FMI 3).
    scalars: Vec<Scalar>,
}

impl Addressing {
    /// The references of `version` over the variables `vars`.
    pub fn new(version: Version, vars: &[Variable]) -> Self {
        let scalars = match version {
            Version::Fmi2 => fmi2_scalars(vars),
            Version::Fmi3 => Vec::new(),
        };
        Self { version, scalars }
    }

    /// Resolves references whose value counts add up to `n_values` (refused otherwise).
    pub fn resolve_values(
        &self,
        vars: &[Variable],
        vrs: &[u32],
        n_values: usize,
    ) -> Result<Vec<Resolved>, String> {
        let refs = self.resolve(vars, vrs)?;
        let needed: usize = refs.iter().map(|r| r.len).sum();
        match needed == n_values {
            true => Ok(refs),
            false => Err(format!("{n_values} values given for {needed} expected")),
        }
    }

    /// Resolves references: FMI 2 one scalar each, FMI 3 one variable (or `time`) each.
    pub fn resolve(&self, vars: &[Variable], vrs: &[u32]) -> Result<Vec<Resolved>, String> {
        let time = time_vr(vars);
        vrs.iter()
            .map(|&vr| {
                let resolved = match self.version {
                    Version::Fmi2 => self.scalars.get(vr as usize).map(|s| Resolved {
                        vr: s.scene_vr,
                        index: s.index,
                        len: 1,
                    }),
                    Version::Fmi3 if vr == time => Some(Resolved {
                        vr,
                        index: 0,
                        len: 1,
                    }),
                    Version::Fmi3 => vars.get(vr as usize).map(|v| Resolved {
                        vr,
                        index: 0,
                        len: v.len,
                    }),
                };
                resolved.ok_or_else(|| format!("unknown value reference {vr}"))
            })
            .collect()
    }

    /// The name of a resolved reference as the model description spells it.
    pub fn name_of(&self, vars: &[Variable], r: Resolved) -> String {
        match vars.get(r.vr as usize) {
            Some(v) if v.len > 1 && self.version == Version::Fmi2 => {
                format!("{}[{}]", v.name, r.index)
            }
            Some(v) => v.name.clone(),
            None => "time".into(),
        }
    }

    /// Why a resolved reference cannot be set at all, if it cannot.
    pub fn unsettable(&self, vars: &[Variable], r: Resolved) -> Option<String> {
        let name = self.name_of(vars, r);
        match vars.get(r.vr as usize) {
            None => Some("the independent variable `time` cannot be set".into()),
            Some(v) if v.causality == Causality::Output => {
                Some(format!("`{name}` is an output and cannot be set"))
            }
            _ => None,
        }
    }
}
