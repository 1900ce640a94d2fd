//! Lines with error bars: a value's mean ± standard deviation against a swept setting, one
//! series per method (the BIP error against the scan angle, one line per BIP rule). A missing
//! mean (no BIP at that angle) breaks the line instead of being drawn as zero. The y axis is
//! logarithmic: errors span decades (a good setting 0.1 mm, a stray BIP on the far side of
//! the pane 80 mm), and on a linear axis the good settings all look like zero. A lower bar
//! that would reach zero or below is drawn to the bottom of the axis.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{padded_range, Figure, PlotError, FONT};

/// One series: name and (x, mean, std) points; NaN means is a gap.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// (x, mean, std) in axis units.
    pub points: Vec<(f64, f64, f64)>,
}

/// The figure.
#[derive(Clone, Debug)]
pub struct ErrorBars {
    /// Title above the plot.
    pub title: String,
    /// x-axis description.
    pub x_desc: String,
    /// y-axis description.
    pub y_desc: String,
    /// The series, drawn in order with distinct colours.
    pub series: Vec<Series>,
}

/// Colours of successive series (red, blue, green, …), readable in print.
const COLOURS: [RGBColor; 4] = [
    RGBColor(200, 30, 30),
    RGBColor(30, 60, 200),
    RGBColor(0, 140, 0),
    RGBColor(120, 0, 160),
];

impl Figure for ErrorBars {
    fn size(&self) -> (u32, u32) {
        (900, 560)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let all = || self.series.iter().flat_map(|s| s.points.iter());
        let (x0, x1) = padded_range(all().map(|p| p.0), (0.0, 90.0));
        let sd = |p: &(f64, f64, f64)| if p.2.is_finite() { p.2 } else { 0.0 };
        let positive = || all().map(|p| p.1).filter(|m| m.is_finite() && *m > 0.0);
        let y0 = positive().fold(f64::INFINITY, f64::min);
        let y1 = all()
            .filter(|p| p.1.is_finite())
            .map(|p| p.1 + sd(p))
            .fold(f64::NEG_INFINITY, f64::max);
        // A decade-aligned range around the means and the upper bars, 1 µm to 1 m if empty.
        let (y0, y1) = if y0.is_finite() && y1 > 0.0 {
            (
                10f64.powf(y0.log10().floor()),
                10f64.powf(y1.max(y0 * 10.0).log10().ceil()),
            )
        } else {
            (1e-3, 1e3)
        };
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FONT, 20))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(self.x_desc.as_str())
            .y_desc(self.y_desc.as_str())
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .draw()?;
        // Shift the series sideways by a fraction of the axis so their bars do not overlap.
        let n = self.series.len().max(1) as f64;
        for (k, s) in self.series.iter().enumerate() {
            let colour = COLOURS[k % COLOURS.len()];
            let dx = (k as f64 - (n - 1.0) / 2.0) * 0.004 * (x1 - x0);
            let pts: Vec<(f64, f64, f64)> = s
                .points
                .iter()
                .map(|&(x, m, sd)| (x + dx, m, if sd.is_finite() { sd } else { 0.0 }))
                .collect();
            for run in pts.split(|p| !(p.1.is_finite() && p.1 > 0.0)) {
                chart.draw_series(LineSeries::new(
                    run.iter().map(|p| (p.0, p.1)),
                    colour.stroke_width(2),
                ))?;
            }
            chart.draw_series(pts.iter().filter(|p| p.1.is_finite() && p.1 > 0.0).map(
                |&(x, m, sd)| {
                    PathElement::new(
                        vec![(x, (m - sd).max(0.0)), (x, m + sd)],
                        colour.stroke_width(1),
                    )
                },
            ))?;
            chart
                .draw_series(
                    pts.iter()
                        .filter(|p| p.1.is_finite() && p.1 > 0.0)
                        .map(|&(x, m, _)| Circle::new((x, m), 4, colour.filled())),
                )?
                .label(s.name.as_str())
                .legend(move |p| Circle::new(p, 4, colour.filled()));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    }
}
