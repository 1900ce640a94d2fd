//! The border of a glass pane given as a triangle mesh (a CAD or Blender part read from glTF):
//! where its top face meets the edge finish, as the same ordered closed [`BorderCurve`] a
//! procedural panel gives (`geometry::panel`), and the part of every triangle (top face,
//! bottom face, edge finish) so that the rough ground-edge model applies to the edge exactly
//! as on a panel.
//!
//! Method:
//! 1. Vertices are welded by exact position (a file repeats a vertex where its normals or
//!    primitives differ: the panel's face/edge seams, glTF primitives of two materials), and
//!    every triangle side must be shared by exactly two triangles wound in opposite directions
//!    (a closed, oriented 2-manifold, which glTF 2.0 §3.7.2.1 asks of a volume: outward
//!    normals, counter-clockwise front faces). Otherwise the mesh is refused: open, non-manifold
//!    or inconsistently wound.
//! 2. The triangles are grouped into smooth patches. By [`EdgeRule::Dihedral`], two neighbours
//!    are in one patch when their normals differ by less than the threshold. By
//!    [`EdgeRule::Marked`] (triangles of a glTF material named like "edge" or marked so in its
//!    `extras`), the unmarked
//!    triangles are grouped by adjacency alone and the marked ones are the edge finish.
//! 3. The top face is the patch of largest area among those whose area-weighted normal points
//!    up (+z of the model frame); the bottom face the largest one pointing down; every other
//!    triangle is the edge finish.
//! 4. The border is the top face's boundary, which must be one simple closed loop (a hole or a
//!    second pane gives several; a mesh that is one smooth patch gives none). It runs in the
//!    winding direction of the top face's triangles, counter-clockwise seen from above as on a
//!    panel, and starts at the boundary vertex that comes first in the mesh (the lowest vertex
//!    index): for a panel written by `scene::gltf_export` that is the panel's own first border
//!    vertex, so a round trip plans the same scan poses.
//!
//! The frame of each border vertex is built as the panel builds it: the surface normal is the
//! top face's shading normal at the vertex (the file's vertex normal, or without normals the
//! angle-weighted mean of the top-face triangles' normals there, Thürmer & Wüthrich 1998), the
//! tangent is the central chord p_{i+1} − p_{i−1} projected into the face's tangent plane
//! (exact on straight sides and on uniformly sampled arcs), outward = tangent × normal.
//!
//! The dihedral rule cannot see a finish that meets the face tangentially (a half-round pencil
//! edge, a fillet sampled in steps below the threshold): such a mesh needs its edge triangles
//! in a material of their own.

use std::collections::HashMap;

use nalgebra::{Point3, Vector3};

use super::border::{BorderCurve, BorderVertex};
use super::mesh::{Mesh, SurfacePart};

/// Default dihedral threshold (deg) between the top face and the edge finish: below the
/// shallowest arris a panel accepts (30°, `geometry::panel::MIN_ARRIS_ANGLE_RAD`, Honda
/// US 6551673's 40–65° widened) and above the largest turn between neighbouring triangles of a
/// sampled arc (10°, the panel's contour and fillet sampling) or of a bent face tessellated at
/// 5 mm on R = 1500 mm (0.19°).
pub const DEFAULT_EDGE_DIHEDRAL_DEG: f64 = 20.0;

/// How the triangles of the edge finish are told from the faces.
#[derive(Clone, Debug, PartialEq)]
pub enum EdgeRule {
    /// Neighbouring triangles whose normals differ by this angle (rad) or more meet at a sharp
    /// crease; the faces are the smooth patches between creases.
    Dihedral {
        /// Threshold (rad), in (0, π).
        threshold_rad: f64,
    },
    /// One flag per triangle: `true` for the edge finish (a material named like "edge").
    Marked(Vec<bool>),
}

/// What [`find_border`] found.
#[derive(Clone, Debug)]
pub struct MeshBorder {
    /// The border curve in the mesh's frame.
    pub border: BorderCurve,
    /// The part of every triangle: `TopFace`, `BottomFace` or `Edge`.
    pub parts: Vec<SurfacePart>,
}

/// Why a mesh has no usable border. Positions are in the mesh's frame, in millimetres.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshBorderError {
    /// A triangle side belongs to one triangle only.
    #[error(
        "the mesh is open: the side from {} to {} mm belongs to 1 triangle, expected a closed \
         mesh (every side shared by exactly 2 triangles)",
        mm(a),
        mm(b)
    )]
    Open {
        /// One end of the side (m).
        a: Point3<f64>,
        /// The other end (m).
        b: Point3<f64>,
    },
    /// A triangle side belongs to three or more triangles.
    #[error(
        "the mesh is not a manifold: the side from {} to {} mm belongs to {count} triangles, \
         expected exactly 2",
        mm(a),
        mm(b)
    )]
    NonManifold {
        /// One end of the side (m).
        a: Point3<f64>,
        /// The other end (m).
        b: Point3<f64>,
        /// How many triangles share it.
        count: usize,
    },
    /// Two triangles run along a shared side in the same direction.
    #[error(
        "the mesh is not consistently wound: the two triangles on the side from {} to {} mm \
         both run from the first point to the second, expected opposite directions \
         (counter-clockwise seen from outside, glTF 2.0 §3.7.2.1)",
        mm(a),
        mm(b)
    )]
    Unoriented {
        /// One end of the side (m).
        a: Point3<f64>,
        /// The other end (m).
        b: Point3<f64>,
    },
    /// No patch faces up.
    #[error(
        "no top face: none of the {patches} smooth patches faces up (+z of the object's frame \
         after `up_axis`), expected the pane's top face"
    )]
    NoTopFace {
        /// Number of patches found.
        patches: usize,
    },
    /// The top face has no boundary: nothing separates it from the rest of the mesh.
    #[error(
        "no border found: the top face is the whole mesh ({patches} smooth patch(es)), \
         expected it to end at an edge finish; the finish may meet it at less than the \
         dihedral threshold ({threshold}), or name its triangles' material like \"edge\""
    )]
    NoBorder {
        /// Number of patches found.
        patches: usize,
        /// The rule's threshold, in words.
        threshold: String,
    },
    /// The top face's boundary is several loops.
    #[error(
        "several borders: the top face's boundary is {count} closed loops ({lengths} mm long), \
         expected one (a hole in the pane or two panes in one file)"
    )]
    SeveralBorders {
        /// Number of loops.
        count: usize,
        /// Their lengths, in words.
        lengths: String,
    },
    /// The top face's boundary passes a vertex more than once.
    #[error(
        "the top face's boundary touches itself at {} mm ({count} boundary sides leave it), \
         expected a simple closed curve",
        mm(at)
    )]
    Pinched {
        /// The vertex (m).
        at: Point3<f64>,
        /// Boundary sides leaving it.
        count: usize,
    },
}

fn mm(p: &Point3<f64>) -> String {
    format!("({:.4}, {:.4}, {:.4})", p.x * 1e3, p.y * 1e3, p.z * 1e3)
}

/// Finds the border of `mesh` (see the module docs).
pub fn find_border(mesh: &Mesh, rule: &EdgeRule) -> Result<MeshBorder, MeshBorderError> {
    let n_tri = mesh.triangles.len();
    // 1. Weld by exact position; -0.0 and 0.0 are one position. The representative of a
    //    position is its lowest vertex index.
    let mut by_position: HashMap<[u64; 3], u32> = HashMap::new();
    let weld: Vec<u32> = (mesh.positions.iter().enumerate())
        .map(|(i, p)| {
            let key = [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits());
            *by_position.entry(key).or_insert(i as u32)
        })
        .collect();
    let tri: Vec<[u32; 3]> = (mesh.triangles.iter())
        .map(|t| t.map(|k| weld[k as usize]))
        .collect();
    // Sides, in a fixed order (sorted), with the triangles on them and their direction.
    let mut sides: Vec<([u32; 2], u32, bool)> = Vec::with_capacity(3 * n_tri);
    for (t, v) in tri.iter().enumerate() {
        if v[0] == v[1] || v[1] == v[2] || v[0] == v[2] {
            continue; // collapsed by welding: no area, no side
        }
        for k in 0..3 {
            let (a, b) = (v[k], v[(k + 1) % 3]);
            sides.push(([a.min(b), a.max(b)], t as u32, a < b));
        }
    }
    sides.sort_unstable();
    let point = |k: u32| mesh.positions[k as usize];
    let mut neighbours: Vec<([u32; 2], u32, u32)> = Vec::with_capacity(sides.len() / 2);
    for group in sides.chunk_by(|x, y| x.0 == y.0) {
        let [a, b] = group[0].0;
        match group {
            [_] => {
                return Err(MeshBorderError::Open {
                    a: point(a),
                    b: point(b),
                })
            }
            [s, t] if s.2 == t.2 => {
                return Err(MeshBorderError::Unoriented {
                    a: point(if s.2 { a } else { b }),
                    b: point(if s.2 { b } else { a }),
                })
            }
            [s, t] => neighbours.push((group[0].0, s.1, t.1)),
            more => {
                return Err(MeshBorderError::NonManifold {
                    a: point(a),
                    b: point(b),
                    count: more.len(),
                })
            }
        }
    }

    // 2. Smooth patches by union–find over the sides.
    let normal: Vec<Vector3<f64>> = (tri.iter())
        .map(|t| {
            let [a, b, c] = t.map(point);
            (b - a).cross(&(c - a))
        })
        .collect();
    let mut parent: Vec<u32> = (0..n_tri as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            let up = parent[parent[i as usize] as usize];
            parent[i as usize] = up;
            i = up;
        }
        i
    }
    for &(_, s, t) in &neighbours {
        let joined = match rule {
            EdgeRule::Dihedral { threshold_rad } => {
                // A triangle without area has no normal: it joins its neighbours.
                match (
                    normal[s as usize].try_normalize(0.0),
                    normal[t as usize].try_normalize(0.0),
                ) {
                    (Some(u), Some(v)) => u.angle(&v) < *threshold_rad,
                    _ => true,
                }
            }
            EdgeRule::Marked(edge) => !edge[s as usize] && !edge[t as usize],
        };
        if joined {
            let (rs, rt) = (root(&mut parent, s), root(&mut parent, t));
            // The lower index becomes the root, so patches are named independently of order.
            let (lo, hi) = (rs.min(rt), rs.max(rt));
            parent[hi as usize] = lo;
        }
    }
    let roots: Vec<u32> = (0..n_tri as u32).map(|i| root(&mut parent, i)).collect();

    // 3. Top and bottom faces: the largest patches facing up and down.
    let marked = |t: usize| matches!(rule, EdgeRule::Marked(e) if e[t]);
    let mut area = vec![0.0; n_tri];
    let mut up = vec![0.0; n_tri];
    for t in 0..n_tri {
        if !marked(t) {
            let r = roots[t] as usize;
            area[r] += 0.5 * normal[t].norm();
            up[r] += 0.5 * normal[t].z; // area-weighted normal's z
        }
    }
    let patches = (0..n_tri)
        .filter(|&t| roots[t] == t as u32 && !marked(t))
        .count();
    let largest = |sign: f64| {
        (0..n_tri)
            .filter(|&r| roots[r] == r as u32 && !marked(r) && sign * up[r] > 0.0)
            .fold(None, |best: Option<usize>, r| match best {
                Some(b) if area[b] >= area[r] => Some(b),
                _ => Some(r),
            })
    };
    let threshold = || match rule {
        EdgeRule::Dihedral { threshold_rad } => format!("{}°", threshold_rad.to_degrees()),
        EdgeRule::Marked(_) => "the edge material's triangles".to_owned(),
    };
    // A closed patch's area-weighted normal sums to zero: one patch that is the whole mesh
    // faces nowhere (or, by rounding, up with no boundary).
    let Some(top) = largest(1.0) else {
        return Err(if patches == 1 {
            MeshBorderError::NoBorder {
                patches,
                threshold: threshold(),
            }
        } else {
            MeshBorderError::NoTopFace { patches }
        });
    };
    let top = top as u32;
    let bottom = largest(-1.0).map(|r| r as u32);
    let parts: Vec<SurfacePart> = (0..n_tri)
        .map(|t| match roots[t] {
            _ if marked(t) => SurfacePart::Edge,
            r if r == top => SurfacePart::TopFace,
            r if Some(r) == bottom => SurfacePart::BottomFace,
            _ => SurfacePart::Edge,
        })
        .collect();

    // 4. The top face's boundary: its sides whose other triangle is not on it, directed as the
    //    top triangle winds them.
    let is_top = |t: u32| roots[t as usize] == top && !marked(t as usize);
    let mut next: HashMap<u32, u32> = HashMap::new();
    let mut leaving: HashMap<u32, usize> = HashMap::new();
    for &([a, b], s, t) in &neighbours {
        let inside = match (is_top(s), is_top(t)) {
            (true, false) => s,
            (false, true) => t,
            _ => continue,
        };
        let v = tri[inside as usize];
        let forward = (0..3).any(|k| v[k] == a && v[(k + 1) % 3] == b);
        let (from, to) = if forward { (a, b) } else { (b, a) };
        *leaving.entry(from).or_default() += 1;
        next.insert(from, to);
    }
    if let Some((&at, &count)) = (leaving.iter())
        .filter(|(_, &c)| c > 1)
        .min_by_key(|(&v, _)| v)
    {
        return Err(MeshBorderError::Pinched {
            at: point(at),
            count,
        });
    }
    if next.is_empty() {
        return Err(MeshBorderError::NoBorder {
            patches,
            threshold: threshold(),
        });
    }
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut seen: HashMap<u32, usize> = HashMap::new();
    let mut loops: Vec<Vec<u32>> = Vec::new();
    for &s in &starts {
        if seen.contains_key(&s) {
            continue;
        }
        let mut cycle = vec![s];
        seen.insert(s, loops.len());
        let mut v = next[&s];
        while v != s {
            seen.insert(v, loops.len());
            cycle.push(v);
            v = next[&v];
        }
        loops.push(cycle);
    }
    if loops.len() > 1 {
        let length = |c: &Vec<u32>| {
            (0..c.len())
                .map(|i| (point(c[(i + 1) % c.len()]) - point(c[i])).norm())
                .sum::<f64>()
        };
        let lengths: Vec<String> = loops
            .iter()
            .map(|c| format!("{:.1}", length(c) * 1e3))
            .collect();
        return Err(MeshBorderError::SeveralBorders {
            count: loops.len(),
            lengths: lengths.join(", "),
        });
    }
    // Started at the lowest welded index, which is the lowest vertex index on the boundary.
    let cycle = loops.pop().expect("one loop");

    // Surface normals at the boundary vertices, from the top face.
    let mut shading: HashMap<u32, Vector3<f64>> = HashMap::new();
    for (t, v) in tri.iter().enumerate() {
        if !is_top(t as u32) {
            continue;
        }
        for k in 0..3 {
            if !next.contains_key(&v[k]) {
                continue;
            }
            let n = match &mesh.normals {
                // The file's shading normal: the first top triangle's vertex decides.
                Some(ns) => {
                    shading
                        .entry(v[k])
                        .or_insert(ns[mesh.triangles[t][k] as usize]);
                    continue;
                }
                None => normal[t].try_normalize(0.0).unwrap_or_else(Vector3::zeros),
            };
            let (p, q, r) = (point(v[k]), point(v[(k + 1) % 3]), point(v[(k + 2) % 3]));
            let corner = (q - p).angle(&(r - p));
            *shading.entry(v[k]).or_insert_with(Vector3::zeros) += n * corner;
        }
    }
    let m = cycle.len();
    let vertices = (0..m)
        .map(|i| {
            let position = point(cycle[i]);
            let surface_normal = shading[&cycle[i]].normalize();
            let chord = point(cycle[(i + 1) % m]) - point(cycle[(i + m - 1) % m]);
            let tangent = (chord - surface_normal * chord.dot(&surface_normal)).normalize();
            BorderVertex {
                position,
                tangent,
                surface_normal,
                outward: tangent.cross(&surface_normal),
            }
        })
        .collect();
    Ok(MeshBorder {
        border: BorderCurve { vertices },
        parts,
    })
}

/// A square pane 2a × 2a with a square hole 2b × 2b, thickness t: closed, outward wound (tests).
#[cfg(test)]
pub(crate) fn ring(a: f64, b: f64, t: f64) -> Mesh {
    let square = |s: f64| [[-s, -s], [s, -s], [s, s], [-s, s]];
    let mut positions = Vec::new();
    for (loop_, z) in [(a, 0.0), (a, t), (b, 0.0), (b, t)] {
        positions.extend(square(loop_).map(|[x, y]| Point3::new(x, y, z)));
    }
    // Loops: outer bottom 0..4, outer top 4..8, inner bottom 8..12, inner top 12..16.
    let mut triangles = Vec::new();
    let mut quad = |q: [u32; 4]| {
        triangles.push([q[0], q[1], q[2]]);
        triangles.push([q[0], q[2], q[3]]);
    };
    for i in 0..4u32 {
        let j = (i + 1) % 4;
        quad([4 + i, 4 + j, 12 + j, 12 + i]); // top
        quad([i, 8 + i, 8 + j, j]); // bottom
        quad([i, j, 4 + j, 4 + i]); // outer wall
        quad([8 + j, 8 + i, 12 + i, 12 + j]); // inner wall
    }
    Mesh::solid(positions, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::cuboid::cuboid;
    use crate::geometry::panel::{build_panel, Curvature, EdgeProfile, Outline, PanelSpec};

    fn dihedral() -> EdgeRule {
        EdgeRule::Dihedral {
            threshold_rad: DEFAULT_EDGE_DIHEDRAL_DEG.to_radians(),
        }
    }

    fn panel(curvature: Curvature, edge: EdgeProfile) -> crate::geometry::panel::Panel {
        build_panel(&PanelSpec {
            outline: Outline::Polygon {
                vertices_m: vec![[-0.1, -0.06], [0.1, -0.06], [0.08, 0.06], [-0.08, 0.06]],
                corner_radius_m: 0.01,
            },
            thickness_m: 0.004,
            curvature,
            edge,
            tessellation_m: 0.005,
        })
        .expect("panel builds")
    }

    /// The mesh's border equals the panel builder's, vertex for vertex, and so do the parts.
    fn same_as_panel(p: &crate::geometry::panel::Panel, rule: &EdgeRule) {
        let found = find_border(&p.mesh, rule).expect("border found");
        assert_eq!(found.parts, p.mesh.parts);
        let (a, b) = (&found.border.vertices, &p.border.vertices);
        assert_eq!(a.len(), b.len());
        for (u, v) in a.iter().zip(b) {
            assert_eq!(u.position, v.position);
            assert!((u.surface_normal - v.surface_normal).norm() < 1e-12);
            assert!((u.outward - v.outward).norm() < 0.1, "{u:?} {v:?}");
        }
    }

    #[test]
    fn a_panel_mesh_gives_the_panels_border_and_parts() {
        for curvature in [Curvature::Flat, Curvature::Cylindrical { radius_m: 0.5 }] {
            for edge in [EdgeProfile::default(), EdgeProfile::FlatGround] {
                let p = panel(curvature, edge);
                same_as_panel(&p, &dihedral());
                let marked = (p.mesh.parts.iter())
                    .map(|&x| x == SurfacePart::Edge)
                    .collect();
                same_as_panel(&p, &EdgeRule::Marked(marked));
                // Without normals the frame comes from the triangles: the same up to the chord
                // of a bend.
                let mut bare = p.mesh.clone();
                bare.normals = None;
                let found = find_border(&bare, &dihedral()).unwrap();
                for (u, v) in found.border.vertices.iter().zip(&p.border.vertices) {
                    assert!((u.surface_normal - v.surface_normal).norm() < 0.01);
                }
            }
        }
    }

    #[test]
    fn an_open_mesh_is_refused_naming_a_side() {
        let mut m = panel(Curvature::Flat, EdgeProfile::default()).mesh;
        m.triangles.pop();
        m.parts.pop();
        let e = find_border(&m, &dihedral()).unwrap_err();
        assert!(matches!(e, MeshBorderError::Open { .. }), "{e}");
        assert!(e.to_string().contains("belongs to 1 triangle"), "{e}");
    }

    #[test]
    fn a_side_of_three_triangles_is_not_a_manifold() {
        let mut m = cuboid([0.1, 0.1, 0.01]);
        let t = m.triangles[0];
        // A fin on the box: a third and fourth triangle on one side (a closed pair).
        let apex = m.positions.len() as u32;
        m.positions.push(Point3::new(0.0, 0.0, 0.5));
        m.triangles.push([t[0], t[1], apex]);
        m.triangles.push([t[1], t[0], apex]);
        m.parts.extend([SurfacePart::Solid; 2]);
        let e = find_border(&m, &dihedral()).unwrap_err();
        assert!(
            matches!(e, MeshBorderError::NonManifold { count: 4, .. }),
            "{e}"
        );
    }

    #[test]
    fn a_flipped_triangle_is_refused() {
        let mut m = cuboid([0.1, 0.1, 0.01]);
        m.triangles[3].swap(1, 2);
        let e = find_border(&m, &dihedral()).unwrap_err();
        assert!(matches!(e, MeshBorderError::Unoriented { .. }), "{e}");
    }

    #[test]
    fn a_box_has_a_border_but_a_smooth_mesh_has_none() {
        // A thin box is a pane with a flat-ground edge: the border is its top rectangle.
        let b = find_border(&cuboid([0.3, 0.2, 0.004]), &dihedral()).unwrap();
        assert_eq!(b.border.vertices.len(), 4);
        assert!((b.border.length() - 1.0).abs() < 1e-12);
        // With every crease below the threshold, the top face is the whole box.
        let e = find_border(
            &cuboid([0.3, 0.2, 0.004]),
            &EdgeRule::Dihedral {
                threshold_rad: 100f64.to_radians(),
            },
        )
        .unwrap_err();
        assert!(
            matches!(e, MeshBorderError::NoBorder { patches: 1, .. }),
            "{e}"
        );
        // Everything marked as edge: no face at all.
        let e = find_border(
            &cuboid([0.3, 0.2, 0.004]),
            &EdgeRule::Marked(vec![true; 12]),
        )
        .unwrap_err();
        assert!(
            matches!(e, MeshBorderError::NoTopFace { patches: 0 }),
            "{e}"
        );
    }

    #[test]
    fn a_pane_with_a_hole_has_several_borders() {
        let m = ring(0.1, 0.05, 0.004);
        let e = find_border(&m, &dihedral()).unwrap_err();
        assert_eq!(
            e,
            MeshBorderError::SeveralBorders {
                count: 2,
                lengths: "800.0, 400.0".into()
            }
        );
        assert!(e.to_string().contains("expected one"), "{e}");
    }
}
