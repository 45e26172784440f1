//! Render settings shared by every method.

/// How rays find their closest hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Accel {
    /// SAH bounding volume hierarchy (the default).
    Bvh,
    /// No hierarchy: every ray tests every primitive, as the seeds' megakernels did. Implemented as a
    /// BVH with a single leaf, so all methods keep one traversal code path.
    None,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Rays per path at most, as the book's `max_depth` (a path that needs more contributes 0).
    pub max_depth: u32,
    pub seed: u32,
    pub accel: Accel,
    /// Next-event estimation: at each diffuse hit, a shadow ray to a point sampled on an emitter.
    /// Emission found by the bounce that follows is then not counted again, so on and off
    /// converge to the same image.
    pub nee: bool,
    /// Russian roulette, pbrt-v4's rule (`cpu::integrator::roulette`): from the second hit on, a
    /// path whose throughput's largest component fell below 1 ends with probability 1 − that
    /// component, and a survivor's throughput is divided by its survival probability. Unbiased,
    /// so on and off converge to the same image; off is the book's (every path runs to
    /// `max_depth` or escape). A bool rather than an enum of rules: there is one rule, and a bool
    /// sweeps in configs as `nee` does; a second rule would make it an enum.
    pub roulette: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 400,
            height: 225,
            spp: 16,
            max_depth: 50,
            seed: 0,
            accel: Accel::Bvh,
            nee: false,
            roulette: false,
        }
    }
}

impl RenderSettings {
    pub fn pixel_count(&self) -> u64 {
        self.width as u64 * self.height as u64
    }

    pub fn sample_count(&self) -> u64 {
        self.pixel_count() * self.spp as u64
    }

    /// Rejects settings no method can render; the message names the setting.
    pub fn validate(&self) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!("image size {}x{} is empty", self.width, self.height));
        }
        if self.spp == 0 {
            return Err("spp must be at least 1".into());
        }
        if self.max_depth == 0 {
            return Err("max-depth must be at least 1".into());
        }
        // Pixel and sample indices key the RNG as u32, and a bounce has 24 bits in the key.
        if self.pixel_count() > u32::MAX as u64 {
            return Err(format!("{}x{} has more than 2^32 pixels", self.width, self.height));
        }
        if self.max_depth >= 1 << 24 {
            return Err("max-depth must be below 2^24".into());
        }
        Ok(())
    }
}
