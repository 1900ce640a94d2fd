//! A `panel` table → `PanelSpec` (SI) → the built panel, with the edge finish's keys and their
//! defaults, and `build_panel`'s errors mapped back to the place of the field they name.
//!
//! Values are range-checked here where the check needs no geometry (a width ≥ 0, an arris
//! angle in [30, 65] degrees, a finite section point), so that the message is in the file's
//! units; rules that need the built geometry (a corner radius too tight for the edge's inset,
//! arrisses that leave no wall, a fillet too large, a bad section polyline) come from
//! `geometry::panel` with the field they concern and are reported at that field's value, or at
//! the nearest enclosing table that is written in the file when the value is a default.

use std::ops::Range;

use serde_spanned::Spanned;

use super::error::{SceneError, SceneSource};
use super::file::{ArrisDef, EdgeDef, PanelDef, SeamedDef};
use crate::geometry::panel::{
    build_panel, Arris, Curvature, EdgeProfile, Outline, Panel, PanelError, PanelSpec, Seamed,
    DEFAULT_ARRIS_ANGLE_RAD, DEFAULT_ARRIS_WIDTH_M,
};

/// Default face and border tessellation of a panel (mm): a chord error of 5²/(8·1500) ≈ 2 µm on
/// the R = 1500 mm side window, far below the sensor's ~12 µm resolution (scenes/README.md,
/// `tessellation_mm`).
const DEFAULT_TESSELLATION_MM: f64 = 5.0;

/// The panel spec of `def` (at field path `prefix`), checked value by value, and the panel.
pub(super) fn panel(
    def: &Spanned<PanelDef>,
    prefix: &str,
    src: &SceneSource,
) -> Result<(PanelSpec, Panel), SceneError> {
    let d = def.get_ref();
    let o = d.outline.get_ref();
    let f = |name: &str| format!("{prefix}.{name}");
    let corner_radius_m = match &o.corner_radius_mm {
        Some(r) => src.non_negative(r, &f("outline.corner_radius_mm"))? * 1e-3,
        None => 0.0,
    };
    let outline = match (&o.width_mm, &o.height_mm, &o.polygon_mm) {
        (Some(w), Some(h), None) => Outline::Rectangle {
            width_m: src.positive(w, &f("outline.width_mm"))? * 1e-3,
            height_m: src.positive(h, &f("outline.height_mm"))? * 1e-3,
            corner_radius_m,
        },
        (None, None, Some(poly)) => {
            let n = poly.get_ref().len();
            if n < 3 {
                return Err(src.invalid(
                    &poly.span(),
                    f("outline.polygon_mm"),
                    format!("must have at least 3 vertices, got {n}"),
                ));
            }
            let mut vertices_m = Vec::with_capacity(n);
            for (k, [x, y]) in poly.get_ref().iter().enumerate() {
                let x = src.finite(x, &format!("{prefix}.outline.polygon_mm[{k}][0]"))?;
                let y = src.finite(y, &format!("{prefix}.outline.polygon_mm[{k}][1]"))?;
                vertices_m.push([x * 1e-3, y * 1e-3]);
            }
            Outline::Polygon {
                vertices_m,
                corner_radius_m,
            }
        }
        (_, _, Some(poly)) => {
            return Err(src.invalid(
                &poly.span(),
                f("outline"),
                "must give either `width_mm` and `height_mm`, or `polygon_mm`, not both",
            ))
        }
        (w, h, None) => {
            let missing = if w.is_none() && h.is_none() {
                "`width_mm` and `height_mm` (or `polygon_mm`)"
            } else if w.is_none() {
                "`width_mm`"
            } else {
                "`height_mm`"
            };
            return Err(src.invalid(
                &d.outline.span(),
                f("outline"),
                format!("is missing {missing}"),
            ));
        }
    };
    let thickness_m = src.positive(&d.thickness_mm, &f("thickness_mm"))? * 1e-3;
    let curvature = match &d.curvature {
        Some(c) => Curvature::Cylindrical {
            radius_m: src.positive(&c.get_ref().radius_mm, &f("curvature.radius_mm"))? * 1e-3,
        },
        None => Curvature::Flat,
    };
    let edge = edge(d.edge.as_ref().map(Spanned::get_ref), &f("edge"), src)?;
    let tessellation_m = match &d.tessellation_mm {
        Some(t) => src.positive(t, &f("tessellation_mm"))? * 1e-3,
        None => DEFAULT_TESSELLATION_MM * 1e-3,
    };
    let spec = PanelSpec {
        outline,
        thickness_m,
        curvature,
        edge,
        tessellation_m,
    };
    let panel = build_panel(&spec).map_err(|e| panel_error(&e, def, prefix, src))?;
    Ok((spec, panel))
}

/// The edge finish; absent: seamed with the IGMA/PPG arrisses (`geometry::panel::profile`).
fn edge(def: Option<&EdgeDef>, prefix: &str, src: &SceneSource) -> Result<EdgeProfile, SceneError> {
    Ok(match def {
        None | Some(EdgeDef::Seamed(None)) => EdgeProfile::default(),
        Some(EdgeDef::FlatGround) => EdgeProfile::FlatGround,
        Some(EdgeDef::Seamed(Some(s))) => {
            let s = s.get_ref();
            let p = format!("{prefix}.seamed");
            let fillet_radius_m = match &s.fillet_radius_mm {
                Some(r) => src.non_negative(r, &format!("{p}.fillet_radius_mm"))? * 1e-3,
                None => 0.0,
            };
            EdgeProfile::Seamed(Seamed {
                top: arris(s.top.as_ref(), &format!("{p}.top"), src)?,
                bottom: arris(s.bottom.as_ref(), &format!("{p}.bottom"), src)?,
                fillet_radius_m,
            })
        }
        Some(EdgeDef::Pencil(p)) => {
            let radius = p.as_ref().and_then(|p| p.get_ref().radius_mm.as_ref());
            EdgeProfile::Pencil {
                radius_m: match radius {
                    Some(r) => Some(src.positive(r, &format!("{prefix}.pencil.radius_mm"))? * 1e-3),
                    None => None,
                },
            }
        }
        Some(EdgeDef::Arrissed(a)) => EdgeProfile::Arrissed {
            bevel_m: src.positive(
                &a.get_ref().bevel_mm,
                &format!("{prefix}.arrissed.bevel_mm"),
            )? * 1e-3,
        },
        Some(EdgeDef::Section(s)) => {
            let points = s.get_ref().points_mm.get_ref();
            let mut points_m = Vec::with_capacity(points.len());
            for (k, point) in points.iter().enumerate() {
                let [d, h] = point.get_ref();
                let field = |c: usize| format!("{prefix}.section.points_mm[{k}][{c}]");
                let d = src.non_negative(d, &field(0))?;
                let h = src.non_negative(h, &field(1))?;
                points_m.push([d * 1e-3, h * 1e-3]);
            }
            EdgeProfile::Section { points_m }
        }
    })
}

/// One arris; absent keys take the defaults (0.8 mm, 45°).
fn arris(
    def: Option<&Spanned<ArrisDef>>,
    prefix: &str,
    src: &SceneSource,
) -> Result<Arris, SceneError> {
    let def = def.map(Spanned::get_ref);
    let width_m = match def.and_then(|a| a.width_mm.as_ref()) {
        Some(w) => src.non_negative(w, &format!("{prefix}.width_mm"))? * 1e-3,
        None => DEFAULT_ARRIS_WIDTH_M,
    };
    let angle_rad = match def.and_then(|a| a.angle_deg.as_ref()) {
        Some(a) => src
            .number(
                a,
                &format!("{prefix}.angle_deg"),
                |a| (30.0..=65.0).contains(&a),
                "must be in [30, 65] degrees",
            )?
            .to_radians(),
        None => DEFAULT_ARRIS_ANGLE_RAD,
    };
    Ok(Arris { width_m, angle_rad })
}

/// Maps a `build_panel` error to the location of the scene-file field it names; a field this
/// loader does not know is reported at the `panel` table.
fn panel_error(
    e: &PanelError,
    def: &Spanned<PanelDef>,
    prefix: &str,
    src: &SceneSource,
) -> SceneError {
    let (field, index, message) = match e {
        PanelError::InvalidParameter { field, message } => (*field, None, message),
        PanelError::InvalidPoint {
            field,
            index,
            message,
        } => (*field, Some(*index), message),
    };
    let d = def.get_ref();
    let o = d.outline.get_ref();
    let outline = d.outline.span();
    let or = |v: &Option<Spanned<f64>>, fallback: &Range<usize>| {
        v.as_ref().map_or_else(|| fallback.clone(), Spanned::span)
    };
    let located: Option<(Range<usize>, String)> = match field {
        "thickness_mm" => Some((d.thickness_mm.span(), "thickness_mm".into())),
        "width_mm" => Some((or(&o.width_mm, &outline), "outline.width_mm".into())),
        "height_mm" => Some((or(&o.height_mm, &outline), "outline.height_mm".into())),
        "corner_radius_mm" => Some((
            or(&o.corner_radius_mm, &outline),
            "outline.corner_radius_mm".into(),
        )),
        "polygon_mm" | "vertices_mm" => Some((
            o.polygon_mm.as_ref().map_or(outline, Spanned::span),
            "outline.polygon_mm".into(),
        )),
        "radius_mm" => d
            .curvature
            .as_ref()
            .map(|c| (c.get_ref().radius_mm.span(), "curvature.radius_mm".into())),
        "tessellation_mm" => Some((
            or(&d.tessellation_mm, &def.span()),
            "tessellation_mm".into(),
        )),
        edge_field => edge_location(d.edge.as_ref(), edge_field, index),
    };
    match located {
        Some((span, name)) => src.invalid(&span, format!("{prefix}.{name}"), message.clone()),
        None if d.edge.is_none() && field.starts_with("seamed") => src.invalid(
            &def.span(),
            format!("{prefix}.edge"),
            format!(
                "(absent: seamed, 0.8 mm arrisses at 45°) {field} {message}; give the panel an \
                 `edge` that fits"
            ),
        ),
        None => src.invalid(&def.span(), prefix, format!("{field} {message}")),
    }
}

/// Where an edge field named by `geometry::panel` is written: the value if given, else the
/// nearest enclosing table in the file; with its field path under the panel.
fn edge_location(
    edge: Option<&Spanned<EdgeDef>>,
    field: &str,
    index: Option<usize>,
) -> Option<(Range<usize>, String)> {
    let edge = edge?;
    let at_edge = || Some((edge.span(), "edge".to_owned()));
    match (edge.get_ref(), field) {
        (EdgeDef::Arrissed(a), "bevel_mm") => {
            Some((a.get_ref().bevel_mm.span(), "edge.arrissed.bevel_mm".into()))
        }
        (EdgeDef::Pencil(p), "pencil.radius_mm") => {
            let r = p.as_ref().and_then(|p| p.get_ref().radius_mm.as_ref());
            Some(match r {
                Some(r) => (r.span(), "edge.pencil.radius_mm".into()),
                None => (edge.span(), "edge".into()),
            })
        }
        (EdgeDef::Section(s), "section.points_mm") => {
            let points = &s.get_ref().points_mm;
            Some(
                match index.and_then(|k| points.get_ref().get(k).map(|p| (k, p))) {
                    Some((k, p)) => (p.span(), format!("edge.section.points_mm[{k}]")),
                    None => (points.span(), "edge.section.points_mm".into()),
                },
            )
        }
        (EdgeDef::Seamed(None), f) if f.starts_with("seamed") => at_edge(),
        (EdgeDef::Seamed(Some(s)), f) if f.starts_with("seamed") => {
            Some(seamed_location(s, f, edge.span()))
        }
        _ => at_edge(),
    }
}

fn seamed_location(
    s: &Spanned<SeamedDef>,
    field: &str,
    edge_span: Range<usize>,
) -> (Range<usize>, String) {
    let def = s.get_ref();
    let path = format!("edge.{field}");
    let arris = |a: &Option<Spanned<ArrisDef>>, key: &str| {
        let Some(a) = a else {
            return s.span();
        };
        let value = match key {
            "width_mm" => a.get_ref().width_mm.as_ref(),
            _ => a.get_ref().angle_deg.as_ref(),
        };
        value.map_or_else(|| a.span(), Spanned::span)
    };
    let span = match field {
        "seamed.top.width_mm" => arris(&def.top, "width_mm"),
        "seamed.top.angle_deg" => arris(&def.top, "angle_deg"),
        "seamed.bottom.width_mm" => arris(&def.bottom, "width_mm"),
        "seamed.bottom.angle_deg" => arris(&def.bottom, "angle_deg"),
        "seamed.fillet_radius_mm" => def
            .fillet_radius_mm
            .as_ref()
            .map_or_else(|| s.span(), Spanned::span),
        "seamed" => s.span(),
        _ => edge_span,
    };
    (span, path)
}

#[cfg(test)]
mod tests {

    use crate::scene::test_scene;
    use crate::scene::world::World;
    use crate::scene::SceneError;

    const BASE: &str = r#"[materials.glass]
kind = "glass"
ior = 1.52
absorption_per_mm = 0.003
face_imperfection = 0.002
edge_roughness = 0.3

[[objects]]
name = "pane"
material = "glass"
[objects.panel]
outline = { width_mm = 300, height_mm = 200, corner_radius_mm = 10 }
thickness_mm = 4
EDGE

[target]
object = "pane"

[sensor]
preset = "scancontrol-2600-100"
"#;

    fn load(edge: &str) -> Result<World, SceneError> {
        test_scene::load_text(&BASE.replace("EDGE", edge))
    }

    /// `bad.toml:line:column:` of the first `needle` in the scene with `edge`.
    fn at(edge: &str, needle: &str) -> String {
        test_scene::location_of(&BASE.replace("EDGE", edge), needle)
    }

    fn error(edge: &str) -> String {
        test_scene::load_error(&BASE.replace("EDGE", edge))
    }

    /// The border's inset (m) from the 300 × 200 mm outline, on the straight side at x > 0.
    fn border_inset(edge: &str) -> f64 {
        let world = load(edge).unwrap_or_else(|e| panic!("{e}"));
        let border = &world.target.expect("target").border;
        let x = border
            .vertices
            .iter()
            .map(|v| v.position.x)
            .fold(f64::MIN, f64::max);
        0.15 - x
    }

    #[test]
    fn every_edge_form_loads_with_its_border() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        // Absent and "seamed": the 0.8 mm IGMA/PPG seam.
        assert!(close(border_inset(""), 0.8e-3));
        assert!(close(border_inset("edge = \"seamed\""), 0.8e-3));
        assert!(close(border_inset("edge = \"flat_ground\""), 0.0));
        assert!(close(border_inset("edge = \"pencil\""), 2e-3));
        assert!(close(
            border_inset("edge = { pencil = { radius_mm = 2 } }"),
            2e-3
        ));
        let d = 3e-3 - (9e-6f64 - 4e-6).sqrt();
        assert!(close(
            border_inset("edge = { pencil = { radius_mm = 3 } }"),
            d
        ));
        assert!(close(
            border_inset("edge = { arrissed = { bevel_mm = 0.5 } }"),
            0.5e-3
        ));
        let seamed = "edge = { seamed = { top = { width_mm = 0.8, angle_deg = 45 }, bottom = \
                      { width_mm = 0.5 }, fillet_radius_mm = 0.1 } }";
        let d = 0.8e-3 + 0.1e-3 * (std::f64::consts::PI / 8.0).tan();
        assert!(close(border_inset(seamed), d));
        assert!(close(border_inset("edge = { seamed = {} }"), 0.8e-3));
        assert!(close(
            border_inset("edge = { seamed = { top = { width_mm = 0 } } }"),
            0.0
        ));
        let section =
            "edge = { section = { points_mm = [[0.6, 4], [0, 3.4], [0, 0.6], [0.6, 0]] } }";
        assert!(close(border_inset(section), 0.6e-3));
    }

    #[test]
    fn edge_errors_name_the_field_at_its_place() {
        let e = "edge = { seamed = { top = { width_mm = 0.8, angle_deg = 70 } } }";
        let m = error(e);
        let expected = format!(
            "{} objects[0].panel.edge.seamed.top.angle_deg must be in [30, 65] degrees, got 70",
            at(e, "70")
        );
        assert_eq!(m, expected);
        let e = "edge = { seamed = { bottom = { width_mm = -0.1 } } }";
        assert_eq!(
            error(e),
            format!(
                "{} objects[0].panel.edge.seamed.bottom.width_mm must be ≥ 0, got -0.1",
                at(e, "-0.1")
            )
        );
        // Rules that need the geometry, at the value or the table they concern.
        let e = "edge = { seamed = { top = { width_mm = 2 }, bottom = { width_mm = 2 } } }";
        let m = error(e);
        assert!(
            m.starts_with(&format!(
                "{} objects[0].panel.edge.seamed must leave a wall",
                at(e, "{ top")
            )),
            "{m}"
        );
        let e = "edge = { seamed = { fillet_radius_mm = 3 } }";
        let m = error(e);
        assert!(
            m.starts_with(&format!(
                "{} objects[0].panel.edge.seamed.fillet_radius_mm is too large",
                at(e, "3 }")
            )),
            "{m}"
        );
        let e = "edge = { pencil = { radius_mm = 1 } }";
        let m = error(e);
        assert!(
            m.starts_with(&format!(
                "{} objects[0].panel.edge.pencil.radius_mm must be ≥ thickness/2",
                at(e, "1 }")
            )),
            "{m}"
        );
        let e = "edge = { section = { points_mm = [[0, 4], [0, 4.5], [0, 0]] } }";
        let m = error(e);
        assert!(
            m.starts_with(&format!(
                "{} objects[0].panel.edge.section.points_mm[1] height must be in [0, thickness",
                at(e, "[0, 4.5]")
            )),
            "{m}"
        );
        let e = "edge = { section = { points_mm = [[0.2, 4], [0.1, 0]] } }";
        let m = error(e);
        assert!(
            m.contains("objects[0].panel.edge.section.points_mm must reach the outline"),
            "{m}"
        );
        // A typo inside the seamed table is a parse error at the key, with its table.
        let e = "edge = { seamed = { top = { width = 0.8 } } }";
        let m = error(e);
        assert!(
            m.starts_with(&format!(
                "{} objects[0].panel.edge.seamed.top: unknown field `width`",
                at(e, "width = 0.8")
            )),
            "{m}"
        );
        let e = "edge = \"arrissed\"";
        assert!(error(e).contains("needs its parameters"));
    }

    #[test]
    fn the_seamed_default_is_named_when_it_does_not_fit() {
        // 1 mm glass cannot carry two 0.8 mm arrisses: the message says the edge is a default.
        let text = BASE
            .replace("thickness_mm = 4", "thickness_mm = 1")
            .replace("EDGE", "");
        let m = test_scene::load_text(&text)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("objects[0].panel.edge (absent: seamed, 0.8 mm arrisses at 45°)"),
            "{m}"
        );
        // A corner radius tighter than the seam's inset.
        let text = BASE
            .replace("corner_radius_mm = 10", "corner_radius_mm = 0.5")
            .replace("EDGE", "");
        let m = test_scene::load_text(&text)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(m.contains("objects[0].panel.outline.corner_radius_mm must be 0 or > the edge finish's deepest inset 0.8 mm"), "{m}");
    }
}
