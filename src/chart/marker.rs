//! Point markers. Each series gets a shape as well as a colour, so series stay apart in
//! greyscale print and once the palette cycles.

use super::svg::{num, SvgWriter, Tag};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    TriangleDown,
}

impl Marker {
    const ALL: [Marker; 5] =
        [Marker::Circle, Marker::Square, Marker::Triangle, Marker::Diamond, Marker::TriangleDown];

    pub fn for_series(i: usize) -> Marker {
        Self::ALL[i % Self::ALL.len()]
    }

    /// Starts the marker's element centred on (`cx`, `cy`) with "radius" `r`; the caller adds
    /// attributes and finishes it (open, to give it a `<title>`, or empty).
    pub fn start<'a>(self, w: &'a mut SvgWriter, cx: f64, cy: f64, r: f64, fill: &str) -> Tag<'a> {
        let polygon = |w: &'a mut SvgWriter, pts: &[(f64, f64)]| {
            let points: Vec<String> =
                pts.iter().map(|(x, y)| format!("{},{}", num(cx + x), num(cy + y))).collect();
            w.tag("polygon").attr("points", points.join(" "))
        };
        // Shapes are scaled to look about as heavy as the circle.
        let tag = match self {
            Marker::Circle => w.tag("circle").attr("cx", cx).attr("cy", cy).attr("r", r),
            Marker::Square => {
                let h = r * 0.9;
                w.tag("rect")
                    .attr("x", cx - h)
                    .attr("y", cy - h)
                    .attr("width", 2.0 * h)
                    .attr("height", 2.0 * h)
            }
            Marker::Triangle => {
                let h = r * 1.2;
                polygon(w, &[(0.0, -h), (h * 0.95, h * 0.7), (-h * 0.95, h * 0.7)])
            }
            Marker::TriangleDown => {
                let h = r * 1.2;
                polygon(w, &[(0.0, h), (h * 0.95, -h * 0.7), (-h * 0.95, -h * 0.7)])
            }
            Marker::Diamond => {
                let h = r * 1.25;
                polygon(w, &[(0.0, -h), (h, 0.0), (0.0, h), (-h, 0.0)])
            }
        };
        tag.attr("fill", fill)
    }
}
