//! `--shadow-rays`: where the wavefront traces next-event estimation's shadow rays (issue 44;
//! `gpu/wavefront/shadow.rs`, or inline in shade).

use super::*;

/// Where the wavefront traces the shadow rays of next-event estimation (`--shadow-rays`, issue
/// 44).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowRays {
    /// Queued by shade with their weights and traced by the shadow pass (pbrt-v4's and Cycles'
    /// way): the ray and its weight stored and read back.
    #[default]
    Pass,
    /// Traced by shade where it samples the light, as the megakernel does: nothing stored but
    /// the radiance, no shadow pass, a traversal inside shade (needs queues).
    Inline,
}
enum_values!(ShadowRays);

flag! {
    /// Wavefront, --nee on: trace the shadow rays in a pass of their own, queued with their
    /// weights (`pass`), or in shade where the light is sampled, storing nothing but the
    /// radiance (`inline`, the megakernel's way; needs queues).
    #[arg(long, value_enum, default_value_t, hide_short_help = true)]
    shadow_rays: ShadowRays
}

pub const KNOB: Knob =
    knob!("shadow_rays", "shadow-rays", WAVEFRONT, ShadowRays, o => o.wavefront.shadow_rays);

pub const RULE: Rule = Rule {
    knob: "shadow_rays",
    why: "traces shadow rays from the queued hits",
    set: |o| name(o.shadow_rays == ShadowRays::Inline, o.shadow_rays),
    needs: queued,
};
