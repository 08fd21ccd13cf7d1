//! The variable table of a scene and the store of its parameter and input values, with the
//! checks every `set` goes through (kind, length, range, and whether it may change now).

use serde::{Deserialize, Serialize};

use super::SceneError;

/// FMI causality.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    /// A value the importer sets to configure the model (fixed or tunable).
    Parameter,
    /// A value the importer sets between steps while the scene runs (a prescribed load or
    /// displacement).
    Input,
    /// A value the scene computes and the importer reads.
    Output,
}

/// FMI variability.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    /// Set before initialization only.
    Fixed,
    /// Changeable between steps.
    Tunable,
    /// Changes continuously in time (inputs and outputs).
    Continuous,
}

impl Causality {
    /// The name FMI gives it (`causality` attribute).
    pub fn name(self) -> &'static str {
        match self {
            Self::Parameter => "parameter",
            Self::Input => "input",
            Self::Output => "output",
        }
    }
}

impl Variability {
    /// The name FMI gives it (`variability` attribute).
    pub fn name(self) -> &'static str {
        match self {
            Self::Fixed => "fixed",
            Self::Tunable => "tunable",
            Self::Continuous => "continuous",
        }
    }
}

/// Value type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VariableKind {
    /// A real number (`f64`), or an array of them.
    Real,
    /// A string.
    String,
}

/// Start value of a parameter or input.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// The start value of a real variable, in its unit.
    Real(f64),
    /// The start value of a string variable.
    String(String),
    /// Outputs have no start value (FMI: initial = calculated).
    None,
}

/// One row of the variable table.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// The name the variable is set, read and looked up by.
    pub name: String,
    /// Value reference: the index of this row.
    pub vr: u32,
    /// Who sets the value: the importer (parameter, input) or the scene (output).
    pub causality: Causality,
    /// When the value may change: before initialization only, between steps, or in time.
    pub variability: Variability,
    /// The value type: real or string.
    pub kind: VariableKind,
    /// Number of elements (1 for scalars; FMI 3 exposes larger ones as arrays).
    pub len: usize,
    /// The unit of the value (`mm`, `N`, `s`, `MPa`, …; `1` for a count or ratio, empty for
    /// a string).
    pub unit: &'static str,
    /// The value before anything is set, in the unit; none for an output.
    pub start: Start,
    /// The smallest value a set takes, in the unit (−∞ for an output, 0 for a string).
    pub min: f64,
    /// The largest value a set takes, in the unit (+∞ for an output, 0 for a string).
    pub max: f64,
    /// What the variable is, in words (the `description` of `modelDescription.xml`).
    pub description: String,
}

/// The outputs of a variable table, in table order.
pub fn outputs(table: &[Variable]) -> impl Iterator<Item = &Variable> {
    table.iter().filter(|v| v.causality == Causality::Output)
}

impl Variable {
    /// A real scalar parameter.
    pub fn parameter(
        name: &str,
        variability: Variability,
        unit: &'static str,
        start: f64,
        range: (f64, f64),
        description: &str,
    ) -> Self {
        Self::real(
            name,
            Causality::Parameter,
            variability,
            unit,
            Start::Real(start),
            range,
            description,
        )
    }

    /// A real scalar input.
    pub fn input(
        name: &str,
        unit: &'static str,
        start: f64,
        range: (f64, f64),
        description: &str,
    ) -> Self {
        Self::real(
            name,
            Causality::Input,
            Variability::Continuous,
            unit,
            Start::Real(start),
            range,
            description,
        )
    }

    /// A real output of `len` elements.
    pub fn output(name: &str, unit: &'static str, len: usize, description: &str) -> Self {
        let mut v = Self::real(
            name,
            Causality::Output,
            Variability::Continuous,
            unit,
            Start::None,
            (f64::NEG_INFINITY, f64::INFINITY),
            description,
        );
        v.len = len;
        v
    }

    /// A fixed string parameter.
    pub fn string(name: &str, start: &str, description: &str) -> Self {
        Self {
            kind: VariableKind::String,
            start: Start::String(start.to_string()),
            ..Self::real(
                name,
                Causality::Parameter,
                Variability::Fixed,
                "",
                Start::None,
                (0.0, 0.0),
                description,
            )
        }
    }

    fn real(
        name: &str,
        causality: Causality,
        variability: Variability,
        unit: &'static str,
        start: Start,
        (min, max): (f64, f64),
        description: &str,
    ) -> Self {
        Self {
            name: name.to_string(),
            vr: 0,
            causality,
            variability,
            kind: VariableKind::Real,
            len: 1,
            unit,
            start,
            min,
            max,
            description: description.to_string(),
        }
    }
}

/// The values of a [`Values`] and whether they are frozen, as a checkpoint holds them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ValuesState {
    reals: Vec<f64>,
    strings: Vec<String>,
    initialized: bool,
}

/// The current values of a scene's parameters and inputs, indexed by value reference.
#[derive(Debug, Clone)]
pub struct Values {
    table: Vec<Variable>,
    reals: Vec<f64>,
    strings: Vec<String>,
    initialized: bool,
}

impl Values {
    /// Numbers the table (vr = row index) and takes the start values.
    pub fn new(mut table: Vec<Variable>) -> Self {
        for (i, v) in table.iter_mut().enumerate() {
            v.vr = i as u32;
        }
        let reals = table
            .iter()
            .map(|v| {
                if let Start::Real(x) = v.start {
                    x
                } else {
                    f64::NAN
                }
            })
            .collect();
        let strings = table
            .iter()
            .map(|v| {
                if let Start::String(s) = &v.start {
                    s.clone()
                } else {
                    String::new()
                }
            })
            .collect();
        Self {
            table,
            reals,
            strings,
            initialized: false,
        }
    }

    /// The variable table, with each row's value reference numbered.
    pub fn table(&self) -> &[Variable] {
        &self.table
    }

    /// The row of `vr`.
    pub fn variable(&self, vr: u32) -> Result<&Variable, SceneError> {
        self.table
            .get(vr as usize)
            .ok_or(SceneError::UnknownVariable(vr))
    }

    /// The values and whether they are frozen.
    pub fn save(&self) -> ValuesState {
        ValuesState {
            reals: self.reals.clone(),
            strings: self.strings.clone(),
            initialized: self.initialized,
        }
    }

    /// Takes saved values back; a state of another table (other lengths) is refused.
    pub fn restore(&mut self, state: &ValuesState) -> Result<(), SceneError> {
        if state.reals.len() != self.reals.len() || state.strings.len() != self.strings.len() {
            return Err(SceneError::Config(format!(
                "the saved values are for a table of {} variables, this one has {}",
                state.reals.len(),
                self.reals.len()
            )));
        }
        self.reals.clone_from(&state.reals);
        self.strings.clone_from(&state.strings);
        self.initialized = state.initialized;
        Ok(())
    }

    /// Marks the scene initialized: fixed parameters are frozen from now on.
    pub fn freeze(&mut self) {
        self.initialized = true;
    }

    fn settable(&self, v: &Variable, kind: VariableKind) -> Result<(), SceneError> {
        if v.kind != kind {
            return Err(SceneError::WrongKind {
                name: v.name.clone(),
                expected: kind_name(kind),
                actual: kind_name(v.kind),
            });
        }
        if v.causality == Causality::Output {
            return Err(SceneError::NotSettable {
                name: v.name.clone(),
                reason: "it is an output",
            });
        }
        if self.initialized && v.variability == Variability::Fixed {
            return Err(SceneError::NotSettable {
                name: v.name.clone(),
                reason: "fixed parameters can only be set before initialization",
            });
        }
        Ok(())
    }

    /// Sets a real scalar parameter or input after checking kind, state and range.
    pub fn set_real(&mut self, vr: u32, values: &[f64]) -> Result<(), SceneError> {
        let v = self.variable(vr)?;
        self.settable(v, VariableKind::Real)?;
        if values.len() != 1 {
            return Err(SceneError::WrongLength {
                name: v.name.clone(),
                expected: 1,
                got: values.len(),
            });
        }
        let x = values[0];
        if !(x.is_finite() && x >= v.min && x <= v.max) {
            return Err(SceneError::OutOfRange {
                name: v.name.clone(),
                value: x,
                min: v.min,
                max: v.max,
            });
        }
        self.reals[vr as usize] = x;
        Ok(())
    }

    /// Sets a string parameter.
    pub fn set_string(&mut self, vr: u32, value: &str) -> Result<(), SceneError> {
        let v = self.variable(vr)?;
        self.settable(v, VariableKind::String)?;
        self.strings[vr as usize] = value.to_string();
        Ok(())
    }

    /// Reads a parameter or input into `out` (length checked) and returns `true`; returns
    /// `false` for an output, which the scene computes itself.
    pub fn read(&self, vr: u32, out: &mut [f64]) -> Result<bool, SceneError> {
        let v = self.variable(vr)?;
        if out.len() != v.len {
            return Err(SceneError::WrongLength {
                name: v.name.clone(),
                expected: v.len,
                got: out.len(),
            });
        }
        if v.causality == Causality::Output {
            return Ok(false);
        }
        if v.kind != VariableKind::Real {
            return Err(SceneError::WrongKind {
                name: v.name.clone(),
                expected: "real",
                actual: kind_name(v.kind),
            });
        }
        out[0] = self.reals[vr as usize];
        Ok(true)
    }

    /// Current value of a real parameter or input.
    pub fn real(&self, vr: u32) -> f64 {
        self.reals[vr as usize]
    }

    /// Current value of a string parameter.
    pub fn string(&self, vr: u32) -> Result<&str, SceneError> {
        let v = self.variable(vr)?;
        if v.kind != VariableKind::String {
            return Err(SceneError::WrongKind {
                name: v.name.clone(),
                expected: "string",
                actual: kind_name(v.kind),
            });
        }
        Ok(&self.strings[vr as usize])
    }
}

fn kind_name(kind: VariableKind) -> &'static str {
    match kind {
        VariableKind::Real => "real",
        VariableKind::String => "string",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values() -> Values {
        Values::new(vec![
            Variable::parameter(
                "E",
                Variability::Tunable,
                "MPa",
                1.0,
                (1e-9, 1e9),
                "modulus",
            ),
            Variable::parameter("n", Variability::Fixed, "1", 4.0, (1.0, 100.0), "divisions"),
            Variable::output("f", "N", 1, "force"),
            Variable::string("mode", "a", "mode"),
        ])
    }

    #[test]
    fn set_checks_range_kind_state_and_causality() {
        let mut v = values();
        v.set_real(0, &[2.0]).unwrap();
        assert_eq!(v.real(0), 2.0);
        let err = v.set_real(0, &[-1.0]).unwrap_err();
        assert!(err.to_string().contains("`E`"), "{err}");
        assert!(matches!(
            v.set_real(0, &[f64::NAN]),
            Err(SceneError::OutOfRange { .. })
        ));
        assert!(matches!(
            v.set_real(2, &[1.0]),
            Err(SceneError::NotSettable { .. })
        ));
        assert!(matches!(
            v.set_real(3, &[1.0]),
            Err(SceneError::WrongKind { .. })
        ));
        assert!(matches!(
            v.set_real(9, &[1.0]),
            Err(SceneError::UnknownVariable(9))
        ));
        v.freeze();
        assert!(matches!(
            v.set_real(1, &[5.0]),
            Err(SceneError::NotSettable { .. })
        ));
        v.set_real(0, &[3.0]).unwrap();
    }
}
