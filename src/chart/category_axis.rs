//! The category (x) axis of bar charts: labels under evenly spaced slots, set horizontally when
//! they fit, otherwise rotated, shortened and, for very narrow slots, thinned, so that
//! neighbouring labels never overlap.

use std::f64::consts::FRAC_1_SQRT_2;

use super::frame::{fitted_text, text_width, Plot, FONT, MUTED};
use super::svg::{num, SvgWriter};

/// Longest a rotated label may run (longer ones are cut, the full text kept as a tooltip).
const MAX_ROTATED_PX: f64 = 110.0;

#[derive(Clone, Debug)]
pub(crate) struct CategoryAxis {
    font: f64,
    /// 0, -45 or -90 degrees.
    angle: f64,
    /// Label every `stride`-th slot.
    stride: usize,
    /// Space the labels need below the plot.
    pub height: f64,
    /// How far the first label reaches left of its slot's centre.
    pub overhang: f64,
}

impl CategoryAxis {
    /// Chooses the label layout for `labels` under slots `slot` pixels wide.
    pub fn layout(labels: &[&str], slot: f64) -> CategoryAxis {
        let widest = labels.iter().map(|l| text_width(l, FONT)).fold(0.0, f64::max);
        let first = labels.first().copied().unwrap_or("");
        if widest <= slot - 4.0 {
            let overhang = text_width(first, FONT) / 2.0;
            return CategoryAxis { font: FONT, angle: 0.0, stride: 1, height: FONT + 10.0, overhang };
        }
        // Rotated labels are stacked `slot·sin(angle)` apart across their baselines, which must
        // be at least a line height: -45° while that holds at full size, else -90° with a font
        // shrunk to the slot (to 7 px at least), and only then every n-th label.
        let (font, angle) = if slot * FRAC_1_SQRT_2 >= FONT + 1.0 {
            (FONT, -45.0)
        } else {
            ((slot - 1.0).clamp(7.0, FONT - 1.0), -90.0)
        };
        let across = if angle == -45.0 { slot * FRAC_1_SQRT_2 } else { slot };
        let stride = ((font + 1.0) / across).ceil().max(1.0) as usize;
        let run = (labels.iter().map(|l| text_width(l, font)).fold(0.0, f64::max)).min(MAX_ROTATED_PX);
        let (height, overhang) = if angle == -45.0 {
            ((run + font) * FRAC_1_SQRT_2 + 10.0, text_width(first, font).min(MAX_ROTATED_PX) * FRAC_1_SQRT_2)
        } else {
            (run + 10.0, font / 2.0)
        };
        CategoryAxis { font, angle, stride, height, overhang }
    }

    /// Draws `labels[i]` under the slot centred at `centre(i)`.
    pub fn draw(&self, w: &mut SvgWriter, plot: &Plot, labels: &[&str], centre: impl Fn(usize) -> f64) {
        for (i, label) in labels.iter().enumerate().step_by(self.stride) {
            let x = centre(i);
            if self.angle == 0.0 {
                fitted_text(w, label, f64::INFINITY, self.font, |t| {
                    t.attr("x", x)
                        .attr("y", plot.bottom + 6.0 + self.font)
                        .attr("text-anchor", "middle")
                        .attr("fill", MUTED)
                });
            } else {
                // The label ends at the slot; shifting the anchor by about a third of the font
                // centres the rotated glyphs on it.
                let (ax, ay) = if self.angle == -45.0 {
                    (x + self.font * 0.25, plot.bottom + 8.0 + self.font * 0.25)
                } else {
                    (x + self.font * 0.35, plot.bottom + 6.0)
                };
                let font = self.font;
                let angle = self.angle;
                fitted_text(w, label, MAX_ROTATED_PX, font, |t| {
                    t.attr("x", ax)
                        .attr("y", ay)
                        .attr("transform", format!("rotate({angle} {} {})", num(ax), num(ay)))
                        .attr("text-anchor", "end")
                        .attr("font-size", font)
                        .attr("fill", MUTED)
                });
            }
        }
    }
}
