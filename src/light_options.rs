//! How next-event estimation samples the lights (`--light-sampling`, `--light-select`): the same
//! meaning on every method, so the older strategies stay selectable for before/after comparisons.

/// How a point is sampled on the chosen light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LightSampling {
    /// Uniformly by area on every shape. A sphere seen from outside wastes the samples that land
    /// on its far side (hidden by the sphere itself): about 65% from `enclosure`'s wall.
    Area,
    /// Spheres uniformly over the cone they subtend from the shading point (pbrt-v4's
    /// `SphereLight`, Shirley–Wang), by area from inside a sphere; quads and triangles by area.
    #[default]
    SolidAngle,
}

/// How the emitting primitive is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LightSelect {
    /// Each emitting primitive equally often: a mesh light of 1 000 triangles gets 1 000 picks to
    /// a lone quad's one, whatever their power.
    Uniform,
    /// With probability proportional to emitted power (mean radiance over the channels × area),
    /// from an alias table built once per scene (`light_table.rs`).
    #[default]
    Power,
}

/// The light-sampling knobs of every method.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
pub struct LightOptions {
    #[serde(rename = "light_sampling")]
    pub sampling: LightSampling,
    #[serde(rename = "light_select")]
    pub select: LightSelect,
}

impl LightSampling {
    /// As the CLI and configs spell it.
    pub fn name(self) -> &'static str {
        match self {
            LightSampling::Area => "area",
            LightSampling::SolidAngle => "solid-angle",
        }
    }
}

impl LightSelect {
    /// As the CLI and configs spell it.
    pub fn name(self) -> &'static str {
        match self {
            LightSelect::Uniform => "uniform",
            LightSelect::Power => "power",
        }
    }
}
