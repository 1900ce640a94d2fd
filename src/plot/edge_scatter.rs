//! The paper's Fig. 7: the profile points of the edge experiment in the edge frame of p_e
//! (x = out_mm, outward from the edge, negative over the glass; y = up_mm above p_e). In the
//! paper's style: cover = blue crosses, tape = green squares, bare glass = red dots; plus p_e
//! (black plus) and the bare pane's BIPs (black rings), which the paper's figure only implies.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{Figure, PlotError, FONT};

/// The data of one edge plot.
#[derive(Clone, Debug, Default)]
pub struct EdgeScatter {
    /// Title above the plot.
    pub title: String,
    /// Cover points (out_mm, up_mm).
    pub cover: Vec<(f64, f64)>,
    /// Tape points.
    pub tape: Vec<(f64, f64)>,
    /// Bare-glass points.
    pub bare: Vec<(f64, f64)>,
    /// BIPs of the bare pane (paper's rule).
    pub bips: Vec<(f64, f64)>,
    /// Plotted window: out range and up range (mm). Points outside are left out (they stay in
    /// the CSV).
    pub window: ((f64, f64), (f64, f64)),
}

impl EdgeScatter {
    /// The window of the edge study: 20 mm over the glass to 10 mm outside, from 6 mm below
    /// p_e (the table is at −4 mm) to 12 mm above (the 10 mm cover's top).
    pub const EDGE_WINDOW: ((f64, f64), (f64, f64)) = ((-20.0, 10.0), (-6.0, 12.0));
}

fn inside(w: &((f64, f64), (f64, f64))) -> impl Fn(&&(f64, f64)) -> bool + '_ {
    move |p| p.0 >= w.0 .0 && p.0 <= w.0 .1 && p.1 >= w.1 .0 && p.1 <= w.1 .1
}

impl Figure for EdgeScatter {
    fn size(&self) -> (u32, u32) {
        (900, 560)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let ((x0, x1), (y0, y1)) = self.window;
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FONT, 20))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(55)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc("out (mm): outward from p_e, negative over the glass")
            .y_desc("up (mm) above p_e")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 15))
            .light_line_style(WHITE.mix(0.0))
            .draw()?;
        let keep = inside(&self.window);
        let blue = BLUE.stroke_width(1);
        chart
            .draw_series(
                self.cover
                    .iter()
                    .filter(&keep)
                    .map(|&p| Cross::new(p, 4, blue)),
            )?
            .label(format!("cover ({} points)", self.cover.len()))
            .legend(|p| Cross::new(p, 4, BLUE.stroke_width(1)));
        let green = RGBColor(0, 150, 0);
        chart
            .draw_series(self.tape.iter().filter(&keep).map(|&p| {
                EmptyElement::at(p) + Rectangle::new([(-3, -3), (3, 3)], green.stroke_width(1))
            }))?
            .label(format!("tape ({} points)", self.tape.len()))
            .legend(move |p| {
                EmptyElement::at(p) + Rectangle::new([(-3, -3), (3, 3)], green.stroke_width(1))
            });
        chart
            .draw_series(
                self.bare
                    .iter()
                    .filter(&keep)
                    .map(|&p| Circle::new(p, 2, RED.filled())),
            )?
            .label(format!("bare glass ({} points)", self.bare.len()))
            .legend(|p| Circle::new(p, 2, RED.filled()));
        chart
            .draw_series(
                self.bips
                    .iter()
                    .filter(&keep)
                    .map(|&p| Circle::new(p, 6, BLACK.stroke_width(2))),
            )?
            .label("BIP, highest point (bare)")
            .legend(|p| Circle::new(p, 6, BLACK.stroke_width(2)));
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((0.0, 0.0))
                    + PathElement::new(vec![(-9, 0), (9, 0)], BLACK.stroke_width(2))
                    + PathElement::new(vec![(0, -9), (0, 9)], BLACK.stroke_width(2)),
            ))?
            .label("p_e (edge line)")
            .legend(|p| {
                EmptyElement::at(p)
                    + PathElement::new(vec![(-6, 0), (6, 0)], BLACK.stroke_width(2))
                    + PathElement::new(vec![(0, -6), (0, 6)], BLACK.stroke_width(2))
            });
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    }
}
