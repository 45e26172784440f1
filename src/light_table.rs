//! The light table: which emitting primitives next-event estimation picks from, and how often.
//! Built once per scene on the CPU as an alias table (Walker 1977, Vose 1991, as pbrt-v4's
//! `AliasTable`) and bound unchanged on the GPU (`lights` in `shaders/shared/scene.wgsl`), so
//! every method picks the same light from the same uniforms in O(1).
//!
//! Picking: column i = ⌊u·n⌋; keep its own light when u' < threshold(i), else take its alias.
//! Column i then carries threshold(i)/n of light i's probability and 1 − threshold(i) of its
//! alias's, and the columns together give each light w_i / Σw (in f64 here; the thresholds are
//! stored in f32, so each light's probability is exact to about 1e-7).

use crate::layout::LightEntry;

/// Emitted power of a light for choosing among them: its radiance averaged over the channels
/// (pbrt-v4's `PowerLightSampler` averages the spectrum) times its area, in f64 from the f32
/// records. The shaders compute the same quantity in f32 for the MIS density.
pub fn power(radiance: [f32; 3], area: f64) -> f64 {
    radiance.iter().map(|&c| c as f64).sum::<f64>() / 3.0 * area
}

/// The alias table of the lights in `slots` with non-negative `weights` (the same length).
/// Returns `None` when the weights do not add up to a positive finite total: then no
/// power-proportional choice exists, and the caller picks uniformly.
pub fn alias_table(slots: &[u32], weights: &[f64]) -> Option<Vec<LightEntry>> {
    assert_eq!(slots.len(), weights.len(), "one weight per light");
    let total: f64 = weights.iter().sum();
    let valid = |w: f64| w.is_finite() && w >= 0.0;
    if !(total > 0.0 && total.is_finite() && weights.iter().all(|&w| valid(w))) {
        return None;
    }
    let n = weights.len();
    // Each column's share of the light, scaled so that a column is worth 1.
    let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
    let mut entries: Vec<LightEntry> = slots
        .iter()
        .enumerate()
        .map(|(i, &slot)| LightEntry { slot, other: i as u32, ..Default::default() })
        .collect();
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
    // Vose: fill each under-full column with the rest from an over-full one.
    while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
        small.pop();
        entries[s].threshold = scaled[s] as f32;
        entries[s].other = l as u32;
        scaled[l] -= 1.0 - scaled[s];
        if scaled[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    // What is left is worth 1 up to rounding: keeps its own light.
    for i in small.into_iter().chain(large) {
        entries[i].threshold = 1.0;
        entries[i].other = i as u32;
    }
    Some(entries)
}

/// The uniform table: every column keeps its own light.
pub fn uniform_table(slots: &[u32]) -> Vec<LightEntry> {
    slots.iter().enumerate().map(|(i, &slot)| LightEntry { slot, other: i as u32, threshold: 1.0 }).collect()
}

/// Each light's probability under the table, in f64 (for tests and checks).
pub fn probabilities(table: &[LightEntry]) -> Vec<f64> {
    let n = table.len() as f64;
    let mut p = vec![0.0; table.len()];
    for (i, e) in table.iter().enumerate() {
        let keep = e.threshold as f64;
        p[i] += keep / n;
        p[e.other as usize] += (1.0 - keep) / n;
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_gives_each_light_its_share_of_the_power() {
        let weights = [0.5, 30.0, 0.0, 2.0, 2.0, 1e-3, 7.25];
        let slots: Vec<u32> = (10..17).collect();
        let table = alias_table(&slots, &weights).unwrap();
        let total: f64 = weights.iter().sum();
        for (i, p) in probabilities(&table).iter().enumerate() {
            let want = weights[i] / total;
            assert!((p - want).abs() <= 1e-7 * want.max(1e-3), "light {i}: {p} vs {want}");
            assert_eq!(table[i].slot, slots[i]);
        }
        // A light of no power is never kept, nor anyone's alias.
        assert_eq!(table[2].threshold, 0.0);
        assert!(table.iter().all(|e| e.other != 2));
    }

    #[test]
    fn no_table_without_positive_finite_power() {
        assert!(alias_table(&[0, 1], &[0.0, 0.0]).is_none());
        assert!(alias_table(&[0, 1], &[1.0, f64::INFINITY]).is_none());
        assert!(alias_table(&[0, 1], &[1.0, f64::NAN]).is_none());
        assert!(alias_table(&[], &[]).is_none());
    }

    #[test]
    fn equal_weights_and_the_uniform_table_keep_every_column() {
        let slots = [3, 5, 8];
        for table in [alias_table(&slots, &[2.0; 3]).unwrap(), uniform_table(&slots)] {
            assert!(table.iter().enumerate().all(|(i, e)| e.threshold == 1.0 && e.other == i as u32));
        }
    }
}
