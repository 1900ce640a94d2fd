//! Figures of the studies, drawn with plotters into PNG and SVG.
//!
//! Every figure is drawn once per backend by the same code (`Figure::draw`, generic over the
//! plotters backend): into an in-memory RGB buffer that is encoded as PNG, and into an SVG
//! string. Files are then written atomically (`io::atomic`), so a reader never sees half a
//! plot. Text uses DejaVu Sans, embedded in the binary (`assets/fonts/`, licence beside it) and
//! registered once: plotters' `ab_glyph` text needs a font from bytes, and the tool must not
//! depend on the fonts installed on the machine.
//!
//! One file per kind of figure: `edge_scatter` (the paper's Fig. 7: points in the edge frame),
//! `error_bars` (mean ± std against a swept value), `heat_map` (a value over a 2-D grid).

pub mod edge_scatter;
pub mod error_bars;
pub mod heat_map;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use image::ImageEncoder;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::io::atomic::write_atomic;
use crate::io::FileError;

/// DejaVu Sans (Bitstream Vera licence, see assets/fonts/LICENSE-DejaVu.txt).
static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The font family every figure uses.
pub const FONT: &str = "sans-serif";

/// Registers the embedded font under [`FONT`] the first time it is needed.
fn register_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, DEJAVU_SANS).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(PlotError::Draw(
            "the embedded DejaVu Sans font does not parse".into(),
        ))
    }
}

/// A failure to draw or to write a figure.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// plotters refused to draw (a degenerate range, a font problem).
    #[error("drawing the figure: {0}")]
    Draw(String),
    /// PNG encoding failed.
    #[error("encoding the PNG: {0}")]
    Encode(String),
    /// Writing a file failed.
    #[error(transparent)]
    Write(#[from] FileError),
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError::Draw(e.to_string())
    }
}

/// A figure that can draw itself on any plotters backend.
pub trait Figure {
    /// Size in pixels (SVG user units).
    fn size(&self) -> (u32, u32);
    /// Draws onto `root` (already filled white).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError>;
}

/// A figure rendered in both formats, in memory.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// PNG file contents (8-bit RGB).
    pub png: Vec<u8>,
    /// SVG document.
    pub svg: String,
}

/// Renders `figure` as PNG and SVG.
pub fn render(figure: &impl Figure) -> Result<Rendered, PlotError> {
    register_font()?;
    let (w, h) = figure.size();
    let mut rgb = vec![0u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE)?;
        figure.draw(&root)?;
        root.present()?;
    }
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&rgb, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| PlotError::Encode(e.to_string()))?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        root.fill(&WHITE)?;
        figure.draw(&root)?;
        root.present()?;
    }
    Ok(Rendered { png, svg })
}

/// Renders `figure` and writes `<dir>/<stem>.png` and `<dir>/<stem>.svg` atomically; returns
/// the two paths.
pub fn save(figure: &impl Figure, dir: &Path, stem: &str) -> Result<[PathBuf; 2], PlotError> {
    let r = render(figure)?;
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    write_atomic(&png, |w| w.write_all(&r.png))?;
    write_atomic(&svg, |w| w.write_all(r.svg.as_bytes()))?;
    Ok([png, svg])
}

/// A range `[lo, hi]` around finite `values` with a 5 % margin on each side; `fallback` when
/// there is no finite value, and widened to ±0.5 around a single value.
pub fn padded_range(values: impl Iterator<Item = f64>, fallback: (f64, f64)) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    if lo > hi {
        return fallback;
    }
    if hi - lo < 1e-9 {
        return (lo - 0.5, hi + 0.5);
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn padded_ranges() {
        assert_eq!(
            padded_range([0.0, 10.0].into_iter(), (0.0, 1.0)),
            (-0.5, 10.5)
        );
        assert_eq!(padded_range([f64::NAN].into_iter(), (0.0, 1.0)), (0.0, 1.0));
        assert_eq!(padded_range([2.0].into_iter(), (0.0, 1.0)), (1.5, 2.5));
    }
}

#[cfg(test)]
mod render_tests {
    use super::*;

    #[test]
    fn every_figure_renders_a_decodable_png_and_an_svg_with_its_text() {
        let scatter = edge_scatter::EdgeScatter {
            title: "edge".into(),
            cover: vec![(0.0, 5.0)],
            tape: vec![(-3.0, 0.1)],
            bare: vec![(0.1, -2.0), (500.0, 0.0)],
            bips: vec![(0.0, -0.1)],
            window: edge_scatter::EdgeScatter::EDGE_WINDOW,
        };
        let bars = error_bars::ErrorBars {
            title: "bars".into(),
            x_desc: "angle".into(),
            y_desc: "error".into(),
            series: vec![error_bars::Series {
                name: "highest rule".into(),
                points: vec![
                    (10.0, 1.0, 0.5),
                    (20.0, f64::NAN, f64::NAN),
                    (30.0, 0.2, 0.1),
                ],
            }],
        };
        let heat = heat_map::HeatMap {
            title: "heat".into(),
            x_desc: "angle".into(),
            x_labels: vec!["10".into(), "40".into()],
            y_desc: "exposure".into(),
            y_labels: vec!["0.1".into()],
            values: vec![vec![0.3, f64::NAN]],
            value_desc: "mm".into(),
            marked: Vec::new(),
        };
        fn check(r: Rendered, size: (u32, u32), text: &str) {
            let img = image::load_from_memory(&r.png).expect("the PNG decodes");
            assert_eq!((img.width(), img.height()), size);
            assert!(r.svg.starts_with("<svg") && r.svg.contains(text), "{text}");
        }
        check(render(&scatter).unwrap(), scatter.size(), "bare glass");
        check(render(&bars).unwrap(), bars.size(), "highest rule");
        check(render(&heat).unwrap(), heat.size(), "0.30");
        let dir = tempfile::tempdir().unwrap();
        let [png, svg] = save(&heat, dir.path(), "h").unwrap();
        assert!(png.is_file() && std::fs::metadata(&svg).unwrap().len() > 0);
    }
}
