//! Whole-panel checks for every edge kind (flat and curved, sharp and filleted junctions,
//! equal and unequal face insets): closed watertight meshes, enclosed volume against the
//! analytic value, outward normals, the border curve's length, frames and place on the mesh,
//! and parameter errors.

use std::collections::HashMap;
use std::f64::consts::PI;

use nalgebra::{Point3, Vector3};

use super::*;

const T: f64 = 0.004;
const S: f64 = 0.005;
const FLAT: Curvature = Curvature::Flat;
const GROUND: EdgeProfile = EdgeProfile::FlatGround;
const BEVEL: f64 = 0.001;
const ARRIS: EdgeProfile = EdgeProfile::Arrissed { bevel_m: BEVEL };
const PENCIL: EdgeProfile = EdgeProfile::Pencil { radius_m: None };
const FILLET: f64 = 0.2e-3;

fn rect(w: f64, h: f64, r: f64) -> Outline {
    Outline::Rectangle {
        width_m: w,
        height_m: h,
        corner_radius_m: r,
    }
}

fn polygon(vertices: &[[f64; 2]], r: f64) -> Outline {
    Outline::Polygon {
        vertices_m: vertices.to_vec(),
        corner_radius_m: r,
    }
}

fn bend(radius_m: f64) -> Curvature {
    Curvature::Cylindrical { radius_m }
}

/// An L-shape (concave), given clockwise to exercise the normalisation.
fn l_shape(r: f64) -> Outline {
    let ccw = [
        [-0.2, -0.15],
        [0.2, -0.15],
        [0.2, 0.0],
        [0.0, 0.0],
        [0.0, 0.15],
        [-0.2, 0.15],
    ];
    Outline::Polygon {
        vertices_m: ccw.iter().rev().copied().collect(),
        corner_radius_m: r,
    }
}

fn spec(outline: Outline, edge: EdgeProfile, curvature: Curvature) -> PanelSpec {
    PanelSpec {
        outline,
        thickness_m: T,
        curvature,
        edge,
        tessellation_m: S,
    }
}

fn build(outline: Outline, edge: EdgeProfile, curvature: Curvature) -> Panel {
    build_panel(&spec(outline, edge, curvature)).unwrap()
}

/// Welds vertices with bit-identical positions and counts the uses of each undirected edge.
fn edge_uses(mesh: &Mesh) -> HashMap<(usize, usize), usize> {
    let mut weld: HashMap<[u64; 3], usize> = HashMap::new();
    let ids: Vec<usize> = mesh
        .positions
        .iter()
        .map(|p| {
            let key = [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits());
            let next = weld.len();
            *weld.entry(key).or_insert(next)
        })
        .collect();
    let mut uses = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (ids[t[k] as usize], ids[t[(k + 1) % 3] as usize]);
            assert_ne!(a, b, "degenerate triangle {t:?}");
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

/// Enclosed volume by the divergence theorem, Σ p0 · (p1 × p2) / 6.
fn volume(mesh: &Mesh) -> f64 {
    let p = |k: u32| mesh.positions[k as usize].coords;
    mesh.triangles
        .iter()
        .map(|t| p(t[0]).dot(&p(t[1]).cross(&p(t[2]))) / 6.0)
        .sum()
}

/// Mesh invariants every panel must satisfy.
fn check_closed_mesh(panel: &Panel) {
    let mesh = &panel.mesh;
    mesh.check().unwrap();
    let uses = edge_uses(mesh);
    let bad: Vec<_> = uses.iter().filter(|(_, &n)| n != 2).take(5).collect();
    assert!(
        bad.is_empty(),
        "{} edges not shared by two triangles, e.g. {bad:?}",
        uses.values().filter(|&&n| n != 2).count()
    );
    let normals = mesh.normals.as_ref().unwrap();
    for (i, t) in mesh.triangles.iter().enumerate() {
        let g = mesh.face_normal(i);
        for &k in t {
            let n = normals[k as usize];
            assert!((n.norm() - 1.0).abs() < 1e-12);
            assert!(
                g.dot(&n) > 0.0,
                "triangle {i} ({:?}) normal {g} vs vertex normal {n}",
                mesh.parts[i]
            );
        }
    }
    for part in [
        SurfacePart::TopFace,
        SurfacePart::BottomFace,
        SurfacePart::Edge,
    ] {
        assert!(mesh.parts.contains(&part));
    }
}

fn seamed(top_width_m: f64, bottom_width_m: f64, fillet_radius_m: f64) -> EdgeProfile {
    let arris = |width_m| Arris {
        width_m,
        ..Arris::default()
    };
    EdgeProfile::Seamed(Seamed {
        top: arris(top_width_m),
        bottom: arris(bottom_width_m),
        fillet_radius_m,
    })
}

fn section_mm(points: &[[f64; 2]]) -> EdgeProfile {
    EdgeProfile::Section {
        points_m: points.iter().map(|p| p.map(|c| c * 1e-3)).collect(),
    }
}

/// Area (m²) a fillet of radius ρ removes at a sharp junction turning by θ: between the two
/// tangent legs ρ·tan(θ/2) and the arc, ρ²·(tan(θ/2) − θ/2).
fn fillet_area(theta: f64) -> f64 {
    FILLET * FILLET * ((0.5 * theta).tan() - 0.5 * theta)
}

/// Edge profiles with the cross-section area each removes from the square edge: an arris of
/// width w at 45° a w²/2 triangle, fillets their `fillet_area`, a pencil arc of radius r over
/// ±ψ (sin ψ = t/2r) r²·(2 sin ψ − ψ − sin ψ cos ψ) (the half round: (2 − π/2)·(t/2)²), a
/// polyline the trapezoids between it and the outline. Times the outline length, that is the
/// volume removed (Pappus, to first order in the corner curvature).
fn profiles() -> Vec<(EdgeProfile, f64)> {
    let w = DEFAULT_ARRIS_WIDTH_M;
    let (r, psi) = (0.003, (T / 0.006).asin());
    vec![
        (GROUND, 0.0),
        (ARRIS, BEVEL * BEVEL),
        (PENCIL, (2.0 - PI / 2.0) * (T / 2.0) * (T / 2.0)),
        (EdgeProfile::default(), w * w),
        // Four 45° junctions, filleted.
        (seamed(w, w, FILLET), w * w + 4.0 * fillet_area(PI / 4.0)),
        // No top arris: the top corner is sharp, the faces' insets differ.
        (seamed(0.0, w, 0.0), w * w / 2.0),
        // The same filleted: a 90° face/wall fillet at the top, two 45° ones at the bottom.
        (
            seamed(0.0, w, FILLET),
            w * w / 2.0 + fillet_area(PI / 2.0) + 2.0 * fillet_area(PI / 4.0),
        ),
        (
            EdgeProfile::Pencil { radius_m: Some(r) },
            r * r * (2.0 * psi.sin() - psi - psi.sin() * psi.cos()),
        ),
        (
            section_mm(&[[0.6, 4.0], [0.0, 3.4], [0.0, 0.6], [0.6, 0.0]]),
            0.36e-6,
        ),
        (section_mm(&[[0.0, 4.0], [0.0, 1.0], [1.0, 0.0]]), 0.5e-6),
    ]
}

fn rounded_rect_area(w: f64, h: f64, r: f64) -> f64 {
    w * h - (4.0 - PI) * r * r
}

#[test]
fn flat_rectangle_is_closed_with_exact_volume() {
    let panel = build(rect(0.55, 0.42, 0.0), GROUND, FLAT);
    check_closed_mesh(&panel);
    assert!((volume(&panel.mesh) / (0.55 * 0.42 * T) - 1.0).abs() < 1e-12);
}

#[test]
fn flat_rounded_rectangle_has_the_analytic_volume() {
    let panel = build(rect(0.55, 0.42, 0.03), GROUND, FLAT);
    check_closed_mesh(&panel);
    let expected = rounded_rect_area(0.55, 0.42, 0.03) * T;
    assert!((volume(&panel.mesh) / expected - 1.0).abs() < 5e-3);
}

#[test]
fn stadium_with_full_half_circle_ends_is_closed() {
    let panel = build(rect(0.3, 0.1, 0.05), PENCIL, FLAT);
    check_closed_mesh(&panel);
}

#[test]
fn concave_l_shape_is_closed_sharp_and_rounded() {
    let area = 0.4 * 0.3 - 0.2 * 0.15;
    for r in [0.0, 0.01] {
        // Rounding removes (1 − π/4)r² at each of 5 convex corners and adds it at the concave
        // one; it shortens the outline by (2 − π/2)r at each of the 6.
        let area = area - 4.0 * (1.0 - PI / 4.0) * r * r;
        let perimeter = 1.4 - 6.0 * (2.0 - PI / 2.0) * r;
        for (edge, removed) in profiles() {
            let panel = build(l_shape(r), edge.clone(), FLAT);
            check_closed_mesh(&panel);
            check_border_frames(&panel.border, FLAT_FACE_GRID_M);
            let expected = area * T - removed * perimeter;
            assert!(
                (volume(&panel.mesh) / expected - 1.0).abs() < 1e-3,
                "r {r}, {edge:?}"
            );
        }
    }
}

#[test]
fn arrissed_and_pencil_edges_remove_their_profile_volume() {
    let (w, h, r) = (0.55, 0.42, 0.02);
    let (area, perimeter) = (
        rounded_rect_area(w, h, r),
        2.0 * (w + h) - (8.0 - 2.0 * PI) * r,
    );
    for (edge, removed) in profiles() {
        let panel = build(rect(w, h, r), edge.clone(), FLAT);
        check_closed_mesh(&panel);
        let v = volume(&panel.mesh);
        assert!((v / (area * T) - 1.0).abs() < 5e-3, "{edge:?}");
        assert!(
            (v / (area * T - removed * perimeter) - 1.0).abs() < 1e-4,
            "{edge:?}"
        );
    }
}

#[test]
fn curved_panel_is_closed_with_top_face_on_its_cylinder() {
    let radius = 1.5;
    for (edge, _) in profiles() {
        let panel = build(rect(0.55, 0.42, 0.02), edge.clone(), bend(radius));
        check_closed_mesh(&panel);
        let mesh = &panel.mesh;
        for (t, part) in mesh.triangles.iter().zip(&mesh.parts) {
            if *part == SurfacePart::TopFace {
                for &k in t {
                    let p = mesh.positions[k as usize];
                    assert!(
                        ((p.x * p.x + (p.z + radius).powi(2)).sqrt() - (radius + T)).abs() < 1e-12
                    );
                }
            }
        }
        // The bend stretches height h by (R + h)/R: volume = A·(t + t²/(2R)) for a flat edge.
        if edge == GROUND {
            let expected = rounded_rect_area(0.55, 0.42, 0.02) * (T + T * T / (2.0 * radius));
            assert!((volume(mesh) / expected - 1.0).abs() < 1e-4);
        }
    }
}

#[test]
fn curved_l_shape_is_closed() {
    check_closed_mesh(&build(l_shape(0.01), PENCIL, bend(0.3)));
    let wide_arris = EdgeProfile::Arrissed { bevel_m: 0.0015 };
    check_closed_mesh(&build(l_shape(0.0), wide_arris, bend(0.3)));
    for (edge, _) in profiles() {
        check_closed_mesh(&build(l_shape(0.01), edge, bend(0.3)));
    }
}

#[test]
fn outlines_on_grid_lines_and_through_grid_corners_are_closed() {
    // Edges at ±55.5 cells lie on the first grid's lines; the hypotenuse y = x runs through its
    // corners; a panel smaller than one cell has no interior corner at all.
    let diagonal = polygon(&[[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1]], 0.0);
    let outlines = [rect(0.555, 0.425, 0.0), diagonal, rect(0.003, 0.002, 0.0)];
    for outline in outlines {
        check_closed_mesh(&build(outline.clone(), GROUND, FLAT));
        check_closed_mesh(&build(outline, GROUND, bend(1.0)));
    }
}

#[test]
fn face_triangles_span_at_most_one_cell() {
    // A bent panel's grid is the tessellation; a flat one's at least FLAT_FACE_GRID_M.
    let bent = Curvature::Cylindrical { radius_m: 1.5 };
    for (curvature, cell) in [(bent, S), (FLAT, FLAT_FACE_GRID_M)] {
        let panel = build(rect(0.55, 0.42, 0.02), PENCIL, curvature);
        let mesh = &panel.mesh;
        let mut widest: f64 = 0.0;
        for (t, part) in mesh.triangles.iter().zip(&mesh.parts) {
            if *part != SurfacePart::Edge {
                // The flat grid's x, i.e. the bent panel's arc length along x.
                let xs = t.map(|k| {
                    let p = mesh.positions[k as usize];
                    match curvature {
                        Curvature::Flat => p.x,
                        Curvature::Cylindrical { radius_m } => radius_m * p.x.atan2(p.z + radius_m),
                    }
                });
                let span = xs.iter().fold(f64::MIN, |a, &b| a.max(b))
                    - xs.iter().fold(f64::MAX, |a, &b| a.min(b));
                assert!(span <= cell * (1.0 + 1e-9), "{span} > {cell}");
                widest = widest.max(span);
            }
        }
        assert!(widest > 0.9 * cell, "{widest} against {cell}");
    }
}

/// The border's frames, and its segments no longer than `longest_step` (m).
fn check_border_frames(border: &BorderCurve, longest_step: f64) {
    let n = border.vertices.len();
    for (i, v) in border.vertices.iter().enumerate() {
        for (a, b) in [
            (v.tangent, v.surface_normal),
            (v.tangent, v.outward),
            (v.outward, v.surface_normal),
        ] {
            assert!(a.dot(&b).abs() < 1e-12);
        }
        for d in [v.tangent, v.surface_normal, v.outward] {
            assert!((d.norm() - 1.0).abs() < 1e-12);
        }
        // Counter-clockwise: the tangent follows the vertex order. Segments stay within the
        // tessellation length (stretched by (R + t)/R on a bent top face), on a flat panel
        // within FLAT_FACE_GRID_M, to which its straight runs are sampled (its arcs are
        // sampled as a bent one's: `contour`'s tests).
        let step = border.vertices[(i + 1) % n].position - v.position;
        assert!(step.dot(&v.tangent) > 0.0);
        assert!(step.norm() <= longest_step * (1.0 + 1e-12));
    }
}

#[test]
fn border_curve_is_the_inset_outline_at_the_top_face() {
    let (w, h, r, b) = (0.55, 0.42, 0.02, BEVEL);
    let panel = build(rect(w, h, r), ARRIS, FLAT);
    let border = &panel.border;
    let (wi, hi, ri) = (w - 2.0 * b, h - 2.0 * b, r - b);
    let expected = 2.0 * (wi + hi) - (8.0 - 2.0 * PI) * ri;
    // 10° chords shorten the arcs by about 1.3e-3 of their length.
    assert!(
        (border.length() / expected - 1.0).abs() < 1e-4,
        "{} vs {expected}",
        border.length()
    );
    check_border_frames(border, FLAT_FACE_GRID_M);
    for v in &border.vertices {
        assert_eq!(v.position.z, T);
        assert_eq!(v.surface_normal, Vector3::z());
        assert!(
            v.outward.dot(&v.position.coords) > 0.0,
            "centroid is the origin"
        );
    }
}

#[test]
fn border_curve_follows_the_bend() {
    let radius = 1.5;
    let panel = build(rect(0.55, 0.42, 0.02), PENCIL, bend(radius));
    check_border_frames(&panel.border, S * 1.003);
    let axis = Point3::new(0.0, 0.0, -radius);
    for v in &panel.border.vertices {
        let radial = Vector3::new(v.position.x - axis.x, 0.0, v.position.z - axis.z);
        assert!((radial.norm() - (radius + T)).abs() < 1e-12);
        assert!((radial.normalize() - v.surface_normal).norm() < 1e-12);
        // Outward points away from the panel's middle, within the top face's tangent plane.
        let from_centre = v.position - Point3::new(0.0, 0.0, T);
        assert!(v.outward.dot(&from_centre) > 0.0);
    }
    // The top face is inset by t/2 and bent at radius R + t: its x extent stretches by (R + t)/R.
    let (wi, hi, ri) = (0.55 - T, 0.42 - T, 0.02 - T / 2.0);
    let straight_y = 2.0 * (hi - 2.0 * ri);
    let straight_x = 2.0 * (wi - 2.0 * ri) * (radius + T) / radius;
    let length = panel.border.length();
    assert!(
        length > straight_x + straight_y && length < straight_x + straight_y + 2.0 * PI * ri * 1.01
    );
}

#[test]
fn default_side_window_stays_small_and_deterministic() {
    let s = spec(rect(0.55, 0.42, 0.02), PENCIL, bend(1.5));
    let a = build_panel(&s).unwrap();
    assert!(
        a.mesh.triangle_count() < 100_000,
        "{} triangles",
        a.mesh.triangle_count()
    );
    let b = build_panel(&s).unwrap();
    assert_eq!(a.mesh.positions, b.mesh.positions);
    assert_eq!(a.mesh.triangles, b.mesh.triangles);
}

/// The field named by the error for the default flat rectangle changed by `tweak`, or "built".
fn rejected_field(tweak: impl Fn(&mut PanelSpec)) -> &'static str {
    let mut s = spec(rect(0.55, 0.42, 0.02), GROUND, FLAT);
    tweak(&mut s);
    match build_panel(&s) {
        Err(
            PanelError::InvalidParameter { field, .. } | PanelError::InvalidPoint { field, .. },
        ) => field,
        Ok(_) => "built",
    }
}

#[test]
fn bad_parameters_name_their_scene_field() {
    fn expect(field: &str, tweak: impl Fn(&mut PanelSpec)) {
        assert_eq!(rejected_field(tweak), field);
    }
    expect("thickness_mm", |s| s.thickness_m = -0.004);
    expect("thickness_mm", |s| s.thickness_m = f64::NAN);
    expect("tessellation_mm", |s| s.tessellation_m = 0.0);
    expect("tessellation_mm", |s| s.tessellation_m = 1e-6);
    expect("width_mm", |s| s.outline = rect(0.0, 0.42, 0.0));
    expect("height_mm", |s| s.outline = rect(0.55, f64::INFINITY, 0.0));
    expect("corner_radius_mm", |s| s.outline = rect(0.55, 0.42, 0.22));
    expect("corner_radius_mm", |s| s.outline = rect(0.55, 0.42, -0.01));
    expect("radius_mm", |s| s.curvature = bend(-1.5));
    // Half-width 0.275 m needs R > 0.275/(π/2) = 0.175 m.
    expect("radius_mm", |s| s.curvature = bend(0.17));
    expect("built", |s| s.curvature = bend(0.18));
    expect("bevel_mm", |s| {
        s.edge = EdgeProfile::Arrissed { bevel_m: 0.002 }
    });
    expect("vertices_mm", |s| {
        s.outline = polygon(&[[0.0, 0.0], [0.1, 0.0]], 0.0)
    });
    let collinear = [[0.0, 0.0], [0.1, 0.0], [0.2, 0.0]];
    expect("vertices_mm", |s| s.outline = polygon(&collinear, 0.0));
    let bow_tie = [[0.0, 0.0], [0.1, 0.1], [0.1, 0.0], [0.0, 0.1]];
    expect("vertices_mm", |s| s.outline = polygon(&bow_tie, 0.0));
    let not_finite = [[0.0, 0.0], [0.1, f64::NAN], [0.0, 0.1]];
    expect("vertices_mm", |s| s.outline = polygon(&not_finite, 0.0));
    let triangle = [[0.0, 0.0], [0.1, 0.0], [0.0, 0.1]];
    expect("corner_radius_mm", |s| s.outline = polygon(&triangle, 0.05));
    expect("built", |s| s.outline = polygon(&triangle, 0.02));
    // A pencil edge insets the faces by t/2 = 2 mm: a 1 mm corner radius cannot carry it, nor
    // can a strip 3 mm wide, nor a sharp 11° corner (its miter exceeds the limit).
    expect("corner_radius_mm", |s| {
        (s.edge, s.outline) = (PENCIL, rect(0.55, 0.42, 0.001))
    });
    expect("thickness_mm", |s| {
        (s.edge, s.outline) = (PENCIL, rect(0.2, 0.003, 0.0))
    });
    let spike = [[0.0, 0.0], [0.1, 0.0], [0.0, 0.02]];
    expect("thickness_mm", |s| {
        (s.edge, s.outline) = (PENCIL, polygon(&spike, 0.0))
    });
    expect("built", |s| s.edge = PENCIL);
    // The new kinds name their own fields.
    expect("seamed.top.angle_deg", |s| {
        s.edge = EdgeProfile::Seamed(Seamed {
            top: Arris {
                angle_rad: 70f64.to_radians(),
                ..Arris::default()
            },
            ..Seamed::default()
        })
    });
    expect("seamed", |s| s.edge = seamed(2e-3, 2e-3, 0.0));
    expect("seamed.fillet_radius_mm", |s| {
        s.edge = seamed(0.8e-3, 0.8e-3, 3e-3)
    });
    expect("pencil.radius_mm", |s| {
        s.edge = EdgeProfile::Pencil {
            radius_m: Some(1e-3),
        }
    });
    expect("section.points_mm", |s| {
        s.edge = section_mm(&[[0.0, 4.0], [0.0, 4.5], [0.0, 0.0]])
    });
    // The seamed default insets the faces by 0.8 mm: a corner radius of 0.5 mm cannot hold
    // it, and neither can a groove 25 mm deep a corner radius of 20 mm.
    expect("corner_radius_mm", |s| {
        (s.edge, s.outline) = (EdgeProfile::default(), rect(0.55, 0.42, 0.5e-3))
    });
    expect("corner_radius_mm", |s| {
        s.edge = section_mm(&[[0.0, 4.0], [25.0, 2.0], [0.0, 0.0]])
    });
    expect("built", |s| s.edge = EdgeProfile::default());
}

#[test]
fn error_message_says_expected_and_got() {
    let mut s = spec(rect(0.55, 0.42, 0.0), GROUND, FLAT);
    s.thickness_m = -0.004;
    let err = build_panel(&s).unwrap_err();
    assert_eq!(err.to_string(), "thickness_mm must be > 0, got -0.004 m");
}

#[test]
fn border_runs_through_mesh_vertices_at_the_top_face_boundary() {
    // Sharp-cornered rectangle: a point's inset is its distance to the nearer side.
    let (w, h) = (0.3, 0.2);
    let inset = |p: &Point3<f64>| (0.5 * w - p.x.abs()).min(0.5 * h - p.y.abs());
    let seam = DEFAULT_ARRIS_WIDTH_M;
    let cases = [
        (EdgeProfile::default(), seam),
        // The fillet's tangent point with the face: r·tan(22.5°) inside the arris top.
        (seamed(seam, seam, FILLET), seam + FILLET * (PI / 8.0).tan()),
        (seamed(0.0, seam, 0.0), 0.0),
        (seamed(0.0, seam, FILLET), FILLET),
        (PENCIL, T / 2.0),
        (
            EdgeProfile::Pencil {
                radius_m: Some(0.003),
            },
            0.003 - (0.003f64.powi(2) - (T / 2.0).powi(2)).sqrt(),
        ),
        (section_mm(&[[0.0, 4.0], [0.0, 1.0], [1.0, 0.0]]), 0.0),
        (GROUND, 0.0),
    ];
    for (edge, expected) in cases {
        let panel = build(rect(w, h, 0.0), edge.clone(), FLAT);
        let vertices: std::collections::HashSet<[u64; 3]> = panel
            .mesh
            .positions
            .iter()
            .map(|p| [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits()))
            .collect();
        check_border_frames(&panel.border, FLAT_FACE_GRID_M);
        for v in &panel.border.vertices {
            let p = v.position;
            assert!(
                vertices.contains(&[p.x, p.y, p.z].map(|c| (c + 0.0).to_bits())),
                "{edge:?}: border vertex {p} is not a mesh vertex"
            );
            assert_eq!(p.z, T);
            assert!(
                (inset(&p) - expected).abs() < 1e-15,
                "{edge:?}: {}",
                inset(&p)
            );
        }
    }
}

#[test]
fn only_the_ground_finish_is_tagged_edge() {
    // With unequal face insets the strip out to the smaller one is glass face, at the face's
    // height, facing up (top) or down (bottom).
    for (edge, strip) in [
        (
            seamed(0.0, DEFAULT_ARRIS_WIDTH_M, 0.0),
            SurfacePart::TopFace,
        ),
        (
            seamed(DEFAULT_ARRIS_WIDTH_M, 0.0, 0.0),
            SurfacePart::BottomFace,
        ),
    ] {
        let panel = build(rect(0.1, 0.08, 0.0), edge, FLAT);
        let mesh = &panel.mesh;
        let (height, normal_z) = if strip == SurfacePart::TopFace {
            (T, 1.0)
        } else {
            (0.0, -1.0)
        };
        for (i, t) in mesh.triangles.iter().enumerate() {
            let on_face_plane = t.iter().all(|&k| mesh.positions[k as usize].z == height);
            if on_face_plane {
                assert_eq!(mesh.parts[i], strip);
                assert!((mesh.face_normal(i).z - normal_z).abs() < 1e-12);
            } else if mesh.parts[i] == strip {
                panic!("triangle {i} tagged {strip:?} off the face plane");
            }
        }
    }
}
