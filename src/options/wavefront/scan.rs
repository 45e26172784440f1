//! `--scan`: how the scan compaction scans a workgroup (`gpu/wavefront/compact.rs`).

use super::*;

/// How the scan compaction scans a workgroup (`--scan`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scan {
    /// Subgroup operations where the adapter has them, else the workgroup scan.
    #[default]
    Auto,
    /// subgroupInclusiveAdd per subgroup, then the subgroup totals (3 barriers).
    Subgroup,
    /// Hillis–Steele over the workgroup in shared memory (16 barriers; no subgroups needed).
    Workgroup,
}
enum_values!(Scan);

flag! {
    /// Wavefront, --compaction-method scan: scan workgroups with subgroup operations (where the
    /// adapter has them: `auto`) or with the Hillis–Steele workgroup scan.
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    scan: Scan
}

pub const KNOB: Knob = knob!("scan", "scan", WAVEFRONT, Scan, o => o.wavefront.scan);

pub const RULE: Rule = Rule {
    knob: "scan",
    why: "sets how the scan compaction (and slot-depth order's scan) scans",
    set: |o| name(o.scan != Scan::Auto, o.scan),
    needs: |o| {
        let scans = o.compaction == Compaction::Scan
            || (o.compaction != Compaction::Off && o.queue_order == QueueOrder::SlotDepth);
        (!scans).then_some(("compaction", &["scan"]))
    },
};
