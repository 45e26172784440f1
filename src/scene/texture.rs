//! Textures: how a material's albedo varies over a surface. Solid and checker are The Next
//! Week's; noise and marble are its Perlin textures, with `octaves` of turbulence as a knob for
//! shading cost.

use glam::Vec3;

/// Most octaves a noise texture may have: beyond ~16 the finest octave is below f32 precision
/// at scene scales, and the cost would only burn time.
pub const MAX_OCTAVES: u32 = 16;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Texture {
    /// One colour everywhere (a plain `[r, g, b]` albedo in scene files).
    Solid(Vec3),
    /// 3D checker of cubes `scale` wide: `even` where floor(x/s)+floor(y/s)+floor(z/s) is even.
    Checker { scale: f32, even: Vec3, odd: Vec3 },
    /// `color` × turbulence(`scale` · p, `octaves`).
    Noise { scale: f32, octaves: u32, color: Vec3 },
    /// `color` × ½(1 + sin(`scale` · p.z + 10 · turbulence(p, `octaves`))): the book's marble.
    Marble { scale: f32, octaves: u32, color: Vec3 },
}

impl Texture {
    /// The stable name used in scene files.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Texture::Solid(_) => "solid",
            Texture::Checker { .. } => "checker",
            Texture::Noise { .. } => "noise",
            Texture::Marble { .. } => "marble",
        }
    }
}

impl From<Vec3> for Texture {
    fn from(c: Vec3) -> Self {
        Texture::Solid(c)
    }
}
