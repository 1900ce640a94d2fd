//! A heat map: a value over a grid of two swept settings (the BIP error over scan angle ×
//! exposure), each cell coloured on a viridis-like ramp and labelled with its value, so the
//! figure reads without the colour bar. Missing values (no BIP) are grey and labelled "–".

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{Figure, PlotError, FONT};

/// The figure.
#[derive(Clone, Debug)]
pub struct HeatMap {
    /// Title above the plot.
    pub title: String,
    /// x-axis description and tick labels (one per column).
    pub x_desc: String,
    /// Column labels.
    pub x_labels: Vec<String>,
    /// y-axis description.
    pub y_desc: String,
    /// Row labels (bottom to top).
    pub y_labels: Vec<String>,
    /// `values[row][column]`; NaN is missing.
    pub values: Vec<Vec<f64>>,
    /// What the colour means, with its unit.
    pub value_desc: String,
    /// Cells to mark with a "*" after their value (`marked[row][column]`; empty: none), for a
    /// yes/no verdict drawn over the value it comes from.
    pub marked: Vec<Vec<bool>>,
}

/// Viridis at five stops (Smith & van der Walt, matplotlib's default colour map).
const VIRIDIS: [(u8, u8, u8); 5] = [
    (68, 1, 84),
    (59, 82, 139),
    (33, 145, 140),
    (94, 201, 98),
    (253, 231, 37),
];

/// The ramp colour of `t` in [0, 1] (linear between the stops).
pub fn ramp(t: f64) -> RGBColor {
    let t = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (t.floor() as usize).min(VIRIDIS.len() - 2);
    let f = t - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |x: u8, y: u8| (x as f64 + (y as f64 - x as f64) * f).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

impl Figure for HeatMap {
    fn size(&self) -> (u32, u32) {
        let w = 360 + 80 * self.x_labels.len().max(1) as u32;
        let h = 200 + 60 * self.y_labels.len().max(1) as u32;
        (w.max(720), h.max(360))
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let nx = self.x_labels.len();
        let ny = self.y_labels.len();
        let finite = self
            .values
            .iter()
            .flatten()
            .copied()
            .filter(|v| v.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
        // Errors span decades (a good setting 0.1 mm, a stray point 100 mm): colours follow the
        // logarithm when every value is positive.
        let log = lo > 0.0 && hi > lo;
        let scale = |v: f64| if log { v.ln() } else { v };
        let (slo, shi) = (scale(lo), scale(hi));
        let t_of = |v: f64| {
            if shi > slo {
                (scale(v) - slo) / (shi - slo)
            } else {
                0.5
            }
        };
        let (plot, bar) = root.split_horizontally(root.dim_in_pixel().0 as i32 - 110);
        let mut chart = ChartBuilder::on(&plot)
            .caption(&self.title, (FONT, 18))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..nx as f64, 0.0..ny as f64)?;
        // Categories have no numeric ticks: plotters' own tick labels are switched off and each
        // category is labelled at its cell centre, below (left of) the axis.
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_desc(self.x_desc.as_str())
            .y_desc(self.y_desc.as_str())
            .axis_desc_style((FONT, 14))
            .draw()?;
        let tick = TextStyle::from((FONT, 13).into_font());
        for (c, label) in self.x_labels.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(c as f64 + 0.5, 0.0));
            plot.draw(&Text::new(
                label.clone(),
                (px, py + 8),
                tick.pos(Pos::new(HPos::Center, VPos::Top)),
            ))?;
        }
        for (r, label) in self.y_labels.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(0.0, r as f64 + 0.5));
            plot.draw(&Text::new(
                label.clone(),
                (px - 8, py),
                tick.pos(Pos::new(HPos::Right, VPos::Center)),
            ))?;
        }
        let centred =
            TextStyle::from((FONT, 13).into_font()).pos(Pos::new(HPos::Center, VPos::Center));
        for (r, row) in self.values.iter().enumerate().take(ny) {
            for (c, &v) in row.iter().enumerate().take(nx) {
                let (x, y) = (c as f64, r as f64);
                let mark = self
                    .marked
                    .get(r)
                    .and_then(|m| m.get(c))
                    .is_some_and(|&m| m);
                let (fill, text) = if v.is_finite() {
                    (
                        ramp(t_of(v)),
                        format!("{v:.2}{}", if mark { " *" } else { "" }),
                    )
                } else {
                    (RGBColor(190, 190, 190), "–".to_owned())
                };
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(x, y), (x + 1.0, y + 1.0)],
                    fill.filled(),
                )))?;
                let ink = if v.is_finite() && t_of(v) <= 0.55 {
                    WHITE
                } else {
                    BLACK
                };
                chart.draw_series(std::iter::once(Text::new(
                    text,
                    (x + 0.5, y + 0.5),
                    centred.color(&ink),
                )))?;
            }
        }
        // The colour bar: 50 steps from the smallest to the largest value.
        if !lo.is_finite() {
            return Ok(());
        }
        let hi_bar = if hi > lo { hi } else { lo + 1.0 };
        let steps = 50;
        let mut builder = ChartBuilder::on(&bar);
        builder
            .margin_top(50)
            .margin_bottom(57)
            .margin_right(10)
            .y_label_area_size(55);
        let step_bounds = |k: usize| {
            let f = |j: usize| {
                let s = slo + (scale(hi_bar) - slo) * j as f64 / steps as f64;
                if log {
                    s.exp()
                } else {
                    s
                }
            };
            (f(k), f(k + 1))
        };
        let cells = (0..steps).map(|k| {
            let (a, b) = step_bounds(k);
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                ramp(k as f64 / (steps - 1) as f64).filled(),
            )
        });
        if log {
            let mut cb = builder.build_cartesian_2d(0.0..1.0, (lo..hi_bar).log_scale())?;
            cb.configure_mesh()
                .disable_mesh()
                .disable_x_axis()
                .y_desc(self.value_desc.as_str())
                .y_label_formatter(&|v| tick_label(*v))
                .label_style((FONT, 12))
                .axis_desc_style((FONT, 13))
                .draw()?;
            cb.draw_series(cells)?;
        } else {
            let mut cb = builder.build_cartesian_2d(0.0..1.0, lo..hi_bar)?;
            cb.configure_mesh()
                .disable_mesh()
                .disable_x_axis()
                .y_desc(self.value_desc.as_str())
                .y_label_formatter(&|v| tick_label(*v))
                .label_style((FONT, 12))
                .axis_desc_style((FONT, 13))
                .draw()?;
            cb.draw_series(cells)?;
        }
        Ok(())
    }
}

/// A colour-bar tick: three significant digits, no float noise (0.7, not 0.7000000000000001).
fn tick_label(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn tick_labels_have_no_float_noise() {
        assert_eq!(super::tick_label(0.7000000000000001), "0.7");
        assert_eq!(super::tick_label(0.30000000000000004), "0.3");
        assert_eq!(super::tick_label(1.36), "1.36");
        assert_eq!(super::tick_label(149.18), "149");
        assert_eq!(super::tick_label(0.0912), "0.0912");
    }

    use super::*;

    #[test]
    fn ramp_ends() {
        assert_eq!(ramp(0.0), RGBColor(68, 1, 84));
        assert_eq!(ramp(1.0), RGBColor(253, 231, 37));
        assert_eq!(ramp(2.0), ramp(1.0));
    }
}
