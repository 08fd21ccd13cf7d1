//! Exact proximity of facets: squared distances between points, segments and triangles
//! (closest-point constructions after Ericson, Real-Time Collision Detection, §5.1), used by
//! the facet-pair test of the search and by the brute-force reference alike.

use nalgebra::Vector3;

type V = Vector3<f64>;

fn v(p: &[f64; 3]) -> V {
    V::from(*p)
}

/// Squared distance from p to the segment ab.
pub fn point_segment2(p: V, a: V, b: V) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + t * ab - p).norm_squared()
}

/// Squared distance between segments p1q1 and p2q2 (Ericson §5.1.9).
pub fn segment_segment2(p1: V, q1: V, p2: V, q2: V) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    let eps = 1e-30;
    let (s, t) = if a <= eps && e <= eps {
        (0.0, 0.0)
    } else if a <= eps {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(&r);
        if e <= eps {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s = if denom > eps {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    (p1 + d1 * s - (p2 + d2 * t)).norm_squared()
}

/// Squared distance from p to the triangle abc (Ericson §5.1.5).
pub fn point_triangle2(p: V, a: V, b: V, c: V) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.norm_squared();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.norm_squared();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)) - p).norm_squared();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.norm_squared();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)) - p).norm_squared();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))) - p).norm_squared();
    }
    let denom = 1.0 / (va + vb + vc);
    (a + ab * (vb * denom) + ac * (vc * denom) - p).norm_squared()
}

/// Whether the segment pq crosses the triangle abc.
pub fn segment_crosses_triangle(p: V, q: V, a: V, b: V, c: V) -> bool {
    let n = (b - a).cross(&(c - a));
    let (dp, dq) = (n.dot(&(p - a)), n.dot(&(q - a)));
    if dp * dq > 0.0 || (dp == 0.0 && dq == 0.0) {
        return false;
    }
    let x = p + (q - p) * (dp / (dp - dq));
    let inside = |u: V, w: V| n.dot(&(w - u).cross(&(x - u))) >= 0.0;
    inside(a, b) && inside(b, c) && inside(c, a)
}

/// Whether two facets (node positions `pa`, `pb`, `arity` 2 or 3) come within `tol`.
pub fn within(pa: &[[f64; 3]; 3], pb: &[[f64; 3]; 3], arity: usize, tol: f64) -> bool {
    let tol2 = tol * tol;
    let (a, b) = (pa.map(|p| v(&p)), pb.map(|p| v(&p)));
    if arity == 2 {
        return segment_segment2(a[0], a[1], b[0], b[1]) <= tol2;
    }
    let edges = [(0, 1), (1, 2), (2, 0)];
    (0..3).any(|i| {
        point_triangle2(a[i], b[0], b[1], b[2]) <= tol2
            || point_triangle2(b[i], a[0], a[1], a[2]) <= tol2
    }) || edges.iter().any(|&(i, j)| {
        edges
            .iter()
            .any(|&(k, l)| segment_segment2(a[i], a[j], b[k], b[l]) <= tol2)
    }) || edges.iter().any(|&(i, j)| {
        segment_crosses_triangle(a[i], a[j], b[0], b[1], b[2])
            || segment_crosses_triangle(b[i], b[j], a[0], a[1], a[2])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_of_simple_configurations() {
        let (a, b, c) = (
            V::new(0.0, 0.0, 0.0),
            V::new(1.0, 0.0, 0.0),
            V::new(0.0, 1.0, 0.0),
        );
        assert!((point_triangle2(V::new(0.2, 0.2, 0.5), a, b, c) - 0.25).abs() < 1e-15);
        assert!((point_triangle2(V::new(2.0, 0.0, 0.0), a, b, c) - 1.0).abs() < 1e-15);
        assert!(
            (segment_segment2(a, b, V::new(0.5, -1.0, 2.0), V::new(0.5, 1.0, 2.0)) - 4.0).abs()
                < 1e-15
        );
        assert!(segment_crosses_triangle(
            V::new(0.2, 0.2, -1.0),
            V::new(0.2, 0.2, 1.0),
            a,
            b,
            c
        ));
        assert!(!segment_crosses_triangle(
            V::new(2.0, 0.2, -1.0),
            V::new(2.0, 0.2, 1.0),
            a,
            b,
            c
        ));
        assert!((point_segment2(V::new(0.5, 1.0, 0.0), a, b) - 1.0).abs() < 1e-15);
    }
}
