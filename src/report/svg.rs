//! The page's own charts, written as SVG text: grouped bars with error whiskers (linear or log
//! scale) and x–y scatter/line plots. Used for what a run has no figure file of (a locate run's
//! per-pose errors, a dataset's distributions, our numbers against the paper's). Every text is
//! escaped; the output is checked well-formed in the tests.

use std::fmt::Write;

use super::format::num;
use super::html::escape;

/// Colours of series, in order (colour-blind-safe Tableau-like set).
pub const PALETTE: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
];
/// The colour of numbers quoted from the paper.
pub const PAPER_COLOR: &str = "#e6a100";

const W: f64 = 760.0;
const H: f64 = 400.0;
const LEFT: f64 = 78.0;
const RIGHT: f64 = 20.0;
const TOP: f64 = 48.0;
const BOTTOM: f64 = 78.0;

/// One series of bars: a value per category (`None`: no bar), and optional ± whiskers.
#[derive(Clone, Debug)]
pub struct BarSeries {
    /// Legend text.
    pub name: String,
    /// Fill colour.
    pub color: &'static str,
    /// One value per category.
    pub values: Vec<Option<f64>>,
    /// Half-lengths of the whiskers, one per category, or empty for none.
    pub errors: Vec<Option<f64>>,
}

/// Grouped bars over named categories.
#[derive(Clone, Debug)]
pub struct BarChart {
    /// Title above the plot.
    pub title: String,
    /// What the categories are.
    pub x_label: String,
    /// What the values are, with unit.
    pub y_label: String,
    /// Logarithmic value axis (values ≤ 0 get no bar).
    pub log_y: bool,
    /// Category names.
    pub categories: Vec<String>,
    /// The series.
    pub series: Vec<BarSeries>,
}

/// One series of an x–y plot.
#[derive(Clone, Debug)]
pub struct XySeries {
    /// Legend text.
    pub name: String,
    /// Colour.
    pub color: &'static str,
    /// The points (non-finite ones are left out).
    pub points: Vec<(f64, f64)>,
    /// Join the points by a line (in the given order) as well as marking them.
    pub line: bool,
}

/// Points (and lines) over two numeric axes.
#[derive(Clone, Debug)]
pub struct XyChart {
    /// Title above the plot.
    pub title: String,
    /// x axis label, with unit.
    pub x_label: String,
    /// y axis label, with unit.
    pub y_label: String,
    /// Logarithmic y axis (points with y ≤ 0 are left out).
    pub log_y: bool,
    /// The series.
    pub series: Vec<XySeries>,
}

/// A value axis: maps data to pixels and knows its ticks.
struct Scale {
    lo: f64,
    hi: f64,
    log: bool,
    p0: f64,
    p1: f64,
}

impl Scale {
    /// An axis over `values` (with a margin; including 0 for linear bars when `zero`).
    fn fit(values: &[f64], log: bool, zero: bool, p0: f64, p1: f64) -> Scale {
        let v: Vec<f64> = values
            .iter()
            .copied()
            .filter(|v| v.is_finite() && (!log || *v > 0.0))
            .collect();
        let (mut lo, mut hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                (l.min(x), h.max(x))
            });
        if lo > hi {
            (lo, hi) = if log { (0.1, 1.0) } else { (0.0, 1.0) };
        }
        if log {
            lo = 10f64.powf(lo.log10().floor());
            hi = 10f64.powf(hi.log10().ceil());
            if hi <= lo {
                hi = lo * 10.0;
            }
        } else {
            if zero {
                lo = lo.min(0.0);
                hi = hi.max(0.0);
            }
            if hi - lo < 1e-12 {
                lo -= 0.5;
                hi += 0.5;
            }
            let step = nice_step(hi - lo);
            lo = (lo / step).floor() * step;
            hi = (hi / step).ceil() * step;
        }
        Scale {
            lo,
            hi,
            log,
            p0,
            p1,
        }
    }

    fn t(&self, v: f64) -> f64 {
        if self.log {
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    /// The pixel of `v` (clamped to the axis).
    fn px(&self, v: f64) -> f64 {
        let t = self.t(v).clamp(0.0, 1.0);
        self.p0 + t * (self.p1 - self.p0)
    }

    fn ticks(&self) -> Vec<f64> {
        if self.log {
            let (a, b) = (
                self.lo.log10().round() as i32,
                self.hi.log10().round() as i32,
            );
            (a..=b).map(|e| 10f64.powi(e)).collect()
        } else {
            let step = nice_step(self.hi - self.lo);
            let n = ((self.hi - self.lo) / step).round() as i64;
            (0..=n).map(|k| self.lo + k as f64 * step).collect()
        }
    }
}

/// A step of 1, 2 or 5 × 10^k giving about 5 intervals over `span`.
fn nice_step(span: f64) -> f64 {
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let f = f - 1e-9;
    mag * if f <= 1.0 {
        1.0
    } else if f <= 2.0 {
        2.0
    } else if f <= 5.0 {
        5.0
    } else {
        10.0
    }
}

/// A tick label: integers without decimals, the rest by [`num`].
fn tick_label(v: f64) -> String {
    if v.abs() < 1e-12 {
        "0".into()
    } else if (v - v.round()).abs() < 1e-9 && v.abs() < 1e6 {
        format!("{}", v.round() as i64)
    } else {
        num(v)
    }
}

/// The frame of every chart: the document, title, y axis with grid and ticks, the axis labels
/// and the legend.
fn frame(
    s: &mut String,
    title: &str,
    x_label: &str,
    y_label: &str,
    y: &Scale,
    legend: &[(&str, &str)],
) {
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{W}\" height=\"{H}\" \
         viewBox=\"0 0 {W} {H}\" font-family=\"sans-serif\" role=\"img\">\
         <title>{t}</title><rect x=\"0\" y=\"0\" width=\"{W}\" height=\"{H}\" fill=\"#ffffff\"/>\
         <text x=\"{cx}\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">{t}</text>",
        t = escape(title),
        cx = W / 2.0
    );
    for v in y.ticks() {
        let py = y.px(v);
        let _ = write!(
            s,
            "<line x1=\"{LEFT}\" y1=\"{py:.1}\" x2=\"{x2}\" y2=\"{py:.1}\" stroke=\"#e4e4e4\"/>\
             <text x=\"{tx}\" y=\"{ty:.1}\" text-anchor=\"end\" font-size=\"11\">{l}</text>",
            x2 = W - RIGHT,
            tx = LEFT - 6.0,
            ty = py + 4.0,
            l = escape(&tick_label(v))
        );
    }
    let _ = write!(
        s,
        "<line x1=\"{LEFT}\" y1=\"{TOP}\" x2=\"{LEFT}\" y2=\"{yb}\" stroke=\"#333\"/>\
         <line x1=\"{LEFT}\" y1=\"{yb}\" x2=\"{xr}\" y2=\"{yb}\" stroke=\"#333\"/>\
         <text x=\"{cx}\" y=\"{H0}\" text-anchor=\"middle\" font-size=\"12\">{xl}</text>\
         <text transform=\"translate(18 {cy}) rotate(-90)\" text-anchor=\"middle\" font-size=\"12\">{yl}</text>",
        yb = H - BOTTOM,
        xr = W - RIGHT,
        cx = (LEFT + W - RIGHT) / 2.0,
        H0 = H - 10.0,
        cy = (TOP + H - BOTTOM) / 2.0,
        xl = escape(x_label),
        yl = escape(y_label)
    );
    let mut lx = LEFT + 8.0;
    for (name, color) in legend {
        let _ = write!(
            s,
            "<rect x=\"{lx:.1}\" y=\"32\" width=\"10\" height=\"10\" fill=\"{color}\"/>\
             <text x=\"{tx:.1}\" y=\"41\" font-size=\"11\">{n}</text>",
            tx = lx + 14.0,
            n = escape(name)
        );
        lx += 24.0 + 6.5 * name.chars().count() as f64;
    }
}

impl BarChart {
    /// The chart as an SVG document.
    pub fn to_svg(&self) -> String {
        let mut values = Vec::new();
        for s in &self.series {
            for (k, v) in s.values.iter().enumerate() {
                if let Some(v) = v {
                    let e = s.errors.get(k).copied().flatten().unwrap_or(0.0);
                    // Whiskers below zero are cut at the axis: errors are not negative.
                    let low = if *v >= 0.0 { (v - e).max(0.0) } else { v - e };
                    values.extend([v + e, if self.log_y { *v } else { low }]);
                }
            }
        }
        let y = Scale::fit(&values, self.log_y, true, H - BOTTOM, TOP);
        let legend: Vec<(&str, &str)> = self
            .series
            .iter()
            .map(|s| (s.name.as_str(), s.color))
            .collect();
        let mut s = String::new();
        frame(
            &mut s,
            &self.title,
            &self.x_label,
            &self.y_label,
            &y,
            &legend,
        );
        let n = self.categories.len().max(1) as f64;
        let slot = (W - LEFT - RIGHT) / n;
        let bar = (slot * 0.8) / self.series.len().max(1) as f64;
        let label_every = (self.categories.len() / 24).max(1);
        let base = if self.log_y { H - BOTTOM } else { y.px(0.0) };
        for (c, name) in self.categories.iter().enumerate() {
            let x0 = LEFT + c as f64 * slot + slot * 0.1;
            if c % label_every == 0 {
                let _ = write!(
                    s,
                    "<text x=\"{x:.1}\" y=\"{ty}\" text-anchor=\"middle\" font-size=\"11\">{l}</text>",
                    x = LEFT + (c as f64 + 0.5) * slot,
                    ty = H - BOTTOM + 16.0,
                    l = escape(name)
                );
            }
            for (k, series) in self.series.iter().enumerate() {
                let Some(v) = series.values.get(c).copied().flatten() else {
                    continue;
                };
                if !v.is_finite() || (self.log_y && v <= 0.0) {
                    continue;
                }
                let x = x0 + k as f64 * bar;
                let top = y.px(v);
                let (y0, h) = if top < base {
                    (top, base - top)
                } else {
                    (base, top - base)
                };
                let _ = write!(
                    s,
                    "<rect x=\"{x:.1}\" y=\"{y0:.1}\" width=\"{w:.1}\" height=\"{h:.1}\" fill=\"{col}\">\
                     <title>{t}</title></rect>",
                    w = (bar - 1.0).max(1.0),
                    col = series.color,
                    t = escape(&format!("{}, {}: {}", series.name, name, num(v)))
                );
                if let Some(e) = series.errors.get(c).copied().flatten().filter(|e| *e > 0.0) {
                    let lo = if self.log_y && v - e <= 0.0 {
                        y.lo
                    } else {
                        v - e
                    };
                    let cx = x + bar / 2.0;
                    let _ = write!(
                        s,
                        "<line x1=\"{cx:.1}\" y1=\"{a:.1}\" x2=\"{cx:.1}\" y2=\"{b:.1}\" stroke=\"#222\"/>",
                        a = y.px(lo),
                        b = y.px(v + e)
                    );
                }
            }
        }
        s += "</svg>";
        s
    }
}

impl XyChart {
    /// The chart as an SVG document.
    pub fn to_svg(&self) -> String {
        let ok = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite() && (!self.log_y || p.1 > 0.0);
        let xs: Vec<f64> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().filter(ok).map(|p| p.0))
            .collect();
        let ys: Vec<f64> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().filter(ok).map(|p| p.1))
            .collect();
        let x = Scale::fit(&xs, false, false, LEFT, W - RIGHT);
        let y = Scale::fit(&ys, self.log_y, false, H - BOTTOM, TOP);
        let legend: Vec<(&str, &str)> = self
            .series
            .iter()
            .map(|s| (s.name.as_str(), s.color))
            .collect();
        let mut s = String::new();
        frame(
            &mut s,
            &self.title,
            &self.x_label,
            &self.y_label,
            &y,
            &legend,
        );
        for v in x.ticks() {
            let _ = write!(
                s,
                "<text x=\"{px:.1}\" y=\"{ty}\" text-anchor=\"middle\" font-size=\"11\">{l}</text>",
                px = x.px(v),
                ty = H - BOTTOM + 16.0,
                l = escape(&tick_label(v))
            );
        }
        for series in &self.series {
            let pts: Vec<(f64, f64)> = series
                .points
                .iter()
                .filter(ok)
                .map(|p| (x.px(p.0), y.px(p.1)))
                .collect();
            if series.line && pts.len() > 1 {
                let path: Vec<String> = pts.iter().map(|(a, b)| format!("{a:.1},{b:.1}")).collect();
                let _ = write!(
                    s,
                    "<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\" points=\"{}\"/>",
                    series.color,
                    path.join(" ")
                );
            }
            for (px, py) in pts {
                let _ = write!(
                    s,
                    "<circle cx=\"{px:.1}\" cy=\"{py:.1}\" r=\"3\" fill=\"{}\"/>",
                    series.color
                );
            }
        }
        s += "</svg>";
        s
    }
}

#[cfg(test)]
mod tests {
    use super::super::xml_check::check_well_formed;
    use super::*;

    #[test]
    fn bar_charts_are_well_formed_with_a_bar_per_value_and_escaped_text() {
        let chart = BarChart {
            title: "BIP error <per pose> & rule".into(),
            x_label: "pose".into(),
            y_label: "|BIP − p_e| (mm)".into(),
            log_y: true,
            categories: vec!["0".into(), "1".into(), "2".into()],
            series: vec![
                BarSeries {
                    name: "edge-line".into(),
                    color: PALETTE[0],
                    values: vec![Some(0.1), None, Some(0.05)],
                    errors: vec![Some(0.5), None, None],
                },
                BarSeries {
                    name: "highest".into(),
                    color: PALETTE[1],
                    values: vec![Some(80.0), Some(0.0), Some(2.0)],
                    errors: Vec::new(),
                },
            ],
        };
        let svg = chart.to_svg();
        check_well_formed(&svg).unwrap();
        assert!(svg.contains("BIP error &lt;per pose&gt; &amp; rule"));
        // 4 bars with values > 0 on the log axis (None and 0 get none), one whisker.
        assert_eq!(svg.matches("<rect x=").count() - 1 - 2, 4, "{svg}");
        assert_eq!(svg.matches("stroke=\"#222\"").count(), 1);
        // Log ticks: decades from 0.01 to 100.
        for t in [">0.010<", ">0.100<", ">1<", ">10<", ">100<"] {
            assert!(svg.contains(t), "tick {t}");
        }
    }

    #[test]
    fn xy_charts_are_well_formed_and_skip_what_cannot_be_drawn() {
        let chart = XyChart {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            log_y: false,
            series: vec![XySeries {
                name: "s".into(),
                color: PALETTE[2],
                points: vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0)],
                line: true,
            }],
        };
        let svg = chart.to_svg();
        check_well_formed(&svg).unwrap();
        assert_eq!(svg.matches("<circle").count(), 2);
        assert_eq!(svg.matches("<polyline").count(), 1);
        // An empty chart still draws its frame.
        let empty = XyChart {
            series: Vec::new(),
            ..chart
        };
        check_well_formed(&empty.to_svg()).unwrap();
    }

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(10.0), 2.0);
        assert_eq!(nice_step(1.0), 0.2);
        assert_eq!(nice_step(300.0), 100.0);
        assert_eq!(nice_step(0.3), 0.1);
    }
}
