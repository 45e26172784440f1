//! Dependency-free SVG charts for experiment reports: line charts (linear or log10 axes),
//! stacked and grouped bar charts, a colour-blind-safe palette and the viridis colormap.
//!
//! Every chart renders to a standalone SVG document of fixed size (720×420, sans-serif) that
//! also works inlined in HTML: it uses no ids, scripts or external resources. The output aims to
//! be honest:
//!
//! - each data point or bar carries a `<title>` tooltip with its series and values;
//! - log axes say "(log scale)" in their title;
//! - values that cannot be drawn (non-finite, or ≤ 0 on a log axis) are left out, never moved,
//!   and a footnote counts them; a line breaks where a point was left out;
//! - a chart with nothing to draw shows its title and a centred "no data" note;
//! - a zero-width data range is padded instead of dividing by zero.
//!
//! Data markers have `class="point"` and bars `class="bar"`, so reports and tests can find them.
//!
//! ```
//! use wavetrace::chart::{LineChart, Series};
//!
//! let chart = LineChart {
//!     title: "Error vs samples".into(),
//!     x_label: "samples per pixel".into(),
//!     y_label: "relMSE".into(),
//!     x_log: true,
//!     y_log: true,
//!     series: vec![Series { name: "wavefront".into(), points: vec![(1.0, 0.3), (16.0, 0.02), (256.0, 0.001)] }],
//! };
//! let svg = chart.to_svg();
//! assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
//! ```

mod axis;
mod bar_chart;
mod category_axis;
mod frame;
mod legend;
mod line_chart;
mod marker;
mod palette;
mod svg;

pub use axis::{format_tick, format_value, log_ticks, nice_ticks, Axis, Tick};
pub use bar_chart::{Bar, GroupedBarChart, StackedBarChart};
pub use line_chart::{LineChart, Series};
pub use palette::{color, hex, viridis, PALETTE};
pub use svg::escape;
