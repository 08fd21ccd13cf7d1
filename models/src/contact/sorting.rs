//! Master/slave facet sorting (seed 001 §3.6): the facets that take part in contact pairs
//! are grouped into patches — connected regions of the dual graph restricted to contact
//! facets — and every pair is oriented from the patch with the lower number (master) to the
//! other (slave). Patches are numbered by their smallest facet, so the assignment depends only
//! on which facets are in contact, not on the order the search found them: it stays the same
//! from one step to the next while the contact region persists. Cost O(k log k + l) for k
//! contact facets in l pairs.

use super::surface::Surface;

/// A contact pair oriented master → slave, with the patch of each side.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Oriented {
    /// The master facet: the side whose patch (then facet) number is the lower.
    pub master: usize,
    /// The slave facet.
    pub slave: usize,
    /// The master facet's patch, numbered by its smallest facet.
    pub master_patch: usize,
    /// The slave facet's patch, numbered by its smallest facet.
    pub slave_patch: usize,
}

/// Orients `pairs` (facet indices of `surface`).
pub fn sort(surface: &Surface, pairs: &[(usize, usize)]) -> Vec<Oriented> {
    let mut facets: Vec<usize> = pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    facets.sort_unstable();
    facets.dedup();
    let index = |f: usize| facets.binary_search(&f).ok();
    let mut parent: Vec<usize> = (0..facets.len()).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for (i, &f) in facets.iter().enumerate() {
        for &g in &surface.neighbours[f] {
            if let Some(j) = index(g) {
                let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                // The root is the smallest facet of the patch.
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let patch = |p: &mut Vec<usize>, f: usize| facets[find(p, index(f).expect("a contact facet"))];
    let mut out: Vec<Oriented> = pairs
        .iter()
        .map(|&(a, b)| {
            let (pa, pb) = (patch(&mut parent, a), patch(&mut parent, b));
            let flip = (pb, b) < (pa, a);
            let (m, s, pm, ps) = if flip { (b, a, pb, pa) } else { (a, b, pa, pb) };
            Oriented {
                master: m,
                slave: s,
                master_patch: pm,
                slave_patch: ps,
            }
        })
        .collect();
    out.sort_unstable();
    out
}
