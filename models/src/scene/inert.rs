//! Parameters that cannot act: a value the present settings make without effect (the
//! abdomen's wall properties with the wall held, the cut block's `max_increment` with the
//! linear law, …) is set without error — FMI allows it — but the scene says so, once per run
//! and parameter, naming the parameter and why. Each scene says which of its parameters
//! cannot act when; this keeps what was said.

use serde::{Deserialize, Serialize};

use super::{Start, Values};

/// The parameters already warned of in this run for having no effect.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Inert {
    warned: Vec<String>,
}

impl Inert {
    /// The warning that variable `vr` of `values` has no effect because of `reason`, if a
    /// reason is given and it was not warned of in this run.
    pub fn check(&mut self, values: &Values, vr: u32, reason: Option<&str>) -> Option<String> {
        let reason = reason?;
        let variable = values.variable(vr).ok()?;
        if self.warned.contains(&variable.name) {
            return None;
        }
        self.warned.push(variable.name.clone());
        let value = match &variable.start {
            Start::String(_) => format!("{:?}", values.string(vr).unwrap_or_default()),
            _ => values.real(vr).to_string(),
        };
        Some(format!(
            "{} = {value} has no effect: {reason}",
            variable.name
        ))
    }

    /// At initialization (a new run, nothing warned yet): the warnings of every parameter
    /// set away from its start value that `inert` says cannot act.
    pub fn check_all(
        &mut self,
        values: &Values,
        inert: impl Fn(&Values, u32) -> Option<&'static str>,
    ) -> Vec<String> {
        self.warned.clear();
        let set: Vec<u32> = values
            .table()
            .iter()
            .filter(|v| match &v.start {
                Start::Real(x) => *x != values.real(v.vr),
                Start::String(s) => values.string(v.vr).is_ok_and(|now| now != s),
                Start::None => false,
            })
            .map(|v| v.vr)
            .collect();
        set.into_iter()
            .filter_map(|vr| self.check(values, vr, inert(values, vr)))
            .collect()
    }
}
