//! Reading the `edge` key: a kind's name or a one-key table naming a kind.
//!
//! `edge = "seamed"` and `edge = { seamed = { top = { width_mm = 0.5 } } }` must both mean
//! the seamed edge, which serde's derived enums cannot express (a variant is either a name or
//! a table). This visitor takes the value as it comes: a string is a kind with every parameter
//! at its default, a table must have exactly one key, the kind, whose value is read straight
//! from the TOML deserializer into the kind's struct, so spans and unknown-key errors keep
//! their places in the file.

use std::fmt;

use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use serde_spanned::Spanned;

use super::file::{ArrissedDef, EdgeDef, PencilDef, SeamedDef, SectionDef};

/// The kinds that can be given by name alone.
const NAMED: &[&str] = &["seamed", "flat_ground", "pencil"];
/// The kinds that take a table of parameters.
const TABLES: &[&str] = &["seamed", "pencil", "arrissed", "section"];

impl<'de> Deserialize<'de> for EdgeDef {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(EdgeVisitor)
    }
}

struct EdgeVisitor;

impl<'de> Visitor<'de> for EdgeVisitor {
    type Value = EdgeDef;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(
            "an edge kind: \"seamed\", \"flat_ground\", \"pencil\", or a table with one of \
             `seamed`, `pencil`, `arrissed`, `section`",
        )
    }

    fn visit_str<E: de::Error>(self, name: &str) -> Result<EdgeDef, E> {
        match name {
            "seamed" => Ok(EdgeDef::Seamed(None)),
            "flat_ground" => Ok(EdgeDef::FlatGround),
            "pencil" => Ok(EdgeDef::Pencil(None)),
            "arrissed" | "section" => Err(E::custom(format!(
                "`{name}` needs its parameters: write `{{ {name} = {{ … }} }}` (scenes/README.md)"
            ))),
            _ => Err(E::unknown_variant(name, NAMED)),
        }
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<EdgeDef, A::Error> {
        let Some(kind) = map.next_key::<String>()? else {
            return Err(de::Error::custom(
                "is an empty table, expected one edge kind (`seamed`, `pencil`, `arrissed`, \
                 `section`)",
            ));
        };
        let edge = match kind.as_str() {
            "seamed" => EdgeDef::Seamed(Some(map.next_value::<Spanned<SeamedDef>>()?)),
            "pencil" => EdgeDef::Pencil(Some(map.next_value::<Spanned<PencilDef>>()?)),
            "arrissed" => EdgeDef::Arrissed(map.next_value::<Spanned<ArrissedDef>>()?),
            "section" => EdgeDef::Section(map.next_value::<Spanned<SectionDef>>()?),
            "flat_ground" => {
                return Err(de::Error::custom(
                    "`flat_ground` has no parameters: write `edge = \"flat_ground\"`",
                ))
            }
            other => return Err(de::Error::unknown_variant(other, TABLES)),
        };
        if let Some(extra) = map.next_key::<String>()? {
            return Err(de::Error::custom(format!(
                "must name one edge kind, got `{kind}` and `{extra}`"
            )));
        }
        Ok(edge)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    struct Wrap {
        edge: Spanned<EdgeDef>,
    }

    fn parse(text: &str) -> Result<EdgeDef, String> {
        toml::from_str::<Wrap>(text)
            .map(|w| w.edge.into_inner())
            .map_err(|e| format!("{:?}: {}", e.span(), e.message()))
    }

    #[test]
    fn names_and_tables_of_one_kind_both_parse() {
        assert!(matches!(
            parse("edge = \"seamed\""),
            Ok(EdgeDef::Seamed(None))
        ));
        assert!(matches!(
            parse("edge = \"pencil\""),
            Ok(EdgeDef::Pencil(None))
        ));
        assert!(matches!(
            parse("edge = \"flat_ground\""),
            Ok(EdgeDef::FlatGround)
        ));
        let Ok(EdgeDef::Seamed(Some(s))) = parse(
            "edge = { seamed = { top = { width_mm = 0.8, angle_deg = 45 }, bottom = { width_mm \
             = 0.5 }, fillet_radius_mm = 0.1 } }",
        ) else {
            panic!("seamed table");
        };
        let s = s.into_inner();
        let top = s.top.unwrap().into_inner();
        assert_eq!(*top.angle_deg.unwrap().get_ref(), 45.0);
        assert!(s.bottom.unwrap().into_inner().angle_deg.is_none());
        assert_eq!(*s.fillet_radius_mm.unwrap().get_ref(), 0.1);
        let Ok(EdgeDef::Pencil(Some(p))) = parse("edge = { pencil = { radius_mm = 3 } }") else {
            panic!("pencil table");
        };
        assert_eq!(*p.into_inner().radius_mm.unwrap().get_ref(), 3.0);
        let Ok(EdgeDef::Section(s)) =
            parse("edge = { section = { points_mm = [[0.6, 4], [0, 3.4], [0, 0.6], [0.6, 0]] } }")
        else {
            panic!("section table");
        };
        assert_eq!(s.into_inner().points_mm.into_inner().len(), 4);
        assert!(matches!(
            parse("edge = { arrissed = { bevel_mm = 0.5 } }"),
            Ok(EdgeDef::Arrissed(_))
        ));
    }

    #[test]
    fn bad_edges_keep_their_place() {
        let text = "edge = { seamed = { top = { width = 0.8 } } }";
        let e = parse(text).unwrap_err();
        // The unknown key is reported where it stands.
        assert!(
            e.starts_with(&format!("Some({}..", text.find("width").unwrap())),
            "{e}"
        );
        assert!(
            e.contains("unknown field `width`, expected `width_mm` or `angle_deg`"),
            "{e}"
        );
        let e = parse("edge = \"seamd\"").unwrap_err();
        assert!(
            e.contains("unknown variant `seamd`, expected one of `seamed`"),
            "{e}"
        );
        let e = parse("edge = \"section\"").unwrap_err();
        assert!(e.contains("needs its parameters"), "{e}");
        let e = parse("edge = { seamed = {}, pencil = {} }").unwrap_err();
        // toml 0.9 hands the keys over in sorted order.
        assert!(
            e.contains("must name one edge kind, got `pencil` and `seamed`"),
            "{e}"
        );
        let e = parse("edge = {}").unwrap_err();
        assert!(e.contains("empty table"), "{e}");
        let e = parse("edge = { flat_ground = {} }").unwrap_err();
        assert!(e.contains("has no parameters"), "{e}");
        let e = parse("edge = 4").unwrap_err();
        assert!(e.contains("expected an edge kind"), "{e}");
    }
}
