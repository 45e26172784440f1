//! `--append`: how passes append paths to queues (`gpu/wavefront/append.rs`).

use super::*;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Append {
    /// Subgroup-aggregated where the adapter has subgroup operations, else per lane.
    #[default]
    Auto,
    /// One atomic per appending lane.
    Lane,
    /// One atomic per subgroup and queue, made by the first of the lanes appending to it.
    Subgroup,
}
enum_values!(Append);

flag! {
    /// Wavefront: append paths to queues with one atomic per subgroup and queue (where the
    /// adapter has subgroups: `auto`) or one per lane.
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    append: Append
}

pub const KNOB: Knob = knob!("append", "append", WAVEFRONT, Append, o => o.wavefront.append);

pub const RULE: Rule = Rule {
    knob: "append",
    why: "sets how paths are appended to queues",
    set: |o| name(o.append != Append::Auto, o.append),
    needs: queued,
};
