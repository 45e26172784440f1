//! Textures: how a material's albedo varies over a surface. Solid and checker are The Next
//! Week's; the procedural patterns (noise and marble, its Perlin textures, and six more) each
//! take `octaves` as a knob for shading cost.

use glam::Vec3;

/// Most octaves a noise texture may have: beyond ~16 the finest octave is below f32 precision
/// at scene scales, and the cost would only burn time.
pub const MAX_OCTAVES: u32 = 16;

/// The costly procedural patterns: each a different code path, with a cost comparable per
/// octave (every octave hashes the 8 lattice corners around the point once; what is done with
/// each corner and how octaves combine differs), so a scene mixing K of them diverges K ways at
/// about the same total cost (`rtiow-kinds-K`). Twins: `src/cpu/texture.rs`,
/// `shaders/shared/texture.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Pattern {
    /// `color` × turbulence(`scale` · p, `octaves`).
    Noise,
    /// `color` × ½(1 + sin(`scale` · p.z + 10 · turbulence(p, `octaves`))): the book's marble.
    Marble,
    /// Rings about the y axis, `scale` per unit, displaced by turbulence.
    Wood,
    /// Ridged multifractal: Σ weight · (1 − |perlin|)².
    Ridged,
    /// Domain warping: each octave's point moved by the octave before's noise.
    Warp,
    /// Worley's cellular noise: the distance to the nearest feature point (F1), summed over
    /// octaves.
    Cellular,
    /// Worley's crackle: the second-nearest feature point's distance less the nearest's (F2 − F1).
    Crackle,
    /// Value noise: a hashed value per lattice corner, interpolated, summed over octaves.
    Value,
}

impl Pattern {
    /// Every pattern, in `layout::texture_kind` order (noise first): `rtiow-kinds-K` takes the
    /// first K.
    pub const ALL: [Pattern; 8] = [
        Pattern::Noise,
        Pattern::Marble,
        Pattern::Wood,
        Pattern::Ridged,
        Pattern::Warp,
        Pattern::Cellular,
        Pattern::Crackle,
        Pattern::Value,
    ];

    /// The stable name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Pattern::Noise => "noise",
            Pattern::Marble => "marble",
            Pattern::Wood => "wood",
            Pattern::Ridged => "ridged",
            Pattern::Warp => "warp",
            Pattern::Cellular => "cellular",
            Pattern::Crackle => "crackle",
            Pattern::Value => "value",
        }
    }

    pub fn from_name(name: &str) -> Option<Pattern> {
        Pattern::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Its `layout::texture_kind`.
    pub fn kind(self) -> u32 {
        crate::layout::texture_kind::NOISE + Pattern::ALL.iter().position(|&p| p == self).unwrap() as u32
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Texture {
    /// One colour everywhere (a plain `[r, g, b]` albedo in scene files).
    Solid(Vec3),
    /// 3D checker of cubes `scale` wide: `even` where floor(x/s)+floor(y/s)+floor(z/s) is even.
    Checker { scale: f32, even: Vec3, odd: Vec3 },
    /// A costly procedural pattern tinted by `color`, `octaves` of it at frequency `scale`.
    Procedural { pattern: Pattern, scale: f32, octaves: u32, color: Vec3 },
    /// [`Scene::images`](super::Scene::images)`[image]` looked up at the surface's texture
    /// coordinates (bilinear, `wrap` along u and v: `super::image`), times `tint`.
    Image { image: u32, wrap: [super::image::Wrap; 2], tint: Vec3 },
}

impl Texture {
    /// The stable name used in scene files.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Texture::Solid(_) => "solid",
            Texture::Checker { .. } => "checker",
            Texture::Procedural { pattern, .. } => pattern.name(),
            Texture::Image { .. } => "image",
        }
    }

    /// The book's noise texture.
    pub fn noise(scale: f32, octaves: u32, color: Vec3) -> Texture {
        Texture::Procedural { pattern: Pattern::Noise, scale, octaves, color }
    }

    /// The book's marble texture.
    pub fn marble(scale: f32, octaves: u32, color: Vec3) -> Texture {
        Texture::Procedural { pattern: Pattern::Marble, scale, octaves, color }
    }
}

impl From<Vec3> for Texture {
    fn from(c: Vec3) -> Self {
        Texture::Solid(c)
    }
}
