//! Objects fitted to a panel of the scene: `tape = { on = "pane", … }` and
//! `cover = { on = "pane", … }` (the paper's edge experiment, steps 1 and 2), built by
//! `geometry::panel::build_tape` / `build_cover` from the named panel's spec and placed at its
//! pose. Defaults (mm): tape 0.1 thick, 0.01 gap, 20 onto the face; cover 20 wide, 10 tall,
//! 0.01 gap (modelling choices: the paper gives no dimensions).

use std::ops::Range;

use serde_spanned::Spanned;

use super::error::{SceneError, SceneSource};
use super::file::{CoverDef, TapeDef};
use crate::geometry::mesh::Mesh;
use crate::geometry::panel::{build_cover, build_tape, CoverSpec, PanelError, PanelSpec, TapeSpec};

/// What a fitted object is, with its table.
pub(super) enum Fitted<'a> {
    Tape(&'a Spanned<TapeDef>),
    Cover(&'a Spanned<CoverDef>),
}

impl Fitted<'_> {
    /// `tape` or `cover`: the key and the word used in messages.
    pub(super) fn key(&self) -> &'static str {
        match self {
            Fitted::Tape(_) => "tape",
            Fitted::Cover(_) => "cover",
        }
    }

    /// The `on` value: the name of the panel object.
    pub(super) fn on(&self) -> &Spanned<String> {
        match self {
            Fitted::Tape(t) => &t.get_ref().on,
            Fitted::Cover(c) => &c.get_ref().on,
        }
    }

    /// Checks the values (`prefix` is the object's field path) and builds the mesh on `panel`,
    /// in the panel's model frame.
    pub(super) fn mesh(
        &self,
        panel: &PanelSpec,
        prefix: &str,
        src: &SceneSource,
    ) -> Result<Mesh, SceneError> {
        let mm = |v: &Option<Spanned<f64>>, name: &str, default_m: f64| match v {
            Some(v) => Ok(src.positive(v, &format!("{prefix}.{}.{name}", self.key()))? * 1e-3),
            None => Ok(default_m),
        };
        match self {
            Fitted::Tape(t) => {
                let (d, def) = (t.get_ref(), TapeSpec::default());
                let spec = TapeSpec {
                    thickness_m: mm(&d.thickness_mm, "thickness_mm", def.thickness_m)?,
                    gap_m: mm(&d.gap_mm, "gap_mm", def.gap_m)?,
                    onto_face_m: mm(&d.onto_face_mm, "onto_face_mm", def.onto_face_m)?,
                };
                build_tape(panel, &spec).map_err(|e| {
                    let span = |field: &str| match field {
                        "thickness_mm" => d.thickness_mm.as_ref(),
                        "gap_mm" => d.gap_mm.as_ref(),
                        "onto_face_mm" => d.onto_face_mm.as_ref(),
                        _ => None,
                    };
                    located(&e, span, t.span(), &format!("{prefix}.tape"), src)
                })
            }
            Fitted::Cover(c) => {
                let (d, def) = (c.get_ref(), CoverSpec::default());
                let spec = CoverSpec {
                    width_m: mm(&d.width_mm, "width_mm", def.width_m)?,
                    height_m: mm(&d.height_mm, "height_mm", def.height_m)?,
                    gap_m: mm(&d.gap_mm, "gap_mm", def.gap_m)?,
                };
                build_cover(panel, &spec).map_err(|e| {
                    let span = |field: &str| match field {
                        "width_mm" => d.width_mm.as_ref(),
                        "height_mm" => d.height_mm.as_ref(),
                        "gap_mm" => d.gap_mm.as_ref(),
                        _ => None,
                    };
                    located(&e, span, c.span(), &format!("{prefix}.cover"), src)
                })
            }
        }
    }
}

/// A builder error at the value of the field it names, or at the table when that value is a
/// default.
fn located<'a>(
    e: &PanelError,
    span_of: impl Fn(&str) -> Option<&'a Spanned<f64>>,
    table: Range<usize>,
    prefix: &str,
    src: &SceneSource,
) -> SceneError {
    let (field, message) = match e {
        PanelError::InvalidParameter { field, message } => (*field, message.clone()),
        PanelError::InvalidPoint {
            field,
            index,
            message,
        } => (*field, format!("[{index}] {message}")),
    };
    match span_of(field) {
        Some(v) => src.invalid(&v.span(), format!("{prefix}.{field}"), message),
        None => src.invalid(
            &table,
            format!("{prefix}.{field}"),
            format!("(default) {message}"),
        ),
    }
}

#[cfg(test)]
mod tests {

    use crate::geometry::mesh::SurfacePart;
    use crate::scene::test_scene;
    use crate::scene::world::World;
    use crate::scene::SceneError;

    const BASE: &str = r#"[materials.glass]
kind = "glass"
ior = 1.52
absorption_per_mm = 0.003
face_imperfection = 0.002
edge_roughness = 0.3

[materials.paper]
kind = "lambertian"
albedo = 0.7

[[objects]]
name = "pane"
material = "glass"
pose = { translation_mm = [1, 2, 0.01], rotation_deg = [0, 0, 5] }
[objects.panel]
outline = { width_mm = 300, height_mm = 200, corner_radius_mm = 30 }
thickness_mm = 4

[[objects]]
name = "table"
material = "paper"
box = { size_mm = [1000, 800, 20] }
pose = { translation_mm = [0, 0, -10] }

[[objects]]
name = "strip"
material = "paper"
label = "tape"
FITTED

[target]
object = "pane"

[sensor]
preset = "scancontrol-2600-100"
"#;

    fn load(fitted: &str) -> Result<World, SceneError> {
        test_scene::load_text(&BASE.replace("FITTED", fitted))
    }

    fn at(fitted: &str, needle: &str) -> String {
        test_scene::location_of(&BASE.replace("FITTED", fitted), needle)
    }

    fn error(fitted: &str) -> String {
        test_scene::load_error(&BASE.replace("FITTED", fitted))
    }

    #[test]
    fn tape_and_cover_sit_on_their_panel() {
        for fitted in [
            "tape = { on = \"pane\" }",
            "cover = { on = \"pane\", width_mm = 25 }",
        ] {
            let world = load(fitted).unwrap_or_else(|e| panic!("{e}"));
            let (pane, strip) = (&world.objects[0], &world.objects[2]);
            assert_eq!(strip.pose, pane.pose);
            strip.mesh.check().unwrap();
            assert!(strip.mesh.triangle_count() > 1000);
            assert!(strip.mesh.parts.iter().all(|&p| p == SurfacePart::Solid));
            assert_eq!(strip.label, crate::scene::world::ObjectLabel::Tape);
        }
    }

    #[test]
    fn fitted_objects_refuse_what_does_not_fit() {
        let f = "tape = { on = \"pane\" }\npose = { translation_mm = [0, 0, 1] }";
        assert_eq!(
            error(f),
            format!(
                "{} objects[2].pose must be absent: a tape is placed at the pose of the panel \
                 it is on (`on`)",
                at(f, "{ translation_mm = [0, 0, 1]")
            )
        );
        let f = "tape = { on = \"pan\" }";
        assert!(error(f).starts_with(&format!(
            "{} objects[2].tape.on: unknown object `pan`, expected one of `pane`, `table`, `strip`",
            at(f, "\"pan\"")
        )));
        let f = "cover = { on = \"table\" }";
        assert_eq!(
            error(f),
            format!(
                "{} objects[2].cover.on must name a panel object (a cover is fitted to a panel's \
                 edge), `table` is a box object",
                at(f, "\"table\" }")
            )
        );
        let f = "tape = { on = \"pane\", thickness_mm = -1 }";
        assert_eq!(
            error(f),
            format!(
                "{} objects[2].tape.thickness_mm must be > 0, got -1",
                at(f, "-1 }")
            )
        );
        // 40 mm in from the border passes the 30 mm corner radius.
        let f = "cover = { on = \"pane\", width_mm = 40 }";
        let m = error(f);
        assert!(
            m.starts_with(&format!(
                "{} objects[2].cover.width_mm reaches",
                at(f, "40 }")
            )),
            "{m}"
        );
        // A default that does not fit is reported at the table.
        let f = "cover = { on = \"pane\", gap_mm = 20 }";
        let m = error(f);
        assert!(
            m.starts_with(&format!(
                "{} objects[2].cover.height_mm (default) must be >",
                at(f, "{ on")
            )),
            "{m}"
        );
        let f = "tape = { on = \"pane\", thicknes_mm = 1 }";
        assert!(error(f).contains("objects[2].tape: unknown field `thicknes_mm`"));
        let f = "tape = { on = \"pane\" }\ncover = { on = \"pane\" }";
        assert!(error(f).contains("got both `tape` and `cover`"));
        let f = "tape = { on = \"pane\" }";
        let glass = BASE.replace("FITTED", f).replacen(
            "material = \"paper\"\nlabel",
            "material = \"glass\"\nlabel",
            1,
        );
        let m = test_scene::load_text(&glass)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("objects[2].material must be a lambertian material"),
            "{m}"
        );
        let target = BASE
            .replace("FITTED", f)
            .replace("object = \"pane\"", "object = \"strip\"");
        let m = test_scene::load_text(&target)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("object `strip` is a tape object, expected a panel or mesh object"),
            "{m}"
        );
    }
}
