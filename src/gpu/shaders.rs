//! WGSL entry shaders, composed from `shaders/` and validated by `build.rs`, which writes these
//! constants from the list in [`super::shader_variants`]: an entry without hooks is its source;
//! one with hooks a [`Shader`] holding a variant per subset of them.

pub use super::shader_variants::Hook;

/// An entry shader in every variant of its hooks.
pub struct Shader {
    /// Under `shaders/`.
    pub file: &'static str,
    pub hooks: &'static [Hook],
    /// Variant `i` has `hooks[k]` where bit `k` of `i` is set (`Entry::variants`).
    pub variants: &'static [&'static str],
}

impl Shader {
    /// The variant with no hook swapped in.
    pub fn plain(&self) -> &'static str {
        self.variants[0]
    }

    /// The variant with the hooks paired with `true` swapped in. Panics on a hook this entry
    /// has no variant of turned on: the list in `shader_variants.rs` lacks it, a bug.
    pub fn select(&self, hooks: &[(Hook, bool)]) -> &'static str {
        let mut i = 0;
        for &(hook, _) in hooks.iter().filter(|(_, on)| *on) {
            let Some(k) = self.hooks.iter().position(|&h| h == hook) else {
                panic!("{} has no {hook:?} variant (src/gpu/shader_variants.rs)", self.file);
            };
            i |= 1 << k;
        }
        self.variants[i]
    }
}

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

#[cfg(test)]
mod tests {
    use super::super::shader_variants::ENTRIES;
    use super::*;
    use std::collections::BTreeSet;

    /// build.rs composes and validates exactly the variants embedded: a variant composed that
    /// nothing embeds, or one embedded that was not composed, fails here.
    #[test]
    fn composed_variants_are_exactly_the_embedded_ones() {
        let composed: BTreeSet<String> = std::fs::read_dir(env!("OUT_DIR"))
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".wgsl"))
            .collect();
        let listed: BTreeSet<String> =
            ENTRIES.iter().flat_map(|e| e.variants().into_iter().map(|v| e.composed_name(&v))).collect();
        assert_eq!(composed, listed);
        // Each variant differs from the entry's others: a hook that changes nothing would be a
        // variant for nothing.
        for e in ENTRIES {
            let texts: BTreeSet<String> = e
                .variants()
                .iter()
                .map(|v| {
                    std::fs::read_to_string(format!("{}/{}", env!("OUT_DIR"), e.composed_name(v))).unwrap()
                })
                .collect();
            assert_eq!(texts.len(), 1 << e.hooks.len(), "{}", e.file);
        }
    }

    #[test]
    fn select_picks_the_variant_of_the_hooks_turned_on() {
        let both = [(Hook::Instrument, true), (Hook::AppendSubgroup, true)];
        assert_eq!(GENERATE.select(&both), GENERATE.variants[3]);
        assert_eq!(GENERATE.select(&[(Hook::AppendSubgroup, true)]), GENERATE.variants[2]);
        assert_eq!(GENERATE.select(&[(Hook::Instrument, false)]), GENERATE.plain());
        assert!(GENERATE.select(&both).contains("subgroupBroadcastFirst"));
        assert!(!GENERATE.plain().contains("subgroupBroadcastFirst"));
        // A hook off needs no variant of it.
        assert_eq!(
            COMPACT.select(&[(Hook::Instrument, false), (Hook::ScanSubgroup, true)]),
            COMPACT.variants[1]
        );
    }
}
