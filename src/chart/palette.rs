//! Colours: a categorical palette safe for colour-vision deficiencies, and the viridis colormap.

use plotters::style::RGBColor;

/// The Okabe–Ito palette (Okabe & Ito, "Color Universal Design", 2002), distinguishable under
/// the common colour-vision deficiencies. Reordered so the first colours contrast best on white;
/// yellow and black come last (yellow is faint as a thin line, black reads as an axis). Then
/// four darker and lighter tones of its hues, because a wavefront's pass chart stacks up to a
/// dozen labels and a colour must not repeat within one chart.
pub const PALETTE: [RGBColor; 12] = [
    RGBColor(0x00, 0x72, 0xb2), // blue
    RGBColor(0xe6, 0x9f, 0x00), // orange
    RGBColor(0x00, 0x9e, 0x73), // bluish green
    RGBColor(0xd5, 0x5e, 0x00), // vermillion
    RGBColor(0xcc, 0x79, 0xa7), // reddish purple
    RGBColor(0x56, 0xb4, 0xe9), // sky blue
    RGBColor(0xf0, 0xe4, 0x42), // yellow
    RGBColor(0x00, 0x00, 0x00), // black
    RGBColor(0x7f, 0x3c, 0x8d), // dark purple
    RGBColor(0x8c, 0x6d, 0x31), // brown
    RGBColor(0xa0, 0xa0, 0xa0), // grey
    RGBColor(0x1b, 0x5e, 0x20), // dark green
];

/// The palette colour for the `i`-th series or segment, cycling after the last.
pub fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// `#rrggbb` for an RGB triple.
pub fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// matplotlib's viridis (van der Walt & Smith, CC0) sampled at t = i/32 and rounded to 8 bits;
/// linear interpolation between these stays within 2/255 of the 256-entry original.
const VIRIDIS: [[u8; 3]; 33] = [
    [68, 1, 84],
    [71, 13, 96],
    [72, 24, 106],
    [72, 35, 116],
    [71, 45, 123],
    [69, 54, 129],
    [66, 64, 134],
    [63, 73, 137],
    [59, 82, 139],
    [55, 90, 141],
    [51, 99, 141],
    [47, 106, 142],
    [44, 114, 142],
    [41, 122, 142],
    [38, 129, 142],
    [35, 137, 142],
    [33, 144, 140],
    [31, 152, 139],
    [31, 159, 136],
    [33, 166, 133],
    [40, 174, 128],
    [49, 181, 123],
    [62, 188, 116],
    [76, 194, 108],
    [93, 201, 99],
    [110, 206, 88],
    [130, 211, 76],
    [150, 216, 63],
    [171, 220, 50],
    [192, 223, 36],
    [213, 226, 26],
    [234, 229, 26],
    [253, 231, 37],
];

/// The viridis colour at `t` in [0, 1]: 0 is dark purple `#440154`, 1 is yellow `#fde725`.
/// Values outside [0, 1] are clamped; NaN maps to 0.
pub fn viridis(t: f32) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let pos = t * (VIRIDIS.len() - 1) as f32;
    let i = (pos.floor() as usize).min(VIRIDIS.len() - 2);
    let f = pos - i as f32;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    std::array::from_fn(|c| (a[c] as f32 + (b[c] as f32 - a[c] as f32) * f).round() as u8)
}
