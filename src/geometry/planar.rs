//! Points and segments in two coordinates of a plane (`[f64; 2]`): the orientation of three
//! points, whether two segments cross, and a point's squared distance from a segment. What the
//! lens's view test (`transport::lens`, in the laser plane) and the layers around a flat pane
//! (`transport::slab_crossing`, in the pane's plane) both ask.

/// (b − a) × (c − a): positive when a, b, c turn counter-clockwise, 0 when collinear.
pub fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether segments a–b and c–d cross (touching counts).
pub fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (d1, d2) = (cross(a, b, c), cross(a, b, d));
    let (d3, d4) = (cross(c, d, a), cross(c, d, b));
    (d1 * d2 <= 0.0) && (d3 * d4 <= 0.0)
}

/// Squared distance from p to the segment a–b (to a when the segment is a point).
pub fn point_segment_dist2(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let ap = [p[0] - a[0], p[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let s = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = [ap[0] - s * ab[0], ap[1] - s * ab[1]];
    d[0] * d[0] + d[1] * d[1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_crossing_and_distance_on_a_unit_square() {
        let (o, x, y, xy) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]);
        assert_eq!(cross(o, x, y), 1.0);
        assert_eq!(cross(o, y, x), -1.0);
        assert_eq!(cross(o, x, [2.0, 0.0]), 0.0);
        assert!(segments_cross(o, xy, x, y));
        assert!(segments_cross(o, x, x, xy), "touching at an end counts");
        assert!(!segments_cross(o, x, y, xy));
        assert_eq!(point_segment_dist2([0.5, 2.0], o, x), 4.0);
        assert_eq!(point_segment_dist2([3.0, 4.0], o, o), 25.0);
        assert_eq!(point_segment_dist2([-3.0, 4.0], o, x), 25.0);
    }
}
