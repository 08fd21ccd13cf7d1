//! The path of equilibria a blade advance starts from: the equilibria of one pattern (the
//! same connectivity and numbering: the front within one cell, [`super::geometry`]'s x
//! planes) at earlier blade positions, and their extrapolation to the new front, a
//! continuation method's predictor (carried onto a new mesh where the advance changes it).

use serde::{Deserialize, Serialize};

/// An equilibrium of a topology of the same pattern at an earlier blade position, under its
/// load (or one carried onto this pattern's mesh from the previous pattern's): a point of
/// the path a blade advance's start is extrapolated along.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Station {
    pub front: f64,
    pub load: (f64, f64),
    pub u: Vec<f64>,
    /// Whether it was carried from another pattern's mesh: kept only until the pattern has
    /// two equilibria of its own.
    pub carried: bool,
}

/// The most equilibria a start is extrapolated from: a quadratic in the blade position.
pub const PATH_POINTS: usize = 3;

/// The start at `front` from the stations of `path` under `load` and the latest equilibrium
/// `latest` (at `latest.front`, under `load`): the extrapolation of the last
/// [`PATH_POINTS`] of them ([`extrapolate`], None where it does not reach; a carried station
/// left out once two are not), and the path the new topology keeps (the last
/// `PATH_POINTS` − 1 of them, `latest` included).
pub fn continue_path(
    path: &[Station],
    latest: Station,
    front: f64,
) -> (Option<Vec<f64>>, Vec<Station>) {
    let mut path: Vec<Station> = path
        .iter()
        .filter(|s| s.load == latest.load)
        .cloned()
        .collect();
    path.push(latest);
    // Two of the pattern's own equilibria extrapolate better than with a carried one
    // through them (along the blade's path: BENCHMARKS.md, "The start of an advance that
    // changes the mesh").
    if path.iter().filter(|s| !s.carried).count() >= 2 {
        path.retain(|s| !s.carried);
    }
    path.drain(..path.len().saturating_sub(PATH_POINTS));
    let points: Vec<(f64, &[f64])> = path.iter().map(|s| (s.front, s.u.as_slice())).collect();
    let start = extrapolate(&points, front);
    path.drain(..path.len().saturating_sub(PATH_POINTS - 1));
    (start, path)
}

/// How far beyond its latest point, in spacings of the latest two, a path is extrapolated.
const REACH: f64 = 2.0;

/// The displacements at blade position `x` extrapolated from equilibria `points` (blade
/// position, displacements) of one pattern, the latest last, by the Lagrange polynomial
/// through them (linear through two, quadratic through three): a continuation method's
/// predictor. Within a cell the x planes slide with the front (the geometry's x planes), so node
/// k lies at an affine function of the blade position and the field around the tip moves
/// with its nodes: each node's displacement is a smooth function of the blade position that
/// the polynomial follows to third order in the step. `None` with fewer than two points, or
/// beyond [`REACH`] spacings of the latest two (steps the samples do not support).
pub fn extrapolate(points: &[(f64, &[f64])], x: f64) -> Option<Vec<f64>> {
    let [.., (before, _), (latest, _)] = points else {
        return None;
    };
    if (x - latest).abs() > REACH * (latest - before).abs() {
        return None;
    }
    let weight = |i: usize| {
        points
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != i)
            .map(|(_, (xj, _))| (x - xj) / (points[i].0 - xj))
            .product::<f64>()
    };
    let mut u = vec![0.0; points[0].1.len()];
    for (i, (_, ui)) in points.iter().enumerate() {
        let w = weight(i);
        for (a, b) in u.iter_mut().zip(ui.iter()) {
            *a += w * b;
        }
    }
    Some(u)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The predictor reproduces a path that is a polynomial of its degree (linear through
    /// two points, quadratic through three, at uneven spacings) and refuses steps beyond
    /// its reach or without two points.
    #[test]
    fn extrapolation_follows_polynomial_paths_within_its_reach() {
        let path = |x: f64| vec![1.0 + 0.5 * x - 0.25 * x * x, -2.0 * x + 0.1 * x * x];
        let (a, b, c) = (path(10.0), path(10.5), path(11.5));
        let quadratic = extrapolate(&[(10.0, &a), (10.5, &b), (11.5, &c)], 13.0).unwrap();
        for (got, want) in quadratic.iter().zip(path(13.0)) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
        let line = |x: f64| vec![3.0 - 0.2 * x];
        let (p, q) = (line(20.0), line(21.0));
        let linear = extrapolate(&[(20.0, &p), (21.0, &q)], 22.5).unwrap();
        assert!((linear[0] - line(22.5)[0]).abs() < 1e-13);
        assert!(extrapolate(&[(20.0, &p), (21.0, &q)], 23.5).is_none());
        assert!(extrapolate(&[(21.0, &q)], 22.0).is_none());
    }

    /// A carried station extrapolates with the pattern's one own equilibrium, and is left
    /// out once there are two: the start is then the line through those.
    #[test]
    fn a_carried_station_serves_until_the_pattern_has_two_of_its_own() {
        let station = |front: f64, u: f64, carried: bool| Station {
            front,
            load: (10.0, 0.0),
            u: vec![u],
            carried,
        };
        let (start, path) =
            continue_path(&[station(1.0, 5.0, true)], station(2.0, 6.0, false), 3.0);
        assert_eq!(start, Some(vec![7.0]));
        assert_eq!(path.len(), 2);
        let (start, path) = continue_path(&path, station(3.0, 8.0, false), 4.0);
        assert_eq!(start, Some(vec![10.0]));
        assert!(path.iter().all(|s| !s.carried));
    }
}
