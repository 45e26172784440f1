//! The methods' options, stated once: every knob's type, default and documentation (each
//! wavefront knob in a module of its own, `wavefront/<knob>.rs`, with its flag, config row,
//! rule and pipeline constant), the one check (`check.rs`), and the table configs, reports and
//! labels name them by (`knobs.rs`).
//! Free of wgpu: the experiment config reads and checks options without a device, and the
//! renderers (`gpu/`) take them as they are.

mod check;
mod knob;
pub mod knobs;
mod measure;
mod megakernel;
mod option_error;
mod schedule;
pub mod wavefront;

pub use check::{check, check_bvh, check_megakernel};
pub use measure::*;
pub use megakernel::MegakernelOptions;
pub use option_error::{OptionError, Problem};
pub use schedule::{RunSchedule, Schedule};
pub use wavefront::*;

use crate::light_options::LightOptions;
use crate::numerics::NumericOptions;
use crate::scene::stress::StressTransform;

/// An option enum's value as the command line, configs and reports spell it: its clap
/// `ValueEnum` name, the one spelling (serde's kebab-case agrees, `knobs.rs`'s tests check it).
pub trait Named {
    fn name(&self) -> String;
}

impl<T: clap::ValueEnum> Named for T {
    fn name(&self) -> String {
        self.to_possible_value().map_or_else(String::new, |v| v.get_name().to_owned())
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// CPU reference computing in f32 (the GPU's arithmetic), rayon-parallel.
    Cpu,
    /// CPU reference computing in f64: the accuracy ground truth.
    CpuF64,
    /// GPU megakernel: one compute kernel traces whole paths.
    Megakernel,
    /// GPU wavefront: each bounce split into passes over queues of paths.
    Wavefront,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Cpu => "cpu",
            Method::CpuF64 => "cpu-f64",
            Method::Megakernel => "megakernel",
            Method::Wavefront => "wavefront",
        }
    }

    pub fn needs_gpu(self) -> bool {
        matches!(self, Method::Megakernel | Method::Wavefront)
    }
}

/// Per-method knobs; methods ignore the ones that are not theirs.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct MethodOptions {
    /// How next-event estimation samples the lights: every method's knobs, with the same meaning
    /// on each.
    #[serde(flatten)]
    pub lights: LightOptions,
    /// How rays leave surfaces, meet spheres and split at glass (`--ray-offset`, `--sphere-hit`,
    /// `--fresnel`): every method's knobs, with the same meaning on each.
    #[serde(flatten)]
    pub numerics: NumericOptions,
    /// The scene scaled and moved before rendering (`--scale`, `--translate`): the same image in
    /// exact arithmetic, so what changes is numerical error.
    #[serde(flatten)]
    pub stress: StressTransform,
    pub megakernel: MegakernelOptions,
    pub wavefront: WavefrontOptions,
    /// Count SIMD efficiency with subgroup operations (GPU methods; not for timing runs).
    pub instrument: bool,
    /// GPU methods: timestamps around every pass, or one host-clock time per submission.
    pub timing: Timing,
    /// GPU methods: shaders compiled with wgpu's runtime checks, or without them.
    pub shader_checks: ShaderChecks,
    /// GPU methods: shaders compiled with only the scene's primitive, material and texture
    /// kinds, or with every kind.
    pub specialize: Specialize,
    /// Every method: the BVH's node layout its traversals read (`--bvh`).
    pub bvh: crate::bvh::BvhLayout,
    /// Every method with `--bvh wide`: how the binary build is collapsed into 8-wide nodes
    /// (`--collapse`).
    pub collapse: crate::bvh::collapse::Collapse,
    /// GPU methods: where the BVH traversal keeps its stack (`--stack`).
    pub stack: crate::bvh::stack::BvhStack,
    /// GPU methods: seconds of busy GPU work just before the first submission, so the frame
    /// starts at the clocks continuous rendering holds (`gpu::preheat`; 0: none). Set by the
    /// experiment runner and `wavetrace render`, not a knob of the method.
    #[serde(skip)]
    pub preheat_seconds: f64,
}

impl MethodOptions {
    /// The options a command line or config asks for when it names none: the library's
    /// defaults with `--schedule auto` (the library's own default is the plain waves, the
    /// baseline its tests compare against).
    pub fn requested() -> Self {
        let mut o = Self::default();
        o.megakernel.schedule = Schedule::Auto;
        o.wavefront.schedule = Schedule::Auto;
        o
    }

    /// The options as `method` runs them on an adapter (`software`: whether it is a software
    /// one; None: not known yet): `--schedule auto` made concrete (the GPU methods resolve it
    /// themselves; reports call this to record what ran).
    pub fn resolve(&self, method: Method, software: Option<bool>) -> Self {
        let mut o = self.clone();
        match (method, software) {
            (Method::Megakernel, _) => o.megakernel = o.megakernel.resolve(),
            (Method::Wavefront, Some(software)) => o.wavefront = o.wavefront.resolve(software).options,
            _ => {}
        }
        o
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(clap::Parser)]
    struct Flags {
        #[command(flatten)]
        megakernel: MegakernelOptions,
        #[command(flatten)]
        wavefront: WavefrontOptions,
    }

    /// The flags' defaults are written beside each field; they must be the options' defaults.
    #[test]
    fn the_flags_default_to_the_options_defaults() {
        let f = Flags::try_parse_from(["wavetrace"]).unwrap();
        assert_eq!(f.megakernel, MegakernelOptions::default());
        assert_eq!(f.wavefront, WavefrontOptions::default());
        let f = Flags::try_parse_from(["wavetrace", "--tail", "megakernel", "--sync-every", "4"]).unwrap();
        assert_eq!((f.wavefront.tail, f.wavefront.sync_every), (Tail::Megakernel, 4));
    }
}
