//! Named node sets (supports, loaded edges, landmarks), validated against the node count.

use std::collections::BTreeMap;

use crate::error::ModelError;

/// Named lists of node indices, sorted and without duplicates.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NodeSets {
    sets: BTreeMap<String, Vec<usize>>,
}

impl NodeSets {
    /// Adds (or replaces) the set `name`; errors if a node is out of range or the set is empty.
    pub fn insert(
        &mut self,
        name: &str,
        mut nodes: Vec<usize>,
        n_nodes: usize,
    ) -> Result<(), ModelError> {
        if nodes.is_empty() {
            return Err(ModelError::NodeSet {
                name: name.to_string(),
                reason: "is empty".to_string(),
            });
        }
        if let Some(&bad) = nodes.iter().find(|&&n| n >= n_nodes) {
            return Err(ModelError::NodeSet {
                name: name.to_string(),
                reason: format!("node {bad} is out of range (mesh has {n_nodes} nodes)"),
            });
        }
        nodes.sort_unstable();
        nodes.dedup();
        self.sets.insert(name.to_string(), nodes);
        Ok(())
    }

    /// The nodes of set `name`, or an error naming the missing set.
    pub fn get(&self, name: &str) -> Result<&[usize], ModelError> {
        self.sets
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| ModelError::NodeSet {
                name: name.to_string(),
                reason: format!(
                    "no such node set (have: {})",
                    self.sets.keys().cloned().collect::<Vec<_>>().join(", ")
                ),
            })
    }

    /// Iterates over (name, nodes).
    pub fn iter(&self) -> impl Iterator<Item = (&str, &[usize])> {
        self.sets.iter().map(|(k, v)| (k.as_str(), v.as_slice()))
    }
}
