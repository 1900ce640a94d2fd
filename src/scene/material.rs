//! Materials of a scene file: Lambertian reflectors and glass, validated value by value.
//!
//! A glass material gives its index at the laser wavelength directly (`ior`) or through a
//! dispersion law (Cauchy or Sellmeier), plus its absorption, face imperfection and edge
//! roughness; all are required, so no glass physics is defaulted silently.

use std::ops::Range;

use serde_spanned::Spanned;

use super::error::{SceneError, SceneSource};
use super::file::{MaterialDef, MaterialKind};
use super::world::{GlassSpec, Material};

pub(super) fn material(
    name: &str,
    def: &Spanned<MaterialDef>,
    wavelength_m: f64,
    src: &SceneSource,
) -> Result<Material, SceneError> {
    let prefix = format!("materials.{name}");
    let d = def.get_ref();
    let field = |f: &str| format!("{prefix}.{f}");
    let glass_fields: [(&str, Option<Range<usize>>); 6] = [
        ("ior", d.ior.as_ref().map(Spanned::span)),
        ("cauchy", d.cauchy.as_ref().map(Spanned::span)),
        ("sellmeier", d.sellmeier.as_ref().map(Spanned::span)),
        (
            "absorption_per_mm",
            d.absorption_per_mm.as_ref().map(Spanned::span),
        ),
        (
            "face_imperfection",
            d.face_imperfection.as_ref().map(Spanned::span),
        ),
        (
            "edge_roughness",
            d.edge_roughness.as_ref().map(Spanned::span),
        ),
    ];
    match d.kind.get_ref() {
        MaterialKind::Lambertian => {
            if let Some((f, Some(span))) = glass_fields.iter().find(|(_, s)| s.is_some()) {
                return Err(src.invalid(
                    span,
                    field(f),
                    "is a glass field, but the material has kind = \"lambertian\" (expected only `albedo`)",
                ));
            }
            let Some(albedo) = &d.albedo else {
                return Err(src.invalid(
                    &def.span(),
                    prefix,
                    "is missing `albedo` (required for kind = \"lambertian\")",
                ));
            };
            let albedo = src.number(
                albedo,
                &field("albedo"),
                |a| (0.0..=1.0).contains(&a),
                "must be in [0, 1]",
            )?;
            Ok(Material::Lambertian { albedo })
        }
        MaterialKind::Glass => {
            if let Some(a) = &d.albedo {
                return Err(src.invalid(
                    &a.span(),
                    field("albedo"),
                    "is a lambertian field, but the material has kind = \"glass\"",
                ));
            }
            let laws: Vec<(&str, Range<usize>)> = glass_fields[..3]
                .iter()
                .filter_map(|(f, s)| s.clone().map(|s| (*f, s)))
                .collect();
            match laws.as_slice() {
                [_] => {}
                [] => {
                    return Err(src.invalid(
                        &def.span(),
                        prefix,
                        "must give exactly one index law (`ior`, `cauchy` or `sellmeier`), got none",
                    ))
                }
                [(a, _), (b, span), ..] => {
                    return Err(src.invalid(
                        span,
                        prefix,
                        format!("must give exactly one index law (`ior`, `cauchy` or `sellmeier`), got both `{a}` and `{b}`"),
                    ))
                }
            }
            let required = |v: &Option<Spanned<f64>>, f: &str| {
                v.as_ref().cloned().ok_or_else(|| {
                    src.invalid(
                        &def.span(),
                        prefix.clone(),
                        format!("is missing `{f}` (required for kind = \"glass\")"),
                    )
                })
            };
            let absorption = required(&d.absorption_per_mm, "absorption_per_mm")?;
            let imperfection = required(&d.face_imperfection, "face_imperfection")?;
            let roughness = required(&d.edge_roughness, "edge_roughness")?;
            let ior = match &d.ior {
                Some(v) => Some(src.number(v, &field("ior"), |n| n >= 1.0, "must be ≥ 1")?),
                None => None,
            };
            let cauchy = match &d.cauchy {
                Some(c) => {
                    let n = c.get_ref().len();
                    if !(1..=4).contains(&n) {
                        return Err(src.invalid(
                            &c.span(),
                            field("cauchy"),
                            format!("must hold 1 to 4 coefficients [A, B, C, D], got {n}"),
                        ));
                    }
                    let mut out = Vec::with_capacity(n);
                    for (k, v) in c.get_ref().iter().enumerate() {
                        out.push(src.finite(v, &format!("{prefix}.cauchy[{k}]"))?);
                    }
                    Some(out)
                }
                None => None,
            };
            let sellmeier = match &d.sellmeier {
                Some(s) => {
                    let s = s.get_ref();
                    let b = src.finite3(&s.b, &field("sellmeier.b"))?;
                    let mut c = [0.0; 3];
                    for (k, v) in s.c.iter().enumerate() {
                        c[k] = src.non_negative(v, &format!("{prefix}.sellmeier.c[{k}]"))?;
                    }
                    Some((b, c))
                }
                None => None,
            };
            let spec = GlassSpec {
                ior,
                cauchy,
                sellmeier,
                absorption_per_m: src.non_negative(&absorption, &field("absorption_per_mm"))? * 1e3,
                face_imperfection: src.number(
                    &imperfection,
                    &field("face_imperfection"),
                    |f| (0.0..1.0).contains(&f),
                    "must be in [0, 1)",
                )?,
                edge_roughness: src.non_negative(&roughness, &field("edge_roughness"))?,
            };
            let law = (d.cauchy.as_ref().map(|c| ("cauchy", c.span())))
                .or_else(|| d.sellmeier.as_ref().map(|c| ("sellmeier", c.span())));
            if let Some((law, span)) = law {
                let n = spec.index_at(wavelength_m);
                if !(n.is_finite() && n >= 1.0) {
                    return Err(src.invalid(
                        &span,
                        field(law),
                        format!(
                            "must give a refractive index ≥ 1 at the laser wavelength {:.1} nm, \
                             got n = {n}",
                            wavelength_m * 1e9
                        ),
                    ));
                }
            }
            Ok(Material::Glass(spec))
        }
    }
}
