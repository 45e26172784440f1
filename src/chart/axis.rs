//! Numeric axes: linear and log10 scales, "nice" tick positions and compact tick labels.
//!
//! Tick values are built from exact decimals (`m × 10^e` parsed from text, which is correctly
//! rounded), so a tick meant to be 0.3 is the same `f64` as the literal `0.3`, never
//! `0.30000000000000004`, and tests can compare ticks with `==`.

/// One position on an axis. Labelled ticks get a gridline and a label; unlabelled ones (log-axis
/// minor ticks, skipped decades) only a short mark.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    pub value: f64,
    pub label: Option<String>,
}

/// A numeric axis: the data range it spans (`min < max`, both positive when `log`) and its ticks.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    pub log: bool,
    pub ticks: Vec<Tick>,
}

impl Axis {
    /// A linear axis covering `[lo, hi]`, extended outward to the [`nice_ticks`] around it.
    pub fn linear(lo: f64, hi: f64, target: usize) -> Axis {
        let values = nice_ticks(lo, hi, target);
        let step = tick_step(&values);
        let ticks = values.iter().map(|&v| Tick { value: v, label: Some(format_tick(v, step)) }).collect();
        let (min, max) = (values[0], values[values.len() - 1]);
        Axis { min, max, log: false, ticks }
    }

    /// A log10 axis covering `[lo, hi]` (both > 0), extended outward to whole decades.
    ///
    /// Labels: up to 2 decades, 1, 2 and 5 in each decade (the other integers get unlabelled
    /// marks); up to 6 decades, each decade with unlabelled 2..9 marks; beyond that, decades
    /// only, every n-th labelled so at most about 8 labels remain. A single value, or values
    /// within one decade boundary, get at least one full decade.
    pub fn log10(lo: f64, hi: f64) -> Axis {
        let (lo, hi) = if lo > 0.0 && hi > 0.0 && lo.is_finite() && hi.is_finite() {
            (lo.min(hi), lo.max(hi))
        } else {
            (1.0, 10.0)
        };
        let (mut e0, mut e1) = (floor_log10(lo), ceil_log10(hi));
        if e1 <= e0 {
            // lo == hi == 10^e: centre the value in two decades rather than put it on the edge.
            e0 -= 1;
            e1 += 1;
        }
        let decades = e1 - e0;
        let stride = if decades <= 8 { 1 } else { (decades + 7) / 8 };
        let mut ticks = Vec::new();
        for e in e0..=e1 {
            let mantissas: &[i64] = if e == e1 || decades > 6 { &[1] } else { &[1, 2, 3, 4, 5, 6, 7, 8, 9] };
            for &m in mantissas {
                let value = decimal(m, e);
                let labelled =
                    if decades <= 2 { matches!(m, 1 | 2 | 5) } else { m == 1 && e.rem_euclid(stride) == 0 };
                let label = labelled.then(|| format_tick(value, value));
                ticks.push(Tick { value, label });
            }
        }
        Axis { min: decimal(1, e0), max: decimal(1, e1), log: true, ticks }
    }

    /// Relabels the ticks as percentages (0.5 → "50%").
    pub fn percent(mut self) -> Axis {
        let values: Vec<f64> = self.ticks.iter().map(|t| t.value).collect();
        let step = tick_step(&values);
        for t in &mut self.ticks {
            if t.label.is_some() {
                t.label = Some(format!("{}%", format_tick(t.value * 100.0, step * 100.0)));
            }
        }
        self
    }

    /// Position of `v` along the axis: 0 at `min`, 1 at `max` (outside for values outside).
    pub fn fraction(&self, v: f64) -> f64 {
        if self.log {
            (v.log10() - self.min.log10()) / (self.max.log10() - self.min.log10())
        } else {
            (v - self.min) / (self.max - self.min)
        }
    }
}

/// Linear ticks on a 1-2-5 grid covering `[min, max]`.
///
/// The step is the smallest of 1, 2, 5 × 10^k that is at least `(max − min) / target`; the ticks
/// are every multiple of the step from the largest one ≤ `min` to the smallest one ≥ `max`, so
/// the first and last ticks enclose the data. Example: `nice_ticks(0.0, 0.93, 5)` is
/// `[0.0, 0.2, 0.4, 0.6, 0.8, 1.0]`. A zero-width range is first widened by 10% of its magnitude
/// on each side (±1 around zero); non-finite bounds give the ticks of `[0, 1]`.
pub fn nice_ticks(min: f64, max: f64, target: usize) -> Vec<f64> {
    let (lo, hi) = padded_range(min, max);
    let span = hi - lo;
    if !span.is_finite() {
        return vec![lo, hi];
    }
    let (m, e) = nice_step(span, target.max(1));
    let step = decimal(m, e);
    // The tolerance keeps a bound that sits on a multiple (up to rounding) from adding a tick.
    let i0 = (lo / step + 1e-9).floor();
    let i1 = (hi / step - 1e-9).ceil();
    if !(i0.abs() < 1e15 && i1.abs() < 1e15 && i1 - i0 <= 1000.0) {
        return vec![lo, hi];
    }
    (i0 as i64..=i1 as i64).map(|i| decimal(i * m, e)).collect()
}

/// The decades `10^k` from the largest one ≤ `min` to the smallest one ≥ `max`; empty unless
/// `0 < min ≤ max` are finite. Example: `log_ticks(1e-4, 1.0)` is `[1e-4, 1e-3, 1e-2, 0.1, 1.0]`.
pub fn log_ticks(min: f64, max: f64) -> Vec<f64> {
    if !(min > 0.0 && min <= max && max.is_finite()) {
        return Vec::new();
    }
    (floor_log10(min)..=ceil_log10(max)).map(|e| decimal(1, e)).collect()
}

/// Formats a tick value compactly, with as many digits as the tick `step` needs.
///
/// Magnitudes from 0.001 to 9999 are written plainly ("0.25", "1500"), 10^4 to 10^12 with SI
/// suffixes ("10k", "2.5M", "1G"), anything else in exponent form ("1e-4", "2.5e-5", "1e12").
/// Rounding to the step's precision removes floating-point noise such as 70.00000000000001.
pub fn format_tick(v: f64, step: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".to_string() } else { String::new() };
    }
    let step = step.abs();
    let step_exp = if step > 0.0 && step.is_finite() { floor_log10(step) } else { floor_log10(v.abs()) };
    // Two digits beyond the step's leading one allow steps such as 2.5 or 0.125.
    let sig = (floor_log10(v.abs()) - step_exp + 3).clamp(1, 15);
    format_sig(v, sig as usize)
}

/// Formats a data value for a tooltip: 6 significant digits in the style of [`format_tick`].
pub fn format_value(v: f64) -> String {
    if v == 0.0 {
        "0".to_string()
    } else if v.is_finite() {
        format_sig(v, 6)
    } else {
        // Tooltips only show drawn (finite) values, but say what it is rather than print "NaN".
        "not finite".to_string()
    }
}

/// `v` (finite, non-zero) rounded to `sig` significant digits, trailing zeros dropped.
fn format_sig(v: f64, sig: usize) -> String {
    // `{:e}` rounds correctly and reports the exponent after rounding (9.99 → 1.0e1).
    let sci = format!("{:.*e}", sig.saturating_sub(1), v.abs());
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let digits = digits.trim_end_matches('0');
    let digits = if digits.is_empty() { "0" } else { digits };
    let body = match exp {
        -3..=3 => place_point(digits, exp),
        4..=11 => {
            let group = exp / 3;
            let suffix = ["k", "M", "G"][group as usize - 1];
            format!("{}{suffix}", place_point(digits, exp - 3 * group))
        }
        _ => format!("{}e{exp}", place_point(digits, 0)),
    };
    if v < 0.0 {
        format!("-{body}")
    } else {
        body
    }
}

/// Writes the digits `d0 d1 d2 ...` as the decimal `d0.d1d2... × 10^exp`.
fn place_point(digits: &str, exp: i32) -> String {
    if exp < 0 {
        format!("0.{}{digits}", "0".repeat((-exp - 1) as usize))
    } else {
        let int_len = exp as usize + 1;
        if digits.len() <= int_len {
            format!("{digits}{}", "0".repeat(int_len - digits.len()))
        } else {
            format!("{}.{}", &digits[..int_len], &digits[int_len..])
        }
    }
}

/// Spacing of a list of evenly spaced ticks (1 when there is nothing to measure).
fn tick_step(values: &[f64]) -> f64 {
    match values {
        [a, b, ..] => b - a,
        [a] if *a != 0.0 => a.abs(),
        _ => 1.0,
    }
}

/// Sorts the bounds and gives a zero-width range a width, so scales never divide by zero.
fn padded_range(a: f64, b: f64) -> (f64, f64) {
    if !a.is_finite() || !b.is_finite() {
        return (0.0, 1.0);
    }
    let (lo, hi) = (a.min(b), a.max(b));
    if hi - lo <= lo.abs().max(hi.abs()) * 1e-12 {
        let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
        return (lo - d, hi + d);
    }
    (lo, hi)
}

/// The 1-2-5 step `m × 10^e` for a span divided into about `target` intervals.
fn nice_step(span: f64, target: usize) -> (i64, i32) {
    let raw = span / target as f64;
    let e = floor_log10(raw);
    let f = raw / decimal(1, e); // in [1, 10)
    match f {
        f if f <= 1.0 + 1e-9 => (1, e),
        f if f <= 2.0 + 1e-9 => (2, e),
        f if f <= 5.0 + 1e-9 => (5, e),
        _ => (1, e + 1),
    }
}

/// The `f64` nearest to `m × 10^e` (parsing is correctly rounded; `m as f64 * 10f64.powi(e)` is not).
pub(crate) fn decimal(m: i64, e: i32) -> f64 {
    format!("{m}e{e}").parse().unwrap_or(0.0)
}

/// `floor(log10(v))` for finite `v > 0`, exact at powers of ten (where `log10` may be an ulp off).
fn floor_log10(v: f64) -> i32 {
    let mut e = v.log10().floor() as i32;
    if decimal(1, e) > v {
        e -= 1;
    } else if decimal(1, e + 1) <= v {
        e += 1;
    }
    e
}

/// `ceil(log10(v))` for finite `v > 0`, exact at powers of ten.
fn ceil_log10(v: f64) -> i32 {
    let e = floor_log10(v);
    if decimal(1, e) == v {
        e
    } else {
        e + 1
    }
}
