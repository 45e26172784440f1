//! The numerical knobs of every method (`--ray-offset`, `--sphere-hit`, `--fresnel`), the same
//! meaning on `cpu`, `cpu-f64`, `megakernel` and `wavefront`, and the failure counters that show
//! where a choice breaks (README, "Where methods fail — numerically").

/// How a secondary or shadow ray leaves the surface it starts on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RayOffset {
    /// The book's guard: hits closer than this distance are ignored, on every ray (camera rays
    /// included). Absolute, so it is too large for small scenes and too small for large ones.
    Tmin(f32),
    /// No distance epsilon: the origin is moved off the surface along the geometric normal by a
    /// conservative bound on the hit point's floating-point error, then rounded away from it
    /// (pbrt-v4's `OffsetRayOrigin`); hits need only t > 0.
    Robust,
}

impl RayOffset {
    /// The book's `t_min`.
    pub const BOOK_T_MIN: f32 = 1e-3;

    /// As the CLI and configs spell it: `tmin` (the book's 1e-3), `tmin=VALUE`, `robust`.
    pub fn name(self) -> String {
        match self {
            RayOffset::Tmin(t) if t == Self::BOOK_T_MIN => "tmin".into(),
            RayOffset::Tmin(t) => format!("tmin={t:e}"),
            RayOffset::Robust => "robust".into(),
        }
    }

    /// Reads `tmin`, `tmin=VALUE` (VALUE finite and ≥ 0) or `robust`.
    pub fn parse(s: &str) -> Result<Self, String> {
        let s = s.trim();
        match s {
            "robust" => return Ok(RayOffset::Robust),
            "tmin" => return Ok(RayOffset::Tmin(Self::BOOK_T_MIN)),
            _ => {}
        }
        let Some(v) = s.strip_prefix("tmin=") else {
            return Err(format!("expected \"tmin\", \"tmin=VALUE\" or \"robust\", found {s:?}"));
        };
        match v.trim().parse::<f32>() {
            Ok(t) if t.is_finite() && t >= 0.0 => Ok(RayOffset::Tmin(t)),
            Ok(t) => Err(format!("tmin must be a finite distance ≥ 0, found {t}")),
            Err(_) => Err(format!("tmin=VALUE needs a number, found {v:?}")),
        }
    }

    /// The t below which hits are ignored (0 with `robust`: any t > 0 counts).
    pub fn t_min(self) -> f32 {
        match self {
            RayOffset::Tmin(t) => t,
            RayOffset::Robust => 0.0,
        }
    }
}

impl Default for RayOffset {
    fn default() -> Self {
        RayOffset::Tmin(Self::BOOK_T_MIN)
    }
}

impl serde::Serialize for RayOffset {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name())
    }
}

/// How a ray meets a sphere.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SphereHit {
    /// The book's quadratic: h = d·(c − o), discriminant h² − |d|²(|c − o|² − r²), roots
    /// (h ∓ √disc)/|d|². Loses digits when the sphere is far away or small against the distance.
    Book,
    /// Ray Tracing Gems ch. 7: the discriminant as r² − |f − (f·d)d|² and the near root as c/q,
    /// without the cancellations (the default since the project began).
    #[default]
    Stable,
}

/// The reflectance of a dielectric boundary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fresnel {
    /// The book's Schlick term in the incident cosine, on both sides of the boundary: 4.1% at
    /// 40° leaving glass where the exact term gives 24.5%.
    #[default]
    Schlick,
    /// The exact unpolarised Fresnel equations for a dielectric, with total internal reflection.
    Exact,
}

impl SphereHit {
    pub fn name(self) -> &'static str {
        match self {
            SphereHit::Book => "book",
            SphereHit::Stable => "stable",
        }
    }
}

impl Fresnel {
    pub fn name(self) -> &'static str {
        match self {
            Fresnel::Schlick => "schlick",
            Fresnel::Exact => "exact",
        }
    }
}

/// The numerical knobs of every method.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct NumericOptions {
    pub ray_offset: RayOffset,
    pub sphere_hit: SphereHit,
    pub fresnel: Fresnel,
    /// Where the scene is rendered (`--render-space`; `cpu-f64` always in camera space).
    pub render_space: crate::render_space::RenderSpace,
}

/// What went wrong numerically in a render, counted per path event on every method (the NaN and
/// infinite samples are counted by the film: `Film::invalid_samples`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Failures {
    /// Secondary rays whose closest hit is the primitive they left, where leaving it cannot
    /// meet it again: any hit on the same quad or triangle, or a sphere's hit nearer than half
    /// the chord (the root at the origin itself).
    pub self_hits: u64,
    /// Shadow rays whose occluder is the primitive they left, by the same rule.
    pub shadow_self_hits: u64,
    /// Paths still going when they reached `max_depth` rays: cut, their remaining light lost.
    pub depth_cut: u64,
}

impl Failures {
    pub fn add(&mut self, o: &Failures) {
        self.self_hits += o.self_hits;
        self.shadow_self_hits += o.shadow_self_hits;
        self.depth_cut += o.depth_cut;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_offset_round_trips_through_its_name() {
        for o in [RayOffset::default(), RayOffset::Tmin(1e-4), RayOffset::Tmin(0.0), RayOffset::Robust] {
            assert_eq!(RayOffset::parse(&o.name()), Ok(o));
        }
        assert_eq!(RayOffset::default().name(), "tmin");
    }

    #[test]
    fn bad_ray_offsets_are_refused() {
        for bad in ["tmin=-1", "tmin=nan", "tmin=inf", "tmin=", "epsilon", "robust=1"] {
            assert!(RayOffset::parse(bad).is_err(), "{bad} accepted");
        }
    }
}
