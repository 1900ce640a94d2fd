//! The figures a run wrote as SVG files (plotters' output of `study`, `sweep`), read to be put
//! inline in the page. A listed figure that is missing, truncated or not an SVG document is an
//! error naming the file, never a broken page.

use std::path::Path;

use super::xml_check::check_well_formed;
use super::ReportError;

/// The SVG document of `dir/name`, without an XML declaration or doctype (which may not appear
/// inside HTML), checked to be one well-formed `<svg>` element.
pub fn read_svg(dir: &Path, name: &str, listed_in: &str) -> Result<String, ReportError> {
    let path = dir.join(name);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        ReportError::input(
            &path,
            format!("could not read the figure {listed_in} lists: {e}"),
        )
    })?;
    let mut body = text.trim_start();
    if body.starts_with("<?xml") {
        body = body[body.find("?>").map_or(body.len(), |e| e + 2)..].trim_start();
    }
    if body.starts_with("<!DOCTYPE") {
        body = body[body.find('>').map_or(body.len(), |e| e + 1)..].trim_start();
    }
    if !body.starts_with("<svg") {
        return Err(ReportError::input(
            &path,
            "expected an SVG document (starting with <svg), found other content",
        ));
    }
    check_well_formed(body)
        .map_err(|e| ReportError::input(&path, format!("expected a complete SVG document: {e}")))?;
    Ok(body.trim_end().to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_an_svg_and_refuses_damaged_ones_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(
            d.join("a.svg"),
            "<?xml version=\"1.0\"?>\n<svg width=\"2\" height=\"2\"><rect/></svg>\n",
        )
        .unwrap();
        assert_eq!(
            read_svg(d, "a.svg", "summary.json").unwrap(),
            "<svg width=\"2\" height=\"2\"><rect/></svg>"
        );
        std::fs::write(d.join("cut.svg"), "<svg width=\"2\"><rect/>").unwrap();
        let e = read_svg(d, "cut.svg", "summary.json")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cut.svg: expected a complete SVG document"),
            "{e}"
        );
        std::fs::write(d.join("png.svg"), "\u{89}PNG").unwrap();
        let e = read_svg(d, "png.svg", "summary.json")
            .unwrap_err()
            .to_string();
        assert!(e.contains("png.svg: expected an SVG document"), "{e}");
        let e = read_svg(d, "gone.svg", "summary.json")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("gone.svg: could not read the figure summary.json lists"),
            "{e}"
        );
    }
}
