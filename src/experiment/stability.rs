//! Whether a run's time is a steady figure: the spread of its timed repetitions, a
//! distribution-free interval for their median, and the flags a results page shows (issue 47).
//!
//! On a GPU, clocks, power and temperature move under a benchmark, so one run's repetitions can
//! disagree (the H200's `regeneration.json`, run without warm-up: 0.1724 s and 0.1180 s for one
//! naive-megakernel job). A run is **unstable** when (max − min) / median of its timed
//! repetitions exceeds the config's `unstable_spread` (default 5%), and **cold** when a GPU
//! method ran its repetitions without any warm-up. Either flag means its times (and every ratio
//! built on them) are not to be quoted as findings; the pages mark them, and the docs tests
//! refuse a quoted figure that only a flagged run gives.

use super::report::{RunRecord, Stat};
// The verdict type lives with the record that stores it (report.rs), so the record does not
// depend on this file; its makers are here.
pub use super::report::Stability;

/// Written right after every figure of a flagged run on the results pages (`0.1180⚠`,
/// `0.07×⚠`), so a figure quoted from one can be refused (tests/suite/docs.rs).
pub const FLAG: &str = "⚠";

pub use super::config::DEFAULT_UNSTABLE_SPREAD;

/// The confidence the median's interval aims for (reached from 6 repetitions on; below that the
/// interval is min–max and its `confidence` says how much it holds).
pub const MEDIAN_CONFIDENCE: f64 = 0.95;

/// The spread of `stat` and its median's interval, flagged against `threshold`.
pub fn of_stat(stat: Option<&Stat>, threshold: f64, cold: bool) -> Stability {
    let (spread, interval) = match stat {
        Some(s) if s.values.len() >= 2 && s.median > 0.0 => {
            (Some((s.max - s.min) / s.median), Some(median_interval(&s.values, MEDIAN_CONFIDENCE)))
        }
        _ => (None, None),
    };
    Stability {
        spread,
        median_low: interval.map(|i| i.0),
        median_high: interval.map(|i| i.1),
        confidence: interval.map(|i| i.2),
        threshold,
        unstable: spread.is_some_and(|s| s > threshold),
        cold,
    }
}

/// A run's stability as its record tells it: the stored one, else computed from the
/// repetitions the record keeps (reports from before stability existed) with `threshold`.
pub fn of_run(r: &RunRecord, threshold: f64) -> Stability {
    r.stability.clone().unwrap_or_else(|| of_record(r, threshold))
}

/// A run's stability computed from its record: the spread of its timed repetitions against
/// `threshold`, and cold where a GPU method rendered no warm-up frame.
pub fn of_record(r: &RunRecord, threshold: f64) -> Stability {
    of_stat(r.timed_stat(), threshold, r.method_needs_gpu() && r.warmup == 0)
}

/// [`FLAG`] where `flagged`, else nothing: written right after each figure of a flagged run,
/// so that a quoted figure can be told from a steady one (tests/suite/docs.rs).
pub fn flag(flagged: bool) -> &'static str {
    if flagged {
        FLAG
    } else {
        ""
    }
}

/// The config's threshold as a report records it (`unstable_spread`), else the default.
pub fn threshold_of(config: &serde_json::Value) -> f64 {
    config.get("unstable_spread").and_then(serde_json::Value::as_f64).unwrap_or(DEFAULT_UNSTABLE_SPREAD)
}

/// The interval `[x(j), x(n−1−j)]` of the sorted `values` with the largest `j` whose
/// probability of holding the median is at least `confidence`: 1 − 2·P(Binomial(n, ½) ≤ j).
/// When even min–max falls short (fewer than 6 values for 95%), min–max and its probability.
/// Returns (low, high, probability).
pub fn median_interval(values: &[f64], confidence: f64) -> (f64, f64, f64) {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    assert!(n >= 1, "an interval needs a value");
    let coverage = |j: usize| 1.0 - 2.0 * binomial_half_cdf(n, j);
    let mut j = 0;
    while 2 * (j + 1) < n && coverage(j + 1) >= confidence {
        j += 1;
    }
    (v[j], v[n - 1 - j], coverage(j))
}

/// P(Binomial(n, ½) ≤ k).
fn binomial_half_cdf(n: usize, k: usize) -> f64 {
    let mut term = 0.5f64.powi(n as i32); // C(n, 0) / 2^n
    let mut sum = term;
    for i in 1..=k.min(n) {
        term *= (n + 1 - i) as f64 / i as f64;
        sum += term;
    }
    sum
}

/// `a / b` as an interval, from the intervals of its medians: [a_low / b_high, a_high / b_low].
/// Conservative: each end takes the worst of both.
pub fn ratio_interval(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 / b.1, a.1 / b.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stat(v: &[f64]) -> Stat {
        Stat::of(v).unwrap()
    }

    #[test]
    fn binomial_tail_matches_hand_counts() {
        assert!((binomial_half_cdf(3, 0) - 0.125).abs() < 1e-15);
        assert!((binomial_half_cdf(4, 1) - 5.0 / 16.0).abs() < 1e-15);
        assert!((binomial_half_cdf(10, 10) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn few_values_give_min_max_and_say_how_sure() {
        let (lo, hi, p) = median_interval(&[3.0, 1.0, 2.0], 0.95);
        assert_eq!((lo, hi), (1.0, 3.0));
        assert!((p - 0.75).abs() < 1e-12, "{p}");
        // Six values: min–max holds the median with 1 − 2/64.
        let (_, _, p) = median_interval(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 0.95);
        assert!((p - (1.0 - 2.0 / 64.0)).abs() < 1e-12);
    }

    #[test]
    fn many_values_narrow_the_interval() {
        let values: Vec<f64> = (0..20).map(f64::from).collect();
        let (lo, hi, p) = median_interval(&values, 0.95);
        // n = 20: [x(6), x(15)] (1-based) holds the median with 0.9586; [x(7), x(14)] with 0.8847.
        assert_eq!((lo, hi), (5.0, 14.0));
        assert!((0.95..0.96).contains(&p), "{p}");
    }

    #[test]
    fn spread_beyond_the_threshold_is_flagged() {
        // The H200's naive megakernel at rtiow-final 1200x675x64, warm-up 0: 46% apart.
        let s = of_stat(Some(&stat(&[0.1724, 0.1180])), DEFAULT_UNSTABLE_SPREAD, true);
        assert!(s.unstable && s.cold && s.flagged());
        assert!((s.spread.unwrap() - (0.1724 - 0.1180) / 0.1452).abs() < 1e-12);
        assert_eq!(s.reason(), "unstable: 37% spread; cold: no warm-up");
        // Within 1%: steady.
        let s = of_stat(Some(&stat(&[0.08685, 0.08679, 0.08696])), DEFAULT_UNSTABLE_SPREAD, false);
        assert!(!s.flagged() && s.reason().is_empty());
        assert_eq!(s.interval_or(0.0), (0.08679, 0.08696));
        // One repetition: no spread, nothing to flag but coldness.
        let s = of_stat(Some(&stat(&[1.0])), DEFAULT_UNSTABLE_SPREAD, false);
        assert!(s.spread.is_none() && !s.flagged());
        assert_eq!(s.interval_or(1.0), (1.0, 1.0));
    }

    #[test]
    fn ratio_interval_takes_the_worst_ends() {
        let (lo, hi) = ratio_interval((0.9, 1.1), (1.8, 2.2));
        assert!((lo - 0.9 / 2.2).abs() < 1e-15 && (hi - 1.1 / 1.8).abs() < 1e-15);
    }
}
